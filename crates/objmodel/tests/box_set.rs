//! One box pushed over 24 times in MuJoCo (`bench/mujoco_box_set.py`, seed 11: a finger pushes
//! it from its axis-aligned rests; 30 Hz, 1 mm and 0.5° tracking noise), the files in
//! `tests/data/mujoco_box_set_30hz` with the box's edges and faces in the tag frame
//! (`box.truth.json`). Another simulator's contacts (soft, the pivot sliding as the box falls),
//! learnt as a user would learn a box's demonstrations: every feature of the tree must be the
//! box's (5 mm and 3° for an edge, 5° and 5 mm for a face), and no push learnt alone may teach
//! an edge off the box at a σ that says it is on it.

mod common;

use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector3};
use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::tree::{Edge, Tree};
use std::path::PathBuf;

const DIR: &str = "mujoco_box_set_30hz";

/// A true edge (point, direction) or face (outward normal, offset), in the tag frame.
struct Truth {
    edges: Vec<(Vector3<f64>, Vector3<f64>)>,
    faces: Vec<(Vector3<f64>, f64)>,
}

fn truth() -> Truth {
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(common::data(&format!("{DIR}/box.truth.json"))).unwrap(),
    )
    .unwrap();
    let v = common::vec3;
    Truth {
        edges: json["edges"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| (v(&e["point"]), v(&e["direction"])))
            .collect(),
        faces: json["faces"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| (v(&f["normal"]), f["offset"].as_f64().unwrap()))
            .collect(),
    }
}

fn pushes() -> Vec<PathBuf> {
    (1..=24)
        .map(|k| common::data(&format!("{DIR}/push_{k}.tum")))
        .collect()
}

fn learnt(paths: &[PathBuf]) -> Tree {
    let learner = Learner::new(Config::default());
    let sources: Vec<Source> = paths
        .iter()
        .map(|p| Source::Files {
            object: p,
            palm: None,
        })
        .collect();
    let mut tree = Tree::default();
    learner.learn(&mut tree, &sources).unwrap();
    tree
}

/// The nearest true edge to `e`: its distance \[m\] normal to `e`, the angle \[rad\] between
/// them, and the χ²₂ of that distance under the edge's point covariance.
fn nearest_edge(e: &Edge, truth: &Truth) -> (f64, f64, f64) {
    let u = e.direction;
    let axes = Matrix3x2::from_columns(&objmodel::geometry::normal_axes(&u));
    let cov = axes.transpose() * Matrix3::from_fn(|i, j| e.point_cov[i][j]) * axes;
    truth
        .edges
        .iter()
        .map(|(q, v)| {
            let d = axes.transpose() * (e.point - q);
            let angle = u.cross(v).norm().atan2(u.dot(v).abs());
            let chi2 = (d.transpose() * cov.try_inverse().unwrap_or(Matrix2::zeros()) * d)[0];
            (d.norm(), angle, chi2)
        })
        .min_by(|x, y| {
            (x.0 / 5e-3 + x.1.to_degrees() / 3.0).total_cmp(&(y.0 / 5e-3 + y.1.to_degrees() / 3.0))
        })
        .unwrap()
}

/// All 24 pushes learnt together: every edge and face of the tree is the box's, and the tree
/// holds most of the edges the pushes turned the box about.
#[test]
fn a_box_pushed_over_in_mujoco_teaches_only_its_own_features() {
    let truth = truth();
    let tree = learnt(&pushes());
    for e in &tree.edges {
        let (d, angle, _) = nearest_edge(e, &truth);
        assert!(
            d < 5e-3 && angle < 3f64.to_radians(),
            "edge {} is {:.1} mm and {:.1}° from the box's nearest edge",
            e.id,
            d * 1e3,
            angle.to_degrees()
        );
    }
    for f in &tree.faces {
        let (angle, off) = truth
            .faces
            .iter()
            .map(|(n, d)| {
                let c = if f.sign_known {
                    f.normal.dot(n)
                } else {
                    f.normal.dot(n).abs()
                };
                (c.clamp(-1.0, 1.0).acos(), f.offset.map(|o| (o - d).abs()))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .unwrap();
        assert!(
            angle < 5f64.to_radians() && off.is_none_or(|o| o < 5e-3),
            "face {} is {:.1}° and {:?} m from the box's nearest face",
            f.id,
            angle.to_degrees(),
            off
        );
    }
    // The pushes turned the box about 11 of its edges; measured with this data: 9 learnt,
    // each within 2.4 mm and 0.6°.
    assert!(tree.edges.len() >= 8, "{} edges", tree.edges.len());
    assert!(tree.faces.len() >= 5, "{} faces", tree.faces.len());
}

/// Each push learnt alone: an edge may be off the box (a 30 Hz push's fall is a few frames,
/// and MuJoCo's soft contact moves the pivot), but then its own σ says so: none is off by more
/// than 5 mm or 3° at a χ²₂ beyond 13.8 (10⁻³), a feature reported with a confidence it does
/// not deserve.
#[test]
fn a_push_learnt_alone_is_never_confidently_off_the_box() {
    let truth = truth();
    let mut edges = 0;
    for p in pushes() {
        let tree = learnt(std::slice::from_ref(&p));
        for e in &tree.edges {
            edges += 1;
            let (d, angle, chi2) = nearest_edge(e, &truth);
            let off = d >= 5e-3 || angle >= 3f64.to_radians();
            assert!(
                !off || chi2 < 13.8,
                "{}: edge {} is {:.1} mm and {:.1}° off the box at χ²₂ {chi2:.1}",
                p.display(),
                e.id,
                d * 1e3,
                angle.to_degrees()
            );
        }
    }
    assert!(edges >= 12, "{edges} edges from 24 pushes");
}
