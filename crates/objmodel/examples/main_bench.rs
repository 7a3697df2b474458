//! CPU time of `learn`'s main thread alone (robust method, no palm): rest detection, segments
//! and blocks, fed the cleaned frames and their accumulated rotation collected beforehand (what
//! the parsing thread hands over). Handy under `perf record`, where `analyze_bench` mixes
//! stages.
//!
//! `cargo run --release --example main_bench -p objmodel [FILE.tum] [REPS]`

use objmodel::bench::{AnalyzerStages, RotatingCleaner};
use objmodel::classify::{Analyzer, Config};
use std::path::PathBuf;
use std::time::Instant;

/// CPU time of this thread in ns, if the OS tells (Linux).
fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().unwrap_or("/tmp/tum/box_1000000.tum".into()));
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(5);
    let poses = objmodel::format::read_trajectory(&path).expect("the benchmark file");
    let config = Config::default();
    let mut rotated = Vec::with_capacity(poses.len());
    {
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = RotatingCleaner::new(a.take_object_cleaner().expect("robust"));
        for p in &poses {
            c.push(p, &mut |f, o, r| rotated.push((f, o, r)));
        }
        c.finish(&mut |f, o, r| rotated.push((f, o, r)));
    }
    let mut best = f64::INFINITY;
    let mut kind = String::new();
    for _ in 0..reps {
        let (c0, t0) = (cpu_ns(), Instant::now());
        let mut a = Analyzer::new("bench", &config, false);
        let _cleaner = a.take_object_cleaner();
        for (f, o, r) in &rotated {
            let frame = (!o).then_some((&f.q, &f.p, r));
            a.push_cleaned_rotated(f.index, f.t, frame);
        }
        kind = a.finish().expect("classify").kind.as_str().to_string();
        let wall = t0.elapsed().as_secs_f64();
        // The thread CPU clock may tick as coarsely as 4 ms: the wall time of a run that was
        // not preempted (wall <= CPU + one tick) is the finer measure.
        let s = match (c0, cpu_ns()) {
            (Some(a), Some(b)) if wall > (b - a) as f64 * 1e-9 + 4e-3 => (b - a) as f64 * 1e-9,
            _ => wall,
        };
        best = best.min(s);
    }
    println!(
        "{} poses, kind {kind}: main thread cpu {best:.4} s = {:.1} ns/pose",
        poses.len(),
        best / poses.len() as f64 * 1e9
    );
}
