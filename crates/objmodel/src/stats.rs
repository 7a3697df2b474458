//! The distributions and robust estimators that the statistical tests need.
//!
//! Every test in the classifier is a χ² test of a residual normalised by its modelled variance.
//! Quantiles are computed here rather than tabulated so that the significance level is a
//! parameter.

/// Quantile of the standard normal distribution: `P(Z <= z) = p`, for p in (0, 1).
///
/// Acklam's rational approximation (relative error < 1.2e-9).
pub fn normal_quantile(p: f64) -> f64 {
    assert!(
        p > 0.0 && p < 1.0,
        "normal_quantile: p = {p} outside (0, 1)"
    );
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.383_577_518_672_69e2,
        -3.066479806614716e1,
        2.506628277459239e0,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838e0,
        -2.549732539343734e0,
        4.374664141464968e0,
        2.938163982698783e0,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996e0,
        3.754408661907416e0,
    ];
    let plow = 0.02425;

    if p < plow {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - plow {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        let q = (-2.0 * (1.0 - p).ln()).sqrt();
        -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    }
}

/// The quantile of Student's t with `nu` degrees of freedom at `p`, by the Cornish-Fisher
/// expansion about the normal quantile (Abramowitz and Stegun 26.7.5): within 2% for
/// p ≤ 0.999 and ν ≥ 5 (9% low at ν = 3).
pub fn student_t_quantile(p: f64, nu: f64) -> f64 {
    let z = normal_quantile(p);
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * nu)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * nu * nu)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * nu.powi(3))
}

/// The two-sided p-value of the sign test: the probability that `n` fair coin flips give at
/// least `max(k, n − k)` of one side or of the other (1 when `n` is 0).
pub fn sign_test(k: u64, n: u64) -> f64 {
    let m = k.max(n - k.min(n));
    let ln_choose = |i: u64| {
        ln_gamma(n as f64 + 1.0) - ln_gamma(i as f64 + 1.0) - ln_gamma((n - i) as f64 + 1.0)
    };
    let tail: f64 = (m..=n)
        .map(|i| (ln_choose(i) - n as f64 * std::f64::consts::LN_2).exp())
        .sum();
    (2.0 * tail).min(1.0)
}

/// ln Γ(x) for x > 0 (Lanczos approximation, g = 7, n = 9; relative error ~1e-15).
pub fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Upper regularised incomplete gamma function Q(a, x) = Γ(a, x)/Γ(a): series for x < a + 1,
/// Lentz continued fraction otherwise (Numerical Recipes §6.2), to 1e-15 relative.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let ln_pre = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        let (mut sum, mut term, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * ln_pre.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        ln_pre.exp() * h
    }
}

/// Survival function of χ²_dof: P(X > x).
pub fn chi2_sf(dof: f64, x: f64) -> f64 {
    gamma_q(0.5 * dof, 0.5 * x)
}

