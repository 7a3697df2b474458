//! Wall time of the parsing thread's work after parsing: the tag-flip cleaner and the
//! accumulated rotation, with what they emit stored in a hand-over chunk (single thread, poses
//! in memory; best of REPS runs).
//!
//! `cargo run --release --example clean_bench -p objmodel [FILE.tum] [REPS]`

use objmodel::classify::{Analyzer, Config, RotatingCleaner};
use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().unwrap_or("/tmp/tum/box_1000000.tum".into()));
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(9);
    let poses = objmodel::format::read_trajectory(&path).expect("the benchmark file");
    let config = Config::default();
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = RotatingCleaner::new(a.take_object_cleaner().expect("robust"));
        let mut chunk = Vec::with_capacity(8192);
        let mut k = 0usize;
        for p in &poses {
            c.push(p, &mut |f, o, r| {
                chunk.push((f.t, f.q, f.p, if o { r * f64::NAN } else { r }))
            });
            if chunk.len() >= 8192 {
                k += std::hint::black_box(&chunk).len();
                chunk.clear();
            }
        }
        std::hint::black_box(k);
        best = best.min(t0.elapsed().as_secs_f64());
    }
    let mut best2 = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = a.take_object_cleaner().expect("robust");
        let mut chunk = Vec::with_capacity(8192);
        let mut k = 0usize;
        for p in &poses {
            c.push(p, &mut |f, o| chunk.push((f.t, f.q, f.p, o)));
            if chunk.len() >= 8192 {
                k += std::hint::black_box(&chunk).len();
                chunk.clear();
            }
        }
        std::hint::black_box(k);
        best2 = best2.min(t0.elapsed().as_secs_f64());
    }
    let n = poses.len() as f64;
    println!(
        "clean + hand-over: {:.1} ms = {:.1} ns/pose",
        best2 * 1e3,
        best2 / n * 1e9
    );
    println!(
        "clean + rotation + hand-over: {:.1} ms = {:.1} ns/pose",
        best * 1e3,
        best / n * 1e9
    );
}
