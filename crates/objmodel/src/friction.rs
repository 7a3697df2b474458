//! What the demonstrations tell of the friction between the object and its support.
//!
//! Kinematics alone says little: a push's force is not measured, so a slide or a pushed topple
//! bounds nothing. An instrumented topple does: the object rested on the palm, without
//! sliding, until the palm's tilt reached φ_onset, where it started to topple about its edge.
//! Resting on a slope of angle θ needs `μ ≥ tan θ`, so each such demonstration gives the
//! **lower bound** `μ > tan(φ_onset - 2 σ_φ)` (2 σ below the measured tilt, so that a noisy
//! onset does not claim a bound it has not shown); the largest over the demonstrations is
//! kept. An **estimate** would need the tilt at which the object starts to slide instead
//! (`μ ≈ tan θ_slide`): the classification does not detect a slide on a tilting palm yet, so
//! there is none; a bound is a bound, not a value.

use crate::tree::Tree;
use serde::{Deserialize, Serialize};

/// The friction the demonstrations show.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionEvidence {
    /// μ the data determine (a slide on a tilting palm), when they do.
    pub estimate: Option<f64>,
    /// μ is above this: the object held on the palm, without sliding, up to the tilt where it
    /// toppled.
    pub lower_bound: Option<f64>,
    /// The demonstration that gives the bound.
    pub bound_from: Option<String>,
    /// How it was found.
    pub note: String,
}

/// The friction evidence of `tree`, `None` when no demonstration tells anything of it.
pub fn evidence(tree: &Tree) -> Option<FrictionEvidence> {
    let mut best: Option<(f64, &str)> = None;
    for e in &tree.edges {
        for p in &e.pendulums {
            for o in &p.observations {
                let Some(onset) = o.phi_onset else { continue };
                let tilt = onset - 2.0 * o.phi_sigma.max(0.0);
                if !(tilt.is_finite() && tilt > 0.0 && tilt < std::f64::consts::FRAC_PI_2) {
                    continue;
                }
                let mu = tilt.tan();
                if best.is_none_or(|(b, _)| mu > b) {
                    best = Some((mu, &o.demo));
                }
            }
        }
    }
    let (mu, demo) = best?;
    Some(FrictionEvidence {
        estimate: None,
        lower_bound: Some(mu),
        bound_from: Some(demo.to_string()),
        note: format!(
            "lower bound: '{demo}' held on the tilting palm without sliding up to its topple \
             onset, so μ > tan(onset tilt - 2σ) = {mu:.2}; no demonstration slid on a tilting \
             palm, so no estimate"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tree::{Edge, Pendulum, PendulumObservation};
    use nalgebra::Vector3;

    fn observation(demo: &str, onset: Option<f64>, sigma: f64) -> PendulumObservation {
        PendulumObservation {
            demo: demo.into(),
            phi: 0.4,
            phi_sigma: sigma,
            phi_onset: onset,
            phi_fall: None,
            inertia_ratio_m: None,
            onset_t: None,
        }
    }

    /// The largest onset tilt, less two sigmas, bounds μ from below; topples without a palm
    /// tell nothing.
    #[test]
    fn instrumented_topples_bound_the_friction_from_below() {
        let mut tree = Tree::default();
        assert!(evidence(&tree).is_none());
        let mut e: Edge = serde_json::from_value(serde_json::json!({
            "id": "e0", "point": [0.0, 0.0, 0.0], "direction": [0.0, 1.0, 0.0],
            "point_cov": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], "direction_cov": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
            "sigma_point_m": 0.0, "sigma_direction_rad": 0.0, "support": [], "n_support": 1,
            "faces": [], "pendulums": [], "observations": []
        }))
        .unwrap();
        e.pendulums.push(Pendulum {
            resting_face_normal: -Vector3::z(),
            toppling_axis: Vector3::y(),
            phi: Some(0.4),
            l_p: None,
            phi_sigma: Some(0.01),
            inertia_ratio_m: None,
            support: vec![],
            observations: vec![
                observation("pushed", None, 0.01),
                observation("palm1", Some(0.40), 0.01),
                observation("palm2", Some(0.50), 0.02),
            ],
            com_conflict: None,
        });
        tree.edges.push(e);
        let f = evidence(&tree).unwrap();
        assert!((f.lower_bound.unwrap() - 0.46f64.tan()).abs() < 1e-12);
        assert_eq!(f.bound_from.as_deref(), Some("palm2"));
        assert!(f.estimate.is_none());
        tree.edges[0].pendulums[0].observations.drain(1..);
        assert!(evidence(&tree).is_none());
    }
}
