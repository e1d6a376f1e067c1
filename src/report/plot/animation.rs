//! An animated GIF of a plan's motion (`--gif`): the robot drawn as the report page's animation
//! draws it (`page.js`), one frame per instant, rasterised by resvg and encoded as a looping GIF.
//!
//! Each frame is an SVG picture: the base (a rectangle of [`BASE_SIZE`] at its orientation around
//! its centre of mass), the bar from the base's centre of mass to the mounting point, link 1 and
//! link 2, the joints, the system's centre of mass (a fixed "+" at the origin: Eq. (4) with zero
//! linear momentum), the end-effector's and the base's paths (whole and faint, travelled so far in
//! colour), a legend, a scale bar and a time stamp. Poses come from
//! [`crate::model::kinematics::pose`]. The SVG is rasterised with resvg (the embedded font only,
//! as the PNGs) and encoded by the `gif` crate, the image-rs project's GIF codec (pure Rust, LZW),
//! with one palette for all frames learnt by its quantiser (NeuQuant, see [`animation_gif`]).
//!
//! Playback: the plan's horizon `T` is shown in a loop of `T` seconds clamped to 5 to 8 s (a 10 s
//! plan plays in 8 s, a 2 s plan in 5 s), at [`GifOptions::fps`] frames per second, then the
//! final pose is held for 1 s and the GIF starts again (infinite loop). GIF delays are counted in
//! hundredths of a second: each frame lasts `round(100 / fps)` of them.

use std::path::Path;

use rayon::prelude::*;

use super::{picture_error, rgba_pixels};
use crate::error::Error;
use crate::model::kinematics::{Pose, pose};
use crate::model::{Configuration, InputError};
use crate::plan::Plan;
use crate::report::figures::BASE_SIZE;
use crate::report::html::escape;

/// Size and frame rate of an animated GIF.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GifOptions {
    /// Width \[px\], from [`GifOptions::MIN_SIDE`] to [`GifOptions::MAX_SIDE`] (default 480).
    pub width: u32,
    /// Height \[px\], from [`GifOptions::MIN_SIDE`] to [`GifOptions::MAX_SIDE`] (default 480).
    pub height: u32,
    /// Frames per second, from 1 to [`GifOptions::MAX_FPS`] (default 25).
    pub fps: u32,
}

impl Default for GifOptions {
    fn default() -> Self {
        Self { width: 480, height: 480, fps: 25 }
    }
}

impl GifOptions {
    /// Smallest width or height \[px\].
    pub const MIN_SIDE: u32 = 240;
    /// Largest width or height \[px\].
    pub const MAX_SIDE: u32 = 1920;
    /// Largest frame rate \[1/s\]: a GIF frame lasts at least 2 hundredths of a second in
    /// browsers (shorter delays are slowed down to 10 hundredths).
    pub const MAX_FPS: u32 = 50;
    /// Largest number of frames of a GIF (8 s at 50 frames/s, and the last frame).
    pub const MAX_FRAMES: usize = 401;

    /// Validated options: `width` and `height` in pixels, `fps` in frames per second; a value
    /// out of range is bad input naming its flag (`--gif-width`, `--gif-height`, `--gif-fps`).
    ///
    /// ```
    /// use freefloat::report::plot::GifOptions;
    ///
    /// assert_eq!(GifOptions::new(480, 480, 25).unwrap(), GifOptions::default());
    /// assert!(GifOptions::new(100, 480, 25).is_err());
    /// ```
    pub fn new(width: u64, height: u64, fps: u64) -> Result<Self, Error> {
        let check = |name: &str, value: u64, max: u32, min: u32, expected: &'static str| {
            if (u64::from(min)..=u64::from(max)).contains(&value) {
                Ok(value as u32)
            } else {
                Err(Error::from(InputError::InvalidParameter { name: name.into(), value: value as f64, expected }))
            }
        };
        let side = "a whole number of pixels from 240 to 1920";
        Ok(Self {
            width: check("--gif-width", width, Self::MAX_SIDE, Self::MIN_SIDE, side)?,
            height: check("--gif-height", height, Self::MAX_SIDE, Self::MIN_SIDE, side)?,
            fps: check("--gif-fps", fps, Self::MAX_FPS, 1, "a whole number of frames per second from 1 to 50")?,
        })
    }

    /// The loop's length \[s\] for a horizon `horizon` \[s\]: `horizon` clamped to 5 to 8 s.
    pub fn loop_seconds(horizon: f64) -> f64 {
        if horizon.is_finite() { horizon.clamp(5.0, 8.0) } else { 8.0 }
    }

    /// The number of frames for a horizon \[s\]: one per `1 / fps` of the loop, and the last,
    /// at most [`GifOptions::MAX_FRAMES`].
    pub fn frame_count(&self, horizon: f64) -> usize {
        let n = (Self::loop_seconds(horizon) * f64::from(self.fps)).round() as usize + 1;
        n.clamp(2, Self::MAX_FRAMES)
    }

    /// A frame's delay in hundredths of a second.
    pub fn delay(&self) -> u16 {
        (100.0 / f64::from(self.fps)).round().max(1.0) as u16
    }
}

