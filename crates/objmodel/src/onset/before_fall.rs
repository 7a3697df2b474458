//! A fall measured from the stop before it. A box on a tilting palm that settles, creeps and
//! slips back on its soft contact before it tips is measured, in the first pass, from the rest
//! before all of it. At a motion-capture rate and noise (120 Hz, 0.1 mm) each of those moves is
//! many times the noise: measured from the rest, the frames of the fall carry them and no fixed
//! edge explains them, and the frames of the creep, turned by a fraction of a degree, outnumber
//! the fall's. The segment then teaches nothing (it is general, or its "edge" turns too little
//! to be located), and no label boundary need mark the fall's onset, so neither a later part
//! ([`super::remeasure_later_parts`]) nor a creep before a first-pass edge
//! ([`super::after_creep`]) may apply.
//!
//! The fall ends where the object first reaches its largest turn from the rest (within the
//! noise of two frames: after the fall it may lie on its next face, or slide on down the palm,
//! for a long time). Before that, the object stopped on the palm: the latest [`STOP_FRAMES`]
//! frames whose orientations (relative to the palm) all lie within the noise of the last of
//! them (χ²₃ at the classifier's α on the difference of two frames' rotations). Their mean
//! pose is the reference: the first frames of a fall turn slowly, and any pose of a rotation
//! about a fixed edge is a valid reference for the rest of it. From there to the end of the
//! fall (then, failing that, to the segment's end) the segment is classified again as a
//! demonstration of its own, and teaches the edge that passes every test of a topple measured
//! from a rest. Its frames may carry less than half the turn: as the box lands, its pivot
//! slides down the tilted palm, and the classifier calls those frames the landing of a
//! completed topple ([`super::adopt::teaches_edge_before_landing`]). The frames after the fall
//! are that landing too.
//!
//! The frames from the rest to the stop are a creep ([`crate::classify::Label::Creep`], no
//! vote) when none of them turned from the rest by a turn that locates an edge (the chord
//! `edge_tolerance / EDGE_LOCATION_M`, 8.6° at the defaults): the object moved on the palm
//! without tipping. (Frames the first pass called a slide stay a slide.)
//!
//! Only instrumented demonstrations are measured so: the palm moves under a box at rest on it,
//! and nothing else moves the box before it falls. (A pushed box is moved by the push, whose
//! parts the first pass's labels split.)

use super::adopt::{adopt, teaches_edge_before_landing, Remeasured};
use super::span::{classify_from, frames_around, instrumented_config, mean_frame, support_pose};
use crate::classify::parts::turn_locates_no_edge;
use crate::classify::{Classification, Config};
use crate::noise::{NoiseModel, SCATTER_WINDOW};
use crate::recording::{RecordedFrame, Recording};
use nalgebra::UnitQuaternion;

/// Frames of the stop before a fall: the scatter window (the fewest frames whose mean the
/// noise estimate trusts).
pub const STOP_FRAMES: usize = SCATTER_WINDOW;

/// Measure again, from the stop before its fall, every instrumented segment that taught
/// neither an edge nor a face (see the module documentation).
pub(super) fn remeasure_from_the_stop(
    c: &mut Classification,
    recording: &Recording,
    config: &Config,
) {
    let Some((config, noise)) = instrumented_config(c, recording, config) else {
        return;
    };
    let mut done = Vec::new();
    for k in 0..c.segments.len() {
        let s = &c.segments[k];
        if s.edge.is_some() || s.face.is_some() || s.remeasured.is_some() {
            continue;
        }
        let t_end = c.segments.get(k + 1).map_or(f64::INFINITY, |n| n.t_start);
        let Some(fall) = stop_before_fall(c, recording, &config, &noise, k) else {
            continue;
        };
        let reference = &fall.reference;
        let sub = classify_from(c, recording, &config, reference, fall.t_landed + 1e-9)
            .filter(teaches_edge_before_landing)
            .or_else(|| classify_from(c, recording, &config, reference, t_end))
            .filter(teaches_edge_before_landing);
        if let Some(sub) = sub {
            done.push(Remeasured {
                segment: k,
                t_reference: reference.t,
                i_reference: reference.index,
                t_onset: reference.t,
                sub,
                note: Some(format!(
                    "measured from the stop on the palm at {:.2} s before its fall (the \
                     object moved on the palm after the rest before it)",
                    reference.t
                )),
                before_fall: true,
                creep: fall.crept,
            });
        }
    }
    for r in done {
        adopt(c, r, recording, &config);
    }
}

/// The stop before the fall of segment `k`.
struct Fall {
    /// The mean pose of the stop's frames, at its last frame.
    reference: RecordedFrame,
    /// When the object first reached its largest turn from the rest \[s\].
    t_landed: f64,
    /// Whether every frame from the rest to the stop turned by less than a turn that locates
    /// an edge.
    crept: bool,
}

/// Where segment `k` stopped before its fall, if it did (see the module documentation).
fn stop_before_fall(
    c: &Classification,
    recording: &Recording,
    config: &Config,
    noise: &NoiseModel,
    k: usize,
) -> Option<Fall> {
    let s = &c.segments[k];
    let kept = frames_around(c, recording, k);
    let rest_last = kept.iter().rev().find(|f| f.t < s.t_start)?;
    let q_rest = support_pose(recording, rest_last)?.rotation;
    // Each moving frame, its orientation relative to the palm and its turn from the rest.
    let turns: Vec<(&RecordedFrame, UnitQuaternion<f64>, f64)> = kept
        .iter()
        .filter(|f| f.t >= s.t_start)
        .filter_map(|f| {
            let q = support_pose(recording, f)?.rotation;
            Some((*f, q, (q_rest.inverse() * q).angle()))
        })
        .collect();
    // Two frames' rotations differ within the noise when the angle between them is within
    // this (χ²₃ at α, each frame's rotation noise σ per axis).
    let level = crate::stats::chi2_threshold(3.0, config.robust.alpha);
    let within = (level * 2.0 * noise.sigma_rotation.powi(2)).sqrt();
    let largest = turns.iter().map(|x| x.2).max_by(f64::total_cmp)?;
    let landed = turns.iter().position(|x| x.2 >= largest - within)?;
    let still = |w: &[(&RecordedFrame, UnitQuaternion<f64>, f64)]| {
        let last = w[w.len() - 1].1;
        w.iter().all(|x| (last.inverse() * x.1).angle() <= within)
    };
    let stop = turns[..landed]
        .windows(STOP_FRAMES)
        .rev()
        .find(|w| still(w))?;
    let stop: Vec<&RecordedFrame> = stop.iter().map(|x| x.0).collect();
    let reference = mean_frame(recording, &stop)?;
    let crept = turns
        .iter()
        .take_while(|x| x.0.t < reference.t)
        .all(|x| turn_locates_no_edge(x.2, config.robust.edge_tolerance_m));
    Some(Fall {
        reference,
        t_landed: turns[landed].0.t,
        crept,
    })
}
