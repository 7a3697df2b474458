//! A tracker that loses the object often goes on publishing its last pose (a tf re-broadcast,
//! a motion-capture stream's "hold last value", a logger sampling the latest message at a
//! fixed rate), or a null pose. Those frames repeat a pose exactly; while the object turned,
//! they show it still and tilted where it never rested, and they look like a tracker without
//! noise. Where the noise measured at rest rules an exact repeat out they must be left out,
//! and teach nothing (`clean::held`, `learn/held_poses.rs`); an exact tracker's repeats (a
//! simulator's, at rest) and a coarsely written file's (repeats by chance) must be kept.
//!
//! (Before: a topple whose tracker held a pose mid-rotation for 1.5 s lost its edge and both
//! rests, its noise "measured" on the held frames at 0.05 mm; given the noise, the held
//! frames taught a resting face 15° off the box.)

use nalgebra::{Isometry3, Vector3};
use objmodel::learn::{Config, Learner, Source};
use objmodel::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
use objmodel::trajectory::StampedPose;
use objmodel::tree::Tree;
use rand::{rngs::StdRng, Rng, SeedableRng};

/// Overwrite the poses from `from_s` after the first stamp for `hold_s` with the pose before
/// them (the tracker held it) or, `null`, with the identity (the tracker wrote zeros):
/// returns how many of them repeat the pose before them.
fn hold(poses: &mut [StampedPose], from_s: f64, hold_s: f64, null: bool) -> usize {
    let t0 = poses[0].t;
    let k = poses.iter().position(|p| p.t - t0 >= from_s).unwrap();
    let held = if null {
        Isometry3::identity()
    } else {
        poses[k - 1].pose
    };
    let mut n = 0;
    for p in poses[k..]
        .iter_mut()
        .take_while(|p| p.t - t0 < from_s + hold_s)
    {
        p.pose = held;
        n += 1;
    }
    // A null pose's first frame is a jump, not a repeat.
    if null {
        n - 1
    } else {
        n
    }
}

/// Topples of `b` over its four sides at `noise`, 30 Hz.
fn topples(b: &SynthBox, noise: &SynthNoise, seed: u64) -> Vec<SynthDemo> {
    (0..4)
        .map(|side| {
            let p = ToppleParams {
                side,
                ..Default::default()
            };
            synth::topple(b, &p, noise, 30.0, seed * 10 + side as u64)
        })
        .collect()
}

/// Every edge and face of `tree` is one of `b`'s; the counts.
fn assert_on_box(tree: &Tree, b: &SynthBox, what: &str) -> (usize, usize) {
    let off = b.features_off(tree);
    assert!(off.is_empty(), "{what}: {off:?}");
    (tree.edges.len(), tree.faces.len())
}

/// Held poses in the middle of the topples (while the box turns, 0.3-1.2 s, a quarter of
/// them null poses), at a real tracker's noise: every repeat left out, nothing off the box
/// learnt, and the edges found as without the hold.
#[test]
fn held_poses_are_left_out_and_teach_nothing() {
    let learner = Learner::new(Config::default());
    let mut rng = StdRng::seed_from_u64(49);
    let (mut edges, mut edges_unheld, mut faces) = (0, 0, 0);
    for seed in 0..3u64 {
        let b = SynthBox::random(&mut rng);
        let clean = topples(&b, &SynthNoise::REAL, seed);
        let mut held = clean.clone();
        for (k, d) in held.iter_mut().enumerate() {
            let null = k == 3;
            let from = rng.random_range(1.2..2.3);
            let repeats = hold(&mut d.demo.object, from, rng.random_range(0.3..1.2), null);
            let c = learner.classify(&Source::Memory(&d.demo)).unwrap();
            assert_eq!(c.held_frames as usize, repeats, "box {seed}, topple {k}");
            assert!(c.outliers >= c.held_frames);
        }
        let learnt = |demos: &[SynthDemo]| {
            let sources: Vec<Source> = demos.iter().map(|d| Source::Memory(&d.demo)).collect();
            let mut tree = Tree::default();
            learner.learn(&mut tree, &sources).unwrap();
            tree
        };
        let (e, f) = assert_on_box(&learnt(&held), &b, &format!("box {seed}, held"));
        let (e0, _) = assert_on_box(&learnt(&clean), &b, &format!("box {seed}"));
        edges += e;
        faces += f;
        edges_unheld += e0;
    }
    assert!(
        edges + 2 >= edges_unheld && edges >= 8 && faces >= 8,
        "{edges} edges ({edges_unheld} without the holds), {faces} faces"
    );
}

