//! The learning pipeline (`objmodel::learn`) and the tree's fusion, on the kinematic generator's
//! demonstrations with exact truth: files and memory give the same model, the dynamics come in
//! the same pass at any length, and fusion does not depend on how the demonstrations arrive.

use objmodel::classify::Kind;
use objmodel::format::{read_demonstration, write_tum};
use objmodel::learn::{Config, Learner, Source};
use objmodel::observation::Observation;
use objmodel::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
use objmodel::tree::Tree;
use objmodel::Demonstration;
use rand::{rngs::StdRng, SeedableRng};
use std::path::{Path, PathBuf};

fn the_box() -> SynthBox {
    SynthBox::random(&mut StdRng::seed_from_u64(5))
}

fn topple(b: &SynthBox, side: usize, seed: u64) -> SynthDemo {
    let p = ToppleParams {
        side,
        ..Default::default()
    };
    synth::topple(b, &p, &SynthNoise::REAL, 30.0, seed)
}

/// Write a demonstration's files into `dir`: the object's, and the palm's beside it.
fn write(dir: &Path, d: &Demonstration) -> (PathBuf, Option<PathBuf>) {
    let object = dir.join(format!("{}.tum", d.name));
    write_tum(&object, &d.object, &d.name).unwrap();
    let palm = d.palm.as_ref().map(|p| {
        let path = dir.join(format!("{}.palm.tum", d.name));
        write_tum(&path, p, &d.name).unwrap();
        path
    });
    (object, palm)
}

fn observe(learner: &Learner, d: &Demonstration) -> Observation {
    learner.observe(&Source::Memory(d)).unwrap()
}

/// A file streamed through the pipeline and the same poses held in memory give the same
/// observation, bit for bit: classification, warnings and dynamics (direct and instrumented).
#[test]
fn files_and_memory_give_the_same_observation() {
    let dir = tempfile::tempdir().unwrap();
    let b = the_box();
    let learner = Learner::new(Config::default());
    for mut d in [
        topple(&b, 1, 11).demo,
        synth::instrumented_topple(&b, 2, 0.2, &SynthNoise::REAL, 30.0, 12).demo,
    ] {
        d.name = format!("demo_{}", d.palm.is_some());
        let (object, palm) = write(dir.path(), &d);
        let from_files = learner
            .observe(&Source::Files {
                object: &object,
                palm: palm.as_deref(),
            })
            .unwrap();
        let mut read = read_demonstration(&object, palm.as_deref()).unwrap();
        read.name = object.file_name().unwrap().to_string_lossy().into_owned();
        let from_memory = observe(&learner, &read);
        assert_eq!(from_files.classification.kind, Kind::Topple);
        assert!(
            !from_files.dynamics.is_empty(),
            "a topple with gravity known has dynamics"
        );
        assert_eq!(format!("{from_files:?}"), format!("{from_memory:?}"));
    }
}

/// A demonstration longer than the recorder keeps is still analysed, in the same pass, at a
/// lower rate, and says so; its φ stays within the two estimates' uncertainty of the
/// full-rate one. The trackers' noise is given: a record that keeps one frame in several
/// cannot measure the noise's correlation from frame to frame, which the full record does
/// (`learn::tracker_noise`; this white noise measures ρ = 0.04 by chance, and its tests then
/// use a σ 5% larger), and the comparison is of the record.
#[test]
fn dynamics_of_a_demonstration_longer_than_the_record() {
    let b = the_box();
    let noise = SynthNoise::REAL;
    let d = synth::instrumented_topple(&b, 0, 0.2, &noise, 120.0, 3).demo;
    let n = d.object.len();
    let mut config = Config::default();
    let given = objmodel::noise::NoiseModel {
        sigma_position: noise.sigma_position,
        sigma_rotation: noise.sigma_rotation,
    };
    config.robust.noise = Some(given);
    config.robust.palm_noise = Some(given);
    let full = observe(&Learner::new(config), &d);
    let thinned = observe(&Learner::new(config).with_capacity(n / 3), &d);
    assert_eq!(full.classification, {
        let mut c = thinned.classification.clone();
        c.warnings.clear();
        // The median frame interval of the thinned record, from gaps of several frames whose
        // stamps (seconds since 1970) hold 0.1 µs, differs in its last digits.
        let (a, b) = (
            full.classification.frame_interval_s.unwrap(),
            c.frame_interval_s.unwrap(),
        );
        assert!((a - b).abs() < 1e-4 * a, "{a} {b}");
        c.frame_interval_s = full.classification.frame_interval_s;
        c
    });
    assert!(
        thinned
            .classification
            .warnings
            .iter()
            .any(|w| w.contains("one object frame in 4")),
        "{:?}",
        thinned.classification.warnings
    );
    let (a, b) = (&full.dynamics[0], &thinned.dynamics[0]);
    let (pa, pb) = (a.phi.unwrap(), b.phi.unwrap());
    let sigma = a.phi_sigma.unwrap().hypot(b.phi_sigma.unwrap());
    eprintln!(
        "phi at full rate {:.3} deg, at 1/4: {:.3} deg (combined sigma {:.3} deg)",
        pa.to_degrees(),
        pb.to_degrees(),
        sigma.to_degrees()
    );
    assert!((pa - pb).abs() < 4.0 * sigma);
    assert!(b.series.t.len() * 3 <= n);
}

