//! The robust fits that a segment's analysis ([`super::fit`]) rests on: MSAC over a
//! segment's blocks for a fixed line (topple hypothesis) and a fixed plane of motion (slide
//! hypothesis), with χ² thresholds by degrees of freedom, the block costs and inlier tests.

use super::blocks::Block;
use crate::geometry::{Line, LineChi2, LineStats, PlaneStats};
use crate::lanes::F4;
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

/// The MSAC cost of candidate lines over a segment's blocks, `Σ min(χ²_b(line), χ²_α(5 n_b))`
/// ([`LineStats::chi2`] truncated at each block's threshold), for many candidates: the blocks'
/// statistics are gathered once into rows of the terms the χ² needs, and the thresholds looked
/// up once. With `P = I - u uᵀ` the projector normal to the line `(p, u)`, `S = Σ w r rᵀ`,
/// `s = Σ w r`, `A = Σ a u uᵀ` (both symmetric):
///
/// ```text
/// χ²_point = tr(P S) - 2 p·(P s) + Σw p·(P p) = tr S - uᵀS u - 2 (p·s - (p·u)(u·s)) + Σw (p·p - (p·u)²)
/// χ²_dir   = Σa - uᵀ A u
/// ```
///
/// the same sums as [`LineStats::chi2_to`], grouped for the six distinct entries of each
/// symmetric matrix (equal up to rounding).
///
/// The rows are stored four blocks to a group, term by term ([`F4`] lanes), so that one
/// candidate's cost takes four blocks per step (in 256-bit registers where the processor has
/// AVX2); a last, partial group is padded with rows of zeros, whose truncated cost is zero.
/// The four lanes are summed apart and then together: the same terms in another order, so
/// the cost equals the sequential sum up to rounding (the MSAC choice compares costs of
/// different lines, never at that level).
struct LineCosts {
    groups: Vec<[F4; LINE_TERMS]>,
}

/// Terms per block in [`LineCosts`]: tr S, S (6), s (3), Σw, Σa, A (6), pitch χ², threshold.
const LINE_TERMS: usize = 20;

impl LineCosts {
    /// Gather the blocks `idx` that have lines.
    fn new(blocks: &[Block], idx: &[usize], th: &mut Thresholds) -> Self {
        let sym6 = |m: &nalgebra::Matrix3<f64>| {
            [
                m[(0, 0)],
                m[(1, 1)],
                m[(2, 2)],
                m[(0, 1)],
                m[(0, 2)],
                m[(1, 2)],
            ]
        };
        // Straight into the groups, allocated once: gathering rows first and regrouping them
        // cost two growing vectors' copies and fresh pages (0.5 ms for 4096 blocks).
        let mut groups: Vec<[F4; LINE_TERMS]> = Vec::with_capacity(idx.len().div_ceil(4));
        let lines = idx.iter().map(|&i| &blocks[i].line).filter(|s| s.n > 0.0);
        for (k, s) in lines.enumerate() {
            let (m, a) = (sym6(&s.swrr), sym6(&s.sauu));
            let row = [
                s.swrr.trace(),
                m[0],
                m[1],
                m[2],
                m[3],
                m[4],
                m[5],
                s.swr.x,
                s.swr.y,
                s.swr.z,
                s.sw,
                s.sa,
                a[0],
                a[1],
                a[2],
                a[3],
                a[4],
                a[5],
                s.pitch_chi2,
                th.get(5.0 * s.n),
            ];
            if k % 4 == 0 {
                groups.push([F4::splat(0.0); LINE_TERMS]);
            }
            let g = groups.last_mut().expect("pushed above");
            for (term, x) in g.iter_mut().zip(row) {
                term.0[k % 4] = x;
            }
        }
        Self { groups }
    }

