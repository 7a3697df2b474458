//! The free-flight model fitted to a window of poses.
//!
//! In free flight the centre of mass, a point `c` fixed in the object frame, moves with
//! gravity's acceleration `g` whatever the object spins:
//!
//! ```text
//! p(t) + R(t) c = x0 + v0 τ + ½ g τ²        (τ = t − t_mid, world_from_object = (R, p))
//! ```
//!
//! which is linear in the nine unknowns `(c, x0, v0)`: three equations per frame, solved by
//! weighted linear least squares. Frame k's residual `e_k = p_k + R_k c − x0 − v0 τ − ½ g τ²`
//! has covariance `Σ_k = (σ_p² + t²) I + σ_r² (|c|² I − r rᵀ)` with `r = R_k c` (a rotation error
//! δθ moves `R c` by `δθ × R c`) and `t` [`FLIGHT_TOLERANCE_M`]; `Σ_k` depends on `c`, so the fit is
//! iterated once with the first pass's `c` (brought within `r_max` of the origin). `c` is unobservable when the object does not turn
//! (then `R c` is a constant that `x0` absorbs): a weak prior `c ~ N(0, r_max² I)` keeps the
//! system solvable, and the residual degrees of freedom are `3n − tr((N + P)⁻¹ N)` (the
//! parameters the data determine; `N` the data's normal matrix, `P` the prior's).
//!
//! The same fit with `g = 0` is the alternative "no acceleration" (a rest, a constant-velocity
//! carry, a rotation about a fixed point, which `c` on the axis makes exactly unaccelerated),
//! with `c` on the object as a centre of mass must be ([`fit_on_object`]): a window is a
//! flight only if the data reject it, i.e. the window is long enough for the fall under
//! gravity to show above the noise.

use crate::noise::NoiseModel;
use crate::recording::RecordedFrame;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// A frame as the fit takes it: its time, rotation matrix and position (world_from_object).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightFrame {
    /// Time \[s\].
    pub t: f64,
    /// Rotation of `world_from_object`.
    pub rotation: Matrix3<f64>,
    /// Position of `world_from_object` \[m\].
    pub position: Vector3<f64>,
}

impl From<&RecordedFrame> for FlightFrame {
    fn from(f: &RecordedFrame) -> Self {
        Self {
            t: f.t,
            rotation: f.rotation.to_rotation_matrix().into_inner(),
            position: f.position,
        }
    }
}

/// Model tolerance \[m\] added in quadrature to the position noise: what a real flight may
/// deviate from a parabola by (air drag on a light box, the simulator's integration) and a
/// floor for exact poses. 0.1 mm: drag of 0.1 m/s² shows by this much over 0.045 s.
pub const FLIGHT_TOLERANCE_M: f64 = 1e-4;

/// Largest standard deviation \[m\] of a flight's centre of mass for it to be reported.
pub const COM_SD_MAX_M: f64 = 5e-3;

type M9 = SMatrix<f64, 9, 9>;
type V9 = SVector<f64, 9>;

/// A flight model fitted to a window of frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightFit {
    /// The point `c` that moves with gravity (the centre of mass), object frame \[m\].
    pub com: Vector3<f64>,
    /// Its covariance \[m²\].
    pub com_cov: Matrix3<f64>,
    /// How `com` moves with the gravity the fit was given: `∂c/∂g` \[m / (m/s²)\], column `k`
    /// the change of `c` (object frame) per unit change of gravity's world component `k`.
    /// A gravity whose direction is off by 1° moves a slowly turning flight's `c` by
    /// millimetres ([`crate::shared_com`] takes it into account).
    pub com_gravity_sensitivity: Matrix3<f64>,
    /// Whether the data determine `c`: the prior's weight is below 1% of the data's in every
    /// direction, and its standard deviation is at most [`COM_SD_MAX_M`] (the object turned
    /// enough over the window, about more than one axis).
    pub com_determined: bool,
    /// `c`'s world position at `t_mid` \[m\].
    pub x0: Vector3<f64>,
    /// Its velocity at `t_mid` \[m/s\].
    pub v0: Vector3<f64>,
    /// The middle time of the window \[s\].
    pub t_mid: f64,
    /// χ² of the residuals.
    pub chi2: f64,
    /// Its degrees of freedom.
    pub dof: f64,
}

