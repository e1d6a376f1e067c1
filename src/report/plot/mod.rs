//! Pictures (SVG or PNG) of plans (Figs. 4-12), domain maps (Figs. 13-14), mount sweeps and the
//! three methods side by side (Fig. 17), drawn with plotters.
//!
//! Text is laid out with DejaVu Sans, embedded in the binary (the `dejavu` crate; Bitstream Vera
//! license), and registered with plotters' `ab_glyph` renderer: pictures render the same on a
//! machine without any system font. A PNG is the SVG rasterised by resvg (anti-aliased, with the
//! same embedded font and no system font), so both formats show the same picture. Pictures are rendered in memory; the caller writes the bytes
//! (atomically, with [`crate::report::io::write_atomic`]).

use crate::model::InputError;
use std::path::Path;
use std::sync::{Arc, OnceLock};

use crate::error::Error;
use plotters::coord::Shift;
use plotters::prelude::*;

mod animation;
mod domain;
mod gif_scene;
mod gif_writer;
mod legend;
mod methods;
mod plan;
pub mod scene;
mod sweep;
#[cfg(test)]
mod tests;

pub use animation::{
    AT_LIMIT_COLOUR, AT_LIMIT_USE, GifView, LEAST_HOLD, LINK_COLOURS, joints_at_limit, watches_limits,
};
pub use domain::{DOMAIN_PAIR_SIZE, DomainOverlay, domain_pair_picture, domain_picture};
pub use gif_writer::{GifOptions, animation_gif, arm_animation_gif, check_gif_path, two_link_animation_gif};
pub use methods::{METHODS_SIZE, methods_picture};
pub use plan::{BOUNDS_LABEL, Bound, Mark, PLAN_FIGURE_SIZE, Panel, PlanFigure, Series, plan_picture};
pub use sweep::{SWEEP_SIZE, sweep_picture};

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
            let svg = render(path, PictureFormat::Svg, size, painter)?;
            rasterise(&String::from_utf8_lossy(&svg), path)
        }
    }
}

/// The fonts of the rasteriser: the embedded DejaVu Sans only, no system font.
fn font_database() -> Arc<resvg::usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<resvg::usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = resvg::usvg::fontdb::Database::new();
            db.load_font_data(dejavu::sans::regular().to_vec());
            db.load_font_data(dejavu::sans::bold().to_vec());
            db.set_sans_serif_family("DejaVu Sans");
            Arc::new(db)
        })
        .clone()
}

/// How resvg reads an SVG picture: DejaVu Sans, the embedded font only.
fn svg_options() -> resvg::usvg::Options<'static> {
    resvg::usvg::Options {
        font_family: "DejaVu Sans".into(),
        fontdb: font_database(),
        ..resvg::usvg::Options::default()
    }
}

/// Rasterises an SVG picture on white with resvg (anti-aliased, the embedded font only): opaque
/// RGBA pixels, row by row, and the size in pixels.
fn rgba_pixels(svg: &str, path: &Path) -> Result<(Vec<u8>, u32, u32), Error> {
    use resvg::{tiny_skia, usvg};
    let fail = |e: &dyn std::fmt::Display| picture_error(path, e);
    let tree = usvg::Tree::from_str(svg, &svg_options()).map_err(|e| fail(&e))?;
    let size = tree.size().to_int_size();
    let mut pixmap =
        tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| fail(&"the picture has no pixels"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    // Opaque (drawn on white): premultiplied RGBA is plain RGBA.
    Ok((pixmap.take(), size.width(), size.height()))
}

/// Rasterises an SVG picture into an anti-aliased PNG (RGB, 8 bits, on white) with resvg, so
/// that the PNG shows what the SVG shows.
fn rasterise(svg: &str, path: &Path) -> Result<Vec<u8>, Error> {
    let fail = |e: &dyn std::fmt::Display| picture_error(path, e);
    let (rgba, width, height) = rgba_pixels(svg, path)?;
    let size = (width, height);
    let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let mut png_bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut png_bytes, size.0, size.1);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Best);
        encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let mut writer = encoder.write_header().map_err(|e| fail(&e))?;
        writer.write_image_data(&rgb).map_err(|e| fail(&e))?;
    }
    Ok(png_bytes)
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
