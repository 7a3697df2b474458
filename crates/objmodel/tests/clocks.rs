//! Two clocks: the object and the palm tracked by different sensors, at different rates, with
//! an offset, or stamped in other units than seconds. Files and memory alike.

use objmodel::classify::Kind;
use objmodel::format::write_tum;
use objmodel::learn::{Config, Learner, Source};
use objmodel::observation::Observation;
use objmodel::synth::{self, SynthBox, SynthNoise};
use objmodel::trajectory::StampedPose;
use objmodel::Demonstration;
use rand::{rngs::StdRng, SeedableRng};
use std::path::{Path, PathBuf};

fn instrumented(seed: u64) -> Demonstration {
    let b = SynthBox::random(&mut StdRng::seed_from_u64(seed + 100));
    synth::instrumented_topple(&b, (seed % 4) as usize, 0.2, &SynthNoise::REAL, 30.0, seed).demo
}

fn learner(offset: f64) -> Learner {
    let mut c = Config::default();
    c.clocks.palm_time_offset_s = offset;
    Learner::new(c)
}

fn shift(poses: &[StampedPose], dt: f64) -> Vec<StampedPose> {
    poses
        .iter()
        .map(|p| StampedPose::new(p.t + dt, p.pose))
        .collect()
}

fn with_palm(d: &Demonstration, palm: Vec<StampedPose>) -> Demonstration {
    Demonstration {
        palm: Some(palm),
        ..d.clone()
    }
}

fn write(dir: &Path, d: &Demonstration) -> (PathBuf, PathBuf) {
    let o = dir.join(format!("{}.tum", d.name));
    let p = dir.join(format!("{}.palm.tum", d.name));
    write_tum(&o, &d.object, "o").unwrap();
    write_tum(&p, d.palm.as_ref().unwrap(), "p").unwrap();
    (o, p)
}

/// Observe `d` from memory and from its files; both results.
fn observe_both(l: &Learner, d: &Demonstration, dir: &Path) -> [objmodel::Result<Observation>; 2] {
    let (o, p) = write(dir, d);
    [
        l.observe(&Source::Memory(d)),
        l.observe(&Source::instrumented(&o, &p)),
    ]
}

fn edges_close(a: &Observation, b: &Observation, tol_m: f64, tol_rad: f64) {
    let (ca, cb) = (&a.classification, &b.classification);
    assert_eq!(ca.kind, cb.kind, "{:?}\n{:?}", ca.warnings, cb.warnings);
    assert_eq!(ca.topples.len(), cb.topples.len());
    for (x, y) in ca.edges().zip(cb.edges()) {
        assert!((x.line.point - y.line.point).norm() < tol_m, "{x:?}\n{y:?}");
        assert!(x.line.direction.angle(&y.line.direction) < tol_rad);
    }
    for (x, y) in a.dynamics.iter().zip(&b.dynamics) {
        let (p, q) = (x.phi.unwrap(), y.phi.unwrap());
        assert!(
            (p - q).abs() < tol_rad,
            "phi {} vs {}",
            p.to_degrees(),
            q.to_degrees()
        );
    }
}

/// A palm clock 1000 s off: a clear error that names the cause and the option, not every
/// object frame "rejected as a tag flip" and a general demonstration.
#[test]
fn a_palm_clock_far_off_is_an_error_not_tag_flips() {
    let dir = tempfile::tempdir().unwrap();
    let d = instrumented(1);
    let far = with_palm(&d, shift(d.palm.as_ref().unwrap(), 1000.0));
    for r in observe_both(&learner(0.0), &far, dir.path()) {
        let e = r.unwrap_err().to_string();
        assert!(e.contains("do not overlap"), "{e}");
        assert!(e.contains("--palm-time-offset"), "{e}");
        assert!(e.contains("-1000.0"), "the offset is suggested: {e}");
    }
    // Corrected, it is the demonstration without offset.
    let truth = learner(0.0).observe(&Source::Memory(&d)).unwrap();
    for r in observe_both(&learner(-1000.0), &far, dir.path()) {
        edges_close(&r.unwrap(), &truth, 1e-6, 1e-6);
    }
}

/// A 0.5 s offset: without correction a warning of the partial overlap, the frames outside
/// the palm's range dropped and not counted as tag flips; corrected by the palm's offset, the
/// edges and φ of the demonstration without offset.
#[test]
fn a_half_second_offset_is_warned_about_and_corrected_by_the_palm_offset() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 2..5 {
        let d = instrumented(seed);
        let truth = learner(0.0).observe(&Source::Memory(&d)).unwrap();
        assert_eq!(truth.classification.kind, Kind::Topple);
        let late = with_palm(&d, shift(d.palm.as_ref().unwrap(), 0.5));
        let palm_start = late.palm.as_ref().unwrap()[0].t;
        // Object frames before the palm's first pose (less any rejected as tag flips anyway).
        let before = d.object.iter().filter(|p| p.t < palm_start).count();
        for r in observe_both(&learner(0.0), &late, dir.path()) {
            let c = r.unwrap().classification;
            assert!(
                c.warnings.iter().any(|w| w.contains("overlap only in part")
                    && (before.saturating_sub(2)..=before)
                        .any(|n| w.contains(&format!(": {n} of")))
                    && w.contains("not tag flips")),
                "{before}: {:?}",
                c.warnings
            );
            assert!(
                c.outliers <= truth.classification.outliers,
                "{}",
                c.outliers
            );
        }
        for r in observe_both(&learner(-0.5), &late, dir.path()) {
            edges_close(&r.unwrap(), &truth, 1e-6, 1e-6);
        }
    }
}

