//! The legend of an animation's frame, laid out in rows: entries left to right, a new row when
//! the next one would pass the right edge. Each label's width is measured with the font the
//! frame is rasterised with (DejaVu Sans, through resvg), so that no entry overlaps another
//! whatever the labels and the number of links (two fixed columns made "system's centre of mass
//! (fixed)" run into the entry beside it; `page.js` lays out its legend the same way, measuring
//! with the browser's font).

use resvg::usvg;

use crate::report::html::escape;

/// How an entry's sample is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Swatch {
    /// A small "+" (the system's centre of mass).
    Cross,
    /// A thick bar (a body).
    Bar,
    /// A thin line (a path).
    Line,
}

/// One entry: its sample, colour (`#rrggbb`) and label.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Entry {
    pub swatch: Swatch,
    pub colour: String,
    pub label: String,
}

impl Entry {
    pub fn new(swatch: Swatch, colour: &str, label: &str) -> Self {
        Self { swatch, colour: colour.into(), label: label.into() }
    }
}

/// Width of an entry's sample \[px at 480\].
pub(super) const SWATCH_WIDTH: f64 = 24.0;
/// From the sample's start to its label \[px at 480\].
pub(super) const LABEL_OFFSET: f64 = 30.0;
/// The labels' font size \[px at 480\].
pub(super) const FONT_SIZE: f64 = 11.0;
/// Room between two entries of a row \[px at 480\].
const ENTRY_GAP: f64 = 18.0;
/// Left and right margin \[px at 480\].
const EDGE: f64 = 10.0;
/// Height of a row \[px at 480\].
pub(super) const ROW: f64 = 19.0;
/// From the strip's top to the first row's middle \[px at 480\].
pub(super) const FIRST_ROW: f64 = 16.0;

/// The legend laid out: each entry with its left edge and row, and the strip's height.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Legend {
    /// Entries, their left edge \[px at 480\] and their row (from 0), with their width.
    pub placed: Vec<(Entry, f64, usize, f64)>,
    /// Number of rows.
    pub rows: usize,
}

impl Legend {
    /// Lays out `entries` in rows of at most `room` \[px at 480\] (the frame's width in layout
    /// units): an entry starts a new row when it would pass `room - EDGE`, unless it is the
    /// row's first (then it stands alone, however wide).
    pub fn new(entries: Vec<Entry>, room: f64) -> Self {
        let labels: Vec<&str> = entries.iter().map(|e| e.label.as_str()).collect();
        let widths = label_widths(&labels);
        let mut placed = Vec::with_capacity(entries.len());
        let (mut x, mut row) = (EDGE, 0);
        for (entry, label) in entries.into_iter().zip(widths) {
            let width = LABEL_OFFSET + label;
            if x > EDGE && x + width > room - EDGE {
                (x, row) = (EDGE, row + 1);
            }
            placed.push((entry, x, row, width));
            x += width + ENTRY_GAP;
        }
        let rows = placed.last().map_or(0, |p| p.2 + 1);
        Self { placed, rows }
    }

    /// The strip's height \[px at 480\]: to the first row, the rows, and room under the last
    /// row's text.
    pub fn height(&self) -> f64 {
        FIRST_ROW + ROW * (self.rows.max(1) - 1) as f64 + 12.0
    }
}

/// The width of each label at [`FONT_SIZE`] \[px at 480\]: its ink's extent as resvg lays it out
/// with the embedded font, plus one pixel of side bearings; `0.62` of the font size per
/// character (DejaVu Sans's mean advance is about 0.55) when the font cannot lay it out.
fn label_widths(labels: &[&str]) -> Vec<f64> {
    let texts: String = labels
        .iter()
        .enumerate()
        .map(|(k, label)| {
            format!(
                "<text id=\"l{k}\" x=\"0\" y=\"{y}\" font-size=\"{FONT_SIZE}\">{}</text>",
                escape(label),
                y = 20.0 * (k + 1) as f64
            )
        })
        .collect();
    let svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"2000\" height=\"{}\" font-family=\"DejaVu Sans\">{texts}</svg>",
        20 * (labels.len() + 2)
    );
    let tree = usvg::Tree::from_str(&svg, &super::svg_options()).ok();
    labels
        .iter()
        .enumerate()
        .map(|(k, label)| {
            let estimate = 0.62 * FONT_SIZE * label.chars().count() as f64;
            let measured = tree.as_ref().and_then(|t| t.node_by_id(&format!("l{k}"))).map(|node| {
                let b = node.abs_bounding_box();
                f64::from(b.right()) + 1.0
            });
            measured.filter(|w| w.is_finite() && *w > 0.0).unwrap_or(estimate)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(links: usize) -> Vec<Entry> {
        let mut e = vec![
            Entry::new(Swatch::Cross, "#999", "system's centre of mass (fixed)"),
            Entry::new(Swatch::Bar, "#444", "base to mounting point (a, b)"),
        ];
        e.extend((1..=links).map(|k| Entry::new(Swatch::Bar, "#000", &format!("link {k}"))));
        e.push(Entry::new(Swatch::Line, "#d55e00", "end-effector path"));
        e
    }

    /// Labels are measured with the font: a longer label is wider, about 0.5 to 0.7 of the font
    /// size per character (DejaVu Sans), and wider than the tight estimate a fixed column took.
    #[test]
    fn labels_are_measured_with_the_embedded_font() {
        let w = label_widths(&["link 1", "system's centre of mass (fixed)", "mmmm", "iiii"]);
        assert!(w[1] > w[0] && w[2] > w[3], "{w:?}");
        let per_char = w[1] / 31.0 / FONT_SIZE;
        assert!((0.45..0.7).contains(&per_char), "{per_char}");
    }

    /// For any number of links and any frame width, entries of a row never overlap and stay
    /// within the frame (up to its right margin), in the given order.
    #[test]
    fn entries_never_overlap() {
        for links in 1..=15 {
            for room in [480.0, 640.0, 960.0, 1920.0] {
                let legend = Legend::new(entries(links), room);
                assert_eq!(legend.placed.len(), links + 3);
                for pair in legend.placed.windows(2) {
                    let ((_, x0, r0, w0), (_, x1, r1, _)) = (&pair[0], &pair[1]);
                    assert!(r1 > r0 || (r1 == r0 && *x1 >= x0 + w0 + 10.0), "{links} links, {room}: {pair:?}");
                }
                assert!(legend.placed.iter().all(|(_, x, _, w)| x + w <= room - EDGE), "{links} links, {room}");
                assert!(legend.height() >= ROW * legend.rows as f64);
            }
        }
    }
}
