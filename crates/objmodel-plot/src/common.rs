//! Shared pieces: the embedded font, rendering to both backends, atomic writes, ranges, colours.

use std::ffi::OsString;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::PlotError;

/// DejaVu Sans (Bitstream Vera licence, see `assets/DejaVuSans-LICENSE.txt`).
static DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Font family used for all text.
pub(crate) const FONT: &str = "sans-serif";

/// Registers the embedded font once per process under every generic family name plotters uses.
fn ensure_font() -> bool {
    static OK: OnceLock<bool> = OnceLock::new();
    *OK.get_or_init(|| {
        ["sans-serif", "serif", "monospace"].iter().all(|name| {
            plotters::style::register_font(name, FontStyle::Normal, DEJAVU_SANS).is_ok()
        })
    })
}

/// Error text from plotters, whatever the backend.
pub(crate) type DrawResult = Result<(), String>;

/// Converts any displayable error into the message carried by [`PlotError::Draw`].
pub(crate) fn de<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// A figure that can draw itself on any plotters backend.
pub(crate) trait Figure {
    /// Size in pixels (SVG user units and PNG pixels alike).
    fn size(&self) -> (u32, u32);
    /// Draws onto a blank root area.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult;
}

/// `base` with `.ext` appended (not replacing an extension `base` may seem to have).
fn with_suffix(base: &Path, ext: &str) -> PathBuf {
    let mut s: OsString = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Draws `fig` on a white `root` and flushes it; errors name `path`, the file it is for.
fn paint<F: Figure, DB: DrawingBackend>(
    fig: &F,
    root: DrawingArea<DB, Shift>,
    path: &Path,
) -> Result<(), PlotError> {
    root.fill(&WHITE)
        .map_err(de)
        .and_then(|()| fig.draw(&root))
        .and_then(|()| root.present().map_err(de))
        .map_err(|reason| PlotError::Draw {
            path: path.to_path_buf(),
            reason,
        })
}

/// Renders `fig` to SVG and PNG and writes both atomically next to `base`.
pub(crate) fn render<F: Figure>(base: &Path, fig: &F) -> Result<(PathBuf, PathBuf), PlotError> {
    let svg_path = with_suffix(base, "svg");
    if !ensure_font() {
        return Err(PlotError::Font { path: svg_path });
    }
    let (w, h) = fig.size();
    let mut svg = String::new();
    paint(
        fig,
        SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area(),
        &svg_path,
    )?;
    render_with_svg(base, fig, &svg)
}

/// Writes `svg` (made otherwise) and `fig` rendered to PNG, atomically next to `base`.
pub(crate) fn render_with_svg<F: Figure>(
    base: &Path,
    fig: &F,
    svg: &str,
) -> Result<(PathBuf, PathBuf), PlotError> {
    let svg_path = with_suffix(base, "svg");
    let png_path = with_suffix(base, "png");
    if !ensure_font() {
        return Err(PlotError::Font { path: png_path });
    }
    let (w, h) = fig.size();
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    paint(
        fig,
        BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area(),
        &png_path,
    )?;
    let png_bytes = encode_png(&rgb, w, h).map_err(|e| PlotError::Encode {
        path: png_path.clone(),
        reason: e.to_string(),
    })?;
    ensure_dir(base)?;
    write_atomic(&svg_path, svg.as_bytes())?;
    write_atomic(&png_path, &png_bytes)?;
    Ok((svg_path, png_path))
}

/// Creates the folder `path` is in, if it has one.
pub(crate) fn ensure_dir(path: &Path) -> Result<(), PlotError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).map_err(|source| PlotError::Io {
            path: dir.to_owned(),
            source,
        })?;
    }
    Ok(())
}

/// Encodes an 8-bit RGB buffer as PNG.
fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Default);
        let mut writer = enc.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()?;
    }
    Ok(out)
}

/// Writes `bytes` to a temporary file in `path`'s folder, flushes it, then renames it over
/// `path`, so readers see either the old file or the whole new one.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        fs::rename(&tmp, path)
    })();
    result.map_err(|source| {
        let _ = fs::remove_file(&tmp);
        PlotError::Io {
            path: path.to_owned(),
            source,
        }
    })
}

