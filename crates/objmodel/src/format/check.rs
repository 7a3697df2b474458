//! The checks of a line's values, as pure functions: every value finite, the quaternion's norm
//! within [`QUAT_NORM_TOLERANCE`] of 1, the timestamp after the previous pose's. A line that
//! passes them gives a pose ([`valid_pose`]); one that fails gives a [`Problem`]
//! ([`check_values`]). [`Track`] carries what the checks need from the lines before.

use super::layout::{QUAT, QUAT_NORM_TOLERANCE, TIME, VALUES};
use super::problem::{Context, Problem};
use crate::trajectory::StampedPose;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

/// The pose of the values `v` (TUM order) if they pass the checks, with `prev_t` the previous
/// pose's time (`-inf` before the first); else `None` (then [`check_values`] tells why). The
/// quaternion is normalised without touching its sign: `q` and `-q` stay distinct.
/// `finite`: the caller knows that every value is finite, which skips that test.
#[inline(always)]
pub(crate) fn valid_pose(v: &[f64; VALUES], prev_t: f64, finite: bool) -> Option<StampedPose> {
    let [t, tx, ty, tz, qx, qy, qz, qw] = *v;
    debug_assert!(!finite || v.iter().all(|x| x.is_finite()));
    // x * 0 is 0 for a finite x and NaN otherwise: one test for all eight values.
    let finite = finite || v.iter().fold(0.0, |a, &x| a + x * 0.0) == 0.0;
    let norm = (qx * qx + qy * qy + qz * qz + qw * qw).sqrt();
    let ok = finite && (norm - 1.0).abs() <= QUAT_NORM_TOLERANCE && t > prev_t;
    if !ok {
        return None;
    }
    let rot = UnitQuaternion::new_unchecked(Quaternion::new(qw, qx, qy, qz) / norm);
    Some(StampedPose::new(
        t,
        Isometry3::from_parts(Translation3::new(tx, ty, tz), rot),
    ))
}

/// [`valid_pose`], or the first check that the values fail: a value that is not finite (the
/// first such column), then a zero quaternion or one whose norm is off, then the time.
#[inline]
pub(crate) fn check_values(v: &[f64; VALUES], prev_t: f64) -> Result<StampedPose, Problem> {
    valid_pose(v, prev_t, false).ok_or_else(|| failed_check(v, prev_t))
}

/// The problem of values that [`valid_pose`] rejected.
#[cold]
#[inline(never)]
fn failed_check(v: &[f64; VALUES], prev_t: f64) -> Problem {
    if let Some(role) = v.iter().position(|x| !x.is_finite()) {
        return Problem::NotFinite {
            role,
            nan: v[role].is_nan(),
        };
    }
    let q = [v[QUAT], v[QUAT + 1], v[QUAT + 2], v[QUAT + 3]];
    let norm = Quaternion::new(q[3], q[0], q[1], q[2]).norm();
    if norm == 0.0 {
        return Problem::ZeroQuaternion { q };
    }
    if norm.is_nan() || (norm - 1.0).abs() > QUAT_NORM_TOLERANCE {
        return Problem::NormOff { q, norm };
    }
    Problem::TimeNotIncreasing { t: v[TIME], prev_t }
}

/// The pose of eight values in TUM order (`t tx ty tz qx qy qz qw`) given other than as a line
/// of a file (rows of an array, for the Python package), checked as a line's values are: every
/// value finite, the quaternion's norm within [`QUAT_NORM_TOLERANCE`] of 1 (then normalised, its
/// sign kept). The order of the times is the caller's to check. The error is the message a
/// line with these values gets, without the `file:line: ` before it.
pub fn pose_from_values(v: &[f64; 8]) -> Result<StampedPose, String> {
    check_values(v, f64::NEG_INFINITY).map_err(|p| p.message(&Context::default()))
}

/// Where a reader is: the line being read, and the previous pose, whose time the next must
/// exceed and whose line messages name.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Track {
    /// Lines read so far (= number of the line being handled, 1-based).
    pub(crate) line_no: usize,
    /// Time of the previous pose (`-inf` before the first).
    pub(crate) prev_t: f64,
    /// Line of the previous pose (0 before the first).
    pub(crate) prev_line: usize,
}

impl Track {
    /// Before the first line.
    pub(crate) fn new() -> Self {
        Track {
            line_no: 0,
            prev_t: f64::NEG_INFINITY,
            prev_line: 0,
        }
    }

    /// [`valid_pose`] for the values of line `line_no`, which then becomes the previous pose;
    /// `None` (and no change) if a check fails.
    #[inline(always)]
    pub(crate) fn accept(&mut self, v: &[f64; VALUES], finite: bool) -> Option<StampedPose> {
        let p = valid_pose(v, self.prev_t, finite)?;
        self.prev_t = v[TIME];
        self.prev_line = self.line_no;
        Some(p)
    }

