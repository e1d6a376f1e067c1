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
