//! The edges checked against the landings' faces: an edge of the object lies in two of its
//! faces, and where the landings know those faces, it must lie in them as precisely as both
//! are measured. An edge that does not is withheld from the tree ([`WithheldEdge`]), with the
//! reason and the faces its topples taught (a topple off the object's faces was no topple on
//! the support, and its rests no rests on it), until the demonstrations change.
//!
//! Why: a roll measured on a soft or sinking contact (the pivot sinks into the support, or
//! slips, as it turns) still fits a fixed line within the tracking noise, a few millimetres
//! off the edge, with a σ of a fraction of a millimetre. The landings measure the faces beside
//! that edge far better: a face on which the object came to rest after several throws has its
//! height above the support known to the support's flatness over the square root of their
//! number, and its normal to the scatter of their downs.
//!
//! The test. Every face `F` with confirmed landings ([`crate::landing`]) gives its normal `n_F`
//! (the mean of the landings' downs) and its landings' mean height `c_F`; the face's offset is
//! `d_F = c_F − z₀`, with `z₀` the support's height at the landings. An edge `(p, u)` in `F`
//! has `n_F · u = 0` and `n_F · p = d_F`, so `z = c_F − n_F · p` measures `z₀`. The faces an
//! edge claims are those the tree's own matching gate (its per-demonstration systematic errors
//! [`SYSTEMATIC_POINT_M`], [`SYSTEMATIC_DIRECTION_RAD`], at [`MATCH_ALPHA`]) cannot tell it
//! from, on a support at a first `z₀`: the robust mean of every edge's lowest value on a face
//! it runs along (from their median, the values a χ² test at [`MATCH_ALPHA`] keeps); the faces
//! an edge is not in lie a face's width away. `z₀` is then the robust mean of all the claimed
//! values. Each edge is tested on every face it claims, without the systematic errors (both
//! measure the same support, and the edge's σ holds its contact's wander already): its value
//! against `z₀` and its direction along the face, χ² with 2 degrees of freedom per face at
//! [`MATCH_ALPHA`]. Nothing is tested where no value is kept by at least half of them (the
//! landings came from several supports) or no face has landings.
//!
//! The scatter. The kept edges' values tell how far they lie from the faces beyond their own
//! σ (on a soft contact a true roll edge is 1-3 mm off at σ 0.5-0.9 mm): the variance between
//! them, by Paule and Mandel's moment estimator, is added to each tested edge's point
//! covariance ([`Edge::between_sigma_m`]). The test does not use it: an edge off the faces
//! must not widen the test it is judged by (with it, MuJoCo's wrong roll edges came back).

use super::{
    matrix, Edge, Tree, WithheldEdge, MATCH_ALPHA, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M,
};
use crate::face::{FaceObservation, FaceSource};
use crate::landing::SUPPORT_FLATNESS_M;
use crate::stats::chi2_threshold;
use nalgebra::Vector3;

/// A face as its confirmed landings show it.
struct LandedFace {
    id: String,
    /// Mean of the landings' downs (unit): the outward normal.
    normal: Vector3<f64>,
    /// Variance \[rad²\] per axis of `normal`.
    normal_var: f64,
    /// Mean height \[m\] of the landings (above the poses' origin).
    height: f64,
    /// Its variance \[m²\].
    height_var: f64,
}

/// One face an edge claims, with the edge's measurement of the support's height from it.
struct Claim {
    face: String,
    /// `c_F − n_F · p` \[m\] and its variance \[m²\].
    z: f64,
    z_var: f64,
    /// The edge's direction out of the face \[rad\], and its variance \[rad²\].
    tilt: f64,
    tilt_var: f64,
}

impl Claim {
    /// χ² (2 dof) of the edge lying in the face, on a support at height `z0` (variance
    /// `z0_var`), with `extra_var` \[m²\] and `extra_dir_var` \[rad²\] of systematic errors.
    fn chi2(&self, z0: f64, z0_var: f64, extra_var: f64, extra_dir_var: f64) -> f64 {
        (self.z - z0).powi(2) / (self.z_var + z0_var + extra_var)
            + self.tilt.powi(2) / (self.tilt_var + extra_dir_var)
    }
}

impl Tree {
    /// Move every withheld edge back into the tree (before a demonstration comes or goes).
    /// The edges' own σ come back too ([`Edge::between_sigma_m`] is taken out).
    pub(super) fn restore_withheld_edges(&mut self) {
        self.edges_to_own_sigma();
        if self.withheld_edges.is_empty() {
            return;
        }
        for w in std::mem::take(&mut self.withheld_edges) {
            let mut edge = w.edge;
            edge.faces
                .retain(|id| self.faces.iter().any(|f| &f.id == id));
            for o in w.faces {
                let id = self.add_face(o);
                if !edge.faces.contains(&id) {
                    edge.faces.push(id);
                }
            }
            self.edges.push(edge);
        }
        self.edges
            .sort_by_key(|e| e.id[1..].parse::<usize>().unwrap_or(usize::MAX));
    }

