//! End-to-end tests of `objmodel learn`: the tree it prints and writes (its schema, against the
//! simulator's truth), and incremental and atomic updates of a model file.

#[allow(unused_imports)]
mod common;
#[allow(unused_imports)]
use common::*;
#[allow(unused_imports)]
use serde_json::Value;
#[allow(unused_imports)]
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// `learn --json`: the tree and its schema

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
// incremental and atomic updates

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
// Motive takes holding the object and the palm

/// An OptiTrack Motive take (CSV export, metres) of the TUM files `bodies` (name, file): one
/// row per stamp of any of them, a body's fields empty where it has no pose at that stamp.
fn motive_take(bodies: &[(&str, &Path)]) -> String {
    let poses: Vec<Vec<Vec<String>>> = bodies
        .iter()
        .map(|(_, f)| {
            std::fs::read_to_string(f)
                .unwrap()
                .lines()
                .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
                .map(|l| l.split_whitespace().map(str::to_string).collect())
                .collect()
        })
        .collect();
    let mut stamps: Vec<String> = poses.iter().flatten().map(|p| p[0].clone()).collect();
    stamps.sort_by(|a, b| a.parse::<f64>().unwrap().total_cmp(&b.parse().unwrap()));
    stamps.dedup();
    let row = |cells: &[&str]| format!(",{}", cells.join(","));
    let mut text = String::from(
        "Format Version,1.23,Take Name,t,Rotation Type,Quaternion,Length Units,Meters\n\n",
    );
    let mut rows = [",Type", ",Name", ",ID", ",", "Frame,Time (Seconds)"].map(String::from);
    for (k, (name, _)) in bodies.iter().enumerate() {
        rows[0] += &row(&["Rigid Body"; 7]);
        rows[1] += &row(&[*name; 7]);
        rows[2] += &row(&[k.to_string().as_str(); 7]);
        rows[3] += ",Rotation,Rotation,Rotation,Rotation,Position,Position,Position";
        rows[4] += ",X,Y,Z,W,X,Y,Z";
    }
    text += &(rows.join("\n") + "\n");
    for (frame, t) in stamps.iter().enumerate() {
        text += &format!("{frame},{t}");
        for body in &poses {
            match body.iter().find(|p| &p[0] == t) {
                // TUM: t tx ty tz qx qy qz qw; Motive: rotation X Y Z W, then position.
                Some(p) => text += &row(&[&p[4], &p[5], &p[6], &p[7], &p[1], &p[2], &p[3]]),
                None => text += &",".repeat(7),
            }
        }
        text += "\n";
    }
    text
}

/// `classify` and `learn` read the object and the palm of a Motive take by their rigid bodies'
/// names, and learn what the same poses in two files teach; without the names, the take is
/// refused with them.
#[test]
fn motive_takes_name_the_object_and_the_palm() {
    let d = TempDir::new("takes");
    let files = synth("instrumented", d.path(), 2, 3, &[]);
    let takes: Vec<PathBuf> = files
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let palm = f.with_file_name(format!(
                "{}.palm.tum",
                f.file_stem().unwrap().to_string_lossy()
            ));
            d.write(
                &format!("take{k}.csv"),
                &motive_take(&[("hand", &palm), ("box", f)]),
            )
        })
        .collect();
    let from_files = run(&["classify", &s(&files[0]), "--json"]).ok().json();
    let take = s(&takes[0]);
    let args = [
        "classify", &take, "--object", "box", "--palm", "hand", "--json",
    ];
    let from_take = run(&args).ok().json();
    assert_eq!(from_take["kind"], from_files["kind"]);
    assert_eq!(from_take["instrumented"], true);
    assert_eq!(from_take["rigid_bodies"]["object"], "box");
    assert_eq!(from_take["rigid_bodies"]["palm"], "hand");
    let edge = |v: &Value| vec3(&v["topples"][0]["edge"]["line"]["point"], "edge point");
    assert!(dist(edge(&from_take), edge(&from_files)) < 1e-9);
    // Several takes learnt at once, each read by the same names.
    let mut args: Vec<String> = vec!["learn".into()];
    args.extend(takes.iter().map(|t| s(t)));
    args.extend(["--object", "box", "--palm", "hand", "--json"].map(String::from));
    let tree = run(&args).ok().json();
    assert!(!tree["edges"].as_array().unwrap().is_empty(), "{tree}");
    // Unnamed: refused, with the names it holds.
    let r = run(&["classify", &take]).fails();
    assert!(
        r.stderr.contains("2 rigid bodies (hand, box)"),
        "{}",
        r.stderr
    );
    // --split is a bag's.
    let r = run(&["classify", &take, "--object", "box", "--split"]).fails();
    assert!(r.stderr.contains("are for bags"), "{}", r.stderr);
}