/// Without gravity there are no dynamics, and the report says why; and a topple in the world
/// teaches no edge (a slide turning about a fixed point is the same motion about a vertical
/// line), while one relative to a palm does.
#[test]
fn without_gravity_the_dynamics_are_not_guessed() {
    let b = the_box();
    let config = Config {
        gravity: None,
        ..Config::default()
    };
    let learner = Learner::new(config);

    let d = topple(&b, 0, 21).demo;
    let mut tree = Tree::default();
    let reports = learner.learn(&mut tree, &[Source::Memory(&d)]).unwrap();
    assert!(tree.edges.is_empty());
    let why = reports[0].classification.segments[0].withheld.as_deref();
    assert!(
        why.is_some_and(|w| w.contains("without gravity")),
        "{why:?}"
    );
    assert!(reports[0]
        .classification
        .warnings
        .iter()
        .any(|w| w.contains("gravity is unknown") && w.contains("taught no edge")));

    let d = synth::instrumented_topple(&b, 0, 0.2, &SynthNoise::REAL, 30.0, 21).demo;
    let mut tree = Tree::default();
    let reports = learner.learn(&mut tree, &[Source::Memory(&d)]).unwrap();
    assert!(reports[0].dynamics.is_empty());
    assert!(reports[0]
        .classification
        .warnings
        .iter()
        .any(|w| w.contains("gravity is unknown")));
    assert!(tree.edges.iter().all(|e| e.pendulums.is_empty()));
    assert_eq!(tree.edges.len(), 1);
}

/// Each topple's pendulum goes to the edge that topple found, in the same step as the edge:
/// four topples of one box, each about its own edge, give four edges with one pendulum each,
/// whose support is that edge's demonstration.
#[test]
fn each_pendulum_joins_its_own_edge() {
    let b = the_box();
    let learner = Learner::new(Config::default());
    let mut tree = Tree::default();
    for side in 0..4 {
        let mut d = synth::instrumented_topple(&b, side, 0.2, &SynthNoise::REAL, 30.0, 40).demo;
        d.name = format!("side{side}");
        learner.learn(&mut tree, &[Source::Memory(&d)]).unwrap();
    }
    assert_eq!(tree.edges.len(), 4);
    for e in &tree.edges {
        assert_eq!(e.pendulums.len(), 1, "{}", e.id);
        assert_eq!(e.pendulums[0].support, e.support, "{}", e.id);
    }
}

/// Adding the same demonstration twice changes nothing; removing it leaves the tree as before.
#[test]
fn the_same_demonstration_twice_is_one() {
    let b = the_box();
    let learner = Learner::new(Config::default());
    let demos: Vec<Demonstration> = (0..3)
        .map(|side| {
            let mut d = synth::instrumented_topple(&b, side, 0.2, &SynthNoise::REAL, 30.0, 50).demo;
            d.name = format!("d{side}");
            d
        })
        .collect();
    let observations: Vec<Observation> = demos.iter().map(|d| observe(&learner, d)).collect();
    let mut tree = Tree::default();
    observations.iter().for_each(|o| {
        tree.add(o);
    });
    let once = tree.clone();
    tree.add(&observations[2]);
    assert_eq!(tree, once);
    let mut two = Tree::default();
    observations[..2].iter().for_each(|o| {
        two.add(o);
    });
    tree.remove_demo("d2");
    assert_eq!(tree.to_json(), two.to_json());
}

