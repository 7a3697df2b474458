//! A topple's dynamics added to the tree: as a pendulum observation of its edge, for the face it
//! rested on, fused with the observations of that (edge, face) before.

use super::{angle, Pendulum, PendulumObservation, Tree, SAME_FACE_RAD};
use crate::classify::Topple;
use crate::dynamics::ToppleDynamics;

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
            phi_onset_sigma: d.phi_onset_sigma,
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
