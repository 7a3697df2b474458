//! The README's example commands run as written, on the outputs of `objmodel demo`: a new
//! user who copies them into a shell in a folder with their demonstrations gets no error.
//!
//! The folder is laid out as the README's names say: `demos/` holds the demo's demonstrations
//! (with their palm files), `demo.tum` is an instrumented one (with `demo.palm.tum`), and
//! `new_demo.tum` another. Every `objmodel ...` line of the README's `sh` blocks is run with
//! `sh` in that folder (globs expanded as a shell would), in order, except the few that take
//! minutes or need another model and have tests of their own (listed in `SLOW`).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Commands not run here, with the test that covers them instead: those that take minutes,
/// and the export, which needs a closed shape (the demo's box shows 3 of its 6 faces).
const SLOW: [(&str, &str); 6] = [
    (
        "objmodel learn session.mcap",
        "objmodel's tests/bags.rs, which writes such a bag (this folder has none)",
    ),
    ("objmodel dataset", "objmodel-sim's tests/dataset.rs"),
    ("objmodel evaluate", "objmodel-sim's tests/dataset.rs"),
    (
        "objmodel calibrate",
        "objmodel-cli's tests/cli_dataset.rs and objmodel-sim's tests/calibration.rs",
    ),
    ("objmodel task", "objmodel-sim's tests/task.rs"),
    ("objmodel export", "objmodel's tests/export.rs"),
];

/// The `objmodel` command lines in the README's `sh` blocks, comments cut.
fn readme_commands() -> Vec<String> {
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md");
    let text = std::fs::read_to_string(&readme).expect("README.md");
    let mut in_sh = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if let Some(lang) = line.strip_prefix("```") {
            in_sh = !in_sh && lang.trim() == "sh";
            continue;
        }
        let command = line.split(" #").next().unwrap_or("").trim();
        if in_sh && command.starts_with("objmodel ") {
            out.push(command.to_string());
        }
    }
    out
}

fn copy(from: &Path, to: &Path) {
    std::fs::copy(from, to)
        .unwrap_or_else(|e| panic!("{} -> {}: {e}", from.display(), to.display()));
}

#[test]
fn the_readme_commands_run_as_written() {
    let commands = readme_commands();
    for needed in ["classify", "learn", "plot", "plan", "simulate"] {
        assert!(
            commands
                .iter()
                .any(|c| c.starts_with(&format!("objmodel {needed} "))),
            "the README shows no `objmodel {needed}`: {commands:#?}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    common::run_in(
        Some(dir),
        &["demo", "-o", "report", "--task-boxes", "0", "--seed", "1"],
    )
    .ok();
    let demos = dir.join("demos");
    std::fs::create_dir(&demos).unwrap();
    let mut instrumented: Vec<PathBuf> = Vec::new();
    let mut all: Vec<PathBuf> = Vec::new();
    for entry in std::fs::read_dir(dir.join("report/demos")).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".tum") {
            copy(&p, &demos.join(&name));
            if name.ends_with(".palm.tum") {
                instrumented.push(p.with_file_name(name.replace(".palm.tum", ".tum")));
            } else {
                all.push(p);
            }
        }
    }
    instrumented.sort();
    all.sort();
    let demo = &instrumented[0];
    copy(demo, &dir.join("demo.tum"));
    copy(
        &demo.with_file_name(
            demo.file_name()
                .unwrap()
                .to_string_lossy()
                .replace(".tum", ".palm.tum"),
        ),
        &dir.join("demo.palm.tum"),
    );
    let other = all.iter().find(|p| *p != demo).expect("another demo");
    copy(other, &dir.join("new_demo.tum"));

    let bin_dir = Path::new(env!("CARGO_BIN_EXE_objmodel")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    for command in &commands {
        if let Some((_, covered)) = SLOW.iter().find(|(p, _)| command.starts_with(p)) {
            eprintln!("skipped (minutes; covered by {covered}): {command}");
            continue;
        }
        let out = Command::new("sh")
            .arg("-c")
            .arg(command)
            .current_dir(dir)
            .env("PATH", &path)
            .output()
            .expect("sh");
        assert!(
            out.status.success(),
            "README command failed: {command}\nstdout:\n{}\nstderr:\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        eprintln!("ran: {command}");
        ran += 1;
    }
    assert!(ran >= 7, "only {ran} commands ran");
    // What they wrote is there: the tree, with the demonstrations and the one fused later.
    let tree = common::read_json(&dir.join("box.json"));
    let names: Vec<&str> = tree["demos"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"new_demo.tum"), "{names:?}");
    assert!(dir.join("plots/demo.angles.svg").exists());
}
