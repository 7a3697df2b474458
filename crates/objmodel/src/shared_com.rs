//! The object's centre of mass, from the flights of all the demonstrations learnt together:
//! what tells a tossed object's roll from its flight.
//!
//! A roll over an edge is a rotation about a fixed line, and over a short window one point of
//! the object falls with gravity as in a flight (its centre of acceleration, 0.1-0.3 m from the
//! edge); only when that point cannot be the centre of mass is the window not a flight
//! ([`crate::roll`], `RollTest::com_rules_out`). A demonstration knows its centre of mass where
//! two of its flights agree on it ([`crate::flight`]); a toss with one flight does not, and its
//! rolls then teach nothing. Learnt with other tosses of the object, it takes the centre of
//! mass that all their flights measure together.
//!
//! One flight's centre of mass is often wrong: a flight window that holds a short bounce
//! passes its own test with a wrong point absorbing the kink (on 200 motion-capture tosses,
//! 3.3 σ off in the median, 47 σ at the 90th percentile). So the pooled point is robust: it
//! starts at the coordinate-wise median of the flights' points, keeps the flights it explains
//! (χ²₃ at [`AGREEMENT_ALPHA`] on each one's residual, under its covariance and the pooled
//! estimate's), and is their weighted least-squares point, its covariance widened by their
//! Birge ratio where they scatter more than their covariances say; repeated until the kept
//! flights do not change. Nothing is shared unless the kept flights come from at least
//! [`MIN_DEMONSTRATIONS`] demonstrations and are most of the flights: flights that do not
//! agree on one point may be of different objects, or of none.
//!
//! **Gravity.** A flight's point is the one that falls with the gravity the learner was given,
//! and a gravity off by 1° in direction (a tracking frame not quite level) moves a slowly
//! turning flight's point by millimetres (`FlightFit::com_gravity_sensitivity`, `S`). That
//! error is common to all the flights (one world frame), so it does not average down as their
//! noise does; but each flight turns it into the object frame in its own way, so the flights
//! together measure it. The pooled estimate is of the point `c` and gravity's error `δg`
//! together: flight `i` measured `cᵢ = c + Sᵢ δg + nᵢ` (`nᵢ` its noise, covariance `Cᵢ`), with
//! the prior `δg ~ N(0, σ_g² I)`, `σ_g` = [`GRAVITY_SIGMA_RAD`] of `g` (direction, and the
//! same fraction in magnitude: a tracker's clock off by 0.9% makes gravity look 1.7% off).
//! The point's covariance is the joint fit's, so it holds what the flights leave unknown of
//! `δg`; the Birge ratio is taken on the fit's residual degrees of freedom,
//! `3n − tr(H⁻¹ N)` (`N` the data's normal matrix, `H` with the prior's).

use crate::flight::ComEstimate;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use serde::{Deserialize, Serialize};

/// The fewest demonstrations whose flights must agree on the point.
pub const MIN_DEMONSTRATIONS: usize = 3;

/// Level of the test of each flight's centre of mass against the pooled one: that at which a
/// demonstration's own flights are tested against each other (`flight::COM_AGREEMENT_ALPHA`),
/// the tree's consistency checks' level.
pub const AGREEMENT_ALPHA: f64 = 1e-4;

/// How well \[rad\] gravity's direction in the tracking frame is taken to be known, the level
/// of the support ([`crate::face::SUPPORT_LEVEL_SIGMA_RAD`]); its magnitude to the same
/// fraction.
pub const GRAVITY_SIGMA_RAD: f64 = crate::face::SUPPORT_LEVEL_SIGMA_RAD;

/// Most passes of the robust estimate (it converges in two or three).
const MAX_PASSES: usize = 20;

/// The centre of mass the flights of the demonstrations learnt together measured.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SharedCom {
    /// The point, object frame \[m\].
    pub point: Vector3<f64>,
    /// Its covariance \[m²\].
    pub covariance: Matrix3<f64>,
    /// How many flights agreed on it.
    pub flights: usize,
    /// Of how many flights that determined a point.
    pub flights_seen: usize,
    /// How many demonstrations the agreeing flights came from.
    pub demonstrations: usize,
    /// What the flights say the gravity they were measured under is off by (the gravity given
    /// less the one the flights fell with), in the poses' frame \[m/s²\] (the estimate of
    /// `δg`; see the module documentation).
    #[serde(default = "Vector3::zeros")]
    pub gravity_error: Vector3<f64>,
}

