use super::*;
use crate::se3::so3_exp;
use nalgebra::{Matrix3, UnitQuaternion};
use rand::{rngs::StdRng, Rng, SeedableRng};
use rand_distr::{Distribution, Normal};

/// χ²₃ quantile at 0.01 / 3: the flight test's threshold at its level.
fn threshold() -> f64 {
    crate::stats::chi2_threshold(3.0, 0.01 / 3.0)
}

/// Frames of `rotation(t)` sampled at `hz` for `duration` s, each turned by a random error of
/// `sigma` rad per axis.
fn sampled(
    rotation: impl Fn(f64) -> UnitQuaternion<f64>,
    hz: f64,
    duration: f64,
    sigma: f64,
    rng: &mut StdRng,
) -> Vec<FlightFrame> {
    let noise = Normal::new(0.0, sigma.max(1e-300)).unwrap();
    let n = (duration * hz).round() as usize + 1;
    (0..n)
        .map(|k| {
            let t = k as f64 / hz;
            let e = Vector3::from_fn(|_, _| noise.sample(rng));
            FlightFrame {
                t,
                rotation: (so3_exp(&e) * rotation(t))
                    .to_rotation_matrix()
                    .into_inner(),
                position: Vector3::zeros(),
            }
        })
        .collect()
}

/// A free rigid body with principal moments `moments` (body frame = principal axes) from
/// `start` with body angular velocity `w0`: Euler's equations by RK4 at 20 µs, the orientation
/// by the body rates; the orientation at `t` (s), sampled from the integration.
fn free_body(
    moments: Vector3<f64>,
    start: UnitQuaternion<f64>,
    w0: Vector3<f64>,
    duration: f64,
) -> Vec<(f64, UnitQuaternion<f64>)> {
    let euler = |w: &Vector3<f64>| -> Vector3<f64> {
        let l = moments.component_mul(w);
        -w.cross(&l).component_div(&moments)
    };
    let h = 2e-5;
    let (mut q, mut w, mut t) = (start, w0, 0.0);
    let mut out = vec![(0.0, q)];
    while t < duration + 0.01 {
        let k1 = euler(&w);
        let k2 = euler(&(w + k1 * (h / 2.0)));
        let k3 = euler(&(w + k2 * (h / 2.0)));
        let k4 = euler(&(w + k3 * h));
        let w_next = w + (k1 + 2.0 * k2 + 2.0 * k3 + k4) * (h / 6.0);
        q *= so3_exp(&((w + w_next) * (h / 2.0)));
        w = w_next;
        t += h;
        out.push((t, q));
    }
    out
}

/// Free bodies of any shape (boxes from a cube to a rod and a plate, spun at up to 20 rad/s
/// about any axis, tumbling about their unstable middle axis too), tracked at 30-250 Hz with
/// 0-0.5° of noise over 0.05-0.4 s: the test passes them at least as often as its level says
/// (at most 1% rejected; it is conservative, so in practice none).
#[test]
fn a_free_body_turns_freely_whatever_its_inertia() {
    let mut rng = StdRng::seed_from_u64(57);
    let (trials, mut rejected) = (300, 0);
    for _ in 0..trials {
        let sides = Vector3::from_fn(|_, _| rng.random_range(0.01..0.4f64));
        let moments = Vector3::new(
            sides.y.powi(2) + sides.z.powi(2),
            sides.x.powi(2) + sides.z.powi(2),
            sides.x.powi(2) + sides.y.powi(2),
        ) / 12.0;
        let start = so3_exp(&Vector3::from_fn(|_, _| rng.random_range(-3.0..3.0f64)));
        let w0 = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0f64)).normalize()
            * rng.random_range(0.5..20.0);
        let duration = rng.random_range(0.05..0.4);
        let path = free_body(moments, start, w0, duration);
        let at = |t: f64| path[((t / 2e-5).round() as usize).min(path.len() - 1)].1;
        let hz = rng.random_range(30.0..250.0);
        let sigma = rng.random_range(0.0..0.5f64).to_radians();
        let frames = sampled(at, hz, duration, sigma, &mut rng);
        let chi2 = torque_chi2(&frames, sigma.max(crate::noise::MIN_SIGMA_ROTATION_RAD));
        if chi2 > threshold() {
            rejected += 1;
        }
    }
    assert!(rejected <= trials / 100, "{rejected} of {trials} rejected");
}

/// A box toppling about its edge (a pendulum falling from near its balance, `θ̈ = (g/l) sin θ`
/// with l = 0.1 m) and a box rolling on an edge whose turn reverses (the ContactNets cube's,
/// 5 rad/s one way to 5 the other in 0.12 s): at motion-capture noise (0.15°, 120 Hz) and at a
/// camera's (0.5°, 30 Hz over twice as long), no free body turns so; the test says so.
#[test]
fn a_topple_and_a_turn_reversed_by_a_contact_are_not_free() {
    let mut rng = StdRng::seed_from_u64(58);
    let axis = Vector3::new(0.3, -0.8, 0.1).normalize();
    // The pendulum: θ from 0.05 rad, ω from 0, integrated finely; sampled by time.
    let mut fall = vec![(0.05f64, 0.0f64)];
    let h = 1e-5;
    for _ in 0..60_000 {
        let (th, w) = *fall.last().unwrap();
        let a = crate::pendulum::G / 0.1 * th.sin();
        fall.push((th + w * h, w + a * h));
    }
    let topple = |t: f64| so3_exp(&(axis * fall[(t / h) as usize].0));
    let reversal = |t: f64| so3_exp(&(axis * (5.0 * t - 5.0 / 0.12 * t * t)));
    for (hz, sigma, scale) in [
        (120.0, 0.15f64.to_radians(), 1.0),
        (30.0, 0.5f64.to_radians(), 2.0),
    ] {
        for (name, start, duration) in [("topple", 0.1, 0.15), ("reversal", 0.0, 0.12)] {
            let rotation = |t: f64| {
                if name == "topple" {
                    topple(start + t)
                } else {
                    reversal(t / scale)
                }
            };
            let frames = sampled(rotation, hz, duration * scale, sigma, &mut rng);
            let chi2 = torque_chi2(&frames, sigma);
            assert!(chi2 > threshold(), "{name} at {hz} Hz: χ² {chi2}");
        }
    }
}

/// A constant spin is free: with exact poses the statistic is 0; a window of two steps has
/// nothing to compare.
#[test]
fn a_steady_spin_is_free_and_two_steps_test_nothing() {
    let w = Vector3::new(4.0, -2.0, 7.0);
    let frames: Vec<FlightFrame> = (0..20)
        .map(|k| {
            let t = k as f64 / 100.0;
            FlightFrame {
                t,
                rotation: so3_exp(&(w * t)).to_rotation_matrix().into_inner(),
                position: Vector3::zeros(),
            }
        })
        .collect();
    assert_eq!(torque_chi2(&frames, 1e-3), 0.0);
    let still = FlightFrame {
        t: 0.0,
        rotation: Matrix3::identity(),
        position: Vector3::zeros(),
    };
    let jump = FlightFrame {
        t: 0.01,
        rotation: so3_exp(&Vector3::new(0.5, 0.0, 0.0))
            .to_rotation_matrix()
            .into_inner(),
        ..still
    };
    let back = FlightFrame { t: 0.02, ..still };
    assert_eq!(torque_chi2(&[still, jump, back], 1e-3), 0.0);
}
