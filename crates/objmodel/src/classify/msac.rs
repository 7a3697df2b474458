//! The robust fits that a segment's analysis ([`super::analysis`]) rests on: MSAC over a
//! segment's blocks for a fixed line (topple hypothesis) and a fixed plane of motion (slide
//! hypothesis), with χ² thresholds by degrees of freedom, the block costs and inlier tests.

use super::block::Block;
use crate::fast::line_costs::LineCosts;
use crate::geometry::{Line, LineChi2, LineStats, PlaneStats};
use nalgebra::Vector3;

/// Candidates tried by MSAC: the blocks with the most information.
const MSAC_CANDIDATES: usize = 48;
/// Refinement iterations after MSAC.
const REFINE_ITERATIONS: usize = 10;
/// χ² thresholds by (integer) degrees of freedom, cached in a table indexed by them.
pub(super) struct Thresholds {
    alpha: f64,
    cache: Vec<f64>,
}

impl Thresholds {
    pub(super) fn new(alpha: f64) -> Self {
        Self {
            alpha,
            cache: Vec::new(),
        }
    }

    #[inline]
    pub(super) fn get(&mut self, dof: f64) -> f64 {
        // dof.round().max(1.0), without the call `round` is on baseline x86-64 (and by i64,
        // which converts in one instruction).
        let k = if dof >= 1.0 {
            let t = dof as i64;
            (t + i64::from(dof - t as f64 >= 0.5)) as usize
        } else {
            1
        };
        if k >= self.cache.len() {
            self.cache.resize(k + 1, f64::NAN);
        }
        if self.cache[k].is_nan() {
            self.cache[k] = crate::stats::chi2_threshold(k as f64, self.alpha);
        }
        self.cache[k]
    }
}

fn plane_cost(blocks: &[Block], idx: &[usize], n: &Vector3<f64>, th: &mut Thresholds) -> f64 {
    idx.iter()
        .map(|&i| &blocks[i].plane)
        .filter(|s| s.n > 0.0)
        .map(|s| s.chi2(n).min(th.get(3.0 * s.n)))
        .sum()
}

/// Whether a block's lines are consistent with `line` (prepared once for many blocks).
pub(super) fn line_inlier(s: &LineStats, line: &LineChi2, th: &mut Thresholds) -> bool {
    s.n > 0.0 && s.chi2_to(line) < th.get(5.0 * s.n)
}

/// Whether a block's motion is consistent with the plane normal to `n`.
pub(super) fn plane_inlier(s: &PlaneStats, n: &Vector3<f64>, th: &mut Thresholds) -> bool {
    s.n > 0.0 && s.chi2(n) < th.get(3.0 * s.n)
}

/// Whether a block's translations could come from rotations about `line` (`true` for a block
/// without moving frames). A frame that turns by `ω` about a line through `p` (the point closest
/// to the origin) moves by `t = (I - R) p ≈ p × ω`; the test matters for frames whose rotation is
/// too small for a screw axis of their own, which [`plane_inlier`] with the line's direction
/// accepts whenever they move across the line, a slide's pure translation included. The block
/// keeps only `Σ t tᵀ` and `Σ ω ωᵀ` (weighted by `w_t`, `w_ω`), so the residual
/// `Σ |t - p × ω|²` is bounded below by `(√Σ|t|² - √Σ|p × ω|²)²` (Minkowski) and that bound is
/// compared with the χ² level of `3 n` degrees of freedom, each frame's residual having
/// variance `σ_t² + |p|² σ_ω²` (`σ² = 1/w`): a conservative test, which rejects only a block
/// whose translation no rotation about the line explains.
pub(super) fn rotation_explains_translation(
    s: &PlaneStats,
    line: &Line,
    w_t: f64,
    w_omega: f64,
    th: &mut Thresholds,
) -> bool {
    if s.n <= 0.0 {
        return true;
    }
    let sum_t2 = s.stt.trace() / w_t;
    let px = line.point.cross_matrix();
    let sum_pw2 = (px * s.sww * px.transpose()).trace() / w_omega;
    let lower = (sum_t2.max(0.0).sqrt() - sum_pw2.max(0.0).sqrt()).powi(2);
    let var = 1.0 / w_t + line.point.norm_squared() / w_omega;
    lower / var < th.get(3.0 * s.n)
}

/// The indices of the `k` blocks with the largest `key`.
fn top_k(idx: &[usize], k: usize, key: impl Fn(usize) -> f64) -> Vec<usize> {
    let mut v: Vec<(f64, usize)> = idx
        .iter()
        .map(|&i| (key(i), i))
        .filter(|(w, _)| *w > 0.0)
        .collect();
    v.sort_by(|a, b| b.0.total_cmp(&a.0));
    v.truncate(k);
    v.into_iter().map(|(_, i)| i).collect()
}

