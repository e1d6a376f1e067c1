//! The animated GIF of a plan's motion (`--gif`): its size and frame rate, and the encoding of
//! the frames that [`GifView`] draws, for the paper's 2-link robot and for any planar serial arm.
//!
//! Each frame (an SVG picture, see [`GifView`]) is rasterised with resvg (the embedded font only,
//! as the PNGs) and encoded by the `gif` crate, the image-rs project's GIF codec (pure Rust, LZW),
//! with one palette for all frames learnt by its quantiser (NeuQuant, see [`animation_gif`]).
//!
//! Playback: the plan's horizon `T` is shown in a loop of `T` seconds clamped to 5 to 8 s (a 10 s
//! plan plays in 8 s, a 2 s plan in 5 s), at [`GifOptions::fps`] frames per second, then the
//! final pose is held for 1 s and the GIF starts again (infinite loop). GIF delays are counted in
//! hundredths of a second: each frame lasts `round(100 / fps)` of them.

use std::path::Path;

use rayon::prelude::*;

use super::animation::{AT_LIMIT_COLOUR, LEAST_HOLD, LINK_COLOURS};
use super::scene::{CLEAR_COLOUR, OBSTACLE_COLOUR};
use super::{GifView, picture_error, rgba_pixels};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::collision::Geometry;
use crate::plan::Plan;
use crate::plan::clearance::ClearanceReport;
use crate::planners::arm::ArmPlanned;

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

/// The hold on the final pose before the loop starts again \[hundredths of a second\].
const FINAL_HOLD: u16 = 100;
/// The palette index of a pixel unchanged since the previous frame (transparent).
const UNCHANGED: u8 = 255;
/// NeuQuant's sampling factor (1 best and slowest, 30 fastest): it learns the palette once, and the
/// swatch keeps the drawing's colours exact.
const QUANTISER_SPEED: i32 = 5;

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

/// The drawing's own colours besides the links' ([`LINK_COLOURS`]), as `#rrggbb`: a swatch of
/// each joins the palette's training pixels, so that the robot keeps its exact colours however
/// few pixels it covers.
const SWATCH: [&str; 8] =
    ["#ffffff", "#000000", "#444444", "#999999", "#d55e00", "#d9d9d9", "#dbe6f0", AT_LIMIT_COLOUR];

/// The RGBA of a `#rrggbb` colour (black if malformed).
fn rgba(colour: &str) -> [u8; 4] {
    let channel = |k: usize| colour.get(1 + 2 * k..3 + 2 * k).and_then(|h| u8::from_str_radix(h, 16).ok());
    [channel(0).unwrap_or(0), channel(1).unwrap_or(0), channel(2).unwrap_or(0), 0xff]
}

/// The animated GIF of `plan`'s motion (the paper's 2-link robot), titled `title` (see the
/// module's documentation); `path` only labels errors.
///
/// One palette of 255 colours serves every frame (the GIF's global palette: no colour flicker
/// between frames, no palette per frame), and each frame after the first stores only the pixels
/// that changed (the others transparent, over the previous frame kept): the `gif` crate's quantiser (NeuQuant, the
/// `color_quant` crate that [`gif::Frame::from_rgba_speed`] uses per frame) learns it from the
/// first, middle and last frames and a swatch of the drawing's colours. Frames are drawn and
/// mapped to the palette on all of rayon's threads, a few at a time (the memory stays that of a
/// few frames).
pub fn animation_gif(plan: &Plan, title: &str, options: &GifOptions, path: &Path) -> Result<Vec<u8>, Error> {
    encode(&GifView::new(plan, options), title, path)
}

/// The animated GIF of the 2-link `plan` as [`animation_gif`] draws it, with the robot's shapes
/// and the obstacles of `geometry` and the least clearance `least` of the verified motion
/// ([`GifView::two_link`]); without shapes and obstacles the same bytes as [`animation_gif`].
pub fn two_link_animation_gif(
    plan: &Plan,
    geometry: &Geometry,
    least: Option<ClearanceReport>,
    title: &str,
    options: &GifOptions,
    path: &Path,
) -> Result<Vec<u8>, Error> {
    encode(&GifView::two_link(plan, geometry, least, options)?, title, path)
}

/// The animated GIF of an arm's motion (any number of links), titled `title`: drawn and encoded
/// as [`animation_gif`] draws the 2-link robot's; `path` only labels errors.
pub fn arm_animation_gif(
    planned: &ArmPlanned,
    title: &str,
    options: &GifOptions,
    path: &Path,
) -> Result<Vec<u8>, Error> {
    encode(&GifView::arm(planned, options), title, path)
}

/// The GIF of `view`'s frames (see [`animation_gif`]).
fn encode(view: &GifView, title: &str, path: &Path) -> Result<Vec<u8>, Error> {
    let options = view.options();
    let fail = |e: gif::EncodingError| picture_error(path, e);
    let (w, h) = (options.width as u16, options.height as u16);
    let n = view.frames().len();
    let draw = |k: usize| rgba_pixels(&view.svg(title, k), path).map(|(rgba, _, _)| rgba);
    let mut training = Vec::new();
    for k in [0, n / 2, n - 1] {
        training.extend(draw(k)?);
    }
    for colour in SWATCH.iter().chain(&LINK_COLOURS) {
        training.extend(rgba(colour).repeat(4096));
    }
    // The scene's own colours, only where there is a scene (a robot without shapes keeps its bytes).
    if view.scene().is_some() {
        // The obstacle's edge, its fill over white (45 % of it), and the marker's purple.
        for colour in [OBSTACLE_COLOUR, "#b7b7b7", CLEAR_COLOUR] {
            training.extend(rgba(colour).repeat(4096));
        }
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
                frame.delay = if k + 1 == n {
                    FINAL_HOLD
                } else if view.marked() == Some(k) {
                    LEAST_HOLD
                } else {
                    options.delay()
                };
                encoder.write_frame(&frame).map_err(fail)?;
                previous = Some(indices);
            }
        }
    }
    Ok(bytes)
}
