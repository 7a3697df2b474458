//! A box thrown past a 30 Hz tracker moves more between frames than the tracker's noise and
//! rests too briefly for a rest to measure it: alone, it teaches nothing. Learnt with other
//! tosses of the same tracker, it takes the noise that their rests measure together
//! ([`objmodel::shared_noise`]), and teaches what it shows (here, the edge it rolled over).
//! Data: `objmodel dataset` (rapier), the brick's tosses at `real` noise (1 mm, 0.5° per axis,
//! white, 30 Hz, dropped frames and tag flips): toss s317 rolls 70° over an edge in 11 frames.

mod common;

use std::path::{Path, PathBuf};

const DIR: &str = "rapier_tosses/shared_noise";
const ROLL: &str = "brick_toss_real_s317.tum";

#[test]
fn a_toss_that_cannot_measure_its_noise_learns_with_the_noise_of_the_others() {
    let all = common::tum_files(DIR);
    let roll: Vec<PathBuf> = all.iter().filter(|p| p.ends_with(ROLL)).cloned().collect();
    // Alone: nothing.
    let (tree, reports) = common::learn_files(&roll);
    let c = &reports[0].classification;
    assert!(c.noise_unmeasurable && c.noise_shared.is_none(), "{c:?}");
    assert!(tree.edges.is_empty() && tree.faces.is_empty());

    // With the other twenty: the noise that their rests measure, near the simulator's.
    let (tree, reports) = common::learn_files(&all);
    let truth = common::box_truth(&format!("{DIR}/brick.truth.json"));
    common::assert_tree_on_box(&tree, &truth, DIR);
    let c = &reports
        .iter()
        .find(|o| o.classification.name == ROLL)
        .unwrap()
        .classification;
    let shared = c.noise_shared.expect("the noise is shared");
    assert!(!c.noise_unmeasurable && !c.noise_given);
    assert!(shared.demonstrations >= 3, "{shared:?}");
    let (p, r) = (
        shared.noise.sigma_position / 1e-3,
        shared.noise.sigma_rotation / 0.5f64.to_radians(),
    );
    assert!(
        (0.8..1.25).contains(&p) && (0.8..1.25).contains(&r),
        "{shared:?}"
    );
    assert!(
        c.warnings[0].contains("measure together"),
        "{:?}",
        c.warnings
    );
    // Its roll teaches the edge it rolled over (and the tree holds nothing off the box).
    let taught: Vec<_> = c.rolls.iter().filter(|r| r.taught).collect();
    assert_eq!(taught.len(), 1, "{:?}", c.rolls);
    assert!(
        tree.edges
            .iter()
            .any(|e| e.support.iter().any(|s| s == ROLL)),
        "{:?}",
        tree.edges
    );
    // A toss that measured its own noise keeps it.
    let own = reports
        .iter()
        .filter(|o| o.classification.noise_shared.is_none())
        .count();
    assert!(own > 0);
}

/// Poses at every other frame of `from`, in `dir`: the same motion tracked at 15 Hz.
fn at_half_rate(from: &Path, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(from).unwrap();
    let lines: String = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .step_by(2)
        .map(|l| format!("{l}\n"))
        .collect();
    let to = dir.join(from.file_name().unwrap());
    std::fs::write(&to, lines).unwrap();
    to
}

#[test]
fn demonstrations_at_another_frame_rate_lend_no_noise() {
    let dir = tempfile::tempdir().unwrap();
    let mut paths: Vec<PathBuf> = common::tum_files(DIR)
        .iter()
        .filter(|p| !p.ends_with(ROLL))
        .map(|p| at_half_rate(p, dir.path()))
        .collect();
    paths.push(common::data(&format!("{DIR}/{ROLL}")));
    let (_, reports) = common::learn_files(&paths);
    let c = &common::report(&reports, ROLL).classification;
    assert!(
        c.noise_unmeasurable && c.noise_shared.is_none(),
        "{:?}",
        c.warnings
    );
    assert!(c.rolls.iter().all(|r| !r.taught));
    // The same tosses at 15 Hz share among themselves where one cannot measure its own.
    assert!(reports
        .iter()
        .filter(|o| o.classification.name != ROLL)
        .all(|o| o
            .classification
            .noise_shared
            .is_none_or(|s| s.demonstrations >= 3)));
}