/// Checks that `path` names a GIF file (`.gif`, any case): bad input otherwise.
pub fn check_gif_path(path: &Path) -> Result<(), Error> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("gif") => Ok(()),
        _ => Err(picture_error(path, "the animation's file name must end in .gif")),
    }
}

/// How many samples of the paths are drawn, at most.
const PATH_POINTS: usize = 500;
/// The hold on the final pose before the loop starts again \[hundredths of a second\].
const FINAL_HOLD: u16 = 100;
/// The palette index of a pixel unchanged since the previous frame (transparent).
const UNCHANGED: u8 = 255;
/// NeuQuant's sampling factor (1 best and slowest, 30 fastest): it learns the palette once, and the
/// swatch keeps the drawing's colours exact.
const QUANTISER_SPEED: i32 = 5;

/// The frames of an animation and where the plane's points fall on them: what [`animation_gif`]
/// draws, for tests and for callers that want the frames' instants.
#[derive(Debug, Clone)]
pub struct GifView {
    width: f64,
    height: f64,
    /// The layout's unit \[px\]: `min(width, height) / 480`; fonts, strokes and strips scale with it.
    unit: f64,
    /// Pixels per metre.
    scale: f64,
    /// The world point at the drawing's centre \[m\].
    centre: [f64; 2],
    /// The drawing's centre on the canvas \[px\].
    middle: [f64; 2],
    /// Frame instants \[s\] and configurations `(phi, theta1, theta2)` \[rad\].
    frames: Vec<(f64, [f64; 3])>,
    /// Samples of the paths: instant \[s\] and pose.
    path: Vec<(f64, Pose)>,
}

/// The strip above the drawing (title, time stamp, scale bar) and below it (legend) \[px at 480\].
const TOP: f64 = 44.0;
const LEGEND: f64 = 66.0;
const MARGIN: f64 = 12.0;

impl GifView {
    /// The view of `plan`'s motion at `options`' size: frames at evenly spaced instants from the
    /// first sample to the last (configurations interpolated linearly between samples), the
    /// scale fitted to the whole motion.
    pub fn new(plan: &Plan, options: &GifOptions) -> Self {
        let tr = &plan.trajectory;
        let robot = &plan.problem.robot;
        let (t0, t1) = (tr.t.first().copied().unwrap_or(0.0), tr.t.last().copied().unwrap_or(0.0));
        let n = options.frame_count(t1 - t0);
        let frames = (0..n)
            .map(|k| {
                let t = if k + 1 == n { t1 } else { t0 + (t1 - t0) * k as f64 / (n - 1) as f64 };
                (t, configuration_at(&tr.t, &tr.q, t))
            })
            .collect();
        let step = tr.t.len().div_ceil(PATH_POINTS).max(1);
        let mut indices: Vec<usize> = (0..tr.t.len()).step_by(step).collect();
        if tr.t.len() > 1 && indices.last() != Some(&(tr.t.len() - 1)) {
            indices.push(tr.t.len() - 1);
        }
        let path: Vec<(f64, Pose)> =
            indices.iter().map(|&i| (tr.t[i], pose(robot, &Configuration::from_array(tr.q[i])))).collect();
        // The bounds of every body over the motion, as page.js takes them.
        let half = BASE_SIZE[0].hypot(BASE_SIZE[1]) / 2.0;
        let mut b = [-half, half, -half, half];
        for (_, p) in &path {
            for (k, point) in [p.base, p.joint1, p.joint2, p.tip].iter().enumerate() {
                let r = if k == 0 { half } else { 0.05 };
                b = [b[0].min(point[0] - r), b[1].max(point[0] + r), b[2].min(point[1] - r), b[3].max(point[1] + r)];
            }
        }
        let (width, height) = (f64::from(options.width), f64::from(options.height));
        let unit = width.min(height) / 480.0;
        let (top, legend, margin) = (TOP * unit, LEGEND * unit, MARGIN * unit);
        let scale =
            ((width - 2.0 * margin) / (b[1] - b[0])).min((height - top - legend - 2.0 * margin) / (b[3] - b[2]));
        Self {
            width,
            height,
            unit,
            scale,
            centre: [(b[0] + b[1]) / 2.0, (b[2] + b[3]) / 2.0],
            middle: [width / 2.0, top + (height - top - legend) / 2.0],
            frames,
            path,
        }
    }

    /// The frames: instant \[s\] and configuration `(phi, theta1, theta2)` \[rad\].
    pub fn frames(&self) -> &[(f64, [f64; 3])] {
        &self.frames
    }