/// Learning in a batch or one by one, in any order, gives the same features within their
/// uncertainty: ten topples about two edges, fused forwards and backwards.
#[test]
fn fusion_does_not_depend_on_the_order() {
    let b = the_box();
    let learner = Learner::new(Config::default());
    let observations: Vec<Observation> = (0..10u64)
        .map(|i| {
            let mut d = topple(&b, (i % 2) as usize, 60 + i).demo;
            d.name = format!("t{i}");
            observe(&learner, &d)
        })
        .collect();
    let mut forwards = Tree::default();
    observations.iter().for_each(|o| {
        forwards.add(o);
    });
    let mut backwards = Tree::default();
    observations.iter().rev().for_each(|o| {
        backwards.add(o);
    });
    assert_eq!(forwards.edges.len(), 2);
    assert_eq!(backwards.edges.len(), 2);
    for e in &forwards.edges {
        let f = backwards
            .edges
            .iter()
            .find(|x| x.direction.dot(&e.direction).abs() > 0.99)
            .expect("the same edge");
        let mut support = f.support.clone();
        support.sort();
        let mut mine = e.support.clone();
        mine.sort();
        assert_eq!(support, mine);
        let d = (e.point - f.point).norm();
        assert!(d <= 1e-9 + 0.1 * e.sigma_point_m, "{d} m");
    }
}

/// A topple about a new edge starts a new edge; one about a known edge joins it.
#[test]
fn a_new_edge_and_a_known_edge() {
    let b = the_box();
    let learner = Learner::new(Config::default());
    let mut tree = Tree::default();
    let mut add = |side: usize, seed: u64| {
        let mut d = topple(&b, side, seed).demo;
        d.name = format!("s{side}_{seed}");
        learner.learn(&mut tree, &[Source::Memory(&d)]).unwrap();
        (
            tree.edges.len(),
            tree.edges.iter().map(|e| e.n_support).sum::<usize>(),
        )
    };
    assert_eq!(add(0, 1), (1, 1));
    assert_eq!(add(0, 2), (1, 2));
    assert_eq!(add(3, 3), (2, 3));
}

/// A demonstration is its poses, not its name: two files named alike in two folders are two
/// demonstrations (the second under `NAME#2`); the same poses under another name are counted
/// once, and the report says so.
#[test]
fn demonstrations_are_identified_by_their_poses() {
    let dir = tempfile::tempdir().unwrap();
    let b = the_box();
    let learner = Learner::new(Config::default());
    let mut files = Vec::new();
    for (day, side) in [("day1", 0), ("day2", 1)] {
        std::fs::create_dir(dir.path().join(day)).unwrap();
        let mut d = topple(&b, side, 70 + side as u64).demo;
        d.name = "demo".into();
        files.push(write(&dir.path().join(day), &d).0);
    }
    let mut tree = Tree::default();
    let sources: Vec<Source> = files.iter().map(Source::file).collect();
    let reports = learner.learn(&mut tree, &sources).unwrap();
    let names: Vec<&str> = tree.demos.iter().map(|d| d.name.as_str()).collect();
    assert_eq!(names, ["demo.tum", "demo.tum#2"]);
    assert_eq!(tree.edges.len(), 2, "each day's edge is kept");
    assert!(reports[1]
        .classification
        .warnings
        .iter()
        .any(|w| w.contains("demo.tum#2")));
    // The first day's file again, copied under another name: replaced, not fused twice.
    let copy = dir.path().join("copy.tum");
    std::fs::copy(&files[0], &copy).unwrap();
    let before = tree.edges.iter().map(|e| e.n_support).sum::<usize>();
    let reports = learner.learn(&mut tree, &[Source::file(&copy)]).unwrap();
    assert!(reports[0]
        .classification
        .warnings
        .iter()
        .any(|w| w.contains("the same poses as 'demo.tum'")));
    assert_eq!(tree.demos.len(), 2);
    assert_eq!(
        tree.edges.iter().map(|e| e.n_support).sum::<usize>(),
        before
    );
}

/// Two demonstrations that share their times and orientations bit for bit but not their
/// positions are two (before 2026-12-08 the fingerprint left positions out and the second
/// replaced the first); a tree written then, whose demonstration holds the fingerprint
/// without positions, still knows those poses again.
#[test]
fn positions_are_part_of_a_demonstrations_poses() {
    let b = the_box();
    let learner = Learner::new(Config::default());
    let mut d = topple(&b, 0, 90).demo;
    d.name = "a".into();
    let mut moved = d.clone();
    moved.name = "b".into();
    for p in &mut moved.object {
        p.pose.translation.vector.x += 1e-3;
    }
    let (a, shifted) = (observe(&learner, &d), observe(&learner, &moved));
    assert_eq!(
        a.fingerprint_without_positions,
        shifted.fingerprint_without_positions
    );
    assert_ne!(a.fingerprint, shifted.fingerprint);
    let mut tree = Tree::default();
    assert_eq!(tree.add(&a).replaced, None);
    let added = tree.add(&shifted);
    assert_eq!((added.name.as_str(), added.replaced), ("b", None));
    assert_eq!(tree.demos.len(), 2);
    // An older tree's record of `a`: the fingerprint without positions.
    let mut old = Tree::default();
    old.add(&a);
    old.demos[0].fingerprint = a.fingerprint_without_positions.clone();
    let again = old.add(&a);
    assert_eq!(again.replaced.as_deref(), Some("a"));
    assert_eq!(old.demos.len(), 1);
    assert_eq!(old.demos[0].fingerprint, a.fingerprint);
}

