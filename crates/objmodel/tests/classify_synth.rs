//! Classification and edge/face accuracy on the kinematic generator, against exact truth, at
//! real tracking noise (1 mm, 0.5°, dropped frames, sign flips, tag flips, pivot slip).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use objmodel::classify::{classify, Config, Kind, Label, Method};
use objmodel::synth::{self, smoothstep, SynthBox, SynthDemo, SynthNoise, ToppleParams};
use objmodel::trajectory::{Demonstration, StampedPose};
use objmodel::tree::Tree;
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::f64::consts::{FRAC_PI_2, PI};

/// A demonstration through the library's learning pipeline, default configuration.
fn observe(demo: &Demonstration) -> objmodel::observation::Observation {
    use objmodel::learn::{Learner, Source};
    Learner::new(Config::default())
        .observe(&Source::Memory(demo))
        .unwrap()
}

fn line_angle_deg(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b).abs()).to_degrees()
}

/// The angle between two directions \[deg\], sign included (0 to 180).
fn angle_deg(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b)).to_degrees()
}

fn demos(kind: usize, n: usize, noise: &SynthNoise) -> Vec<SynthDemo> {
    (0..n as u64)
        .map(|seed| {
            let mut rng = StdRng::seed_from_u64(1000 * kind as u64 + seed);
            let b = SynthBox::random(&mut rng);
            let side = rng.random_range(0..4);
            match kind {
                0 => synth::topple(
                    &b,
                    &ToppleParams {
                        side,
                        push_s: rng.random_range(0.8..2.5),
                        ..Default::default()
                    },
                    noise,
                    30.0,
                    seed,
                ),
                1 => synth::instrumented_topple(
                    &b,
                    side,
                    rng.random_range(0.1..0.3),
                    noise,
                    30.0,
                    seed,
                ),
                2 => synth::slide(&b, noise, 30.0, seed),
                _ => synth::general(&b, noise, 30.0, seed),
            }
        })
        .collect()
}

fn accuracy(method: Method, noise: &SynthNoise, per_kind: usize) -> Vec<(Kind, usize, usize)> {
    let config = Config {
        method,
        ..Config::default()
    };
    (0..4)
        .map(|k| {
            let ds = demos(k, per_kind, noise);
            let ok = ds
                .iter()
                .filter(|d| classify(&d.demo, &config).unwrap().kind == d.truth.kind)
                .count();
            (ds[0].truth.kind, ok, ds.len())
        })
        .collect()
}

/// docs/method.md, whitespace folded: its quoted figures are checked against what the tests
/// measure.
fn method_doc() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/method.md"))
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn robust_classification_is_at_least_98_percent_at_real_noise() {
    let acc = accuracy(Method::Robust, &SynthNoise::REAL, 50);
    let (ok, n) = acc.iter().fold((0, 0), |a, r| (a.0 + r.1, a.1 + r.2));
    eprintln!("robust, real noise: {acc:?} -> {ok}/{n}");
    let clean = accuracy(Method::Robust, &SynthNoise::CLEAN, 20);
    let (ok_clean, n_clean) = clean.iter().fold((0, 0), |a, r| (a.0 + r.1, a.1 + r.2));
    let quoted =
        format!("real noise, 50 demos per kind): {ok}/{n} correct; clean {ok_clean}/{n_clean}.");
    assert!(
        method_doc().contains(&quoted),
        "docs/method.md should say: {quoted}"
    );
    assert!(ok as f64 >= 0.98 * n as f64, "{acc:?}");
    for (_, ok, n) in &acc {
        assert!(*ok as f64 >= 0.94 * *n as f64, "{acc:?}");
    }
}

#[test]
fn robust_classification_is_exact_on_clean_data() {
    let acc = accuracy(Method::Robust, &SynthNoise::CLEAN, 20);
    eprintln!("robust, clean: {acc:?}");
    assert!(acc.iter().all(|(_, ok, n)| ok == n), "{acc:?}");
}

