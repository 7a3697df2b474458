//! Simulated seconds per wall-clock second for each scene (one thread), and how rapier's
//! default contact settings compare with this crate's on the toppling onset.
//!
//! `cargo run --release -p objmodel-sim --example speed`
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::events::{rest_face, topple_events};
use objmodel_sim::scenes::instrumented::{run_with, Tilt};
use objmodel_sim::{simulate_clean, PhysicsParams, SceneKind, SimOptions};
use rand::SeedableRng;
use std::time::Instant;

fn main() {
    let opts = SimOptions::default();
    println!("| scene | runs | simulated [s] | wall [s] | sim s / wall s | steps / s |");
    println!("|---|---|---|---|---|---|");
    for kind in SceneKind::ALL {
        let (mut sim, mut wall, mut runs) = (0.0, 0.0, 0);
        for b in standard_boxes() {
            for seed in 1..=3 {
                let t0 = Instant::now();
                if let Ok(d) = simulate_clean(kind, &b, seed, &opts) {
                    wall += t0.elapsed().as_secs_f64();
                    sim += d.truth.duration;
                    runs += 1;
                }
            }
        }
        let steps = sim * opts.physics.step_hz;
        println!(
            "| {} | {runs} | {sim:.1} | {wall:.2} | {:.0} | {:.0} |",
            kind.name(),
            sim / wall,
            steps / wall
        );
    }

    {
        let spec = standard_boxes().remove(0);
        let mut run = objmodel_sim::scenes::Run::new(&opts.physics);
        run.world.add_table(spec.friction);
        run.place_box(
            &spec,
            spec.friction,
            &nalgebra::Isometry3::translation(0.0, 0.0, 0.1),
        );
        run.rest(0.5).unwrap();
        let p0 = run.world.pose(run.boxb);
        let t0 = Instant::now();
        run.rest(10.0).unwrap();
        let wall = t0.elapsed().as_secs_f64();
        let drift = (run.world.pose(run.boxb).translation.vector - p0.translation.vector).norm();
        println!(
            "| rest (box on table, 10 s) | 1 | 10.0 | {wall:.3} | {:.0} | {:.0} |  drift {drift:.1e} m",
            10.0 / wall,
            9600.0 / wall
        );
    }

    println!("\nToppling onset on a palm tilting at 1 deg/s (tall box 0.1 x 0.1 x 0.2 m, phi = 26.565 deg):\n");
    println!(
        "| settings | palm tilt at onset [deg] | error [deg] | pivot slip [m] | sim s / wall s |"
    );
    println!("|---|---|---|---|---|");
    let spec = standard_boxes().remove(0).with_friction(0.9);
    let tuned = PhysicsParams::default();
    let rapier_default = PhysicsParams {
        contact_hz: 30.0,
        contact_damping: 10.0,
        contact_recycling: true,
        simplified_friction: true,
        ..tuned
    };
    let variants = [
        ("this crate (no recycling, Coulomb, 240 Hz contacts)", tuned),
        (
            "rapier defaults (recycling, simplified friction, 30/60 Hz contacts)",
            rapier_default,
        ),
        (
            "defaults but no contact recycling",
            PhysicsParams {
                contact_recycling: false,
                ..rapier_default
            },
        ),
        (
            "tuned but with contact recycling",
            PhysicsParams {
                contact_recycling: true,
                ..tuned
            },
        ),
        (
            "tuned, 480 Hz steps",
            PhysicsParams {
                step_hz: 480.0,
                contact_hz: 120.0,
                ..tuned
            },
        ),
    ];
    for (label, p) in variants {
        let tilt = Tilt {
            axis: 0,
            sign: 1.0,
            rate: 1f64.to_radians(),
            pivot: [0.0, 0.0],
            max_tilt: 1.2,
        };
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let t0 = Instant::now();
        match run_with(&spec, spec.friction, &tilt, &p, &mut rng) {
            Ok(out) => {
                let wall = t0.elapsed().as_secs_f64();
                let (f0, f1) = (
                    rest_face(&out.samples[0]),
                    rest_face(out.samples.last().unwrap()),
                );
                match topple_events(&spec, &out, out.script.motion_start, f0, f1) {
                    Ok(ev) => println!(
                        "| {label} | {:.3} | {:+.3} | {:.1e} | {:.0} |",
                        ev.support_tilt.to_degrees(),
                        (ev.support_tilt - ev.phi).to_degrees(),
                        ev.pivot_slip,
                        out.samples.last().unwrap().t / wall
                    ),
                    Err(e) => println!("| {label} | {e} | | | |"),
                }
            }
            Err(e) => println!("| {label} | failed: {e} | | | |"),
        }
    }
}
