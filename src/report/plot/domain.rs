//! Domain pictures (Figs. 13-14): one map, or two side by side, with its legend, `q0`, `qd` and
//! the planned path.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Painter, PictureFormat, render, wrap_text};
use crate::analysis::domain::{DomainMap, Signs};
use crate::error::{Error, Singularity};
use crate::model::Configuration;

/// What a domain picture shows besides the map.
#[derive(Debug, Clone, Default)]
pub struct DomainOverlay {
    /// `q0`.
    pub start: Option<Configuration>,
    /// `qd`.
    pub goal: Option<Configuration>,
    /// The planned joint path `(theta1, theta2)` \[rad\], when a plan exists.
    pub path: Option<Vec<(f64, f64)>>,
    /// One line about the plan (e.g. its verified final error, or why there is none).
    pub plan_note: Option<String>,
}

/// The colour of a component, by its signs alone: a component of branch `+` and `sigma > 0` has
/// the same colour in every map (the colours of ColorBrewer's Paired and Set3).
pub(super) fn signs_colour(signs: Signs) -> RGBColor {
    match (signs.branch > 0, signs.sigma.map(|s| s > 0)) {
        (true, Some(true) | None) => RGBColor(166, 206, 227),
        (true, Some(false)) => RGBColor(202, 178, 214),
        (false, Some(true) | None) => RGBColor(253, 191, 111),
        (false, Some(false)) => RGBColor(255, 255, 153),
    }
}

/// `branch +, σ > 0`: the signs of a component in words.
fn signs_text(signs: Signs) -> String {
    let branch = if signs.branch > 0 { "+" } else { "-" };
    match signs.sigma {
        Some(s) => format!("branch {branch}, σ {} 0", if s > 0 { ">" } else { "<" }),
        None => format!("branch {branch}"),
    }
}

const START_COLOUR: RGBColor = RGBColor(35, 139, 69);
const SLIVER_COLOUR: RGBColor = RGBColor(120, 120, 120);
const UNDEFINED_COLOUR: RGBColor = RGBColor(0, 0, 0);

fn curve_colour(which: Singularity) -> RGBColor {
    match which {
        Singularity::Sigma => RGBColor(215, 25, 28),
        Singularity::P => RGBColor(44, 123, 182),
        _ => RGBColor(110, 40, 160),
    }
}

fn curve_label(which: Singularity) -> &'static str {
    match which {
        Singularity::Sigma => "σ = 0 (Eq. 9)",
        Singularity::P => "P = 0 (Eq. 13)",
        Singularity::SinTheta2 => "sin θ2 = 0",
        _ => "other",
    }
}

/// The size \[px\] of one domain map ([`domain_picture`]): a square chart and a legend column
/// just wide enough for its text.
pub const DOMAIN_SIZE: (u32, u32) = (1050, 800);

/// The picture of a domain map: components coloured (`q0`'s highlighted), the zero curves as the
/// cell sides they cut, axes in degrees, a legend, `q0`, `qd` and the planned path.
pub fn domain_picture(
    map: &DomainMap,
    overlay: &DomainOverlay,
    format: PictureFormat,
    path: &Path,
) -> Result<Vec<u8>, Error> {
    struct Domain<'a>(&'a DomainMap, &'a DomainOverlay, Option<usize>);
    impl Painter for Domain<'_> {
        fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            draw_domain(root, self.0, self.1, self.2)
        }
    }
    let start_component = overlay.start.and_then(|q| map.component_at(&q));
    render(path, format, DOMAIN_SIZE, &Domain(map, overlay, start_component))
}

