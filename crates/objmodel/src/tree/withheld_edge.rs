//! An edge the tree holds back, with why and the faces its topples taught (decided in
//! `tree/landing_edges.rs` and `tree/rolls_off_shape.rs`).

use super::Edge;
use crate::face::FaceObservation;
use serde::{Deserialize, Serialize};

/// An edge the tree holds back: it contradicts the faces the landings show, or it is a roll's
/// edge off the shape.
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
}
