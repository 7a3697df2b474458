//! The tree's centre of mass: from the planes of its pendulums ([`super::com_planes`]), without
//! those the others contradict, and from the point its flights agree on
//! ([`Tree::flights_com`]).
//!
//! The pendulums' CoM is that of the planes the others do not contradict
//! ([`super::com_without_conflicts`]): a plane beyond its uncertainty from the CoM of the
//! others is left out, not averaged in. The flights' point is tested against it (χ²₃ at
//! [`MATCH_ALPHA`], both covariances): where they agree, the planes are tested again with the
//! point among the others and the CoM holds both. Where they disagree, a minority of wrong
//! pendulums may be to blame: tested one at a time against the point and the other planes, the
//! planes left out must be fewer than half, and the rest must agree with the point; else
//! neither can be singled out (a pusher's drive biases falls, a gravity off biases flights), so
//! the CoM holds both with its covariance widened by their χ² over its 3 degrees of freedom,
//! and the tree says so (`tree/checks.rs`). Where the pendulums fix no CoM, the flights' point
//! does, and the planes there are tested against it.

use super::com_planes::{com_from, CentreOfMass, ComPlane, ComPoint, UNKNOWN_PHI_SIGMA_RAD};
use super::{com_without_conflicts, matrix, ComConflict, Tree, MATCH_ALPHA, SAME_FACE_RAD};
use crate::shared_com::SharedCom;

/// A pendulum left out of the CoM: its place (edge index, pendulum index in that edge) and
/// what the others say of it.
pub type LeftOutPendulum = ((usize, usize), ComConflict);

impl Tree {
    /// The planes of the pendulums with a φ, from the fused edges and the resting faces.
    pub fn com_planes(&self) -> Vec<ComPlane> {
        self.com_planes_owned()
            .into_iter()
            .map(|(p, _)| p)
            .collect()
    }

    /// [`Tree::com_planes`], each with its pendulum's place: (edge index, pendulum index).
    fn com_planes_owned(&self) -> Vec<(ComPlane, (usize, usize))> {
        let mut planes = Vec::new();
        for (ei, e) in self.edges.iter().enumerate() {
            // The edge's own estimate: conditioned on its faces, edges share their errors,
            // which the planes' fit would count as independent (`tree/edge_faces.rs`).
            let own = e.own();
            for (pi, p) in e.pendulums.iter().enumerate() {
                let Some(phi) = p.phi else { continue };
                // The fused edge's direction, turned the way this pendulum toppled.
                let axis = if own.direction.dot(&p.toppling_axis) < 0.0 {
                    -own.direction
                } else {
                    own.direction
                };
                let normal_sigma = self
                    .faces
                    .iter()
                    .filter(|f| super::angle(&f.normal, &p.resting_face_normal) < SAME_FACE_RAD)
                    .map(|f| f.sigma_normal_own_rad())
                    .next()
                    .unwrap_or(0.0);
                let plane = ComPlane {
                    phi,
                    phi_sigma: p.phi_sigma.unwrap_or(UNKNOWN_PHI_SIGMA_RAD),
                    point: own.point,
                    point_cov: matrix(&own.point_cov),
                    axis,
                    axis_cov: matrix(&own.direction_cov),
                    normal: p.resting_face_normal,
                    normal_sigma,
                };
                planes.push((plane, (ei, pi)));
            }
        }
        planes
    }

    /// The CoM from the pendulums that agree and the flights (`com_of`), and the places of
    /// the pendulums left out, with what the others say of them; `None` where neither fixes
    /// one.
    pub fn centre_of_mass(&self) -> Option<(CentreOfMass, Vec<LeftOutPendulum>)> {
        let owned = self.com_planes_owned();
        let planes: Vec<ComPlane> = owned.iter().map(|(p, _)| p.clone()).collect();
        let (com, left_out) = com_of(&planes, self.flights_com().as_ref())?;
        Some((
            com,
            left_out.into_iter().map(|(i, c)| (owned[i].1, c)).collect(),
        ))
    }