/// The tracker lost the box while it fell and saw it again where it landed: no frames for
/// 0.7-1.2 s over the fall. The windowed rest test sees each side of the gap at rest, and the
/// frames before the gap (the box about to tip) must not join the rest after it: that rest
/// taught a face 5° off at ±1°, with its offset 6 mm off.
#[test]
fn a_gap_over_the_fall_parts_the_rests() {
    let learner = Learner::new(Config::default());
    let mut rng = StdRng::seed_from_u64(50);
    let (mut edges, mut faces) = (0, 0);
    for seed in 0..3u64 {
        let b = SynthBox::random(&mut rng);
        let mut demos = topples(&b, &SynthNoise::REAL, seed);
        for d in &mut demos {
            let t0 = d.demo.object[0].t;
            // The fall is at 2.5-2.85 s; the gap starts before it and ends after it.
            let (from, to) = (rng.random_range(2.0..2.45), rng.random_range(2.9..3.3));
            d.demo.object.retain(|p| p.t - t0 < from || p.t - t0 >= to);
        }
        let sources: Vec<Source> = demos.iter().map(|d| Source::Memory(&d.demo)).collect();
        let mut tree = Tree::default();
        learner.learn(&mut tree, &sources).unwrap();
        let (e, f) = assert_on_box(&tree, &b, &format!("box {seed}, gaps"));
        edges += e;
        faces += f;
    }
    assert!(edges >= 8 && faces >= 8, "{edges} edges, {faces} faces");
}

/// A logger that samples a 30 Hz tracker at 90 Hz writes every pose three times: the repeats
/// are left out, and the topple teaches what the tracker's own frames teach. (Before: the
/// noise was "measured" on the repeats, 0.64 mm for 1 mm, and the topple fell apart into
/// short parts with no edge.)
#[test]
fn a_logger_faster_than_the_tracker() {
    let learner = Learner::new(Config::default());
    let mut rng = StdRng::seed_from_u64(51);
    for seed in 0..4u64 {
        let b = SynthBox::random(&mut rng);
        let d = topples(&b, &SynthNoise::REAL, seed).swap_remove(0);
        let mut logged = d.clone();
        logged.demo.object = d
            .demo
            .object
            .iter()
            .flat_map(|p| (0..3).map(move |k| StampedPose::new(p.t + k as f64 / 90.0, p.pose)))
            .collect();
        let c = learner.classify(&Source::Memory(&logged.demo)).unwrap();
        assert_eq!(
            c.held_frames as usize,
            2 * d.demo.object.len(),
            "box {seed}"
        );
        let mut tree = Tree::default();
        learner
            .learn(&mut tree, &[Source::Memory(&logged.demo)])
            .unwrap();
        let (edges, _) = assert_on_box(&tree, &b, &format!("box {seed}, logged at 90 Hz"));
        assert_eq!(edges, 1, "box {seed}");
    }
}

/// A file is read as poses in memory are: the same frames left out.
#[test]
fn held_poses_in_a_file() {
    let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.07), (0.004, -0.003), 0.6);
    let mut d = topples(&b, &SynthNoise::REAL, 7).swap_remove(1);
    let repeats = hold(&mut d.demo.object, 1.6, 1.0, false);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("held.tum");
    objmodel::format::write_tum(&path, &d.demo.object, "held poses").unwrap();
    let learner = Learner::new(Config::default());
    let from_file = learner.classify(&Source::file(&path)).unwrap();
    let in_memory = learner.classify(&Source::Memory(&d.demo)).unwrap();
    assert_eq!(from_file.held_frames as usize, repeats);
    assert_eq!(in_memory.held_frames as usize, repeats);
    assert_eq!(from_file.topples.len(), 1, "{:?}", from_file.warnings);
    assert!(from_file.warnings[0].contains("holding its last pose"));
}

