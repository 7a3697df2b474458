//! Tracker glitches: a misread tag, a swapped marker put a pose centimetres and degrees off for
//! one to a few frames, and then the tracker is right again. Runs of up to
//! [`objmodel::clean::MAX_RUN`] such frames, in the object's stream and in the palm's, must be
//! rejected, and teach nothing that is not on the box. (Before the cleaner tested positions and
//! runs longer than two, the standard data set's `real` and `mocap` demonstrations with such
//! glitches, about one every 5 s, taught 3 edges and 3 faces off the box among its
//! instrumented topples.)

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use objmodel::clean::MAX_RUN;
use objmodel::learn::{Config, Learner, Source};
use objmodel::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
use objmodel::trajectory::StampedPose;
use objmodel::tree::Tree;
use rand::{rngs::StdRng, Rng, SeedableRng};

/// A run of wrong poses put into a stream: its frames' times, and whether the
/// cleaner can see it while the object rests: its position 15 mm or its orientation 7.5° off
/// (the test's least significant residual is 6.8-6.9 σ, and σ is estimated from each stream's
/// first frames, glitches and motion among them: 1.1-1.8 mm and 0.5-0.9° here for 1 mm and
/// 0.5°).
struct Glitch {
    /// The times of its frames \[s\].
    times: Vec<f64>,
    visible: bool,
}

/// Put runs of 1 to [`MAX_RUN`] wrong poses (5-30 mm and 2-10° off, one error per run) into
/// `poses`, one run per `every_s` seconds on average, apart from each other and from the ends.
fn glitch(poses: &mut [StampedPose], every_s: f64, rng: &mut StdRng) -> Vec<Glitch> {
    let duration = poses.last().unwrap().t - poses[0].t;
    let runs = (duration / every_s).round() as usize;
    let mut wrong = vec![false; poses.len()];
    let mut glitches = Vec::new();
    for _ in 0..runs {
        let n = rng.random_range(1..=MAX_RUN);
        let start = rng.random_range(3..poses.len() - 3 - n);
        // Runs apart from each other, so that each is a run of its own length.
        if wrong[start - 2..start + n + 2].iter().any(|&w| w) {
            continue;
        }
        let unit =
            |rng: &mut StdRng| Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
        let (shift, turn) = (
            rng.random_range(5e-3..30e-3),
            rng.random_range(2f64..10.0).to_radians(),
        );
        let offset = Isometry3::from_parts(
            Translation3::from(unit(rng) * shift),
            UnitQuaternion::from_scaled_axis(unit(rng) * turn),
        );
        for (p, w) in poses[start..start + n].iter_mut().zip(&mut wrong[start..]) {
            // The error in the tracker's frame: a wrong position, and a wrong orientation
            // about the tag's own origin.
            p.pose = Isometry3::from_parts(
                offset.translation * p.pose.translation,
                offset.rotation * p.pose.rotation,
            );
            *w = true;
        }
        glitches.push(Glitch {
            times: poses[start..start + n].iter().map(|p| p.t).collect(),
            visible: shift > 15e-3 || turn > 7.5f64.to_radians(),
        });
    }
    glitches
}

/// The demonstrations of one box: topples over its four sides, two instrumented topples and a
/// slide, at real tracking noise (1 mm, 0.5°), 30 Hz, each with glitches in every stream; and
/// the object's glitches.
fn glitched_demos(b: &SynthBox, seed: u64, rng: &mut StdRng) -> Vec<(SynthDemo, Vec<Glitch>)> {
    let noise = SynthNoise::REAL;
    let mut demos: Vec<SynthDemo> = (0..4)
        .map(|side| {
            let p = ToppleParams {
                side,
                ..Default::default()
            };
            synth::topple(b, &p, &noise, 30.0, seed * 10 + side as u64)
        })
        .collect();
    for side in [0, 2] {
        demos.push(synth::instrumented_topple(
            b,
            side,
            0.2,
            &noise,
            30.0,
            seed * 10 + 5 + side as u64,
        ));
    }
    demos.push(synth::slide(b, &noise, 30.0, seed * 10 + 9));
    demos
        .into_iter()
        .map(|mut d| {
            // The palm's glitches are not counted: its frames are interpolated at the object's
            // stamps, so a palm frame rejected is bridged, not an object frame lost.
            let g = glitch(&mut d.demo.object, 1.0, rng);
            if let Some(palm) = d.demo.palm.as_mut() {
                glitch(palm, 1.0, rng);
            }
            (d, g)
        })
        .collect()
}

#[test]
fn glitches_are_rejected_and_teach_nothing_off_the_box() {
    let learner = Learner::new(Config::default());
    let mut rng = StdRng::seed_from_u64(2026);
    let (mut edges, mut faces, mut seen, mut rejected) = (0, 0, 0, 0);
    for seed in 0..4u64 {
        let b = SynthBox::random(&mut rng);
        let demos = glitched_demos(&b, seed, &mut rng);
        // Every visible run while the object rests (both streams still: the first and the last
        // 0.8 s of each demonstration) is rejected, every frame of it. (In motion, a run is
        // rejected only when it is farther off than the motion between its neighbours.)
        for (d, glitches) in &demos {
            let c = learner.classify(&Source::Memory(&d.demo)).unwrap();
            let t0 = d.demo.object[0].t;
            let t_end = d.demo.object.last().unwrap().t;
            let at_rest = |t: f64| t - t0 < 0.8 || t_end - t < 0.8;
            let rejected_at = |t: f64| {
                c.labels.iter().any(|r| {
                    r.label == objmodel::classify::Label::Outlier
                        && r.t_start - 1e-9 <= t
                        && t <= r.t_end + 1e-9
                })
            };
            for g in glitches {
                let after = g.times.last().unwrap() + 1.0 / 30.0;
                if !(g.visible && g.times.iter().all(|&t| at_rest(t)) && at_rest(after)) {
                    continue;
                }
                let out = g.times.iter().filter(|&&t| rejected_at(t)).count();
                assert_eq!(out, g.times.len(), "{}: a run at {:?} s", c.name, g.times);
                seen += g.times.len();
                rejected += out;
            }
        }
        let sources: Vec<Source> = demos.iter().map(|(d, _)| Source::Memory(&d.demo)).collect();
        let mut tree = Tree::default();
        learner.learn(&mut tree, &sources).unwrap();
        let off = b.features_off(&tree);
        assert!(off.is_empty(), "box {seed}: {off:?}");
        edges += tree.edges.len();
        faces += tree.faces.len();
    }
    assert!(seen >= 40, "only {seen} wrong frames in rests");
    assert_eq!(rejected, seen);
    assert!(edges >= 12 && faces >= 12, "{edges} edges, {faces} faces");
}
