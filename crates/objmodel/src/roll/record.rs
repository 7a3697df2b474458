//! A roll as a classification records it: where in the stream, the edge it turned about and
//! what it taught (found by [`super::mark_rolls`]).

use crate::edge::EdgeObservation;
use serde::{Deserialize, Serialize};

/// One roll of a demonstration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Roll {
    /// Index of its first frame in the object stream.
    pub first: usize,
    /// Index of its last frame.
    pub last: usize,
    /// Time of its first frame \[s\].
    pub t_start: f64,
    /// Time of its last frame \[s\].
    pub t_end: f64,
    /// The edge it turned about, object frame, with its covariance.
    pub edge: EdgeObservation,
    /// The angle it turned about the edge \[rad\].
    pub turn: f64,
    /// χ² of the fixed-line fit and its degrees of freedom.
    pub chi2: f64,
    /// Degrees of freedom of that χ².
    pub dof: f64,
    /// Whether its edge is taught (enters the tree).
    pub taught: bool,
    /// Why it taught nothing, when it did not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub withheld: Option<String>,
    /// The support's height it measured (its edge, on the support, in the world), when it
    /// taught its edge and gravity is known ([`crate::support`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support: Option<crate::support::SupportObservation>,
}

/// A turn that looked like a roll and is not one: a window of a motion that the fixed-line
/// model explained, about a level line, over enough frames and far enough to locate the line,
/// which a later test rejected (its χ² at the tests' level, a line off the object, or the free
/// fall of a point of the object explaining it too). Reported so that a user sees why a motion
/// that turned over an edge taught none; it teaches nothing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RejectedRoll {
    /// Time of its first frame \[s\].
    pub t_start: f64,
    /// Time of its last frame \[s\].
    pub t_end: f64,
    /// Its frames (outliers left out).
    pub frames: usize,
    /// The angle it turned about its line \[rad\].
    pub turn: f64,
    /// Why it is no roll.
    pub why: String,
}
