//! The features checked against each other: an edge must lie in the faces it joins (its point
//! on each face's plane, its direction along it) and be an edge of the shape (in two of its
//! faces: the edges of another object are not), and the centre of mass inside the shape. A
//! check that fails beyond the features' uncertainty (a χ² test at [`MATCH_ALPHA`] with the
//! same per-demonstration systematic errors as the fusion) is a [`Contradiction`]: it says
//! which features disagree and by how much, so that neither is trusted silently. A pendulum
//! the others contradict is one too (left out of the CoM: `tree/com_conflicts.rs`).

use super::{Contradiction, Tree, MATCH_ALPHA, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};

impl Tree {
    /// Every contradiction between the tree's features (see the module documentation).
    pub fn contradictions(&self) -> Vec<Contradiction> {
        // An edge held back as too loosely located contradicts nothing (`tree/unlocated.rs`).
        let mut out: Vec<Contradiction> = self
            .withheld_edges
            .iter()
            .filter(|w| !w.unlocated)
            .map(|w| Contradiction {
                features: vec![w.edge.id.clone()],
                what: w.why.clone(),
            })
            .collect();
        let limit = crate::stats::chi2_threshold(2.0, MATCH_ALPHA);
        for e in &self.edges {
            for fid in &e.faces {
                let Some(f) = self.faces.iter().find(|f| &f.id == fid) else {
                    continue;
                };
                let plane = f.offset.zip(f.offset_sigma_m);
                let (chi2, off, tilt) = edge_in_plane(e, &f.normal, f.sigma_normal_rad, plane);
                if chi2 > limit {
                    out.push(Contradiction {
                        features: vec![e.id.clone(), f.id.clone()],
                        what: format!(
                            "edge {} is not in face {}: {:.1} mm from its plane, {:.1}° out of \
                             it (χ² {chi2:.1} > {limit:.1})",
                            e.id,
                            f.id,
                            off.abs() * 1e3,
                            tilt.abs().to_degrees()
                        ),
                    });
                }
            }
        }
        // Every edge is an edge of the shape: the two of its faces it fits best both hold it.
        // Demonstrations of two objects learnt into one tree make a shape of the faces that
        // agree, and the other object's edges are off it.
        // Without a shape, no edge lies outside a face whose outward normal and offset are
        // known (the object is on its inner side of every face).
        for e in &self.edges {
            out.extend(self.off_object(e));
        }
        // A pendulum the others contradict (left out of the CoM: `tree/com_conflicts.rs`).
        for e in &self.edges {
            for p in &e.pendulums {
                let (Some(c), Some(phi)) = (&p.com_conflict, p.phi) else {
                    continue;
                };
                out.push(Contradiction {
                    features: vec![e.id.clone(), "com".into()],
                    what: format!(
                        "the pendulum of edge {} has φ {:.1}° ± {:.1}°, where the centre of mass \
                         of the other pendulums puts it at {:.1}° ± {:.1}° ({:.1} σ): left out \
                         of the centre of mass, the inertia and the plans",
                        e.id,
                        phi.to_degrees(),
                        p.phi_sigma.unwrap_or(0.0).to_degrees(),
                        c.phi_others.to_degrees(),
                        c.phi_others_sigma.to_degrees(),
                        c.z.abs()
                    ),
                });
            }
        }
        // Pendulums that disagree beyond their σ when none of them can be singled out (each
        // one is needed to fix the CoM, or leaving out any one leaves the rest disagreeing as
        // much): the CoM's covariance is widened by the reduced χ², and the user is told.
        if let Some(com) = &self.com {
            let dof = com.pendulums.saturating_sub(3);
            if let Some(c) = com.chi2_per_dof.filter(|_| dof > 0) {
                let chi2 = c * dof as f64;
                let limit = crate::stats::chi2_threshold(dof as f64, MATCH_ALPHA);
                if chi2 > limit {
                    let features = self.com_features();
                    out.push(Contradiction {
                        features,
                        what: format!(
                            "the {} pendulums of the centre of mass disagree beyond their \
                             uncertainty (χ² {chi2:.1} over {dof} degrees of freedom > \
                             {limit:.1}), and no one of them can be singled out: the centre of \
                             mass's covariance is widened by {c:.1}; demonstrate topples about \
                             other edges to tell which is wrong",
                            com.pendulums
                        ),
                    });
                }
            }
        }
        // The flights' point and the pendulums' CoM disagree (`tree/com.rs`): the CoM holds
        // both, its covariance widened.
        if let Some(com) = &self.com {
            let limit = crate::stats::chi2_threshold(3.0, MATCH_ALPHA);
            if let Some(chi2) = com.flights_chi2.filter(|c| *c > limit) {
                let features = self.com_features();
                out.push(Contradiction {
                    features,
                    what: format!(
                        "the centre of mass that {} flights of {} demonstrations agree on and \
                         the one of the {} pendulums disagree beyond their uncertainty (χ² \
                         {chi2:.1} over 3 degrees of freedom > {limit:.1}): the centre of mass \
                         holds both, its covariance widened by {:.1}; a gravity off by more \
                         than a degree, or falls a pusher drove, would do this",
                        com.flights,
                        com.flight_demonstrations,
                        com.pendulums,
                        chi2 / 3.0
                    ),
                });
            }
        }
        if let (Some(com), Some(shape)) = (&self.com, &self.shape) {
            if let Some((outside, face)) = shape.outside(&com.point).filter(|(d, _)| *d > 0.0) {
                out.push(Contradiction {
                    features: vec!["com".into(), face.id.clone()],
                    what: format!(
                        "the centre of mass lies {:.1} mm outside the shape, beyond face {}",
                        outside * 1e3,
                        face.id
                    ),
                });
            }
        }
        out
    }

