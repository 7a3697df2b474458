//! Positions in millimetres: declared by a CSV header, given by the user, or neither. Declared
//! or given, a millimetre demonstration teaches what its metre copy does; neither, it teaches
//! nothing wrong (and says which unit to give) where its noise or features are implausible in
//! metres.

use objmodel::classify::Kind;
use objmodel::format::{write_tum, LengthUnit};
use objmodel::learn::{Config, Learner, Source};
use objmodel::observation::Observation;
use objmodel::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
use objmodel::trajectory::StampedPose;
use objmodel::tree::Tree;
use objmodel::Demonstration;
use rand::{rngs::StdRng, SeedableRng};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A motion-capture tracker: 0.2 mm and 0.1° per axis, no drops or flips.
const MOCAP: SynthNoise = SynthNoise {
    sigma_position: 2e-4,
    sigma_rotation: 0.001_745_329_251_994_329_5,
    drop: 0.0,
    sign_flip: 0.0,
    tag_flip: 0.0,
};

/// A topple, an instrumented topple and a slide of a random box.
fn demos(seed: u64, noise: &SynthNoise) -> Vec<SynthDemo> {
    let b = SynthBox::random(&mut StdRng::seed_from_u64(seed));
    let p = ToppleParams {
        side: (seed % 4) as usize,
        ..Default::default()
    };
    vec![
        synth::topple(&b, &p, noise, 30.0, seed),
        synth::instrumented_topple(&b, (seed % 4) as usize, 0.2, noise, 30.0, seed + 1),
        synth::slide(&b, noise, 30.0, seed + 2),
    ]
}

fn scaled(poses: &[StampedPose], k: f64) -> Vec<StampedPose> {
    poses
        .iter()
        .map(|p| {
            let mut p = *p;
            p.pose.translation.vector *= k;
            p
        })
        .collect()
}

fn in_mm(d: &Demonstration) -> Demonstration {
    Demonstration {
        name: d.name.clone(),
        object: scaled(&d.object, 1e3),
        palm: d.palm.as_ref().map(|p| scaled(p, 1e3)),
    }
}

/// A CSV file of `poses` with positions in millimetres, declared, and stamps in seconds,
/// declared (stamps through milliseconds and back may round differently by a bit, which may
/// move a frame across a test's boundary: `format`'s unit tests check the time units).
fn write_mm_csv(path: &Path, poses: &[StampedPose]) {
    let mut s = String::from(
        "Time (Seconds),X (Millimeters),Y (Millimeters),Z (Millimeters),qx,qy,qz,qw\n",
    );
    for p in poses {
        let (v, q) = (p.pose.translation.vector, p.pose.rotation.coords);
        writeln!(
            s,
            "{},{},{},{},{},{},{},{}",
            p.t,
            v.x * 1e3,
            v.y * 1e3,
            v.z * 1e3,
            q.x,
            q.y,
            q.z,
            q.w
        )
        .unwrap();
    }
    std::fs::write(path, s).unwrap();
}

fn learner(unit: Option<LengthUnit>) -> Learner {
    Learner::new(Config {
        length_unit: unit,
        ..Config::default()
    })
}

/// `a` and `b` teach the same: kind, edges, faces, pendulums, to `tol` (metres, radians; a
/// covariance to `tol` relative to 1 mm).
fn same(a: &Observation, b: &Observation, tol: f64) {
    let (ca, cb) = (&a.classification, &b.classification);
    assert_eq!(
        ca.kind, cb.kind,
        "{}: {:?}\n{:?}",
        ca.name, ca.warnings, cb.warnings
    );
    assert_eq!(ca.withheld, None, "{}", ca.name);
    assert_eq!(cb.withheld, None, "{}", cb.name);
    assert_eq!(ca.topples.len(), cb.topples.len(), "{}", ca.name);
    for (x, y) in ca.edges().zip(cb.edges()) {
        assert!((x.line.point - y.line.point).norm() < tol, "{x:?}\n{y:?}");
        assert!(x.line.direction.angle(&y.line.direction) < tol);
        assert!(
            (x.point_cov - y.point_cov).norm() < tol * 1e-3,
            "{x:?}\n{y:?}"
        );
    }
    let (fa, fb) = (ca.faces(), cb.faces());
    assert_eq!(fa.len(), fb.len(), "{}", ca.name);
    for (x, y) in fa.iter().zip(&fb) {
        assert!(x.normal.angle(&y.normal) < tol, "{}: {x:?}\n{y:?}", ca.name);
        match (x.offset, y.offset) {
            (Some(p), Some(q)) => assert!((p - q).abs() < tol, "{p} {q}"),
            (p, q) => assert_eq!(p, q),
        }
    }
    assert_eq!(a.dynamics.len(), b.dynamics.len());
    for (x, y) in a.dynamics.iter().zip(&b.dynamics) {
        match (x.phi, y.phi) {
            (Some(p), Some(q)) => assert!((p - q).abs() < tol, "{p} {q}"),
            (p, q) => assert_eq!(p, q),
        }
    }
}

fn files(dir: &Path, d: &Demonstration, ext: &str) -> (PathBuf, Option<PathBuf>) {
    let o = dir.join(format!("{}.{ext}", d.name));
    let p = d
        .palm
        .as_ref()
        .map(|_| dir.join(format!("{}.palm.{ext}", d.name)));
    (o, p)
}

