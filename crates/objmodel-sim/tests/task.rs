//! The toppling task on the simulated Panda: the palm rotation about the plan's axis, the
//! default policy failing on a tall box, and the planned topple after one demonstration.

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use objmodel_sim::arm::{Arm, ArmSim, ArmSimOptions};
use objmodel_sim::task::run::{draw_trial, run_trial, Trial};
use objmodel_sim::task::{rotate_about, run_task, SkillOptions, TaskConfig};
use objmodel_sim::{BoxSpec, TagMount};
use rand::rngs::StdRng;
use rand::SeedableRng;

#[test]
fn rotate_about_keeps_the_line_fixed_and_turns_by_theta() {
    let start = Isometry3::new(Vector3::new(0.45, 0.0, 0.35), Vector3::new(0.1, -0.2, 0.3));
    let p = Vector3::new(0.47, 0.03, 0.35);
    let u = Unit::new_normalize(Vector3::new(0.3, 1.0, 0.1));
    let local = start.inverse() * Point3::from(p);
    for theta in [0.1, 0.5, -0.7] {
        let m = rotate_about(&start, &p, &u, theta);
        assert!(((m * local).coords - p).norm() < 1e-12);
        let rel = m.rotation * start.rotation.inverse();
        assert!((rel.angle() - theta.abs()).abs() < 1e-12);
        assert!((rel.axis().unwrap().dot(&u) - theta.signum()).abs() < 1e-9);
    }
}

/// The simulated palm tilting 25° about a line on its surface (through the bottom edge of a box
/// standing on it, below its tipping angle): the line's points and the box's edge stay fixed in
/// the world to within a millimetre.
#[test]
fn palm_rotation_about_the_plan_axis_keeps_the_edge_fixed() {
    let arm = Arm::panda();
    let q0 = arm.palm_up_configuration().unwrap();
    let mut sim = ArmSim::new(&arm, &q0, &ArmSimOptions::default()).unwrap();
    // A 6 x 6 x 16 cm box (phi = atan(3/8) = 20.6 deg), its -y bottom edge along x at y = -0.01.
    let spec = BoxSpec::new("tall", [0.06, 0.06, 0.16], 0.6);
    let body = sim.add_box_on_palm(&spec, &ArmSim::on_palm(&spec, 0.0, 0.02, 0.0));
    sim.run_for(0.5);
    let axis_point = Vector3::new(0.0, -0.01, 0.0);
    let axis = Vector3::x(); // +x: the -y side goes down
    let start = arm.fk(sim.targets().0);
    let p_b = (start * Point3::from(axis_point)).coords;
    let u_b = Unit::new_normalize(start.rotation * axis);
    let tilt = 17f64.to_radians();
    let dur = 4.0;
    let tr = arm
        .plan_palm_motion(
            |t| {
                let s = (t / dur).clamp(0.0, 1.0);
                rotate_about(&start, &p_b, &u_b, tilt * s * s * (3.0 - 2.0 * s))
            },
            dur,
            0.04,
            sim.targets().0,
        )
        .unwrap();
    let wfb = sim.world_from_base;
    let line_w = |sim: &ArmSim, x: f64| sim.palm_pose() * Point3::new(x, -0.01, 0.0);
    let edge_w = |sim: &ArmSim| sim.body_pose(body) * Point3::new(0.0, -0.03, -0.08);
    let (a0, b0, e0) = (line_w(&sim, -0.05), line_w(&sim, 0.05), edge_w(&sim));
    let planned0 = wfb * Point3::from(p_b);
    sim.follow(tr);
    let (mut worst_line, mut worst_edge) = (0.0f64, 0.0f64);
    while sim.t < 0.5 + dur + 0.5 {
        sim.step();
        worst_line = worst_line
            .max((line_w(&sim, -0.05) - a0).norm())
            .max((line_w(&sim, 0.05) - b0).norm());
        worst_edge = worst_edge.max((edge_w(&sim) - e0).norm());
    }
    let tilt_now = sim.palm_pose().rotation.angle_to(&(wfb * start).rotation);
    eprintln!(
        "line drift {:.3} mm, box edge drift {:.3} mm, planned point {:?}, tilt {:.2} deg",
        worst_line * 1e3,
        worst_edge * 1e3,
        planned0,
        tilt_now.to_degrees()
    );
    assert!(worst_line < 1e-3, "palm line moved {worst_line} m");
    assert!(worst_edge < 1e-3, "box edge moved {worst_edge} m");
    assert!((tilt_now - tilt).abs() < 0.5f64.to_radians());
    assert!(sim.touches_palm_only(body));
}