/// Quantile of the χ² distribution with `dof` degrees of freedom: the value that a χ²_dof
/// variable exceeds with probability `alpha` (the test threshold at significance `alpha`).
///
/// Solved from [`chi2_sf`] by Newton's method on `ln Q(x) - ln α`, where
/// `d ln Q / dx = -f(x)/Q(x)` with `f` the χ² density, started from the Wilson–Hilferty
/// approximation `x ≈ k (1 - 2/(9k) + z √(2/(9k)))³` (`z` the normal quantile of `1 - α`) and
/// kept inside a bracket that every evaluation narrows (a step that would leave it bisects
/// instead). It stops when a step moves `x` by less than 1e-14 relative: `ln Q` is concave in
/// `x` for `k >= 2`, so the iterates converge quadratically, in 3-6 evaluations of `Q` against
/// the ~45 of a bisection to 1e-12 (each a continued fraction of ~√k terms; MSAC asks for
/// thresholds of hundreds of degrees of freedom).
pub fn chi2_threshold(dof: f64, alpha: f64) -> f64 {
    assert!(dof > 0.0 && alpha > 0.0 && alpha < 1.0);
    let target = alpha.ln();
    let half = 0.5 * dof;
    // ln f(x) = (k/2 - 1) ln x - x/2 - (k/2) ln 2 - ln Γ(k/2).
    let ln_norm = half * std::f64::consts::LN_2 + ln_gamma(half);
    let h = 2.0 / (9.0 * dof);
    let z = normal_quantile(1.0 - alpha);
    let mut x = (dof * (1.0 - h + z * h.sqrt()).powi(3)).max(1e-3 * dof.min(1.0));
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    for _ in 0..200 {
        let q = chi2_sf(dof, x);
        let g = q.ln() - target;
        if g > 0.0 {
            lo = lo.max(x);
        } else {
            hi = hi.min(x);
        }
        let ln_f = (half - 1.0) * x.ln() - 0.5 * x - ln_norm;
        // Newton: x - g / (d ln Q/dx) = x + g Q / f.
        let mut next = x + g * (q.ln() - ln_f).exp();
        if !(next > lo && next < hi && next.is_finite()) {
            next = if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                2.0 * x.max(lo)
            };
        }
        let step = (next - x).abs();
        x = next;
        if step <= 1e-14 * x || (hi.is_finite() && hi - lo <= 1e-15 * hi) {
            break;
        }
    }
    x
}

