//! The arm: the URDF against Franka's published parameters, forward kinematics against hand
//! computations, inverse kinematics round trips, palm paths, and the simulated arm tracking a
//! palm tilt with a box riding on it.
//!
//! `cargo test -p objmodel-sim --test arm -- --nocapture` prints the measured numbers.

use nalgebra::{Isometry3, Matrix4, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use objmodel_sim::arm::{
    Arm, ArmError, ArmSim, ArmSimOptions, IkOptions, TrackingError, PANDA_PALM_UP,
    PANDA_PALM_UP_POSITION, PANDA_READY,
};
use objmodel_sim::BoxSpec;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Franka's published modified DH table (a, d, alpha) and the flange offset.
const DH: [(f64, f64, f64); 7] = [
    (0.0, 0.333, 0.0),
    (0.0, 0.0, -FRAC_PI_2),
    (0.0, 0.316, FRAC_PI_2),
    (0.0825, 0.0, FRAC_PI_2),
    (-0.0825, 0.384, -FRAC_PI_2),
    (0.0, 0.0, FRAC_PI_2),
    (0.088, 0.0, FRAC_PI_2),
];
const FLANGE_D: f64 = 0.107;
const PALM_THICKNESS: f64 = 0.01;

/// `base_from_palm` by the textbook modified-DH product, independent of the URDF and of `k`.
fn dh_fk(q: &[f64]) -> Matrix4<f64> {
    let rx = |a: f64| {
        let (s, c) = a.sin_cos();
        Matrix4::new(
            1.0, 0.0, 0.0, 0.0, 0.0, c, -s, 0.0, 0.0, s, c, 0.0, 0.0, 0.0, 0.0, 1.0,
        )
    };
    let rz = |a: f64| {
        let (s, c) = a.sin_cos();
        Matrix4::new(
            c, -s, 0.0, 0.0, s, c, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        )
    };
    let tx = |x: f64| Matrix4::new_translation(&Vector3::new(x, 0.0, 0.0));
    let tz = |z: f64| Matrix4::new_translation(&Vector3::new(0.0, 0.0, z));
    let mut t = Matrix4::<f64>::identity();
    for (i, &(a, d, alpha)) in DH.iter().enumerate() {
        t = t * rx(alpha) * tx(a) * rz(q[i]) * tz(d);
    }
    t * tz(FLANGE_D + PALM_THICKNESS)
}

/// Hand-derived palm position and normal for planar configurations (q1 = q3 = q5 = 0): the
/// pitch joints 2, 4, 6 turn about +y, -y, -y, so the link directions in the x-z plane are at
/// the cumulative pitch angles a2 = q2, a4 = q2 - q4, a6 = a4 - q6; with `R(a)` the rotation
/// about +y, the shoulder is at (0, 0, 0.333), then +0.316 R(a2) z, +0.0825 R(a2) x,
/// -0.0825 R(a4) x + 0.384 R(a4) z, +0.088 R(a6) x, and the palm 0.107 + 0.01 along
/// z7 = -R(a6) z.
fn planar_palm(q2: f64, q4: f64, q6: f64) -> (Vector3<f64>, Vector3<f64>) {
    let rx = |a: f64| Vector3::new(a.cos(), 0.0, -a.sin());
    let rz = |a: f64| Vector3::new(a.sin(), 0.0, a.cos());
    let (a2, a4) = (q2, q2 - q4);
    let a6 = a4 - q6;
    let p = Vector3::new(0.0, 0.0, 0.333) + rz(a2) * 0.316 + rx(a2) * 0.0825 - rx(a4) * 0.0825
        + rz(a4) * 0.384
        + rx(a6) * 0.088
        - rz(a6) * (FLANGE_D + PALM_THICKNESS);
    (p, -rz(a6))
}

fn pose_gap(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

#[test]
fn urdf_carries_frankas_published_limits() {
    let arm = Arm::panda();
    assert_eq!(arm.dof(), 7);
    let lo = [
        -2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973,
    ];
    let hi = [2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973];
    let v = [2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61];
    assert_eq!(arm.lower_limits(), lo);
    assert_eq!(arm.upper_limits(), hi);
    assert_eq!(arm.velocity_limits(), v);
    let effort: Vec<f64> = arm.model().joints.iter().map(|j| j.effort).collect();
    assert_eq!(effort, [87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0]);
    // Gaz et al. masses of links 1..7; link 7 carries the 0.48 kg palm plate.
    let m: Vec<f64> = arm.model().bodies[1..]
        .iter()
        .map(|b| b.inertial.mass)
        .collect();
    let expect = [
        4.970684,
        0.646926,
        3.228604,
        3.587895,
        1.225946,
        1.666555,
        0.735522 + 0.48,
    ];
    for (a, b) in m.iter().zip(expect) {
        assert!((a - b).abs() < 1e-12, "{m:?}");
    }
    // Loading from the file gives the same arm as the embedded copy.
    let from_file = Arm::load(objmodel_sim::arm::PANDA_PALM_URDF_PATH).unwrap();
    assert_eq!(from_file.model(), arm.model());
}

#[test]
fn fk_matches_hand_computed_poses() {
    let arm = Arm::panda();
    // Zero: stretched up, flange (0.088, 0, 0.926) facing down; the palm 1 cm below it.
    let t = arm.fk(&[0.0; 7]);
    assert!((t.translation.vector - Vector3::new(0.088, 0.0, 0.916)).norm() < 1e-12);
    let r = t.rotation.to_rotation_matrix();
    let expect = nalgebra::Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
    assert!((r.matrix() - expect).norm() < 1e-12, "{r}");

    // Ready (q2 = -45, q4 = -135, q6 = 90 deg): pitch angles a2 = -45, a4 = 90, a6 = 0 deg (see
    // `planar_palm`): the upper arm leans back, the forearm is horizontal, the flange points down.
    // x = 0.384 + 0.088 - (0.316 - 0.0825) cos 45, z = 0.333 + (0.316 + 0.0825) sin 45 + 0.0825
    // - 0.107: the flange at (0.306891, 0, 0.590282); the palm x axis turned by q7 = 45 deg.
    let t = arm.fk(&PANDA_READY);
    let flange = t * Point3::new(0.0, 0.0, -PALM_THICKNESS);
    let (c, s) = (FRAC_PI_4.cos(), FRAC_PI_4.sin());
    let hand = Vector3::new(
        0.384 + 0.088 - (0.316 - 0.0825) * c,
        0.0,
        0.333 + (0.316 + 0.0825) * s + 0.0825 - FLANGE_D,
    );
    assert!(
        (hand - Vector3::new(0.306891, 0.0, 0.590282)).norm() < 1e-6,
        "{hand}"
    );
    assert!(
        (flange.coords - hand).norm() < 1e-12,
        "{} vs {hand}",
        flange.coords
    );
    let x = t.rotation * Vector3::x();
    assert!((x - Vector3::new(FRAC_PI_4.cos(), -FRAC_PI_4.sin(), 0.0)).norm() < 1e-12);
    assert!((t.rotation * Vector3::z() + Vector3::z()).norm() < 1e-12);

    // Planar configurations: the closed form.
    let mut rng = StdRng::seed_from_u64(11);
    for _ in 0..50 {
        let (q2, q4, q6) = (
            rng.random_range(-1.7..1.7),
            rng.random_range(-3.0..-0.1),
            rng.random_range(0.0..3.7),
        );
        let t = arm.fk(&[0.0, q2, 0.0, q4, 0.0, q6, rng.random_range(-2.8..2.8)]);
        let (p, n) = planar_palm(q2, q4, q6);
        assert!((t.translation.vector - p).norm() < 1e-12);
        assert!((t.rotation * Vector3::z() - n).norm() < 1e-12);
    }

    // Any configuration: the textbook DH product, and the model's own joint product.
    for _ in 0..200 {
        let q: Vec<f64> = (0..7).map(|_| rng.random_range(-PI..PI)).collect();
        let t = arm.fk(&q);
        assert!((t.to_homogeneous() - dh_fk(&q)).norm() < 1e-12);
        let p = arm.model().fk_product(&q);
        assert!((t.to_homogeneous() - p.to_homogeneous()).norm() < 1e-12);
    }
}

#[test]
fn jacobian_matches_finite_differences() {
    let arm = Arm::panda();
    let mut rng = StdRng::seed_from_u64(3);
    for _ in 0..20 {
        let q: Vec<f64> = (0..7).map(|_| rng.random_range(-2.0..2.0)).collect();
        let (t, j) = arm.fk_jacobian(&q);
        let h = 1e-7;
        for c in 0..7 {
            let mut qh = q.clone();
            qh[c] += h;
            let th = arm.fk(&qh);
            let v = (th.translation.vector - t.translation.vector) / h;
            let w = (th.rotation * t.rotation.inverse()).scaled_axis() / h;
            assert!((v - j.fixed_view::<3, 1>(0, c)).norm() < 1e-6);
            assert!((w - j.fixed_view::<3, 1>(3, c)).norm() < 1e-6);
        }
        let m = arm.manipulability(&q);
        assert!((m - (&j * j.transpose()).determinant().sqrt()).abs() < 1e-12);
    }
}

#[test]
fn ik_round_trips_within_limits() {
    let arm = Arm::panda();
    let (lo, hi) = (arm.lower_limits(), arm.upper_limits());
    let mut rng = StdRng::seed_from_u64(7);
    let (mut worst_p, mut worst_r, mut iters, mut min_w): (f64, f64, Vec<usize>, f64) =
        (0.0, 0.0, Vec::new(), f64::INFINITY);
    let n = 150;
    for _ in 0..n {
        // A reachable pose: the palm at a random configuration inside the limits.
        let qt: Vec<f64> = (0..7)
            .map(|i| rng.random_range(lo[i] + 0.02..hi[i] - 0.02))
            .collect();
        let target = arm.fk(&qt);
        // Seeded within 0.3 rad of it, as when tracking.
        let seed: Vec<f64> = (0..7)
            .map(|i| (qt[i] + rng.random_range(-0.3..0.3)).clamp(lo[i], hi[i]))
            .collect();
        let sol = arm
            .ik_with(&target, &seed, &IkOptions::default())
            .unwrap_or_else(|e| panic!("target from {qt:?}, seed {seed:?}: {e}"));
        assert!(arm.within_limits(&sol.q, 0.0), "{:?}", sol.q);
        let (dp, dr) = pose_gap(&arm.fk(&sol.q), &target);
        assert!(dp < 1e-6 && dr < 1e-6, "{dp} {dr}");
        assert!((sol.manipulability - arm.manipulability(&sol.q)).abs() < 1e-12);
        worst_p = worst_p.max(dp);
        worst_r = worst_r.max(dr);
        iters.push(sol.iterations);
        min_w = min_w.min(sol.manipulability);
    }
    iters.sort();
    println!(
        "IK round trip, {n} random poses, seeds within 0.3 rad: worst |dp| {worst_p:.1e} m, \
         |dR| {worst_r:.1e} rad; iterations median {} max {}; min manipulability {min_w:.4}",
        iters[n / 2],
        iters[n - 1]
    );

    // From a fixed start (no good seed): several seeds and restarts.
    let mut ok = 0;
    let m = 40;
    for _ in 0..m {
        let qt: Vec<f64> = (0..7)
            .map(|i| rng.random_range(lo[i] + 0.05..hi[i] - 0.05))
            .collect();
        let target = arm.fk(&qt);
        if let Ok(sol) = arm.ik_multi(&target, &PANDA_PALM_UP) {
            let (dp, dr) = pose_gap(&arm.fk(&sol.q), &target);
            assert!(dp < 1e-6 && dr < 1e-6);
            assert!(arm.within_limits(&sol.q, 0.0));
            ok += 1;
        }
    }
    println!("IK from the palm-up pose with restarts: {ok}/{m} random reachable poses solved");
    assert!(ok >= m * 9 / 10, "{ok}/{m}");
}

#[test]
fn ik_keeps_limits_and_reports_unreachable_targets() {
    let arm = Arm::panda();
    let q0 = arm.palm_up_configuration().unwrap();
    let p = arm.fk(&q0);
    assert!((p.translation.vector - Vector3::from(PANDA_PALM_UP_POSITION)).norm() < 1e-9);
    assert!((p.rotation * Vector3::z() - Vector3::z()).norm() < 1e-9);
    // 2 m away: out of reach; the error says so and nothing panics.
    let far = Isometry3::translation(2.0, 0.0, 0.3);
    match arm.ik(&far, &q0) {
        Err(ArmError::NoConvergence { position_error, .. }) => assert!(position_error > 0.5),
        other => panic!("{other:?}"),
    }
    // Wrong seed length.
    assert!(matches!(arm.ik(&p, &[0.0; 6]), Err(ArmError::BadJoints(_))));
    // A seed outside the limits is clamped into them; the solution keeps the IK margin.
    let mut seed = q0.clone();
    seed[6] = 3.5; // joint 7's upper limit is 2.8973
    let sol = arm.ik(&p, &seed).unwrap();
    assert!(arm.within_limits(&sol, 0.0), "{sol:?}");
    let (dp, dr) = pose_gap(&arm.fk(&sol), &p);
    assert!(dp < 1e-6 && dr < 1e-6);
    // Targets at the edge of the joint space: joint 4 near its upper limit (elbow almost
    // straight). Whatever converges is inside the limits shrunk by the 0.01 rad margin.
    let mut rng = StdRng::seed_from_u64(9);
    let (lo, hi) = (arm.lower_limits(), arm.upper_limits());
    for _ in 0..20 {
        let mut q: Vec<f64> = (0..7)
            .map(|i| rng.random_range(lo[i] + 0.05..hi[i] - 0.05))
            .collect();
        q[3] = -0.0698 - 0.002;
        let t = arm.fk(&q);
        if let Ok(sol) = arm.ik(&t, &q) {
            assert!(sol[3] <= -0.0698 - 0.01 + 1e-12, "{sol:?}");
            assert!(arm.within_limits(&sol, 0.0));
        }
    }
    // The null-space term raises manipulability compared with plain damped least squares.
    let mut rng = StdRng::seed_from_u64(5);
    let (mut with, mut without) = (0.0, 0.0);
    for _ in 0..20 {
        let target = Isometry3::from_parts(
            Translation3::new(
                rng.random_range(0.35..0.6),
                rng.random_range(-0.2..0.2),
                rng.random_range(0.2..0.5),
            ),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rng.random_range(-1.0..1.0)),
        );
        let a = arm.ik_with(&target, &q0, &IkOptions::default());
        let b = arm.ik_with(
            &target,
            &q0,
            &IkOptions {
                null_space_iterations: 0,
                ..IkOptions::default()
            },
        );
        if let (Ok(a), Ok(b)) = (a, b) {
            with += a.manipulability;
            without += b.manipulability;
        }
    }
    println!("mean manipulability: with null-space term {with:.3}, without {without:.3} (sums)");
    assert!(with > without);
}

/// `base_from_palm` over time for a tilt by `angle` about a horizontal palm axis through a point
/// on the palm's surface `offset` from its middle; smoothstep timing over `duration`.
fn tilt_path(
    start: Isometry3<f64>,
    axis_palm: Vector3<f64>,
    offset: Vector3<f64>,
    angle: f64,
    duration: f64,
) -> impl Fn(f64) -> Isometry3<f64> {
    let pivot = start * Point3::from(offset);
    let axis = Unit::new_normalize(start.rotation * axis_palm);
    move |t: f64| {
        let s = (t / duration).clamp(0.0, 1.0);
        let r = UnitQuaternion::from_axis_angle(&axis, angle * s * s * (3.0 - 2.0 * s));
        Isometry3::from_parts(
            Translation3::from(pivot.coords + r * (start.translation.vector - pivot.coords)),
            r * start.rotation,
        )
    }
}

#[test]
fn palm_paths_become_continuous_velocity_limited_joint_paths() {
    let arm = Arm::panda();
    let q0 = arm.palm_up_configuration().unwrap();
    let start = arm.fk(&q0);
    let f = tilt_path(
        start,
        Vector3::x(),
        Vector3::new(0.0, 0.05, 0.0),
        20f64.to_radians(),
        4.0,
    );
    let tr = arm.plan_palm_motion(&f, 4.0, 0.01, &q0).unwrap();
    assert_eq!(tr.len(), 401);
    let acc = tr.max_acceleration_fraction(&objmodel_sim::arm::PANDA_ACCEL_LIMITS);
    assert!(acc < 0.2, "{acc}");
    assert!((tr.duration() - 4.0).abs() < 1e-12);
    let v = arm.velocity_limits();
    for (k, q) in tr.q.iter().enumerate() {
        assert!(arm.within_limits(q, 0.0));
        let (dp, dr) = pose_gap(&arm.fk(q), &f(k as f64 * tr.dt));
        assert!(dp < 1e-6 && dr < 1e-6);
        if k > 0 {
            for i in 0..7 {
                assert!((q[i] - tr.q[k - 1][i]).abs() <= 0.5 * v[i] * tr.dt);
            }
        }
    }
    assert!(tr.q[0].iter().zip(&q0).all(|(a, b)| (a - b).abs() < 1e-6));
    // Interpolation passes through the samples.
    let (qs, _) = tr.sample(1.0);
    assert!(qs
        .iter()
        .zip(&tr.q[100])
        .all(|(a, b)| (a - b).abs() < 1e-12));
    println!(
        "tilt 20 deg / 4 s: max joint speed {:.1}% of the limit, acceleration {:.1}%, min \
         manipulability {:.4}, IK residual {:.1e} m {:.1e} rad",
        100.0 * tr.max_velocity_fraction(),
        100.0 * acc,
        tr.min_manipulability(),
        tr.ik_residual.0,
        tr.ik_residual.1
    );
    // The same tilt in 0.05 s needs joints faster than half their limits.
    let fast = tilt_path(
        start,
        Vector3::x(),
        Vector3::zeros(),
        20f64.to_radians(),
        0.05,
    );
    match arm.plan_palm_motion(&fast, 0.05, 0.005, &q0) {
        Err(ArmError::VelocityLimit { factor, .. }) => assert!(factor > 1.0),
        other => panic!("{other:?}"),
    }
}

#[test]
fn simulated_arm_matches_kinematics() {
    let arm = Arm::panda();
    let base = Isometry3::from_parts(
        Translation3::new(0.1, -0.2, 0.05),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3),
    );
    for q in [arm.palm_up_configuration().unwrap(), PANDA_READY.to_vec()] {
        let o = ArmSimOptions {
            world_from_base: base,
            ..ArmSimOptions::default()
        };
        let mut sim = ArmSim::new(&arm, &q, &o).unwrap();
        let (dp, dr) = pose_gap(&sim.palm_pose(), &(base * arm.fk(&q)));
        assert!(dp < 1e-12 && dr < 1e-12, "{dp} {dr}");
        assert!(sim
            .joint_positions()
            .iter()
            .zip(&q)
            .all(|(a, b)| (a - b).abs() < 1e-12));
        sim.run_for(0.5);
        let e = sim.tracking_error();
        assert!(e.position < 1e-6 && e.angle < 1e-6, "{e:?}");
    }
    assert!(ArmSim::new(&arm, &[0.0; 7], &ArmSimOptions::default()).is_err());
}

