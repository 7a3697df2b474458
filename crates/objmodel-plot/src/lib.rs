//! Figures for objmodel, written as SVG and PNG with no system library.
//!
//! Plain data goes in, two files come out: `<path>.svg` and `<path>.png`, each written
//! atomically (to a temporary name in the same folder, then renamed), so a reader never sees
//! a half-written figure. Data are in SI units and angles in radians; the axes show degrees.
//!
//! * [`plot_angles`]: the paper's Fig. 8 — angles over time (for example the box angle relative
//!   to the palm and the palm tilt), a dashed vertical line at the topple onset, a dashed
//!   horizontal line at the CoM angle φ, and red dots at marked instants.
//! * [`plot_side_view`]: the paper's Fig. 5 — outlines of the box and the palm in the plane
//!   normal to the toppling edge at several instants, as small multiples sharing one scale,
//!   with equal aspect ratio (a metre is as long across as it is up).
//! * [`plot_xy`]: generic x-y line plot with a legend.
//! * [`plot_model`]: the paper's Fig. 9a — the learnt object (shape, edges, faces, vertices,
//!   centre of mass, the object frame's origin) in an oblique view, each part coloured by how it
//!   is known ([`Known`]: seen, inferred, unknown, contradicted). Its SVG is written by hand:
//!   every part is one element with `data-kind`, `data-id`, `data-known` and a `<title>` that a
//!   browser shows on hover.
//! * [`view_page`] / [`write_view`]: the learnt object in 3D, one offline HTML page with
//!   three.js inlined (see `assets/three/README.md`): turn it with the mouse, hover for each
//!   feature's support and uncertainty, play the demonstrations back.
//!
//! Text is drawn with the DejaVu Sans font embedded in the library (`include_bytes!`) through
//! plotters' `ab_glyph` support, so neither fontconfig nor freetype is needed, at build or at
//! run time. The SVG files hold text as `<text>` elements (rendered by the viewer with its own
//! sans-serif font); the PNG files have it rasterised from the embedded font.
//!
//! Non-finite values (NaN, ±∞) are skipped: they split a line into separate pieces.
//!
//! ```no_run
//! use objmodel_plot::{plot_angles, AngleSeries, Fig8};
//! use std::path::Path;
//!
//! let t: Vec<f64> = (0..300).map(|i| i as f64 * 0.01).collect();
//! let palm: Vec<f64> = t.iter().map(|t| 0.17 * t).collect();
//! let fig = Fig8 {
//!     title: "Topple demonstration 3".into(),
//!     series: vec![AngleSeries { label: "palm tilt".into(), t, angle_rad: palm }],
//!     onset_t: Some(2.0),
//!     phi_rad: Some(0.34),
//!     marks: vec![("ψe palm".into(), 2.0, 0.34)],
//! };
//! let (svg, png) = plot_angles(&fig, Path::new("out/demo3_angles"))?;
//! # Ok::<(), objmodel_plot::PlotError>(())
//! ```
#![warn(missing_docs)]

mod angles;
mod canvas;
mod common;
mod error;
mod feature;
mod fig9a;
mod fig9a_legend;
mod fig9a_view;
mod figures;
mod model;
mod model_edges;
mod side_view;
mod view;
mod xy;

pub use error::PlotError;
pub use feature::{Feature, FeatureKind, Known};
pub use figures::{AngleSeries, Fig8, Outline, SideView};
pub use model::ModelDrawing;
pub use view::{MAX_PLAYBACK_FRAMES, THREE_VERSION};

use std::path::{Path, PathBuf};

/// Draws the paper's Fig. 8: each series' angle (°) over time (s) on one chart, a dashed
/// vertical line at `onset_t`, a dashed horizontal line at `phi_rad`, and red dots at `marks`.
///
/// Writes `<path_without_ext>.svg` and `<path_without_ext>.png` (creating the folder if needed)
/// and returns their paths in that order.
///
/// # Errors
/// [`PlotError::InvalidInput`] when a series' `t` and `angle_rad` differ in length; otherwise
/// drawing, encoding and I/O errors.
pub fn plot_angles(fig: &Fig8, path_without_ext: &Path) -> Result<(PathBuf, PathBuf), PlotError> {
    angles::plot(fig, path_without_ext)
}

/// Draws the paper's Fig. 5: one panel per frame, in a grid, all with the same scale and an
/// equal aspect ratio, each outline filled lightly and stroked in a colour chosen by its label.
///
/// Writes `<path_without_ext>.svg` and `<path_without_ext>.png` (creating the folder if needed)
/// and returns their paths in that order. With no frames, the figure says so.
///
/// # Errors
/// Drawing, encoding and I/O errors.
pub fn plot_side_view(
    v: &SideView,
    path_without_ext: &Path,
) -> Result<(PathBuf, PathBuf), PlotError> {
    side_view::plot(v, path_without_ext)
}

/// Draws a generic x-y line plot: one line per `(label, points)` series, with a legend of the
/// non-empty labels.
///
/// Writes `<path_without_ext>.svg` and `<path_without_ext>.png` (creating the folder if needed)
/// and returns their paths in that order.
///
/// # Errors
/// Drawing, encoding and I/O errors.
pub fn plot_xy(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(String, Vec<(f64, f64)>)],
    path_without_ext: &Path,
) -> Result<(PathBuf, PathBuf), PlotError> {
    xy::plot(title, x_label, y_label, series, path_without_ext)
}

/// Draws the paper's Fig. 9a: the learnt object of `tree` ([`ModelDrawing::from_tree`]) in an
/// oblique orthographic view of its object frame (z up), each part coloured by how it is known,
/// with a legend and notes on what is unknown.
///
/// Writes `<path_without_ext>.svg` and `<path_without_ext>.png` (creating the folder if needed)
/// and returns their paths in that order.
///
/// # Errors
/// Drawing, encoding and I/O errors.
pub fn plot_model(
    tree: &objmodel::tree::Tree,
    title: &str,
    path_without_ext: &Path,
) -> Result<(PathBuf, PathBuf), PlotError> {
    fig9a::plot(&ModelDrawing::from_tree(tree), title, path_without_ext)
}

/// The learnt object of `tree` in 3D as one self-contained, offline HTML page titled `title`
/// (three.js inlined): edges, faces, vertices, the centre of mass, each feature's support and
/// uncertainty on hover, and `demos` to play back (their poses, at most
/// [`MAX_PLAYBACK_FRAMES`] each).
pub fn view_page(
    tree: &objmodel::tree::Tree,
    title: &str,
    demos: &[objmodel::Demonstration],
) -> String {
    view::page(tree, title, demos)
}

/// Writes [`view_page`] to `path` atomically (creating the folder if needed) and returns it.
///
/// # Errors
/// I/O errors, naming the file.
pub fn write_view(
    tree: &objmodel::tree::Tree,
    title: &str,
    demos: &[objmodel::Demonstration],
    path: &Path,
) -> Result<PathBuf, PlotError> {
    view::write(tree, title, demos, path)
}
