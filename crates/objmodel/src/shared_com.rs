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
//! (χ²₃ at [`AGREEMENT_ALPHA`] on each one's difference, under its covariance and the pooled
//! point's), and is their weighted mean, its covariance widened by their Birge ratio where
//! they scatter more than their covariances say; repeated until the kept flights do not
//! change. Nothing is shared unless the kept flights come from at least
//! [`MIN_DEMONSTRATIONS`] demonstrations and are most of the flights: flights that do not
//! agree on one point may be of different objects, or of none.

use crate::flight::ComEstimate;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// The fewest demonstrations whose flights must agree on the point.
pub const MIN_DEMONSTRATIONS: usize = 3;

/// Level of the test of each flight's centre of mass against the pooled one: that at which a
/// demonstration's own flights are tested against each other (`flight::COM_AGREEMENT_ALPHA`),
/// the tree's consistency checks' level.
pub const AGREEMENT_ALPHA: f64 = 1e-4;

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
}

/// The centre of mass that `flights` (each the index of its demonstration and the point its
/// flight measured) agree on, if enough of them do (see the module documentation).
pub fn shared_com(flights: &[(usize, ComEstimate)]) -> Option<SharedCom> {
    let usable: Vec<&(usize, ComEstimate)> = flights
        .iter()
        .filter(|(_, e)| {
            e.covariance.try_inverse().is_some() && e.point.iter().all(|x| x.is_finite())
        })
        .collect();
    if usable.is_empty() {
        return None;
    }
    let median = |k: usize| {
        let mut v: Vec<f64> = usable.iter().map(|(_, e)| e.point[k]).collect();
        crate::stats::median(&mut v).unwrap_or(0.0)
    };
    let mut point = Vector3::new(median(0), median(1), median(2));
    let mut covariance = Matrix3::zeros();
    let limit = crate::stats::chi2_threshold(3.0, AGREEMENT_ALPHA);
    let mut kept: Vec<bool> = Vec::new();
    for _ in 0..MAX_PASSES {
        let now: Vec<bool> = usable
            .iter()
            .map(|(_, e)| {
                let d = e.point - point;
                (e.covariance + covariance)
                    .try_inverse()
                    .is_some_and(|w| d.dot(&(w * d)) <= limit)
            })
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
        (point, covariance) = weighted_mean(&chosen)?;
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
        point,
        covariance,
        flights: agreeing.len(),
        flights_seen: usable.len(),
        demonstrations: demos.len(),
    })
}

/// The inverse-covariance weighted mean of `points` and its covariance, widened by the Birge
/// ratio (χ² of the points about the mean over its 3 (n − 1) degrees of freedom) where it
/// exceeds one; `None` for no points.
fn weighted_mean(points: &[&ComEstimate]) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    let (mut info, mut info_x) = (Matrix3::zeros(), Vector3::zeros());
    for e in points {
        let w = e.covariance.try_inverse()?;
        info += w;
        info_x += w * e.point;
    }
    let cov = info.try_inverse()?;
    let mean = cov * info_x;
    if points.len() < 2 {
        return Some((mean, cov));
    }
    let chi2: f64 = points
        .iter()
        .filter_map(|e| {
            let d = e.point - mean;
            e.covariance.try_inverse().map(|w| d.dot(&(w * d)))
        })
        .sum();
    let birge = chi2 / (3.0 * (points.len() - 1) as f64);
    Some((mean, cov * birge.max(1.0)))
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
