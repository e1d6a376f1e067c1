//! Mount-sweep pictures (Sec. 6, item 3: mounting-point design): heat maps over the mounting
//! point `(a, b)`.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Painter, PictureFormat, picture_error, render, round_label, viridis};
use crate::analysis::sweep::SweepRow;
use crate::error::Error;

/// The size \[px\] of a sweep picture of the NFA's two panels ([`sweep_picture`]); each more
/// panel adds half the width.
pub const SWEEP_SIZE: (u32, u32) = (1300, 620);

/// One heat map: its title, its colour bar's title, the value of a row (`None`: not computed or
/// no certified plan, drawn grey) and the point it marks.
struct Panel<'a> {
    title: String,
    bar: &'static str,
    value: fn(&SweepRow) -> Option<f64>,
    mark: Option<(&'a SweepRow, &'static str)>,
}

/// The heat maps of a mount sweep over `(a, b)`, each coloured from its smallest to its largest
/// value: with the NFA's metric the start-component fraction and the best NFA success rate (the
/// best point marked), with the effort metric the effort of the reference plan (the least marked,
/// points without a certified plan grey).
pub fn sweep_picture(rows: &[SweepRow], format: PictureFormat, path: &Path) -> Result<Vec<u8>, Error> {
    let Some(first) = rows.first() else {
        return Err(picture_error(path, "no sweep rows to draw"));
    };
    let mut panels = Vec::new();
    if first.eq14_rate.is_some() {
        let best = crate::analysis::sweep::best(rows).map(|r| (r, "best"));
        panels.push(Panel {
            title: format!("Start-component fraction (grid {})", first.grid),
            bar: "fraction of the torus",
            value: |r| r.start_component_fraction,
            mark: best,
        });
        panels.push(Panel {
            title: format!("Best NFA success rate ({} random pairs)", first.trials),
            bar: "success rate",
            value: SweepRow::best_rate,
            mark: best,
        });
    }
    if first.planned.is_some() {
        panels.push(Panel {
            title: "Effort of the minimum-effort plan".into(),
            bar: "effort [rad^2/s]",
            value: |r| r.effort,
            mark: crate::analysis::sweep::least_effort(rows).map(|r| (r, "least")),
        });
    }
    if panels.is_empty() {
        return Err(picture_error(path, "the sweep rows hold no metric to draw"));
    }
    struct Sweep<'a>(&'a [SweepRow], Vec<Panel<'a>>);
    impl Painter for Sweep<'_> {
        fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            draw_sweep(root, self.0, &self.1)
        }
    }
    let width = SWEEP_SIZE.0 / 2 * panels.len() as u32;
    render(path, format, (width, SWEEP_SIZE.1), &Sweep(rows, panels))
}

fn draw_sweep<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rows: &[SweepRow],
    panels: &[Panel<'_>],
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
    let title = if rows[0].eq14_rate.is_some() {
        "Fig. 16: mounting-point map of the domain of Eq. (14) and of the NFA's success"
    } else {
        "Mounting-point map of the minimum-effort plan's effort"
    };
    let root = root.titled(title, (FONT, 22)).map_err(e)?;
    let areas = root.split_evenly((1, panels.len()));
    for (panel, area) in panels.iter().zip(&areas) {
        let (plot, bar) = area.split_horizontally(560);
        let mut chart = ChartBuilder::on(&plot)
            .caption(&panel.title, (FONT, 19))
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
        let value = panel.value;
        let max = rows.iter().filter_map(value).fold(f64::NEG_INFINITY, f64::max);
        let min = rows.iter().filter_map(value).fold(f64::INFINITY, f64::min);
        let (min, max) = if min <= max { (min, max) } else { (0.0, 1.0) };
        let span = (max - min).max(1e-12);
        chart
            .draw_series(rows.iter().map(|r| {
                let colour = value(r).map_or(RGBColor(190, 190, 190), |v| viridis((v - min) / span));
                Rectangle::new([(r.a - da / 2.0, r.b - db / 2.0), (r.a + da / 2.0, r.b + db / 2.0)], colour.filled())
            }))
            .map_err(e)?;
        if let Some((b, label)) = panel.mark {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((b.a, b.b))
                        + Circle::new((0, 0), 8, RED.stroke_width(3))
                        + Text::new(label, (10, -20), (FONT, 15).into_font().color(&RED)),
                ))
                .map_err(e)?;
        }
        // Colour bar from the panel's smallest to its largest value, with what it measures.
        bar.draw(&Text::new(panel.bar, (4, 24), (FONT, 14).into_font().color(&BLACK))).map_err(e)?;
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