/// `--quat-order wxyz` reads TUM files written w first as they were written: the same
/// classification as the file written x y z w; an order that is neither is refused. Without
/// it, such a file teaches nothing (read x y z w its topple is no rotation about a line, which
/// read w first it is) and says which order to give.
#[test]
fn quat_order_reads_w_first_tum_files() {
    let d = TempDir::new("quat-order");
    let files = synth("topple", d.path(), 1, 4, &[]);
    let text = std::fs::read_to_string(&files[0]).unwrap();
    let w_first: String = text
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            if l.starts_with('#') || f.len() != 8 {
                return format!("{l}\n");
            }
            format!(
                "{} {} {} {} {} {} {} {}\n",
                f[0], f[1], f[2], f[3], f[7], f[4], f[5], f[6]
            )
        })
        .collect();
    let w = d.write("w_first.tum", &w_first);
    let x = run(&["classify", &s(&files[0]), "--json"]).ok().json();
    let given = run(&["classify", &s(&w), "--quat-order", "wxyz", "--json"])
        .ok()
        .json();
    assert_eq!(given["kind"], x["kind"]);
    assert_eq!(given["labels"], x["labels"]);
    let edge = |v: &Value| vec3(&v["topples"][0]["edge"]["line"]["point"], "edge point");
    assert!(dist(edge(&given), edge(&x)) < 1e-9);
    assert!(given["withheld"].is_null(), "{given}");
    let misread = run(&["classify", &s(&w), "--json"]).ok().json();
    let why = misread["withheld"].as_str().unwrap_or_default();
    assert!(
        why.contains("written in w x y z order") && why.contains("--quat-order wxyz"),
        "{misread}"
    );
    let tree = run(&["learn", &s(&w), "--json"]).ok().json();
    assert_eq!(tree["edges"].as_array().map(Vec::len), Some(0), "{tree}");
    assert_eq!(tree["faces"].as_array().map(Vec::len), Some(0), "{tree}");
    // An argument error: clap's message (with ours) and exit code 2.
    let r = run(&["classify", &s(&w), "--quat-order", "wzyx"]);
    assert!(
        r.code == Some(2) && r.stderr.contains("unknown quaternion order \"wzyx\""),
        "{}",
        r.stderr
    );
}

/// `--support-height`: real tosses (the ContactNets cube, `objmodel`'s
/// `tests/data/contactnets_tosses`) learnt with the board's height give every face an offset
/// and the tree a shape, as the README says; a σ without a height, or a height that is not a
/// number, is refused.
#[test]
fn learn_with_the_supports_height_gives_the_tossed_cube_its_shape() {
    let data =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../objmodel/tests/data/contactnets_tosses");
    let mut files: Vec<String> = std::fs::read_dir(&data)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "tum"))
        .map(|p| s(&p))
        .collect();
    files.sort();
    let mut args = vec!["learn".to_string()];
    args.extend(files.iter().cloned());
    let with = |extra: &[&str]| {
        let mut a = args.clone();
        a.extend(extra.iter().map(|x| x.to_string()));
        a
    };
    let t = run(&with(&[
        "--json",
        "--support-height",
        "0",
        "--support-sigma",
        "0.001",
    ]))
    .ok()
    .json();
    let faces = t["faces"].as_array().unwrap();
    assert_eq!(faces.len(), 6);
    for f in faces {
        let d = f["offset"].as_f64().expect("an offset");
        assert!((d - 0.0524).abs() < 5e-3, "{f}");
    }
    assert_eq!(t["support"]["given"], true);
    assert_eq!(t["shape"]["vertices"].as_array().unwrap().len(), 8);
    let summary = run(&with(&["--support-height", "0"])).ok();
    summary.check(
        summary
            .stdout
            .contains("support: height +0.0000 m ±1.00 mm (given)"),
        "the summary shows the support given",
    );
    let without = run(&with(&["--json"])).ok().json();
    assert!(without["faces"]
        .as_array()
        .unwrap()
        .iter()
        .all(|f| f["offset"].is_null()));
    // (clap's own message, not objmodel's.)
    let r = run(&with(&["--support-sigma", "0.001"]));
    r.check(
        r.code == Some(2) && r.stderr.contains("--support-height"),
        "a σ alone names the height it needs",
    );
    let r = run(&with(&["--support-height", "nan"])).fails();
    r.check(
        r.stderr.contains("must be finite"),
        "a height that is not a number is refused",
    );
}

/// `learn --keep-going`: a file that cannot be read is left out with its error (file, line,
/// problem), the model is written from the others as `learn` of those alone writes it, and the
/// exit status is an error's; without the option, nothing is written.
#[test]
fn keep_going_learns_the_readable_demonstrations() {
    let d = TempDir::new("keepgoing");
    let mut files = synth("topple", d.path(), 2, 5, &[]);
    let broken = d.write("broken.tum", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
    let (strict, kept, alone) = (
        d.join("strict.json"),
        d.join("kept.json"),
        d.join("alone.json"),
    );
    run(&[
        vec!["learn".to_string(), "-o".into(), s(&alone)],
        files.iter().map(|f| s(f)).collect(),
    ]
    .concat())
    .ok();
    files.insert(1, broken.clone());
    let args = |out: &Path, keep: bool| {
        let mut a = vec!["learn".to_string(), "-o".into(), s(out)];
        a.extend(keep.then(|| "--keep-going".to_string()));
        a.extend(files.iter().map(|f| s(f)));
        a
    };
    let r = run(&args(&strict, false)).fails();
    r.check(!strict.exists(), "nothing written without --keep-going");
    let r = run(&args(&kept, true));
    r.check(r.code == Some(2), "an error's exit status");
    let place = format!("error: {}:2: expected 8 columns", broken.display());
    r.check(
        r.stderr.contains(&place),
        "the broken file's error, with its line",
    );
    r.check(
        r.stderr
            .contains("objmodel: error: 1 demonstration could not be read and left out"),
        "the closing error",
    );
    let (a, b) = (read_json(&kept), read_json(&alone));
    r.check(
        a["edges"] == b["edges"] && a["faces"] == b["faces"],
        "the others' model",
    );
    r.check(
        a["edges"].as_array().is_some_and(|e| !e.is_empty()),
        "edges learnt",
    );
}
