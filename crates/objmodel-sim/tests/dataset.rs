//! The data set writer end to end, and the ground truth's consistency with the clean poses.

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use objmodel::StampedPose;
use objmodel_sim::dataset::{standard_boxes, standard_dataset};
use objmodel_sim::{write_dataset, SceneKind, TrackerNoise, Truth};
use rand::SeedableRng;

#[test]
fn small_dataset_round_trips_through_the_core_reader() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let mut plan = standard_dataset(true);
    plan.boxes = vec![standard_boxes()[0].clone(), standard_boxes()[3].clone()];
    plan.noises = vec![TrackerNoise::clean(), TrackerNoise::real()];
    plan.messy = vec![];
    plan.tosses = 2;
    plan.mocap_kinds = vec![SceneKind::Toss];
    let mut calls = 0;
    let m = write_dataset(dir, &plan, &mut |p| {
        calls += 1;
        assert!(p.done <= p.total);
    })
    .unwrap();
    assert_eq!(calls, 2 * SceneKind::ALL.len() + 2);
    assert!(m.failures.is_empty(), "{:?}", m.failures);
    assert_eq!(m.demos.len(), 2 * SceneKind::ALL.len() * 2 + 2 * 3);
    assert!(dir.join("manifest.json").exists());
    for e in &m.demos {
        let palm = e.palm.as_ref().map(|p| dir.join(p));
        assert_eq!(palm.is_some(), e.scene == "instrumented");
        let demo =
            objmodel::format::read_demonstration(&dir.join(&e.tum), palm.as_deref()).unwrap();
        assert_eq!(demo.object.len(), e.frames);
        let truth: Truth =
            serde_json::from_str(&std::fs::read_to_string(dir.join(&e.truth)).unwrap()).unwrap();
        assert_eq!(truth.kind, e.kind);
        assert_eq!(truth.noise.name, e.noise);
        assert_eq!(truth.rate_hz, e.rate_hz);
        if e.noise == "mocap" {
            assert!(TrackerNoise::MOCAP_RATES.contains(&e.rate_hz));
            let s = &truth.noise.sigma;
            assert!((1e-4..5e-4).contains(&s.sigma_position), "{s:?}");
            assert!(
                (0.05..0.3).contains(&s.sigma_rotation.to_degrees()),
                "{s:?}"
            );
        } else {
            assert_eq!(e.rate_hz, 30.0);
        }
        // The modes cover the demo without gaps, and the box has 6 faces and 12 edges.
        assert_eq!(truth.features.faces.len(), 6);
        assert_eq!(truth.features.edges.len(), 12);
        assert_eq!(truth.modes.first().map(|m| m.t0), Some(0.0));
        assert!((truth.modes.last().unwrap().t1 - truth.duration).abs() < 1e-9);
        for w in truth.modes.windows(2) {
            assert_eq!(w[0].t1, w[1].t0);
        }
        match e.kind.as_str() {
            "topple" => {
                assert!(truth.edge.is_some() && truth.face.is_none() && truth.phi.is_some())
            }
            "slide" => assert!(truth.face.is_some() && truth.edge.is_none()),
            "compound" => assert!(truth.face.is_some() && truth.edge.is_some()),
            _ => assert!(truth.face.is_none() && truth.edge.is_none()),
        }
        if e.noise == "clean" && e.kind != "toss" {
            // The resting normals, mapped by the first and last tag poses, point down the support.
            let support = |i: usize| {
                demo.palm
                    .as_ref()
                    .map(|p| p[i].pose)
                    .unwrap_or_else(Isometry3::identity)
            };
            let n = demo.object.len() - 1;
            let down = |i: usize, nt: [f64; 3]| {
                (support(i).inverse() * demo.object[i].pose).rotation * Vector3::from(nt)
            };
            assert!(
                down(0, truth.rest_normal_before).dot(&-Vector3::z()) > 0.999,
                "{}",
                e.name
            );
            assert!(
                down(n, truth.rest_normal_after).dot(&-Vector3::z()) > 0.999,
                "{}",
                e.name
            );
            if let Some(edge) = truth.edge {
                // The edge lies on the support at the end (the box rests on a face that has it).
                let end = support(n).inverse() * demo.object[n].pose;
                for p in [edge.p0, edge.p1] {
                    assert!(
                        (end * nalgebra::Point3::from(p)).z.abs() < 1e-3,
                        "{}: edge off the support",
                        e.name
                    );
                }
                let u = Vector3::from(edge.direction);
                assert!((u.norm() - 1.0).abs() < 1e-12);
                assert!(Vector3::from(edge.point).dot(&u).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn real_noise_has_its_advertised_statistics() {
    let clean: Vec<StampedPose> = (0..20000)
        .map(|i| StampedPose {
            t: i as f64 / 30.0,
            pose: Isometry3::from_parts(
                nalgebra::Translation3::new(0.1, 0.05, 0.1),
                UnitQuaternion::from_euler_angles(std::f64::consts::FRAC_PI_2, 0.1, 0.3), // tag faces the camera (35°)
            ),
        })
        .collect();
    let model = TrackerNoise::real();
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    let noisy = model.apply(&clean, &mut rng);
    let drop = 1.0 - noisy.len() as f64 / clean.len() as f64;
    let q0 = clean[0].pose.rotation;
    let (mut flips, mut mirrors, mut sx) = (0, 0, 0.0);
    for p in &noisy {
        let q = p.pose.rotation.quaternion();
        if q.coords.dot(&q0.quaternion().coords) < 0.0 {
            flips += 1;
        }
        if p.pose.rotation.angle_to(&q0) > 5f64.to_radians() {
            mirrors += 1;
        }
        sx += (p.pose.translation.x - 0.1).powi(2);
    }
    let n = noisy.len() as f64;
    let sigma = (sx / n).sqrt();
    println!(
        "drop {drop:.4}, flips {:.4}, mirrors {:.4}, sigma_x {sigma:.2e}",
        flips as f64 / n,
        mirrors as f64 / n
    );
    assert!((drop - model.drop_prob).abs() < 0.006);
    assert!((flips as f64 / n - model.sign_flip_prob).abs() < 0.008);
    assert!((mirrors as f64 / n - model.mirror_prob).abs() < 0.004);
    assert!((sigma - model.sigma.sigma_position).abs() < 0.05 * model.sigma.sigma_position);
}