/// A centre of mass known before a window is fitted: the point the flights of the
/// demonstrations learnt together agree on ([`crate::shared_com`]), with its covariance, and
/// the acceleration those flights fell with (the gravity given less the error they measured in
/// it). With it, a window is a flight of *that* point: over a short window a flight's own
/// point can absorb frames that are no flight (a box that lands on an edge and rolls over it
/// in a few hundredths of a second), which the known point cannot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnownCom {
    /// The point, object frame \[m\].
    pub point: Vector3<f64>,
    /// Its covariance \[m²\].
    pub covariance: Matrix3<f64>,
    /// The acceleration the flights fell with, world frame \[m/s²\].
    pub fall: Vector3<f64>,
}

/// Weighted least-squares fit of `p + R c = x0 + v0 τ + ½ a τ²` to `frames` (at least 4), with
/// the prior `c ~ N(0, r_max²)`. `None` if degenerate.
///
/// `with_com`: whether to work out `com_determined` (a 6×6 inverse and two eigen
/// decompositions, for a flight's final fit only; otherwise it is false).
pub fn fit(
    frames: &[FlightFrame],
    accel: &Vector3<f64>,
    noise: &NoiseModel,
    r_max: f64,
    with_com: bool,
) -> Option<FlightFit> {
    fit_with(frames, accel, noise, r_max, with_com, false, None)
}

/// [`fit`] of a flight of the point `known` (its prior `c ~ N(point, covariance)` in place of
/// the weak one, its acceleration `known.fall`): the prior's residual counts in the χ², as
/// three more measurements, so the degrees of freedom are `3n + 3 − 9`.
pub fn fit_known(
    frames: &[FlightFrame],
    known: &KnownCom,
    noise: &NoiseModel,
    r_max: f64,
) -> Option<FlightFit> {
    fit_with(frames, &known.fall, noise, r_max, false, false, Some(known))
}

/// [`fit`] with the point `c` on the object: at most `r_max` from its origin, the bound a
/// flight's centre of mass must meet. The alternatives a flight is tested against take it:
/// without it, "no acceleration" explains a short flight of a slowly turning object by a
/// point a metre away, whose circle through the window bends as gravity does (a real toss
/// of the ContactNets cube at 3 rad/s: `c` 0.99 m from the cube, χ² 16 on 30 degrees of
/// freedom). `com_cov` and `com_determined` are the unbounded fit's.
pub fn fit_on_object(
    frames: &[FlightFrame],
    accel: &Vector3<f64>,
    noise: &NoiseModel,
    r_max: f64,
) -> Option<FlightFit> {
    fit_with(frames, accel, noise, r_max, false, true, None)
}

