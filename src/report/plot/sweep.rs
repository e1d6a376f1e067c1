//! Mount-sweep pictures (Sec. 6, item 3: mounting-point design): heat maps over the mounting
//! point `(a, b)`.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Painter, PictureFormat, picture_error, render, round_label, viridis};
use crate::analysis::sweep::SweepRow;
use crate::error::Error;

/// The size \[px\] of a sweep picture ([`sweep_picture`]).
pub const SWEEP_SIZE: (u32, u32) = (1300, 620);

/// The heat maps of a mount sweep: start-component fraction and best NFA success rate over
/// `(a, b)`, each coloured from its smallest to its largest value, the best point marked.
pub fn sweep_picture(rows: &[SweepRow], format: PictureFormat, path: &Path) -> Result<Vec<u8>, Error> {
    if rows.is_empty() {
        return Err(picture_error(path, "no sweep rows to draw"));
    }
    struct Sweep<'a>(&'a [SweepRow], Option<&'a SweepRow>);
    impl Painter for Sweep<'_> {
        fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            draw_sweep(root, self.0, self.1)
        }
    }
    render(path, format, SWEEP_SIZE, &Sweep(rows, crate::analysis::sweep::best(rows)))
}

fn draw_sweep<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rows: &[SweepRow],
    best: Option<&SweepRow>,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let mut a_values: Vec<f64> = rows.iter().map(|r| r.a).collect();
    let mut b_values: Vec<f64> = rows.iter().map(|r| r.b).collect();
    for v in [&mut a_values, &mut b_values] {
        v.sort_by(f64::total_cmp);
        v.dedup();
    }
    let step = |v: &[f64]| if v.len() > 1 { (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64 } else { 0.1 };
    let (da, db) = (step(&a_values), step(&b_values));
    let a_range = (a_values[0] - da / 2.0)..(a_values[a_values.len() - 1] + da / 2.0);
    let b_range = (b_values[0] - db / 2.0)..(b_values[b_values.len() - 1] + db / 2.0);
    let trials = rows[0].trials;
    let root = root
        .titled("Fig. 16: mounting-point map of the domain of Eq. (14) and of the NFA's success", (FONT, 22))
        .map_err(e)?;
    let panels = root.split_evenly((1, 2));
    let bar_titles = ["fraction of the torus", "success rate"];
    let titles = [
        format!("Start-component fraction (grid {})", rows[0].grid),
        format!("Best NFA success rate ({trials} random pairs)"),
    ];
    for (k, panel) in panels.iter().enumerate() {
        let (plot, bar) = panel.split_horizontally(560);
        let mut chart = ChartBuilder::on(&plot)
            .caption(&titles[k], (FONT, 19))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(a_range.clone(), b_range.clone())
            .map_err(e)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("a [m]")
            .y_desc("b [m]")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .x_label_formatter(&|x| format!("{:.2}", round_label(*x)))
            .y_label_formatter(&|y| format!("{:.2}", round_label(*y)))
            .draw()
            .map_err(e)?;
        let value = |r: &SweepRow| if k == 0 { r.start_component_fraction } else { r.best_rate() };
        let max = rows.iter().map(value).fold(f64::NEG_INFINITY, f64::max);
        let min = rows.iter().map(value).fold(f64::INFINITY, f64::min);
        let span = (max - min).max(1e-12);
        chart
            .draw_series(rows.iter().map(|r| {
                Rectangle::new(
                    [(r.a - da / 2.0, r.b - db / 2.0), (r.a + da / 2.0, r.b + db / 2.0)],
                    viridis((value(r) - min) / span).filled(),
                )
            }))
            .map_err(e)?;
        if let Some(b) = best {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((b.a, b.b))
                        + Circle::new((0, 0), 8, RED.stroke_width(3))
                        + Text::new("best", (10, -20), (FONT, 15).into_font().color(&RED)),
                ))
                .map_err(e)?;
        }
        // Colour bar from the panel's smallest to its largest value, with what it measures.
        bar.draw(&Text::new(bar_titles[k], (4, 24), (FONT, 14).into_font().color(&BLACK))).map_err(e)?;
        let (_, height) = bar.dim_in_pixel();
        let (top, bottom) = (60i32, height as i32 - 60);
        for y in top..bottom {
            let x = (bottom - y) as f64 / (bottom - top) as f64;
            bar.draw(&Rectangle::new([(10, y), (34, y + 1)], viridis(x).filled())).map_err(e)?;
        }
        for (frac, label) in [(0.0, min), (0.5, min + span / 2.0), (1.0, min + span)] {
            let y = bottom - ((bottom - top) as f64 * frac) as i32;
            bar.draw(&Text::new(format!("{label:.3}"), (40, y - 7), (FONT, 14).into_font().color(&BLACK)))
                .map_err(e)?;
        }
    }
    Ok(())
}
