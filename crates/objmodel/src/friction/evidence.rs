//! The friction the demonstrations show, as the tree keeps it (found by [`super::evidence`]).

use serde::{Deserialize, Serialize};

/// The friction the demonstrations show.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionEvidence {
    /// μ the data determine (a slide on a tilting palm), when they do.
    pub estimate: Option<f64>,
    /// Its standard deviation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimate_sigma: Option<f64>,
    /// The demonstrations that slid on the palm.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub estimate_from: Vec<String>,
    /// μ is above this: the object held on the palm, without sliding, up to the tilt where it
    /// toppled.
    pub lower_bound: Option<f64>,
    /// The demonstration that gives the bound.
    pub bound_from: Option<String>,
    /// How it was found.
    pub note: String,
}