fn draw_domain<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    map: &DomainMap,
    overlay: &DomainOverlay,
    start_component: Option<usize>,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (left, right) = root.split_horizontally(770);
    let n = map.grid();
    let h = 360.0 / n as f64;
    let mount = map.robot().mount;
    let title = format!("Domain of {} for a = {} m, b = {} m", map.transform().name(), mount.a, mount.b);
    let mut chart = ChartBuilder::on(&left)
        .caption(title, (FONT, 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..360.0, 0.0..360.0)
        .map_err(e)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(9)
        .y_labels(9)
        .x_desc("θ1 [deg]")
        .y_desc("θ2 [deg]")
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&|y| format!("{y:.0}"))
        .draw()
        .map_err(e)?;
    let colour = |label: Option<usize>| match label {
        None => UNDEFINED_COLOUR,
        Some(c) if Some(c) == start_component => START_COLOUR,
        Some(c) if !map.components()[c].resolved => SLIVER_COLOUR,
        Some(c) => signs_colour(map.components()[c].signs),
    };
    // Cells, merged into runs of one component along each row.
    let mut rects = Vec::new();
    for i2 in 0..n {
        let mut i1 = 0;
        while i1 < n {
            let label = map.component(i1, i2);
            let mut end = i1 + 1;
            while end < n && map.component(end, i2) == label {
                end += 1;
            }
            let (y0, y1) = (i2 as f64 * h, (i2 + 1) as f64 * h);
            rects.push(Rectangle::new([(i1 as f64 * h, y0), (end as f64 * h, y1)], colour(label).filled()));
            i1 = end;
        }
    }
    chart.draw_series(rects).map_err(e)?;
    // Zero curves: the cell sides across which a function changes sign, merged into runs.
    for curve in map.curves() {
        let v = &curve.values;
        let cut = |a: usize, b: usize| (v[a] > 0.0) != (v[b] > 0.0) || !(v[a].abs() > 0.0);
        let style = ShapeStyle::from(&curve_colour(curve.which)).stroke_width(2);
        let mut lines: Vec<[(f64, f64); 2]> = Vec::new();
        for i2 in 0..n {
            // Horizontal sides y = (i2 + 1) h between rows i2 and i2 + 1 (mod n).
            let up = (i2 + 1) % n;
            let mut run: Option<usize> = None;
            for i1 in 0..=n {
                let is_cut = i1 < n && cut(i2 * n + i1, up * n + i1);
                match (is_cut, run) {
                    (true, None) => run = Some(i1),
                    (false, Some(s)) => {
                        let y = (i2 + 1) as f64 * h;
                        lines.push([(s as f64 * h, y), (i1 as f64 * h, y)]);
                        if up == 0 {
                            lines.push([(s as f64 * h, 0.0), (i1 as f64 * h, 0.0)]);
                        }
                        run = None;
                    }
                    _ => {}
                }
            }
        }
        for i1 in 0..n {
            // Vertical sides x = (i1 + 1) h between columns i1 and i1 + 1 (mod n).
            let right = (i1 + 1) % n;
            let mut run: Option<usize> = None;
            for i2 in 0..=n {
                let is_cut = i2 < n && cut(i2 * n + i1, i2 * n + right);
                match (is_cut, run) {
                    (true, None) => run = Some(i2),
                    (false, Some(s)) => {
                        let x = (i1 + 1) as f64 * h;
                        lines.push([(x, s as f64 * h), (x, i2 as f64 * h)]);
                        if right == 0 {
                            lines.push([(0.0, s as f64 * h), (0.0, i2 as f64 * h)]);
                        }
                        run = None;
                    }
                    _ => {}
                }
            }
        }
        chart.draw_series(lines.into_iter().map(|l| PathElement::new(l.to_vec(), style))).map_err(e)?;
    }
    // The planned path, broken where it wraps around.
    let deg = |x: f64| x.to_degrees().rem_euclid(360.0);
    if let Some(path) = &overlay.path {
        let mut pieces: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for &(t1, t2) in path {
            let p = (deg(t1), deg(t2));
            if let Some(last) = pieces.last_mut().and_then(|piece| piece.last().copied())
                && ((p.0 - last.0).abs() > 180.0 || (p.1 - last.1).abs() > 180.0)
            {
                pieces.push(Vec::new());
            }
            if let Some(piece) = pieces.last_mut() {
                piece.push(p);
            }
        }
        let style = ShapeStyle::from(&WHITE).stroke_width(5);
        chart.draw_series(pieces.iter().map(|p| PathElement::new(p.clone(), style))).map_err(e)?;
        let style = ShapeStyle::from(&BLACK).stroke_width(2);
        chart.draw_series(pieces.into_iter().map(|p| PathElement::new(p, style))).map_err(e)?;
    }
    let marker_text = |p: (f64, f64), name: &'static str| {
        EmptyElement::at(p) + Text::new(name, (9, -22), (FONT, 18).into_font().color(&BLACK))
    };
    if let Some(q) = overlay.start {
        let p = (deg(q.theta1), deg(q.theta2));
        let mark = EmptyElement::at(p)
            + Circle::new((0, 0), 7, WHITE.filled())
            + Circle::new((0, 0), 7, BLACK.stroke_width(2));
        chart.draw_series(std::iter::once(mark)).map_err(e)?;
        chart.draw_series(std::iter::once(marker_text(p, "q0"))).map_err(e)?;
    }
    if let Some(q) = overlay.goal {
        let p = (deg(q.theta1), deg(q.theta2));
        let mark = EmptyElement::at(p)
            + Rectangle::new([(-6, -6), (6, 6)], WHITE.filled())
            + Rectangle::new([(-6, -6), (6, 6)], BLACK.stroke_width(2));
        chart.draw_series(std::iter::once(mark)).map_err(e)?;
        chart.draw_series(std::iter::once(marker_text(p, "qd"))).map_err(e)?;
    }
    draw_domain_legend(&right, map, overlay, start_component, colour).map_err(e)
}

