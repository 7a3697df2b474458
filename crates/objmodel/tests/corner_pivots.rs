//! A box pushed off its middle may pivot on a corner instead of an edge (Drake, point contact:
//! `bench/drake_probe.py`, motion-capture noise; `tests/data/drake_corner_pivots`): it turns
//! about a line a few degrees out of the face it stood on, one end of its bottom edge lifting
//! off the table. That line is no edge of the box. The topple's edge fails the test that an
//! edge toppled about is level (6.8° from level at ±1.8°), and before, a window of the same
//! turn, searched for rolls, passed for one (3.0° from level at ±0.4°, its error too small to
//! fail that test alone) and taught an edge 3.2° off the box's. The turn of a topple whose edge
//! is off level is not searched for rolls now (`crate::classify::OFF_LEVEL`).
//!
//! A box may also twist as it tips (`b`: a push of the tallest Drake box): its line of rotation
//! went from 8° to 3.6° out of the face it stood on during the turn. The split-half lack of fit
//! of the turn's axis widened the edge's σ to 2° in every direction, with which the line, 6.3°
//! from level, passed the level test, and it taught an edge 6.4° off the box's and a resting
//! face 6° off. A pivot that slips turns its axis within the level plane, never out of it: the
//! level test now sees the edge's direction without that lack of fit (`classify::analysis`,
//! `level_cov`), and the turn is not taught.

mod common;

use objmodel::classify::Classification;

const DIR: &str = "drake_corner_pivots";

/// Learn the Drake file `name` alone: the tree must hold no feature off the box, and a part of
/// the file must be withheld as off level. Its classification, for further checks.
fn learn_off_level(name: &str) -> Classification {
    let c = common::learn_alone_on_box(&format!("{DIR}/{name}"));
    let off_level = c
        .parts
        .iter()
        .filter_map(|p| p.withheld.as_deref())
        .any(|w| w.contains(objmodel::classify::OFF_LEVEL));
    assert!(off_level, "{name}: {:?}", c.parts);
    c
}

#[test]
fn a_corner_pivot_teaches_no_edge_off_the_box() {
    let c = learn_off_level("a");
    assert!(c.rolls.iter().all(|r| !r.taught), "{:?}", c.rolls);
}

#[test]
fn a_box_that_twists_as_it_tips_teaches_no_edge_off_the_box() {
    learn_off_level("b");
}
