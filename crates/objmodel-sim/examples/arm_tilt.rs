//! The simulated Panda tilts its palm with a box on it: palm tracking error and sim speed.
//!
//! ```text
//! cargo run --release -p objmodel-sim --example arm_tilt
//! cargo run --release -p objmodel-sim --example arm_tilt -- --angle 20 --duration 4 \
//!     --box 0.1x0.1x0.2 --mass 0.6 --motor-hz 40 [--no-gravity-compensation]
//! ```
//!
//! The arm starts in its palm-up configuration with the box standing in the middle of the palm,
//! settles for 0.5 s, then rotates the palm by `--angle` degrees about the palm's x axis through
//! a point on its surface 5 cm from the middle (smoothstep timing over `--duration` s), and
//! holds for 1 s. Printed: the planned joint trajectory, the palm tracking error (simulated palm
//! against the palm the joint targets ask for) every 0.5 s and at worst, how far the box moved
//! on the palm, and the simulation speed.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use objmodel_sim::arm::{Arm, ArmSim, ArmSimOptions, TrackingError};
use objmodel_sim::BoxSpec;
use std::time::Instant;

fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> T {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(|v| {
            v.parse()
                .unwrap_or_else(|_| panic!("cannot read {name} {v}"))
        })
        .unwrap_or(default)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let angle: f64 = arg(&args, "--angle", 20.0);
    let duration: f64 = arg(&args, "--duration", 4.0);
    let mass: f64 = arg(&args, "--mass", 0.6);
    let motor_hz: f64 = arg(&args, "--motor-hz", 40.0);
    let dims: String = arg(&args, "--box", "0.1x0.1x0.2".to_string());
    let dims: Vec<f64> = dims
        .split('x')
        .map(|v| v.parse().expect("--box AxBxC in metres"))
        .collect();
    assert_eq!(dims.len(), 3, "--box AxBxC in metres");
    let gravity_compensation = !args.iter().any(|a| a == "--no-gravity-compensation");

    let arm = Arm::panda();
    let q0 = arm.palm_up_configuration().expect("the shipped Panda");
    let opts = ArmSimOptions {
        motor_frequency: motor_hz,
        gravity_compensation,
        ..ArmSimOptions::default()
    };
    let mut sim = ArmSim::new(&arm, &q0, &opts).expect("arm in the world");
    let spec = BoxSpec::new("box", [dims[0], dims[1], dims[2]], mass);
    let b = sim.add_box_on_palm(&spec, &ArmSim::on_palm(&spec, 0.0, 0.0, 0.0));
    println!(
        "Franka Panda (URDF {}), palm 0.20 x 0.20 m, friction {}; box {:?} m, {} kg; motors {} Hz, \
         gravity compensation {}; physics {} Hz",
        objmodel_sim::arm::PANDA_PALM_URDF_PATH,
        opts.palm_friction,
        spec.dims,
        mass,
        motor_hz,
        if gravity_compensation { "on" } else { "off" },
        opts.physics.step_hz
    );

    let wall = Instant::now();
    sim.run_for(0.5);
    let rel0 = sim.palm_pose().inverse() * sim.body_pose(b);
    let settle = sim.tracking_error();
    println!(
        "settled: palm sag under the box {:.3} mm, {:.4} deg",
        settle.position * 1e3,
        settle.angle.to_degrees()
    );

    let start = arm.fk(sim.targets().0);
    let pivot = start * Point3::new(0.0, 0.05, 0.0);
    let axis = Unit::new_normalize(start.rotation * Vector3::x());
    let total = angle.to_radians();
    let path = |t: f64| {
        let s = (t / duration).clamp(0.0, 1.0);
        let r = UnitQuaternion::from_axis_angle(&axis, total * s * s * (3.0 - 2.0 * s));
        Isometry3::from_parts(
            Translation3::from(pivot.coords + r * (start.translation.vector - pivot.coords)),
            r * start.rotation,
        )
    };
    let plan_t = Instant::now();
    let tr = match arm.plan_palm_motion(path, duration, 0.01, sim.targets().0) {
        Ok(tr) => tr,
        Err(e) => {
            eprintln!("cannot plan the tilt: {e}");
            std::process::exit(1);
        }
    };
    println!(
        "planned {} samples in {:.1} ms: max joint speed {:.1}% of the limits, min manipulability \
         {:.4}, IK residual {:.1e} m",
        tr.len(),
        plan_t.elapsed().as_secs_f64() * 1e3,
        100.0 * tr.max_velocity_fraction(),
        tr.min_manipulability(),
        tr.ik_residual.0
    );

    sim.follow(tr);
    let t0 = sim.t;
    let mut worst = TrackingError::default();
    let mut next_print = 0.0;
    println!("    t [s]  palm tilt [deg]  error [mm]  error [deg]  box on palm [mm]");
    while sim.t - t0 < duration + 1.0 {
        sim.step();
        let e = sim.tracking_error();
        worst = worst.max(e);
        if sim.t - t0 >= next_print - 1e-9 {
            next_print += 0.5;
            let palm = sim.palm_pose();
            let rel = palm.inverse() * sim.body_pose(b);
            println!(
                "    {:5.2}  {:15.3}  {:10.4}  {:11.5}  {:16.4}",
                sim.t - t0,
                (palm.rotation * Vector3::z())
                    .angle(&Vector3::z())
                    .to_degrees(),
                e.position * 1e3,
                e.angle.to_degrees(),
                (rel.translation.vector - rel0.translation.vector).norm() * 1e3
            );
        }
    }
    let rel = sim.palm_pose().inverse() * sim.body_pose(b);
    let elapsed = wall.elapsed().as_secs_f64();
    println!(
        "max palm tracking error {:.4} mm, {:.5} deg; the box moved {:.4} mm and turned {:.4} deg \
         on the palm",
        worst.position * 1e3,
        worst.angle.to_degrees(),
        (rel.translation.vector - rel0.translation.vector).norm() * 1e3,
        rel.rotation.angle_to(&rel0.rotation).to_degrees()
    );
    println!(
        "simulated {:.1} s in {:.2} s wall: {:.1} sim s / wall s ({:.0} steps/s)",
        sim.t,
        elapsed,
        sim.t / elapsed,
        sim.t / sim.dt / elapsed
    );
}
