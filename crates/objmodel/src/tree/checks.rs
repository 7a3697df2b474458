//! The features checked against each other: an edge must lie in the faces it joins (its point
//! on each face's plane, its direction along it) and be an edge of the shape (in two of its
//! faces: the edges of another object are not), and the centre of mass inside the shape. A
//! check that fails beyond the features' uncertainty (a χ² test at [`MATCH_ALPHA`] with the
//! same per-demonstration systematic errors as the fusion) is a [`Contradiction`]: it says
//! which features disagree and by how much, so that neither is trusted silently.

use super::{Tree, MATCH_ALPHA, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};
use serde::{Deserialize, Serialize};

/// Two (or more) features of the tree that their uncertainties cannot reconcile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contradiction {
    /// The features' ids (`e1`, `f2`, `com`).
    pub features: Vec<String>,
    /// What disagrees, with numbers.
    pub what: String,
}

impl Tree {
    /// Every contradiction between the tree's features (see the module documentation).
    pub fn contradictions(&self) -> Vec<Contradiction> {
        let mut out = Vec::new();
        let limit = crate::stats::chi2_threshold(2.0, MATCH_ALPHA);
        for e in &self.edges {
            for fid in &e.faces {
                let Some(f) = self.faces.iter().find(|f| &f.id == fid) else {
                    continue;
                };
                // Its direction lies in the face: n·u ≈ 0.
                let tilt = f.normal.dot(&e.direction).clamp(-1.0, 1.0).asin();
                let var_dir = e.sigma_direction_rad.powi(2)
                    + f.sigma_normal_rad.powi(2)
                    + SYSTEMATIC_DIRECTION_RAD.powi(2);
                // Its point lies on the face's plane: n·p ≈ d.
                let (off, var_off) = match (f.offset, f.offset_sigma_m) {
                    (Some(d), Some(s)) => (
                        f.normal.dot(&e.point) - d,
                        e.sigma_point_m.powi(2) + s * s + SYSTEMATIC_POINT_M.powi(2),
                    ),
                    _ => (0.0, 1.0),
                };
                let chi2 = tilt * tilt / var_dir + off * off / var_off;
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
        if let Some(shape) = &self.shape {
            for e in &self.edges {
                let mut fits: Vec<(f64, &str, f64, f64)> = shape
                    .faces
                    .iter()
                    .map(|sf| {
                        let sigma_n = self
                            .faces
                            .iter()
                            .find(|f| f.id == sf.id)
                            .map_or(crate::face::SUPPORT_LEVEL_SIGMA_RAD, |f| f.sigma_normal_rad);
                        let tilt = sf.normal.dot(&e.direction).clamp(-1.0, 1.0).asin();
                        let off = sf.normal.dot(&e.point) - sf.offset;
                        let chi2 = tilt * tilt
                            / (e.sigma_direction_rad.powi(2)
                                + sigma_n.powi(2)
                                + SYSTEMATIC_DIRECTION_RAD.powi(2))
                            + off * off
                                / (e.sigma_point_m.powi(2)
                                    + sf.offset_sigma_m.powi(2)
                                    + SYSTEMATIC_POINT_M.powi(2));
                        (chi2, sf.id.as_str(), off, tilt)
                    })
                    .collect();
                // Nor does it lie outside the shape: its point (closest to the object origin,
                // which lies on the object, so within the edge's extent on a box) is inside
                // every face.
                if let Some((d, sf)) = shape.outside(&e.point).filter(|(d, _)| *d > 0.0) {
                    let var = e.sigma_point_m.powi(2)
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
}