/// An exact tracker repeats its poses wherever the object rests (the simulator's rests do,
/// bit for bit), and a file written to whole millimetres by a 0.1 mm tracker repeats its
/// positions by chance: kept.
#[test]
fn exact_and_coarse_repeats_are_kept() {
    let learner = Learner::new(Config::default());
    let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.07), (0.004, -0.003), 0.6);
    let repeats = |poses: &[StampedPose]| {
        poses
            .windows(2)
            .filter(|w| w[0].pose.translation == w[1].pose.translation)
            .count()
    };
    for d in topples(&b, &SynthNoise::CLEAN, 3) {
        assert!(repeats(&d.demo.object) > 40);
        let c = learner.classify(&Source::Memory(&d.demo)).unwrap();
        assert_eq!(c.held_frames, 0);
        assert_eq!(c.topples.len(), 1);
    }
    let fine = SynthNoise {
        sigma_position: 1e-4,
        ..SynthNoise::CLEAN
    };
    for mut d in topples(&b, &fine, 4) {
        for p in &mut d.demo.object {
            let v = &mut p.pose.translation.vector;
            *v = v.map(|x| (x * 1e3).round() * 1e-3);
        }
        assert!(repeats(&d.demo.object) > 20);
        let c = learner.classify(&Source::Memory(&d.demo)).unwrap();
        assert_eq!(c.held_frames, 0, "{:?}", c.warnings);
    }
}

/// A tracker that lost the box writes its frames on with every pose value NaN, empty or zero
/// (`format/skipped.rs`): the file learns what the file without those lines learns, and says
/// which lines it skipped. (Before: the file was refused at its first such line.)
#[test]
fn lost_frames_written_as_nan_or_zeros_are_gaps() {
    let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.07), (0.004, -0.003), 0.6);
    let learner = Learner::new(Config::default());
    let dir = tempfile::tempdir().unwrap();
    for (k, blank) in ["nan nan nan nan nan nan nan", "0 0 0 0 0 0 0"]
        .into_iter()
        .enumerate()
    {
        let d = topples(&b, &SynthNoise::REAL, 8 + k as u64).swap_remove(k);
        let t0 = d.demo.object[0].t;
        // Lost over the start of the fall (at 2.5-2.85 s) and once in the first rest.
        let lost = |t: f64| (2.3..2.6).contains(&(t - t0)) || (0.9..1.0).contains(&(t - t0));
        let whole = dir.path().join(format!("whole{k}.tum"));
        objmodel::format::write_tum(&whole, &d.demo.object, "topple").unwrap();
        let mut kept = d.demo.object.clone();
        kept.retain(|p| !lost(p.t));
        let gapped = dir.path().join(format!("gapped{k}.tum"));
        objmodel::format::write_tum(&gapped, &kept, "topple").unwrap();
        let (mut lines, mut at) = (Vec::new(), Vec::new());
        for (i, line) in std::fs::read_to_string(&whole).unwrap().lines().enumerate() {
            let t = line.split(' ').next().unwrap().parse::<f64>().ok();
            match t.filter(|&t| lost(t)) {
                Some(_) => {
                    lines.push(format!("{} {blank}", line.split(' ').next().unwrap()));
                    at.push(i + 1);
                }
                None => lines.push(line.to_string()),
            }
        }
        let written = dir.path().join(format!("lost{k}.tum"));
        std::fs::write(&written, lines.join("\n") + "\n").unwrap();
        let with_lost = learner.classify(&Source::file(&written)).unwrap();
        let without = learner.classify(&Source::file(&gapped)).unwrap();
        assert_eq!(with_lost.topples.len(), 1, "{:?}", with_lost.warnings);
        // The same topple, bit for bit (its demonstration's name aside).
        let topples = |c: &objmodel::classify::Classification, name: &str| {
            format!("{:?}", c.topples).replace(name, "demo")
        };
        assert_eq!(
            topples(&with_lost, &format!("lost{k}.tum")),
            topples(&without, &format!("gapped{k}.tum"))
        );
        let first_run = at.iter().take_while(|&&l| l - at[0] < at.len()).count();
        let says = format!(
            "the object's tracker lost it on {} lines in 2 runs (lines {}-{}, {}-{})",
            at.len(),
            at[0],
            at[first_run - 1],
            at[first_run],
            at[at.len() - 1]
        );
        assert!(
            with_lost.warnings.iter().any(|w| w.starts_with(&says)),
            "{says:?} not in {:?}",
            with_lost.warnings
        );
        assert!(!without.warnings.iter().any(|w| w.contains("lost it")));
        assert_eq!(with_lost.lost_frames as usize, at.len());
        assert_eq!((without.lost_frames, with_lost.palm_lost_frames), (0, 0));
    }
}