    /// The features the CoM rests on, as a contradiction names them: the edges whose pendulums
    /// are in it, and "com".
    fn com_features(&self) -> Vec<String> {
        self.edges
            .iter()
            .filter(|e| {
                e.pendulums
                    .iter()
                    .any(|p| p.phi.is_some() && p.com_conflict.is_none())
            })
            .map(|e| e.id.clone())
            .chain(["com".to_string()])
            .collect()
    }

    /// The contradictions between the edge `e` and the object: with a shape, those of
    /// [`Tree::off_shape`]; without one, the learnt faces it lies outside of
    /// ([`Tree::outside_faces`]).
    pub(super) fn off_object(&self, e: &super::Edge) -> Vec<Contradiction> {
        match &self.shape {
            Some(shape) => self.off_shape(e, shape),
            None => self.outside_faces(e),
        }
    }

    /// The faces with a known outward normal and offset that the edge `e` (its own estimate,
    /// at its point nearest the object origin) lies outside of, beyond their uncertainty with
    /// the fusion's per-demonstration systematic error.
    pub(super) fn outside_faces(&self, e: &super::Edge) -> Vec<Contradiction> {
        let own = e.own();
        let limit = crate::stats::chi2_threshold(1.0, MATCH_ALPHA);
        self.faces
            .iter()
            .filter(|f| f.sign_known)
            .filter_map(|f| {
                let (d, s) = f.offset.zip(f.offset_sigma_m)?;
                let out = f.normal.dot(&own.point) - d;
                let chi2 =
                    out * out / (own.sigma_point_m.powi(2) + s * s + SYSTEMATIC_POINT_M.powi(2));
                (out > 0.0 && chi2 > limit).then(|| Contradiction {
                    features: vec![e.id.clone(), f.id.clone()],
                    what: format!(
                        "edge {} lies {:.1} mm outside face {} (χ² {chi2:.1} > {limit:.1})",
                        e.id,
                        out * 1e3,
                        f.id
                    ),
                })
            })
            .collect()
    }

