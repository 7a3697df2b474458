//! Cutting a session's recording into demonstrations at the object's rests (`--split`).
//!
//! The rule: a *rest* is a run of object poses (in the reference frame, so the object on a
//! still palm) each within [`SPLIT_RADIUS_M`] and [`SPLIT_ANGLE_RAD`] of the run's first pose,
//! where a single pose outside that is ignored (a tag flip) if the next one is inside again.
//! Every rest lasting at least the split duration (default [`DEFAULT_SPLIT_REST_S`]) is cut at
//! its middle (the stamp halfway through it), so that each part keeps half of the rests around
//! its motion, which the classifier needs as the reference before and after. Parts that lie
//! wholly within one rest (the start and end of a session spent waiting) are dropped.

use crate::trajectory::StampedPose;
use std::ops::Range;

/// How far \[m\] the object may move and still be at rest, for splitting.
pub const SPLIT_RADIUS_M: f64 = 0.01;
/// How far \[rad\] (3°) the object may turn and still be at rest, for splitting.
pub const SPLIT_ANGLE_RAD: f64 = 0.052_359_877_559_829_89;
/// The shortest rest \[s\] at which a session is cut by default.
pub const DEFAULT_SPLIT_REST_S: f64 = 2.0;

fn near(a: &StampedPose, b: &StampedPose) -> bool {
    (a.pose.translation.vector - b.pose.translation.vector).norm() <= SPLIT_RADIUS_M
        && a.pose.rotation.angle_to(&b.pose.rotation) <= SPLIT_ANGLE_RAD
}

/// The rests of `poses` (index ranges) lasting at least `min_rest_s`.
pub fn rests(poses: &[StampedPose], min_rest_s: f64) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < poses.len() {
        let anchor = &poses[i];
        let mut j = i + 1;
        while j < poses.len() {
            if near(anchor, &poses[j]) {
                j += 1;
            } else if j + 1 < poses.len() && near(anchor, &poses[j + 1]) {
                j += 2; // One outlying pose inside a rest.
            } else {
                break;
            }
        }
        if poses[j - 1].t - anchor.t >= min_rest_s {
            out.push(i..j);
        }
        i = j;
    }
    out
}

/// The parts of `poses` between the middles of its rests of at least `min_rest_s` (see the
/// module's documentation), in time order.
pub fn split_at_rests(poses: &[StampedPose], min_rest_s: f64) -> Vec<Range<usize>> {
    let rests = rests(poses, min_rest_s);
    let mut cuts = vec![0];
    for r in &rests {
        let mid_t = 0.5 * (poses[r.start].t + poses[r.end - 1].t);
        cuts.push(r.start + poses[r.clone()].partition_point(|p| p.t < mid_t));
    }
    cuts.push(poses.len());
    cuts.windows(2)
        .map(|w| w[0]..w[1])
        .filter(|part| !part.is_empty())
        .filter(|part| {
            !rests
                .iter()
                .any(|r| r.start <= part.start && part.end <= r.end)
        })
        .collect()
}

/// The poses of `palm` that cover the times of `object[part]`: those inside, and one on
/// each side (for interpolation at the ends).
pub fn palm_for_part(palm: &[StampedPose], t0: f64, t1: f64) -> Vec<StampedPose> {
    let a = palm.partition_point(|p| p.t < t0).saturating_sub(1);
    let b = (palm.partition_point(|p| p.t <= t1) + 1).min(palm.len());
    palm[a..b.max(a)].to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Translation3};

    /// At 30 Hz: rest 3 s at 0, move 0.3 m in 1 s, rest 3 s, move back, rest 1 s; one tag
    /// flip (a single pose 0.1 m off) inside the first rest.
    fn session() -> Vec<StampedPose> {
        let x = |t: f64| {
            if t < 3.0 {
                0.0
            } else if t < 4.0 {
                0.3 * (t - 3.0)
            } else if t < 7.0 {
                0.3
            } else if t < 8.0 {
                0.3 * (8.0 - t)
            } else {
                0.0
            }
        };
        (0..270)
            .map(|k| {
                let t = k as f64 / 30.0;
                let flip = if k == 40 { 0.1 } else { 0.0 };
                StampedPose::new(t, Isometry3::from(Translation3::new(x(t) + flip, 0.0, 0.0)))
            })
            .collect()
    }

    #[test]
    fn a_session_is_cut_in_the_middle_of_its_long_rests() {
        let s = session();
        let r = rests(&s, 2.0);
        assert_eq!(r.len(), 2, "{r:?}");
        // The second starts within 1 cm of where the move ends (at frame 120).
        assert_eq!(r[0].start, 0);
        assert!((118..=120).contains(&r[1].start), "{r:?}");
        let parts = split_at_rests(&s, 2.0);
        // [0, mid of the first rest) is only rest: dropped. Then the first move, then the move
        // back with the short last rest.
        assert_eq!(parts.len(), 2, "{parts:?}");
        assert!((s[parts[0].start].t - 1.5).abs() < 0.05);
        assert!((s[parts[1].start].t - 5.5).abs() < 0.05);
        assert_eq!(parts[1].end, s.len());
        // Rests shorter than asked cut nothing.
        assert_eq!(split_at_rests(&s, 10.0), vec![0..s.len()]);
    }
}