#[test]
fn box_on_level_palm_stays_put() {
    let arm = Arm::panda();
    let q0 = arm.palm_up_configuration().unwrap();
    let mut sim = ArmSim::new(&arm, &q0, &ArmSimOptions::default()).unwrap();
    let spec = BoxSpec::new("tall", [0.1, 0.1, 0.2], 0.6).with_com([0.01, 0.0, 0.0]);
    let b = sim.add_box_on_palm(&spec, &ArmSim::on_palm(&spec, 0.02, -0.01, 0.4));
    sim.run_for(0.5);
    let rel0 = sim.palm_pose().inverse() * sim.body_pose(b);
    sim.run_for(3.0);
    let rel1 = sim.palm_pose().inverse() * sim.body_pose(b);
    let (dp, dr) = pose_gap(&rel0, &rel1);
    let e = sim.tracking_error();
    println!(
        "box resting on the level palm for 3 s: drift {dp:.1e} m, turn {:.1e} deg relative to \
         the palm; palm sag under the box {:.3} mm, {:.4} deg",
        dr.to_degrees(),
        e.position * 1e3,
        e.angle.to_degrees()
    );
    assert!(dp < 1e-3, "{dp}");
    assert!(dr < 1e-3, "{dr}");
    // It really rests on the palm: its bottom face is on the surface.
    assert!(
        (rel1.translation.z - 0.1).abs() < 1e-4,
        "{}",
        rel1.translation.z
    );
}

