//! Measuring the readers' limits (issue 22 item 4), outside the test suite (the inputs are
//! gigabytes):
//!
//! * `read_limits gen N`: write N TUM lines (`k 0 0 0 0 0 0 1`, k = 1..=N) to stdout, fast;
//!   e.g. into a named pipe (`mkfifo`), so that 10^9 lines need no disk.
//! * `read_limits read FILE`: stream FILE with `format::open` and the reader's chunked read
//!   (as the classifier does), and print the poses, the lines, the first error and the time;
//!   run it under `/usr/bin/time -v` for the peak memory.
//! * `read_limits long FILE BYTES`: write FILE with a pose, one line of BYTES bytes, and a pose.

use std::io::Write;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    match args.get(1).map(String::as_str) {
        Some("gen") => generate(args[2].parse().expect("N")),
        Some("read") => read(&args[2]),
        Some("long") => long(&args[2], args[3].parse().expect("BYTES")),
        _ => eprintln!("usage: read_limits gen N | read FILE | long FILE BYTES"),
    }
}

fn generate(n: u64) {
    let out = std::io::stdout();
    let mut out = std::io::BufWriter::with_capacity(1 << 20, out.lock());
    let mut line = Vec::with_capacity(64);
    for k in 1..=n {
        line.clear();
        let mut digits = [0u8; 20];
        let (mut i, mut x) = (20, k);
        while x > 0 {
            i -= 1;
            digits[i] = b'0' + (x % 10) as u8;
            x /= 10;
        }
        line.extend_from_slice(&digits[i..]);
        line.extend_from_slice(b" 0 0 0 0 0 0 1\n");
        if out.write_all(&line).is_err() {
            return; // the reader stopped
        }
    }
}

fn read(path: &str) {
    let start = std::time::Instant::now();
    let mut r = objmodel::format::open(std::path::Path::new(path)).expect("open");
    let mut chunk = Vec::with_capacity(4096);
    let mut poses = 0u64;
    let mut last_t = 0.0;
    let err = loop {
        chunk.clear();
        match r.read_chunk(&mut chunk, 4096) {
            Ok(more) => {
                poses += chunk.len() as u64;
                if let Some(p) = chunk.last() {
                    last_t = p.t;
                }
                if !more {
                    break None;
                }
            }
            Err(e) => {
                poses += chunk.len() as u64;
                if let Some(p) = chunk.last() {
                    last_t = p.t;
                }
                break Some(e.to_string());
            }
        }
    };
    let s = start.elapsed().as_secs_f64();
    println!(
        "poses {poses}, lines {}, last t {last_t}, {s:.1} s ({:.1} M lines/s)",
        r.lines_read(),
        r.lines_read() as f64 / s / 1e6
    );
    if let Some(e) = err {
        println!("error: {e}");
    }
}

fn long(path: &str, bytes: usize) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).expect("create"));
    f.write_all(b"1 0 0 0 0 0 0 1\n2 ").unwrap();
    let block = vec![b'0'; 1 << 16];
    let mut left = bytes.saturating_sub(2);
    while left > 0 {
        let n = left.min(block.len());
        f.write_all(&block[..n]).unwrap();
        left -= n;
    }
    f.write_all(b"\n3 0 0 0 0 0 0 1\n").unwrap();
}