    /// Give every edge its own σ back: take out the scatter between edges
    /// ([`Edge::between_sigma_m`]) that the last check added.
    fn edges_to_own_sigma(&mut self) {
        for e in self
            .edges
            .iter_mut()
            .filter(|e| e.between_sigma_m.is_some())
        {
            e.refit();
        }
    }

    /// Withhold the edges the landings' faces contradict (see the module documentation).
    pub(super) fn withhold_edges_off_landed_faces(&mut self) {
        self.edges_to_own_sigma();
        let faces = self.landed_faces();
        if faces.is_empty() {
            return;
        }
        let candidates: Vec<Vec<Claim>> =
            self.edges.iter().map(|e| candidates(e, &faces)).collect();
        // The support's height at the landings: first from each edge's lowest value on a face
        // it runs along, then from the values of the faces the edges claim on that support.
        let along = |c: &&Claim| {
            let sys_dir = SYSTEMATIC_DIRECTION_RAD.powi(2);
            c.tilt.powi(2) / (c.tilt_var + sys_dir) < chi2_threshold(1.0, MATCH_ALPHA)
        };
        let lowest: Vec<(f64, f64)> = candidates
            .iter()
            .filter_map(|cs| cs.iter().filter(along).min_by(|a, b| a.z.total_cmp(&b.z)))
            .map(|c| (c.z, c.z_var))
            .collect();
        let Some((first, first_var)) = robust_mean(&lowest) else {
            return;
        };
        let claims: Vec<Vec<Claim>> = candidates
            .into_iter()
            .map(|cs| claimed(cs, first, first_var))
            .collect();
        let values: Vec<(f64, f64)> = claims.iter().flatten().map(|c| (c.z, c.z_var)).collect();
        let Some((z0, z0_var)) = robust_mean(&values) else {
            return;
        };
        let mut kept = Vec::with_capacity(self.edges.len());
        let mut tested = Vec::new();
        for (e, cs) in std::mem::take(&mut self.edges).into_iter().zip(claims) {
            let chi2: f64 = cs.iter().map(|c| c.chi2(z0, z0_var, 0.0, 0.0)).sum();
            if cs.is_empty() || chi2 <= chi2_threshold(2.0 * cs.len() as f64, MATCH_ALPHA) {
                if !cs.is_empty() {
                    tested.push((kept.len(), cs));
                }
                kept.push(e);
                continue;
            }
            let what: Vec<String> = cs
                .iter()
                .map(|c| {
                    format!(
                        "{:.1} mm from {}'s plane (σ {:.1} mm)",
                        (z0 - c.z) * 1e3,
                        c.face,
                        (c.z_var + z0_var).sqrt() * 1e3
                    )
                })
                .collect();
            let why = format!(
                "edge {} is not in the faces the landings show: {} (χ² {chi2:.1} over {} \
                 degrees of freedom); withheld",
                e.id,
                what.join(", "),
                2 * cs.len()
            );
            let faces = self.take_topple_faces(&e);
            self.withheld_edges.push(WithheldEdge {
                edge: e,
                why,
                faces,
                unlocated: false,
            });
        }
        if self.withheld_edges.iter().any(|w| !w.faces.is_empty()) {
            self.prune_faces();
        }
        // The kept edges' scatter about the faces beyond their σ: one variance between edges
        // (a contact that sinks or slips more than the edge's σ holds), by the moment
        // estimator of Paule and Mandel over their values.
        if tested.len() >= 2 {
            let residuals: Vec<(f64, f64)> = tested
                .iter()
                .flat_map(|(_, cs)| cs.iter().map(|c| (c.z - z0, c.z_var)))
                .collect();
            let between = between_variance(&residuals).sqrt();
            if between > 0.0 {
                for (i, _) in &tested {
                    kept[*i].add_between(between);
                }
            }
        }
        self.edges = kept;
    }

    /// Take out of the faces the observations that the topples of the edge `e` taught
    /// ([`FaceObservation::from_rest`]: its demonstration, its frames, an offset).
    pub(super) fn take_topple_faces(&mut self, e: &Edge) -> Vec<FaceObservation> {
        let taught = |o: &FaceObservation| {
            o.source == FaceSource::Rest
                && o.offset.is_some()
                && e.observations
                    .iter()
                    .any(|t| t.demo == o.demo && t.frames == o.frames)
        };
        let mut out = Vec::new();
        for f in self.faces.iter_mut().filter(|f| e.faces.contains(&f.id)) {
            let (taken, kept) = std::mem::take(&mut f.observations)
                .into_iter()
                .partition(|o| taught(o));
            f.observations = kept;
            out.extend::<Vec<FaceObservation>>(taken);
        }
        out
    }

