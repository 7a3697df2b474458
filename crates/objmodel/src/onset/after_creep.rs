//! A topple measured from a rest the object had already left: the first pass measures every
//! frame of a segment from the rest before it, and a box that creeps down a tilting palm in
//! stick-slip steps too small to end the rest or to start a part of their own (each step a
//! tenth of a millimetre to half a millimetre, the stops between them shorter than a rest)
//! is measured from the pose before the creep. Its edge then carries the creep divided by the
//! chord of each frame's rotation (on MuJoCo's palm topples at 0.3 mm noise, 2.9-14 mm off).
//!
//! Only instrumented demonstrations are tested: the palm moves under a box at rest on it, and
//! a soft or sticky contact lets it creep; a pivot that moves by less than the contact's own
//! wander (the edge tolerance, 0.3 mm) is not a creep. (On the standard dataset's pushed
//! topples the test found 1-10 mm "creeps" at mocap and camera noise before the pushes'
//! topples, and re-measuring them lost their pendulums and a centre of mass.)
//!
//! The creep shows in the edge's own pivot ([`super::creep`]): over the rest and the segment up
//! to the topple (the frames turned from the rest by less than an edge rotation that locates
//! its edge, 8.6° at the default tolerance), the edge point's position on the support changes
//! its mean. When it
//! does, the segment is measured again from the pose after the last change (found by scanning
//! again after each significant cut; the mean pose of the frames from there on that have not
//! turned beyond their noise, the stop before the topple), as a later part is
//! ([`super::remeasure_later_parts`]);
//! if that teaches no edge, the first pass's edge is withheld: it was measured from a pose the
//! object had left.

use super::adopt::{adopt, teaches_edge, Remeasured};
use super::creep::pivot_moved;
use super::span::{
    classify_from, frames_around, instrumented_config, largest_turn, mean_frame, support_pose,
};
use crate::classify::parts::turn_locates_no_edge;
use crate::classify::{Classification, Config};
use crate::recording::{RecordedFrame, Recording};

/// Measure again, from after its creep, every first-pass topple segment whose edge's pivot
/// moved before it turned (see the module documentation).
pub(super) fn remeasure_after_creep(
    c: &mut Classification,
    recording: &Recording,
    config: &Config,
) {
    let Some((config, noise)) = instrumented_config(c, recording, config) else {
        return;
    };
    let mut done = Vec::new();
    let mut withheld = Vec::new();
    for k in 0..c.segments.len() {
        let s = &c.segments[k];
        let (Some(edge), None) = (&s.edge, &s.remeasured) else {
            continue;
        };
        let t_end = c.segments.get(k + 1).map_or(f64::INFINITY, |n| n.t_start);
        let kept = frames_around(c, recording, k);
        let Some(rest_last) = kept.iter().rev().find(|f| f.t < s.t_start) else {
            continue;
        };
        let Some(t_turned) = largest_turn(recording, rest_last, t_end) else {
            continue;
        };
        // The frames before the topple: turned from the rest by less than an edge rotation
        // that locates its edge (`edge_turns_too_little`: the contact's wander moves the axis
        // of a smaller turn by more than EDGE_LOCATION_M).
        let rest_pose = support_pose(recording, rest_last);
        let tolerance = config.robust.edge_tolerance_m;
        let before_topple: Vec<(f64, nalgebra::Isometry3<f64>)> = kept
            .iter()
            .filter(|f| f.t <= t_turned)
            .filter_map(|f| Some((f.t, support_pose(recording, f)?)))
            .take_while(|(_, x)| {
                rest_pose.is_some_and(|r| {
                    turn_locates_no_edge((r.rotation.inverse() * x.rotation).angle(), tolerance)
                })
            })
            .collect();
        let pivot = |from: f64| {
            let frames: Vec<(f64, nalgebra::Isometry3<f64>)> = before_topple
                .iter()
                .filter(|(t, _)| *t >= from)
                .copied()
                .collect();
            pivot_moved(
                &frames,
                &edge.line,
                &edge.point_cov,
                &noise,
                config.robust.alpha,
            )
            .filter(|m| m.distance_m > config.robust.edge_tolerance_m)
        };
        // The last significant change of the pivot before the largest turn.
        let Some(mut moved) = pivot(f64::NEG_INFINITY) else {
            continue;
        };
        while let Some(m) = pivot(moved.t_cut) {
            moved = m;
        }
        // The reference: the mean pose of the frames from the cut on that have not turned
        // from the first of them beyond their noise (the stop before the topple).
        let stop: Vec<&RecordedFrame> = {
            let after: Vec<&RecordedFrame> = kept
                .iter()
                .copied()
                .filter(|f| f.t >= moved.t_cut && f.t <= t_turned)
                .collect();
            let level = crate::stats::chi2_threshold(3.0, config.robust.alpha);
            let var = 2.0 * noise.sigma_rotation.powi(2);
            let rot = |f: &RecordedFrame| support_pose(recording, f).map(|p| p.rotation);
            let first = after.first().and_then(|f| rot(f));
            after
                .iter()
                .copied()
                .take_while(|f| {
                    first.zip(rot(f)).is_some_and(|(a, b)| {
                        let angle = (a.inverse() * b).angle();
                        angle * angle <= level * var
                    })
                })
                .collect()
        };
        let Some(reference) = mean_frame(recording, &stop) else {
            continue;
        };
        let reference = &reference;
        let turned = largest_turn(recording, reference, t_end);
        let sub = turned
            .and_then(|t| classify_from(c, recording, &config, reference, t + 1e-9))
            .filter(teaches_edge)
            .or_else(|| classify_from(c, recording, &config, reference, t_end))
            .filter(teaches_edge);
        let why = format!(
            "the edge's pivot moved by {:.1} mm before {:.2} s (a creep: χ² {:.1} > {:.1})",
            moved.distance_m * 1e3,
            moved.t_cut,
            moved.chi2,
            moved.level
        );
        match sub {
            Some(sub) => done.push(Remeasured {
                segment: k,
                t_reference: reference.t,
                i_reference: reference.index,
                t_onset: reference.t,
                sub,
                note: Some(format!(
                    "measured from the pose at {:.2} s, after a creep from the rest before \
                     it: {why}",
                    reference.t
                )),
                before_fall: false,
                creep: false,
            }),
            None => withheld.push((k, why)),
        }
    }
    for r in done {
        adopt(c, r, recording, &config);
    }
    if withheld.is_empty() {
        return;
    }
    for (k, why) in withheld {
        let seg = &mut c.segments[k];
        seg.edge = None;
        seg.topple_best = None;
        seg.topple_stats = Default::default();
        seg.topple_systematic_var = 0.0;
        seg.topple_systematic_direction_var = 0.0;
        seg.withheld = Some(format!(
            "edge not taught: measured from the rest before the segment, but {why}, and \
             measured from after it the topple teaches no edge"
        ));
    }
    c.topples = crate::classify::group_topples(&c.segments, config.robust.alpha, &c.name);
}