#[test]
fn paper_method_runs_and_is_worse_at_real_noise() {
    // Recorded for the note: the literal algorithm at real noise.
    let paper = accuracy(Method::Paper, &SynthNoise::REAL, 30);
    let robust = accuracy(Method::Robust, &SynthNoise::REAL, 30);
    eprintln!("paper, real noise: {paper:?}\nrobust: {robust:?}");
    let sum = |a: &[(Kind, usize, usize)]| a.iter().map(|r| r.1).sum::<usize>();
    assert!(sum(&robust) > sum(&paper));
    // docs/method.md quotes these counts: they must be what this test measures.
    let method = method_doc();
    let quoted = format!(
        "labels {}/{} direct topples, {}/{} instrumented topples and {}/{} slides correctly",
        paper[0].1, paper[0].2, paper[1].1, paper[1].2, paper[2].1, paper[2].2
    );
    assert!(
        method.contains(&quoted),
        "docs/method.md should say: {quoted}"
    );
    // On clean data the literal algorithm gets topples right.
    let clean = accuracy(Method::Paper, &SynthNoise::CLEAN, 10);
    assert_eq!(clean[0].1, clean[0].2, "{clean:?}");
}

/// Ten demonstrations of one edge of one box, fused: direction within 1°, position within 2 mm.
#[test]
fn fused_edge_from_ten_topples_meets_targets() {
    for (box_seed, instrumented) in [(7u64, false), (8, true), (9, false)] {
        let mut rng = StdRng::seed_from_u64(box_seed);
        let b = SynthBox::random(&mut rng);
        let mut tree = Tree::default();
        let mut per_demo = Vec::new();
        let mut truth = None;
        for seed in 0..10 {
            let d = if instrumented {
                synth::instrumented_topple(
                    &b,
                    1,
                    0.15 + 0.02 * seed as f64,
                    &SynthNoise::REAL,
                    30.0,
                    100 + seed,
                )
            } else {
                synth::topple(
                    &b,
                    &ToppleParams {
                        side: 1,
                        push_s: 1.0 + 0.1 * seed as f64,
                        ..Default::default()
                    },
                    &SynthNoise::REAL,
                    30.0,
                    100 + seed,
                )
            };
            let o = observe(&d.demo);
            let c = &o.classification;
            assert_eq!(c.kind, Kind::Topple);
            let t = d.truth.edge.unwrap();
            let e = c.edges().next().unwrap();
            per_demo.push((
                line_angle_deg(&e.line.direction, &t.direction),
                (e.line.point - t.point).norm() * 1e3,
            ));
            truth = Some(t);
            tree.add(&o);
        }
        let t = truth.unwrap();
        assert_eq!(
            tree.edges.len(),
            1,
            "ten demos of one edge must fuse into one edge: {:#?}",
            tree.edges
                .iter()
                .map(|e| (e.point, e.direction))
                .collect::<Vec<_>>()
        );
        let e = &tree.edges[0];
        let dir_err = line_angle_deg(&e.direction, &t.direction);
        let pos_err = (e.point - t.point).norm() * 1e3;
        eprintln!("box {box_seed} instrumented={instrumented}: per demo (deg, mm) {per_demo:.2?}\n  fused: {dir_err:.3} deg, {pos_err:.3} mm (sigma {:.3} mm, {:.3} deg), support {}", e.sigma_point_m * 1e3, e.sigma_direction_rad.to_degrees(), e.n_support);
        assert!(dir_err <= 1.0, "direction error {dir_err} deg");
        assert!(pos_err <= 2.0, "position error {pos_err} mm");
        assert_eq!(e.n_support, 10);
    }
}

