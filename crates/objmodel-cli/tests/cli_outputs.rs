//! End-to-end tests of the `objmodel` binary's `classify`: its JSON contract, its text (per-frame
//! labels, the paper's method), what it says of correlated noise and of length units; and shell
//! completions. `learn`'s outputs: `cli_learn.rs`; the dataset and `evaluate`: `cli_dataset.rs`.

#[allow(unused_imports)]
mod common;
#[allow(unused_imports)]
use common::*;
#[allow(unused_imports)]
use serde_json::Value;
#[allow(unused_imports)]
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// output contract of `classify --json`

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
// classify's text output: per-frame labels, the paper's method

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
    // The noise line says where the noise came from; the JSON says it too.
    plain.check(
        plain.stdout.contains("tracking noise (estimated)"),
        "an estimated noise is called estimated",
    );
    let given = ["--noise-position=0.001", "--noise-rotation=0.01"];
    let mut args = vec!["classify".to_string(), s(demo)];
    args.extend(given.iter().map(|a| a.to_string()));
    let r = run(&args).ok();
    r.check(
        r.stdout.contains("tracking noise (given): 1.00 mm"),
        "a given noise is called given",
    );
    assert_eq!(classify_json(demo, &given)["noise_given"], true);
    assert_eq!(classify_json(demo, &[])["noise_given"], false);

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

/// `objmodel completions SHELL` prints a completion script that knows the subcommands and
/// their options; an unknown shell is a clear error.
#[test]
fn completion_scripts() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let r = run(&["completions", shell]).ok();
        for word in ["learn", "classify", "gravity", "into"] {
            r.check(
                r.stdout.contains(word),
                &format!("{shell} script should know {word}"),
            );
        }
    }
    // (an argument error: clap's message and exit code 2)
    let r = run(&["completions", "tcsh"]);
    r.check(
        r.code == Some(2) && r.stderr.contains("'tcsh'") && r.stderr.contains("bash"),
        "the message should name the shell and the ones there are",
    );
}

/// `classify --json` says what it measured of noise correlated from frame to frame
/// (`noise_correlation`): a camera's (correlated at 0.5) is found, with a long-run noise above
/// the independent one; independent noise gives none.
#[test]
fn classify_json_reports_correlated_noise() {
    let d = TempDir::new("correlated");
    let mut found = 0;
    for (noise, seed) in [("camera", 1), ("camera", 2), ("camera", 3), ("real", 1)] {
        let out = d.join(&format!("{noise}{seed}"));
        run(&[
            "simulate".to_string(),
            "slide".into(),
            "--noise".into(),
            noise.into(),
            "--seed".into(),
            seed.to_string(),
            "-q".into(),
            "-o".into(),
            s(&out),
        ])
        .ok();
        let demo = out.join(format!("slide_{noise}_s{seed}.tum"));
        let v = classify_json(&demo, &[]);
        let k = &v["noise_correlation"];
        if noise == "real" {
            assert!(k.is_null(), "independent noise: {k}");
            continue;
        }
        if k.is_null() {
            continue;
        }
        found += 1;
        let rho = k["object"]["rho"].as_f64().unwrap();
        assert!((0.2..=0.7).contains(&rho), "rho {rho}");
        let long_run = k["object"]["long_run"]["sigma_position"].as_f64().unwrap();
        let white = k["object"]["white"]["sigma_position"].as_f64().unwrap();
        assert!(long_run > 1.3 * white, "{long_run} vs {white}");
        assert_eq!(v["noise"]["sigma_position"].as_f64().unwrap(), long_run);
        assert!(v["warnings"]
            .to_string()
            .contains("correlated from frame to frame"));
    }
    assert!(found >= 2, "found in {found} of 3 camera slides");
}

// ---------------------------------------------------------------------------------------------
// Positions in millimetres: declared by a CSV header, given with --length-unit, or neither.

/// A TUM file's poses with positions times `k`, as TUM lines and as CSV lines.
fn scaled_lines(tum: &Path, k: f64) -> (String, String) {
    let (mut t, mut c) = (String::new(), String::new());
    for line in std::fs::read_to_string(tum).unwrap().lines() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let mut v: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        v[1..4].iter_mut().for_each(|x| *x *= k);
        let f: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        t += &(f.join(" ") + "\n");
        c += &(f.join(",") + "\n");
    }
    (t, c)
}

