//! The learnt object in objmodel's own simulator: the URDF that `objmodel export` writes, read
//! back with urdf-rs and built in f64, is the exported body; a scene runs with a learnt body
//! in place of a specified box and its truth is in the model's frame.

use nalgebra::{Point3, Vector3};
use objmodel::export::{urdf::urdf, Body};
use objmodel::shape::{reconstruct, LearntFace};
use objmodel_sim::claims::truth_body;
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::learnt::learnt_spec;
use objmodel_sim::rigid::{Geometry, RigidModel};
use objmodel_sim::{simulate, SceneKind, TrackerNoise};

/// Every corner of `a` has one of `b` within `tol` \[m\], and the other way round.
fn same_corners(a: &RigidModel, b: &RigidModel, tol: f64) -> bool {
    let near = |p: &Vector3<f64>, set: &[Vector3<f64>]| set.iter().any(|q| (p - q).norm() < tol);
    let (ca, cb) = (a.corners(), b.corners());
    ca.iter().all(|p| near(p, &cb)) && cb.iter().all(|p| near(p, &ca))
}

/// The box of the standard "weighted" box, and the same box with a corner cut off (a shape
/// that is not a box: a mesh in the URDF), each written as URDF and read back.
#[test]
fn the_urdf_read_back_is_the_exported_body() {
    let spec = standard_boxes()
        .into_iter()
        .find(|b| b.name == "weighted")
        .unwrap();
    let boxed = truth_body(&spec);
    let mut faces: Vec<LearntFace> = boxed
        .shape
        .faces
        .iter()
        .map(|f| LearntFace {
            id: f.id.clone(),
            normal: f.normal,
            outward: true,
            offset: Some(f.offset),
            offset_sigma_m: 1e-3,
            normal_sigma_rad: 0.01,
        })
        .collect();
    let corner = boxed.shape.vertices[0];
    let centre = boxed.shape.vertices.iter().sum::<Vector3<f64>>() / 8.0;
    let n = (corner - centre).normalize();
    faces.push(LearntFace {
        id: "cut".into(),
        normal: n,
        outward: true,
        offset: Some(n.dot(&corner) - 0.01),
        offset_sigma_m: 1e-3,
        normal_sigma_rad: 0.01,
    });
    let cut_shape = reconstruct(&faces).unwrap();
    assert_eq!(cut_shape.vertices.len(), 10);
    let cut = Body {
        box_fit: None,
        shape: cut_shape,
        ..boxed.clone()
    };
    let dir = tempfile::tempdir().unwrap();
    for (name, body) in [("box", &boxed), ("cut", &cut)] {
        let (text, mesh) = urdf(body, name, &format!("{name}.obj"));
        assert_eq!(mesh.is_some(), body.box_fit.is_none());
        if let Some(m) = mesh {
            std::fs::write(dir.path().join(format!("{name}.obj")), m).unwrap();
        }
        let path = dir.path().join(format!("{name}.urdf"));
        std::fs::write(&path, text).unwrap();
        let read = objmodel_sim::urdf_body::read(&path, 0.9).unwrap();
        let want = RigidModel::of_body(body);
        assert_eq!(
            matches!(read.geometry, Geometry::Cuboid { .. }),
            body.box_fit.is_some()
        );
        assert!((read.mass - body.mass_kg).abs() < 1e-12);
        assert!((read.com - body.com).norm() < 1e-12);
        assert!((read.inertia - body.inertia).norm() < 1e-12 * body.inertia.norm().max(1.0));
        assert!(same_corners(&read, &want, 1e-9), "{name}");
        assert!(read
            .builders(0.9, &nalgebra::Isometry3::identity())
            .is_some());
    }
    // A bad file is an error naming it, not a panic.
    let bad = dir.path().join("bad.urdf");
    std::fs::write(&bad, "<robot name='x'><link name='l'/></robot>").unwrap();
    let e = objmodel_sim::urdf_body::read(&bad, 0.9)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.urdf"), "{e}");
}

/// An instrumented topple of the learnt body of the offset-CoM box: the truth the scene writes
/// is in the model's (tag) frame: its CoM is the body's, its edge one of the box's edges, and
/// the palm tilted to within a degree of the tipping angle before it toppled.
#[test]
fn a_scene_runs_with_the_learnt_object() {
    let spec = standard_boxes()
        .into_iter()
        .find(|b| b.name == "weighted")
        .unwrap();
    let body = truth_body(&spec);
    let learnt = learnt_spec(&body, "learnt");
    learnt.validate().unwrap();
    for (kind, seed) in [(SceneKind::InstrumentedTopple, 1), (SceneKind::Topple, 2)] {
        let demo = simulate(kind, &learnt, &TrackerNoise::clean(), seed).unwrap();
        let t = &demo.truth;
        assert!((Vector3::from(t.com) - body.com).norm() < 1e-9);
        let e = t.edge.expect("a topple has an edge");
        for p in [e.p0, e.p1] {
            let p = Vector3::from(p);
            let nearest = body
                .shape
                .vertices
                .iter()
                .map(|v| (v - p).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest < 1e-6,
                "{kind:?}: edge end {p} is no corner ({nearest} m)"
            );
        }
        if let (Some(tilt), Some(phi)) = (t.palm_tilt_at_start_deg, t.phi_deg) {
            assert!((tilt - phi).abs() < 1.0, "tilt {tilt} vs phi {phi}");
        }
        // The tag frame the scene tracked is the object frame: the first pose puts the CoM
        // above the support.
        let first = demo.object_clean[0].pose;
        let com_world = first * Point3::from(body.com);
        assert!(com_world.z > 0.0);
    }
}