#[test]
fn slide_gives_the_face_normal_and_topples_give_its_offset() {
    let mut rng = StdRng::seed_from_u64(21);
    let b = SynthBox::random(&mut rng);
    let mut tree = Tree::default();
    let mut truth = None;
    for seed in 0..5 {
        let d = synth::slide(&b, &SynthNoise::REAL, 30.0, 300 + seed);
        let o = observe(&d.demo);
        let c = &o.classification;
        assert_eq!(c.kind, Kind::Slide);
        truth = d.truth.face;
        tree.add(&o);
    }
    let (n, offset) = truth.unwrap();
    assert_eq!(tree.faces.len(), 1);
    let f = &tree.faces[0];
    let err = angle_deg(&f.normal, &n);
    eprintln!(
        "slide face normal error {err:.3} deg (sign included), offset {:?}",
        f.offset
    );
    assert!(err < 1.0);
    assert!(f.offset.is_none(), "a slide alone cannot give the offset");
    // Topples from the same resting face give the offset: every edge toppled about lies in it.
    for side in 0..4 {
        let d = synth::topple(
            &b,
            &ToppleParams {
                side,
                ..Default::default()
            },
            &SynthNoise::REAL,
            30.0,
            5 + side as u64,
        );
        tree.add(&observe(&d.demo));
    }
    let f = tree.faces.iter().find(|f| f.evidence.slide > 0).unwrap();
    let got = f.offset.expect("offset from the edges in the face");
    let sigma = f.offset_sigma_m.unwrap();
    eprintln!(
        "offset {got:.4} vs {offset:.4} (sigma {sigma:.4}), evidence {:?}",
        f.evidence
    );
    assert_eq!(
        f.evidence.rest,
        4 + 2 * 5,
        "the four topples rested on the slide's face first, and the five slides started and \
         ended on it"
    );
    // The generator's pivot slips by up to 8 mm at the end of each topple; the frames of that
    // slip that pass the change-point test bias the edge by 1-3 mm along the face normal.
    assert!((got - offset).abs() < 3.5e-3);
    // Four bottom edges, and the five faces: bottom, and the four it landed on.
    assert_eq!(tree.edges.len(), 4);
    assert_eq!(tree.faces.len(), 5);
}

/// A straight push (no turning) leaves the face normal undetermined by the motion: every
/// normal perpendicular to the travel fits it. With gravity, the face slid on is the one facing
/// down; that face, and only one, must come out of ten pushes in different directions.
#[test]
fn straight_pushes_give_the_bottom_face() {
    let mut rng = StdRng::seed_from_u64(31);
    let b = SynthBox::random(&mut rng);
    // Exact poses too: then nothing but the prior decides the normal about the travel.
    for noise in [SynthNoise::REAL, SynthNoise::CLEAN] {
        let mut tree = Tree::default();
        let mut worst: f64 = 0.0;
        for seed in 0..10 {
            let d = synth::straight_slide(&b, &noise, 30.0, 400 + seed);
            let o = observe(&d.demo);
            let c = &o.classification;
            assert_eq!(c.kind, Kind::Slide, "{}", d.demo.name);
            let (n, _) = d.truth.face.unwrap();
            let f = c
                .segments
                .iter()
                .find_map(|s| s.face.as_ref())
                .expect("a face");
            worst = worst.max(angle_deg(&f.normal, &n));
            tree.add(&o);
        }
        eprintln!("straight pushes: largest face normal error {worst:.3} deg (sign included)");
        assert!(worst < 1.0, "{worst} deg");
        assert_eq!(tree.faces.len(), 1);
    }
}

