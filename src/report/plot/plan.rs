//! Plan pictures (Figs. 4-12): up to four panels of curves against time and a caption.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{FONT, Painter, PictureFormat, render, round_label};
use crate::error::Error;

/// The size \[px\] of a plan picture ([`plan_picture`]).
pub const PLAN_FIGURE_SIZE: (u32, u32) = (1400, 1050);

/// One curve of a [`Panel`]: `(x, y)` points and the legend's label.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points, in the panel's units (non-finite points are skipped).
    pub points: Vec<(f64, f64)>,
}

/// A horizontal limit line of a [`Panel`] (e.g. a joint's velocity limit): drawn dashed across
/// the panel, in the colour of its series (or grey), and always inside the vertical range, so
/// that a limit far from the curves still shows how far they stay from it.
#[derive(Debug, Clone, PartialEq)]
pub struct Bound {
    /// The value, in the panel's units (a non-finite value is not drawn).
    pub value: f64,
    /// The legend's label, e.g. `θ1' limit`, when every line of the panel has it; lines of
    /// several labels share one entry, [`BOUNDS_LABEL`] (each drawn in its curve's colour).
    pub label: String,
    /// The index of the [`Series`] whose colour the line takes; `None`: grey.
    pub series: Option<usize>,
}

/// A vertical line of a [`Panel`] at one instant (e.g. the least clearance of the verified
/// motion): drawn solid across the chart in its colour, its label at the top beside it; the
/// horizontal axis always reaches it.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// The instant, in the horizontal axis' units (e.g. s; a non-finite value is not drawn).
    pub x: f64,
    /// The words beside the line, e.g. `least clearance 12.3 mm, base / link 4`.
    pub label: String,
    /// The colour `(red, green, blue)`.
    pub colour: (u8, u8, u8),
}

/// The legend's entry for limit lines of several labels.
pub const BOUNDS_LABEL: &str = "limits (dashed)";

/// The colour of a [`Bound`] without a series.
const BOUND_GREY: RGBColor = RGBColor(110, 110, 110);

/// One panel of a plan picture: curves against time, or (without curves) lines of text.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Caption above the panel.
    pub title: String,
    /// Label of the horizontal axis, e.g. `t [s]`.
    pub x_label: String,
    /// Label of the vertical axis, with its unit.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// Lines of text, drawn in place of the chart when there are no curves.
    pub text: Vec<String>,
    /// The vertical axis reaches down (or up) to zero, so that a small ripple on a large value
    /// looks small.
    pub include_zero: bool,
    /// Horizontal limit lines (dashed; empty: none). The vertical axis reaches each of them.
    pub bounds: Vec<Bound>,
    /// Vertical lines at given instants (empty: none).
    pub marks: Vec<Mark>,
}

/// A plan picture: a title, up to four panels in a 2 x 2 grid, and a caption of a few lines
/// below (e.g. the plan's certificates).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlanFigure {
    /// Title above the panels.
    pub title: String,
    /// Panels, row by row (at most four are drawn).
    pub panels: Vec<Panel>,
    /// Lines under the panels.
    pub caption: Vec<String>,
}

/// Colours of a panel's curves, in order (colour-blind safe, after Okabe and Ito).
const SERIES_COLOURS: [RGBColor; 4] =
    [RGBColor(0, 114, 178), RGBColor(213, 94, 0), RGBColor(0, 158, 115), RGBColor(204, 121, 167)];

/// The height \[px\] of the legend's strip above a panel's chart.
const LEGEND_HEIGHT: u32 = 26;
/// Where the legend starts \[px\]: above the chart's left edge.
const LEGEND_LEFT: i32 = 78;

/// The picture of a plan ([`PlanFigure`]) on a [`PLAN_FIGURE_SIZE`] canvas.
pub fn plan_picture(figure: &PlanFigure, format: PictureFormat, path: &Path) -> Result<Vec<u8>, Error> {
    struct Figure<'a>(&'a PlanFigure);
    impl Painter for Figure<'_> {
        fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            draw_plan(root, self.0)
        }
    }
    render(path, format, PLAN_FIGURE_SIZE, &Figure(figure))
}