fn draw_domain_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    map: &DomainMap,
    overlay: &DomainOverlay,
    start_component: Option<usize>,
    colour: impl Fn(Option<usize>) -> RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let text = |s: &str, y: i32, size: i32| Text::new(s.to_string(), (10, y), (FONT, size).into_font().color(&BLACK));
    let swatch = |c: RGBColor, y: i32| Rectangle::new([(10, y), (34, y + 16)], c.filled());
    let line = |c: RGBColor, y: i32| PathElement::new(vec![(10, y + 8), (34, y + 8)], c.stroke_width(3));
    let mut y = 60;
    let resolved = map.resolved_count();
    area.draw(&text(&format!("{resolved} components ({}x{} grid)", map.grid(), map.grid()), y, 17))?;
    y += 30;
    let mut shown = 0;
    for (c, comp) in map.components().iter().enumerate() {
        let is_start = Some(c) == start_component;
        if !(is_start || (comp.resolved && shown < 10)) {
            continue;
        }
        shown += 1;
        area.draw(&swatch(colour(Some(c)), y))?;
        let tag = if is_start { "  ← q0" } else { "" };
        area.draw(&Text::new(
            format!("{:.2} %, {}{tag}", 100.0 * comp.fraction, signs_text(comp.signs)),
            (42, y),
            (FONT, 15).into_font().color(&BLACK),
        ))?;
        y += 24;
    }
    if shown < resolved {
        area.draw(&text(&format!("... {} more", resolved - shown), y, 15))?;
        y += 24;
    }
    let slivers: Vec<_> = map.components().iter().filter(|c| !c.resolved).collect();
    if !slivers.is_empty() {
        area.draw(&swatch(SLIVER_COLOUR, y))?;
        let area_sum: f64 = slivers.iter().map(|c| c.fraction).sum();
        area.draw(&Text::new(
            format!("{} slivers, {:.1e} of the torus", slivers.len(), area_sum),
            (42, y),
            (FONT, 15).into_font().color(&BLACK),
        ))?;
        y += 24;
    }
    if map.defined_fraction() < 1.0 {
        area.draw(&swatch(UNDEFINED_COLOUR, y))?;
        area.draw(&Text::new("undefined", (42, y), (FONT, 15).into_font().color(&BLACK)))?;
        y += 24;
    }
    y += 10;
    for curve in map.curves() {
        area.draw(&line(curve_colour(curve.which), y))?;
        area.draw(&Text::new(curve_label(curve.which), (42, y), (FONT, 15).into_font().color(&BLACK)))?;
        y += 24;
    }
    y += 10;
    area.draw(&(EmptyElement::at((22, y + 8)) + Circle::new((0, 0), 6, BLACK.stroke_width(2))))?;
    area.draw(&Text::new("q0 (start)", (42, y), (FONT, 15).into_font().color(&BLACK)))?;
    y += 24;
    area.draw(&Rectangle::new([(16, y + 2), (28, y + 14)], BLACK.stroke_width(2)))?;
    area.draw(&Text::new("qd (goal)", (42, y), (FONT, 15).into_font().color(&BLACK)))?;
    y += 24;
    if overlay.path.is_some() {
        area.draw(&line(BLACK, y))?;
        area.draw(&Text::new("planned NFA path", (42, y), (FONT, 15).into_font().color(&BLACK)))?;
        y += 24;
    }
    if let Some(note) = &overlay.plan_note {
        for chunk in wrap_text(note, 36) {
            area.draw(&text(&chunk, y, 13))?;
            y += 18;
        }
    }
    Ok(())
}

/// The size \[px\] of a picture of two domain maps side by side ([`domain_pair_picture`]).
pub const DOMAIN_PAIR_SIZE: (u32, u32) = (2 * DOMAIN_SIZE.0, DOMAIN_SIZE.1);

/// Two domain maps side by side, as in the paper's Figs. 13 and 14: each as
/// [`domain_picture`] draws it, on a [`DOMAIN_PAIR_SIZE`] canvas.
pub fn domain_pair_picture(
    maps: [(&DomainMap, &DomainOverlay); 2],
    format: PictureFormat,
    path: &Path,
) -> Result<Vec<u8>, Error> {
    struct Pair<'a>([(&'a DomainMap, &'a DomainOverlay, Option<usize>); 2]);
    impl Painter for Pair<'_> {
        fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
            for (area, (map, overlay, start)) in root.split_evenly((1, 2)).iter().zip(self.0) {
                draw_domain(area, map, overlay, start)?;
            }
            Ok(())
        }
    }
    let start = |(map, overlay): (&DomainMap, &DomainOverlay)| overlay.start.and_then(|q| map.component_at(&q));
    let pair = Pair([(maps[0].0, maps[0].1, start(maps[0])), (maps[1].0, maps[1].1, start(maps[1]))]);
    render(path, format, DOMAIN_PAIR_SIZE, &pair)
}