    /// The contradictions between the edge `e` and the shape: its own estimate lies outside
    /// the shape, or is not in two of its faces (the two it fits best), beyond their
    /// uncertainty with the fusion's per-demonstration systematic errors.
    pub(super) fn off_shape(
        &self,
        e: &super::Edge,
        shape: &crate::shape::Shape,
    ) -> Vec<Contradiction> {
        let mut out = Vec::new();
        let limit = crate::stats::chi2_threshold(2.0, MATCH_ALPHA);
        let mut fits: Vec<(f64, &str, f64, f64)> = shape
            .faces
            .iter()
            .map(|sf| {
                let sigma_n = self
                    .faces
                    .iter()
                    .find(|f| f.id == sf.id)
                    .map_or(crate::face::SUPPORT_LEVEL_SIGMA_RAD, |f| f.sigma_normal_rad);
                let plane = Some((sf.offset, sf.offset_sigma_m));
                let (chi2, off, tilt) = edge_in_plane(e, &sf.normal, sigma_n, plane);
                (chi2, sf.id.as_str(), off, tilt)
            })
            .collect();
        // Nor does it lie outside the shape: its point (closest to the object origin,
        // which lies on the object, so within the edge's extent on a box) is inside
        // every face.
        if let Some((d, sf)) = shape.outside(&e.own().point).filter(|(d, _)| *d > 0.0) {
            let var = e.own().sigma_point_m.powi(2)
                + sf.offset_sigma_m.powi(2)
                + SYSTEMATIC_POINT_M.powi(2);
            let limit1 = crate::stats::chi2_threshold(1.0, MATCH_ALPHA);
            if d * d / var > limit1 {
                out.push(Contradiction {
                    features: vec![e.id.clone(), sf.id.clone()],
                    what: format!(
                        "edge {} lies {:.1} mm outside the shape, beyond face {} (χ² \
                         {:.1} > {limit1:.1}); are all the demonstrations of one object?",
                        e.id,
                        d * 1e3,
                        sf.id,
                        d * d / var
                    ),
                });
            }
        }
        fits.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let [_, (chi2, fid, off, tilt), ..] = fits[..] {
            if chi2 > limit {
                out.push(Contradiction {
                    features: vec![e.id.clone(), fid.to_string()],
                    what: format!(
                        "edge {} is not an edge of the shape: the second face it fits \
                         best, {fid}, is {:.1} mm and {:.1}° from it (χ² {chi2:.1} > \
                         {limit:.1}); are all the demonstrations of one object?",
                        e.id,
                        off.abs() * 1e3,
                        tilt.abs().to_degrees()
                    ),
                });
            }
        }
        out
    }
}

/// χ² (2 dof) of the edge `e` (its own estimate, [`super::Edge::own`]) lying in the plane of
/// unit normal `normal` (its σ per axis `sigma_normal`) and, when known, offset
/// `plane = (d, σ_d)`: its direction along the plane (n·u ≈ 0) and its point on it (n·p ≈ d),
/// with the fusion's per-demonstration systematic errors. Also the point's signed distance from the plane \[m\] (0 without an offset) and
/// the direction's tilt out of it \[rad\].
fn edge_in_plane(
    e: &super::Edge,
    normal: &nalgebra::Vector3<f64>,
    sigma_normal: f64,
    plane: Option<(f64, f64)>,
) -> (f64, f64, f64) {
    let e = e.own();
    let tilt = normal.dot(&e.direction).clamp(-1.0, 1.0).asin();
    let var_dir =
        e.sigma_direction_rad.powi(2) + sigma_normal.powi(2) + SYSTEMATIC_DIRECTION_RAD.powi(2);
    let (off, var_off) = match plane {
        Some((d, s)) => (
            normal.dot(&e.point) - d,
            e.sigma_point_m.powi(2) + s * s + SYSTEMATIC_POINT_M.powi(2),
        ),
        None => (0.0, 1.0),
    };
    (tilt * tilt / var_dir + off * off / var_off, off, tilt)
}
