//! Real tosses from another lab (`tests/data/contactnets_tosses`: 58 tosses of the ContactNets
//! cube, AprilTag tracking at 148 Hz; see its README). Learnt together as a user would learn
//! them, every feature of the tree must be the cube's, and the rests at the ends of the files
//! (a tenth of a second each) must find its faces. Real contacts, not a simulator's: the cube's
//! edges are rounded, the board's friction is low (μ ≈ 0.18, its edges slide as it tumbles),
//! and each file starts in flight.

mod common;

use objmodel::learn::{Config, Learner, Source};
use objmodel::tree::Tree;
use std::path::PathBuf;

const DIR: &str = "contactnets_tosses";

fn tosses() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(common::data(DIR))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "tum"))
        .collect();
    paths.sort();
    paths
}

#[test]
fn every_feature_learnt_from_real_tosses_is_the_cubes_and_the_rests_find_its_faces() {
    let paths = tosses();
    assert_eq!(paths.len(), 58);
    let sources: Vec<Source> = paths.iter().map(Source::file).collect();
    let mut tree = Tree::default();
    Learner::new(Config::default())
        .learn(&mut tree, &sources)
        .unwrap();
    let truth = common::box_truth(&format!("{DIR}/cube.truth.json"));
    common::assert_tree_on_box(&tree, &truth, DIR);
    // Each of the six faces, found by one face of the tree.
    for (n, _) in &truth.faces {
        let found = tree
            .faces
            .iter()
            .filter(|f| f.normal.angle(n) < 5f64.to_radians())
            .count();
        assert_eq!(found, 1, "face {n:?} found {found} times: {:?}", tree.faces);
    }
}
