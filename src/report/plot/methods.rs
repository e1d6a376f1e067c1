//! Fig. 17 (beyond the paper): the three methods' effort and peak joint velocity per mounting
//! point, as grouped bars on logarithmic axes.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Painter, PictureFormat, picture_error, render};
use crate::error::Error;
use crate::report::methods::MethodRow;

/// The size \[px\] of the methods picture ([`methods_picture`]).
pub const METHODS_SIZE: (u32, u32) = (1300, 560);

/// One bar group per mounting point, one bar per method (in the rows' order of first appearance):
/// left the effort `integral |u|^2 dt` \[rad^2/s\], right the peak `max |u|` \[rad/s\]; a method
/// without a plan has no bar.
pub fn methods_picture(rows: &[MethodRow], format: PictureFormat, path: &Path) -> Result<Vec<u8>, Error> {
    if rows.iter().all(|r| r.effort.is_none()) {
        return Err(picture_error(path, "no planned rows to draw"));
    }
    struct Bars<'a>(&'a [MethodRow]);
    impl Painter for Bars<'_> {
        fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            draw_methods(root, self.0)
        }
    }
    render(path, format, METHODS_SIZE, &Bars(rows))
}

/// The distinct values in order of first appearance.
fn distinct<T: PartialEq + Clone>(values: impl Iterator<Item = T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for v in values {
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

fn draw_methods<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, rows: &[MethodRow]) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    // Mounting points by their bits: the rows' own values, compared exactly.
    let key = |m: [f64; 2]| m.map(f64::to_bits);
    let mounts = distinct(rows.iter().map(|r| key(r.mount)));
    let methods = distinct(rows.iter().map(|r| r.method.clone()));
    let colours = [RGBColor(213, 94, 0), RGBColor(0, 114, 178), RGBColor(0, 158, 115), RGBColor(120, 120, 120)];
    let panels = root.split_evenly((1, 2));
    type Value = fn(&MethodRow) -> Option<f64>;
    let quantities: [(&str, &str, Value); 2] = [
        ("Effort ∫|u|² dt", "effort [rad²/s]", |r| r.effort),
        ("Peak joint velocity max |u|", "peak |u| [rad/s]", |r| r.peak_u()),
    ];
    let width = 0.8 / methods.len().max(1) as f64;
    for (panel, (title, label, value)) in panels.iter().zip(quantities) {
        let values: Vec<f64> = rows.iter().filter_map(value).filter(|v| *v > 0.0).collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        // At least half a decade under the smallest bar, so that every bar shows.
        let (lo, hi) = (10f64.powf((lo / 3.0).log10().floor()), 10f64.powf(hi.log10().ceil()).max(10.0 * lo));
        let mut chart = ChartBuilder::on(panel)
            .caption(title, (FONT, 19))
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(-0.5f64..(mounts.len() as f64 - 0.5), (lo..hi).log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(mounts.len())
            .x_desc("mounting point a, b [m]")
            .y_desc(label)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .x_label_formatter(&|x| {
                let i = x.round();
                match mounts.get(i as usize) {
                    Some(m) if (x - i).abs() < 1e-9 && i >= 0.0 => {
                        format!("{}, {}", f64::from_bits(m[0]), f64::from_bits(m[1]))
                    }
                    _ => String::new(),
                }
            })
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()
            .map_err(e)?;
        for (k, method) in methods.iter().enumerate() {
            let colour = colours[k.min(colours.len() - 1)];
            let bars = rows.iter().filter(|r| &r.method == method).filter_map(|r| {
                let i = mounts.iter().position(|m| *m == key(r.mount))? as f64;
                let v = value(r).filter(|v| *v > 0.0)?;
                let x0 = i - 0.4 + k as f64 * width;
                Some(Rectangle::new([(x0, lo), (x0 + width * 0.92, v)], colour.filled()))
            });
            chart
                .draw_series(bars)
                .map_err(e)?
                .label(method.to_uppercase())
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], colour.filled()));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 14))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}
