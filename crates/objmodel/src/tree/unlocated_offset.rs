//! A face's offset that the tree does not teach because its σ does not locate it well enough
//! (decided in `tree/unlocated.rs`).

use serde::{Deserialize, Serialize};

/// A face's offset that its σ does not locate within [`super::FACE_OFFSET_MATCH_M`] at
/// [`super::LOCATED_ALPHA`]: the estimate, kept for the reader, not taught.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnlocatedOffset {
    /// The offset's estimate \[m\].
    pub offset: f64,
    /// Its standard deviation \[m\].
    pub sigma_m: f64,
    /// Why it is not the face's, with numbers.
    pub why: String,
}
