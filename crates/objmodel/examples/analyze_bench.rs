//! CPU time of the robust classifier's stages on poses already in memory (single thread).
//!
//! `cargo run --release --example analyze_bench -p objmodel [FILE.tum] [REPS]`
//!
//! Prints the best of REPS runs of: cleaning alone, cleaning + the rest front end (the parsing
//! thread's work after parsing, with `OBJMODEL_FRONT_REST`), cleaning + rest detection + blocks (the
//! whole robust analysis after parsing; also with the front end split off as `learn` runs it),
//! the back end alone (segments and blocks, fed the front end's output collected beforehand),
//! and the paper's Algorithm 1, as thread CPU time. (`learn`'s main thread alone:
//! `examples/main_bench.rs`.)
//!
//! Environment: `ONLY_CLEAN=1` times the cleaning alone, `ONLY_ROBUST=1` skips Algorithm 1
//! (both handy under `perf record`), `ONLY_BACK=1` times the back end alone (`BACK_PASSES=10`
//! passes per timing), `REST_WINDOW=30` sets the rest window \[s\].

use objmodel::bench::AnalyzerStages;
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
    let mut config = Config::default();
    if let Some(w) = std::env::var("REST_WINDOW")
        .ok()
        .and_then(|w| w.parse().ok())
    {
        config.robust.rest_window_s = w; // e.g. 30 for gen_tum.py's 2.3-hour topple
    }
    let only_back = std::env::var_os("ONLY_BACK").is_some();
    let front_reps = if only_back { 0 } else { reps };
    let clean = best(front_reps, || {
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = a.take_object_cleaner().expect("robust");
        let mut k = 0usize;
        for p in &poses {
            c.push(p, &mut |_, o| k += o as usize);
        }
        std::hint::black_box(k);
    });
    // The cleaner and the rest front end, their output gathered in hand-over chunks as on
    // `learn`'s parsing thread.
    let front = best(front_reps, || {
        let mut a = Analyzer::new("bench", &config, false);
        let mut front = a.take_object_rest_test().expect("robust, no palm");
        let mut chunk = Vec::with_capacity(8192);
        let mut k = 0usize;
        let mut keep = |j: objmodel::bench::Verdict| {
            chunk.push(j);
            if chunk.len() == 8192 {
                k += std::hint::black_box(&chunk).len();
                chunk.clear();
            }
        };
        for p in &poses {
            front.push(p, &mut keep);
        }
        front.finish(&mut keep);
        std::hint::black_box(k);
    });
    let mut kind = String::new();
    let only_clean = std::env::var_os("ONLY_CLEAN").is_some();
    let all = best(if only_clean { 0 } else { front_reps }, || {
        let mut a = Analyzer::new("bench", &config, false);
        let mut c = a.take_object_cleaner().expect("robust");
        for p in &poses {
            c.push(p, &mut |f, o| a.push_cleaned_object(f, o));
        }
        c.finish(&mut |f, o| a.push_cleaned_object(f, o));
        kind = a.finish().expect("classify").kind.as_str().to_string();
    });
    let paper_config = Config {
        method: objmodel::classify::Method::Paper,
        ..Config::default()
    };
    let skip_paper = only_back || std::env::var_os("ONLY_ROBUST").is_some();
    let paper = best(if skip_paper { 0 } else { reps }, || {
        let mut a = Analyzer::new("bench", &paper_config, false);
        for p in &poses {
            a.push_object(p);
        }
        std::hint::black_box(a.finish().expect("classify").kind);
    });
    let mut split_kind = String::new();
    let split = best(if only_clean { 0 } else { front_reps }, || {
        let mut a = Analyzer::new("bench", &config, false);
        let mut front = a.take_object_rest_test().expect("robust, no palm");
        for p in &poses {
            front.push(p, &mut |j| a.push_verdict(j));
        }
        front.finish(&mut |j| a.push_verdict(j));
        split_kind = a.finish().expect("classify").kind.as_str().to_string();
    });
    assert_eq!(kind, split_kind);
    // The back end alone (segments and blocks): the front end's output collected first.
    let mut judged = Vec::with_capacity(poses.len() + 1);
    {
        let mut a = Analyzer::new("bench", &config, false);
        let mut front = a.take_object_rest_test().expect("robust, no palm");
        for p in &poses {
            front.push(p, &mut |j| judged.push(j));
        }
        front.finish(&mut |j| judged.push(j));
    }
    let mut back_kind = String::new();
    // Several passes per timing: the thread CPU clock may tick as coarsely as 4 ms.
    let passes: usize = std::env::var("BACK_PASSES")
        .ok()
        .and_then(|p| p.parse().ok())
        .unwrap_or(10);
    let back = best(if only_clean { 0 } else { reps }, || {
        for _ in 0..passes {
            let mut a = Analyzer::new("bench", &config, false);
            let _front = a.take_object_rest_test().expect("robust, no palm");
            for j in &judged {
                a.push_verdict(*j);
            }
            back_kind = a.finish().expect("classify").kind.as_str().to_string();
        }
    }) / passes as f64;
    if only_back {
        kind = back_kind;
    } else if !only_clean {
        assert_eq!(kind, back_kind);
    }
    println!("{} poses ({}), kind {kind}", poses.len(), path.display());
    println!(
        "paper (Algorithm 1): cpu {paper:.3} s = {:.0} ns/pose",
        paper / n * 1e9
    );
    println!(
        "clean only:          cpu {clean:.3} s = {:.0} ns/pose",
        clean / n * 1e9
    );
    println!(
        "clean + rest front:  cpu {front:.3} s = {:.0} ns/pose",
        front / n * 1e9
    );
    println!(
        "clean + analysis:    cpu {all:.3} s = {:.0} ns/pose",
        all / n * 1e9
    );
    println!(
        "same, split front:   cpu {split:.3} s = {:.0} ns/pose",
        split / n * 1e9
    );
    println!(
        "back end alone:      cpu {back:.3} s = {:.1} ns/pose",
        back / n * 1e9
    );
}
