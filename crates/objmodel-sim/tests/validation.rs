//! Physics validation against analytic rigid-body truth. Run in release or with the workspace's
//! test profile (opt-level 2): `cargo test -p objmodel-sim --test validation`.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use objmodel_sim::events::{rest_face, support_from_box, topple_events};
use objmodel_sim::scenes::instrumented::{run_with, Tilt};
use objmodel_sim::scenes::Run;
use objmodel_sim::{simulate_clean, BoxFace, BoxSpec, PhysicsParams, SceneKind, SimOptions};
use rand::SeedableRng;

fn boxes() -> Vec<(BoxSpec, usize, f64)> {
    vec![
        (
            BoxSpec::new("tall", [0.10, 0.10, 0.20], 0.6).with_friction(0.9),
            0,
            1.0,
        ),
        (
            BoxSpec::new("slab", [0.12, 0.06, 0.10], 0.4).with_friction(0.9),
            1,
            -1.0,
        ),
        (
            BoxSpec::new("weighted", [0.08, 0.08, 0.16], 0.8)
                .with_com([0.015, 0.0, -0.02])
                .with_friction(0.9),
            0,
            1.0,
        ),
        (
            BoxSpec::new("post", [0.06, 0.07, 0.22], 0.35)
                .with_com([0.0, 0.008, 0.03])
                .with_friction(0.7),
            1,
            -1.0,
        ),
    ]
}

/// On a palm tilting at 1°/s, the box starts to turn when the tilt reaches φ = atan2(d, h_c).
#[test]
fn tilting_palm_topples_at_phi() {
    let p = PhysicsParams::default();
    for (spec, axis, sign) in boxes() {
        let tilt = Tilt {
            axis,
            sign,
            rate: 1f64.to_radians(),
            pivot: [0.01, -0.02],
            max_tilt: 1.2,
        };
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let out = run_with(&spec, spec.friction, &tilt, &p, &mut rng).expect("scene runs");
        let f0 = rest_face(&out.samples[0]);
        let f1 = rest_face(out.samples.last().unwrap());
        assert_eq!(f0, BoxFace::NegZ);
        assert_eq!(
            f1,
            BoxFace::from_axis_sign(axis, sign),
            "{}: toppled over the downhill edge",
            spec.name
        );
        let ev = topple_events(&spec, &out, out.script.motion_start, f0, f1).unwrap();
        let h = spec.half_extents();
        let c = spec.com_box();
        let phi = (h[axis] - sign * c[axis]).atan2(h.z + c.z);
        assert!((ev.phi - phi).abs() < 1e-12);
        let err = (ev.support_tilt - phi).to_degrees();
        println!(
            "{:9} phi {:7.3} deg, palm tilt at onset {:7.3} deg, error {:+.3} deg, pivot slip {:.2e} m",
            spec.name,
            phi.to_degrees(),
            ev.support_tilt.to_degrees(),
            err,
            ev.pivot_slip
        );
        assert!(
            err.abs() < 0.5,
            "{}: onset {err:+.3} deg from phi",
            spec.name
        );
        assert!(
            ev.pivot_slip < 1e-3,
            "{}: the edge slipped {} m",
            spec.name,
            ev.pivot_slip
        );
    }
}

/// A box resting on a level table for 10 s moves less than 0.1 mm and turns less than 0.01°.
#[test]
fn resting_box_does_not_creep() {
    for (spec, _, _) in boxes() {
        let mut run = Run::new(&PhysicsParams::default());
        run.world.add_table(spec.friction);
        let pose = Isometry3::from_parts(
            Translation3::new(0.0, 0.0, spec.dims[2] / 2.0 + 1e-4),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.4),
        );
        run.place_box(&spec, spec.friction, &pose);
        run.rest(0.5).unwrap();
        let a = run.world.pose(run.boxb);
        run.rest(10.0).unwrap();
        let b = run.world.pose(run.boxb);
        let drift = (b.translation.vector - a.translation.vector).norm();
        let turn = a.rotation.angle_to(&b.rotation).to_degrees();
        println!(
            "{:9} drift {:.3e} m, turn {:.3e} deg over 10 s",
            spec.name, drift, turn
        );
        assert!(drift < 1e-4, "{}: drifted {drift} m", spec.name);
        assert!(turn < 0.01, "{}: turned {turn} deg", spec.name);
    }
}