/// The `x` in `[lo, hi]` where an increasing `f` reaches `target`, by bisection (`halvings`
/// halvings of the interval): `lo` where `target <= f(lo)`, `hi` where `target >= f(hi)`.
pub fn invert_increasing(
    f: impl Fn(f64) -> f64,
    target: f64,
    (mut lo, mut hi): (f64, f64),
    halvings: usize,
) -> f64 {
    if target <= f(lo) {
        return lo;
    }
    if target >= f(hi) {
        return hi;
    }
    for _ in 0..halvings {
        let mid = 0.5 * (lo + hi);
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Median of a slice (reorders it). `None` when empty.
pub fn median(xs: &mut [f64]) -> Option<f64> {
    if xs.is_empty() {
        return None;
    }
    let mid = xs.len() / 2;
    xs.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
    let hi = xs[mid];
    if xs.len() % 2 == 1 {
        return Some(hi);
    }
    let lo = xs[..mid].iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Some(0.5 * (lo + hi))
}

/// Robust standard deviation of zero-mean Gaussian samples: `1.4826 · median(|x|)`.
pub fn robust_sigma_zero_mean(abs_values: &mut [f64]) -> Option<f64> {
    median(abs_values).map(|m| 1.482_602_218_505_602 * m)
}

/// The minimum of `f` on `[lo, hi]` by golden-section search, to `tol`.
pub(crate) fn golden_min(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, tol: f64) -> f64 {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut fa, mut fb) = (f(a), f(b));
    while hi - lo > tol {
        if fa < fb {
            hi = b;
            (b, fb) = (a, fa);
            a = hi - r * (hi - lo);
            fa = f(a);
        } else {
            lo = a;
            (a, fa) = (b, fb);
            b = lo + r * (hi - lo);
            fb = f(b);
        }
    }
    (lo + hi) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bisection finds the cube root to the interval's width over 2^halvings, and clamps
    /// to its ends outside the range f covers.
    #[test]
    fn an_increasing_function_is_inverted_and_clamped() {
        let cube = |x: f64| x * x * x;
        for target in [-0.5, 0.001, 0.3, 0.9] {
            let x = invert_increasing(cube, target, (-1.0, 1.0), 50);
            assert!(
                (x - f64::cbrt(target)).abs() < 2.0 / 2f64.powi(50) + 1e-15,
                "{target}"
            );
        }
        assert_eq!(invert_increasing(cube, -2.0, (-1.0, 1.0), 50), -1.0);
        assert_eq!(invert_increasing(cube, 1.0, (-1.0, 1.0), 50), 1.0);
    }

    #[test]
    fn student_quantiles_are_the_tables() {
        // Tables of Student's t, one-sided 0.999 and 0.99.
        for (p, nu, t) in [
            (0.999, 5.0, 5.893),
            (0.999, 9.0, 4.297),
            (0.999, 20.0, 3.552),
            (0.99, 5.0, 3.365),
            (0.99, 30.0, 2.457),
        ] {
            let q = student_t_quantile(p, nu);
            assert!((q / t - 1.0).abs() < 0.02, "{p} {nu}: {q} vs {t}");
        }
    }

    #[test]
    fn sign_test_against_exact_binomial_tails() {
        // n = 10: P(X >= 9) = 11/1024, two-sided 22/1024; P(X >= 5) two-sided > 1 -> 1.
        assert!((sign_test(9, 10) - 22.0 / 1024.0).abs() < 1e-12);
        assert!((sign_test(1, 10) - 22.0 / 1024.0).abs() < 1e-12);
        assert_eq!(sign_test(5, 10), 1.0);
        assert!((sign_test(11, 11) - 2.0 / 2048.0).abs() < 1e-14);
        assert_eq!(sign_test(0, 0), 1.0);
        // Against a direct sum of binomial coefficients for every k of n = 30.
        let choose = |n: u64, k: u64| (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64);
        for k in 0..=30u64 {
            let m = k.max(30 - k);
            let exact: f64 = (m..=30).map(|i| choose(30, i)).sum::<f64>() / 2f64.powi(30);
            assert!(
                (sign_test(k, 30) - (2.0 * exact).min(1.0)).abs() < 1e-12,
                "k = {k}"
            );
        }
    }

    #[test]
    fn known_quantiles() {
        assert!((normal_quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-8);
        assert!((normal_quantile(0.5)).abs() < 1e-12);
        assert!((normal_quantile(1e-6) + 4.753_424_308_822_899).abs() < 1e-7);
        // Tabulated χ² quantiles.
        assert!((chi2_threshold(1.0, 0.05) - 3.841_458_820_694_124).abs() < 1e-9);
        assert!((chi2_sf(4.0, 9.487_729_036_781_154) - 0.05).abs() < 1e-12);
        assert!((chi2_threshold(2.0, 0.01) - 9.210_340_371_976_182).abs() < 1e-9);
        assert!((chi2_threshold(3.0, 0.001) / 16.266_236_196_238_13 - 1.0).abs() < 1e-9);
        assert!((chi2_threshold(6.0, 0.001) / 22.457_744_484_825_323 - 1.0).abs() < 1e-9);
        assert!((chi2_threshold(50.0, 0.01) / 76.153_891_249_012_7 - 1.0).abs() < 1e-9);
        // Each threshold is the quantile it claims, over the degrees of freedom and levels
        // the classifier uses (1-3 per frame, up to thousands for merged blocks).
        for dof in [
            0.5, 1.0, 2.0, 3.0, 5.0, 6.0, 15.0, 100.0, 640.0, 1280.0, 5000.0, 2e5,
        ] {
            for alpha in [0.5, 0.05, 1e-3, 1e-6, 1e-12] {
                let x = chi2_threshold(dof, alpha);
                let q = chi2_sf(dof, x);
                assert!(
                    (q / alpha - 1.0).abs() < 1e-9,
                    "dof {dof} alpha {alpha}: Q({x}) = {q}"
                );
            }
        }
    }

    #[test]
    fn median_and_robust_sigma() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&mut []), None);
        // Deterministic Gaussian-like sample from the quantile function.
        let mut v: Vec<f64> = (1..2000)
            .map(|i| normal_quantile(i as f64 / 2000.0).abs() * 0.3)
            .collect();
        let s = robust_sigma_zero_mean(&mut v).unwrap();
        assert!((s - 0.3).abs() < 0.003, "{s}");
    }
}