#[test]
fn default_fails_on_a_tall_box_and_one_demonstration_fixes_it() {
    let arm = Arm::panda();
    let q_up = arm.palm_up_configuration().unwrap();
    let mut spec = BoxSpec::new("tall", [0.06, 0.06, 0.11], 0.6);
    spec.friction = 0.9;
    spec.tag = TagMount {
        face: objmodel_sim::BoxFace::NegY,
        offset: [0.002, -0.003],
        yaw: 0.3,
    };
    let trial = Trial {
        phi_true: 0.03f64.atan2(0.055),
        spec,
        axis: 0,
        sign: 1.0,
        position: [0.005, 0.06],
        yaw: -std::f64::consts::FRAC_PI_2 + 0.1,
        rejected_before: 0,
    };
    let o = run_trial(&arm, &q_up, &trial, &SkillOptions::default(), 11).unwrap();
    eprintln!("{}", serde_json::to_string_pretty(&o).unwrap());
    assert!(!o.success_default, "{}", o.reason);
    assert!(!o.default.topple_detected);
    let planned = o.planned.as_ref().expect("a planned attempt");
    assert!(o.success_after_one_demo, "{}", o.reason);
    assert!(planned.topple_detected);
    let phi = o.phi_learnt_deg.unwrap();
    assert!(
        (phi - o.phi_true_deg).abs() < 3.0,
        "phi {phi} vs {}",
        o.phi_true_deg
    );
    // The truth agrees with the tracked verdict.
    let t = planned.truth.as_ref().unwrap();
    assert!(
        t.touches_palm_only && (t.face_change_deg - 90.0).abs() < 5.0,
        "{t:?}"
    );
    assert!(planned.tracking_mm < 5.0);
}

#[test]
fn the_loop_runs_end_to_end_on_two_random_boxes() {
    let cfg = TaskConfig {
        boxes: 2,
        seed: 7,
        ..TaskConfig::default()
    };
    let rep = run_task(&cfg, |i, b| eprintln!("{i}: {}", b.reason)).unwrap();
    let v = serde_json::to_value(&rep).unwrap();
    assert_eq!(v["trials"], 2);
    assert!(v["success_default"].is_u64() && v["success_after_one_demo"].is_u64());
    assert_eq!(v["boxes"].as_array().unwrap().len(), 2);
    assert!(rep.success_default <= 1);
    assert!(
        rep.success_after_one_demo >= 1,
        "{:?}",
        rep.boxes.iter().map(|b| &b.reason).collect::<Vec<_>>()
    );
    // Where one demonstration did not locate the edge well enough to be taught (box01: its
    // palm topple at 1 mm / 0.5° and 30 Hz located it to ±2.2 mm), the loop asked for another,
    // said why, and the plan from both succeeded.
    assert_eq!(
        rep.demonstrations,
        rep.boxes.iter().map(|b| b.demonstrations).sum::<usize>()
    );
    let again: Vec<_> = rep.boxes.iter().filter(|b| b.demonstrations > 1).collect();
    assert!(!again.is_empty(), "no box needed a second demonstration");
    for b in again {
        assert!(b.demonstrations <= objmodel_sim::task::MAX_DEMOS);
        assert!(!b.success_after_one_demo);
        assert!(
            b.planned.as_ref().is_some_and(|a| a.success),
            "{}",
            b.reason
        );
        assert!(
            !b.asked_again.is_empty()
                && b.asked_again
                    .iter()
                    .all(|w| w.contains("too loosely to be taught")),
            "{:?}",
            b.asked_again
        );
    }
}

#[test]
fn drawn_trials_are_admissible() {
    let mut rng = StdRng::seed_from_u64(3);
    for i in 0..50 {
        let t = draw_trial(&mut rng, &format!("b{i}"));
        assert!(t.phi_true <= objmodel_sim::task::run::MAX_PHI_TASK + 1e-12);
        assert!(t.spec.friction.min(0.9) >= 1.15 * t.phi_true.tan());
        assert!(t.spec.dims.iter().all(|d| (0.06..0.2).contains(d)));
        assert!(t.position[1].abs() < 0.1 && t.position[0].abs() < 0.1);
    }
}
