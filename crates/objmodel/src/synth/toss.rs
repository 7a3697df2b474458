//! A kinematic toss with exact flights: the box rests, a hand lifts it while it starts to
//! spin (an acceleration that is not gravity's), releases it; it flies on an exact parabola
//! (its centre falls with gravity, it spins at a constant rate about a random axis), bounces
//! (its vertical velocity reverses, scaled by a restitution, its spin changes), flies again and
//! lands, stopping dead, and rests. The truth is the flights' times and the centre of mass in
//! the tag frame.

use super::{add_noise, world_start, SynthBox, SynthNoise};
use crate::se3::so3_exp;
use crate::trajectory::{Demonstration, StampedPose};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// Gravity of the generator \[m/s²\] (z up).
pub const TOSS_G: f64 = crate::pendulum::G;

/// A synthetic toss and its truth.
#[derive(Clone, Debug)]
pub struct SynthToss {
    /// The (noisy) demonstration, `world_from_tag`.
    pub demo: Demonstration,
    /// The flights' start and end times \[s\] (release to bounce, bounce to landing).
    pub flights: Vec<(f64, f64)>,
    /// The centre of mass (the box's centre) in the tag frame \[m\].
    pub com: Vector3<f64>,
}

/// The box's pose at one instant: centre (world) and orientation.
#[derive(Clone, Copy, Debug)]
struct State {
    centre: Vector3<f64>,
    rotation: UnitQuaternion<f64>,
}

/// A toss of `b` tracked at `rate` \[Hz\]: 1 s of rest, a 0.5 s lift, two flights, 1 s of
/// rest after the landing.
pub fn toss(b: &SynthBox, noise: &SynthNoise, rate: f64, seed: u64) -> SynthToss {
    let mut rng = StdRng::seed_from_u64(seed);
    let start = world_start(&mut rng, &b.half);
    let unit = |rng: &mut StdRng| loop {
        let v = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if (0.2..1.0).contains(&v.norm()) {
            return v.normalize();
        }
    };
    let (rest, lift) = (1.0, 0.5);
    let lift_height = rng.random_range(0.1..0.3);
    let heading: f64 = rng.random_range(-3.2..3.2);
    let speed = rng.random_range(0.2..1.2);
    let v_release = Vector3::new(
        speed * heading.cos(),
        speed * heading.sin(),
        rng.random_range(-0.3..1.0),
    );
    let spin1 = unit(&mut rng) * rng.random_range(1.0..12.0);
    let spin2 = unit(&mut rng) * rng.random_range(1.0..8.0);
    let restitution = rng.random_range(0.2..0.5);
    // In flight the box spins about a body axis that precesses (a torque-free top's motion).
    let body = unit(&mut rng) * rng.random_range(2.0..6.0);
    let g = Vector3::new(0.0, 0.0, -TOSS_G);
    let p0 = start.translation.vector;
    let q0 = start.rotation;
    // The lift: the hand raises the box by lift_height, decelerating, while it speeds it up
    // to the release velocity at a constant rate and spins it up to spin1: an acceleration
    // within 4 m/s² of level, never gravity's.
    let lifted = |s: f64| -> State {
        let u = s / lift;
        State {
            centre: p0
                + v_release * (0.5 * s * u)
                + Vector3::new(0.0, 0.0, lift_height * (1.0 - (1.0 - u).powi(2))),
            rotation: so3_exp(&(spin1 * (0.5 * s * u))) * q0,
        }
    };
    let at_release = lifted(lift);
    // Flight 1 until the centre is back at its resting height; then the bounce.
    let fall_time =
        |z0: f64, vz: f64| (vz + (vz * vz + 2.0 * TOSS_G * (z0 - p0.z)).sqrt()) / TOSS_G;
    let t1 = fall_time(at_release.centre.z, v_release.z);
    let bounce_c = at_release.centre + v_release * t1 + 0.5 * g * t1 * t1;
    let bounce_q = so3_exp(&(spin1 * t1)) * at_release.rotation * so3_exp(&(body * t1));
    let v_in = v_release + g * t1;
    let v_out = Vector3::new(0.6 * v_in.x, 0.6 * v_in.y, -restitution * v_in.z);
    let t2 = 2.0 * v_out.z / TOSS_G;
    let flight = |c: Vector3<f64>, q: UnitQuaternion<f64>, v: Vector3<f64>, w: Vector3<f64>| {
        move |s: f64| State {
            centre: c + v * s + 0.5 * g * s * s,
            rotation: so3_exp(&(w * s)) * q * so3_exp(&(body * s)),
        }
    };
    let f1 = flight(at_release.centre, at_release.rotation, v_release, spin1);
    let f2 = flight(bounce_c, bounce_q, v_out, spin2);
    let landed = f2(t2);
    let duration = rest + lift + t1 + t2 + rest;
    let n = (duration * rate).round() as usize + 1;
    let t0 = 1_700_000_000.0;
    let poses: Vec<StampedPose> = (0..n)
        .map(|k| {
            let s = k as f64 / rate;
            let st = if s < rest {
                State {
                    centre: p0,
                    rotation: q0,
                }
            } else if s < rest + lift {
                lifted(s - rest)
            } else if s < rest + lift + t1 {
                f1(s - rest - lift)
            } else if s < rest + lift + t1 + t2 {
                f2(s - rest - lift - t1)
            } else {
                landed
            };
            let world_from_box = Isometry3::from_parts(Translation3::from(st.centre), st.rotation);
            StampedPose::new(t0 + s, world_from_box * b.box_from_tag)
        })
        .collect();
    let release = t0 + rest + lift;
    SynthToss {
        demo: Demonstration {
            name: format!("toss_{seed}"),
            object: add_noise(&poses, noise, &mut rng),
            palm: None,
        },
        flights: vec![(release, release + t1), (release + t1, release + t1 + t2)],
        com: (b.box_from_tag.inverse() * nalgebra::Point3::origin()).coords,
    }
}
