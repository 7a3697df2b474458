//! Do a demonstration's positions look like metres? A file whose unit is not known (a TUM
//! file, a CSV header without units, poses in memory: [`crate::format::LengthUnit`]) is read
//! in metres; motion-capture software writes millimetres as often. Read in the wrong unit, a
//! millimetre file's noise is a thousand times too large and its features lie tens of metres
//! from the object: whatever it taught would be wrong, with confidence, in every downstream
//! use (the shape, the export, the plan).
//!
//! Two things that no demonstration in metres shows, each a factor of ten or more from what
//! any does:
//!
//! * an estimated tracking noise above [`MAX_NOISE_M`] per axis (the noise is estimated, not
//!   given): motion capture is at 0.1-0.5 mm, tags seen by a camera at 1-10 mm, and a
//!   tracker coarser than 5 cm cannot locate a contact feature of an object a palm topples;
//! * a feature farther than [`MAX_FEATURE_M`] from the tracked frame (an edge's line, a
//!   face's plane): the tracked frame is on the object (a tag, a rigid body's markers), and a
//!   robot's palm topples no object two metres across.
//!
//! Such a demonstration teaches nothing ([`Classification::withhold_all`]), and its report
//! says what was seen and which unit to give. Exact millimetre poses (a simulator's) with no
//! feature escape both tests; they then teach what does not depend on the unit, if anything
//! (the normal of a face, whose plane is found without its offset).

use crate::classify::Classification;

/// Largest tracking noise \[m\] per axis that a demonstration in metres is believed to have.
pub const MAX_NOISE_M: f64 = 0.05;

/// Largest distance \[m\] from the tracked frame to a feature that a demonstration in metres is
/// believed to show.
pub const MAX_FEATURE_M: f64 = 2.0;

/// What makes `c`'s positions implausible in metres, if anything (`None` where the unit is
/// known: [`Classification::length_unit`]).
pub fn implausible_in_metres(c: &Classification) -> Option<String> {
    if c.length_unit.is_some() {
        return None;
    }
    let noise = c
        .noise
        .filter(|_| !c.noise_given)
        .map(|n| n.sigma_position)
        .filter(|&s| s > MAX_NOISE_M);
    let rolls = c.rolls.iter().filter(|r| r.taught).map(|r| &r.edge);
    let edges = c.edges().chain(rolls).map(|e| e.line.point.norm());
    let faces = c.faces().into_iter().filter_map(|f| f.offset.map(f64::abs));
    let feature = edges.chain(faces).fold(0.0, f64::max);
    let what = match noise {
        Some(s) => format!(
            "the tracking noise would be {s:.3} m per axis (beyond {MAX_NOISE_M} m; in \
             millimetres it is {s:.3} mm)"
        ),
        None if feature > MAX_FEATURE_M => format!(
            "a feature would lie {feature:.2} m from the tracked frame (beyond {MAX_FEATURE_M} \
             m; in millimetres {feature:.2} mm)"
        ),
        None => return None,
    };
    Some(format!(
        "the positions do not look like metres: {what}; give their unit (--length-unit mm or \
         cm; a CSV header may declare it, as in x [mm]), or --length-unit m if they are metres"
    ))
}

/// Withhold everything `c` teaches when its positions are implausible in metres
/// ([`implausible_in_metres`]); that warning comes first, as the one to act on (a motion a
/// thousand times too large for its rotation may also look like a slide under another gravity,
/// and is then said to be).
pub fn withhold_if_not_metres(c: &mut Classification) {
    if let Some(why) = implausible_in_metres(c) {
        c.withhold_all(&why);
        if let Some(mut w) = c.warnings.pop() {
            if c.gravity_doubted {
                w += " (a warning below about gravity may have the same cause)";
            }
            c.warnings.insert(0, w);
        }
    }
}
