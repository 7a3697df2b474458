//! What the fuzz targets check (`fuzz/fuzz_targets/*.rs`), shared with the regression tests
//! that run the found inputs on stable (`tests/fuzz_regressions.rs`): each function takes the
//! fuzzer's bytes and panics when something is wrong. A panic inside the library is a finding
//! as much as a failed comparison.
//!
//! The reference reader is the general (scalar) path: a 1-byte read buffer makes every line
//! straddle two buffer fills, so no line takes the fast scanners (`fast_line.rs`, `simd.rs`).

#![allow(dead_code)] // each test binary and fuzz target uses a part

use objmodel::format::{open, open_mapped, read_trajectory, Format, PoseReader};
use objmodel::tree::Tree;
use objmodel::StampedPose;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// How the data are read: the format given, or detected.
#[derive(Clone, Copy, Debug)]
pub enum Mode {
    Tum,
    Csv,
    Detect,
}

/// A reader of `src` in `mode`, with `name` in its messages.
fn reader<R: BufRead>(src: R, name: &str, mode: Mode) -> PoseReader<R> {
    match mode {
        Mode::Tum => PoseReader::new(src, name.into(), Format::Tum),
        Mode::Csv => PoseReader::new(src, name.into(), Format::Csv),
        Mode::Detect => PoseReader::detecting(src, name.into()),
    }
}

/// A pose as the bits of its eight values.
fn bits(p: &StampedPose) -> [u64; 8] {
    let (v, q) = (p.pose.translation.vector, p.pose.rotation.coords);
    [p.t, v.x, v.y, v.z, q.x, q.y, q.z, q.w].map(f64::to_bits)
}

/// Everything an iterating reader says: each item with the reader's line after it, then the
/// number of lines read. Also checks what every accepted pose must be.
pub fn items<R: BufRead>(mut r: PoseReader<R>) -> Vec<String> {
    let mut out = Vec::new();
    let mut prev = f64::NEG_INFINITY;
    // At most one item after the reader said None: it must stay done.
    let mut ended = false;
    for _ in 0..1_000_000 {
        match r.next() {
            Some(Ok(p)) => {
                assert!(!ended, "a pose after the end");
                sane(&p, prev);
                prev = p.t;
                out.push(format!("{} {:x?}", r.line(), bits(&p)));
            }
            Some(Err(e)) => {
                assert!(!ended, "an error after the end");
                out.push(format!("{} {e}", r.line()));
            }
            None if ended => break,
            None => ended = true,
        }
    }
    out.push(format!("{} lines", r.lines_read()));
    out
}

/// What a pose that a reader accepted must be: finite, after the one before, a unit
/// quaternion.
fn sane(p: &StampedPose, prev: f64) {
    let b = bits(p).map(f64::from_bits);
    assert!(b.iter().all(|x| x.is_finite()), "{b:?}");
    assert!(p.t > prev, "{} after {prev}", p.t);
    assert!((p.pose.rotation.coords.norm() - 1.0).abs() < 1e-12, "{b:?}");
}

/// The poses and the error of [`items`] (without line numbers), as the bulk reading
/// ([`PoseReader::read_chunk`]) gives them.
fn bulk_of(items: &[String]) -> Vec<String> {
    let mut want = Vec::new();
    for it in &items[..items.len() - 1] {
        let (_, rest) = it.split_once(' ').unwrap();
        want.push(rest.to_string());
    }
    want
}

/// The poses and the error of reading `r` in chunks of `step` poses.
fn bulk<R: BufRead>(mut r: PoseReader<R>, step: usize) -> Vec<String> {
    let mut poses = Vec::new();
    let mut out = Vec::new();
    loop {
        let before = poses.len();
        match r.read_chunk(&mut poses, step) {
            Ok(more) => {
                assert!(poses.len() - before <= step.max(1));
                if more {
                    assert_eq!(poses.len() - before, step.max(1), "a short chunk");
                    continue;
                }
                out.extend(poses.iter().map(|p| format!("{:x?}", bits(p))));
                break;
            }
            Err(e) => {
                out.extend(poses.iter().map(|p| format!("{:x?}", bits(p))));
                out.push(e.to_string());
                break;
            }
        }
    }
    out
}