#[test]
fn simulated_arm_tracks_a_palm_tilt_with_a_box_on_it() {
    let arm = Arm::panda();
    let q0 = arm.palm_up_configuration().unwrap();
    let mut sim = ArmSim::new(&arm, &q0, &ArmSimOptions::default()).unwrap();
    let spec = BoxSpec::new("tall", [0.1, 0.1, 0.2], 0.6);
    let b = sim.add_box_on_palm(&spec, &ArmSim::on_palm(&spec, 0.0, 0.0, 0.0));
    sim.run_for(0.5);
    let rel0 = sim.palm_pose().inverse() * sim.body_pose(b);
    // 20 deg over 4 s about the palm's x axis through a point on its surface 5 cm off the
    // middle: the box (phi = 26.6 deg) must not topple and rides along on friction.
    let start = arm.fk(sim.targets().0);
    let f = tilt_path(
        start,
        Vector3::x(),
        Vector3::new(0.0, 0.05, 0.0),
        20f64.to_radians(),
        4.0,
    );
    let tr = arm
        .plan_palm_motion(&f, 4.0, 0.01, sim.targets().0)
        .unwrap();
    sim.follow(tr);
    let mut worst = TrackingError::default();
    let wall = std::time::Instant::now();
    let t0 = sim.t;
    while sim.t - t0 < 4.5 {
        sim.step();
        worst = worst.max(sim.tracking_error());
        assert!(arm.within_limits(&sim.joint_positions(), 1e-3));
    }
    let speed = (sim.t - t0) / wall.elapsed().as_secs_f64();
    let palm_end = sim.palm_pose();
    let tilt = (palm_end.rotation * Vector3::z()).angle(&Vector3::z());
    let rel1 = palm_end.inverse() * sim.body_pose(b);
    let (dp, dr) = pose_gap(&rel0, &rel1);
    println!(
        "palm tilt 20 deg / 4 s with a 0.6 kg box: max tracking error {:.3} mm, {:.4} deg; final \
         palm tilt {:.3} deg; box moved {:.1e} m, turned {:.1e} deg on the palm; {speed:.0} sim s \
         per wall s",
        worst.position * 1e3,
        worst.angle.to_degrees(),
        tilt.to_degrees(),
        dp,
        dr.to_degrees()
    );
    assert!(worst.position < 5e-3, "{worst:?}");
    assert!(worst.angle < 1f64.to_radians(), "{worst:?}");
    assert!(
        (tilt.to_degrees() - 20.0).abs() < 0.2,
        "{}",
        tilt.to_degrees()
    );
    // The box went up with the palm through contact and friction alone, touching nothing of
    // the arm but the palm.
    assert!(dp < 1e-3 && dr < 1e-3, "{dp} {dr}");
    assert!(
        sim.touches_palm_only(b),
        "{:?}",
        sim.arm_colliders_touching(b)
    );
    assert!(sim.world.bodies[b].is_dynamic());
}
