//! A topple that flies: a segment whose rotation about a line ends in a free flight did not
//! turn about an edge of the object on a support.
//!
//! The frames after a completed topple's rotation are its landing: the object left its edge
//! and came down on the face across it, a consequence of the topple that does not vote
//! (`classify::analysis`). An object that turns about an edge on a support stays on it until
//! that face lands; if it flies freely instead (a flight among the landing's frames, by the
//! flight test: gravity explains them and no acceleration does not), what it turned about was
//! not such an edge. A hand that swings a held object about its wrist and throws it turns it
//! about a fixed line before the flight (on MuJoCo tosses, by 13° about a line 15 cm from the
//! object's origin, with no pitch: an "edge" 58 mm off the box, and the hold in the air taught
//! two resting faces); a box that tips over the edge of a table turns about the table's edge, a line in
//! its face, not an edge of it, and falls. Such a segment's edge is withheld and its rests are
//! not on a support.

use super::{find_flights, FlightFrame, FlightTest};
use crate::classify::{Classification, Config, Label};
use crate::recording::Recording;

/// Withhold the edges of `c`'s segments whose landing frames hold a free flight, and do not
/// take their rests as on the support (see the module documentation). Needs gravity and a
/// noise model; direct demonstrations only (on a palm the palm is the support and moves).
pub fn withhold_topples_that_fly(c: &mut Classification, recording: &Recording, config: &Config) {
    let Some(test) = FlightTest::of_demonstration(c, config) else {
        return;
    };
    let outlier = c.is_outlier();
    let flies = |k: usize| {
        c.labels
            .iter()
            .filter(|r| r.segment == Some(k) && r.label == Label::Landing)
            .any(|r| {
                let frames: Vec<FlightFrame> = recording
                    .objects_in(r.first, r.last)
                    .iter()
                    .filter(|f| !outlier(f.index))
                    .map(|f| f.into())
                    .collect();
                !find_flights(&frames, &test).is_empty()
            })
    };
    let flying: Vec<usize> = (0..c.segments.len()).filter(|&k| flies(k)).collect();
    for &k in &flying {
        let s = &mut c.segments[k];
        if s.edge.is_some() {
            s.withheld = Some(
                "edge not taught: the object flew freely after turning about it, so it did not \
                 turn about an edge on a support (a throw's swing, a fall off the support's edge)"
                    .into(),
            );
        }
        s.edge = None;
        s.departs_from_support = false;
        s.arrives_on_support = false;
        c.topples.retain(|t| !t.segments.contains(&k));
    }
    if !flying.is_empty() && c.topples.is_empty() {
        c.paper_edge = None;
    }
}
