//! Tests of the pictures: both formats render, plan panels, viridis and text wrapping.

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
    assert!(svg.contains("Domain of eq14") && svg.contains("θ1 [deg]"), "{}", &svg[..200]);
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
        include_zero: false,
        bounds: vec![],
        marks: vec![],
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

/// The PNG is the SVG rasterised with anti-aliasing: a blue curve on white leaves many shades of
/// blue at its edges (a bitmap without anti-aliasing leaves one or two).
#[test]
fn png_curves_are_anti_aliased() {
    let figure = PlanFigure {
        title: "aa".into(),
        panels: vec![Panel {
            title: "one curve".into(),
            x_label: "t [s]".into(),
            y_label: "y".into(),
            series: vec![Series {
                label: "s".into(),
                points: (0..=200).map(|i| (f64::from(i), f64::from(i).sin())).collect(),
            }],
            text: vec![],
            include_zero: false,
            bounds: vec![],
            marks: vec![],
        }],
        caption: vec![],
    };
    let png = plan_picture(&figure, PictureFormat::Png, Path::new("x.png")).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(png)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let mut blues = std::collections::BTreeSet::new();
    for px in buf[..info.buffer_size()].chunks(channels) {
        if i32::from(px[2]) > i32::from(px[0]) + 30 {
            blues.insert((px[0], px[1], px[2]));
        }
    }
    assert!(blues.len() > 20, "{} shades of blue: not anti-aliased", blues.len());
}

/// The `(x, y)` of every `<text>` whose content is `label`, and the y range of every polyline.
fn svg_geometry(svg: &str, label: &str) -> (Vec<(f64, f64)>, (f64, f64)) {
    let doc = roxmltree::Document::parse(svg).unwrap();
    let num = |n: roxmltree::Node, a: &str| n.attribute(a).and_then(|v| v.parse::<f64>().ok()).unwrap_or(f64::NAN);
    let texts = doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.text().is_some_and(|t| t.trim() == label))
        .map(|n| (num(n, "x"), num(n, "y")))
        .collect();
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for n in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
        for pair in n.attribute("points").unwrap_or_default().split_whitespace() {
            if let Some((_, y)) = pair.split_once(',') {
                let y: f64 = y.parse().unwrap();
                range = (range.0.min(y), range.1.max(y));
            }
        }
    }
    (texts, range)
}

/// The legend sits in a strip above the chart: its labels are above every curve, even when the
/// curves end at the top right corner (where plotters' legend box used to be).
#[test]
fn plan_legends_sit_above_the_curves() {
    let series = |label: &str, k: f64| Series {
        label: label.into(),
        points: (0..=100).map(|i| (f64::from(i), k * f64::from(i))).collect(),
    };
    let figure = PlanFigure {
        title: "legend".into(),
        panels: vec![Panel {
            title: "rising".into(),
            x_label: "t [s]".into(),
            y_label: "y".into(),
            series: vec![series("first", 1.0), series("second", 0.99)],
            ..Default::default()
        }],
        caption: vec![],
    };
    let svg = String::from_utf8(plan_picture(&figure, PictureFormat::Svg, Path::new("x.svg")).unwrap()).unwrap();
    for label in ["first", "second"] {
        let (texts, (top, _)) = svg_geometry(&svg, label);
        assert_eq!(texts.len(), 1, "{label}");
        assert!(texts[0].1 < top - 5.0, "{label} at y = {} is not above the curves (top {top})", texts[0].1);
    }
}

/// With `include_zero`, a ripple of 0.099..0.111 is drawn on an axis from 0 (a tick label `0`);
/// without it, the axis spans the ripple only.
#[test]
fn include_zero_puts_zero_on_the_axis() {
    let ripple = Series {
        label: "u".into(),
        // Times 5..15, so that no x tick is labelled 0.
        points: (0..=100).map(|i| (5.0 + f64::from(i) / 10.0, 0.105 + 0.006 * (f64::from(i) / 8.0).sin())).collect(),
    };
    let draw = |include_zero| {
        let panel = Panel { title: "u".into(), series: vec![ripple.clone()], include_zero, ..Default::default() };
        let figure = PlanFigure { title: "zero".into(), panels: vec![panel], caption: vec![] };
        String::from_utf8(plan_picture(&figure, PictureFormat::Svg, Path::new("x.svg")).unwrap()).unwrap()
    };
    let has_zero = |svg: &str| !svg_geometry(svg, "0").0.is_empty();
    assert!(has_zero(&draw(true)));
    assert!(!has_zero(&draw(false)));
}