/// The features of one box's topples agree with each other (no contradiction at real noise);
/// an edge moved 2 cm off its faces, or a centre of mass outside the shape, is reported, with
/// the features named.
#[test]
fn contradictions_between_features_are_reported() {
    let learner = Learner::new(Config::default());
    for seed in 0..3u64 {
        let b = SynthBox::random(&mut StdRng::seed_from_u64(500 + seed));
        let mut tree = Tree::default();
        for side in 0..4 {
            let mut d = topple(&b, side, 90 + 10 * seed + side as u64).demo;
            d.name = format!("s{side}");
            learner.learn(&mut tree, &[Source::Memory(&d)]).unwrap();
        }
        let found = tree.contradictions();
        assert!(found.is_empty(), "seed {seed}: {found:#?}");
        let mut wrong = tree.clone();
        let e = &mut wrong.edges[0];
        // The edge as moved observations would give it: its own estimate, not conditioned on
        // its faces (the checks test the edge's own estimate).
        e.observed = None;
        e.conditioned_on.clear();
        let along_face = e.direction.cross(&nalgebra::Vector3::z()).normalize();
        let off_face = e.direction.cross(&along_face).normalize();
        e.point += off_face * 0.02;
        let found = wrong.contradictions();
        assert!(
            found.iter().any(|c| c.features[0] == wrong.edges[0].id),
            "seed {seed}: {found:#?}"
        );
    }
}

/// A demonstration that starts in flight and rests only at its end (a toss whose file begins
/// at the release): its first frames measure the motion, not the noise, so the noise is
/// measured on the rest and the demonstration classified again with it, which the report says.
#[test]
fn noise_is_measured_on_the_rest_when_the_first_frames_are_motion() {
    let learner = Learner::new(Config::default());
    let truth = SynthNoise {
        drop: 0.0,
        sign_flip: 0.0,
        tag_flip: 0.0,
        ..SynthNoise::REAL
    };
    let mut motion_first = 0;
    for seed in 0..6u64 {
        let b = SynthBox::random(&mut StdRng::seed_from_u64(40 + seed));
        let toss = synth::toss(&b, &truth, 30.0, 70 + seed);
        let mut d = toss.demo.clone();
        let landing = toss.flights.last().unwrap().1;
        d.object
            .retain(|p| p.t >= toss.flights[0].0 && p.t <= landing + 0.8);
        let first: Vec<objmodel::noise::PoseSample> = d
            .object
            .iter()
            .map(|p| (p.t, p.pose.rotation, p.pose.translation.vector))
            .collect();
        let from_first = objmodel::noise::estimate(&first).unwrap();
        let c = observe(&learner, &d).classification;
        let n = c.noise.unwrap();
        let ratio = n.sigma_position / truth.sigma_position;
        assert!(
            (0.6..1.6).contains(&ratio),
            "seed {seed}: {:.2} mm measured for {:.2} mm (the first frames gave {:.2} mm)",
            n.sigma_position * 1e3,
            truth.sigma_position * 1e3,
            from_first.sigma_position * 1e3
        );
        let rot = n.sigma_rotation / truth.sigma_rotation;
        assert!((0.6..1.6).contains(&rot), "seed {seed}: rotation {rot:.2}");
        if from_first.sigma_position > 2.0 * truth.sigma_position {
            motion_first += 1;
            assert!(
                c.warnings
                    .iter()
                    .any(|w| w.contains("measured on the rest")),
                "seed {seed}: {:?}",
                c.warnings
            );
        }
    }
    // The case this is about: first frames that measured the motion.
    assert!(motion_first >= 3, "{motion_first} of 6");
}

