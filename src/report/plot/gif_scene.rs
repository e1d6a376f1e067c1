//! The GIF frames' drawing of the shapes, the obstacles and the least clearance (issue 21 item
//! 7; [`super::scene`] holds what is drawn, [`GifView::svg`] calls these): SVG elements in the
//! frame's pixels.

use super::GifView;
use super::animation::LINK_COLOURS;
use super::legend::{Entry, Swatch};
use super::scene::{OBSTACLE_COLOUR, Scene};
use crate::model::arm::collision::Body;

impl GifView {
    /// A closed outline \[m\] as an SVG polygon, with extra attributes `style`.
    pub(super) fn outline_svg(&self, points: &[[f64; 2]], style: &str) -> String {
        let list: Vec<String> = points
            .iter()
            .map(|&p| {
                let (x, y) = self.pixel(p);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        format!("<polygon points=\"{}\" stroke-linejoin=\"round\" {style}/>\n", list.join(" "))
    }

    /// The obstacles (a circle as an SVG circle, any other shape by its outline) and each body's
    /// shapes at `q` (the base's in grey, each link's in its colour); empty without a scene.
    pub(super) fn shapes_svg(&self, q: &[f64]) -> String {
        let Some((scene, arm, _)) = &self.scene else { return String::new() };
        let u = self.unit;
        let mut s = String::new();
        let obstacle = format!("fill=\"{OBSTACLE_COLOUR}\" fill-opacity=\"0.45\" stroke=\"{OBSTACLE_COLOUR}\"");
        for (k, (shape, outline)) in scene.obstacles.iter().zip(scene.obstacle_outlines()).enumerate() {
            let id = format!("id=\"obstacle{}\"", k + 1);
            s += &match shape.points.as_slice() {
                [c] => {
                    let (x, y) = self.pixel(*c);
                    format!(
                        "<circle {id} cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"{:.2}\" {obstacle} stroke-width=\"{:.2}\"/>\n",
                        shape.radius * self.scale,
                        1.5 * u
                    )
                }
                _ => self.outline_svg(&outline, &format!("{id} {obstacle} stroke-width=\"{:.2}\"", 1.5 * u)),
            };
        }
        for (body, outlines) in scene.placed_bodies(arm, q).iter().enumerate() {
            let colour = if body == 0 { "#444" } else { LINK_COLOURS[(body - 1) % LINK_COLOURS.len()] };
            let fill = if body == 0 { "rgb(120,120,120)\" fill-opacity=\"0.35" } else { colour };
            let opacity = if body == 0 { "" } else { " fill-opacity=\"0.25\"" };
            for o in outlines {
                s += &self.outline_svg(
                    o,
                    &format!("fill=\"{fill}\"{opacity} stroke=\"{colour}\" stroke-width=\"{:.2}\"", 1.5 * u),
                );
            }
        }
        s
    }

    /// The least clearance's marker at `q`: the pair's outlines and the segment between their
    /// nearest points, in the marker's colour (red when the clearance does not hold).
    pub(super) fn marker_svg(&self, q: &[f64]) -> String {
        let Some((scene, arm, _)) = &self.scene else { return String::new() };
        let (Some(c), Some(colour)) = (scene.least, scene.marker_colour()) else { return String::new() };
        let u = self.unit;
        let mut s = format!("<g id=\"least-clearance\" stroke=\"{colour}\" fill=\"none\">\n");
        let placed = scene.placed_bodies(arm, q);
        let obstacles = scene.obstacle_outlines();
        for body in [c.a, c.b] {
            let outlines: &[Vec<[f64; 2]>] = match body {
                Body::Base => placed.first().map_or(&[], Vec::as_slice),
                Body::Link(k) => placed.get(k).map_or(&[], Vec::as_slice),
                Body::Obstacle(k) => obstacles.get(k.wrapping_sub(1)).map(std::slice::from_ref).unwrap_or(&[]),
            };
            for o in outlines {
                s += &self.outline_svg(o, &format!("stroke-width=\"{:.2}\"", 3.0 * u));
            }
        }
        if let Some([a, b]) = scene.least_points(arm, q) {
            let ((xa, ya), (xb, yb)) = (self.pixel(a), self.pixel(b));
            s += &format!(
                "<line x1=\"{xa:.2}\" y1=\"{ya:.2}\" x2=\"{xb:.2}\" y2=\"{yb:.2}\" stroke-width=\"{:.2}\"/>\n",
                2.0 * u
            );
            for (x, y) in [(xa, ya), (xb, yb)] {
                s += &format!("<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"{:.2}\" fill=\"{colour}\"/>\n", 3.5 * u);
            }
        }
        s + "</g>\n"
    }
}

/// The legend's entries of a scene: the obstacles (when there are any) and the least clearance
/// (when it was checked), in the marker's colour.
pub(super) fn scene_entries(scene: &Scene) -> Vec<Entry> {
    let mut entries = Vec::new();
    if !scene.obstacles.is_empty() {
        entries.push(Entry::new(Swatch::Bar, OBSTACLE_COLOUR, "obstacle"));
    }
    if let Some(colour) = scene.marker_colour() {
        entries.push(Entry::new(Swatch::Line, colour, "least clearance (nearest points)"));
    }
    entries
}