/// `read_memory`: the in-memory reader (`&[u8]`, the fast scanners where the processor runs
/// them), the same with only the scalar scanners, buffered readers of a size the data choose,
/// and the bulk reading all say what the general path says. Byte 0 picks the format, byte 1
/// the buffer size and the chunk size; the rest is the file.
pub fn read_memory(data: &[u8]) {
    let [a, b, text @ ..] = data else { return };
    let mode = [Mode::Tum, Mode::Csv, Mode::Detect][usize::from(*a % 3)];
    let cap = 1 + usize::from(*b) * 7;
    let name = "f";
    let want = items(reader(BufReader::with_capacity(1, text), name, mode).scalar_only());
    let got = items(reader(text, name, mode));
    assert_eq!(got, want, "in memory, {mode:?}");
    let got = items(reader(text, name, mode).scalar_only());
    assert_eq!(got, want, "in memory, scalar scanners, {mode:?}");
    let got = items(reader(BufReader::with_capacity(cap, text), name, mode));
    assert_eq!(got, want, "buffer of {cap} bytes, {mode:?}");
    let step = 1 + usize::from(*b % 16);
    let got = bulk(reader(text, name, mode), step);
    assert_eq!(got, bulk_of(&want), "bulk in chunks of {step}, {mode:?}");
}

/// A folder for the files of the checks, for the life of the process.
fn scratch() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| tempfile::tempdir().expect("a temporary folder"))
        .path()
}

/// A fresh file name in [`scratch`] ending in `ext`.
fn scratch_file(ext: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let n = N.fetch_add(1, Ordering::Relaxed);
    scratch().join(format!("f{n}{ext}"))
}

/// `read_mapped`: a file read through memory-mapped windows ([`open_mapped`]), read with
/// `read` calls ([`open`]) and in memory all say the same, and [`read_trajectory`] gives
/// the poses and the first error. Byte 0 picks the file name's extension (`.tum`, `.csv`,
/// none: the format is detected unless it is `.csv`); the rest is the file.
pub fn read_mapped(data: &[u8]) {
    let [a, text @ ..] = data else { return };
    let ext = [".tum", ".csv", ""][usize::from(*a % 3)];
    let mode = if ext == ".csv" {
        Mode::Csv
    } else {
        Mode::Detect
    };
    let path = scratch_file(ext);
    let mut f = std::fs::File::create(&path).unwrap();
    f.write_all(text).unwrap();
    drop(f);
    let name = path.to_str().unwrap();
    let want = items(reader(BufReader::with_capacity(1, text), name, mode).scalar_only());
    let got = items(open_mapped(&path).unwrap());
    assert_eq!(got, want, "memory-mapped");
    let got = items(open(&path).unwrap());
    assert_eq!(got, want, "open");
    // read_trajectory: the poses, or the first error; or that there is no pose.
    let whole = read_trajectory(&path);
    let bulk_want = bulk_of(&want);
    match whole {
        Ok(poses) => {
            let got: Vec<String> = poses.iter().map(|p| format!("{:x?}", bits(p))).collect();
            assert_eq!(got, bulk_want, "read_trajectory");
        }
        Err(e) => {
            let e = e.to_string();
            if bulk_want.iter().all(|s| s.starts_with('[')) {
                assert!(bulk_want.is_empty(), "{e}, after poses");
                assert!(e.contains("no poses"), "{e}");
            } else {
                assert_eq!(Some(&e), bulk_want.last(), "read_trajectory's error");
            }
        }
    }
    std::fs::remove_file(&path).unwrap();
}

/// A cursor over the fuzzer's bytes that gives zeros once they run out.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        match self.0.split_first() {
            Some((b, rest)) => {
                self.0 = rest;
                *b
            }
            None => 0,
        }
    }
    fn below(&mut self, n: u8) -> u8 {
        self.byte() % n
    }
}

