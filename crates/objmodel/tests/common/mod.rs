//! Shared by the tests that read MuJoCo scenes from `tests/data` (written by
//! `bench/mujoco_probe.py`).

use nalgebra::Vector3;
use objmodel::geometry::Line;
use std::path::PathBuf;

/// The path of `tests/data/{file}`.
pub fn data(file: &str) -> PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(file)
}

/// The true edge of the scene `name` (`{name}.truth.json`), in the tracked frame. (Not every
/// test binary that includes this module reads one.)
#[allow(dead_code)]
pub fn truth_edge(name: &str) -> Line {
    let truth = truth(name);
    Line::through(
        vec3(&truth["edge"]["point"]),
        vec3(&truth["edge"]["direction"]),
    )
}

/// A JSON array of three numbers as a vector.
#[allow(dead_code)]
pub fn vec3(a: &serde_json::Value) -> Vector3<f64> {
    let a = a.as_array().unwrap();
    Vector3::new(
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    )
}

/// The true φ \[rad\] of the scene `name` (`{name}.truth.json`: the homogeneous box's, about
/// its truth edge from the face it rests on).
#[allow(dead_code)]
pub fn truth_phi(name: &str) -> f64 {
    truth(name)["phi"].as_f64().unwrap()
}

/// The scene `name`'s truth file, `{name}.truth.json`.
#[allow(dead_code)]
fn truth(name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(data(&format!("{name}.truth.json"))).unwrap())
        .unwrap()
}

/// Assert that two classifications taught the same edges, in order, to within `tol` (metres
/// for points, unit vectors' difference for directions).
#[allow(dead_code)]
pub fn assert_same_edges(
    a: &objmodel::classify::Classification,
    b: &objmodel::classify::Classification,
    tol: f64,
) {
    assert_eq!(a.edges().count(), b.edges().count());
    for (x, y) in a.edges().zip(b.edges()) {
        assert!((x.line.point - y.line.point).norm() < tol, "{x:?} {y:?}");
        assert!(
            (x.line.direction - y.line.direction).norm() < tol,
            "{x:?} {y:?}"
        );
    }
}

/// A box's faces (outward normal, offset) and edges (point, direction) in its tag's frame, as
/// the probes with other simulators write them (`bench/mujoco_tosses.py`'s `write_truth`).
#[allow(dead_code)]
pub struct BoxTruth {
    pub faces: Vec<(Vector3<f64>, f64)>,
    pub edges: Vec<(Vector3<f64>, Vector3<f64>)>,
}

/// The box truth `tests/data/{file}`.
#[allow(dead_code)]
pub fn box_truth(file: &str) -> BoxTruth {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data(file)).unwrap()).unwrap();
    let faces = json["faces"].as_array().unwrap();
    let edges = json["edges"].as_array().unwrap();
    BoxTruth {
        faces: faces
            .iter()
            .map(|f| (vec3(&f["normal"]), f["offset"].as_f64().unwrap()))
            .collect(),
        edges: edges
            .iter()
            .map(|e| (vec3(&e["point"]), vec3(&e["direction"])))
            .collect(),
    }
}

/// Assert that every face and edge of `tree` is one of the box's, as `bench/precision.py`
/// counts them: a face within 5° (and, with an offset, 5 mm), an edge within 3° and 5 mm.
#[allow(dead_code)]
pub fn assert_tree_on_box(tree: &objmodel::tree::Tree, truth: &BoxTruth, name: &str) {
    for f in &tree.faces {
        let on_box = truth.faces.iter().any(|(n, d)| {
            f.normal.angle(n) < 5f64.to_radians() && f.offset.is_none_or(|o| (o - d).abs() < 5e-3)
        });
        assert!(
            on_box,
            "{name}: face {} {:?} is no face of the box",
            f.id, f.normal
        );
    }
    for e in &tree.edges {
        let on_box = truth.edges.iter().any(|(p, u)| {
            let off = e.point - p;
            let across = off - u * u.dot(&off);
            e.direction.dot(u).abs().min(1.0).acos() < 3f64.to_radians() && across.norm() < 5e-3
        });
        assert!(on_box, "{name}: edge {} is no edge of the box", e.id);
    }
}

/// Learn `tests/data/{stem}.tum` alone (default configuration, no palm) and assert that the
/// tree holds no feature off the box of `{stem}.truth.json` ([`assert_tree_on_box`]); its
/// classification, for further checks.
#[allow(dead_code)]
pub fn learn_alone_on_box(stem: &str) -> objmodel::classify::Classification {
    use objmodel::learn::{Config, Learner, Source};
    let truth = box_truth(&format!("{stem}.truth.json"));
    let object = data(&format!("{stem}.tum"));
    let mut tree = objmodel::tree::Tree::default();
    let mut reports = Learner::new(Config::default())
        .learn(&mut tree, &[Source::file(&object)])
        .unwrap();
    assert_tree_on_box(&tree, &truth, stem);
    reports.remove(0).classification
}

/// The `.tum` files in `tests/data/{dir}`, sorted by name.
#[allow(dead_code)]
pub fn tum_files(dir: &str) -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> = std::fs::read_dir(data(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "tum"))
        .collect();
    all.sort();
    all
}

/// `paths` learnt together (default configuration, no palm): the tree and each file's report.
#[allow(dead_code)]
pub fn learn_files(
    paths: &[PathBuf],
) -> (
    objmodel::tree::Tree,
    Vec<objmodel::observation::Observation>,
) {
    let mut tree = objmodel::tree::Tree::default();
    let reports = learn_into(objmodel::learn::Config::default(), &mut tree, paths);
    (tree, reports)
}

/// `paths` learnt together under `config` (no palm) into `tree`: each file's report.
#[allow(dead_code)]
pub fn learn_into(
    config: objmodel::learn::Config,
    tree: &mut objmodel::tree::Tree,
    paths: &[PathBuf],
) -> Vec<objmodel::observation::Observation> {
    use objmodel::learn::{Learner, Source};
    let sources: Vec<Source> = paths.iter().map(Source::file).collect();
    Learner::new(config).learn(tree, &sources).unwrap()
}

/// The report of the demonstration named `name` among `reports`.
#[allow(dead_code)]
pub fn report<'a>(
    reports: &'a [objmodel::observation::Observation],
    name: &str,
) -> &'a objmodel::observation::Observation {
    reports
        .iter()
        .find(|o| o.classification.name == name)
        .unwrap()
}
