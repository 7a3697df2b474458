//! Parse speed of the pose reader.
//!
//! `cargo run --release --example parse_bench -p objmodel [FILE.tum] [REPS]`
//! (make a file with `python3 /work/shared/bench/gen_tum.py 1000000 /tmp/tum/box_1000000.tum`).

use objmodel::format::{self, Format, PoseReader};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = PathBuf::from(
        args.get(1)
            .map_or("/tmp/tum/box_1000000.tum", |s| s.as_str()),
    );
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(7);
    let size = std::fs::metadata(&path).expect("bench file").len() as f64;
    let mb = size / 1e6;

    let mut best_file = f64::INFINITY;
    let mut n = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let poses = format::read_trajectory(Path::new(&path)).expect("parse");
        best_file = best_file.min(t0.elapsed().as_secs_f64());
        n = poses.len();
        std::hint::black_box(&poses);
    }

    let bytes = std::fs::read(&path).unwrap();
    let mut best_mem = f64::INFINITY;
    let mut checksum = 0.0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let r = PoseReader::new(&bytes[..], path.clone(), Format::Tum);
        let mut s = 0.0;
        for p in r {
            let p = p.expect("parse");
            s += p.pose.translation.vector.x + p.pose.rotation.w;
        }
        best_mem = best_mem.min(t0.elapsed().as_secs_f64());
        checksum = s;
    }
    println!("{n} poses, {mb:.1} MB (checksum {checksum:.6})");
    println!(
        "read_trajectory (file, 1 MiB BufReader, Vec): best {:.3} s = {:.0} MB/s",
        best_file,
        mb / best_file
    );
    println!(
        "PoseReader over &[u8] (streaming, no Vec):    best {:.3} s = {:.0} MB/s",
        best_mem,
        mb / best_mem
    );
}