    /// Set `com` and every pendulum's `com_conflict` from [`Tree::centre_of_mass`].
    pub(super) fn refit_centre_of_mass(&mut self) {
        for p in self.edges.iter_mut().flat_map(|e| e.pendulums.iter_mut()) {
            p.com_conflict = None;
        }
        self.com = self.centre_of_mass().map(|(com, left_out)| {
            for ((ei, pi), c) in left_out {
                self.edges[ei].pendulums[pi].com_conflict = Some(c);
            }
            com
        });
    }
}

/// The `planes` but those `left_out`.
fn without(planes: &[ComPlane], left_out: &[(usize, ComConflict)]) -> Vec<ComPlane> {
    (0..planes.len())
        .filter(|i| left_out.iter().all(|(k, _)| k != i))
        .map(|i| planes[i].clone())
        .collect()
}

/// χ²₃ of the pendulums' CoM `p` against the flights' point, under both covariances.
fn agreement(p: &CentreOfMass, f: &SharedCom) -> Option<f64> {
    let d = p.point - f.point;
    (p.covariance_matrix()? + f.covariance)
        .try_inverse()
        .map(|w| d.dot(&(w * d)))
}

/// Where the pendulums' CoM and the flights' point disagree: the planes tested one at a time
/// against the point and the other planes, if that leaves out fewer than half of them and the
/// planes kept, where they fix a CoM on their own, agree with the point (a wrong pendulum, or
/// a few, that the point singles out; a wrong point would take most of the planes with it).
/// The CoM, the planes left out and the kept planes' χ²₃ against the point, if they fix one.
#[allow(clippy::type_complexity)]
fn singled_out(
    planes: &[ComPlane],
    f: &SharedCom,
    point: &ComPoint,
    limit: f64,
) -> Option<(CentreOfMass, Vec<(usize, ComConflict)>, Option<f64>)> {
    let (com, left_out) = com_without_conflicts(planes, Some(point))?;
    if 2 * left_out.len() >= planes.len() {
        return None;
    }
    let kept = without(planes, &left_out);
    let chi2 = match com_without_conflicts(&kept, None) {
        Some((p, _)) => Some(agreement(&p, f)?).filter(|c| *c <= limit),
        None => return Some((com, left_out, None)),
    };
    chi2.map(|c| (com, left_out, Some(c)))
}

/// The CoM of the pendulums' `planes` and the `flights`' point (see the module documentation),
/// and the planes left out (their indices, with what the others said of them).
pub(super) fn com_of(
    planes: &[ComPlane],
    flights: Option<&SharedCom>,
) -> Option<(CentreOfMass, Vec<(usize, ComConflict)>)> {
    let pendulums = com_without_conflicts(planes, None);
    let Some(f) = flights else {
        return pendulums;
    };
    let point = ComPoint {
        point: f.point,
        covariance: f.covariance,
    };
    let (mut com, left_out, chi2) = match pendulums {
        None => {
            let (com, left_out) = com_without_conflicts(planes, Some(&point))?;
            (com, left_out, None)
        }
        Some((p, left_out)) => {
            let limit = crate::stats::chi2_threshold(3.0, MATCH_ALPHA);
            let chi2 = agreement(&p, f)?;
            if chi2 <= limit {
                let (com, left_out) = com_without_conflicts(planes, Some(&point))?;
                (com, left_out, Some(chi2))
            } else if let Some((com, left_out, chi2)) = singled_out(planes, f, &point, limit) {
                (com, left_out, chi2)
            } else {
                let kept = without(planes, &left_out);
                let mut com = com_from(&kept, Some(&point))?;
                let widen = chi2 / 3.0;
                com.covariance = com.covariance_matrix().map(|c| super::rows(&(c * widen)));
                com.sigma_m = com.sigma_m.map(|s| s * widen.sqrt());
                (com, left_out, Some(chi2))
            }
        }
    };
    com.flights = f.flights;
    com.flight_demonstrations = f.demonstrations;
    com.flights_chi2 = chi2;
    com.flights_gravity_error = Some(f.gravity_error);
    Some((com, left_out))
}

#[cfg(test)]
#[path = "com_tests.rs"]
mod tests;