    /// Where the point `p` of the plane \[m\] (the system's centre of mass at the origin, y up)
    /// falls on a frame: `(column, row)` \[px\], from the top left corner.
    pub fn pixel(&self, p: [f64; 2]) -> (f64, f64) {
        (self.middle[0] + (p[0] - self.centre[0]) * self.scale, self.middle[1] - (p[1] - self.centre[1]) * self.scale)
    }

    /// Frame `k` as an SVG picture; `robot` and `title` as in [`animation_gif`].
    fn svg(&self, plan: &Plan, title: &str, k: usize) -> String {
        let u = self.unit;
        let (t, q) = self.frames[k];
        let now = pose(&plan.problem.robot, &Configuration::from_array(q));
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
        let so_far = |f: fn(&Pose) -> [f64; 2]| -> Vec<[f64; 2]> {
            let mut v: Vec<[f64; 2]> = self.path.iter().filter(|(s, _)| *s <= t).map(|(_, p)| f(p)).collect();
            v.push(f(&now));
            v
        };
        let whole = |f: fn(&Pose) -> [f64; 2]| -> Vec<[f64; 2]> { self.path.iter().map(|(_, p)| f(p)).collect() };
        s += &polyline(&whole(|p| p.tip), "#d9d9d9", 1.5);
        s += &polyline(&so_far(|p| p.tip), "#d55e00", 2.0);
        s += &polyline(&whole(|p| p.base), "#dbe6f0", 1.5);
        s += &polyline(&so_far(|p| p.base), "#0072b2", 2.0);
        // The base at its orientation around its centre of mass, and its own x axis.
        let (sin, cos) = q[0].sin_cos();
        let (w, h) = (BASE_SIZE[0] / 2.0, BASE_SIZE[1] / 2.0);
        let corners: Vec<[f64; 2]> = [[-w, -h], [w, -h], [w, h], [-w, h], [-w, -h]]
            .iter()
            .map(|c| [now.base[0] + cos * c[0] - sin * c[1], now.base[1] + sin * c[0] + cos * c[1]])
            .collect();
        s += &polyline(&corners, "#444", 2.0)
            .replace("fill=\"none\"", "fill=\"rgb(120,120,120)\" fill-opacity=\"0.35\"");
        s += &polyline(&[now.base, [now.base[0] + cos * w, now.base[1] + sin * w]], "#444", 1.0);
        s += &polyline(&[now.base, now.joint1], "#444", 3.0);
        s += &polyline(&[now.joint1, now.joint2], "#0072b2", 6.0);
        s += &polyline(&[now.joint2, now.tip], "#009e73", 6.0);
        s += &dot(now.base, 4.0, "#444");
        s += &dot(now.joint1, 5.0, "#000");
        s += &dot(now.joint2, 5.0, "#000");
        s += &dot(now.tip, 5.0, "#d55e00");
        s += &self.captions(title, t, q[0]);
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
        // The legend, in two columns under the drawing.
        let top = self.height / u - LEGEND + 6.0;
        s += &format!(
            "<line x1=\"0\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"#ddd\" stroke-width=\"{:.2}\"/>\n",
            (top - 4.0) * u,
            self.width,
            (top - 4.0) * u,
            u
        );
        let entries = [
            ("+", "#999", "system's centre of mass (fixed)"),
            ("bar", "#444", "base to mounting point (a, b)"),
            ("bar", "#0072b2", "link 1"),
            ("bar", "#009e73", "link 2"),
            ("line", "#d55e00", "end-effector path"),
            ("line", "#0072b2", "base's centre of mass path"),
        ];
        for (k, (kind, colour, label)) in entries.iter().enumerate() {
            let x = 10.0 + (self.width / u / 2.0) * (k % 2) as f64;
            let y = top + 10.0 + 19.0 * (k / 2) as f64;
            let stroke = |x0: f64, y0: f64, x1: f64, y1: f64, width: f64| {
                format!(
                    "<line x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{colour}\" stroke-width=\"{:.2}\"/>\n",
                    x0 * u,
                    y0 * u,
                    x1 * u,
                    y1 * u,
                    width * u
                )
            };
            s += &match *kind {
                "+" => stroke(x + 6.0, y, x + 18.0, y, 2.0) + &stroke(x + 12.0, y - 6.0, x + 12.0, y + 6.0, 2.0),
                "bar" => stroke(x, y, x + 24.0, y, 4.0),
                _ => stroke(x, y, x + 24.0, y, 2.0),
            };
            s += &text(x + 30.0, y + 4.0, 11.0, "start", label);
        }
        s
    }
}

