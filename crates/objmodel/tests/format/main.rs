//! Tests of the pose file formats, one file per subject: lines and their errors (`lines.rs`),
//! files (`files.rs`: round trips, streams, palm files, atomic writes), numbers
//! (`numbers.rs`), other tools' exports (`exports.rs`). The helpers they share are here.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use objmodel::format::{self, Format, PoseReader, QUAT_NORM_TOLERANCE};
use objmodel::{Error, StampedPose};
use std::path::{Path, PathBuf};

mod exports;
mod files;
mod lines;
mod numbers;

/// A fresh, empty directory (`tempfile`), removed when dropped (a failed test's too).
fn tmpdir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("objmodel-fmt-{tag}-"))
        .tempdir()
        .unwrap()
}

fn write(dir: &Path, name: &str, content: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// Run `f` on a file `name` holding `content`, in a fresh directory.
fn with_file<T>(name: &str, content: &str, f: impl FnOnce(&Path) -> T) -> T {
    let dir = tmpdir("f");
    f(&write(dir.path(), name, content))
}

/// Read `content` as file `name` and return the error's text, asserting it is at `line`.
fn parse_error(name: &str, content: &str, line: usize) -> String {
    with_file(name, content, |p| {
        let e = format::read_trajectory(p).expect_err(content);
        let (text, prefix) = (e.to_string(), format!("{}:{line}: ", p.display()));
        assert!(matches!(e, Error::Parse { .. }), "{text}");
        assert!(text.starts_with(&prefix), "expected {prefix:?} in {text:?}");
        text
    })
}

/// Read `content` as file `name` and return the whole-file error's text.
fn file_error(name: &str, content: &str) -> String {
    with_file(name, content, |p| {
        let e = format::read_trajectory(p).expect_err(content);
        assert!(matches!(e, Error::File { .. }), "{e}");
        e.to_string()
    })
}

fn read_str(name: &str, content: &str) -> Vec<StampedPose> {
    with_file(name, content, |p| {
        format::read_trajectory(p).unwrap_or_else(|e| panic!("{e}"))
    })
}

fn xyzw(p: &StampedPose) -> [f64; 4] {
    let q = p.pose.rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}

fn xyz(p: &StampedPose) -> [f64; 3] {
    let t = p.pose.translation.vector;
    [t.x, t.y, t.z]
}

const LINE: &str = "0.5 1 2 3 0 0 0 1";

/// Deterministic test randomness (`rand`'s `StdRng`, seeded).
struct Rng(rand::rngs::StdRng);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(<rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(
            seed,
        ))
    }
    fn below(&mut self, n: u64) -> u64 {
        rand::Rng::random_range(&mut self.0, 0..n)
    }
    fn f64(&mut self) -> f64 {
        rand::Rng::random::<f64>(&mut self.0)
    }
    fn digits(&mut self, n: u64) -> String {
        (0..n)
            .map(|_| char::from(b'0' + self.below(10) as u8))
            .collect()
    }
}

fn random_pose(rng: &mut Rng, t: f64) -> StampedPose {
    let axis = Vector3::new(rng.f64() - 0.5, rng.f64() - 0.5, rng.f64() - 0.5);
    let rot = UnitQuaternion::from_scaled_axis(axis * 6.0);
    let tr = Translation3::new(rng.f64() * 4.0 - 2.0, rng.f64() - 0.5, rng.f64() * 100.0);
    StampedPose::new(t, Isometry3::from_parts(tr, rot))
}
