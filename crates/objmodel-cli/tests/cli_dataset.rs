//! End-to-end tests of `objmodel dataset` and `evaluate`: the noise levels asked for, and the
//! learner over a slice of the standard (simulated) dataset.

#[allow(unused_imports)]
mod common;
#[allow(unused_imports)]
use common::*;
#[allow(unused_imports)]
use serde_json::Value;
#[allow(unused_imports)]
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// the learner over a slice of the standard (simulated) dataset

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