/// The configuration at time `t` \[s\]: linear between the samples `(ts, qs)` (times ascending),
/// the first or last sample outside them.
fn configuration_at(ts: &[f64], qs: &[[f64; 3]], t: f64) -> [f64; 3] {
    let i = ts.partition_point(|&s| s <= t);
    match (i, qs.len()) {
        (_, 0) => [0.0; 3],
        (0, _) => qs[0],
        (i, n) if i >= n => qs[n - 1],
        (i, _) => {
            let (a, b) = (ts[i - 1], ts[i]);
            let w = if b > a { (t - a) / (b - a) } else { 0.0 };
            std::array::from_fn(|k| qs[i - 1][k] + w * (qs[i][k] - qs[i - 1][k]))
        }
    }
}

/// The palette index of each RGBA pixel; a run of one colour (most of a frame is white) is
/// looked up once.
fn palette_indices(quantiser: &color_quant::NeuQuant, rgba: &[u8]) -> Vec<u8> {
    let mut last: Option<(&[u8], u8)> = None;
    rgba.chunks_exact(4)
        .map(|p| match last {
            Some((colour, index)) if colour == p => index,
            _ => {
                let index = quantiser.index_of(p) as u8;
                last = Some((p, index));
                index
            }
        })
        .collect()
}

/// The drawing's own colours (RGBA): a swatch of each joins the palette's training pixels, so
/// that the robot keeps its exact colours however few pixels it covers.
const SWATCH: [[u8; 4]; 9] = [
    [0xff, 0xff, 0xff, 0xff],
    [0x00, 0x00, 0x00, 0xff],
    [0x44, 0x44, 0x44, 0xff],
    [0x99, 0x99, 0x99, 0xff],
    [0x00, 0x72, 0xb2, 0xff],
    [0x00, 0x9e, 0x73, 0xff],
    [0xd5, 0x5e, 0x00, 0xff],
    [0xd9, 0xd9, 0xd9, 0xff],
    [0xdb, 0xe6, 0xf0, 0xff],
];

/// The animated GIF of `plan`'s motion, titled `title` (see the module's documentation); `path`
/// only labels errors.
///
/// One palette of 255 colours serves every frame (the GIF's global palette: no colour flicker
/// between frames, no palette per frame), and each frame after the first stores only the pixels
/// that changed (the others transparent, over the previous frame kept): the `gif` crate's quantiser (NeuQuant, the
/// `color_quant` crate that [`gif::Frame::from_rgba_speed`] uses per frame) learns it from the
/// first, middle and last frames and a swatch of the drawing's colours. Frames are drawn and
/// mapped to the palette on all of rayon's threads, a few at a time (the memory stays that of a
/// few frames).
pub fn animation_gif(plan: &Plan, title: &str, options: &GifOptions, path: &Path) -> Result<Vec<u8>, Error> {
    let view = GifView::new(plan, options);
    let fail = |e: gif::EncodingError| picture_error(path, e);
    let (w, h) = (options.width as u16, options.height as u16);
    let n = view.frames.len();
    let draw = |k: usize| rgba_pixels(&view.svg(plan, title, k), path).map(|(rgba, _, _)| rgba);
    let mut training = Vec::new();
    for k in [0, n / 2, n - 1] {
        training.extend(draw(k)?);
    }
    for colour in SWATCH {
        training.extend(colour.repeat(4096));
    }
    let quantiser = color_quant::NeuQuant::new(QUANTISER_SPEED, 255, &training);
    drop(training);
    // 255 learnt colours, and one more index for "as in the previous frame".
    let mut palette = quantiser.color_map_rgb();
    palette.resize(3 * 256, 0);
    let mut bytes = Vec::new();
    {
        let mut encoder = gif::Encoder::new(&mut bytes, w, h, &palette).map_err(fail)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(fail)?;
        let batch = 2 * rayon::current_num_threads().max(1);
        let mut previous: Option<Vec<u8>> = None;
        for first in (0..n).step_by(batch) {
            let indexed: Vec<Vec<u8>> = (first..(first + batch).min(n))
                .into_par_iter()
                .map(|k| Ok(palette_indices(&quantiser, &draw(k)?)))
                .collect::<Result<_, Error>>()?;
            for (k, indices) in (first..).zip(indexed) {
                // A pixel as in the previous frame is transparent: the frame is drawn over it.
                let pixels: Vec<u8> = match &previous {
                    Some(before) => {
                        indices.iter().zip(before).map(|(&i, &b)| if i == b { UNCHANGED } else { i }).collect()
                    }
                    None => indices.clone(),
                };
                let mut frame = gif::Frame::from_indexed_pixels(w, h, pixels, Some(UNCHANGED));
                frame.dispose = gif::DisposalMethod::Keep;
                frame.delay = if k + 1 == n { FINAL_HOLD } else { options.delay() };
                encoder.write_frame(&frame).map_err(fail)?;
                previous = Some(indices);
            }
        }
    }
    Ok(bytes)
}
