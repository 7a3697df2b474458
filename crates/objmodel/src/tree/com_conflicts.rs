//! Pendulums the others contradict: each pendulum's φ tested against the centre of mass that
//! all the other pendulums determine, and the worst one beyond its uncertainty left out, one at
//! a time, until the rest agree (issue 19: a feature that contradicts the rest is reported and
//! kept out, not averaged in).
//!
//! The test of plane `i` is leave-one-out: the CoM `x₋ᵢ` and its covariance `C₋ᵢ` from the
//! other planes ([`com_from_planes`], its covariance already widened by their own reduced χ²
//! when they scatter), and `i`'s residual there over everything it is uncertain by,
//! `z² = rᵢ² / (σᵢ²(x₋ᵢ) + mᵢᵀ C₋ᵢ mᵢ)`, against χ²₁ at [`MATCH_ALPHA`], the level of the
//! tree's other checks. A plane is tested only where the others fix a point on their own; so
//! with four planes or fewer only a plane whose three partners fix the CoM can be tested, and
//! three planes cannot contradict each other. What a plane that fails is told: the φ its edge
//! would have about the others' CoM, with that φ's σ (`√(mᵀ C₋ᵢ m) / l`, `l` the CoM's
//! distance from the edge), and `z`.
//!
//! With the flights' point ([`ComPoint`]), every plane is tested against it and the other
//! planes together (the point alone fixes a CoM); the point itself is not left out here (it
//! is tested against the pendulums by the tree, `tree/com.rs`).
//!
//! What this catches (measured on the standard data set, `docs/calibration.md`): a fall a
//! pusher drove through its balance point fits a free pendulum with φ far too low, and such a
//! pendulum, alone with the others, pulled the CoM by its weight.

use super::com_planes::{com_from, CentreOfMass, ComPlane, ComPoint};
use super::MATCH_ALPHA;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// What the other pendulums say of a pendulum they contradict.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ComConflict {
    /// φ \[rad\] of this (edge, resting face) about the CoM of the other pendulums.
    pub phi_others: f64,
    /// Its standard deviation \[rad\] (from their CoM's covariance).
    pub phi_others_sigma: f64,
    /// The leave-one-out residual over its standard deviation (see the module documentation).
    pub z: f64,
}

/// The CoM of the planes that agree (with the flights' `point`, if given), and the planes left
/// out (their indices in `planes`, in the order they were left out, with what the others
/// said); `None` where [`com_from`] of all the planes is.
pub fn com_without_conflicts(
    planes: &[ComPlane],
    point: Option<&ComPoint>,
) -> Option<(CentreOfMass, Vec<(usize, ComConflict)>)> {
    let limit = crate::stats::chi2_threshold(1.0, MATCH_ALPHA);
    let mut kept: Vec<usize> = (0..planes.len()).collect();
    let mut left_out = Vec::new();
    loop {
        let subset = |skip: Option<usize>| -> Vec<ComPlane> {
            kept.iter()
                .filter(|&&i| Some(i) != skip)
                .map(|&i| planes[i].clone())
                .collect()
        };
        let com = com_from(&subset(None), point)?;
        let mut worst: Option<(usize, f64, ComConflict)> = None;
        for &i in &kept {
            let Some(others) = com_from(&subset(Some(i)), point) else {
                continue;
            };
            let Some(cov) = others.covariance_matrix() else {
                continue;
            };
            let p = &planes[i];
            let (m, d) = p.plane();
            let r = m.dot(&others.point) - d;
            let var_x = (m.transpose() * cov * m)[0];
            let z2 = r * r / (p.residual_variance(&others.point) + var_x);
            if z2 > limit && worst.as_ref().is_none_or(|w| z2 > w.1) {
                let (phi_others, l) = phi_about(p, &others.point);
                let conflict = ComConflict {
                    phi_others,
                    phi_others_sigma: var_x.sqrt() / l.max(1e-9),
                    z: r.signum() * z2.sqrt(),
                };
                worst = Some((i, z2, conflict));
            }
        }
        match worst {
            Some((i, _, conflict)) => {
                kept.retain(|&k| k != i);
                left_out.push((i, conflict));
            }
            None => return Some((com, left_out)),
        }
    }
}

