//! Helpers shared by the CLI tests: temporary folders, running the binary, JSON access.
#![allow(dead_code)]

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

// ---------------------------------------------------------------------------------------------
// helpers

/// A unique temporary folder (`tempfile`), removed on drop, kept if the test failed, for
/// inspection.
pub struct TempDir(Option<tempfile::TempDir>);

impl TempDir {
    pub fn new(tag: &str) -> Self {
        let dir = tempfile::Builder::new()
            .prefix(&format!("objmodel-cli-test-{tag}-"))
            .tempdir()
            .expect("create temp dir");
        TempDir(Some(dir))
    }

    pub fn path(&self) -> &Path {
        self.0.as_ref().expect("the folder lives").path()
    }

    pub fn join(&self, p: &str) -> PathBuf {
        self.path().join(p)
    }

    /// Write `content` to `name` in the folder and return its path.
    pub fn write(&self, name: &str, content: &str) -> PathBuf {
        let p = self.join(name);
        std::fs::write(&p, content).expect("write test file");
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            if let Some(dir) = self.0.take() {
                eprintln!("test files kept in {}", dir.keep().display());
            }
        }
    }
}

/// The result of one run of the binary.
pub struct Run {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    pub cmdline: String,
}

impl Run {
    /// Panic with the whole run if `cond` is false.
    pub fn check(&self, cond: bool, what: &str) {
        assert!(
            cond,
            "{what}\n  command: {}\n  exit code: {:?}\n  stdout:\n{}\n  stderr:\n{}",
            self.cmdline, self.code, self.stdout, self.stderr
        );
    }

    /// Assert success (exit code 0, no panic) and return self.
    pub fn ok(self) -> Self {
        self.check(self.code == Some(0), "expected exit code 0");
        self.check(!self.stderr.contains("panicked"), "the binary panicked");
        self
    }

    /// Assert a clean failure: exit code 2, no panic, one `objmodel: error:` message, nothing on
    /// standard output.
    pub fn fails(self) -> Self {
        self.check(self.code == Some(2), "expected exit code 2");
        self.check(!self.stderr.contains("panicked"), "the binary panicked");
        self.check(
            !self.stderr.contains("RUST_BACKTRACE"),
            "the binary panicked (backtrace note)",
        );
        self.check(
            self.stderr.starts_with("objmodel: error: "),
            "expected stderr to start with 'objmodel: error: '",
        );
        self.check(
            self.stdout.is_empty(),
            "expected no output on stdout for a failure",
        );
        self
    }

    pub fn json(&self) -> Value {
        match serde_json::from_str(&self.stdout) {
            Ok(v) => v,
            Err(e) => {
                self.check(false, &format!("stdout is not one JSON value: {e}"));
                unreachable!()
            }
        }
    }
}

/// Run `objmodel ARGS` (in `cwd` if given).
pub fn run_in<S: AsRef<std::ffi::OsStr>>(cwd: Option<&Path>, args: &[S]) -> Run {
    let mut c = Command::new(env!("CARGO_BIN_EXE_objmodel"));
    c.args(args);
    if let Some(d) = cwd {
        c.current_dir(d);
    }
    c.env_remove("RUST_BACKTRACE");
    let out: Output = c.output().expect("run objmodel");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        cmdline: std::iter::once("objmodel".to_string())
            .chain(
                args.iter()
                    .map(|a| a.as_ref().to_string_lossy().into_owned()),
            )
            .collect::<Vec<_>>()
            .join(" "),
    }
}

pub fn run<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Run {
    run_in(None, args)
}

pub fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Write `n` synthetic demonstrations of `kind` (one box, from `seed`) into `dir`; returns the
/// object files printed by `objmodel synth`.
pub fn synth(kind: &str, dir: &Path, count: u64, seed: u64, extra: &[&str]) -> Vec<PathBuf> {
    let mut args = vec![
        "synth".to_string(),
        kind.to_string(),
        "-o".into(),
        s(dir),
        "--count".into(),
        count.to_string(),
        "--seed".into(),
        seed.to_string(),
    ];
    args.extend(extra.iter().map(|x| x.to_string()));
    let r = run(&args).ok();
    let files: Vec<PathBuf> = r.stdout.lines().map(PathBuf::from).collect();
    r.check(
        files.len() == count as usize,
        &format!("expected {count} file names on stdout"),
    );
    for f in &files {
        r.check(
            f.is_file(),
            &format!("synth printed {} but it does not exist", f.display()),
        );
        r.check(
            f.extension().is_some_and(|e| e == "tum"),
            "synth should print .tum files",
        );
    }
    files
}

pub fn vec3(v: &Value, what: &str) -> [f64; 3] {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("{what} is not an array: {v}"));
    assert_eq!(a.len(), 3, "{what} should have 3 numbers: {v}");
    let x: Vec<f64> = a
        .iter()
        .map(|x| {
            x.as_f64()
                .unwrap_or_else(|| panic!("{what} has a non-number: {v}"))
        })
        .collect();
    assert!(x.iter().all(|x| x.is_finite()), "{what} is not finite: {v}");
    [x[0], x[1], x[2]]
}

pub fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// Angle in degrees between two lines (directions up to sign).
pub fn line_angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).abs();
    let cross = norm([
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]);
    cross.atan2(dot).to_degrees()
}

pub fn read_json(p: &Path) -> Value {
    let text =
        std::fs::read_to_string(p).unwrap_or_else(|e| panic!("reading {}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} is not JSON: {e}", p.display()))
}

/// The truth file beside a synthetic demonstration `DIR/NAME.tum`.
pub fn truth_of(demo: &Path) -> Value {
    read_json(&demo.with_extension("truth.json"))
}

/// Five good TUM lines (line numbers 1-5, t = 0.0 .. 0.4).
pub const GOOD: &str = "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n0.2 0 0 0 0 0 0 1\n0.3 0 0 0 0 0 0 1\n0.4 0 0 0 0 0 0 1\n";
