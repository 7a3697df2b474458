//! The tree's dynamic models: a planar pendulum per (edge, resting face); the centre of mass
//! they determine together is in [`super::com`].

use super::{angle, Tree, SAME_FACE_RAD};
use crate::classify::Topple;
use crate::dynamics::ToppleDynamics;
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
    /// φ from the pendulum fitted to the fall \[rad\].
    pub phi_fall: Option<f64>,
    /// `I_e / (m l_p)` \[m\] from the fall.
    pub inertia_ratio_m: Option<f64>,
    /// Onset time \[s\] (instrumented).
    pub onset_t: Option<f64>,
}

impl Pendulum {
    pub(crate) fn refit(&mut self) {
        let w: Vec<f64> = self
            .observations
            .iter()
            .map(|o| 1.0 / (o.phi_sigma.powi(2) + 1e-12))
            .collect();
        let sw: f64 = w.iter().sum();
        let phi = self
            .observations
            .iter()
            .zip(&w)
            .map(|(o, w)| o.phi * w)
            .sum::<f64>()
            / sw;
        // Between-demonstration scatter guards against over-confident single estimates.
        let n = self.observations.len() as f64;
        let scatter = if n > 1.0 {
            self.observations
                .iter()
                .map(|o| (o.phi - phi).powi(2))
                .sum::<f64>()
                / (n - 1.0)
                / n
        } else {
            0.0
        };
        self.phi = Some(phi);
        self.phi_sigma = Some((1.0 / sw).max(scatter).sqrt());
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

impl Tree {
    /// Add a topple's dynamics as a pendulum observation of the edge `edge_id` (the edge its
    /// topple `top` of the demonstration `demo` was just fused into), for the face it rested
    /// on.
    pub(super) fn add_pendulum(
        &mut self,
        edge_id: &str,
        demo: &str,
        top: &Topple,
        d: &ToppleDynamics,
    ) {
        let (Some(phi), Some(phi_sigma)) = (d.phi, d.phi_sigma) else {
            return;
        };
        let edge = self
            .edges
            .iter_mut()
            .find(|e| e.id == edge_id)
            .expect("the topple's edge is in the tree");
        let obs = PendulumObservation {
            demo: demo.to_string(),
            phi,
            phi_sigma,
            phi_onset: d.phi_onset,
            phi_fall: d.fall.map(|f| f.phi),
            inertia_ratio_m: d.fall.map(|f| f.inertia_ratio_m),
            onset_t: d.onset.map(|o| o.t),
        };
        let n = d.resting_face_normal;
        match edge
            .pendulums
            .iter_mut()
            .find(|p| angle(&p.resting_face_normal, &n) < SAME_FACE_RAD)
        {
            Some(p) => {
                p.observations.retain(|o| o.demo != demo);
                p.observations.push(obs);
                p.refit();
            }
            None => {
                let mut p = Pendulum {
                    resting_face_normal: n,
                    // The edge direction of the tree may be reversed relative to this
                    // demonstration's: the pendulum keeps the one it turned about.
                    toppling_axis: top.edge.line.direction,
                    phi: None,
                    l_p: None,
                    phi_sigma: None,
                    inertia_ratio_m: None,
                    support: Vec::new(),
                    observations: vec![obs],
                    com_conflict: None,
                };
                p.refit();
                edge.pendulums.push(p);
            }
        }
    }
}