/// Other trackers run at other rates: the tests are in seconds and noise units, not frames.
#[test]
fn classification_holds_at_15_and_120_hz() {
    for rate in [15.0, 120.0] {
        let config = Config::default();
        let mut wrong = Vec::new();
        for kind in 0..4 {
            for seed in 0..10u64 {
                let mut rng = StdRng::seed_from_u64(5000 + 100 * kind as u64 + seed);
                let b = SynthBox::random(&mut rng);
                let side = rng.random_range(0..4);
                let d = match kind {
                    0 => synth::topple(
                        &b,
                        &ToppleParams {
                            side,
                            ..Default::default()
                        },
                        &SynthNoise::REAL,
                        rate,
                        seed,
                    ),
                    1 => synth::instrumented_topple(&b, side, 0.2, &SynthNoise::REAL, rate, seed),
                    2 => synth::slide(&b, &SynthNoise::REAL, rate, seed),
                    _ => synth::general(&b, &SynthNoise::REAL, rate, seed),
                };
                let c = classify(&d.demo, &config).unwrap();
                if c.kind != d.truth.kind {
                    wrong.push((rate, kind, seed, c.kind));
                }
            }
        }
        eprintln!("{rate} Hz: {} of 40 wrong: {wrong:?}", wrong.len());
        assert!(wrong.len() <= 1, "{wrong:?}");
    }
}

/// A camera-frame tracker: the same demonstrations seen in a frame with y down (and turned),
/// with gravity given in that frame, are classified and learnt the same, without warnings; with
/// the default gravity instead, a slide that comes out general warns about the gravity.
#[test]
fn gravity_in_a_camera_frame() {
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};
    let camera_from_world = Isometry3::from_parts(
        Translation3::new(0.3, -0.2, 1.1),
        UnitQuaternion::from_euler_angles(-1.9, 0.3, 0.7),
    );
    let config = Config {
        gravity: Some(camera_from_world.rotation * Vector3::new(0.0, 0.0, -9.81)),
        ..Config::default()
    };
    let mut wrong_gravity_warnings = 0;
    for kind in 0..4 {
        for seed in 0..5u64 {
            let mut rng = StdRng::seed_from_u64(7000 + 10 * kind as u64 + seed);
            let b = SynthBox::random(&mut rng);
            let mut d = match kind {
                0 => synth::topple(&b, &ToppleParams::default(), &SynthNoise::REAL, 30.0, seed),
                1 => synth::instrumented_topple(&b, 1, 0.2, &SynthNoise::REAL, 30.0, seed),
                2 => synth::slide(&b, &SynthNoise::REAL, 30.0, seed),
                _ => synth::general(&b, &SynthNoise::REAL, 30.0, seed),
            };
            d.demo = d.demo.in_frame(&camera_from_world);
            let c = classify(&d.demo, &config).unwrap();
            assert_eq!(c.kind, d.truth.kind, "kind {kind} seed {seed}");
            assert!(c.warnings.is_empty(), "{:?}", c.warnings);
            if let (Some(t), Some(e)) = (d.truth.edge, c.edges().next()) {
                assert!(line_angle_deg(&e.line.direction, &t.direction) < 2.0);
            };
            // With the default gravity (z up, wrong here) a slide that comes out general says
            // why: its plane of motion is far from level.
            if kind == 2 {
                let c = classify(&d.demo, &Config::default()).unwrap();
                if c.kind == Kind::General {
                    wrong_gravity_warnings += c.warnings.len();
                    assert!(
                        c.warnings.iter().any(|w| w.contains("--gravity")),
                        "{:?}",
                        c.warnings
                    );
                }
            }
        }
    }
    assert!(wrong_gravity_warnings > 0, "no slide came out general");
}

/// A quasi-static push (the box turned onto its edge over a minute, about 0.5°/s: within the
/// tracking noise over any 0.6 s rest window) is still a topple about the right edge: the
/// rest's drift test finds the slow motion.
#[test]
fn quasi_static_topples_give_the_edge() {
    for seed in 0..5u64 {
        let mut rng = StdRng::seed_from_u64(300 + seed);
        let b = SynthBox::random(&mut rng);
        let d = synth::topple(
            &b,
            &ToppleParams {
                side: (seed % 4) as usize,
                push_s: 60.0,
                ..Default::default()
            },
            &SynthNoise::REAL,
            30.0,
            seed,
        );
        let c = classify(&d.demo, &Config::default()).unwrap();
        let t = d.truth.edge.unwrap();
        let e = c.edges().next().expect("an edge");
        let (angle, dist) = (
            line_angle_deg(&e.line.direction, &t.direction),
            (e.line.point - t.point).norm() * 1e3,
        );
        eprintln!("seed {seed}: {:?}, {angle:.3} deg, {dist:.2} mm", c.kind);
        assert_eq!(c.kind, Kind::Topple);
        // Every frame is labelled exactly once.
        assert_eq!(c.labels.iter().map(|r| r.frames).sum::<u64>(), c.frames);
        assert!(angle < 1.0 && dist < 3.0, "{angle} deg, {dist} mm");
    }
}

