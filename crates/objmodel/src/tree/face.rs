//! A face of the object in the tree: the weighted mean of its observations' normals and of
//! the offsets that are known (see the [tree documentation](super)).

use super::{angle, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};
use crate::face::{FaceObservation, FaceSource};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A face of the object: the plane `{x : normal·x = offset}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Face {
    /// Identifier, `f0`, `f1`, ...
    pub id: String,
    /// Unit normal (outward when `sign_known`).
    pub normal: Vector3<f64>,
    /// Offset \[m\], or null when the data do not determine it (a slide alone does not).
    pub offset: Option<f64>,
    /// Standard deviation of the offset \[m\].
    pub offset_sigma_m: Option<f64>,
    /// RMS standard deviation of the normal \[rad\].
    pub sigma_normal_rad: f64,
    /// Whether the normal is known to point out of the object.
    pub sign_known: bool,
    /// Names of the demonstrations that show this face.
    pub support: Vec<String>,
    /// Number of supporting demonstrations.
    pub n_support: usize,
    /// How many observations came from slides and from rests.
    pub evidence: Evidence,
    /// The per-demonstration observations.
    pub observations: Vec<FaceObservation>,
}

/// Counts of face observations by source.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Evidence {
    /// From slides.
    pub slide: usize,
    /// From rests before or after topples.
    pub rest: usize,
}

impl Face {
    pub(super) fn new(id: String, obs: FaceObservation) -> Self {
        let mut f = Self {
            id,
            normal: obs.normal,
            offset: None,
            offset_sigma_m: None,
            sigma_normal_rad: 0.0,
            sign_known: obs.sign_known,
            support: Vec::new(),
            n_support: 0,
            evidence: Evidence::default(),
            observations: vec![obs],
        };
        f.refit();
        f
    }

    /// Recompute the estimate from the observations.
    pub(super) fn refit(&mut self) {
        // Reference sign: the first observation whose sign is known, else the first.
        let reference = self
            .observations
            .iter()
            .find(|o| o.sign_known)
            .unwrap_or(&self.observations[0])
            .normal;
        let (mut sum, mut wsum, mut wsum2) = (Vector3::zeros(), 0.0, 0.0);
        let (mut off, mut off_w) = (0.0, 0.0);
        let mut evidence = Evidence::default();
        for o in &self.observations {
            let w = 1.0 / (o.sigma_normal().powi(2) + 1e-12);
            let n = if o.normal.dot(&reference) < 0.0 {
                -o.normal
            } else {
                o.normal
            };
            sum += n * w;
            wsum += w;
            wsum2 += w * w;
            if let (Some(d), Some(v)) = (o.offset, o.offset_var) {
                let d = if o.normal.dot(&reference) < 0.0 {
                    -d
                } else {
                    d
                };
                let wo = 1.0 / (v + 1e-12);
                off += d * wo;
                off_w += wo;
            }
            match o.source {
                FaceSource::Slide => evidence.slide += 1,
                FaceSource::Rest => evidence.rest += 1,
            }
        }
        let n = sum.normalize();
        // Scatter of the normals about their mean, per axis, over the effective count.
        let n_eff = (wsum * wsum / wsum2).max(1.0);
        let scatter: f64 = self
            .observations
            .iter()
            .map(|o| {
                let w = 1.0 / (o.sigma_normal().powi(2) + 1e-12);
                let a = angle(&n, &o.normal);
                w * a.min(std::f64::consts::PI - a).powi(2)
            })
            .sum::<f64>()
            / wsum;
        self.normal = n;
        self.sigma_normal_rad = ((scatter / 2.0) / n_eff + 1.0 / wsum).sqrt();
        self.sign_known = self.observations.iter().any(|o| o.sign_known);
        self.offset = (off_w > 0.0).then(|| off / off_w);
        self.offset_sigma_m = (off_w > 0.0).then(|| (1.0 / off_w).sqrt());
        self.support = self.observations.iter().map(|o| o.demo.clone()).collect();
        self.support.sort();
        self.support.dedup();
        self.n_support = self.support.len();
        self.evidence = evidence;
    }

    /// χ² (2 dof) of an observation's normal against this face, and whether offsets agree.
    pub(super) fn match_chi2(&self, o: &FaceObservation) -> f64 {
        let a = angle(&self.normal, &o.normal);
        // Signs: when both are known, opposite normals are different faces.
        let a = if self.sign_known && o.sign_known {
            a
        } else {
            a.min(std::f64::consts::PI - a)
        };
        let var = self.sigma_normal_rad.powi(2)
            + o.sigma_normal().powi(2)
            + SYSTEMATIC_DIRECTION_RAD.powi(2);
        let mut chi2 = a * a / var;
        if let (Some(d0), Some(d1), Some(v1)) = (self.offset, o.offset, o.offset_var) {
            let d1 = if self.normal.dot(&o.normal) < 0.0 {
                -d1
            } else {
                d1
            };
            let v = self.offset_sigma_m.unwrap_or(0.0).powi(2) + v1 + SYSTEMATIC_POINT_M.powi(2);
            chi2 += (d0 - d1).powi(2) / v;
        }
        chi2
    }
}
