//! A first-quadrant `atan2`, scalar and in four lanes.
//!
//! [`atan2_nonneg`] is the arctangent of the rotation angle in every SE(3) logarithm of the
//! classifiers (`θ = 2·atan2(|q_v|, |w|)`), where libm's general `atan2` was the largest single
//! cost per frame. Both arguments are non-negative there, which removes the quadrant logic.

use super::lanes::{Real, F4};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

/// `π/2 = FRAC_PI_2 + MOREBITS`: the part of π/2 below the last bit of `FRAC_PI_2`, added back
/// after the reduction `atan(x) = π/2 - atan(1/x)` so that no precision is lost there.
const MOREBITS: f64 = 6.123_233_995_736_766e-17;
/// `tan(3π/8)`: above it the argument is reduced by `π/2 - atan(1/x)`.
const TAN_3PI_8: f64 = 2.414_213_562_373_095;
/// Below this the rational approximation is used directly; between it and [`TAN_3PI_8`] the
/// argument is reduced by `π/4 + atan((x-1)/(x+1))`.
const REDUCE_AT: f64 = 0.66;

/// Numerator coefficients of Cephes' `atan` rational approximation (see [`atan_reduced`]).
const P: [f64; 5] = [
    -8.750_608_600_031_904e-1,
    -1.615_753_718_733_365e1,
    -7.500_855_792_314_705e1,
    -1.228_866_684_490_136e2,
    -6.485_021_904_942_025e1,
];
/// Denominator coefficients (leading 1 implied) of the same approximation.
const Q: [f64; 5] = [
    2.485_846_490_142_306e1,
    1.650_270_098_316_988_5e2,
    4.328_810_604_912_903e2,
    4.853_903_996_359_137e2,
    1.945_506_571_482_614e2,
];

/// `atan(x)` for `x ∈ [0, 0.66]`: `x + x·z·P(z)/Q(z)` with `z = x²`, the degree-4/5 rational
/// approximation of Cephes' `atan` (relative error about 1e-16 on this interval).
#[inline(always)]
fn atan_reduced<T: Real>(x: T) -> T {
    let z = x * x;
    let p = (((z * P[0] + P[1]) * z + P[2]) * z + P[3]) * z + P[4];
    let q = ((((z + Q[0]) * z + Q[1]) * z + Q[2]) * z + Q[3]) * z + Q[4];
    x + x * (z * p / q)
}

/// `atan2(y, x)` for `y ≥ 0` and `x ≥ 0` (the first quadrant), in `[0, π/2]`; `0` for
/// `(0, 0)`. Within 2 ulp of libm's `atan2` (tested over 24 decades of y/x), at about a third
/// of its cost: one reduction with one division, then a rational approximation.
#[inline]
pub fn atan2_nonneg(y: f64, x: f64) -> f64 {
    debug_assert!(y >= 0.0 && x >= 0.0, "atan2_nonneg({y}, {x})");
    if y > TAN_3PI_8 * x {
        // atan(y/x) = π/2 - atan(x/y); y > 0 here.
        FRAC_PI_2 - atan_reduced(x / y) + MOREBITS
    } else if y > REDUCE_AT * x {
        // atan(y/x) = π/4 + atan((y - x)/(y + x)).
        FRAC_PI_4 + atan_reduced((y - x) / (y + x)) + 0.5 * MOREBITS
    } else if x > 0.0 {
        atan_reduced(y / x)
    } else {
        0.0
    }
}

/// [`atan2_nonneg`] of four lanes, each rounded as the scalar one: the three cases of the
/// reduction are selected per lane, around one division and one rational approximation.
#[inline(always)]
pub fn atan2_nonneg4(y: F4, x: F4) -> F4 {
    let high = y.gt(x * TAN_3PI_8);
    let mid = !high & y.gt(x * REDUCE_AT);
    let num = high.select(x, mid.select(y - x, y));
    let den = high.select(y, mid.select(y + x, x));
    let r = atan_reduced(num / den);
    let low = x.gt(F4::splat(0.0)).select(r, F4::splat(0.0));
    high.select(
        (FRAC_PI_2 - r) + MOREBITS,
        mid.select((FRAC_PI_4 + r) + 0.5 * MOREBITS, low),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place between `a` and `b` (both finite, same sign).
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    #[test]
    fn matches_libm_over_all_ratios() {
        let mut worst = 0;
        let mut state =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x9e37_79b9_7f4a_7c15);
        for k in 0..200_000 {
            // log10(y/x) uniform in [-12, 12], and a random scale of both.
            let u = rand::Rng::random::<f64>(&mut state);
            let ratio = 10f64.powf(24.0 * u - 12.0);
            let x = 1e-3 + (k % 1000) as f64 * 1e-3;
            let y = ratio * x;
            let (a, b) = (atan2_nonneg(y, x), y.atan2(x));
            worst = worst.max(ulps(a, b));
            assert!(ulps(a, b) <= 2, "atan2({y}, {x}): {a} vs {b}");
        }
        // The reduction boundaries, and the axes.
        for &(y, x) in &[
            (TAN_3PI_8, 1.0),
            (0.66, 1.0),
            (1.0, 1.0),
            (1.0, 0.0),
            (0.0, 1.0),
            (1e-300, 1.0),
            (1.0, 1e-300),
        ] {
            for (yy, xx) in [(y, x), (f64::from_bits(y.to_bits() + 1), x)] {
                assert!(
                    ulps(atan2_nonneg(yy, xx), yy.atan2(xx)) <= 2,
                    "({yy}, {xx})"
                );
            }
        }
        assert_eq!(atan2_nonneg(0.0, 0.0), 0.0);
        println!("largest difference from libm: {worst} ulp");
    }
    #[test]
    fn four_lanes_give_the_scalar_bits() {
        let mut state =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x2545_f491_4f6c_dd1d);
        let mut pairs: Vec<(f64, f64)> = (0..40_000)
            .map(|_| {
                let u = rand::Rng::random::<f64>(&mut state);
                let x = rand::Rng::random::<f64>(&mut state) + 1e-3;
                (10f64.powf(24.0 * u - 12.0) * x, x)
            })
            .collect();
        for &(y, x) in &[
            (TAN_3PI_8, 1.0),
            (REDUCE_AT, 1.0),
            (1.0, 1.0),
            (1.0, 0.0),
            (0.0, 1.0),
        ] {
            pairs.extend([(y, x), (f64::from_bits(y.to_bits() + 1), x)]);
        }
        pairs.extend([(0.0, 0.0), (f64::INFINITY, 1.0), (1e-300, 1e-300)]);
        for c in pairs.chunks(4) {
            let y = F4::from_fn(|k| c[k % c.len()].0);
            let x = F4::from_fn(|k| c[k % c.len()].1);
            let r = atan2_nonneg4(y, x);
            for k in 0..4 {
                let s = atan2_nonneg(y.0[k], x.0[k]);
                assert!(
                    r.0[k].to_bits() == s.to_bits() || (r.0[k].is_nan() && s.is_nan()),
                    "atan2({}, {}): {} vs {s}",
                    y.0[k],
                    x.0[k],
                    r.0[k]
                );
            }
        }
    }
}