    /// The truncated cost of `line`.
    fn cost(&self, line: &Line) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if crate::lanes::avx2() {
            // SAFETY: the processor runs AVX2 code (checked just above).
            return unsafe { self.cost_avx2(line) };
        }
        self.cost_lanes(line)
    }

    /// [`LineCosts::cost_lanes`] in AVX2 intrinsics: the same operations in the same order,
    /// lane by lane (so the same bits), four blocks per instruction. (The compiler does not
    /// turn the lane-by-lane source into clean 256-bit code here.)
    ///
    /// # Safety
    /// The processor must run AVX2 code.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn cost_avx2(&self, line: &Line) -> f64 {
        use std::arch::x86_64::*;
        let (p, u) = (line.point, line.direction);
        let c = [
            u.x * u.x,
            u.y * u.y,
            u.z * u.z,
            2.0 * u.x * u.y,
            2.0 * u.x * u.z,
            2.0 * u.y * u.z,
        ]
        .map(|x| _mm256_set1_pd(x));
        let pu = p.dot(&u);
        let ppp = _mm256_set1_pd(p.dot(&p) - pu * pu);
        let (px, py, pz) = (
            _mm256_set1_pd(p.x),
            _mm256_set1_pd(p.y),
            _mm256_set1_pd(p.z),
        );
        let (ux, uy, uz) = (
            _mm256_set1_pd(u.x),
            _mm256_set1_pd(u.y),
            _mm256_set1_pd(u.z),
        );
        let (pu, two, zero) = (_mm256_set1_pd(pu), _mm256_set1_pd(2.0), _mm256_setzero_pd());
        let (add, sub, mul) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd);
        let mut sum = zero;
        for g in &self.groups {
            // SAFETY: each of the 20 terms is four f64.
            let r = |k: usize| unsafe { _mm256_loadu_pd(g[k].0.as_ptr()) };
            let quad = |at: usize| {
                add(
                    add(
                        add(mul(c[0], r(at)), mul(c[1], r(at + 1))),
                        mul(c[2], r(at + 2)),
                    ),
                    add(
                        add(mul(c[3], r(at + 3)), mul(c[4], r(at + 4))),
                        mul(c[5], r(at + 5)),
                    ),
                )
            };
            let ps = add(add(mul(px, r(7)), mul(py, r(8))), mul(pz, r(9)));
            let us = add(add(mul(ux, r(7)), mul(uy, r(8))), mul(uz, r(9)));
            let point = add(
                sub(sub(r(0), quad(1)), mul(two, sub(ps, mul(pu, us)))),
                mul(r(10), ppp),
            );
            let dir = sub(r(11), quad(12));
            // `max(x, 0)` and `min(x, threshold)` take the second operand when x is NaN, as
            // `f64::max` and `f64::min` do.
            let term = add(
                add(_mm256_max_pd(point, zero), _mm256_max_pd(dir, zero)),
                r(18),
            );
            sum = add(sum, _mm256_min_pd(term, r(19)));
        }
        let mut lanes = [0.0; 4];
        // SAFETY: four f64.
        unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), sum) };
        F4(lanes).sum()
    }

    /// [`LineCosts::cost`] on every processor: four blocks per step in [`F4`] lanes.
    #[inline(always)]
    fn cost_lanes(&self, line: &Line) -> f64 {
        let (p, u) = (line.point, line.direction);
        // uᵀ M u = Σ c_j m_j over the six distinct entries of a symmetric M.
        let c = [
            u.x * u.x,
            u.y * u.y,
            u.z * u.z,
            2.0 * u.x * u.y,
            2.0 * u.x * u.z,
            2.0 * u.y * u.z,
        ];
        let pu = p.dot(&u);
        let ppp = p.dot(&p) - pu * pu;
        let zero = F4::splat(0.0);
        let quad = |r: &[F4; LINE_TERMS], at: usize| {
            c[0] * r[at]
                + c[1] * r[at + 1]
                + c[2] * r[at + 2]
                + (c[3] * r[at + 3] + c[4] * r[at + 4] + c[5] * r[at + 5])
        };
        let mut sum = zero;
        for r in &self.groups {
            let ps = p.x * r[7] + p.y * r[8] + p.z * r[9];
            let us = u.x * r[7] + u.y * r[8] + u.z * r[9];
            let point = r[0] - quad(r, 1) - 2.0 * (ps - pu * us) + r[10] * ppp;
            let dir = r[11] - quad(r, 12);
            sum = sum + (point.max(zero) + dir.max(zero) + r[18]).min(r[19]);
        }
        sum.sum()
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
    let costs = LineCosts::new(blocks, idx, th);
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
    use crate::classify::blocks::Phase;

    /// The cost of a line over blocks, term by term with [`LineStats::chi2_to`].
    fn line_cost(blocks: &[Block], idx: &[usize], line: &Line, th: &mut Thresholds) -> f64 {
        let line = LineChi2::new(line);
        idx.iter()
            .map(|&i| &blocks[i].line)
            .filter(|s| s.n > 0.0)
            .map(|s| s.chi2_to(&line).min(th.get(5.0 * s.n)))
            .sum()
    }

    #[test]
    fn line_costs_equal_the_sum_of_block_chi2() {
        let mut seed = 0x5eed_1234_u64;
        let mut rnd = move || crate::testing::unit(&mut seed) - 0.5;
        let mut th = Thresholds::new(0.01);
        for round in 0..20 {
            // Blocks of lines scattered about a true line, some empty, at scales from
            // millimetres to decimetres.
            let truth = Line::through(
                Vector3::new(rnd(), rnd(), rnd()) * 0.2,
                Vector3::new(rnd(), rnd(), rnd()),
            );
            let scale = [1e-4, 1e-3, 1e-2, 1e-1][round % 4];
            let blocks: Vec<Block> = (0..60)
                .map(|k| {
                    let mut b = Block::new(k, 0.0, Phase::Moving, Some(0));
                    for _ in 0..(k % 5) {
                        let r = truth.point + Vector3::new(rnd(), rnd(), rnd()) * scale;
                        let u = (truth.direction + Vector3::new(rnd(), rnd(), rnd()) * scale)
                            .normalize();
                        let w = 1.0 / (scale * scale) * (1.0 + rnd());
                        b.line.add(&r, &u, w, w * 1e-2, rnd().abs() * 3.0);
                    }
                    b
                })
                .collect();
            let idx: Vec<usize> = (0..blocks.len()).filter(|k| k % 7 != 3).collect();
            let costs = LineCosts::new(&blocks, &idx, &mut th);
            for cand in 0..10 {
                let line = if cand == 0 {
                    truth
                } else {
                    Line::through(
                        truth.point + Vector3::new(rnd(), rnd(), rnd()) * scale * cand as f64,
                        truth.direction + Vector3::new(rnd(), rnd(), rnd()) * 0.05 * cand as f64,
                    )
                };
                let (fast, direct) = (costs.cost(&line), line_cost(&blocks, &idx, &line, &mut th));
                // The AVX2 kernel (where it runs) mirrors the portable one bit for bit.
                assert_eq!(fast.to_bits(), costs.cost_lanes(&line).to_bits());
                assert!(
                    (fast - direct).abs() <= 1e-9 * direct.abs().max(1.0),
                    "round {round} candidate {cand}: {fast} vs {direct}"
                );
            }
        }
    }

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
