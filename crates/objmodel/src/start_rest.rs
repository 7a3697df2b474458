//! Whether the rest a demonstration starts with was a rest.
//!
//! A frame is moving when the rest test's windows ([`crate::classify::RobustConfig::rest_window_s`])
//! on both sides of it move; the first frames of a file have no window before them, so a file
//! that starts in motion (a box already carried by the hand that throws it) starts with a few
//! frames called rest that no test established. Its first segment is then measured from a
//! pose that was not at rest, and "down", the face rested on and whether the motion left the
//! support all come from a hand's pose: on 500 simulated tosses, a throw's swing about the
//! wrist and the flight after it taught edges 27-28° and 36-49 mm off any edge of the box, and
//! slides and rests taught faces 6-23° off. What a part teaches rests on its start being a rest;
//! the first segment of a file whose rest before it is shorter than the rest test's window
//! teaches nothing from its first part (its later parts are measured from their own onset,
//! [`crate::onset`]).
//!
//! Those first frames are not called rest when they move ([`unlabel_moving_start`]): a file
//! that starts at a throw's release (real tosses tracked at 148 Hz move 7 mm between their
//! first two frames, at 0.15 mm of noise) starts with general motion, not with a rest.

use crate::classify::{Classification, Label};
use crate::recording::Recording;

/// How long \[s\] `c` rests before its first segment, from the first kept frame, when that is
/// less than `window_s` (the rest test's window): a start not known to be a rest.
fn unrested_start(c: &Classification, recording: &Recording, window_s: f64) -> Option<f64> {
    let (first, s) = (recording.object.first()?, c.segments.first()?);
    let rest = s.t_start - first.t;
    (rest < window_s).then_some(rest)
}

/// Withhold what the first segment of `c` taught when the rest before it, from the first kept
/// frame, lasts less than `window_s` (the rest test's window); see the module documentation.
pub fn withhold_unrested_start(c: &mut Classification, recording: &Recording, window_s: f64) {
    let Some(rest) = unrested_start(c, recording, window_s) else {
        return;
    };
    let s = &mut c.segments[0];
    if s.edge.is_some() || s.face.is_some() {
        s.withheld = Some(format!(
            "{} not taught: the demonstration starts {rest:.2} s before it, less than the rest \
             test's window ({window_s:.2} s), so it is not known to start from a rest",
            if s.edge.is_some() { "edge" } else { "face" }
        ));
    }
    s.edge = None;
    s.face = None;
    s.departs_from_support = false;
    c.topples.retain(|t| !t.segments.contains(&0));
    if c.topples.is_empty() {
        c.paper_edge = None;
    }
}

/// Label the frames that `c` calls rest before its first segment [`Label::General`] when they
/// move: when the rest before the first segment is shorter than the rest test's window
/// (`window_s`, measured as [`withhold_unrested_start`] measures it) and the position moves between two of its
/// frames, or from its last frame to the next, by more than the tracking noise allows (χ²₃ of
/// the step under twice the position noise, at `alpha` over the steps tested). The votes and
/// what the demonstration taught do not change: those frames voted for nothing, and a rest
/// shorter than the window teaches nothing ([`withhold_unrested_start`]). The parts, filled
/// from the labels afterwards, follow.
pub fn unlabel_moving_start(
    c: &mut Classification,
    recording: &Recording,
    window_s: f64,
    alpha: f64,
) {
    let Some(noise) = c.noise else { return };
    let Some(lead) = c
        .labels
        .first()
        .filter(|r| r.label == Label::Rest && r.segment.is_none())
    else {
        return;
    };
    if unrested_start(c, recording, window_s).is_none() {
        return;
    }
    let last = lead.last as u64;
    let frames = &recording.object;
    let k = frames.partition_point(|f| f.index <= last);
    // The leading rest's kept frames and the frame after them.
    let steps: Vec<f64> = frames[..(k + 1).min(frames.len())]
        .windows(2)
        .map(|w| (w[1].position - w[0].position).norm_squared())
        .collect();
    if steps.is_empty() {
        return;
    }
    let var = 2.0 * noise.sigma_position.powi(2);
    let limit = crate::stats::chi2_threshold(3.0, alpha / steps.len() as f64);
    if steps.iter().all(|d| d / var <= limit) {
        return;
    }
    for r in c.labels.iter_mut().take_while(|r| r.segment.is_none()) {
        if r.label == Label::Rest {
            r.label = Label::General;
        }
    }
}