/// The centre of mass that `flights` (each the index of its demonstration and the point its
/// flight measured) agree on, if enough of them do (see the module documentation).
pub fn shared_com(flights: &[(usize, ComEstimate)]) -> Option<SharedCom> {
    let usable: Vec<&(usize, ComEstimate)> = flights
        .iter()
        .filter(|(_, e)| {
            e.covariance.try_inverse().is_some()
                && e.point.iter().all(|x| x.is_finite())
                && e.gravity_sensitivity.iter().all(|x| x.is_finite())
        })
        .collect();
    if usable.is_empty() {
        return None;
    }
    let median = |k: usize| {
        let mut v: Vec<f64> = usable.iter().map(|(_, e)| e.point[k]).collect();
        crate::stats::median(&mut v).unwrap_or(0.0)
    };
    // The start: the median point, gravity as given, known to the prior.
    let mut pooled = Pooled {
        point: Vector3::new(median(0), median(1), median(2)),
        gravity_error: Vector3::zeros(),
        covariance: SMatrix::from_diagonal(&SVector::<f64, 6>::from_fn(|k, _| {
            if k < 3 {
                0.0
            } else {
                Pooled::gravity_variance()
            }
        })),
    };
    let limit = crate::stats::chi2_threshold(3.0, AGREEMENT_ALPHA);
    let mut kept: Vec<bool> = Vec::new();
    for _ in 0..MAX_PASSES {
        let now: Vec<bool> = usable
            .iter()
            .map(|(_, e)| pooled.explains(e, limit))
            .collect();
        if now == kept {
            break;
        }
        kept = now;
        let chosen: Vec<&ComEstimate> = usable
            .iter()
            .zip(&kept)
            .filter(|(_, &k)| k)
            .map(|((_, e), _)| e)
            .collect();
        pooled = Pooled::fit(&chosen)?;
    }
    let agreeing: Vec<usize> = usable
        .iter()
        .zip(&kept)
        .filter(|(_, &k)| k)
        .map(|((d, _), _)| *d)
        .collect();
    let mut demos = agreeing.clone();
    demos.sort_unstable();
    demos.dedup();
    let most = 2 * agreeing.len() > usable.len();
    (most && demos.len() >= MIN_DEMONSTRATIONS).then_some(SharedCom {
        point: pooled.point,
        covariance: pooled.covariance.fixed_view::<3, 3>(0, 0).into_owned(),
        flights: agreeing.len(),
        flights_seen: usable.len(),
        demonstrations: demos.len(),
        gravity_error: pooled.gravity_error,
    })
}

/// The joint estimate of the point and gravity's error, with their covariance (6 × 6: the
/// point's rows first).
struct Pooled {
    point: Vector3<f64>,
    gravity_error: Vector3<f64>,
    covariance: SMatrix<f64, 6, 6>,
}

impl Pooled {
    /// The variance \[(m/s²)²\] of the prior on gravity's error, per world axis.
    fn gravity_variance() -> f64 {
        (crate::pendulum::G * GRAVITY_SIGMA_RAD).powi(2)
    }

