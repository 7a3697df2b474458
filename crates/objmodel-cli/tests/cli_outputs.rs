//! End-to-end tests of the `objmodel` binary: the output contracts of `classify` and `learn`,
//! incremental and atomic tree updates, per-frame labels, and `evaluate` on a simulated dataset.

#[allow(unused_imports)]
mod common;
#[allow(unused_imports)]
use common::*;
#[allow(unused_imports)]
use serde_json::Value;
#[allow(unused_imports)]
use std::path::{Path, PathBuf};

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

// ---------------------------------------------------------------------------------------------
// 7. the learner over a slice of the standard (simulated) dataset

/// `dataset --noise` makes the levels asked for, and the truth says what noise each has.
#[test]
fn dataset_makes_the_noise_levels_asked_for() {
    let d = TempDir::new("dataset-noise");
    let data = d.join("data");
    run(&[
        "dataset".to_string(),
        "-o".into(),
        s(&data),
        "--quick".into(),
        "--noise".into(),
        "clean,camera".into(),
    ])
    .ok();
    let manifest = read_json(&data.join("manifest.json"));
    let demos = manifest["demos"].as_array().expect("demos");
    let mut levels: Vec<&str> = demos.iter().filter_map(|x| x["noise"].as_str()).collect();
    levels.sort();
    levels.dedup();
    assert_eq!(levels, ["camera", "clean"], "levels made");
    let camera = demos.iter().find(|x| x["noise"] == "camera").unwrap();
    let truth = read_json(&data.join(camera["truth"].as_str().unwrap()));
    assert_eq!(truth["noise"]["sight_ratio"], 3.0, "{}", truth["noise"]);
    assert_eq!(truth["noise"]["correlation"], 0.5, "{}", truth["noise"]);
    // The correlation and the sight ratio, at any level.
    let other = d.join("other");
    run(&[
        "dataset".to_string(),
        "-o".into(),
        s(&other),
        "--quick".into(),
        "--noise".into(),
        "real".into(),
        "--correlation".into(),
        "0.3".into(),
        "--sight-ratio".into(),
        "2".into(),
    ])
    .ok();
    let manifest = read_json(&other.join("manifest.json"));
    let real = manifest["demos"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["noise"] == "real")
        .unwrap();
    let truth = read_json(&other.join(real["truth"].as_str().unwrap()));
    assert_eq!(truth["noise"]["correlation"], 0.3, "{}", truth["noise"]);
    assert_eq!(truth["noise"]["sight_ratio"], 2.0, "{}", truth["noise"]);
    let r = run(&["dataset", "-o", &s(&other), "--correlation", "1"]);
    r.check(
        r.code == Some(2) && r.stderr.contains("correlation in [0, 1)"),
        "a correlation of 1 is refused",
    );
    let r = run(&["dataset", "-o", &s(&data), "--noise", "loud"]);
    r.check(
        r.code == Some(2) && r.stderr.contains("'loud'") && r.stderr.contains("camera"),
        "an unknown level is refused, naming the levels there are",
    );
}

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

    // the Markdown tables go to a file on request, after the file's hand-written header,
    // which a second run keeps too
    let md = d.join("eval.md");
    let header = "# Our learner\n\nWritten by hand.\n";
    std::fs::write(&md, header).unwrap();
    for _ in 0..2 {
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
        let page = std::fs::read_to_string(&md).unwrap();
        assert!(page.starts_with(header), "{page}");
        assert!(page.ends_with(&r.stdout), "{page}");
        assert_eq!(page.matches("Classification accuracy").count(), 1);
    }

    // calibrate: every sample names its quantity, set and noise level and has a z; the table
    // goes after the page's header like evaluate's
    let r = run(&["calibrate".to_string(), s(&data), "--json".into()]).ok();
    let samples = r.json();
    let samples = samples.as_array().expect("samples array");
    for q in ["phi", "edge_point", "edge_direction", "face_offset"] {
        r.check(
            samples
                .iter()
                .any(|x| x["quantity"] == q && x["set"] == "demo"),
            &format!("no {q} sample"),
        );
    }
    for x in samples {
        assert!(x["error"].as_f64().is_some_and(|e| e >= 0.0), "{x}");
        assert!(x["noise"].is_string() && x["source"].is_string(), "{x}");
    }
    let cal = d.join("calibration.md");
    std::fs::write(&cal, header).unwrap();
    let r = run(&[
        "calibrate".to_string(),
        s(&data),
        "--markdown".into(),
        s(&cal),
    ])
    .ok();
    let page = std::fs::read_to_string(&cal).unwrap();
    r.check(
        page.starts_with(header) && page.contains("| phi |"),
        "calibration table",
    );

    // a folder that is not a dataset is a clear error
    let r = run(&["evaluate".to_string(), s(d.path())]).fails();
    r.check(
        r.stderr.contains("manifest.json") || r.stderr.contains(&s(d.path())),
        "the message should name the folder or its manifest",
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