    /// The faces with at least two confirmed landings whose heights agree (χ² of their
    /// scatter about their mean, with the support's flatness at each, at [`MATCH_ALPHA`]).
    fn landed_faces(&self) -> Vec<LandedFace> {
        let mut out = Vec::new();
        for f in &self.faces {
            let landings: Vec<&crate::landing::Landing> = self
                .landings
                .iter()
                .filter(|l| l.confirmed && f.observations.iter().any(|o| l.taught(o)))
                .collect();
            let n = landings.len() as f64;
            if landings.len() < 2 {
                continue;
            }
            let sum = landings.iter().fold(Vector3::zeros(), |s, l| s + l.down);
            let normal = sum.normalize();
            let height = landings.iter().map(|l| l.place.height).sum::<f64>() / n;
            let flat = |l: &&crate::landing::Landing| {
                SUPPORT_FLATNESS_M.powi(2) + l.sigma_height_m.powi(2)
            };
            let chi2: f64 = landings
                .iter()
                .map(|l| (l.place.height - height).powi(2) / flat(l))
                .sum();
            if chi2 > chi2_threshold(n - 1.0, MATCH_ALPHA) {
                continue;
            }
            // The mean's variance: the model's (noise and flatness at each) or the scatter's,
            // whichever is larger; for the normal, the downs' scatter (2 axes) or their noise.
            let model = landings.iter().map(flat).sum::<f64>() / (n * n);
            let scatter = landings
                .iter()
                .map(|l| (l.place.height - height).powi(2))
                .sum::<f64>()
                / ((n - 1.0) * n);
            let spread = landings
                .iter()
                .map(|l| (l.down - normal).norm_squared())
                .sum::<f64>()
                / (2.0 * (n - 1.0) * n);
            let noise = landings
                .iter()
                .map(|l| l.sigma_down_rad.powi(2))
                .sum::<f64>()
                / (n * n);
            out.push(LandedFace {
                id: f.id.clone(),
                normal,
                normal_var: spread.max(noise),
                height,
                height_var: model.max(scatter),
            });
        }
        out
    }
}

/// The edge `e`'s values on every face of `faces`.
fn candidates(e: &Edge, faces: &[LandedFace]) -> Vec<Claim> {
    // The edge's own σ, without the contact's depth: the depth is how far a pivot may lie off
    // its faces, and that is what this test judges (with it, a MuJoCo roll edge 6 mm off its
    // faces passed).
    let p_cov = matrix(&e.point_cov) - e.common_point_cov();
    faces
        .iter()
        .map(|f| {
            let n = &f.normal;
            let lever = (e.point - n * n.dot(&e.point)).norm_squared();
            Claim {
                face: f.id.clone(),
                z: f.height - n.dot(&e.point),
                z_var: (n.transpose() * p_cov * n)[0] + f.height_var + f.normal_var * lever,
                tilt: n.dot(&e.direction).clamp(-1.0, 1.0).asin(),
                tilt_var: e.sigma_direction_rad.powi(2) + f.normal_var,
            }
        })
        .collect()
}

/// The faces an edge claims: those the tree's matching gate, with the systematic errors,
/// cannot tell it from, on a support at `z0` (variance `z0_var`). The faces an edge is not in
/// are a face's width off.
fn claimed(candidates: Vec<Claim>, z0: f64, z0_var: f64) -> Vec<Claim> {
    let gate = chi2_threshold(2.0, MATCH_ALPHA);
    let (sys, sys_dir) = (SYSTEMATIC_POINT_M.powi(2), SYSTEMATIC_DIRECTION_RAD.powi(2));
    candidates
        .into_iter()
        .filter(|c| c.chi2(z0, z0_var, sys, sys_dir) < gate)
        .collect()
}

/// The variance `τ²` between `residuals` (each about one common mean, with its own variance)
/// beyond their own: the `τ² ≥ 0` with `Σ r²/(v + τ²)` equal to its expectation, `n − 1`
/// (Paule and Mandel's estimator); 0 where their own variances explain them.
fn between_variance(residuals: &[(f64, f64)]) -> f64 {
    let dof = residuals.len() as f64 - 1.0;
    let q = |tau2: f64| {
        residuals
            .iter()
            .map(|(r, v)| r * r / (v + tau2))
            .sum::<f64>()
    };
    if dof < 1.0 || q(0.0) <= dof {
        return 0.0;
    }
    let mut hi = residuals.iter().map(|(r, _)| r * r).fold(0.0, f64::max);
    while q(hi) > dof {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if q(mid) > dof {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The mean of `values` (value, variance) that a χ² test (1 dof, [`MATCH_ALPHA`]) keeps,
/// starting from their median, and its variance; `None` when it keeps fewer than half.
fn robust_mean(values: &[(f64, f64)]) -> Option<(f64, f64)> {
    if values.is_empty() {
        return None;
    }
    let mut zs: Vec<f64> = values.iter().map(|v| v.0).collect();
    zs.sort_by(f64::total_cmp);
    let mut mean = zs[zs.len() / 2];
    let mut var = 0.0;
    let gate = chi2_threshold(1.0, MATCH_ALPHA);
    let mut kept = 0;
    for _ in 0..5 {
        let (mut sw, mut swz) = (0.0, 0.0);
        kept = 0;
        for &(z, v) in values {
            if (z - mean).powi(2) / (v + var) <= gate {
                sw += 1.0 / v;
                swz += z / v;
                kept += 1;
            }
        }
        if kept == 0 {
            return None;
        }
        mean = swz / sw;
        var = 1.0 / sw;
    }
    (2 * kept >= values.len()).then_some((mean, var))
}

#[cfg(test)]
#[path = "landing_edges_tests.rs"]
mod tests;