/// Millimetres declared by a CSV header, given for TUM files, or given for
/// poses in memory: the same observation as the metres, edge for edge.
#[test]
fn millimetres_declared_or_given_teach_what_metres_do() {
    let dir = tempfile::tempdir().unwrap();
    let metres = learner(None);
    let mm = learner(Some(LengthUnit::Millimetres));
    let mut checked = 0;
    for seed in 0..4 {
        for noise in [SynthNoise::REAL, MOCAP] {
            for sd in demos(seed, &noise) {
                let d = &sd.demo;
                let in_metres = metres.observe(&Source::Memory(d)).unwrap();
                let d_mm = in_mm(d);
                // Poses in memory, the unit given.
                let given = mm.observe(&Source::Memory(&d_mm)).unwrap();
                assert_eq!(
                    given.classification.length_unit,
                    Some(LengthUnit::Millimetres)
                );
                same(&in_metres, &given, 1e-9);
                // TUM files (no unit of their own), the unit given: as the metre files (the
                // same rounding of the quaternions).
                let (o, p) = files(dir.path(), &d_mm, "tum");
                let (om, pm) = files(dir.path(), &d_mm, "m.tum");
                write_tum(&o, &d_mm.object, "mm").unwrap();
                write_tum(&om, &d.object, "m").unwrap();
                if let (Some(p), Some(pm)) = (&p, &pm) {
                    write_tum(p, d_mm.palm.as_ref().unwrap(), "mm").unwrap();
                    write_tum(pm, d.palm.as_ref().unwrap(), "m").unwrap();
                }
                let tum = mm
                    .observe(&Source::Files {
                        object: &o,
                        palm: p.as_deref(),
                    })
                    .unwrap();
                let tum_metres = metres
                    .observe(&Source::Files {
                        object: &om,
                        palm: pm.as_deref(),
                    })
                    .unwrap();
                // (The metre files round positions to 1 nm, the millimetre files to 1 pm.)
                same(&tum_metres, &tum, 1e-7);
                // CSV files that declare millimetres and milliseconds, no unit given.
                let (o, p) = files(dir.path(), &d_mm, "csv");
                write_mm_csv(&o, &d.object);
                if let (Some(p), Some(palm)) = (&p, &d.palm) {
                    write_mm_csv(p, palm);
                }
                let csv = metres
                    .observe(&Source::Files {
                        object: &o,
                        palm: p.as_deref(),
                    })
                    .unwrap();
                assert_eq!(
                    csv.classification.length_unit,
                    Some(LengthUnit::Millimetres)
                );
                same(&in_metres, &csv, 1e-7);
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 24);
}

/// Millimetres read as metres: at any real tracker's noise the demonstration is withheld, with
/// the unit to give; learnt together, the tree holds nothing.
#[test]
fn millimetres_read_as_metres_teach_nothing() {
    let metres = learner(None);
    let mut tree = Tree::default();
    let mut all = Vec::new();
    for seed in 0..4 {
        for noise in [SynthNoise::REAL, MOCAP] {
            all.extend(demos(seed, &noise).into_iter().map(|sd| in_mm(&sd.demo)));
        }
    }
    let sources: Vec<Source> = all.iter().map(Source::Memory).collect();
    let reports = metres.learn(&mut tree, &sources).unwrap();
    assert_eq!(reports.len(), 24);
    for r in &reports {
        let c = &r.classification;
        let why = c
            .withheld
            .as_deref()
            .unwrap_or_else(|| panic!("{}: {:?}", c.name, c.warnings));
        assert!(why.contains("do not look like metres"), "{why}");
        assert!(why.contains("--length-unit mm"), "{why}");
        assert!(c.topples.is_empty() && c.faces().is_empty(), "{}", c.name);
    }
    assert!(tree.edges.is_empty(), "{:?}", tree.edges);
    assert!(tree.faces.is_empty(), "{:?}", tree.faces);
}

/// Exact millimetre poses read as metres have no noise to betray them: whatever they teach
/// must not depend on the unit (a face's normal), and no edge.
#[test]
fn exact_millimetres_read_as_metres_teach_no_edge() {
    let metres = learner(None);
    for seed in 0..4 {
        for sd in demos(seed, &SynthNoise::CLEAN) {
            let o = metres.observe(&Source::Memory(&in_mm(&sd.demo))).unwrap();
            let c = &o.classification;
            assert!(
                c.topples.is_empty(),
                "{}: {:?}",
                c.name,
                c.edges().collect::<Vec<_>>()
            );
            assert!(c.rolls.iter().all(|r| !r.taught));
            for f in c.faces() {
                assert!(f.offset.is_none(), "{}: {f:?}", c.name);
            }
            // A slide teaches its face's normal, whatever the unit; or, where its smooth
            // exact frames read as metres are correlated beyond what the noise's windows
            // resolve (`Correlation::beyond_resolution`), nothing, and says why.
            if c.kind == Kind::Slide && c.faces().is_empty() {
                let why = c.withheld.as_deref().unwrap_or_default();
                assert!(
                    why.contains("beyond what ten-frame windows resolve"),
                    "{}: {why}",
                    c.name
                );
            } else if c.kind == Kind::Slide {
                let (n, _) = sd.truth.face.unwrap();
                let learnt = c
                    .faces()
                    .into_iter()
                    .map(|f| f.normal.angle(&n))
                    .fold(9.0, f64::min);
                assert!(learnt < 0.01, "{}: {learnt}", c.name);
            }
        }
    }
}
