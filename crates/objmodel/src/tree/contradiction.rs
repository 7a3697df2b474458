//! A contradiction between features of the tree (found by the checks, `tree/checks.rs`, and
//! the pendulums' test against the CoM of the others, `tree/com_conflicts.rs`).

use serde::{Deserialize, Serialize};

/// Two (or more) features of the tree that their uncertainties cannot reconcile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contradiction {
    /// The features' ids (`e1`, `f2`, `com`).
    pub features: Vec<String>,
    /// What disagrees, with numbers.
    pub what: String,
}