/// The same at a motion-capture rate, where a toss's file may end a few tenths of a second
/// after the landing: a rest shorter than the rest test's window (0.6 s) holds 30 frames at
/// 100 Hz, which measure the noise; the pipeline measures it there rather than teach nothing.
/// (Each estimate rests on the last 15 frames: one in 30 seeds is 1.64 times the truth.)
#[test]
fn a_short_rest_at_a_high_rate_measures_the_noise() {
    let learner = Learner::new(Config::default());
    let truth = SynthNoise {
        sigma_position: 1e-4,
        sigma_rotation: 0.05f64.to_radians(),
        drop: 0.0,
        sign_flip: 0.0,
        tag_flip: 0.0,
    };
    let mut ratios = Vec::new();
    for seed in 0..30u64 {
        let b = SynthBox::random(&mut StdRng::seed_from_u64(60 + seed));
        let toss = synth::toss(&b, &truth, 100.0, 90 + seed);
        let mut d = toss.demo.clone();
        let landing = toss.flights.last().unwrap().1;
        d.object
            .retain(|p| p.t >= toss.flights[0].0 && p.t <= landing + 0.3);
        let c = observe(&learner, &d).classification;
        assert!(
            !c.warnings.iter().any(|w| w.contains("cannot be estimated")),
            "seed {seed}: {:?}",
            c.warnings
        );
        // Where the first frames measured the motion (beyond the model tolerance the tests
        // add), the noise is the rest's.
        if c.warnings
            .iter()
            .any(|w| w.contains("measured on the rest"))
        {
            let n = c.noise.unwrap();
            let ratio = (
                n.sigma_position / truth.sigma_position,
                n.sigma_rotation / truth.sigma_rotation,
            );
            assert!(
                (0.5..2.0).contains(&ratio.0) && (0.5..2.0).contains(&ratio.1),
                "seed {seed}: {ratio:?}"
            );
            ratios.push(ratio);
        }
    }
    assert!(
        ratios.len() >= 20,
        "{} of 30 measured on the rest",
        ratios.len()
    );
    let mean = |f: fn(&(f64, f64)) -> f64| ratios.iter().map(f).sum::<f64>() / ratios.len() as f64;
    let (p, r) = (mean(|r| r.0), mean(|r| r.1));
    assert!(
        (0.8..1.3).contains(&p) && (0.8..1.3).contains(&r),
        "{p:.2}, {r:.2}"
    );
}

/// `Learner::learn_readable`: a source whose file does not read is left out with its error,
/// and the tree is the one the others give alone, each source read once (a batch with many
/// broken files costs one pass, not one per broken file); an error that no source can be left
/// out for is returned, and the tree is left as it was.
#[test]
fn the_readable_demonstrations_are_learnt_and_the_others_named() {
    let dir = tempfile::tempdir().unwrap();
    let b = the_box();
    let learner = Learner::new(Config::default());
    let demos: Vec<Demonstration> = (0..3)
        .map(|k| {
            let mut d = topple(&b, k, 80 + k as u64).demo;
            d.name = format!("t{k}");
            d
        })
        .collect();
    let files: Vec<PathBuf> = demos[..2].iter().map(|d| write(dir.path(), d).0).collect();
    let broken = dir.path().join("broken.tum");
    std::fs::write(&broken, "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n").unwrap();
    let missing = dir.path().join("missing.tum");
    let sources = [
        Source::file(&files[0]),
        Source::file(&broken),
        Source::Memory(&demos[2]),
        Source::file(&missing),
        Source::file(&files[1]),
        Source::file(&broken),
    ];
    let mut tree = Tree::default();
    let mut seen = Vec::new();
    let (reports, left_out) = learner
        .learn_readable(&mut tree, &sources, |k| seen.push(k))
        .unwrap();
    let indices: Vec<usize> = left_out.iter().map(|l| l.index).collect();
    assert_eq!(indices, [1, 3, 5]);
    assert!(left_out[0]
        .error
        .to_string()
        .contains("broken.tum:2: expected 8 columns"));
    assert!(left_out[1].error.to_string().contains("missing.tum"));
    assert_eq!(reports.len(), 3);
    assert_eq!(seen, [0, 1, 2, 3, 4, 5], "each source read once");
    let mut alone = Tree::default();
    let others = [sources[0], sources[2], sources[4]];
    learner.learn(&mut alone, &others).unwrap();
    assert_eq!(tree.to_json(), alone.to_json());
    // Only the broken file: its error, and the tree as it was.
    let before = tree.to_json();
    let e = learner
        .learn_readable(&mut tree, &[Source::file(&broken)], |_| {})
        .unwrap_err();
    assert!(e.to_string().contains("broken.tum:2"), "{e}");
    assert_eq!(tree.to_json(), before);
}
