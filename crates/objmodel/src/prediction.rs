//! What the shape and the centre of mass predict of topples no one demonstrated: for every
//! (resting face, edge of it) pair of a closed [`Shape`], the pendulum of Sec. II-B, i.e. the
//! CoM angle φ from the vertical through the edge while the object rests on the face, and the
//! CoM's distance `l_p` from the edge.
//!
//! Resting on a face with outward normal `n`, "up" is `-n`; the edge (point `p`, direction `u`
//! with `u × n` pointing from the edge into the face) carries the object when it topples; in the
//! plane normal to `u`, the CoM `c` sits at `r = c - p` (its part along `u` dropped), and
//! `φ = atan2(r · (u × n), r · (-n))`, `l_p = |r|`. φ > 0 for every edge of a face means the
//! object can rest on it (the CoM is above the face); the support must tilt past φ about that
//! edge to topple it.
//!
//! [`uncertain`] adds their standard deviations (see `prediction/sigma.rs`).

mod sigma;
pub use sigma::{observed_beside, uncertain, EDGE_MATCH_M};

use crate::shape::Shape;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A predicted pendulum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PredictedPendulum {
    /// The face rested on (its id in the tree).
    pub resting_face: String,
    /// The face it lands on, across the edge.
    pub landing_face: String,
    /// A point of the edge \[m\] (its first corner) and its direction, oriented so that
    /// `direction × resting normal` points into the resting face.
    pub edge_point: Vector3<f64>,
    /// See `edge_point`.
    pub edge_direction: Vector3<f64>,
    /// φ \[rad\].
    pub phi: f64,
    /// `l_p` \[m\].
    pub l_p: f64,
    /// Outward normal of the resting face (object frame).
    #[serde(default)]
    pub resting_normal: Vector3<f64>,
    /// Standard deviation of φ \[rad\], propagated from the two faces that make the edge and
    /// the CoM ([`uncertain`]); absent from [`pendulums`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phi_sigma: Option<f64>,
    /// Standard deviation of `l_p` \[m\], likewise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub l_p_sigma: Option<f64>,
    /// The pendulum the tree observed on this (face, edge), when one was demonstrated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observed: Option<ObservedPendulum>,
}

/// An observed pendulum beside its prediction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObservedPendulum {
    /// The tree's edge.
    pub edge: String,
    /// Observed φ \[rad\].
    pub phi: f64,
    /// Its standard deviation \[rad\].
    pub phi_sigma: Option<f64>,
    /// Observed `l_p` \[m\] (the fall's ratio under the homogeneous-box model), if any.
    pub l_p: Option<f64>,
    /// (observed - predicted) φ over the two sigmas combined.
    pub phi_z: Option<f64>,
    /// Whether the other pendulums contradict the observed one (it is left out of the CoM:
    /// `Pendulum::com_conflict`); the prediction is then the one to use.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub contradicted: bool,
}

/// The pendulums of every (face, edge) pair of `shape` for the centre of mass `com`.
pub fn pendulums(shape: &Shape, com: &Vector3<f64>) -> Vec<PredictedPendulum> {
    let mut out = Vec::new();
    for face in &shape.faces {
        let p = &face.polygon;
        for k in 0..p.len() {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            // The neighbour across this edge: the other face with both corners.
            let Some(other) = shape
                .faces
                .iter()
                .find(|f| f.id != face.id && f.polygon.contains(&a) && f.polygon.contains(&b))
            else {
                continue;
            };
            let (pa, pb) = (shape.vertices[a], shape.vertices[b]);
            let n = face.normal;
            let mut u = (pb - pa).normalize();
            let centre =
                p.iter().map(|&i| shape.vertices[i]).sum::<Vector3<f64>>() / p.len() as f64;
            if u.cross(&n).dot(&(centre - pa)) < 0.0 {
                u = -u;
            }
            let w = u.cross(&n);
            let r = (com - pa) - u * u.dot(&(com - pa));
            out.push(PredictedPendulum {
                resting_face: face.id.clone(),
                landing_face: other.id.clone(),
                edge_point: pa,
                edge_direction: u,
                phi: r.dot(&w).atan2(-r.dot(&n)),
                l_p: r.norm(),
                resting_normal: n,
                phi_sigma: None,
                l_p_sigma: None,
                observed: None,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{reconstruct, tests_support::box_faces};
    use nalgebra::UnitQuaternion;

    /// A box `w x d x h` with its CoM at its centre: resting on its bottom, toppling over an
    /// edge along its depth needs a tilt of atan(w/h) (φ), and the CoM is `√(w² + h²)/2` from
    /// the edge; every face of it gives 4 pendulums, 24 in all.
    #[test]
    fn a_box_topples_at_its_textbook_angle() {
        let rotation = UnitQuaternion::from_euler_angles(0.2, 0.4, -0.3);
        let centre = Vector3::new(0.01, 0.02, -0.05);
        let size = Vector3::new(0.2, 0.1, 0.3);
        let shape = reconstruct(&box_faces(centre, &rotation, &size)).unwrap();
        let all = pendulums(&shape, &centre);
        assert_eq!(all.len(), 24);
        // f5: the face with outward normal -z of the box (its bottom); over an edge along y
        // the lever is half the width (x) against half the height (z).
        let bottom = &shape.faces.iter().find(|f| f.id == "f5").unwrap().id;
        for p in all.iter().filter(|p| &p.resting_face == bottom) {
            let along_y = (rotation.inverse() * p.edge_direction).y.abs() > 0.99;
            let (half_w, half_h) = if along_y { (0.1, 0.15) } else { (0.05, 0.15) };
            let phi = f64::atan2(half_w, half_h);
            assert!((p.phi - phi).abs() < 1e-12, "{} vs {phi}", p.phi);
            assert!((p.l_p - f64::hypot(half_w, half_h)).abs() < 1e-12);
        }
        assert!(all
            .iter()
            .all(|p| p.phi > 0.0 && p.phi < std::f64::consts::FRAC_PI_2));
        // A CoM outside a face's footprint makes it a face the box cannot rest on: some φ < 0.
        let off = centre + rotation * Vector3::new(0.15, 0.0, 0.0);
        assert!(pendulums(&shape, &off).iter().any(|p| p.phi < 0.0));
    }
}