/// Running the cleaner and rest detection apart from the segments and blocks (as `learn` does,
/// on another thread) gives exactly the same classification as the sequential analyser.
#[test]
fn split_front_end_gives_the_same_classification() {
    use objmodel::bench::AnalyzerStages;
    use objmodel::classify::Analyzer;
    for kind in 0..4 {
        for d in demos(kind, 3, &SynthNoise::REAL) {
            if d.demo.palm.is_some() {
                continue; // The palm merge comes before the rest test: no split front end.
            }
            let config = Config::default();
            let sequential = classify(&d.demo, &config).unwrap();
            let mut a = Analyzer::new(&d.demo.name, &config, false);
            let mut front = a.take_object_rest_test().expect("robust, no palm");
            for p in &d.demo.object {
                front.push(p, &mut |j| a.push_verdict(j));
            }
            front.finish(&mut |j| a.push_verdict(j));
            assert_eq!(a.finish().unwrap(), sequential);
        }
    }
}

/// Tracking glitches of one or two frames (here: two tag flips in a row in the object's or the
/// palm's stream, which single-frame rejection does not catch) must not become a topple with an
/// edge of their own: one frame always has a screw axis, so a fixed line needs several frames
/// to be tested (`MIN_EDGE_FRAMES`). The generator's instrumented demonstrations 24004 and 24012
/// (box of seed 24, as `objmodel synth instrumented --seed 24`) have such glitches; each must
/// give one edge, the true one.
#[test]
fn glitches_of_two_frames_are_not_topples() {
    let b = SynthBox::random(&mut StdRng::seed_from_u64(24));
    for seed in [24004, 24012] {
        let d = synth::instrumented_topple(&b, 0, 0.2, &SynthNoise::REAL, 30.0, seed);
        let c = classify(&d.demo, &Config::default()).unwrap();
        let t = d.truth.edge.unwrap();
        let edges: Vec<_> = c.edges().collect();
        assert_eq!(edges.len(), 1, "seed {seed}: {} edges", edges.len());
        let angle = line_angle_deg(&edges[0].line.direction, &t.direction);
        assert!(angle < 5.0, "seed {seed}: edge {angle:.1}° off");
    }
}

