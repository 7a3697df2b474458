//! End-to-end tests of the `objmodel` binary: bad input, the output contracts of `classify`,
//! `learn` and `evaluate`, incremental and atomic tree updates, and help texts.
//!
//! Every test runs the real binary in its own temporary folder and checks what it prints.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

// ---------------------------------------------------------------------------------------------
// helpers

/// A unique temporary folder, removed on drop (kept if the test failed, for inspection).
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let dir = std::env::temp_dir().join(format!(
            "objmodel-cli-test-{tag}-{}-{n}-{nanos}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    fn path(&self) -> &Path {
        &self.0
    }

    fn join(&self, p: &str) -> PathBuf {
        self.0.join(p)
    }

    /// Write `content` to `name` in the folder and return its path.
    fn write(&self, name: &str, content: &str) -> PathBuf {
        let p = self.join(name);
        std::fs::write(&p, content).expect("write test file");
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// The result of one run of the binary.
struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    cmdline: String,
}

impl Run {
    /// Panic with the whole run if `cond` is false.
    fn check(&self, cond: bool, what: &str) {
        assert!(
            cond,
            "{what}\n  command: {}\n  exit code: {:?}\n  stdout:\n{}\n  stderr:\n{}",
            self.cmdline, self.code, self.stdout, self.stderr
        );
    }

    /// Assert success (exit code 0, no panic) and return self.
    fn ok(self) -> Self {
        self.check(self.code == Some(0), "expected exit code 0");
        self.check(!self.stderr.contains("panicked"), "the binary panicked");
        self
    }

    /// Assert a clean failure: exit code 2, no panic, one `objmodel: error:` message, nothing on
    /// standard output.
    fn fails(self) -> Self {
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

    fn json(&self) -> Value {
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
fn run_in<S: AsRef<std::ffi::OsStr>>(cwd: Option<&Path>, args: &[S]) -> Run {
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

fn run<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Run {
    run_in(None, args)
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Write `n` synthetic demonstrations of `kind` (one box, from `seed`) into `dir`; returns the
/// object files printed by `objmodel synth`.
fn synth(kind: &str, dir: &Path, count: u64, seed: u64, extra: &[&str]) -> Vec<PathBuf> {
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

fn vec3(v: &Value, what: &str) -> [f64; 3] {
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

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// Angle in degrees between two lines (directions up to sign).
fn line_angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).abs();
    let cross = norm([
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]);
    cross.atan2(dot).to_degrees()
}

fn read_json(p: &Path) -> Value {
    let text =
        std::fs::read_to_string(p).unwrap_or_else(|e| panic!("reading {}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} is not JSON: {e}", p.display()))
}

/// The truth file beside a synthetic demonstration `DIR/NAME.tum`.
fn truth_of(demo: &Path) -> Value {
    read_json(&demo.with_extension("truth.json"))
}

// ---------------------------------------------------------------------------------------------
// 1. bad input: a clear error naming the file and line, exit code 2, no panic

/// Five good TUM lines (line numbers 1-5, t = 0.0 .. 0.4).
const GOOD: &str = "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n0.2 0 0 0 0 0 0 1\n0.3 0 0 0 0 0 0 1\n0.4 0 0 0 0 0 0 1\n";

/// `objmodel classify FILE` must fail cleanly; its message must contain `FILE:LINE:` (or just
/// `FILE` for `line == None`) and every string in `expect`.
fn expect_bad(
    dir: &TempDir,
    name: &str,
    content: Option<&str>,
    line: Option<usize>,
    expect: &[&str],
) {
    let path = match content {
        Some(c) => dir.write(name, c),
        None => dir.join(name),
    };
    let r = run(&["classify".to_string(), s(&path)]).fails();
    let at = match line {
        Some(l) => format!("{}:{l}: ", path.display()),
        None => format!("{}", path.display()),
    };
    r.check(
        r.stderr.contains(&at),
        &format!("the message should name the place '{at}'"),
    );
    for e in expect {
        r.check(
            r.stderr.to_lowercase().contains(&e.to_lowercase()),
            &format!("the message should mention '{e}'"),
        );
    }
    r.check(
        r.stderr.trim_end().lines().count() == 1,
        "expected a one-line message",
    );
}

#[test]
fn bad_input_empty_file() {
    let d = TempDir::new("empty");
    expect_bad(&d, "empty.tum", Some(""), None, &["no", "poses"]);
    // only comments and blank lines: no poses either
    expect_bad(
        &d,
        "comments.tum",
        Some("# nothing here\n\n   \n# timestamp tx ty tz qx qy qz qw\n"),
        None,
        &["poses"],
    );
}

#[test]
fn bad_input_wrong_column_count() {
    let d = TempDir::new("columns");
    expect_bad(
        &d,
        "seven.tum",
        Some(&format!("# a comment\n{GOOD}0.5 0 0 0 0 0 1\n")),
        Some(7),
        &["expected 8 columns", "found 7"],
    );
    expect_bad(
        &d,
        "nine.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 1 9\n")),
        Some(6),
        &["expected 8 columns", "found 9"],
    );
    // commas without a header: hint at the CSV header
    expect_bad(
        &d,
        "commas.tum",
        Some("0,0,0,0,0,0,0,1\n"),
        Some(1),
        &["expected 8 columns", "header"],
    );
}

#[test]
fn bad_input_not_a_number() {
    let d = TempDir::new("nan-text");
    expect_bad(
        &d,
        "word.tum",
        Some(&format!("{GOOD}0.5 0 0 0.2x 0 0 0 1\n")),
        Some(6),
        &["column 4", "tz", "\"0.2x\"", "not a number"],
    );
}

#[test]
fn bad_input_nan_and_infinity() {
    let d = TempDir::new("nan");
    expect_bad(
        &d,
        "nan.tum",
        Some(&format!("{GOOD}0.5 0 NaN 0 0 0 0 1\n")),
        Some(6),
        &["ty", "NaN", "finite"],
    );
    expect_bad(
        &d,
        "inf.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 inf\n")),
        Some(6),
        &["qw", "infinite", "finite"],
    );
}

#[test]
fn bad_input_zero_quaternion() {
    let d = TempDir::new("zeroq");
    expect_bad(
        &d,
        "zero.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 0\n")),
        Some(6),
        &["quaternion", "zero"],
    );
}