fn fit_with(
    frames: &[FlightFrame],
    accel: &Vector3<f64>,
    noise: &NoiseModel,
    r_max: f64,
    with_com: bool,
    bounded: bool,
    known: Option<&KnownCom>,
) -> Option<FlightFit> {
    if frames.len() < 4 {
        return None;
    }
    // The prior on c: its information and mean (the weak one's information per axis `prior`).
    let prior = 1.0 / (r_max * r_max);
    let (prior_info, prior_mean) = match known {
        Some(k) => (k.covariance.try_inverse()?, k.point),
        None => (Matrix3::identity() * prior, Vector3::zeros()),
    };
    let t_mid = 0.5 * (frames[0].t + frames[frames.len() - 1].t);
    let var_p = noise.sigma_position.powi(2) + FLIGHT_TOLERANCE_M.powi(2);
    let var_r = noise.sigma_rotation.powi(2);
    let mut com = prior_mean;
    let mut out = None;
    for _pass in 0..2 {
        // The weights' c, at most r_max from the origin: a window the model does not explain
        // may pull c far (to use a slight turn), and its noise would then excuse anything.
        let c0 = if com.norm() > r_max {
            com * (r_max / com.norm())
        } else {
            com
        };
        let weight = |r: &Matrix3<f64>| -> Matrix3<f64> {
            let (com, rc) = (c0, r * c0);
            let cov = Matrix3::identity() * (var_p + var_r * com.norm_squared())
                - rc * rc.transpose() * var_r;
            cov.try_inverse()
                .unwrap_or_else(|| Matrix3::identity() / var_p)
        };
        let (mut n, mut rhs) = (M9::zeros(), V9::zeros());
        // ∂rhs/∂g: the right-hand side's derivative with respect to gravity.
        let mut rhs_g = SMatrix::<f64, 9, 3>::zeros();
        for f in frames {
            let (r, w) = (&f.rotation, weight(&f.rotation));
            let tau = f.t - t_mid;
            let y = 0.5 * accel * tau * tau - f.position;
            // A = [R, -I, -τ I]; accumulate Aᵀ W A and Aᵀ W y block by block.
            let blocks = [*r, -Matrix3::identity(), -Matrix3::identity() * tau];
            for (a, ba) in blocks.iter().enumerate() {
                let bw = ba.transpose() * w;
                let mut r = rhs.fixed_rows_mut::<3>(3 * a);
                r += bw * y;
                let mut rg = rhs_g.fixed_rows_mut::<3>(3 * a);
                rg += bw * (0.5 * tau * tau);
                for (b, bb) in blocks.iter().enumerate().skip(a) {
                    let m = bw * bb;
                    let mut ab = n.fixed_view_mut::<3, 3>(3 * a, 3 * b);
                    ab += m;
                    if b != a {
                        let mut ba = n.fixed_view_mut::<3, 3>(3 * b, 3 * a);
                        ba += m.transpose();
                    }
                }
            }
        }
        let mut np = n;
        let mut np_cc = np.fixed_view_mut::<3, 3>(0, 0);
        np_cc += prior_info;
        let mut rhs_prior = rhs;
        let mut rhs_c = rhs_prior.fixed_rows_mut::<3>(0);
        rhs_c += prior_info * prior_mean;
        let inv = np.try_inverse()?;
        let mut x = inv * rhs_prior;
        if bounded && x.fixed_rows::<3>(0).norm() > r_max {
            x = on_ball(&np, &rhs_prior, r_max)?;
        }
        com = x.fixed_rows::<3>(0).into_owned();
        let (x0, v0) = (
            x.fixed_rows::<3>(3).into_owned(),
            x.fixed_rows::<3>(6).into_owned(),
        );
        let mut chi2 = 0.0;
        for f in frames {
            let (r, w) = (&f.rotation, weight(&f.rotation));
            let tau = f.t - t_mid;
            let e = f.position + r * com - x0 - v0 * tau - 0.5 * accel * tau * tau;
            chi2 += e.dot(&(w * e));
        }
        // A known point's prior is three more measurements: its residual counts, and the
        // degrees of freedom are 3n + 3 − 9 (the data's 3n less the 6 that the nine unknowns
        // take beyond the prior's 3).
        let (prior_chi2, used) = match known {
            Some(_) => {
                let d = com - prior_mean;
                (d.dot(&(prior_info * d)), 6.0)
            }
            None => (0.0, (inv * n).trace()),
        };
        chi2 += prior_chi2;
        let cov_c = inv.fixed_view::<3, 3>(0, 0).into_owned();
        let determined = with_com && determines_com(&n, &cov_c, prior);
        out = Some(FlightFit {
            com,
            com_cov: cov_c,
            com_gravity_sensitivity: (inv * rhs_g).fixed_rows::<3>(0).into_owned(),
            com_determined: determined,
            x0,
            v0,
            t_mid,
            chi2,
            dof: (3.0 * frames.len() as f64 - used).max(1.0),
        });
    }
    out
}