/// A logger that wrote lines twice (the same time and pose: a buffer flushed twice), in the
/// object's file and the palm's of an instrumented topple: the copies are left out, counted
/// and said, and the demonstration teaches what the file without them teaches, bit for bit.
/// (Before: the file was refused at the first copy, "timestamp ... repeats timestamp".)
#[test]
fn lines_written_twice_are_left_out() {
    let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.07), (0.004, -0.003), 0.6);
    let d = synth::instrumented_topple(&b, 0, 0.3, &SynthNoise::REAL, 30.0, 67);
    let palm = d.demo.palm.as_ref().expect("instrumented");
    let dir = tempfile::tempdir().unwrap();
    let learner = Learner::new(Config::default());
    // `poses` as a TUM file, every `every`-th pose line (from the second) written twice
    // (none for 0); the path and how many lines were written twice.
    let write = |name: &str, poses: &[StampedPose], every: usize| {
        let path = dir.path().join(name);
        objmodel::format::write_tum(&path, poses, "topple").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let (mut lines, mut copies) = (Vec::new(), 0);
        for (k, line) in text.lines().filter(|l| !l.starts_with('#')).enumerate() {
            lines.push(line);
            if every > 0 && k > 0 && k % every == 0 {
                lines.push(line);
                copies += 1;
            }
        }
        std::fs::write(&path, lines.join("\n") + "\n").unwrap();
        (path, copies)
    };
    let (object, _) = write("demo.tum", &d.demo.object, 0);
    let (palm_file, _) = write("demo.palm.tum", palm, 0);
    let clean = learner
        .classify(&Source::instrumented(&object, &palm_file))
        .unwrap();
    let (object2, n_object) = write("copies.tum", &d.demo.object, 7);
    let (palm2, n_palm) = write("copies.palm.tum", palm, 5);
    assert!(n_object > 10 && n_palm > 10);
    let copies = learner
        .classify(&Source::instrumented(&object2, &palm2))
        .unwrap();
    assert_eq!(clean.topples.len(), 1, "{:?}", clean.warnings);
    let topples = |c: &objmodel::classify::Classification, name: &str| {
        format!("{:?}", c.topples).replace(name, "demo.tum")
    };
    assert_eq!(topples(&copies, "copies.tum"), topples(&clean, "demo.tum"));
    assert_eq!(copies.frames, clean.frames);
    assert_eq!(
        (copies.duplicate_lines, copies.palm_duplicate_lines),
        (n_object as u64, n_palm as u64)
    );
    assert_eq!((clean.duplicate_lines, clean.palm_duplicate_lines), (0, 0));
    for (what, n) in [("object", n_object), ("palm", n_palm)] {
        let says = format!("the {what}'s file repeats {n} lines exactly");
        assert!(
            copies.warnings.iter().any(|w| w.starts_with(&says)),
            "{says:?} not in {:?}",
            copies.warnings
        );
    }
}