#[test]
fn bad_input_far_from_unit_quaternion() {
    let d = TempDir::new("farq");
    expect_bad(
        &d,
        "far.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 1.5\n")),
        Some(6),
        &["quaternion", "norm 1.5"],
    );
    expect_bad(
        &d,
        "small.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0.5 0 0 0.5\n")),
        Some(6),
        &["quaternion", "norm"],
    );
    // a quaternion off by rounding is normalised, not rejected
    let ok = d.write("rounding.tum", &GOOD.replace(" 1\n", " 1.001\n"));
    run(&["classify".to_string(), s(&ok)]).ok();
}

#[test]
fn bad_input_timestamps_not_increasing() {
    let d = TempDir::new("time");
    expect_bad(
        &d,
        "repeat.tum",
        Some(&format!("{GOOD}0.4 0 0 0 0 0 0 1\n")),
        Some(6),
        &["timestamp", "repeats", "line 5", "strictly increase"],
    );
    expect_bad(
        &d,
        "back.tum",
        Some(&format!("{GOOD}0.25 0 0 0 0 0 0 1\n")),
        Some(6),
        &["timestamp 0.25", "goes back", "line 5", "strictly increase"],
    );
}

#[test]
fn bad_input_missing_file() {
    let d = TempDir::new("missing");
    expect_bad(&d, "does-not-exist.tum", None, None, &["no such file"]);
    // a named palm file that does not exist is reported by its name too
    let demo = d.write("demo.tum", GOOD);
    let palm = d.join("nopalm.tum");
    let r = run(&["classify".to_string(), s(&demo), "--palm".into(), s(&palm)]).fails();
    r.check(
        r.stderr.contains(&s(&palm)),
        "the message should name the missing palm file",
    );
}