/// A palm tracked at 10 Hz (both with tracking noise) beside a 30 Hz object, tilted slowly
/// (a long rest of the object on the palm): interpolated at the object's stamps, the topple
/// stays one topple with its edge, and no slide or other motion is invented during the rest.
#[test]
fn a_slow_palm_does_not_invent_a_slide() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 5..9 {
        let b = SynthBox::random(&mut StdRng::seed_from_u64(seed + 100));
        let d =
            synth::instrumented_topple(&b, seed as usize % 4, 0.04, &SynthNoise::REAL, 30.0, seed)
                .demo;
        let truth = learner(0.0).observe(&Source::Memory(&d)).unwrap();
        let slow: Vec<StampedPose> = d
            .palm
            .as_ref()
            .unwrap()
            .iter()
            .step_by(3)
            .copied()
            .collect();
        let slow = with_palm(&d, slow);
        for r in observe_both(&learner(0.0), &slow, dir.path()) {
            let o = r.unwrap();
            let c = &o.classification;
            let kinds: Vec<Kind> = c.segments.iter().map(|s| s.kind).collect();
            assert_eq!(kinds, [Kind::Topple], "seed {seed}: {:?}", c.segments);
            edges_close(&o, &truth, 5e-3, 3f64.to_radians());
        }
    }
}

/// Stamps in nanoseconds or milliseconds (files and memory): recognised, converted with a
/// warning, and classified as in seconds.
#[test]
fn nanoseconds_and_milliseconds_classify_as_seconds() {
    let dir = tempfile::tempdir().unwrap();
    let d = instrumented(9);
    let truth = learner(0.0).observe(&Source::Memory(&d)).unwrap();
    for (unit, name) in [(1e9, "nanoseconds"), (1e3, "milliseconds")] {
        let scale = |v: &[StampedPose]| -> Vec<StampedPose> {
            v.iter()
                .map(|p| StampedPose::new((p.t * unit).round(), p.pose))
                .collect()
        };
        let e = Demonstration {
            name: format!("u{unit}"),
            object: scale(&d.object),
            palm: Some(scale(d.palm.as_ref().unwrap())),
        };
        for r in observe_both(&learner(0.0), &e, dir.path()) {
            let o = r.unwrap();
            let w = &o.classification.warnings;
            assert!(
                w.iter().any(|w| w.contains("object") && w.contains(name)),
                "{w:?}"
            );
            assert!(
                w.iter().any(|w| w.contains("palm") && w.contains(name)),
                "{w:?}"
            );
            edges_close(&o, &truth, 1e-4, 1e-3);
        }
        // Relative stamps (from zero) are recognised by their spacing.
        let t0 = e.object[0].t;
        let rel = Demonstration {
            object: shift(&e.object, -t0),
            palm: Some(shift(e.palm.as_ref().unwrap(), -t0)),
            ..e.clone()
        };
        let o = learner(0.0).observe(&Source::Memory(&rel)).unwrap();
        assert!(o.classification.warnings.iter().any(|w| w.contains(name)));
        assert_eq!(o.classification.kind, Kind::Topple);
    }
}

/// What recognising the stamps' unit costs the fast path (a TUM file without palm): reading
/// the first stamps again, against classifying the whole file (`cargo test --release -p
/// objmodel --test clocks -- --ignored --nocapture`).
#[test]
#[ignore]
fn measure_the_unit_check_against_the_benchmark_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = synth::topple(
        &SynthBox::random(&mut StdRng::seed_from_u64(3)),
        &synth::ToppleParams::default(),
        &SynthNoise::REAL,
        30.0,
        3,
    )
    .demo;
    // 10^6 poses: the demonstration repeated, on increasing stamps.
    let n = 1_000_000;
    let span = d.object.last().unwrap().t - d.object[0].t + 1.0 / 30.0;
    let poses: Vec<StampedPose> = (0..n)
        .map(|k| {
            let (rep, i) = (k / d.object.len(), k % d.object.len());
            StampedPose::new(d.object[i].t + rep as f64 * span, d.object[i].pose)
        })
        .collect();
    let path = dir.path().join("big.tum");
    write_tum(&path, &poses, "big").unwrap();
    let best = |reps: usize, f: &dyn Fn()| {
        (0..reps)
            .map(|_| {
                let t = std::time::Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let l = learner(0.0);
    let whole = best(5, &|| {
        l.observe(&Source::file(&path)).unwrap();
    });
    let peek = best(50, &|| {
        objmodel::format::read_first(&path, objmodel::format::TIME_UNIT_STAMPS).unwrap();
    });
    eprintln!(
        "{n} poses: learn's observe {:.1} ms, the unit check {:.3} ms ({:.3}%)",
        whole * 1e3,
        peek * 1e3,
        100.0 * peek / whole
    );
}
