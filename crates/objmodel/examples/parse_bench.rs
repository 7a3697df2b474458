//! Parse speed of the pose reader (single thread).
//!
//! `cargo run --release --example parse_bench -p objmodel [FILE.tum] [REPS]`
//! (make a file with `python3 /work/shared/bench/gen_tum.py 1000000 /tmp/tum/box_1000000.tum`).
//!
//! Prints the best of REPS runs, as wall time and, on Linux, as the thread's CPU time (which
//! other processes on a busy machine do not inflate).

use objmodel::format::{self, Format, PoseReader};
use std::path::PathBuf;
use std::time::Instant;

/// CPU time of this thread in ns, if the OS tells (Linux).
fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// Best (wall, cpu) seconds of `reps` runs of `f`.
fn best(reps: usize, mut f: impl FnMut()) -> (f64, Option<f64>) {
    let (mut wall, mut cpu) = (f64::INFINITY, None::<f64>);
    for _ in 0..reps {
        let (c0, t0) = (cpu_ns(), Instant::now());
        f();
        wall = wall.min(t0.elapsed().as_secs_f64());
        if let (Some(a), Some(b)) = (c0, cpu_ns()) {
            let s = (b - a) as f64 * 1e-9;
            cpu = Some(cpu.map_or(s, |c| c.min(s)));
        }
    }
    (wall, cpu)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().unwrap_or("/tmp/tum/box_1000000.tum".into()));
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(7);
    let bytes = std::fs::read(&path).expect("the benchmark file");
    let mb = bytes.len() as f64 / 1e6;
    let mut n = 0;
    let report = |what: &str, (wall, cpu): (f64, Option<f64>)| {
        let cpu = cpu.map_or(String::new(), |c| {
            format!(", cpu {c:.3} s = {:.0} MB/s", mb / c)
        });
        println!("{what:32} wall {wall:.3} s = {:4.0} MB/s{cpu}", mb / wall);
    };
    let in_memory = best(reps, || {
        let mut s = 0.0;
        for p in PoseReader::new(&bytes[..], path.clone(), Format::Tum) {
            s += p.expect("parse").pose.translation.vector.x;
        }
        std::hint::black_box(s);
    });
    let streamed = best(reps, || {
        let mut s = 0.0;
        for p in format::open(&path).expect("open") {
            s += p.expect("parse").t;
        }
        std::hint::black_box(s);
    });
    let whole = best(reps, || {
        let v = format::read_trajectory(&path).expect("parse");
        n = v.len();
    });
    println!("{n} poses, {mb:.1} MB ({})", path.display());
    report("PoseReader over &[u8]:", in_memory);
    report("open() (1 MiB BufReader):", streamed);
    report("read_trajectory (into a Vec):", whole);
}
