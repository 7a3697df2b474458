//! The tree's centre of mass: from the planes of its pendulums ([`super::com_planes`]), without
//! those the others contradict.
//!
//! The tree's CoM is that of the planes the others do not contradict
//! ([`super::com_without_conflicts`]): a plane beyond its uncertainty from the CoM of the
//! others is left out, not averaged in.

use super::com_planes::{CentreOfMass, ComPlane, UNKNOWN_PHI_SIGMA_RAD};
use super::{com_without_conflicts, matrix, ComConflict, Tree, SAME_FACE_RAD};

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

    /// The CoM from the pendulums that agree (see [`CentreOfMass`] and
    /// [`super::com_without_conflicts`]), and the places of those left out, with what the
    /// others say of them; `None` with fewer than three independent planes.
    pub fn centre_of_mass(&self) -> Option<(CentreOfMass, Vec<LeftOutPendulum>)> {
        let owned = self.com_planes_owned();
        let planes: Vec<ComPlane> = owned.iter().map(|(p, _)| p.clone()).collect();
        let (com, left_out) = com_without_conflicts(&planes)?;
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

#[cfg(test)]
#[path = "com_tests.rs"]
mod tests;
