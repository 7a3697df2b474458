//! The features checked against each other: an edge must lie in the faces it joins (its point
//! on each face's plane, its direction along it), and the centre of mass inside the shape. A
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
