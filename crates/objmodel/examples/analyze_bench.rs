//! CPU time of the robust classifier's stages on poses already in memory (single thread).
//!
//! `cargo run --release --example analyze_bench -p objmodel [FILE.tum] [REPS]`
//!
//! Prints the best of REPS runs of: cleaning alone, and cleaning + rest detection + blocks
//! (the whole analysis after parsing), as thread CPU time.

use objmodel::classify::{Analyzer, Config};
use std::path::PathBuf;
use std::time::Instant;

/// CPU time of this thread in ns, if the OS tells (Linux).
fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn best(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut cpu = f64::INFINITY;
    for _ in 0..reps {
        let (c0, t0) = (cpu_ns(), Instant::now());
        f();
        let s = match (c0, cpu_ns()) {
            (Some(a), Some(b)) => (b - a) as f64 * 1e-9,
            _ => t0.elapsed().as_secs_f64(),
        };
        cpu = cpu.min(s);
    }
    cpu
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().unwrap_or("/tmp/tum/box_1000000.tum".into()));
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(5);
    let poses = objmodel::format::read_trajectory(&path).expect("the benchmark file");
    let n = poses.len() as f64;
    let config = Config::default();
    let clean = best(reps, || {
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = a.take_object_cleaner().expect("robust");
        let mut k = 0usize;
        for p in &poses {
            c.push(p, &mut |_, o| k += o as usize);
        }
        std::hint::black_box(k);
    });
    let mut kind = String::new();
    let only_clean = std::env::var_os("ONLY_CLEAN").is_some();
    let all = best(if only_clean { 0 } else { reps }, || {
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = a.take_object_cleaner().expect("robust");
        for p in &poses {
            c.push(p, &mut |f, o| a.push_cleaned_object(f, o));
        }
        c.finish(&mut |f, o| a.push_cleaned_object(f, o));
        kind = a.finish().expect("classify").kind.as_str().to_string();
    });
    println!("{} poses ({}), kind {kind}", poses.len(), path.display());
    println!("clean only:          cpu {clean:.3} s = {:.0} ns/pose", clean / n * 1e9);
    println!("clean + analysis:    cpu {all:.3} s = {:.0} ns/pose", all / n * 1e9);
}
