//! The parts of a drawing of the learnt object ([`Feature`]), each with how it is known
//! ([`Known`]), and the small formatting helpers the drawings share.

use nalgebra::Vector3;
use serde::Serialize;

/// How a drawn part of the object is known (each kind is described in `model.rs`, the drawing
/// of the object).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Known {
    /// Shown by the demonstrations.
    Seen,
    /// Derived from seen parts.
    Inferred,
    /// Not determined by the data.
    Unknown,
    /// At odds with the other features beyond their uncertainty.
    Contradicted,
}

impl Known {
    /// Every status, in legend order.
    pub const ALL: [Known; 4] = [
        Known::Seen,
        Known::Inferred,
        Known::Unknown,
        Known::Contradicted,
    ];

    /// Its colour in every picture, `[r, g, b]`.
    pub fn rgb(self) -> [u8; 3] {
        match self {
            Known::Seen => [31, 119, 180],
            Known::Inferred => [255, 127, 14],
            Known::Unknown => [127, 127, 127],
            Known::Contradicted => [214, 39, 40],
        }
    }

    /// Its name, as in the JSON (`"seen"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Known::Seen => "seen",
            Known::Inferred => "inferred",
            Known::Unknown => "unknown",
            Known::Contradicted => "contradicted",
        }
    }

    /// What it means, for a legend.
    pub fn meaning(self) -> &'static str {
        match self {
            Known::Seen => "seen: shown by the demonstrations",
            Known::Inferred => "inferred: derived from seen features",
            Known::Unknown => "unknown: not determined by the data",
            Known::Contradicted => "contradicted: at odds with the other features",
        }
    }
}

/// What kind of part a [`Feature`] is, and so how many points it has.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FeatureKind {
    /// A face: its polygon, counter-clockwise seen from outside (3 or more points).
    Face,
    /// An edge: a segment (2 points).
    Edge,
    /// A vertex (1 point).
    Vertex,
    /// The centre of mass (1 point).
    Com,
    /// The object frame's origin (1 point).
    Origin,
    /// An arrow from the first point to the second: the normal of a face whose offset is
    /// unknown, or a direction in which the shape is open.
    Direction,
}

/// One drawable part of the learnt object, in the object frame \[m\].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Feature {
    /// What it is.
    pub kind: FeatureKind,
    /// Its id: the tree's (`e0`, `f2`), `com`, `origin`, `v3` for vertex 3, `f0|f2` for the
    /// inferred edge between faces f0 and f2, `open0`, ... for open directions.
    pub id: String,
    /// How it is known.
    pub known: Known,
    /// Its points (see [`FeatureKind`]).
    pub points: Vec<[f64; 3]>,
    /// How many demonstrations show it (None for inferred parts).
    pub support: Option<usize>,
    /// Standard deviation of its position \[m\], when known.
    pub sigma_m: Option<f64>,
    /// What it is and how well it is known, one fact per line (shown on hover).
    pub info: String,
}

pub(crate) fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

pub(crate) fn mm(x: f64) -> String {
    format!("{:.1} mm", x * 1e3)
}

pub(crate) fn v3(v: &Vector3<f64>) -> String {
    format!("[{:+.4}, {:+.4}, {:+.4}] m", v.x, v.y, v.z)
}