/// The least-squares solution of `np x = rhs` with `c` (its first three rows) at most `r_max`
/// from the origin, when the unconstrained one is farther: with `x0, v0` eliminated
/// (`o(c) = D⁻¹ (r_o − Bᵀ c)`), `c` minimises `½ cᵀ S c − sᵀ c` on the ball, which is
/// `c(λ) = (S + λ I)⁻¹ s` with the `λ ≥ 0` that puts it on the sphere (`|c(λ)|` falls as `λ`
/// grows: bisection).
fn on_ball(np: &M9, rhs: &V9, r_max: f64) -> Option<V9> {
    let a = np.fixed_view::<3, 3>(0, 0).into_owned();
    let b = np.fixed_view::<3, 6>(0, 3).into_owned();
    let d_inv = np.fixed_view::<6, 6>(3, 3).into_owned().try_inverse()?;
    let (r_c, r_o) = (
        rhs.fixed_rows::<3>(0).into_owned(),
        rhs.fixed_rows::<6>(3).into_owned(),
    );
    let s_mat = a - b * d_inv * b.transpose();
    let s = r_c - b * d_inv * r_o;
    let c_of = |l: f64| {
        (s_mat + Matrix3::identity() * l)
            .try_inverse()
            .map(|m| m * s)
    };
    // At λ = |s| / r_max, |c| ≤ |s| / λ = r_max (S is positive semi-definite).
    let (mut lo, mut hi) = (0.0, s.norm() / r_max);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if c_of(mid)?.norm() > r_max {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let c = c_of(hi)?;
    let o = d_inv * (r_o - b.transpose() * c);
    let mut x = V9::zeros();
    x.fixed_rows_mut::<3>(0).copy_from(&c);
    x.fixed_rows_mut::<6>(3).copy_from(&o);
    Some(x)
}

/// Whether the data (normal matrix `n`) determine `c`: its information with `x0` and `v0`
/// eliminated (the Schur complement) exceeds 100 times the prior's in every direction, and
/// its covariance `cov_c` has standard deviations of at most [`COM_SD_MAX_M`].
fn determines_com(n: &M9, cov_c: &Matrix3<f64>, prior: f64) -> bool {
    let n_cc = n.fixed_view::<3, 3>(0, 0).into_owned();
    let n_co = n.fixed_view::<3, 6>(0, 3).into_owned();
    let n_oo = n.fixed_view::<6, 6>(3, 3).into_owned();
    let info = n_oo
        .try_inverse()
        .map(|i| n_cc - n_co * i * n_co.transpose());
    info.is_some_and(|m| m.symmetric_eigenvalues().iter().all(|&l| l > 100.0 * prior))
        && cov_c.symmetric_eigenvalues().max() <= COM_SD_MAX_M.powi(2)
}

/// Whether a fit passes its χ² test at `alpha`.
pub fn passes(f: &FlightFit, alpha: f64) -> bool {
    f.chi2 <= crate::stats::chi2_threshold(f.dof, alpha)
}

/// χ² (3 degrees of freedom) of one frame's residual under a fit with acceleration `accel`
/// (its noise only: the fit's own uncertainty is left out, which makes the test stricter).
pub fn frame_chi2(
    fit: &FlightFit,
    f: &FlightFrame,
    accel: &Vector3<f64>,
    noise: &NoiseModel,
) -> f64 {
    let tau = f.t - fit.t_mid;
    let rc = f.rotation * fit.com;
    let e = f.position + rc - fit.x0 - fit.v0 * tau - 0.5 * accel * tau * tau;
    let var_r = noise.sigma_rotation.powi(2);
    let cov = Matrix3::identity()
        * (noise.sigma_position.powi(2)
            + FLIGHT_TOLERANCE_M.powi(2)
            + var_r * fit.com.norm_squared())
        - rc * rc.transpose() * var_r;
    cov.try_inverse().map_or(f64::INFINITY, |w| e.dot(&(w * e)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// `½ xᵀ N x − rhsᵀ x`, which the least-squares solution minimises.
    fn objective(np: &M9, rhs: &V9, x: &V9) -> f64 {
        0.5 * x.dot(&(np * x)) - rhs.dot(x)
    }

    /// On random positive definite systems whose free solution lies outside the ball: the
    /// bounded solution's point is on the sphere, `x0, v0` are optimal for it (the gradient
    /// along them vanishes), and no other point of the ball, with its own optimal `x0, v0`,
    /// does better.
    #[test]
    fn the_bounded_solution_is_the_best_point_of_the_ball() {
        let mut rng = StdRng::seed_from_u64(58);
        for _ in 0..200 {
            let a = SMatrix::<f64, 12, 9>::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let np = a.transpose() * a + M9::identity() * 1e-3;
            let rhs = V9::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let free = np.try_inverse().unwrap() * rhs;
            let r_max = 0.5 * free.fixed_rows::<3>(0).norm();
            let x = on_ball(&np, &rhs, r_max).unwrap();
            let c = x.fixed_rows::<3>(0).into_owned();
            assert!(
                (c.norm() / r_max - 1.0).abs() < 1e-9,
                "{} vs {r_max}",
                c.norm()
            );
            let gradient = np * x - rhs;
            assert!(gradient.fixed_rows::<6>(3).norm() < 1e-9 * rhs.norm().max(1.0));
            let best = objective(&np, &rhs, &x);
            let d_inv = np
                .fixed_view::<6, 6>(3, 3)
                .into_owned()
                .try_inverse()
                .unwrap();
            let b = np.fixed_view::<3, 6>(0, 3).into_owned();
            for _ in 0..50 {
                let dir = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0f64)).normalize();
                let other = dir * r_max * rng.random_range(0.0..=1.0f64).cbrt();
                let o = d_inv * (rhs.fixed_rows::<6>(3) - b.transpose() * other);
                let mut y = V9::zeros();
                y.fixed_rows_mut::<3>(0).copy_from(&other);
                y.fixed_rows_mut::<6>(3).copy_from(&o);
                assert!(objective(&np, &rhs, &y) >= best - 1e-9 * best.abs().max(1.0));
            }
        }
    }
}