#[test]
fn bad_input_csv() {
    let d = TempDir::new("csv");
    // a header without a qz column
    expect_bad(
        &d,
        "noqz.csv",
        Some("timestamp,tx,ty,tz,qx,qy,qw\n0,0,0,0,0,0,1\n"),
        Some(1),
        &["no column for qz"],
    );
    // a header without a timestamp (detected as CSV from the header, not the name)
    expect_bad(
        &d,
        "not",
        Some("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n"),
        Some(1),
        &["no column for timestamp"],
    );
    // a data row with a field missing
    expect_bad(
        &d,
        "short.csv",
        Some("t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n0.1,0,0,0,0,0,1\n"),
        Some(3),
        &["expected 8 columns", "found 7"],
    );
    // a good CSV file (columns in another order, an extra column) is read
    let ok = d.write(
        "ok.csv",
        "qw,qx,qy,qz,frame,t,x,y,z\n1,0,0,0,a,0,0,0,0\n1,0,0,0,b,0.1,0,0,0\n1,0,0,0,c,0.2,0,0,0\n",
    );
    let r = run(&["classify".to_string(), s(&ok), "--json".into()]).ok();
    r.check(r.json()["frames"] == 3, "a 3-line CSV should give 3 frames");
}

#[test]
fn bad_input_late_in_a_long_file() {
    // the error comes after many good lines (more than one parsing chunk): still its line
    let d = TempDir::new("long");
    let mut text = String::with_capacity(30 * 20_001);
    for i in 0..20_000 {
        text += &format!("{}.{:03} 0 0 0 0 0 0 1\n", i / 1000, i % 1000);
    }
    text += "25 0 0 0 0 0 0\n";
    expect_bad(
        &d,
        "long.tum",
        Some(&text),
        Some(20_001),
        &["expected 8 columns", "found 7"],
    );
}