/// A box tracked precisely (0.3 mm, 0.15°) at 30 Hz: a second of rest at `start` (its pose in
/// the world), the motion `motion(s)` (relative to `start`, `s` from 0 to `motion_s` \[s\]),
/// then `tail` \[s\] of bouncing and sliding on the table (it slides 4 cm, turns 0.4 rad about
/// the vertical and rocks about a horizontal axis and back to level), then a second of rest.
fn precise_demo(
    start: &Isometry3<f64>,
    motion: impl Fn(f64) -> Isometry3<f64>,
    motion_s: f64,
    tail: f64,
    seed: u64,
) -> Demonstration {
    let wander = |s: f64| {
        // Bounces (rocking about a horizontal axis, back to level) while sliding and turning.
        let x = if tail > 0.0 {
            (s / tail).clamp(0.0, 1.0)
        } else {
            0.0
        };
        Isometry3::from_parts(
            Translation3::new(0.04 * x, 0.015 * (PI * x).sin(), 0.0),
            UnitQuaternion::from_scaled_axis(Vector3::z() * 0.4 * x)
                * UnitQuaternion::from_scaled_axis(Vector3::x() * 0.15 * (2.0 * PI * x).sin()),
        )
    };
    let rate = 30.0;
    let n = ((1.0 + motion_s + tail + 1.0) * rate) as usize;
    let end = start * motion(motion_s);
    let poses: Vec<StampedPose> = (0..n)
        .map(|i| {
            let t = i as f64 / rate;
            let s = t - 1.0;
            let pose = if s < motion_s {
                start * motion(s.max(0.0))
            } else {
                // The wander turns about the box's resting point, in the world.
                let c = Translation3::from(end.translation.vector.xy().push(0.0));
                c * wander(s - motion_s) * c.inverse() * end
            };
            StampedPose::new(t, pose)
        })
        .collect();
    let noise = SynthNoise {
        sigma_position: 3e-4,
        sigma_rotation: 0.15f64.to_radians(),
        ..SynthNoise::CLEAN
    };
    Demonstration {
        name: format!("precise_{seed}"),
        object: synth::add_noise(&poses, &noise, &mut StdRng::seed_from_u64(seed)),
        palm: None,
    }
}

/// The landing of a topple: after a box leaves its edge it falls, bounces and may slide before
/// it comes to rest on the adjacent face. With a precise tracker those frames are measurably
/// general, and there can be more of them than of the edge rotation; they must not outvote it.
/// The same frames after a tip that falls back onto the face it started on are a motion of
/// their own, and do vote.
#[test]
fn a_topples_landing_does_not_vote() {
    for seed in 0..6u64 {
        let mut rng = StdRng::seed_from_u64(500 + seed);
        let yaw = rng.random_range(-3.0..3.0);
        let (edge, start) = box_on_table(&mut rng, yaw);
        let about_edge = |alpha: f64| about_line(&edge, alpha);
        // Over onto the next face (half a second, smooth), then 2 s of landing.
        let over = |s: f64| about_edge(FRAC_PI_2 * smoothstep(s / 0.5));
        let d = precise_demo(&start, over, 0.5, 2.0, seed);
        let c = classify(&d, &Config::default()).unwrap();
        let landing: u64 = c
            .labels
            .iter()
            .filter(|r| r.label == Label::Landing)
            .map(|r| r.frames)
            .sum();
        eprintln!("seed {seed}: {:?} {:?}, landing {landing}", c.kind, c.votes);
        assert_eq!(c.kind, Kind::Topple, "seed {seed}: {:?}", c.votes);
        assert!(
            landing > c.votes.topple,
            "seed {seed}: {landing} landing frames"
        );
        let e = c.edges().next().expect("an edge");
        assert!(line_angle_deg(&e.line.direction, &edge.direction) < 1.0);
        assert!(e.line.distance_to(&edge.point) < 2e-3);

        // Tipped by 25° and back onto the same face: the wander after it is general.
        let tip = |s: f64| about_edge(0.44 * (PI * (s / 0.5).min(1.0)).sin().max(0.0));
        let d = precise_demo(&start, tip, 0.5, 2.0, seed);
        let c = classify(&d, &Config::default()).unwrap();
        eprintln!("seed {seed}, tipped back: {:?} {:?}", c.kind, c.votes);
        assert!(c.labels.iter().all(|r| r.label != Label::Landing));
        assert_eq!(c.kind, Kind::General, "seed {seed}: {:?}", c.votes);
    }
}

/// A random box resting on a level table, turned by `yaw` \[rad\]: the edge the generator
/// topples it about (side 0, in the tag frame) and the tag's pose in the world.
fn box_on_table(rng: &mut StdRng, yaw: f64) -> (objmodel::geometry::Line, Isometry3<f64>) {
    let b = SynthBox::random(rng);
    let edge = synth::topple(&b, &ToppleParams::default(), &SynthNoise::CLEAN, 30.0, 0)
        .truth
        .edge
        .unwrap();
    let start = Isometry3::from_parts(
        Translation3::new(0.1, -0.1, b.half.z),
        UnitQuaternion::from_scaled_axis(Vector3::z() * yaw),
    ) * b.box_from_tag;
    (edge, start)
}

