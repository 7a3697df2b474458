//! An edge the tree holds back, with why and the faces its topples taught (decided in
//! `tree/landing_edges.rs`, `tree/edge_faces.rs`, `tree/rolls_off_shape.rs` and
//! `tree/unlocated.rs`).

use super::Edge;
use crate::face::FaceObservation;
use serde::{Deserialize, Serialize};

/// An edge the tree holds back: it contradicts the faces the landings show, it is a roll's
/// edge off the shape, or its σ does not locate it well enough to be the object's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WithheldEdge {
    /// The edge, as it would be in the tree.
    pub edge: Edge,
    /// Why it is withheld, with numbers.
    pub why: String,
    /// The face observations its topples taught (the rests before and after, with offsets
    /// from this edge), held back with it: a topple whose edge is off the object's faces was
    /// no topple on the support.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub faces: Vec<FaceObservation>,
    /// Withheld for its σ alone (`tree/unlocated.rs`): an estimate of an edge of the object
    /// that nothing contradicts, too loose to be taught.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub unlocated: bool,
}