/// How a column is printed: digits before and after the point, and the sign.
#[derive(Clone, Copy)]
struct Layout {
    int: usize,
    frac: usize,
    /// 0 none, 1 `+`, 2 `-` where negative.
    sign: u8,
}

/// `x` as `layout` says: at least `int` integer digits (zeros in front), `frac` after the
/// point (none, and no point, for 0).
fn print(x: f64, l: Layout) -> String {
    let body = format!("{:.*}", l.frac, x.abs());
    let (i, f) = body.split_once('.').unwrap_or((&body, ""));
    let mut s = String::new();
    if x.is_sign_negative() && l.sign == 2 {
        s.push('-');
    } else if l.sign == 1 {
        s.push(if x.is_sign_negative() { '-' } else { '+' });
    } else if x.is_sign_negative() {
        s.push('-');
    }
    for _ in i.len()..l.int {
        s.push('0');
    }
    s.push_str(i);
    if l.frac > 0 {
        s.push('.');
        s.push_str(f);
    }
    s
}

/// Unit quaternions (x y z w) whose values print exactly in few digits.
const UNIT: [[f64; 4]; 6] = [
    [0.0, 0.0, 0.0, 1.0],
    [0.0, 0.0, 0.6, 0.8],
    [0.5, 0.5, 0.5, 0.5],
    [0.0, 0.28, 0.0, 0.96],
    [0.36, 0.48, 0.0, 0.8],
    [0.0, 0.0, 0.0, -1.0],
];

/// The pose file that the bytes describe for [`read_simd`]: up to 400 TUM lines of mostly
/// valid poses whose columns keep a layout (digits before and after the point, signs) for a
/// while and then change it, so that the vectorised scanner's table of line shapes fills,
/// hits, misses and gives up; with now and then a line of raw bytes, other separators, a
/// comment or `\r\n`.
pub fn simd_text(data: &[u8]) -> Vec<u8> {
    let mut b = Bytes(data);
    let lines = usize::from(b.byte()) + usize::from(b.byte()) % 145;
    let mut layout = [Layout {
        int: 1,
        frac: 6,
        sign: 0,
    }; 8];
    let mut text = Vec::new();
    let mut t = 1.0 + f64::from(b.byte());
    for _ in 0..lines {
        if b.0.is_empty() {
            break;
        }
        let what = b.byte();
        match what {
            // A new layout of one column.
            0..=40 => {
                let k = usize::from(b.below(8));
                layout[k] = Layout {
                    int: usize::from(b.below(21)),
                    frac: usize::from(b.below(21)),
                    sign: b.below(3),
                };
            }
            // A line of raw bytes (up to its `\n`).
            41..=44 => {
                let n = usize::from(b.below(64));
                for _ in 0..n {
                    text.push(b.byte());
                }
                text.push(b'\n');
                continue;
            }
            _ => {}
        }
        t += f64::from(b.byte()) / 16.0 + 1e-3;
        let q = UNIT[usize::from(b.below(6))];
        let mut vals = [t, 0.0, 0.0, 0.0, q[0], q[1], q[2], q[3]];
        for v in &mut vals[1..4] {
            let m = u32::from(b.byte()) << 8 | u32::from(b.byte());
            *v = (f64::from(m) - 32768.0) / 10f64.powi(i32::from(b.below(8)));
        }
        let fields: Vec<String> = (0..8).map(|k| print(vals[k], layout[k])).collect();
        let sep = match what {
            45..=47 => "\t",
            48..=49 => "  ",
            _ => " ",
        };
        text.extend_from_slice(fields.join(sep).as_bytes());
        match what {
            50..=51 => text.extend_from_slice(b"\r\n"),
            52 => text.extend_from_slice(b" # comment\n"),
            53 => text.extend_from_slice(b" \n"),
            _ => text.push(b'\n'),
        }
    }
    text
}

