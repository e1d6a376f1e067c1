//! The frames of an animated GIF (`--gif`): the robot drawn as the report page's animation draws
//! it (`page.js`), one SVG picture per instant, for an arm of any number of links (the paper's
//! 2-link robot is the case `n = 2`). [`super::gif_writer`] rasterises and encodes them.
//!
//! A frame shows the base (a rectangle of [`BASE_SIZE`] at its orientation around its centre of
//! mass), the bar from the base's centre of mass to the mounting point, the `n` links in their
//! colours ([`LINK_COLOURS`]), the joints, the end effector, the system's centre of mass (a fixed
//! "+" at the origin: Eq. (4) with zero linear momentum), the end effector's and the base's paths
//! (the drift: whole and faint, travelled so far in colour), a legend (laid out by
//! [`super::legend`], so that its entries never overlap), a scale bar and a time stamp. The
//! points come from [`crate::model::kinematics::pose`] for the 2-link robot and from
//! [`Arm::joint_positions`] for any arm: both put the system's centre of mass at the origin.
//!
//! For an arm with shapes or obstacles (issue 21, [`super::scene`]) a frame also shows each
//! body's shapes in its pose (the base's in place of the illustrative rectangle), the obstacles,
//! and a caption with the least clearance of the verified motion; the frame nearest its time
//! marks the pair and their nearest points (red when the clearance does not hold) and is held
//! [`LEAST_HOLD`] hundredths of a second. Without shapes and obstacles nothing of this is drawn.

use super::GifOptions;
use super::gif_scene::scene_entries;
use super::legend::{Entry, FIRST_ROW, FONT_SIZE, LABEL_OFFSET, Legend, ROW, SWATCH_WIDTH, Swatch};
use super::scene::{Scene, nearest_instant};
use crate::error::Error;
use crate::model::Configuration;
use crate::model::arm::collision::Geometry;
use crate::model::arm::{Arm, Limits};
use crate::model::kinematics::pose;
use crate::plan::Plan;
use crate::plan::clearance::ClearanceReport;
use crate::planners::arm::ArmPlanned;
use crate::report::figures::BASE_SIZE;
use crate::report::html::escape;

