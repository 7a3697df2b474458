//! A box pushed over on its side may roll on with its contact sliding (Drake, point contact,
//! motion-capture noise: `bench/drake_probe.py`, seed 3; `tests/data/drake_rolling_contact`):
//! it turned 32° about a line that moved 10 mm and turned 3.3° half-way through, 15-25 mm
//! outside the box's edge. The change test cut the turn into two windows, each a fixed line
//! within its σ (±1 mm, ±0.4°); since the two lines were not parallel within those σ (the test
//! of one turn whose line moved asked for parallel lines), both taught, and the tree held an
//! edge 20 mm off the box. Two windows right after each other that turn the same way about
//! lines less than half a right angle apart are one turn (`roll::same_turn`): its line moved,
//! and it teaches nothing.

mod common;

#[test]
fn a_roll_whose_line_moves_teaches_no_edge() {
    let c = common::learn_alone_on_box("drake_rolling_contact/push");
    assert!(c.rolls.iter().all(|r| !r.taught), "{:?}", c.rolls);
    let moved = c
        .parts
        .iter()
        .filter(|p| {
            p.withheld
                .as_deref()
                .is_some_and(|w| w.contains("line moved"))
        })
        .count();
    assert_eq!(moved, 2, "{:?}", c.parts);
}
