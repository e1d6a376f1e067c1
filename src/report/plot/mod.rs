//! Pictures (SVG or PNG) of plans (Figs. 4-12), domain maps (Figs. 13-14) and of mount sweeps,
//! drawn with plotters.
//!
//! Text is laid out with DejaVu Sans, embedded in the binary (the `dejavu` crate; Bitstream Vera
//! license), and registered with plotters' `ab_glyph` renderer: pictures render the same on a
//! machine without any system font. Pictures are rendered in memory; the caller writes the bytes
//! (atomically, with [`crate::report::io::write_atomic`]).

use crate::model::InputError;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::analysis::domain::DomainMap;
use crate::analysis::sweep::SweepRow;
use crate::error::{Error, Singularity};
use crate::model::Configuration;

/// The file format of a picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PictureFormat {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics (RGB, 8 bits).
    Png,
}

impl PictureFormat {
    /// The format named by a file's extension (`.svg` or `.png`).
    pub fn from_path(path: &Path) -> Result<Self, Error> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("svg") => Ok(Self::Svg),
            Some("png") => Ok(Self::Png),
            _ => Err(picture_error(path, "the picture's file name must end in .svg or .png")),
        }
    }
}

fn picture_error(path: &Path, reason: impl std::fmt::Display) -> Error {
    Error::from(InputError::Io { path: path.to_path_buf(), source: std::io::Error::other(reason.to_string()) })
}

const FONT: &str = "sans-serif";

/// Registers the embedded font once.
fn register_font(path: &Path) -> Result<(), Error> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    });
    if ok { Ok(()) } else { Err(picture_error(path, "the embedded font could not be registered")) }
}

/// Something that draws itself on any plotters backend.
trait Painter {
    fn paint<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Renders `painter` on a `size` canvas in `format`; `path` only labels errors.
fn render(path: &Path, format: PictureFormat, size: (u32, u32), painter: &impl Painter) -> Result<Vec<u8>, Error> {
    register_font(path)?;
    let fail = |e: String| picture_error(path, e);
    match format {
        PictureFormat::Svg => {
            let mut text = String::new();
            {
                let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
                painter.paint(&root).map_err(fail)?;
                root.present().map_err(|e| fail(e.to_string()))?;
            }
            Ok(text.into_bytes())
        }
        PictureFormat::Png => {
            let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
                painter.paint(&root).map_err(fail)?;
                root.present().map_err(|e| fail(e.to_string()))?;
            }
            let mut png_bytes = Vec::new();
            {
                let mut encoder = png::Encoder::new(&mut png_bytes, size.0, size.1);
                encoder.set_color(png::ColorType::Rgb);
                encoder.set_depth(png::BitDepth::Eight);
                encoder.set_compression(png::Compression::Best);
                encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
                let mut writer = encoder.write_header().map_err(|e| fail(e.to_string()))?;
                writer.write_image_data(&rgb).map_err(|e| fail(e.to_string()))?;
            }
            Ok(png_bytes)
        }
    }
}

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

const PALETTE: [RGBColor; 10] = [
    RGBColor(166, 206, 227),
    RGBColor(251, 154, 153),
    RGBColor(253, 191, 111),
    RGBColor(202, 178, 214),
    RGBColor(255, 255, 153),
    RGBColor(178, 223, 138),
    RGBColor(141, 211, 199),
    RGBColor(252, 205, 229),
    RGBColor(217, 217, 217),
    RGBColor(188, 128, 189),
];
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
        Singularity::Sigma => "sigma = 0 (Eq. 9)",
        Singularity::P => "P = 0 (Eq. 13)",
        Singularity::SinTheta2 => "sin theta2 = 0",
        _ => "other",
    }
}

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
    render(path, format, (1100, 800), &Domain(map, overlay, start_component))
}

fn draw_domain<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    map: &DomainMap,
    overlay: &DomainOverlay,
    start_component: Option<usize>,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (left, right) = root.split_horizontally(800);
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
        .x_desc("theta1 [deg]")
        .y_desc("theta2 [deg]")
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
        Some(c) => PALETTE[c % PALETTE.len()],
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
        let branch = if comp.signs.branch > 0 { "+" } else { "-" };
        let tag = if is_start { "  <- q0" } else { "" };
        area.draw(&Text::new(
            format!("{:.2} %, branch {branch}{tag}", 100.0 * comp.fraction),
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
        for chunk in wrap_text(note, 34) {
            area.draw(&text(&chunk, y, 13))?;
            y += 18;
        }
    }
    Ok(())
}

/// Splits `s` into lines of at most about `width` characters at spaces.
fn wrap_text(s: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in s.split_whitespace() {
        if let Some(line) = lines.last_mut() {
            if !line.is_empty() && line.len() + word.len() + 1 > width {
                lines.push(word.to_string());
            } else {
                if !line.is_empty() {
                    line.push(' ');
                }
                line.push_str(word);
            }
        }
    }
    lines
}