/// With friction below tan φ the box slides down the palm when the tilt reaches atan μ, flat on
/// its face, instead of toppling.
#[test]
fn low_friction_slides_instead_of_toppling() {
    let spec = BoxSpec::new("tall", [0.10, 0.10, 0.20], 0.6).with_friction(0.3);
    let mu: f64 = 0.3;
    let mut run = Run::new(&PhysicsParams::default());
    let plate0 = Isometry3::translation(0.0, 0.0, 0.3);
    let plate = run.world.add_plate([0.6, 0.6, 0.005], mu, &plate0);
    run.plate = Some(plate);
    run.place_box(
        &spec,
        mu,
        &(plate0 * Isometry3::translation(0.0, 0.0, 0.1 + 1e-4)),
    );
    run.rest(0.5).unwrap();
    let (mut theta, rate) = (0.0f64, 2f64.to_radians());
    let down = -Vector3::z();
    let mut slide_tilt = None;
    let mut max_box_tilt: f64 = 0.0;
    let start = support_from_box(run.samples.last().unwrap())
        .translation
        .vector;
    while theta < 24f64.to_radians() {
        theta += rate * run.world.dt;
        run.world
            .set_kinematic(plate, &(Isometry3::rotation(Vector3::x() * theta) * plate0));
        run.step().unwrap();
        max_box_tilt = max_box_tilt.max(run.tilt(&down));
        let moved = (support_from_box(run.samples.last().unwrap())
            .translation
            .vector
            - start)
            .norm();
        if slide_tilt.is_none() && moved > 1e-3 {
            slide_tilt = Some(theta);
        }
        if moved > 0.1 {
            break;
        }
    }
    let slide_tilt = slide_tilt.expect("the box slid");
    let moved = (support_from_box(run.samples.last().unwrap())
        .translation
        .vector
        - start)
        .norm();
    println!("slides 1 mm at tilt {:.2} deg (atan mu = {:.2} deg, phi = 26.57 deg), box tilt on palm at most {:.3} deg, slid {:.3} m",
        slide_tilt.to_degrees(), mu.atan().to_degrees(), max_box_tilt.to_degrees(), moved);
    assert!((slide_tilt - mu.atan()).abs() < 1f64.to_radians());
    assert!(
        max_box_tilt < 0.5f64.to_radians(),
        "the box tipped {} deg",
        max_box_tilt.to_degrees()
    );
    assert!(moved > 0.05);
}

/// Pushed above the CoM on a high-friction table, the box pivots on its bottom edge: the edge
/// slips less than 3 mm before the box has turned φ + 10°, it ends on the adjacent face, and the
/// truth edge (tag frame) stays on the table, where it was, from onset to landing.
#[test]
fn pushed_box_pivots_on_its_edge() {
    let opts = SimOptions::default();
    for (spec, _, _) in boxes() {
        let spec = spec.with_friction(1.0);
        for seed in 1..=3 {
            let d = simulate_clean(SceneKind::Topple, &spec, seed, &opts).expect("topple runs");
            let t = &d.truth;
            let slip = t.pivot_slip.unwrap();
            let edge = t.edge.unwrap();
            let at = |time: f64| {
                let i = d.object.iter().position(|s| s.t >= time).unwrap();
                let w = d.object[i].pose;
                (w * Point3::from(edge.p0), w * Point3::from(edge.p1))
            };
            let (a0, b0) = at(t.topple_start.unwrap());
            let (a1, b1) = at(t.pivot_end.unwrap() - 0.05);
            let moved = (a1 - a0).norm().max((b1 - b0).norm());
            println!("{:9} seed {seed}: phi {:6.2} deg, slip before phi+10 {:.2e} m, edge moved {:.2e} m by landing, heights {:.1e} {:.1e}",
                spec.name, t.phi_deg.unwrap(), slip, moved, a0.z, b0.z);
            assert!(slip < 3e-3, "{} seed {seed}: slipped {slip} m", spec.name);
            assert!(
                a0.z.abs() < 5e-4 && b0.z.abs() < 5e-4,
                "edge on the table at onset"
            );
            assert!(
                moved < 5e-3,
                "{} seed {seed}: edge moved {moved} m while pivoting",
                spec.name
            );
            let n0 = Vector3::from(t.rest_normal_before);
            let n1 = Vector3::from(t.rest_normal_after);
            assert!(n0.dot(&n1).abs() < 1e-9, "adjacent faces");
            assert!(Vector3::from(edge.direction).dot(&n0).abs() < 1e-9);
        }
    }
}