    /// [`check_values`] for the values of line `line_no`, which then becomes the previous pose
    /// if they pass.
    pub(crate) fn check(&mut self, v: &[f64; VALUES]) -> Result<StampedPose, Problem> {
        let p = check_values(v, self.prev_t)?;
        self.prev_t = v[TIME];
        self.prev_line = self.line_no;
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Eight values that pass the checks after an earlier time: any time and translation, a
    /// quaternion of norm within the tolerance.
    fn good_values() -> impl Strategy<Value = [f64; VALUES]> {
        (
            -1e6..1e6f64,
            prop::array::uniform3(-1e6..1e6f64),
            prop::array::uniform4(-1.0..1.0f64),
            0.991..1.009f64,
        )
            .prop_filter("a quaternion with a direction", |(_, _, q, _)| {
                q.iter().map(|x| x * x).sum::<f64>() > 1e-6
            })
            .prop_map(|(t, [x, y, z], q, norm)| {
                let n = q.iter().map(|a| a * a).sum::<f64>().sqrt() / norm;
                [t, x, y, z, q[0] / n, q[1] / n, q[2] / n, q[3] / n]
            })
    }

    proptest! {
        /// Values that pass give the pose written: the time and translation as they are, the
        /// quaternion scaled to norm 1 with its sign.
        #[test]
        fn good_values_give_their_pose(v in good_values(), back in 1e-3..1e3f64) {
            let prev_t = v[TIME] - back;
            let p = check_values(&v, prev_t).unwrap();
            let same = valid_pose(&v, prev_t, true).unwrap();
            prop_assert_eq!(p, same);
            let t = p.pose.translation.vector;
            prop_assert_eq!([p.t, t.x, t.y, t.z], [v[0], v[1], v[2], v[3]]);
            let q = p.pose.rotation.coords;
            let n = (v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]).sqrt();
            prop_assert_eq!([q.x, q.y, q.z, q.w], [v[4] / n, v[5] / n, v[6] / n, v[7] / n]);
            prop_assert!((q.norm() - 1.0).abs() < 1e-15);
        }

        /// A value that is not finite is named, the first one if there are several, before
        /// any other problem.
        #[test]
        fn not_finite_values_are_named(
            v in good_values(),
            k in 0..VALUES,
            j in 0..VALUES,
            bad in prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
        ) {
            let mut v = v;
            v[k] = bad;
            if j > k {
                v[j] = f64::NAN;
            }
            v[7] *= 3.0; // the norm is off too, and the time goes back: named after
            let want = Problem::NotFinite { role: k, nan: bad.is_nan() };
            prop_assert_eq!(check_values(&v, f64::INFINITY).unwrap_err(), want);
        }

        /// A quaternion whose norm is off by more than the tolerance, or zero, is named with
        /// its values, before the time.
        #[test]
        fn norms_off_are_named(v in good_values(), scale in 0.0..0.98f64, up in any::<bool>()) {
            let mut v = v;
            let s = if up { 1.0 / (1.0 - scale) + 0.02 } else { scale };
            for x in &mut v[QUAT..] {
                *x *= s;
            }
            let q = [v[4], v[5], v[6], v[7]];
            let norm = Quaternion::new(q[3], q[0], q[1], q[2]).norm();
            let want = if norm == 0.0 {
                Problem::ZeroQuaternion { q }
            } else {
                Problem::NormOff { q, norm }
            };
            prop_assert!(norm == 0.0 || (norm - 1.0).abs() > QUAT_NORM_TOLERANCE);
            prop_assert_eq!(check_values(&v, v[0] + 1.0).unwrap_err(), want);
        }

        /// A timestamp that does not exceed the previous one is named with both.
        #[test]
        fn time_must_increase(v in good_values(), back in 0.0..1e3f64) {
            let prev_t = v[TIME] + back;
            let want = Problem::TimeNotIncreasing { t: v[TIME], prev_t };
            prop_assert_eq!(check_values(&v, prev_t).unwrap_err(), want.clone());
            let mut track = Track { line_no: 7, prev_t, prev_line: 3 };
            prop_assert!(track.accept(&v, true).is_none());
            prop_assert_eq!(track.check(&v).unwrap_err(), want);
            prop_assert_eq!((track.prev_t, track.prev_line), (prev_t, 3));
        }
    }

    #[test]
    fn zero_quaternion() {
        let v = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.0];
        let want = Problem::ZeroQuaternion {
            q: [0.0, 0.0, 0.0, -0.0],
        };
        assert_eq!(check_values(&v, 0.0).unwrap_err(), want);
        let mut track = Track::new();
        track.line_no = 4;
        let ok = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        assert!(track.check(&ok).is_ok());
        assert_eq!((track.prev_t, track.prev_line), (1.0, 4));
    }

    /// Values outside a file: the pose of good values, and a line's message for bad ones.
    #[test]
    fn pose_from_values_speaks_as_a_line() {
        let good = [2.0, 0.1, 0.2, 0.3, 0.0, 0.0, 0.0, -1.001];
        let p = pose_from_values(&good).unwrap();
        assert_eq!((p.t, p.pose.translation.vector.x), (2.0, 0.1));
        assert_eq!(p.pose.rotation.w, -1.0);
        let off = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0];
        let want = check_values(&off, 0.0)
            .unwrap_err()
            .message(&Context::default());
        assert_eq!(pose_from_values(&off).unwrap_err(), want);
        assert!(want.contains("has norm 2"), "{want}");
        let nan = [0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        assert_eq!(
            pose_from_values(&nan).unwrap_err(),
            "tx is NaN; every value must be a finite number"
        );
    }
}