/// The size \[px\] of a picture of two domain maps side by side ([`domain_pair_picture`]).
pub const DOMAIN_PAIR_SIZE: (u32, u32) = (2200, 800);

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
    if !(x1 > x0) {
        x1 = x0 + 1.0;
    }
    // A flat curve (e.g. a control that is zero) still gets a visible range.
    let pad = ((y1 - y0) * 0.06).max(1e-9 * y0.abs().max(y1.abs())).max(1e-12);
    let (y0, y1) = (y0 - pad, y1 + pad);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT, 19))
        .margin(14)
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
        chart
            .draw_series(LineSeries::new(series.points.iter().copied().filter(|p| finite(&p)), style))
            .map_err(e)?
            .label(series.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], colour.stroke_width(3)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .label_font((FONT, 15))
        .draw()
        .map_err(e)?;
    Ok(())
}

/// A tick label without float noise (`0.30000000000000004` is shown as `0.3`).
fn round_label(x: f64) -> f64 {
    // `+ 0.0` turns -0 into 0.
    (x * 1e6).round() / 1e6 + 0.0
}

/// Viridis, by linear interpolation between 9 of its colours; `x` in `[0, 1]`.
fn viridis(x: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let x = if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
    let u = x * (STOPS.len() - 1) as f64;
    let i = (u.floor() as usize).min(STOPS.len() - 2);
    let t = u - i as f64;
    let mix = |a: u8, b: u8| (a as f64 * (1.0 - t) + b as f64 * t).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

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
    let panels = root.split_evenly((1, 2));
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
        // Colour bar from 0 to the panel's largest value.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::domain::DomainMap;
    use crate::model::{Mount, RobotParams, paper_problem};
    use crate::planners::nfa::normal_form::Transform;

    /// Both formats render with the embedded font only: an SVG with the title's text, and a PNG
    /// with the PNG signature and some non-white pixels.
    #[test]
    fn domain_pictures_render_in_both_formats() {
        let robot = RobotParams::src().with_mount(Mount::new(0.2, 0.2).unwrap()).unwrap();
        let map = DomainMap::new(&robot, Transform::Eq14, 90).unwrap();
        let (q0, qd, _) = paper_problem();
        let overlay = DomainOverlay {
            start: Some(q0),
            goal: Some(qd),
            path: Some(vec![(q0.theta1, q0.theta2), (qd.theta1, qd.theta2)]),
            plan_note: Some("test".into()),
        };
        let p = Path::new("x.svg");
        let svg = String::from_utf8(domain_picture(&map, &overlay, PictureFormat::Svg, p).unwrap()).unwrap();
        assert!(svg.contains("Domain of eq14") && svg.contains("theta1 [deg]"), "{}", &svg[..200]);
        let png = domain_picture(&map, &overlay, PictureFormat::Png, Path::new("x.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert!(png.len() > 10_000);
        assert!(PictureFormat::from_path(Path::new("x.pdf")).is_err());
        assert_eq!(PictureFormat::from_path(Path::new("x.PNG")).unwrap(), PictureFormat::Png);
    }

    /// A plan picture labels its axes and legends, skips non-finite points (no NaN in the
    /// output), draws a flat curve, and shows a text panel in place of a chart.
    #[test]
    fn plan_pictures_label_axes_and_skip_non_finite_points() {
        let curve = |label: &str, f: fn(f64) -> f64| Series {
            label: label.into(),
            points: (0..=100).map(|i| f64::from(i) / 10.0).map(|t| (t, f(t))).collect(),
        };
        let mut bad = curve("u1", f64::sin);
        bad.points[50].1 = f64::NAN;
        bad.points[60].1 = f64::INFINITY;
        let panel = |title: &str, series| Panel {
            title: title.into(),
            x_label: "t [s]".into(),
            y_label: "u [rad/s]".into(),
            series,
            text: vec![],
        };
        let figure = PlanFigure {
            title: "test figure".into(),
            panels: vec![
                panel("controls", vec![bad, curve("zero", |_| 0.0)]),
                Panel { title: "words".into(), text: vec!["a line of text".into()], ..Default::default() },
            ],
            caption: vec!["caption line".into()],
        };
        let svg = String::from_utf8(plan_picture(&figure, PictureFormat::Svg, Path::new("x.svg")).unwrap()).unwrap();
        for text in ["test figure", "t [s]", "u [rad/s]", "u1", "zero", "a line of text", "caption line"] {
            assert!(svg.contains(text), "{text} missing");
        }
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        let png = plan_picture(&figure, PictureFormat::Png, Path::new("x.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }

    #[test]
    fn viridis_ends_and_text_wrap() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(wrap_text("aa bb cc", 5), vec!["aa bb", "cc"]);
    }
}