/// Each part of an error message once: the file name is not repeated, nor the OS's message.
#[test]
fn error_messages_do_not_repeat_themselves() {
    let d = TempDir::new("repeat");
    for (name, content, needle) in [
        ("empty.tum", Some(""), "empty.tum"),
        ("nosuch.tum", None, "No such file"),
    ] {
        let path = match content {
            Some(c) => d.write(name, c),
            None => d.join(name),
        };
        let r = run(&["classify".to_string(), s(&path)]).fails();
        r.check(
            r.stderr.contains(needle),
            &format!("the message should contain '{needle}'"),
        );
        r.check(
            r.stderr.matches(needle).count() == 1,
            &format!("'{needle}' should appear once in the message"),
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. output contract of `classify --json`

fn classify_json(demo: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["classify".to_string(), s(demo), "--json".into()];
    args.extend(extra.iter().map(|x| x.to_string()));
    let r = run(&args).ok();
    let v = r.json();
    r.check(
        v.is_object(),
        "classify --json should print one JSON object",
    );
    v
}

#[test]
fn classify_json_kinds() {
    let d = TempDir::new("kinds");
    for (kind, expected) in [
        ("topple", "topple"),
        ("slide", "slide"),
        ("general", "general"),
    ] {
        let files = synth(kind, &d.join(kind), 1, 3, &[]);
        let v = classify_json(&files[0], &[]);
        assert_eq!(
            v["kind"], expected,
            "synth {kind} classified as {}: {v}",
            v["kind"]
        );
        assert_eq!(v["instrumented"], false, "{kind}: not instrumented");
        assert_eq!(v["method"], "robust");
        assert_eq!(v["file"], s(&files[0]));
        assert!(
            v["palm_file"].is_null(),
            "{kind}: no palm file expected, got {}",
            v["palm_file"]
        );
        assert!(
            v["frames"].as_u64().is_some_and(|n| n > 10),
            "{kind}: frames: {}",
            v["frames"]
        );
        let labels = v["labels"].as_array().expect("labels array");
        assert!(!labels.is_empty(), "{kind}: per-frame labels expected");
        // the truth agrees
        assert_eq!(truth_of(&files[0])["kind"], expected);
    }
}

#[test]
fn classify_instrumented_picks_up_palm() {
    let d = TempDir::new("instr");
    let files = synth("instrumented", d.path(), 1, 3, &[]);
    let demo = &files[0];
    let palm = demo.with_extension("palm.tum");
    assert!(
        palm.is_file(),
        "synth instrumented should write {}",
        palm.display()
    );
    let v = classify_json(demo, &[]);
    assert_eq!(v["instrumented"], true, "{v}");
    assert_eq!(
        v["kind"], "topple",
        "an instrumented topple is a topple: {v}"
    );
    assert_eq!(v["palm_file"], s(&palm));
    // --no-palm ignores it
    let v = classify_json(demo, &["--no-palm"]);
    assert_eq!(v["instrumented"], false);
    assert!(v["palm_file"].is_null());
    // --palm names it explicitly
    let v = classify_json(demo, &["--no-palm", "--palm", &s(&palm)]);
    assert_eq!(v["instrumented"], true);
}

// ---------------------------------------------------------------------------------------------
// 3. `learn --json`: the tree and its schema

#[test]
fn learn_json_tree_matches_truth() {
    let d = TempDir::new("learn");
    let files = synth("topple", d.path(), 2, 3, &[]);
    let r = run(&[
        "learn".to_string(),
        s(&files[0]),
        s(&files[1]),
        "--json".into(),
    ])
    .ok();
    let t = r.json();
    assert_eq!(t["schema"], "objmodel.tree");
    assert_eq!(t["version"], 1);
    let edges = t["edges"].as_array().expect("edges array");
    let faces = t["faces"].as_array().expect("faces array");
    assert!(!edges.is_empty(), "no edges learnt: {t}");
    for e in edges {
        let p = vec3(&e["point"], "edge point");
        let dir = vec3(&e["direction"], "edge direction");
        assert!(
            (norm(dir) - 1.0).abs() < 1e-9,
            "direction not unit: {dir:?}"
        );
        // the point is the one closest to the origin: perpendicular to the line
        assert!(
            (p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2]).abs() < 1e-6,
            "point {p:?} not closest to the origin on {dir:?}"
        );
        assert!(
            e["pendulums"].is_array(),
            "pendulums should be an array: {e}"
        );
    }
    for f in faces {
        let n = vec3(&f["normal"], "face normal");
        assert!((norm(n) - 1.0).abs() < 1e-6, "normal not unit: {n:?}");
        assert!(
            f["offset"].is_null() || f["offset"].as_f64().is_some_and(f64::is_finite),
            "offset should be a number or null: {f}"
        );
    }
    // both demonstrations show the same edge of the same box: one edge, and it is the true one
    let truth = truth_of(&files[0]);
    assert_eq!(
        truth["edge"],
        truth_of(&files[1])["edge"],
        "count 2 should give two demos of one edge"
    );
    let tp = vec3(&truth["edge"]["point"], "truth point");
    let td = vec3(&truth["edge"]["direction"], "truth direction");
    assert_eq!(
        edges.len(),
        1,
        "two topples over one edge should fuse into one edge: {}",
        t["edges"]
    );
    let e = &edges[0];
    let angle = line_angle_deg(vec3(&e["direction"], "dir"), td);
    let off = dist(vec3(&e["point"], "point"), tp);
    assert!(angle < 2.0, "edge direction off by {angle:.3} deg");
    assert!(off < 5e-3, "edge point off by {:.3} mm", off * 1e3);
    assert_eq!(e["n_support"], 2);
    // the faces the box rested on are there: the true resting face (normal and offset)
    let tn = vec3(&truth["face"]["normal"], "truth normal");
    let to = truth["face"]["offset"].as_f64().unwrap();
    let rest = faces
        .iter()
        .find(|f| line_angle_deg(vec3(&f["normal"], "n"), tn) < 3.0);
    let rest = rest.unwrap_or_else(|| {
        panic!(
            "no face with the true resting normal {tn:?}: {}",
            t["faces"]
        )
    });
    let n = vec3(&rest["normal"], "n");
    let sign = if n[0] * tn[0] + n[1] * tn[1] + n[2] * tn[2] > 0.0 {
        1.0
    } else {
        -1.0
    };
    if let Some(o) = rest["offset"].as_f64() {
        assert!(
            (sign * o - to).abs() < 5e-3,
            "resting face offset {o} vs truth {to}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 4. incremental and atomic updates

fn temp_leftovers(dir: &Path, prefix: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(prefix))
        .collect()
}

#[test]
fn learn_incremental_and_atomic() {
    let d = TempDir::new("incr");
    let files = synth("topple", &d.join("demos"), 2, 3, &["--side", "1"]);
    let tree = d.join("box.json");
    // first demonstration
    let r = run(&["learn".to_string(), s(&files[0]), "-o".into(), s(&tree)]).ok();
    r.check(
        r.stdout.contains(&format!("wrote {}", tree.display())),
        "learn -o should say where it wrote",
    );
    let t1 = read_json(&tree);
    assert_eq!(t1["schema"], "objmodel.tree");
    assert_eq!(t1["demos"].as_array().map(Vec::len), Some(1));
    let e1 = t1["edges"].as_array().expect("edges");
    assert_eq!(e1.len(), 1, "one topple, one edge: {}", t1["edges"]);
    assert_eq!(e1[0]["n_support"], 1);
    // second demonstration of the same edge, fused in
    run(&["learn".to_string(), s(&files[1]), "--into".into(), s(&tree)]).ok();
    let t2 = read_json(&tree);
    assert_eq!(t2["demos"].as_array().map(Vec::len), Some(2));
    let e2 = t2["edges"].as_array().expect("edges");
    assert_eq!(
        e2.len(),
        1,
        "the same edge should be fused, not added: {}",
        t2["edges"]
    );
    assert_eq!(e2[0]["n_support"], 2, "{}", t2["edges"]);
    let support: Vec<&str> = e2[0]["support"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(support.len(), 2, "support: {support:?}");
    // the fused edge is still the true one
    let truth = truth_of(&files[0]);
    let angle = line_angle_deg(
        vec3(&e2[0]["direction"], "dir"),
        vec3(&truth["edge"]["direction"], "td"),
    );
    let off = dist(
        vec3(&e2[0]["point"], "p"),
        vec3(&truth["edge"]["point"], "tp"),
    );
    assert!(
        angle < 2.0 && off < 5e-3,
        "fused edge off by {angle:.3} deg, {:.3} mm",
        off * 1e3
    );

    // a malformed demonstration: the command fails and the tree file is untouched
    let before = std::fs::read(&tree).unwrap();
    let bad = d.write("bad.tum", &format!("{GOOD}0.5 0 0 0 0 0 0\n"));
    let r = run(&["learn".to_string(), s(&bad), "--into".into(), s(&tree)]).fails();
    r.check(
        r.stderr.contains(&format!("{}:6: ", bad.display())),
        "the message should name bad.tum line 6",
    );
    // a good one followed by a bad one: nothing is written either
    let r = run(&[
        "learn".to_string(),
        s(&files[0]),
        s(&bad),
        "--into".into(),
        s(&tree),
    ])
    .fails();
    r.check(
        r.stderr.contains(&format!("{}:6: ", bad.display())),
        "the message should name bad.tum line 6",
    );
    assert!(
        std::fs::read(&tree).unwrap() == before,
        "a failed learn must leave box.json byte-identical"
    );
    let left = temp_leftovers(d.path(), ".box.json");
    assert!(left.is_empty(), "temporary files left behind: {left:?}");

    // a corrupt tree file is reported, not overwritten
    let corrupt = d.write("corrupt.json", "{ not json");
    let r = run(&[
        "learn".to_string(),
        s(&files[0]),
        "--into".into(),
        s(&corrupt),
    ])
    .fails();
    r.check(
        r.stderr.contains("corrupt.json"),
        "the message should name the corrupt tree file",
    );
    assert_eq!(std::fs::read_to_string(&corrupt).unwrap(), "{ not json");
    assert!(temp_leftovers(d.path(), ".corrupt.json").is_empty());

    // a tree that cannot be written (its folder does not exist): error, nothing left behind
    let nowhere = d.join("no-such-dir").join("box.json");
    let r = run(&["learn".to_string(), s(&files[0]), "-o".into(), s(&nowhere)]).fails();
    r.check(
        r.stderr.contains("box.json"),
        "the message should name the output file",
    );
    assert!(!d.join("no-such-dir").exists());
}

// ---------------------------------------------------------------------------------------------
// 5. classify's text output: per-frame labels, the paper's method

#[test]
fn classify_frames_and_paper_method() {
    let d = TempDir::new("frames");
    let files = synth("topple", d.path(), 1, 3, &[]);
    let demo = &files[0];
    let plain = run(&["classify".to_string(), s(demo)]).ok();
    plain.check(
        plain
            .stdout
            .lines()
            .next()
            .is_some_and(|l| l.contains("topple") && l.contains("robust")),
        "first line: name, kind, method",
    );
    plain.check(
        !plain.stdout.contains("frames:"),
        "no frame runs without --frames",
    );

    let r = run(&["classify".to_string(), s(demo), "--frames".into()]).ok();
    let runs: Vec<&str> = r
        .stdout
        .lines()
        .skip_while(|l| l.trim() != "frames:")
        .skip(1)
        .collect();
    r.check(!runs.is_empty(), "expected a 'frames:' section");
    let label = |l: &str| l.split_whitespace().last().unwrap_or("").to_string();
    r.check(
        runs.iter().any(|l| label(l) == "rest"),
        "expected a 'rest' run",
    );
    r.check(
        runs.iter().any(|l| label(l) == "topple"),
        "expected a 'topple' run",
    );
    // the runs cover the frames in order, without gaps: FIRST-LAST ranges
    let mut next = 0u64;
    for l in &runs {
        let range = l.split_whitespace().next().unwrap();
        let (a, b) = range
            .split_once('-')
            .unwrap_or_else(|| panic!("bad run line {l:?}"));
        let (a, b): (u64, u64) = (a.parse().unwrap(), b.parse().unwrap());
        assert_eq!(a, next, "runs should be contiguous: {l:?}");
        assert!(b >= a);
        next = b + 1;
    }
    let frames = classify_json(demo, &[])["frames"].as_u64().unwrap();
    assert_eq!(next, frames, "the runs should cover all {frames} frames");

    let r = run(&[
        "classify".to_string(),
        s(demo),
        "--method".into(),
        "paper".into(),
    ])
    .ok();
    r.check(
        r.stdout.contains("paper"),
        "the summary should say the paper's method was used",
    );
    r.check(
        r.stdout
            .lines()
            .next()
            .is_some_and(|l| l.contains("(paper method)")),
        "first line should name the paper method",
    );
    let v = classify_json(demo, &["--method", "paper"]);
    assert_eq!(v["method"], "paper");
    // an unknown method is rejected by the argument parser
    let r = run(&[
        "classify".to_string(),
        s(demo),
        "--method".into(),
        "magic".into(),
    ]);
    r.check(
        r.code == Some(2) && r.stderr.contains("magic") && !r.stderr.contains("panicked"),
        "unknown --method should be a usage error",
    );
}

// ---------------------------------------------------------------------------------------------
// 6. help

#[test]
fn help_top_level_mentions_gravity() {
    let top = run(&["--help"]).ok();
    top.check(
        top.stdout.contains("classify") && top.stdout.contains("learn"),
        "top-level help should list the commands",
    );
    top.check(top.stdout.contains("--gravity"), "top-level help should mention --gravity (README: gravity must be given for camera-frame trackers)");
}

#[test]
fn help_classify_mentions_gravity() {
    let c = run(&["classify", "--help"]).ok();
    c.check(
        c.stdout.contains("--gravity"),
        "classify help should mention --gravity",
    );
    c.check(
        c.stdout.contains("--frames") && c.stdout.contains("--json"),
        "classify help should list --frames and --json",
    );
}

#[test]
fn bad_gravity_is_a_clear_error() {
    let d = TempDir::new("gravity");
    let demo = d.write("demo.tum", GOOD);
    let r = run(&[
        "classify".to_string(),
        s(&demo),
        "--gravity".into(),
        "0,0".into(),
    ])
    .fails();
    r.check(
        r.stderr.contains("--gravity"),
        "the message should name --gravity",
    );
    let r = run(&[
        "classify".to_string(),
        s(&demo),
        "--gravity".into(),
        "0,0,0".into(),
    ])
    .fails();
    r.check(
        r.stderr.contains("--gravity") && r.stderr.contains("zero"),
        "zero gravity should be refused",
    );
    run(&[
        "classify".to_string(),
        s(&demo),
        "--gravity".into(),
        "none".into(),
    ])
    .ok();
}

// ---------------------------------------------------------------------------------------------
// 7. the learner over a slice of the standard (simulated) dataset

#[test]
fn dataset_quick_evaluate_end_to_end() {
    let d = TempDir::new("dataset");
    let data = d.join("data");
    let r = run(&[
        "dataset".to_string(),
        "-o".into(),
        s(&data),
        "--quick".into(),
        "--json".into(),
    ])
    .ok();
    let m = r.json();
    let n_demos = m["demos"].as_u64().unwrap_or(0);
    r.check(
        n_demos >= 20,
        "the quick dataset should have demonstrations",
    );
    assert!(data.join("manifest.json").is_file());

    let r = run(&["evaluate".to_string(), s(&data), "--json".into()]).ok();
    let e = r.json();
    let demos = e["demos"].as_array().expect("demos array");
    assert_eq!(
        demos.len() as u64,
        n_demos,
        "every demonstration should be evaluated"
    );
    for noise in ["clean", "real", "noisy"] {
        assert!(
            demos.iter().any(|x| x["noise"] == noise),
            "no {noise} demos"
        );
    }
    let real: Vec<&Value> = demos.iter().filter(|x| x["noise"] == "real").collect();
    let correct = real.iter().filter(|x| x["correct"] == true).count();
    assert!(!real.is_empty());
    assert!(
        correct * 10 >= real.len() * 9,
        "only {correct}/{} real-noise demos classified correctly: {:?}",
        real.len(),
        real.iter()
            .filter(|x| x["correct"] != true)
            .map(|x| x["name"].as_str().unwrap_or("?"))
            .collect::<Vec<_>>()
    );
    let topples: Vec<&Value> = demos.iter().filter(|x| x["scene"] == "topple").collect();
    assert!(!topples.is_empty(), "no topple demos");
    for t in topples {
        let deg = t["edge_direction_deg"]
            .as_f64()
            .unwrap_or_else(|| panic!("topple demo without an edge: {t}"));
        assert!(
            deg < 5.0,
            "{}: edge direction off by {deg:.2} deg",
            t["name"]
        );
    }
    assert!(
        e["fused"].as_array().is_some_and(|f| !f.is_empty()),
        "fused edges expected"
    );

    // the Markdown tables go to a file on request
    let md = d.join("eval.md");
    let r = run(&[
        "evaluate".to_string(),
        s(&data),
        "--markdown".into(),
        s(&md),
    ])
    .ok();
    r.check(
        r.stdout.contains("Classification accuracy"),
        "tables on stdout",
    );
    assert_eq!(std::fs::read_to_string(&md).unwrap(), r.stdout);

    // a folder that is not a dataset is a clear error
    let r = run(&["evaluate".to_string(), s(d.path())]).fails();
    r.check(
        r.stderr.contains("manifest.json") || r.stderr.contains(&s(d.path())),
        "the message should name the folder or its manifest",
    );
}