/// `read_simd`: on the TUM file of [`simd_text`], the vectorised scanner (where the
/// processor runs it) says what the scalar scanners and the general path say.
pub fn read_simd(data: &[u8]) {
    let text = simd_text(data);
    let name = "f.tum";
    let want = items(reader(
        BufReader::with_capacity(1, &text[..]),
        name,
        Mode::Tum,
    ));
    let got = items(reader(&text[..], name, Mode::Tum));
    assert_eq!(got, want, "vectorised");
    let got = items(reader(&text[..], name, Mode::Tum).scalar_only());
    assert_eq!(got, want, "scalar scanners");
    let got = bulk(reader(&text[..], name, Mode::Tum), usize::MAX);
    assert_eq!(got, bulk_of(&want), "bulk");
}

/// A demonstration's observation to learn into loaded trees: a topple of a synthetic box.
fn observation() -> &'static objmodel::observation::Observation {
    use objmodel::learn::{Config, Learner, Source};
    use objmodel::synth::{topple, SynthBox, SynthNoise, ToppleParams};
    static OBS: OnceLock<objmodel::observation::Observation> = OnceLock::new();
    OBS.get_or_init(|| {
        let b = SynthBox::new(nalgebra::Vector3::new(0.05, 0.05, 0.1), (0.0, 0.0), 0.0);
        let d = topple(&b, &ToppleParams::default(), &SynthNoise::REAL, 30.0, 1);
        Learner::new(Config::default())
            .observe(&Source::Memory(&d.demo))
            .expect("the synthetic topple is observed")
    })
}

/// `tree_load`: any bytes in a model file give a tree or an error, never a panic; a tree
/// that loads is written ([`Tree::to_json`]) and loads again equal, and written again the
/// same. Learning a demonstration into it (what `learn --into` does next) does not panic.
pub fn tree_load(data: &[u8]) {
    let path = scratch_file(".json");
    std::fs::write(&path, data).unwrap();
    let loaded = Tree::load(&path);
    if let Ok(tree) = loaded {
        let json = tree.to_json();
        std::fs::write(&path, &json).unwrap();
        let again = Tree::load(&path).unwrap_or_else(|e| panic!("{e}\n{json}"));
        assert!(again == tree, "loads again different:\n{json}");
        assert_eq!(again.to_json(), json);
        let mut more = tree;
        more.add(observation());
        let _ = more.to_json();
    }
    std::fs::remove_file(&path).unwrap();
}

/// `cli_args`: the parsers of the command line's `--object-in-palm`, `--gravity` and
/// 3-vector options take any text: a value that is what it should be, or an error.
pub fn cli_args(data: &[u8]) {
    let Ok(s) = std::str::from_utf8(data) else {
        return;
    };
    use objmodel::args::{gravity, pose_xyz_xyzw, vec3};
    if let Ok(p) = pose_xyz_xyzw(s) {
        let (v, q) = (p.translation.vector, p.rotation.coords);
        assert!(v.iter().chain(q.iter()).all(|x| x.is_finite()), "{s:?}");
        assert!((q.norm() - 1.0).abs() < 1e-12, "{s:?}");
        // Printed and read again: the same translation.
        let again = pose_xyz_xyzw(&format!(
            "{} {} {} {} {} {} {}",
            v.x, v.y, v.z, q.x, q.y, q.z, q.w
        ));
        assert_eq!(again.map(|a| a.translation.vector), Ok(v), "{s:?}");
    }
    let v = vec3(s);
    if let Ok(v) = &v {
        assert!(v.iter().all(|x| x.is_finite()), "{s:?}");
    }
    match gravity(s) {
        Ok(None) => assert_eq!(s.trim(), "none"),
        Ok(Some(g)) => {
            assert!(g.iter().all(|x| x.is_finite()) && g.norm() > 0.0, "{s:?}");
            assert_eq!(vec3(s.trim()), Ok(g));
        }
        Err(e) => assert!(e.to_string().starts_with("--gravity"), "{e}"),
    }
}