    /// `∂cᵢ/∂(c, δg) = [I, Sᵢ]` of flight `e`.
    fn jacobian(e: &ComEstimate) -> SMatrix<f64, 3, 6> {
        let mut j = SMatrix::<f64, 3, 6>::zeros();
        j.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        j.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&e.gravity_sensitivity);
        j
    }

    /// Flight `e`'s residual `cᵢ − c − Sᵢ δg` and its covariance (its own and the estimate's).
    fn residual(&self, e: &ComEstimate) -> (Vector3<f64>, Matrix3<f64>) {
        let d = e.point - self.point - e.gravity_sensitivity * self.gravity_error;
        let j = Self::jacobian(e);
        (d, e.covariance + j * self.covariance * j.transpose())
    }

    /// Whether flight `e`'s residual passes χ²₃ at `limit`.
    fn explains(&self, e: &ComEstimate, limit: f64) -> bool {
        let (d, cov) = self.residual(e);
        cov.try_inverse().is_some_and(|w| d.dot(&(w * d)) <= limit)
    }

    /// The weighted least-squares estimate of `(c, δg)` from `flights`, its covariance widened
    /// by the Birge ratio where it exceeds one; `None` for no flights.
    fn fit(flights: &[&ComEstimate]) -> Option<Self> {
        if flights.is_empty() {
            return None;
        }
        let (mut n, mut b) = (SMatrix::<f64, 6, 6>::zeros(), SVector::<f64, 6>::zeros());
        for e in flights {
            let w = e.covariance.try_inverse()?;
            let j = Self::jacobian(e);
            n += j.transpose() * w * j;
            b += j.transpose() * (w * e.point);
        }
        let mut h = n;
        for k in 3..6 {
            h[(k, k)] += 1.0 / Self::gravity_variance();
        }
        let covariance = h.try_inverse()?;
        let x = covariance * b;
        let mut pooled = Self {
            point: x.fixed_rows::<3>(0).into_owned(),
            gravity_error: x.fixed_rows::<3>(3).into_owned(),
            covariance,
        };
        let chi2: f64 = flights
            .iter()
            .filter_map(|e| {
                let d = e.point - pooled.point - e.gravity_sensitivity * pooled.gravity_error;
                e.covariance.try_inverse().map(|w| d.dot(&(w * d)))
            })
            .sum();
        let dof = 3.0 * flights.len() as f64 - (covariance * n).trace();
        if dof > 0.5 {
            pooled.covariance *= (chi2 / dof).max(1.0);
        }
        Some(pooled)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    fn estimate(point: Vector3<f64>, sigma: f64) -> ComEstimate {
        ComEstimate {
            point,
            covariance: Matrix3::identity() * sigma * sigma,
            gravity_sensitivity: Matrix3::zeros(),
            frames: 30,
        }
    }

    /// Flights of one object (σ 2-6 mm each, drawn about the truth), a third of them wrong (a
    /// bounce absorbed: 20-80 mm off, with a σ as small as a good one's): the pooled
    /// point is within 3 of its σ of the truth in every draw, and its σ is honest (the median
    /// of its χ²₃ over the draws near the χ₃ median, 1.54, squared: 2.37).
    #[test]
    fn the_pooled_point_is_robust_to_wrong_flights_and_its_sigma_honest() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let truth = Vector3::new(0.004, -0.012, -0.035);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let mut chi2s = Vec::new();
        for _ in 0..200 {
            let mut flights = Vec::new();
            for demo in 0..12 {
                let sigma = rng.random_range(0.002..0.006);
                let wrong = demo % 3 == 0;
                let noise = Vector3::from_fn(|_, _| unit.sample(&mut rng)) * sigma;
                let off = if wrong {
                    let dir = Vector3::from_fn(|_, _| unit.sample(&mut rng)).normalize();
                    dir * rng.random_range(0.02..0.08)
                } else {
                    Vector3::zeros()
                };
                flights.push((demo, estimate(truth + noise + off, sigma)));
            }
            let s = shared_com(&flights).expect("most flights agree");
            let d = s.point - truth;
            let chi2 = d.dot(&(s.covariance.try_inverse().unwrap() * d));
            assert!(chi2 < crate::stats::chi2_threshold(3.0, 1e-4), "χ² {chi2}");
            chi2s.push(chi2);
        }
        let m = crate::stats::median(&mut chi2s).unwrap();
        assert!((1.6..3.4).contains(&m), "median χ²₃ {m} (honest 2.37)");
    }

    /// Flights of one object measured under a gravity off by about a degree (drawn from the
    /// prior, common to the flights of a draw), each moved by its own sensitivity to it
    /// (random, up to 0.08 m per m/s²: a slow spin's): the pooled point's σ is honest (median
    /// χ²₃ near 2.37 over 300 draws), the gravity's error is measured, and the same flights
    /// pooled as if their points did not depend on gravity give a dishonest σ.
    #[test]
    fn a_gravity_common_to_the_flights_is_estimated_with_the_point() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(62);
        let truth = Vector3::new(0.004, -0.012, -0.035);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let sigma_g = crate::pendulum::G * GRAVITY_SIGMA_RAD;
        let (mut chi2s, mut blind, mut g_chi2s) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..300 {
            let dg = Vector3::from_fn(|_, _| unit.sample(&mut rng)) * sigma_g;
            let mut flights = Vec::new();
            for demo in 0..15 {
                let sigma = rng.random_range(0.001..0.004);
                let sens = Matrix3::from_fn(|_, _| rng.random_range(-0.08..0.08));
                let noise = Vector3::from_fn(|_, _| unit.sample(&mut rng)) * sigma;
                let mut e = estimate(truth + sens * dg + noise, sigma);
                e.gravity_sensitivity = sens;
                flights.push((demo, e));
            }
            let chi2 = |s: &SharedCom| {
                let d = s.point - truth;
                d.dot(&(s.covariance.try_inverse().unwrap() * d))
            };
            let s = shared_com(&flights).expect("the flights agree");
            chi2s.push(chi2(&s));
            g_chi2s.push((s.gravity_error - dg).norm_squared());
            for (_, e) in &mut flights {
                e.gravity_sensitivity = Matrix3::zeros();
            }
            if let Some(s) = shared_com(&flights) {
                blind.push(chi2(&s));
            }
        }
        let m = crate::stats::median(&mut chi2s).unwrap();
        assert!((1.8..3.0).contains(&m), "median χ²₃ {m} (honest 2.37)");
        let g_rms = (g_chi2s.iter().sum::<f64>() / g_chi2s.len() as f64).sqrt();
        assert!(g_rms < 0.3 * sigma_g, "gravity's error to {g_rms} m/s²");
        let b = crate::stats::median(&mut blind).unwrap();
        assert!(b > 5.0, "blind to gravity: median χ²₃ {b}");
    }

    /// Flights of two objects, half and half, or too few demonstrations: nothing is shared.
    #[test]
    fn flights_that_do_not_agree_or_too_few_share_nothing() {
        let a = Vector3::new(0.0, 0.0, -0.03);
        let b = Vector3::new(0.05, 0.0, -0.03);
        let two_objects: Vec<(usize, ComEstimate)> = (0..8)
            .map(|d| (d, estimate(if d % 2 == 0 { a } else { b }, 0.002)))
            .collect();
        assert_eq!(shared_com(&two_objects), None);
        let few: Vec<(usize, ComEstimate)> = (0..4).map(|k| (k / 2, estimate(a, 0.002))).collect();
        assert_eq!(shared_com(&few), None);
        let enough: Vec<(usize, ComEstimate)> = (0..3).map(|d| (d, estimate(a, 0.002))).collect();
        let s = shared_com(&enough).unwrap();
        assert_eq!((s.flights, s.flights_seen, s.demonstrations), (3, 3, 3));
        assert!((s.point - a).norm() < 1e-12);
    }
}