/// The links' colours from the base outwards, repeated beyond six links (Okabe and Ito's
/// colour-blind-safe set; links 1 and 2 as in the 2-link figures, and as `page.js` draws them).
pub const LINK_COLOURS: [&str; 6] = ["#0072b2", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#f0e442"];

/// The colour of a joint at its limit and of the link it drives (the GIF's and `page.js`'s).
pub const AT_LIMIT_COLOUR: &str = "#e8000b";

/// The use of a position range or a velocity limit from which a joint counts as at its limit
/// (drawn in [`AT_LIMIT_COLOUR`]): 99 %.
pub const AT_LIMIT_USE: f64 = 0.99;

/// Which joints are at a limit at angles `theta` \[rad\] and rates `rate` \[rad/s\]: the use of
/// the joint's position range (`|theta - mid| / half`) or of its velocity limit (`|rate| / L`) is
/// at least [`AT_LIMIT_USE`] (as [`crate::plan::limit_use`] counts uses). One entry per joint;
/// all `false` for an arm without such limits.
pub fn joints_at_limit(limits: &Limits, theta: &[f64], rate: &[f64]) -> Vec<bool> {
    theta
        .iter()
        .zip(rate)
        .enumerate()
        .map(|(j, (&q, &r))| {
            let l = limits.joint(j);
            let range =
                l.position.is_some_and(|[lo, hi]| ((q - 0.5 * (lo + hi)) / (0.5 * (hi - lo))).abs() >= AT_LIMIT_USE);
            let speed = l.velocity.is_some_and(|v| r.abs() / v >= AT_LIMIT_USE);
            range || speed
        })
        .collect()
}

/// Whether an arm has a limit that [`joints_at_limit`] watches (a position range or a velocity
/// limit of a joint).
pub fn watches_limits(limits: &Limits) -> bool {
    limits.joints.iter().any(|j| j.position.is_some() || j.velocity.is_some())
}

/// How long the frame nearest the least clearance is shown \[1/100 s\]: 1 s.
pub const LEAST_HOLD: u16 = 100;

/// How many samples of the paths are drawn, at most.
const PATH_POINTS: usize = 500;
/// The strip above the drawing (title, time stamp, scale bar) \[px at 480\].
const TOP: f64 = 44.0;
/// Room around the drawing \[px at 480\].
const MARGIN: f64 = 12.0;

/// The points of a pose, as [`Arm::joint_positions`] lists them: the base's centre of mass,
/// joint 1 (the mounting point), joints `2..n`, the tip of link `n` (`n + 2` points) \[m\].
type Points = Vec<[f64; 2]>;

/// The frames of an animation and where the plane's points fall on them: what
/// [`super::animation_gif`] and [`super::arm_animation_gif`] draw, for tests and for callers that
/// want the frames' instants.
#[derive(Debug, Clone)]
pub struct GifView {
    options: GifOptions,
    width: f64,
    height: f64,
    /// The layout's unit \[px\]: `min(width, height) / 480`; fonts, strokes and strips scale with it.
    pub(super) unit: f64,
    /// Pixels per metre.
    pub(super) scale: f64,
    /// The world point at the drawing's centre \[m\].
    centre: [f64; 2],
    /// The drawing's centre on the canvas \[px\].
    middle: [f64; 2],
    /// Frame instants \[s\], configurations `(phi, theta_1..theta_n)` \[rad\] and the points there.
    frames: Vec<(f64, Vec<f64>, Points)>,
    /// Samples of the paths: instant \[s\] and points.
    path: Vec<(f64, Points)>,
    /// The legend, laid out for the frame's width.
    legend: Legend,
    /// Per frame, per joint: at a limit ([`joints_at_limit`]); empty for a robot without
    /// position or velocity limits.
    at_limit: Vec<Vec<bool>>,
    /// The shapes and obstacles with the arm that places them, and the frame nearest the least
    /// clearance; `None` without shapes and obstacles.
    pub(super) scene: Option<(Scene, Arm, Option<usize>)>,
}

impl GifView {
    /// The view of the 2-link `plan`'s motion at `options`' size (points from
    /// [`crate::model::kinematics::pose`]); see [`GifView::arm`].
    pub fn new(plan: &Plan, options: &GifOptions) -> Self {
        let tr = &plan.trajectory;
        let robot = &plan.problem.robot;
        let q: Vec<Vec<f64>> = tr.q.iter().map(|q| q.to_vec()).collect();
        Self::of_motion(&tr.t, &q, options, false, None, &|q| {
            let p = pose(robot, &Configuration::from_array([q[0], q[1], q[2]]));
            vec![p.base, p.joint1, p.joint2, p.tip]
        })
    }

    /// The view of the 2-link `plan`'s motion as [`GifView::new`] draws it, with the robot's
    /// shapes and the obstacles of `geometry` and the verified motion's least clearance `least`
    /// (module docs); without shapes and obstacles the same as [`GifView::new`]. Fails only when
    /// `geometry` does not fit the 2-link robot.
    pub fn two_link(
        plan: &Plan,
        geometry: &Geometry,
        least: Option<ClearanceReport>,
        options: &GifOptions,
    ) -> Result<Self, Error> {
        let arm = Arm::from_params(&plan.problem.robot).with_geometry(geometry.clone())?;
        let Some(scene) = Scene::new(&arm, least) else {
            return Ok(Self::new(plan, options));
        };
        let tr = &plan.trajectory;
        let robot = &plan.problem.robot;
        let q: Vec<Vec<f64>> = tr.q.iter().map(|q| q.to_vec()).collect();
        Ok(Self::of_motion(&tr.t, &q, options, false, Some((scene, arm)), &|q| {
            let p = pose(robot, &Configuration::from_array([q[0], q[1], q[2]]));
            vec![p.base, p.joint1, p.joint2, p.tip]
        }))
    }

    /// The view of an arm's motion at `options`' size: frames at evenly spaced instants from
    /// the first sample to the last (configurations interpolated linearly between samples), the
    /// scale fitted to the whole motion; points from [`Arm::joint_positions`]. A joint at its
    /// position range or velocity limit ([`joints_at_limit`], on the plan's exact angles and rates
    /// at the frame's instant) is drawn in [`AT_LIMIT_COLOUR`] with the link it drives. The arm's
    /// shapes, its obstacles and the certificate's least clearance are drawn too (module docs).
    pub fn arm(planned: &ArmPlanned, options: &GifOptions) -> Self {
        let t: Vec<f64> = planned.trajectory.iter().map(|p| p.t).collect();
        let q: Vec<Vec<f64>> = planned
            .trajectory
            .iter()
            .map(|p| std::iter::once(p.phi).chain(p.theta.iter().copied()).collect())
            .collect();
        let arm: &Arm = &planned.arm;
        let watched = watches_limits(&arm.limits);
        let scene = Scene::new(arm, planned.verification().clearance).map(|s| (s, arm.clone()));
        let mut view = Self::of_motion(&t, &q, options, watched, scene, &|q| arm.joint_positions(q));
        if watched {
            let motion = planned.plan.motion();
            let n = arm.joints();
            let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
            view.at_limit = view
                .frames
                .iter()
                .map(|(t, _, _)| {
                    motion.joint_state(*t, &mut theta, &mut rate);
                    joints_at_limit(&arm.limits, &theta, &rate)
                })
                .collect();
        }
        view
    }

    /// The view of the samples `(ts, qs)` (times ascending), `points` giving a configuration's
    /// points; `limited`: the legend lists a joint at its limit; `scene`: the shapes and
    /// obstacles to draw, with the arm that places them (the drawing fits them too).
    fn of_motion(
        ts: &[f64],
        qs: &[Vec<f64>],
        options: &GifOptions,
        limited: bool,
        scene: Option<(Scene, Arm)>,
        points: &dyn Fn(&[f64]) -> Points,
    ) -> Self {
        let (t0, t1) = (ts.first().copied().unwrap_or(0.0), ts.last().copied().unwrap_or(0.0));
        let n = options.frame_count(t1 - t0);
        let frames: Vec<(f64, Vec<f64>, Points)> = (0..n)
            .map(|k| {
                let t = if k + 1 == n { t1 } else { t0 + (t1 - t0) * k as f64 / (n - 1) as f64 };
                let q = configuration_at(ts, qs, t);
                let p = points(&q);
                (t, q, p)
            })
            .collect();
        let step = ts.len().div_ceil(PATH_POINTS).max(1);
        let mut indices: Vec<usize> = (0..ts.len()).step_by(step).collect();
        if ts.len() > 1 && indices.last() != Some(&(ts.len() - 1)) {
            indices.push(ts.len() - 1);
        }
        let path: Vec<(f64, Points)> = indices.iter().map(|&i| (ts[i], points(&qs[i]))).collect();
        // The bounds of every body over the motion, as page.js takes them.
        let half = BASE_SIZE[0].hypot(BASE_SIZE[1]) / 2.0;
        let mut b = [-half, half, -half, half];
        for (_, p) in &path {
            for (k, point) in p.iter().enumerate() {
                let r = if k == 0 { half } else { 0.05 };
                b = [b[0].min(point[0] - r), b[1].max(point[0] + r), b[2].min(point[1] - r), b[3].max(point[1] + r)];
            }
        }
        if let Some((s, arm)) = &scene {
            let sampled: Vec<Vec<f64>> = indices.iter().map(|&i| qs[i].clone()).collect();
            if let Some(e) = s.bounds(arm, &sampled) {
                b = [b[0].min(e[0]), b[1].max(e[1]), b[2].min(e[2]), b[3].max(e[3])];
            }
        }
        let (width, height) = (f64::from(options.width), f64::from(options.height));
        let unit = width.min(height) / 480.0;
        let links = frames.first().map_or(0, |f| f.2.len().saturating_sub(2));
        let mut entries = legend_entries(links, limited);
        if let Some((s, _)) = &scene {
            entries.extend(scene_entries(s));
        }
        let legend = Legend::new(entries, width / unit);
        let (top, strip, margin) = (TOP * unit, legend.height() * unit, MARGIN * unit);
        let scale = ((width - 2.0 * margin) / (b[1] - b[0])).min((height - top - strip - 2.0 * margin) / (b[3] - b[2]));
        let marked = scene.as_ref().and_then(|(s, _)| s.least).and_then(|c| {
            let instants: Vec<f64> = frames.iter().map(|f| f.0).collect();
            nearest_instant(&instants, c.time)
        });
        Self {
            options: *options,
            width,
            height,
            unit,
            scale,
            centre: [(b[0] + b[1]) / 2.0, (b[2] + b[3]) / 2.0],
            middle: [width / 2.0, top + (height - top - strip) / 2.0],
            frames,
            path,
            legend,
            at_limit: Vec::new(),
            scene: scene.map(|(s, arm)| (s, arm, marked)),
        }
    }

    /// The frame that marks the least clearance (the one nearest its time), when the plan has one.
    pub fn marked(&self) -> Option<usize> {
        self.scene.as_ref().and_then(|s| s.2)
    }

    /// The shapes and obstacles drawn, when the robot has any.
    pub fn scene(&self) -> Option<&Scene> {
        self.scene.as_ref().map(|s| &s.0)
    }

    /// Pixels per metre of the drawing.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The size and frame rate.
    pub fn options(&self) -> &GifOptions {
        &self.options
    }

    /// The frames: instant \[s\] and configuration `(phi, theta_1..theta_n)` \[rad\].
    pub fn frames(&self) -> Vec<(f64, &[f64])> {
        self.frames.iter().map(|(t, q, _)| (*t, q.as_slice())).collect()
    }

    /// Per joint, whether it is drawn at its limit in frame `k` (all `false` without position or
    /// velocity limits).
    pub fn at_limit(&self, k: usize) -> Vec<bool> {
        let links = self.frames.get(k).map_or(0, |f| f.2.len().saturating_sub(2));
        self.at_limit.get(k).cloned().unwrap_or_else(|| vec![false; links])
    }

    /// Where the point `p` of the plane \[m\] (the system's centre of mass at the origin, y up)
    /// falls on a frame: `(column, row)` \[px\], from the top left corner.
    pub fn pixel(&self, p: [f64; 2]) -> (f64, f64) {
        (self.middle[0] + (p[0] - self.centre[0]) * self.scale, self.middle[1] - (p[1] - self.centre[1]) * self.scale)
    }

    /// Frame `k` as an SVG picture, titled `title`.
    pub fn svg(&self, title: &str, k: usize) -> String {
        let u = self.unit;
        let (t, q, now) = &self.frames[k];
        let mut s = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" \
             font-family=\"DejaVu Sans\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"#fff\"/>\n",
            w = self.width,
            h = self.height
        );
        let px = |p: [f64; 2]| self.pixel(p);
        let polyline = |points: &[[f64; 2]], colour: &str, width: f64| {
            let list: Vec<String> = points
                .iter()
                .map(|&p| {
                    let (x, y) = px(p);
                    format!("{x:.2},{y:.2}")
                })
                .collect();
            format!(
                "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{:.2}\" \
                 stroke-linejoin=\"round\"/>\n",
                list.join(" "),
                width * u
            )
        };
        let dot = |p: [f64; 2], r: f64, colour: &str| {
            let (x, y) = px(p);
            format!("<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"{:.2}\" fill=\"{colour}\"/>\n", r * u)
        };
        // The system's centre of mass, fixed at the origin.
        s += &polyline(&[[-0.05, 0.0], [0.05, 0.0]], "#999", 1.0);
        s += &polyline(&[[0.0, -0.05], [0.0, 0.05]], "#999", 1.0);
        // The paths: whole (faint) and travelled so far (to the current pose).
        let tip = |p: &Points| p[p.len() - 1];
        let base = |p: &Points| p[0];
        let so_far = |f: &dyn Fn(&Points) -> [f64; 2]| -> Vec<[f64; 2]> {
            let mut v: Vec<[f64; 2]> = self.path.iter().filter(|(s, _)| s <= t).map(|(_, p)| f(p)).collect();
            v.push(f(now));
            v
        };
        let whole =
            |f: &dyn Fn(&Points) -> [f64; 2]| -> Vec<[f64; 2]> { self.path.iter().map(|(_, p)| f(p)).collect() };
        s += &polyline(&whole(&tip), "#d9d9d9", 1.5);
        s += &polyline(&so_far(&tip), "#d55e00", 2.0);
        s += &polyline(&whole(&base), "#dbe6f0", 1.5);
        s += &polyline(&so_far(&base), "#0072b2", 2.0);
        // The obstacles and the bodies' shapes, under the robot's lines.
        s += &self.shapes_svg(q);
        // The base at its orientation around its centre of mass (unless its shapes are drawn),
        // and its own x axis.
        let (sin, cos) = q[0].sin_cos();
        let (w, h) = (BASE_SIZE[0] / 2.0, BASE_SIZE[1] / 2.0);
        let centre = now[0];
        let corners: Vec<[f64; 2]> = [[-w, -h], [w, -h], [w, h], [-w, h], [-w, -h]]
            .iter()
            .map(|c| [centre[0] + cos * c[0] - sin * c[1], centre[1] + sin * c[0] + cos * c[1]])
            .collect();
        if self.scene().is_none_or(|sc| sc.bodies.first().is_none_or(Vec::is_empty)) {
            s += &polyline(&corners, "#444", 2.0)
                .replace("fill=\"none\"", "fill=\"rgb(120,120,120)\" fill-opacity=\"0.35\"");
        }
        s += &polyline(&[centre, [centre[0] + cos * w, centre[1] + sin * w]], "#444", 1.0);
        // The bar to the mounting point, each link from its joint to the next (the last to the
        // tip), then the joints and the end effector.
        s += &polyline(&[centre, now[1]], "#444", 3.0);
        let hot = self.at_limit(k);
        let hot = |j: usize| hot.get(j).copied().unwrap_or(false);
        for (j, pair) in now[1..].windows(2).enumerate() {
            let colour = if hot(j) { AT_LIMIT_COLOUR } else { LINK_COLOURS[j % LINK_COLOURS.len()] };
            s += &polyline(pair, colour, 6.0);
        }
        s += &dot(centre, 4.0, "#444");
        for (j, &joint) in now[1..now.len() - 1].iter().enumerate() {
            s += &if hot(j) { dot(joint, 8.0, AT_LIMIT_COLOUR) } else { dot(joint, 5.0, "#000") };
        }
        s += &dot(tip(now), 5.0, "#d55e00");
        if self.marked() == Some(k) {
            s += &self.marker_svg(q);
        }
        s += &self.captions(title, *t, q[0]);
        s + "</svg>\n"
    }

    /// Title, time stamp, scale bar and legend.
    fn captions(&self, title: &str, t: f64, phi: f64) -> String {
        let u = self.unit;
        let text = |x: f64, y: f64, size: f64, anchor: &str, body: &str| {
            format!(
                "<text x=\"{:.2}\" y=\"{:.2}\" font-size=\"{:.2}\" text-anchor=\"{anchor}\" fill=\"#000\">{}</text>\n",
                x * u,
                y * u,
                size * u,
                escape(body)
            )
        };
        // A scale bar of a round length about 100 px long (at 480 px), top right.
        let bar = [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .min_by(|a: &f64, b: &f64| {
                (a * self.scale - 100.0 * u).abs().total_cmp(&(b * self.scale - 100.0 * u).abs())
            })
            .unwrap_or(1.0);
        let (x1, y) = (self.width - 12.0 * u, 36.0 * u);
        let x0 = x1 - bar * self.scale;
        let mut s = format!(
            "<polyline points=\"{x0:.2},{:.2} {x0:.2},{y:.2} {x1:.2},{y:.2} {x1:.2},{:.2}\" fill=\"none\" \
             stroke=\"#000\" stroke-width=\"{:.2}\"/>\n",
            y - 5.0 * u,
            y - 5.0 * u,
            2.0 * u
        );
        s += &text((x0 + x1) / 2.0 / u, 30.0, 11.0, "middle", &format!("{bar} m"));
        // The title, cut to the room left of the scale bar.
        let room = ((x0 / u - 24.0) / 7.0).max(8.0) as usize;
        let title: String = if title.chars().count() > room {
            title.chars().take(room.saturating_sub(1)).chain(std::iter::once('…')).collect()
        } else {
            title.to_string()
        };
        s += &text(10.0, 17.0, 12.0, "start", &title);
        s += &text(10.0, 36.0, 13.0, "start", &format!("t = {t:.2} s, φ = {:.1} deg", phi.to_degrees()));
        // The legend, in rows under the drawing.
        let top = self.height / u - self.legend.height();
        // The least clearance, above the legend, in the marker's colour.
        if let Some((Some(caption), Some(colour))) = self.scene().map(|sc| (sc.caption(), sc.marker_colour())) {
            s += &text(10.0, top - 6.0, FONT_SIZE, "start", &caption)
                .replace("fill=\"#000\"", &format!("fill=\"{colour}\" id=\"least-caption\""));
        }
        s += &format!(
            "<line x1=\"0\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"#ddd\" stroke-width=\"{:.2}\"/>\n",
            (top + 2.0) * u,
            self.width,
            (top + 2.0) * u,
            u
        );
        for (entry, x, row, _) in &self.legend.placed {
            let (x, y) = (*x, top + FIRST_ROW + ROW * *row as f64);
            let stroke = |x0: f64, y0: f64, x1: f64, y1: f64, width: f64| {
                format!(
                    "<line x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{}\" stroke-width=\"{:.2}\"/>\n",
                    x0 * u,
                    y0 * u,
                    x1 * u,
                    y1 * u,
                    entry.colour,
                    width * u
                )
            };
            s += &match entry.swatch {
                Swatch::Cross => {
                    stroke(x + 6.0, y, x + 18.0, y, 2.0) + &stroke(x + 12.0, y - 6.0, x + 12.0, y + 6.0, 2.0)
                }
                Swatch::Bar => stroke(x, y, x + SWATCH_WIDTH, y, 4.0),
                Swatch::Line => stroke(x, y, x + SWATCH_WIDTH, y, 2.0),
            };
            s += &text(x + LABEL_OFFSET, y + 4.0, FONT_SIZE, "start", &entry.label);
        }
        s
    }
}

/// The legend's entries for `links` links, in the order `page.js` lists them; `limited`: and a
/// joint at its limit.
fn legend_entries(links: usize, limited: bool) -> Vec<Entry> {
    let mut entries = vec![
        Entry::new(Swatch::Cross, "#999", "system's centre of mass (fixed)"),
        Entry::new(Swatch::Bar, "#444", "base to mounting point (a, b)"),
    ];
    entries.extend(
        (0..links).map(|k| Entry::new(Swatch::Bar, LINK_COLOURS[k % LINK_COLOURS.len()], &format!("link {}", k + 1))),
    );
    entries.push(Entry::new(Swatch::Line, "#d55e00", "end-effector path"));
    entries.push(Entry::new(Swatch::Line, "#0072b2", "base's centre of mass path"));
    if limited {
        entries.push(Entry::new(Swatch::Bar, AT_LIMIT_COLOUR, "joint at its limit (≥ 99 %)"));
    }
    entries
}

/// The configuration at time `t` \[s\]: linear between the samples `(ts, qs)` (times ascending),
/// the first or last sample outside them (empty without samples).
fn configuration_at(ts: &[f64], qs: &[Vec<f64>], t: f64) -> Vec<f64> {
    let i = ts.partition_point(|&s| s <= t);
    match (i, qs.len()) {
        (_, 0) => Vec::new(),
        (0, _) => qs[0].clone(),
        (i, n) if i >= n => qs[n - 1].clone(),
        (i, _) => {
            let (a, b) = (ts[i - 1], ts[i]);
            let w = if b > a { (t - a) / (b - a) } else { 0.0 };
            qs[i - 1].iter().zip(&qs[i]).map(|(x, y)| x + w * (y - x)).collect()
        }
    }
}