#[test]
fn length_units_declared_given_or_refused() {
    let d = TempDir::new("units");
    let file = &synth("topple", &d.join("m"), 1, 5, &[])[0];
    let metres = classify_json(file, &[]);
    assert_eq!(metres["kind"], "topple", "{metres}");
    assert!(metres.get("length_unit").is_none(), "{metres}");
    let (tum, csv) = scaled_lines(file, 1e3);
    let mm_tum = d.join("mm.tum");
    let mm_csv = d.join("mm.csv");
    std::fs::write(&mm_tum, tum).unwrap();
    std::fs::write(
        &mm_csv,
        format!("t (s),x [mm],y [mm],z [mm],qx,qy,qz,qw\n{csv}"),
    )
    .unwrap();
    let point = |v: &Value| -> Vec<f64> {
        let p = &v["topples"][0]["edge"]["line"]["point"];
        (0..3)
            .map(|k| p[k].as_f64().expect("an edge point"))
            .collect()
    };
    for v in [
        classify_json(&mm_tum, &["--length-unit", "mm"]),
        classify_json(&mm_csv, &[]),
    ] {
        assert_eq!(v["kind"], "topple", "{v}");
        assert_eq!(v["length_unit"], "mm", "{v}");
        let (a, b) = (point(&metres), point(&v));
        assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-7), "{a:?} {b:?}");
    }
    // Read as metres: nothing taught, and the report says which unit to give.
    let v = classify_json(&mm_tum, &[]);
    let why = v["withheld"]
        .as_str()
        .unwrap_or_else(|| panic!("not withheld: {v}"));
    assert!(
        why.contains("do not look like metres") && why.contains("--length-unit mm"),
        "{why}"
    );
    assert!(v["topples"].as_array().unwrap().is_empty(), "{v}");
    // The summary says what it read.
    let r = run(&["classify".to_string(), s(&mm_csv)]).ok();
    r.check(
        r.stdout
            .contains("positions read in mm, converted to metres"),
        "the summary names the unit",
    );
    // A unit that is not a length is an error naming the column.
    std::fs::write(&mm_csv, "t,x [deg],y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n").unwrap();
    let r = run(&["classify".to_string(), s(&mm_csv)]).fails();
    r.check(
        r.stderr.contains("mm.csv:1: CSV header: column 2"),
        "a unit that is no length is refused with its place",
    );
}

/// A toss whose turn over an edge a fall of a point of the object explains too (rapier, brick
/// tossed, motion-capture noise): `classify --json` lists the turn under `"rolls_rejected"`,
/// inside a motion and not in a flight, over at least five frames and turned far enough to
/// locate a line (8.6°), with why; the summary says it on a `no roll` line, one per entry.
#[test]
fn a_turn_that_is_no_roll_says_why() {
    let demo = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../objmodel/tests/data/rapier_tosses/shared_com/brick/brick_toss_mocap_s117.tum");
    let v = classify_json(&demo, &[]);
    let rejected = v["rolls_rejected"].as_array().expect("rolls_rejected");
    assert!(!rejected.is_empty());
    let parts = v["parts"].as_array().unwrap();
    for r in rejected {
        let (t0, t1) = (r["t_start"].as_f64().unwrap(), r["t_end"].as_f64().unwrap());
        assert!(r["frames"].as_u64().unwrap() >= 5, "{r}");
        assert!(r["turn"].as_f64().unwrap().to_degrees() >= 8.6, "{r}");
        assert!(r["why"].as_str().unwrap().contains("falling freely"), "{r}");
        let within =
            |p: &&Value| p["t_start"].as_f64().unwrap() <= t0 && t1 <= p["t_end"].as_f64().unwrap();
        let part = parts.iter().find(within).expect("a part holds it");
        assert!(
            !["flight", "rest", "roll"].contains(&part["kind"].as_str().unwrap()),
            "{part}"
        );
    }
    let text = run(&["classify".to_string(), s(&demo)]).ok().stdout;
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("no roll"))
        .collect();
    assert_eq!(lines.len(), rejected.len(), "{text}");
    assert!(lines[0].contains("falling freely"), "{text}");
}
