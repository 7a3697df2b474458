//! The tree's dynamic models: a planar pendulum per (edge, resting face); the centre of mass
//! they determine together is in [`super::com`].

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A dynamic model on an edge's contact sub-manifold: the planar pendulum of Sec. II-B, one per
/// face the object rested on when toppling about the edge (an edge has two sides).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pendulum {
    /// Outward normal (object frame) of the face the object rested on before toppling.
    pub resting_face_normal: Vector3<f64>,
    /// The edge direction about which the object turned (right-hand rule) when toppling off
    /// this face; `toppling_axis × resting_face_normal` points from the edge into the face.
    pub toppling_axis: Vector3<f64>,
    /// Angle \[rad\] of the CoM from the vertical through the edge, resting on that face: the
    /// support must tilt past it for the object to topple.
    pub phi: Option<f64>,
    /// Distance \[m\] of the CoM from the edge (homogeneous-box inertia model, see
    /// [`crate::pendulum`]).
    pub l_p: Option<f64>,
    /// Standard deviation of phi \[rad\].
    pub phi_sigma: Option<f64>,
    /// `I_e / (m l_p)` \[m\], what the fall determines without an inertia model.
    pub inertia_ratio_m: Option<f64>,
    /// Demonstrations behind it.
    pub support: Vec<String>,
    /// Per-demonstration estimates.
    pub observations: Vec<PendulumObservation>,
    /// What the other pendulums say of this one when they contradict it beyond its
    /// uncertainty (`tree/com_conflicts.rs`): it is then left out of the centre of mass, the
    /// inertia and the plans. Absent when it agrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com_conflict: Option<super::ComConflict>,
}

/// One demonstration's pendulum estimate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PendulumObservation {
    /// The demonstration.
    pub demo: String,
    /// φ \[rad\] and its standard deviation.
    pub phi: f64,
    /// Standard deviation of φ \[rad\].
    pub phi_sigma: f64,
    /// φ as the palm tilt at the topple onset (instrumented) \[rad\].
    pub phi_onset: Option<f64>,
    /// Standard deviation of `phi_onset` \[rad\] (absent in files written before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phi_onset_sigma: Option<f64>,
    /// φ from the pendulum fitted to the fall \[rad\].
    pub phi_fall: Option<f64>,
    /// `I_e / (m l_p)` \[m\] from the fall.
    pub inertia_ratio_m: Option<f64>,
    /// Onset time \[s\] (instrumented).
    pub onset_t: Option<f64>,
}

impl Pendulum {
    pub(crate) fn refit(&mut self) {
        // (φ, weight) of each observation.
        let values: Vec<(f64, f64)> = self
            .observations
            .iter()
            .map(|o| (o.phi, 1.0 / (o.phi_sigma.powi(2) + 1e-12)))
            .collect();
        let sw: f64 = values.iter().map(|(_, w)| w).sum();
        let phi = values.iter().map(|(p, w)| p * w).sum::<f64>() / sw;
        // The observations' disagreement beyond their sigmas (the Birge ratio: χ² per degree
        // of freedom, when above 1) widens the weighted mean's variance.
        let birge = super::face::birge_ratio(&values, phi);
        self.phi = Some(phi);
        self.phi_sigma = Some((birge / sw).sqrt());
        let ratios: Vec<f64> = self
            .observations
            .iter()
            .filter_map(|o| o.inertia_ratio_m)
            .collect();
        self.inertia_ratio_m =
            (!ratios.is_empty()).then(|| ratios.iter().sum::<f64>() / ratios.len() as f64);
        self.l_p = self.inertia_ratio_m.map(|r| 0.75 * r);
        self.support = self.observations.iter().map(|o| o.demo.clone()).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::{Distribution, StandardNormal};

    fn fused(obs: &[(f64, f64)]) -> Pendulum {
        let mut p = Pendulum {
            resting_face_normal: -Vector3::z(),
            toppling_axis: Vector3::x(),
            phi: None,
            l_p: None,
            phi_sigma: None,
            inertia_ratio_m: None,
            support: Vec::new(),
            observations: obs
                .iter()
                .enumerate()
                .map(|(i, &(phi, phi_sigma))| PendulumObservation {
                    demo: format!("d{i}"),
                    phi,
                    phi_sigma,
                    phi_onset: None,
                    phi_onset_sigma: None,
                    phi_fall: Some(phi),
                    inertia_ratio_m: None,
                    onset_t: None,
                })
                .collect(),
            com_conflict: None,
        };
        p.refit();
        p
    }

    /// Three palm onsets (σ 0.2°) and two falls (σ 3°) that agree within their sigmas: the
    /// mean keeps the onsets' precision (the falls' own scatter does not widen it).
    #[test]
    fn agreeing_observations_keep_the_weighted_sigma() {
        let d = f64::to_radians;
        let obs = [
            (d(31.0), d(0.2)),
            (d(31.1), d(0.2)),
            (d(30.9), d(0.2)),
            (d(27.0), d(3.0)),
            (d(33.5), d(3.0)),
        ];
        let p = fused(&obs);
        let sw: f64 = obs.iter().map(|(_, s)| 1.0 / (s * s + 1e-12)).sum();
        assert!((p.phi_sigma.unwrap() - (1.0 / sw).sqrt()).abs() < 1e-12);
        assert!((p.phi.unwrap() - d(31.0)).abs() < d(0.1));
    }

    /// Two estimates 10 σ apart: the mean's σ is widened by the Birge ratio √(χ²/(N-1)).
    #[test]
    fn disagreeing_observations_widen_the_sigma() {
        let p = fused(&[(0.50, 0.01), (0.60, 0.01)]);
        let chi2: f64 = 2.0 * (0.05f64 / 0.01).powi(2);
        let expected = (chi2 / 1.0 / (2.0 / (1e-4 + 1e-12))).sqrt();
        assert!((p.phi_sigma.unwrap() - expected).abs() < 1e-9);
        assert!(p.phi_sigma.unwrap() > 0.04);
    }

    /// Honest observations of mixed precision give an honest fused σ: over many trials the
    /// median |error| / σ is near 0.674.
    #[test]
    fn the_fused_sigma_is_honest_for_honest_observations() {
        let mut rng = StdRng::seed_from_u64(17);
        let mut z: Vec<f64> = (0..2000)
            .map(|_| {
                let n = rng.random_range(2..7);
                let obs: Vec<(f64, f64)> = (0..n)
                    .map(|_| {
                        let s = 10f64.powf(rng.random_range(-2.5..-1.0));
                        let e: f64 = StandardNormal.sample(&mut rng);
                        (0.5 + s * e, s)
                    })
                    .collect();
                let p = fused(&obs);
                (p.phi.unwrap() - 0.5).abs() / p.phi_sigma.unwrap()
            })
            .collect();
        z.sort_by(f64::total_cmp);
        let median = z[z.len() / 2];
        assert!((0.5..0.75).contains(&median), "median |z| {median:.3}");
        assert!(z[z.len() - 1] < 5.0, "max |z| {:.2}", z[z.len() - 1]);
    }
}
