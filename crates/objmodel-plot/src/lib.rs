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
mod fig9a;
mod fig9a_legend;
mod model;
mod model_edges;
mod side_view;
mod view;
mod xy;

pub use model::{Feature, FeatureKind, Known, ModelDrawing};
pub use view::{MAX_PLAYBACK_FRAMES, THREE_VERSION};

use std::path::{Path, PathBuf};

/// One angle signal sampled over time, for [`Fig8`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AngleSeries {
    /// Name shown in the legend, e.g. `"box angle relative to palm"`.
    pub label: String,
    /// Sample times (s); same length as `angle_rad`.
    pub t: Vec<f64>,
    /// Angle at each sample (rad); plotted in degrees.
    pub angle_rad: Vec<f64>,
}

/// Data for the paper's Fig. 8: angles over time around a topple.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fig8 {
    /// Figure title, drawn above the chart.
    pub title: String,
    /// Angle signals, overlaid on one chart (e.g. box angle relative to the palm, palm tilt).
    pub series: Vec<AngleSeries>,
    /// Time of the topple onset (s): drawn as a dashed vertical line.
    pub onset_t: Option<f64>,
    /// CoM angle φ from the edge (rad): drawn as a dashed horizontal line.
    pub phi_rad: Option<f64>,
    /// Marked points `(label, t [s], angle [rad])`: drawn as red dots with their label
    /// and value, e.g. the box and palm angles at the onset.
    pub marks: Vec<(String, f64, f64)>,
}

/// A closed polygon in the plane of a [`SideView`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Outline {
    /// Name of the body, e.g. `"box"` or `"palm"`; outlines with the same label get the same
    /// colour in every panel.
    pub label: String,
    /// Vertices `[horizontal, vertical]` (m) in the plane normal to the edge, vertical pointing
    /// up; the polygon is closed (the last vertex joins the first).
    pub points: Vec<[f64; 2]>,
}

/// Data for the paper's Fig. 5: body outlines in the plane normal to an edge at several
/// instants.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SideView {
    /// Figure title, drawn above the panels.
    pub title: String,
    /// One panel per entry: the time (s) and the outlines at that time.
    pub frames: Vec<(f64, Vec<Outline>)>,
}

/// Why a figure could not be made; every message names the file concerned.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The data cannot be plotted as given (e.g. times and angles of different lengths).
    #[error("{}: invalid plot data: {reason}", .path.display())]
    InvalidInput {
        /// File that was to be written.
        path: PathBuf,
        /// What is wrong with the data.
        reason: String,
    },
    /// The embedded font could not be registered with plotters.
    #[error("{}: the embedded font could not be loaded", .path.display())]
    Font {
        /// File that was to be written.
        path: PathBuf,
    },
    /// Plotters failed while drawing.
    #[error("{}: drawing failed: {reason}", .path.display())]
    Draw {
        /// File that was being drawn.
        path: PathBuf,
        /// Plotters' message.
        reason: String,
    },
    /// The PNG encoder failed.
    #[error("{}: PNG encoding failed: {reason}", .path.display())]
    Encode {
        /// File that was being encoded.
        path: PathBuf,
        /// The encoder's message.
        reason: String,
    },
    /// Creating the folder, writing the temporary file or renaming it failed.
    #[error("{}: {source}", .path.display())]
    Io {
        /// File (or folder) concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

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