/// Line colours (Tableau 10 without its red, which is kept for marks).
const PALETTE: [RGBColor; 9] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colour of the `i`-th series.
pub(crate) fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Colour of marked points.
pub(crate) const MARK_RED: RGBColor = RGBColor(214, 39, 40);
/// Grid lines.
pub(crate) const GRID_BOLD: RGBColor = RGBColor(215, 215, 215);
/// Fine grid lines.
pub(crate) const GRID_LIGHT: RGBColor = RGBColor(238, 238, 238);

/// Range covering the finite values, padded by `pad` of its width on each side; a single value
/// gets a small range around it, no value gets `0..1`.
pub(crate) fn span(values: impl IntoIterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.into_iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return (0.0, 1.0);
    }
    let width = hi - lo;
    if width <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let half = if lo.abs() > 0.0 { 0.1 * lo.abs() } else { 1.0 };
        return (lo - half, hi + half);
    }
    (lo - pad * width, hi + pad * width)
}

/// Tick label formatter for an axis over `lo..hi` with about `n` labels: as many decimals as
/// the tick spacing needs, the same for every label, and no "-0".
pub(crate) fn tick_formatter(lo: f64, hi: f64, n: usize) -> impl Fn(&f64) -> String {
    let step = (hi - lo).abs() / n.max(1) as f64;
    let decimals = if step > 0.0 && step.is_finite() {
        (-step.log10()).ceil().clamp(0.0, 9.0) as usize
    } else {
        3
    };
    move |v: &f64| {
        let s = format!("{v:.decimals$}");
        if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
            s[1..].to_owned()
        } else {
            s
        }
    }
}

/// Splits points into runs of consecutive finite points.
pub(crate) fn finite_runs(points: impl IntoIterator<Item = (f64, f64)>) -> Vec<Vec<(f64, f64)>> {
    let mut runs = vec![Vec::new()];
    for p in points {
        if p.0.is_finite() && p.1.is_finite() {
            runs.last_mut().expect("never empty").push(p);
        } else if !runs.last().expect("never empty").is_empty() {
            runs.push(Vec::new());
        }
    }
    runs.retain(|r| !r.is_empty());
    runs
}

/// Legend swatch: a short horizontal line.
pub(crate) fn legend_line(style: ShapeStyle) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style)
}

/// Legend swatch: a short dashed line, for reference lines.
pub(crate) fn legend_dashes(
    style: ShapeStyle,
) -> impl Fn((i32, i32)) -> DashedPathElement<std::vec::IntoIter<(i32, i32)>, i32> {
    move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 26, y)], 7, 4, style)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn span_pads_and_handles_degenerate_input() {
        assert_eq!(span([], 0.1), (0.0, 1.0));
        assert_eq!(span([f64::NAN], 0.1), (0.0, 1.0));
        assert_eq!(span([0.0, 10.0], 0.1), (-1.0, 11.0));
        assert_eq!(span([0.0, 0.0], 0.1), (-1.0, 1.0));
        let (lo, hi) = span([2.0], 0.1);
        assert!(lo < 2.0 && hi > 2.0);
    }

    #[test]
    fn finite_runs_split_at_non_finite_points() {
        let runs = finite_runs([
            (0.0, 0.0),
            (1.0, f64::NAN),
            (2.0, 2.0),
            (3.0, 3.0),
            (f64::INFINITY, 0.0),
        ]);
        assert_eq!(runs, vec![vec![(0.0, 0.0)], vec![(2.0, 2.0), (3.0, 3.0)]]);
    }

    #[test]
    fn tick_labels_have_even_decimals_and_no_negative_zero() {
        let f = tick_formatter(-10.0, 95.0, 10);
        assert_eq!((f(&90.0), f(&-0.0001)), ("90".to_owned(), "0".to_owned()));
        let f = tick_formatter(-0.12, 0.22, 6);
        assert_eq!(
            (f(&0.1), f(&0.15), f(&-1e-9)),
            ("0.10".to_owned(), "0.15".to_owned(), "0.00".to_owned())
        );
        let f = tick_formatter(0.0, 3.6, 12);
        assert_eq!(f(&2.5), "2.5");
    }

    #[test]
    fn suffix_is_appended_not_replaced() {
        assert_eq!(
            with_suffix(Path::new("a/fig.v2"), "svg"),
            PathBuf::from("a/fig.v2.svg")
        );
    }
}