/// MSAC: the valid candidate with the smallest truncated cost, then refinement: refit on its
/// inlier blocks (`inliers`: their indices, in order) until the inlier set stops changing (or
/// the refit is no longer valid).
fn msac<H>(
    candidates: Vec<H>,
    valid: impl Fn(&H) -> bool,
    th: &mut Thresholds,
    cost: impl Fn(&H, &mut Thresholds) -> f64,
    inliers: impl Fn(&H, &mut Thresholds) -> Vec<usize>,
    refit: impl Fn(&[usize]) -> Option<H>,
) -> Option<H> {
    let mut best = candidates
        .into_iter()
        .filter(|h| valid(h))
        .map(|h| (cost(&h, th), h))
        .min_by(|a, b| a.0.total_cmp(&b.0))?
        .1;
    let mut previous: Vec<usize> = Vec::new();
    for _ in 0..REFINE_ITERATIONS {
        let inliers = inliers(&best, th);
        if inliers.is_empty() || inliers == previous {
            break;
        }
        match refit(&inliers) {
            Some(h) if valid(&h) => best = h,
            _ => break,
        }
        previous = inliers;
    }
    Some(best)
}

/// The segment's fixed line (topple hypothesis): MSAC over the lines of the most informative
/// blocks and the mean of all.
pub(super) fn fit_line(
    blocks: &[Block],
    idx: &[usize],
    valid: impl Fn(&Line) -> bool,
    th: &mut Thresholds,
) -> Option<Line> {
    let mut all = LineStats::default();
    idx.iter().for_each(|&i| all.merge(&blocks[i].line));
    let mut candidates: Vec<Line> = top_k(idx, MSAC_CANDIDATES, |i| blocks[i].line.sw)
        .iter()
        .filter_map(|&i| blocks[i].line.mean())
        .collect();
    candidates.extend(all.mean());
    let costs = LineCosts::new(
        idx.iter()
            .map(|&i| &blocks[i].line)
            .filter(|s| s.n > 0.0)
            .map(|s| (s, th.get(5.0 * s.n))),
    );
    msac(
        candidates,
        valid,
        th,
        |l, _| costs.cost(l),
        |l, th| {
            let l = LineChi2::new(l);
            idx.iter()
                .copied()
                .filter(|&i| line_inlier(&blocks[i].line, &l, th))
                .collect()
        },
        |inliers| {
            let mut s = LineStats::default();
            inliers.iter().for_each(|&i| s.merge(&blocks[i].line));
            s.mean()
        },
    )
}

/// The segment's fixed plane of motion (slide hypothesis): MSAC over the normals of the most
/// informative blocks and the fit to all, each with the level-support prior on the normal when
/// `down` is given (see [`slide_normal`]); the costs are the data's alone.
pub(super) fn fit_plane(
    blocks: &[Block],
    idx: &[usize],
    valid: impl Fn(&Vector3<f64>) -> bool,
    down: Option<&Vector3<f64>>,
    th: &mut Thresholds,
) -> Option<Vector3<f64>> {
    let normal = |s: &PlaneStats| slide_normal(s, down).normal().map(|n| n.into_inner());
    let mut all = PlaneStats::default();
    idx.iter().for_each(|&i| all.merge(&blocks[i].plane));
    let info = |i: usize| blocks[i].plane.sww.trace() + blocks[i].plane.stt.trace();
    let mut candidates: Vec<Vector3<f64>> = top_k(idx, MSAC_CANDIDATES, info)
        .iter()
        .filter_map(|&i| normal(&blocks[i].plane))
        .collect();
    candidates.extend(normal(&all));
    msac(
        candidates,
        valid,
        th,
        |n, th| plane_cost(blocks, idx, n, th),
        |n, th| {
            idx.iter()
                .copied()
                .filter(|&i| plane_inlier(&blocks[i].plane, n, th))
                .collect()
        },
        |inliers| {
            let mut s = PlaneStats::default();
            inliers.iter().for_each(|&i| s.merge(&blocks[i].plane));
            normal(&s)
        },
    )
}

/// Slide statistics with the level-support prior when `down` (unit, in the frame of the
/// statistics) is given: on a level support the face slid on faces down, to within the
/// support's tilt ([`crate::face::SUPPORT_LEVEL_SIGMA_RAD`]). The prior decides the normal where
/// the motion does not (a straight push leaves it free about the direction of travel, and the
/// slight rocking of a pushed box, about the horizontal axis across the push, then pulls it
/// sideways); where the motion decides, the prior barely moves it.
pub(super) fn slide_normal(s: &PlaneStats, down: Option<&Vector3<f64>>) -> PlaneStats {
    match down {
        Some(d) => s.with_normal_prior(d, crate::face::SUPPORT_LEVEL_SIGMA_RAD),
        None => *s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_round_the_degrees_of_freedom_as_f64_round() {
        let mut th = Thresholds::new(0.01);
        for dof in [
            f64::NAN,
            -3.0,
            0.0,
            0.49,
            0.5,
            0.99,
            1.0,
            1.49,
            1.5,
            2.5,
            5.0,
            7.499999999999999,
            7.5,
            3e6,
        ] {
            let k = dof.round().max(1.0);
            assert_eq!(
                th.get(dof),
                crate::stats::chi2_threshold(k, 0.01),
                "dof {dof}"
            );
        }
    }
}
