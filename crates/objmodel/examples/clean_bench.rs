//! Wall time of the parsing thread's work after parsing: the tag-flip cleaner and the
//! accumulated rotation, with what they emit stored in a hand-over chunk (single thread, poses
//! in memory; best of REPS runs).
//!
//! `cargo run --release --example clean_bench -p objmodel [FILE.tum] [REPS]`

use nalgebra::{UnitQuaternion, Vector3};
use objmodel::bench::{AnalyzerStages, RotatingCleaner};
use objmodel::classify::{Analyzer, Config};
use objmodel::trajectory::StampedPose;
use std::path::PathBuf;
use std::time::Instant;

/// A hand-over chunk as `learn` fills it: emptied every 8192 items.
struct Chunk<T> {
    items: Vec<T>,
    handed: usize,
}

impl<T> Chunk<T> {
    #[inline(always)]
    fn keep(&mut self, item: T) {
        self.items.push(item);
        if self.items.len() >= 8192 {
            self.handed += std::hint::black_box(&self.items).len();
            self.items.clear();
        }
    }
}

/// Best wall time \[s\] of `reps` runs of `run`, which pushes every pose through a fresh stage
/// and keeps what it emits in the chunk.
fn best<T>(reps: usize, mut run: impl FnMut(&mut Chunk<T>)) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        let mut chunk = Chunk {
            items: Vec::with_capacity(8192),
            handed: 0,
        };
        run(&mut chunk);
        std::hint::black_box(chunk.handed);
        best = best.min(t0.elapsed().as_secs_f64());
    }
    best
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().unwrap_or("/tmp/tum/box_1000000.tum".into()));
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(9);
    let poses = objmodel::format::read_trajectory(&path).expect("the benchmark file");
    let config = Config::default();
    let clean = best(reps, |chunk| {
        let mut c = Analyzer::new("bench", &config, false)
            .take_object_cleaner()
            .expect("robust");
        for p in &poses {
            c.push(p, |f: objmodel::clean::RawFrame, o| {
                chunk.keep((f.t, f.q, f.p, o))
            });
        }
    });
    let rotated = best(reps, |chunk| {
        let cleaner = Analyzer::new("bench", &config, false)
            .take_object_cleaner()
            .expect("robust");
        let mut c = RotatingCleaner::new(cleaner);
        for p in &poses {
            c.push(p, &mut |f, o, r| {
                chunk.keep((f.t, f.q, f.p, if o { r * f64::NAN } else { r }))
            });
        }
    });
    // As `learn` runs it: the loop compiled for AVX2 where the processor has it.
    let rotated_avx2 = best(reps, |chunk| {
        let cleaner = Analyzer::new("bench", &config, false)
            .take_object_cleaner()
            .expect("robust");
        let mut c = RotatingCleaner::new(cleaner);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor runs AVX2 code (checked just above).
            return unsafe { rotate_avx2(&mut c, &poses, chunk) };
        }
        rotate(&mut c, &poses, chunk)
    });
    let n = poses.len() as f64;
    for (what, s) in [
        ("clean", clean),
        ("clean + rotation", rotated),
        ("clean + rotation (AVX2 code)", rotated_avx2),
    ] {
        println!(
            "{what} + hand-over: {:.1} ms = {:.1} ns/pose",
            s * 1e3,
            s / n * 1e9
        );
    }
}

/// Cleaner and rotation over `poses`, into `chunk`.
#[inline(always)]
fn rotate(c: &mut RotatingCleaner, poses: &[StampedPose], chunk: &mut Chunk<Handed>) {
    for p in poses {
        c.push(p, &mut |f, o, r| {
            chunk.keep((f.t, f.q, f.p, if o { r * f64::NAN } else { r }))
        });
    }
}

/// [`rotate`] compiled for AVX2.
///
/// # Safety
/// The processor must run AVX2 code.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn rotate_avx2(c: &mut RotatingCleaner, poses: &[StampedPose], chunk: &mut Chunk<Handed>) {
    rotate(c, poses, chunk)
}

/// What the parsing thread hands over per frame.
type Handed = (f64, UnitQuaternion<f64>, Vector3<f64>, Vector3<f64>);
