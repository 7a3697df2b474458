//! The tree's dynamic models: a planar pendulum per (edge, resting face), and the centre of
//! mass that the pendulums of several edges determine.

use super::{angle, Tree, CONDITION_MIN, SAME_FACE_RAD};
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

/// Where the centre of mass is, from the pendulums: each (edge, resting face, φ) puts the CoM
/// in the plane through the edge tilted by φ from the face's inward normal; three or more
/// independent planes give the point by least squares.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CentreOfMass {
    /// The CoM in the object frame \[m\].
    pub point: Vector3<f64>,
    /// RMS residual distance of the CoM from the planes \[m\].
    pub rms_residual_m: f64,
    /// Pendulums used.
    pub pendulums: usize,
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
                };
                p.refit();
                edge.pendulums.push(p);
            }
        }
    }

    /// The CoM from the pendulums (see [`CentreOfMass`]); `None` with fewer than three
    /// independent planes.
    pub fn centre_of_mass(&self) -> Option<CentreOfMass> {
        let mut planes = Vec::new();
        for e in &self.edges {
            for p in &e.pendulums {
                let (Some(phi), n) = (p.phi, p.resting_face_normal) else {
                    continue;
                };
                let u = p.toppling_axis;
                let inward = -n;
                // Along the face from the edge into the object: the face lifts on that side.
                let w = u.cross(&n).normalize();
                let d = inward * phi.cos() + w * phi.sin();
                let m = u.cross(&d).normalize();
                let sigma = p.phi_sigma.unwrap_or(0.02).max(1e-3);
                planes.push((m, m.dot(&e.point), 1.0 / sigma));
            }
        }
        com_from_planes(&planes)
    }
}

/// The point closest, in the weighted least-squares sense, to planes `m · x = d` given as
/// `(unit m, d [m], weight [1/rad])`; `None` with fewer than three planes or when their normals
/// are too close to parallel to fix a point ([`CONDITION_MIN`] on `Σ m mᵀ`: the geometry decides
/// whether the planes meet in a point, the weights only how well each is known).
fn com_from_planes(planes: &[(Vector3<f64>, f64, f64)]) -> Option<CentreOfMass> {
    if planes.len() < 3 {
        return None;
    }
    let mut a = nalgebra::Matrix3::zeros();
    let mut b = Vector3::zeros();
    let mut geometry = nalgebra::Matrix3::zeros();
    for (m, d, w) in planes {
        a += m * m.transpose() * (w * w);
        b += m * (d * w * w);
        geometry += m * m.transpose();
    }
    let eig = geometry.symmetric_eigenvalues();
    if eig.min() < CONDITION_MIN * eig.max() {
        return None;
    }
    let x = a.try_inverse()? * b;
    let rms = (planes
        .iter()
        .map(|(m, d, _)| (m.dot(&x) - d).powi(2))
        .sum::<f64>()
        / planes.len() as f64)
        .sqrt();
    Some(CentreOfMass {
        point: x,
        rms_residual_m: rms,
        pendulums: planes.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three planes along z known well and one across z known poorly still fix the point: the
    /// geometry is good, only the weights differ (by 200 here).
    #[test]
    fn planes_of_unequal_weight_fix_a_point() {
        let x = Vector3::new(0.01, -0.02, 0.03);
        let plane = |m: Vector3<f64>, w: f64| {
            let m = m.normalize();
            (m, m.dot(&x), w)
        };
        let planes = [
            plane(Vector3::new(1.0, 0.0, 0.1), 1000.0),
            plane(Vector3::new(0.0, 1.0, 0.1), 1000.0),
            plane(Vector3::new(1.0, 1.0, 0.0), 1000.0),
            plane(Vector3::new(0.1, 0.0, 1.0), 5.0),
        ];
        let com = com_from_planes(&planes).expect("a point");
        assert!((com.point - x).norm() < 1e-12, "{}", com.point);
        // Three planes through one line do not.
        let line = [
            plane(Vector3::new(1.0, 0.0, 0.0), 1.0),
            plane(Vector3::new(0.0, 1.0, 0.0), 1.0),
            plane(Vector3::new(1.0, 1.0, 0.0), 1.0),
        ];
        assert!(com_from_planes(&line).is_none());
    }
}