/// The rotation by `alpha` \[rad\] about `line`: `x -> R (x - p) + p`.
fn about_line(line: &objmodel::geometry::Line, alpha: f64) -> Isometry3<f64> {
    let r = UnitQuaternion::from_scaled_axis(line.direction * alpha);
    Isometry3::from_parts(Translation3::from(line.point - r * line.point), r)
}

/// A φ is reported only when a fit determines it better than its bounds (0, π/2) do. A box
/// turned over its edge at a steady, smooth pace (`gen_tum.py`'s motion: a smoothstep from 0 to
/// 90°, no free fall anywhere) gives a "fall" fit whose φ is anything: it must not be reported.
#[test]
fn an_undetermined_phi_is_not_reported() {
    use objmodel::dynamics::PHI_PRIOR_SIGMA_RAD;
    let (edge, start) = box_on_table(&mut StdRng::seed_from_u64(77), 0.0);
    let about_edge = |alpha: f64| about_line(&edge, alpha);
    let over = |s: f64| about_edge(FRAC_PI_2 * smoothstep(s / 20.0));
    let d = precise_demo(&start, over, 20.0, 0.0, 7);
    let o = observe(&d);
    assert_eq!(o.classification.kind, Kind::Topple);
    let dy = o.dynamics;
    // A window the uniform-motion test lets through gets a fit whose φ is no better than its
    // bounds; mostly there is no fit at all.
    if let Some(fall) = dy[0].fall {
        eprintln!("fall fit: phi {:.3} ± {:.3} rad", fall.phi, fall.phi_sigma);
        assert!(fall.phi_sigma > PHI_PRIOR_SIGMA_RAD);
    }
    assert_eq!(dy[0].phi, None);
}

/// An edge's point is never known better than the contact's own wander (the model tolerance,
/// `edge_tolerance_m`): a rounded edge or a soft contact moves the pivot along one trajectory
/// per demonstration, which does not average down over its frames. On exact poses and at real
/// noise, every topple's edge point has σ ≥ 0.3 mm along one axis normal to the line; along the
/// other, the rests may measure it (`tests/rests_measure_edges.rs`), to the
/// contact's wander in each rest: `2 tol²` over `|g|² ≤ 4`, which with the pivot's `tol²`
/// leaves at least `tol² / 3`.
#[test]
fn edge_points_are_never_known_better_than_the_contact_tolerance() {
    let tol = Config::default().robust.edge_tolerance_m;
    let mut n = 0;
    for noise in [SynthNoise::CLEAN, SynthNoise::REAL] {
        for d in demos(0, 10, &noise) {
            let c = classify(&d.demo, &Config::default()).unwrap();
            for e in c.edges() {
                let u = e.line.direction;
                let a = u.cross(&Vector3::x());
                let a = if a.norm() < 0.5 {
                    u.cross(&Vector3::y())
                } else {
                    a
                }
                .normalize();
                let b = u.cross(&a);
                let m = nalgebra::Matrix2::new(
                    a.dot(&(e.point_cov * a)),
                    a.dot(&(e.point_cov * b)),
                    b.dot(&(e.point_cov * a)),
                    b.dot(&(e.point_cov * b)),
                );
                let ev = m.symmetric_eigenvalues();
                let (small, large) = (ev.min(), ev.max());
                let name = &d.demo.name;
                assert!(
                    large >= tol * tol * (1.0 - 1e-9),
                    "{name}: σ {:e}",
                    large.sqrt()
                );
                assert!(
                    small >= tol * tol / 3.0 * (1.0 - 1e-9),
                    "{name}: σ {:e}",
                    small.sqrt()
                );
                n += 1;
            }
        }
    }
    assert!(n >= 15, "{n} edges");
}