/// A component's colour depends on its signs only: the same in every map.
#[test]
fn domain_components_are_coloured_by_their_signs() {
    use crate::analysis::domain::Signs;
    let robot = |a: f64| RobotParams::src().with_mount(Mount::new(a, a).unwrap()).unwrap();
    let maps = [0.1, 0.3].map(|a| DomainMap::new(&robot(a), Transform::Eq14, 90).unwrap());
    let plus = Signs { branch: 1, sigma: Some(1) };
    for map in &maps {
        assert!(map.components().iter().any(|c| c.signs == plus));
    }
    assert_eq!(domain::signs_colour(plus), RGBColor(166, 206, 227));
    let (q0, qd, _) = paper_problem();
    let overlay = DomainOverlay { start: Some(q0), goal: Some(qd), ..Default::default() };
    let svg =
        String::from_utf8(domain_picture(&maps[0], &overlay, PictureFormat::Svg, Path::new("x.svg")).unwrap()).unwrap();
    assert!(svg.contains("θ1 [deg]") && svg.contains("branch +, σ &gt; 0") || svg.contains("branch +, σ > 0"));
    assert!(!svg.contains("theta1"));
}

/// A panel's limit lines are drawn dashed at their values, inside the vertical range even far
/// from the curves, with one legend entry per label; the picture renders as PNG too.
#[test]
fn limit_lines_are_dashed_at_their_values_and_always_visible() {
    // A ramp from (0, 0) to (10, 1): its two ends give the axis' scale in pixels.
    let ramp = Series { label: "θ1'".into(), points: (0..=10).map(|i| (f64::from(i), f64::from(i) / 10.0)).collect() };
    let bound = |value: f64| Bound { value, label: "θ1' limit".into(), series: Some(0) };
    let panel = Panel {
        title: "rates".into(),
        x_label: "t [s]".into(),
        y_label: "rate [rad/s]".into(),
        series: vec![ramp],
        bounds: vec![bound(3.0), bound(-3.0), Bound { value: f64::NAN, label: "never".into(), series: None }],
        ..Default::default()
    };
    let figure = PlanFigure { title: "limits".into(), panels: vec![panel], caption: vec![] };
    let svg = String::from_utf8(plan_picture(&figure, PictureFormat::Svg, Path::new("x.svg")).unwrap()).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let lines: Vec<Vec<(f64, f64)>> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| {
            let points = n.attribute("points").unwrap_or_default().split_whitespace();
            points.filter_map(|p| p.split_once(',')).map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap())).collect()
        })
        .collect();
    // The ramp is the one polyline of 11 points.
    let ramp = lines.iter().find(|l| l.len() == 11).expect("the ramp");
    let (zero, one) = (ramp[0].1, ramp[10].1);
    let pixel = |v: f64| zero + v * (one - zero);
    for value in [3.0, -3.0] {
        let dashes = lines
            .iter()
            .filter(|l| l.len() == 2 && (l[0].1 - l[1].1).abs() < 1e-9 && (l[0].1 - pixel(value)).abs() < 1.5)
            .count();
        assert!(dashes >= 50, "{dashes} dashes at {value} (pixel {})", pixel(value));
    }
    assert_eq!(svg_geometry(&svg, "θ1' limit").0.len(), 1, "one legend entry for both signs");
    assert!(svg_geometry(&svg, "never").0.is_empty(), "a non-finite bound is not drawn");
    let png = plan_picture(&figure, PictureFormat::Png, Path::new("x.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}

/// Limit lines of several labels share one legend entry, [`BOUNDS_LABEL`].
#[test]
fn limit_lines_of_several_labels_share_one_legend_entry() {
    let flat = Series { label: "u".into(), points: vec![(0.0, 0.0), (1.0, 0.5)] };
    let bound = |value: f64, label: &str| Bound { value, label: label.into(), series: None };
    let panel = Panel { series: vec![flat], bounds: vec![bound(1.0, "a"), bound(-1.0, "b")], ..Default::default() };
    let figure = PlanFigure { title: "limits".into(), panels: vec![panel], caption: vec![] };
    let svg = String::from_utf8(plan_picture(&figure, PictureFormat::Svg, Path::new("x.svg")).unwrap()).unwrap();
    assert_eq!(svg_geometry(&svg, BOUNDS_LABEL).0.len(), 1);
    assert!(svg_geometry(&svg, "a").0.is_empty() && svg_geometry(&svg, "b").0.is_empty());
}
