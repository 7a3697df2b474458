//! What the demonstrations tell of the friction between the object and its support.
//!
//! Kinematics alone says little: a push's force is not measured, so a slide or a pushed topple
//! bounds nothing. An instrumented topple does: the object rested on the palm, without
//! sliding, until the palm's tilt reached φ_onset, where it started to topple about its edge.
//! Resting on a slope of angle θ needs `μ ≥ tan θ`, so each such demonstration gives the
//! **lower bound** `μ > tan(φ_onset - 2 σ_φ)` (2 σ below the measured tilt, so that a noisy
//! onset does not claim a bound it has not shown); the largest over the demonstrations is
//! kept. An **estimate** needs an instrumented demonstration whose object slid down the
//! tilting palm instead: the Coulomb slide fitted to it ([`crate::dynamics::palm_slide`])
//! gives μ with its σ, and the estimate is their weighted mean over such demonstrations.

mod evidence;

pub use evidence::FrictionEvidence;

use crate::dynamics::PalmSlide;
use crate::tree::Tree;

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
    let slides: Vec<(&str, &PalmSlide)> = tree
        .demos
        .iter()
        .filter_map(|d| d.palm_slide.as_ref().map(|s| (d.name.as_str(), s)))
        .collect();
    let estimate = estimate(&slides);
    if best.is_none() && estimate.is_none() {
        return None;
    }
    let mut notes = Vec::new();
    if let Some((mu, sigma)) = estimate {
        notes.push(format!(
            "estimate: {} slid on the tilting palm; μ = {mu:.3} ± {sigma:.3} (the Coulomb \
             slide fitted to each, weighted mean)",
            if slides.len() == 1 {
                format!("'{}'", slides[0].0)
            } else {
                format!("{} demonstrations", slides.len())
            }
        ));
    }
    match best {
        Some((mu, demo)) => notes.push(format!(
            "lower bound: '{demo}' held on the tilting palm without sliding up to its topple \
             onset, so μ > tan(onset tilt - 2σ) = {mu:.2}"
        )),
        None => notes.push("no instrumented topple bounds it".into()),
    }
    if estimate.is_none() {
        notes.push("no demonstration slid on a tilting palm, so no estimate".into());
    }
    Some(FrictionEvidence {
        estimate: estimate.map(|e| e.0),
        estimate_sigma: estimate.map(|e| e.1),
        estimate_from: slides.iter().map(|(d, _)| d.to_string()).collect(),
        lower_bound: best.map(|b| b.0),
        bound_from: best.map(|b| b.1.to_string()),
        note: notes.join("; "),
    })
}

/// The inverse-variance weighted mean of the slides' μ and its σ (at least the slides'
/// scatter over their number, when they scatter more than their σ say).
fn estimate(slides: &[(&str, &PalmSlide)]) -> Option<(f64, f64)> {
    if slides.is_empty() {
        return None;
    }
    let w: Vec<f64> = slides
        .iter()
        .map(|(_, s)| 1.0 / s.mu_sigma.max(1e-9).powi(2))
        .collect();
    let sw: f64 = w.iter().sum();
    let mu = slides
        .iter()
        .zip(&w)
        .map(|((_, s), w)| s.mu * w)
        .sum::<f64>()
        / sw;
    let n = slides.len() as f64;
    let scatter = if n > 1.0 {
        slides.iter().map(|(_, s)| (s.mu - mu).powi(2)).sum::<f64>() / (n - 1.0) / n
    } else {
        0.0
    };
    Some((mu, (1.0 / sw).max(scatter).sqrt()))
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
            phi_onset_sigma: None,
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

    /// Slides on the palm give the estimate: their inverse-variance weighted mean, its σ at
    /// least their scatter over their number.
    #[test]
    fn slides_on_the_palm_give_the_estimate() {
        let slide = |mu: f64, mu_sigma: f64| PalmSlide {
            mu,
            mu_sigma,
            slide_tilt: mu.atan(),
            max_tilt: 0.4,
            distance_m: 0.03,
            frames: 100,
            chi2_per_dof: 1.0,
        };
        let mut tree = Tree::default();
        for (name, s) in [("a", slide(0.30, 0.01)), ("b", slide(0.32, 0.02))] {
            tree.demos.push(crate::tree::DemoRecord {
                name: name.into(),
                kind: crate::classify::Kind::Slide,
                frames: 100,
                outliers: 0,
                instrumented: true,
                noise: None,
                fingerprint: None,
                palm_slide: Some(s),
            });
        }
        let f = evidence(&tree).unwrap();
        let (w1, w2) = (1e4, 2.5e3);
        let mean = (0.30 * w1 + 0.32 * w2) / (w1 + w2);
        assert!((f.estimate.unwrap() - mean).abs() < 1e-12);
        let scatter = (((0.30 - mean).powi(2) + (0.32 - mean).powi(2)) / 2.0).sqrt();
        let sigma = (1.0 / (w1 + w2)).sqrt().max(scatter);
        assert!((f.estimate_sigma.unwrap() - sigma).abs() < 1e-12);
        assert_eq!(f.estimate_from, vec!["a", "b"]);
        assert!(f.lower_bound.is_none());
    }
}
