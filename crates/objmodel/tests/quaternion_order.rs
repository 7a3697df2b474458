//! TUM files written with the quaternion w first (as MuJoCo, transforms3d or pyquaternion
//! order it): read in the order given (`Config::quaternion_order`), they teach what the same
//! poses written x y z w teach; read as the format says, they teach another object's features.
//! A CSV header names its columns, which decide.

mod common;

use objmodel::format::{write_tum, QuaternionOrder};
use objmodel::learn::{Config, Learner, Source};
use objmodel::synth::{self, SynthBox, SynthNoise, ToppleParams};
use objmodel::trajectory::StampedPose;
use objmodel::tree::Tree;
use rand::{rngs::StdRng, SeedableRng};
use std::path::{Path, PathBuf};

/// `poses` as a TUM-shaped file with the quaternion written `qw qx qy qz`.
fn write_w_first(path: &Path, poses: &[StampedPose]) {
    let mut s = String::from("# timestamp tx ty tz qw qx qy qz\n");
    for p in poses {
        let (t, q) = (p.pose.translation.vector, p.pose.rotation.quaternion());
        s += &format!(
            "{:.6} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9}\n",
            p.t, t.x, t.y, t.z, q.w, q.i, q.j, q.k
        );
    }
    std::fs::write(path, s).unwrap();
}

/// The object's file (and the palm's beside it) in `dir`, named `demo`, written x y z w or w
/// first.
fn files(dir: &Path, d: &objmodel::Demonstration, w_first: bool) -> (PathBuf, Option<PathBuf>) {
    let write = |path: &Path, poses: &[StampedPose]| {
        if w_first {
            write_w_first(path, poses)
        } else {
            write_tum(path, poses, "demo").unwrap()
        }
    };
    let object = dir.join("demo.tum");
    write(&object, &d.object);
    let palm = d.palm.as_ref().map(|p| {
        let path = dir.join("demo.palm.tum");
        write(&path, p);
        path
    });
    (object, palm)
}

#[test]
fn w_first_files_read_in_their_order_teach_what_x_first_files_do() {
    let the_box = SynthBox::random(&mut StdRng::seed_from_u64(7));
    let p = ToppleParams {
        side: 1,
        ..Default::default()
    };
    let demos = [
        synth::topple(&the_box, &p, &SynthNoise::REAL, 30.0, 3).demo,
        synth::instrumented_topple(&the_box, 2, 0.2, &SynthNoise::REAL, 30.0, 4).demo,
        synth::straight_slide(&the_box, &SynthNoise::REAL, 30.0, 5).demo,
        synth::slide(&the_box, &SynthNoise::REAL, 30.0, 6).demo,
    ];
    let (x_dir, w_dir) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let mut wrong_trees_off = 0;
    for d in &demos {
        let (xo, xp) = files(x_dir.path(), d, false);
        let (wo, wp) = files(w_dir.path(), d, true);
        let x_first = Learner::new(Config::default());
        let w_first = Learner::new(Config::default().with_quaternion_order(QuaternionOrder::Wxyz));
        let observe = |l: &Learner, object: &Path, palm: &Option<PathBuf>| {
            l.observe(&Source::Files {
                object,
                palm: palm.as_deref(),
            })
            .unwrap()
        };
        let truth = observe(&x_first, &xo, &xp);
        assert!(
            !truth.classification.faces().is_empty(),
            "{:?}",
            truth.classification
        );

        // The same numbers, moved: the same observation (to rounding: such files are read
        // on the converting path, not the fast one).
        let given = observe(&w_first, &wo, &wp);
        let (a, b) = (&given.classification, &truth.classification);
        assert_eq!(
            (a.kind, &a.labels, &a.warnings),
            (b.kind, &b.labels, &b.warnings)
        );
        common::assert_same_edges(a, b, 1e-9);
        let (fa, fb) = (a.faces(), b.faces());
        assert_eq!(fa.len(), fb.len());
        for (x, y) in fa.iter().zip(&fb) {
            assert!((x.normal - y.normal).norm() < 1e-9, "{x:?} {y:?}");
        }
        // Read as x y z w, the rotations are others: the topples and the turning slide fail
        // their models and teach nothing, but a slide that does not turn keeps one rotation,
        // the wrong one, and teaches a face that is not this box's.
        let misread = observe(&x_first, &wo, &wp);
        let mut tree = Tree::default();
        tree.add(&misread);
        let off = the_box.features_off(&tree);
        let mut right = Tree::default();
        right.add(&truth);
        assert!(
            the_box.features_off(&right).is_empty(),
            "{:?}",
            the_box.features_off(&right)
        );
        assert!(
            misread.classification.edges().count() == 0 || !off.is_empty(),
            "{:?}",
            misread.classification
        );
        wrong_trees_off += !off.is_empty() as usize;
    }
    // The hazard the option is for: a misread file teaches a feature off the box (the slide
    // that does not turn).
    assert_eq!(
        wrong_trees_off, 1,
        "misread files that taught a feature off the box"
    );
}

#[test]
fn a_csv_header_names_its_columns_whatever_order_is_given() {
    let b = SynthBox::random(&mut StdRng::seed_from_u64(8));
    let d = synth::topple(&b, &ToppleParams::default(), &SynthNoise::REAL, 30.0, 5).demo;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("demo.csv");
    let mut s = String::from("t,qw,qx,qy,qz,x,y,z\n");
    for p in &d.object {
        let (t, q) = (p.pose.translation.vector, p.pose.rotation.quaternion());
        s += &format!(
            "{},{},{},{},{},{},{},{}\n",
            p.t, q.w, q.i, q.j, q.k, t.x, t.y, t.z
        );
    }
    std::fs::write(&path, s).unwrap();
    let source = Source::file(&path);
    let plain = Learner::new(Config::default()).observe(&source).unwrap();
    let given = Learner::new(Config::default().with_quaternion_order(QuaternionOrder::Wxyz))
        .observe(&source)
        .unwrap();
    assert!(plain.classification.edges().count() > 0);
    let mut warned = given.classification.clone();
    let w = warned.warnings.remove(0);
    assert!(w.contains("names its columns"), "{w}");
    assert_eq!(warned, plain.classification);
}