fn draw_plan<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, figure: &PlanFigure) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (_, height) = root.dim_in_pixel();
    let caption_height = 24 * figure.caption.len() as u32 + 16;
    let titled = root.titled(&figure.title, (FONT, 24)).map_err(e)?;
    let (body, foot) = titled.split_vertically(height.saturating_sub(caption_height + 40));
    for (area, panel) in body.split_evenly((2, 2)).iter().zip(&figure.panels) {
        draw_panel(area, panel)?;
    }
    for (k, line) in figure.caption.iter().enumerate() {
        foot.draw(&Text::new(line.clone(), (24, 8 + 24 * k as i32), (FONT, 17).into_font().color(&BLACK)))
            .map_err(e)?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let points = || panel.series.iter().flat_map(|s| s.points.iter().filter(finite));
    if points().next().is_none() {
        let area = area.margin(14, 14, 14, 14).titled(&panel.title, (FONT, 19)).map_err(e)?;
        for (k, line) in panel.text.iter().enumerate() {
            area.draw(&Text::new(line.clone(), (40, 30 + 26 * k as i32), (FONT, 17).into_font().color(&BLACK)))
                .map_err(e)?;
        }
        return Ok(());
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in points() {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if panel.include_zero {
        (y0, y1) = (y0.min(0.0), y1.max(0.0));
    }
    for b in panel.bounds.iter().filter(|b| b.value.is_finite()) {
        (y0, y1) = (y0.min(b.value), y1.max(b.value));
    }
    for m in panel.marks.iter().filter(|m| m.x.is_finite()) {
        (x0, x1) = (x0.min(m.x), x1.max(m.x));
    }
    if !(x1 > x0) {
        x1 = x0 + 1.0;
    }
    // A flat curve (e.g. a control that is zero) still gets a visible range.
    let pad = ((y1 - y0) * 0.06).max(1e-9 * y0.abs().max(y1.abs())).max(1e-12);
    let (y0, y1) = (y0 - pad, y1 + pad);
    // The title, then the legend in a strip of its own above the chart: never over a curve.
    let area = area.margin(14, 0, 14, 14).titled(&panel.title, (FONT, 19)).map_err(e)?;
    let (strip, area) = area.split_vertically(LEGEND_HEIGHT);
    let mut x = LEGEND_LEFT;
    for (k, series) in panel.series.iter().enumerate() {
        let colour = SERIES_COLOURS[k % SERIES_COLOURS.len()];
        let y = LEGEND_HEIGHT as i32 / 2;
        strip.draw(&PathElement::new(vec![(x, y), (x + 22, y)], colour.stroke_width(3))).map_err(e)?;
        let text = Text::new(series.label.clone(), (x + 28, y - 8), (FONT, 15).into_font().color(&BLACK));
        strip.draw(&text).map_err(e)?;
        let (width, _) =
            strip.estimate_text_size(&series.label, &TextStyle::from((FONT, 15).into_font())).map_err(e)?;
        x += 28 + width as i32 + 24;
    }
    // One legend entry for the limit lines: their label when they share one (a joint's +limit and
    // -limit), else "limits (dashed)" in grey (each line has its curve's colour): room for the
    // curves' entries.
    let drawn: Vec<&Bound> = panel.bounds.iter().filter(|b| b.value.is_finite()).collect();
    if let Some(first) = drawn.first() {
        let shared = drawn.iter().all(|b| b.label == first.label);
        let (label, colour) =
            if shared { (first.label.clone(), bound_colour(first)) } else { (BOUNDS_LABEL.to_string(), BOUND_GREY) };
        let y = LEGEND_HEIGHT as i32 / 2;
        for k in 0..3 {
            let x = x + 8 * k;
            strip.draw(&PathElement::new(vec![(x, y), (x + 5, y)], colour.stroke_width(2))).map_err(e)?;
        }
        let text = Text::new(label, (x + 28, y - 8), (FONT, 15).into_font().color(&BLACK));
        strip.draw(&text).map_err(e)?;
    }
    let mut chart = ChartBuilder::on(&area)
        .margin_right(14)
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .x_label_formatter(&|x| format!("{}", round_label(*x)))
        .y_label_formatter(&|y| format!("{}", round_label(*y)))
        .draw()
        .map_err(e)?;
    for (k, series) in panel.series.iter().enumerate() {
        let colour = SERIES_COLOURS[k % SERIES_COLOURS.len()];
        let style = ShapeStyle::from(&colour).stroke_width(2);
        chart.draw_series(LineSeries::new(series.points.iter().copied().filter(|p| finite(&p)), style)).map_err(e)?;
    }
    for b in panel.bounds.iter().filter(|b| b.value.is_finite()) {
        let style = ShapeStyle::from(&bound_colour(b)).stroke_width(2);
        let dashes = dashes(x0, x1, 60);
        chart
            .draw_series(dashes.into_iter().map(|(a, c)| PathElement::new(vec![(a, b.value), (c, b.value)], style)))
            .map_err(e)?;
    }
    for (k, m) in panel.marks.iter().filter(|m| m.x.is_finite()).enumerate() {
        let colour = RGBColor(m.colour.0, m.colour.1, m.colour.2);
        chart
            .draw_series(std::iter::once(PathElement::new(vec![(m.x, y0), (m.x, y1)], colour.stroke_width(2))))
            .map_err(e)?;
        // The label on the side with more room, one line lower per earlier mark (marks of
        // nearby instants do not write over each other).
        let right = m.x - x0 > 0.6 * (x1 - x0);
        let (h, dx) = if right { (HPos::Right, -6) } else { (HPos::Left, 6) };
        let style = (FONT, 14).into_font().color(&colour).pos(Pos::new(h, VPos::Top));
        let dy = 4 + 18 * k as i32;
        let label = EmptyElement::at((m.x, y1)) + Text::new(m.label.clone(), (dx, dy), style);
        chart.draw_series(std::iter::once(label)).map_err(e)?;
    }
    Ok(())
}

/// The colour of a limit line: its series' colour, or grey.
fn bound_colour(b: &Bound) -> RGBColor {
    b.series.map_or(BOUND_GREY, |k| SERIES_COLOURS[k % SERIES_COLOURS.len()])
}

/// `count` dashes from `x0` to `x1`: `(start, end)` of each, the gaps as long as the dashes.
fn dashes(x0: f64, x1: f64, count: usize) -> Vec<(f64, f64)> {
    let step = (x1 - x0) / count as f64;
    (0..count).map(|k| (x0 + step * k as f64, x0 + step * (k as f64 + 0.5))).collect()
}
