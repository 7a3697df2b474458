//! The MSAC line cost of many blocks (see `crate::classify`'s MSAC fits), four blocks per step.

use super::avx2_or_baseline;
use super::lanes::F4;
use crate::geometry::{Line, LineStats};

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
pub struct LineCosts {
    groups: Vec<[F4; LINE_TERMS]>,
}

/// Terms per block in [`LineCosts`]: tr S, S (6), s (3), Σw, Σa, A (6), pitch χ², threshold.
const LINE_TERMS: usize = 20;

impl LineCosts {
    /// Gather the blocks' line statistics (blocks that have lines, `n > 0`), each with its
    /// threshold (the χ² level at `5 n` degrees of freedom).
    pub fn new<'a>(lines: impl IntoIterator<Item = (&'a LineStats, f64)>) -> Self {
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
        let lines = lines.into_iter();
        let mut groups: Vec<[F4; LINE_TERMS]> = Vec::with_capacity(lines.size_hint().0.div_ceil(4));
        for (k, (s, threshold)) in lines.into_iter().enumerate() {
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
                threshold,
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
    pub fn cost(&self, line: &Line) -> f64 {
        avx2_or_baseline!(avx2: self.cost_avx2(line), baseline: self.cost_lanes(line))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::LineChi2;
    use nalgebra::Vector3;

    /// The cost of a line over blocks' line statistics, term by term with [`LineStats::chi2_to`].
    fn line_cost(lines: &[(LineStats, f64)], line: &Line) -> f64 {
        let line = LineChi2::new(line);
        lines.iter().map(|(s, th)| s.chi2_to(&line).min(*th)).sum()
    }

    #[test]
    fn line_costs_equal_the_sum_of_block_chi2() {
        let mut seed = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x5eed_1234);
        let mut rnd = move || rand::Rng::random::<f64>(&mut seed) - 0.5;
        let th = |n: f64| crate::stats::chi2_threshold((5.0 * n).round().max(1.0), 0.01);
        for round in 0..20 {
            // Blocks of lines scattered about a true line, some empty, at scales from
            // millimetres to decimetres.
            let truth = Line::through(
                Vector3::new(rnd(), rnd(), rnd()) * 0.2,
                Vector3::new(rnd(), rnd(), rnd()),
            );
            let scale = [1e-4, 1e-3, 1e-2, 1e-1][round % 4];
            let blocks: Vec<LineStats> = (0..60)
                .map(|k: usize| {
                    let mut b = LineStats::default();
                    for _ in 0..(k % 5) {
                        let r = truth.point + Vector3::new(rnd(), rnd(), rnd()) * scale;
                        let u = (truth.direction + Vector3::new(rnd(), rnd(), rnd()) * scale)
                            .normalize();
                        let w = 1.0 / (scale * scale) * (1.0 + rnd());
                        b.add(&r, &u, w, w * 1e-2, rnd().abs() * 3.0);
                    }
                    b
                })
                .collect();
            let lines: Vec<(LineStats, f64)> = (0..blocks.len())
                .filter(|k| k % 7 != 3)
                .map(|k| blocks[k])
                .filter(|s| s.n > 0.0)
                .map(|s| (s, th(s.n)))
                .collect();
            let costs = LineCosts::new(lines.iter().map(|(s, t)| (s, *t)));
            for cand in 0..10 {
                let line = if cand == 0 {
                    truth
                } else {
                    Line::through(
                        truth.point + Vector3::new(rnd(), rnd(), rnd()) * scale * cand as f64,
                        truth.direction + Vector3::new(rnd(), rnd(), rnd()) * 0.05 * cand as f64,
                    )
                };
                let (fast, direct) = (costs.cost(&line), line_cost(&lines, &line));
                // The AVX2 kernel (where it runs) mirrors the portable one bit for bit.
                assert_eq!(fast.to_bits(), costs.cost_lanes(&line).to_bits());
                assert!(
                    (fast - direct).abs() <= 1e-9 * direct.abs().max(1.0),
                    "round {round} candidate {cand}: {fast} vs {direct}"
                );
            }
        }
    }
}
