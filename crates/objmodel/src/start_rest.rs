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

use crate::classify::Classification;
use crate::recording::Recording;

/// Withhold what the first segment of `c` taught when the rest before it, from the first kept
/// frame, lasts less than `window_s` (the rest test's window); see the module documentation.
pub fn withhold_unrested_start(c: &mut Classification, recording: &Recording, window_s: f64) {
    let (Some(first), Some(s)) = (recording.object.first(), c.segments.first()) else {
        return;
    };
    let rest = s.t_start - first.t;
    if rest >= window_s {
        return;
    }
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