/// φ \[rad\] of the plane's (edge, resting face) about the point `x`, and `x`'s distance \[m\]
/// from the edge: the angle from the resting face's inward normal to `x`, seen along the edge.
fn phi_about(p: &ComPlane, x: &Vector3<f64>) -> (f64, f64) {
    let r = x - p.point;
    let r = r - p.axis * p.axis.dot(&r);
    let w = p.axis.cross(&p.normal).normalize();
    (r.dot(&w).atan2(-r.dot(&p.normal)), r.norm())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    /// The pendulums of an axis-aligned box of half extents `h` with its CoM at `com`, about
    /// the edges `(face axis, face sign, side axis, side sign)`, exact, each with σ_φ `s`.
    fn exact_planes(
        h: &Vector3<f64>,
        com: &Vector3<f64>,
        edges: &[(usize, f64, usize, f64)],
        s: f64,
    ) -> Vec<ComPlane> {
        edges
            .iter()
            .map(|&(k, sk, j, sj)| {
                let n = Vector3::ith(k, sk);
                let side = Vector3::ith(j, sj);
                let point = n * h[k] + side * h[j];
                let axis = side.cross(&n);
                let mut p = ComPlane {
                    phi: 0.0,
                    phi_sigma: s,
                    point,
                    point_cov: Matrix3::identity() * 1e-10,
                    axis,
                    axis_cov: Matrix3::identity() * 1e-8,
                    normal: n,
                    normal_sigma: 1e-4,
                };
                p.phi = phi_about(&p, com).0;
                p
            })
            .collect()
    }

    /// Bottom, top and side edges: seven planes of three directions.
    const EDGES: [(usize, f64, usize, f64); 7] = [
        (2, -1.0, 0, 1.0),
        (2, -1.0, 0, -1.0),
        (2, -1.0, 1, 1.0),
        (2, -1.0, 1, -1.0),
        (2, 1.0, 0, 1.0),
        (0, 1.0, 1, 1.0),
        (0, 1.0, 1, -1.0),
    ];

    /// The test box: half extents and CoM \[m\].
    fn test_box() -> (Vector3<f64>, Vector3<f64>) {
        (
            Vector3::new(0.03, 0.04, 0.06),
            Vector3::new(0.004, -0.003, -0.01),
        )
    }

    #[test]
    fn planes_that_agree_are_all_kept_and_give_the_com() {
        let (h, com) = test_box();
        let planes = exact_planes(&h, &com, &EDGES, 0.5f64.to_radians());
        let (c, left_out) = com_without_conflicts(&planes, None).unwrap();
        assert!(left_out.is_empty(), "{left_out:?}");
        assert!((c.point - com).norm() < 1e-9, "{:?}", c.point);
        assert_eq!(c.pendulums, EDGES.len());
    }

    /// One φ 15° low (a fall a pusher drove through its balance) among six right ones: it is
    /// left out, told the φ the others give (its true one, within their σ), and the CoM is
    /// the others'.
    #[test]
    fn a_pendulum_far_from_the_others_is_left_out_and_told_its_phi() {
        let (h, com) = test_box();
        let s = 0.5f64.to_radians();
        for bad in 0..EDGES.len() {
            let mut planes = exact_planes(&h, &com, &EDGES, s);
            let truth = planes[bad].phi;
            planes[bad].phi -= 15f64.to_radians();
            let (c, left_out) = com_without_conflicts(&planes, None).unwrap();
            assert_eq!(left_out.len(), 1, "plane {bad}: {left_out:?}");
            let (i, conflict) = &left_out[0];
            assert_eq!(*i, bad);
            assert!((c.point - com).norm() < 1e-9, "plane {bad}: {:?}", c.point);
            assert!((conflict.phi_others - truth).abs() < 1e-9);
            assert!(conflict.z.abs() > 3.9, "{conflict:?}");
            assert_eq!(c.pendulums, EDGES.len() - 1);
        }
    }

    /// Within its σ a plane is kept: 2σ off is no contradiction.
    #[test]
    fn a_pendulum_within_its_sigma_is_kept() {
        let (h, com) = test_box();
        let s = 0.5f64.to_radians();
        let mut planes = exact_planes(&h, &com, &EDGES, s);
        planes[0].phi += 2.0 * s;
        let (c, left_out) = com_without_conflicts(&planes, None).unwrap();
        assert!(left_out.is_empty(), "{left_out:?}");
        assert_eq!(c.pendulums, EDGES.len());
    }

    /// Three planes always meet: none can be left out, however wrong.
    #[test]
    fn three_planes_cannot_contradict_each_other() {
        let (h, com) = test_box();
        let mut planes = exact_planes(&h, &com, &[EDGES[0], EDGES[2], EDGES[5]], 1e-3);
        planes[0].phi -= 0.3;
        let (c, left_out) = com_without_conflicts(&planes, None).unwrap();
        assert!(left_out.is_empty());
        assert_eq!(c.pendulums, 3);
    }
}
