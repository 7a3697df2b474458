//! Planning speed: choosing the tilt from the learnt pendulum ([`objmodel::skill::plan`])
//! against finding the tipping tilt by bisection with the full 6D simulation (each probe a rapier
//! run of the box on a kinematic plate tilted to the probe angle at 4°/s and held).

use crate::scenes::{instrumented::PLATE_HALF, Run};
use crate::spec::BoxSpec;
use crate::world::PhysicsParams;
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use objmodel::skill::{plan, PlanRequest};
use objmodel::tree::Tree;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The comparison.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SpeedReport {
    /// Mean time of one `skill::plan` call \[µs\].
    pub plan_us: f64,
    /// φ the plan uses \[deg\].
    pub plan_phi_deg: f64,
    /// Wall time of the simulation search \[s\].
    pub search_s: f64,
    /// Probes (simulations) the search ran.
    pub probes: usize,
    /// Tipping tilt found by the search \[deg\].
    pub search_phi_deg: f64,
    /// `search_s / plan time`.
    pub ratio: f64,
}

/// Whether the box (on its `-z` face, downhill box direction `sign · e_axis`) topples when the
/// plate is tilted to `theta` at `rate` and held for 1.5 s (rapier, physics defaults).
pub fn probe(spec: &BoxSpec, axis: usize, sign: f64, theta: f64, rate: f64) -> bool {
    let p = PhysicsParams::default();
    let mut run = Run::new(&p);
    let plate0 = Isometry3::translation(0.0, 0.0, 0.25);
    let plate = run
        .world
        .add_plate(PLATE_HALF, spec.friction.max(1.0), &plate0);
    run.plate = Some(plate);
    let h = spec.half_extents();
    let mut e = Vector3::zeros();
    e[axis] = sign;
    // start uphill so the box lands on the plate
    let start = Isometry3::from_parts(
        Translation3::new(-e.x * 0.05, -e.y * 0.05, h.z + 1e-4),
        UnitQuaternion::identity(),
    );
    run.place_box(spec, spec.friction, &(plate0 * start));
    if run.rest(0.5).is_err() {
        return false;
    }
    let a = Unit::new_normalize(Vector3::z().cross(&e));
    let down = -Vector3::z();
    let mut th = 0.0;
    let hold_end = theta / rate + 1.5;
    let t0 = run.world.t;
    while run.world.t - t0 < hold_end {
        th = (th + rate * run.world.dt).min(theta);
        let pose = Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 0.25),
            UnitQuaternion::from_axis_angle(&a, th),
        );
        run.world.set_kinematic(plate, &pose);
        if run.step().is_err() {
            return true;
        }
        if run.tilt(&down) > 20f64.to_radians() {
            return true;
        }
    }
    false
}

/// Time `skill::plan` (`reps` calls) against a bisection to `tol` \[rad\] with [`probe`].
pub fn compare(
    tree: &Tree,
    req: &PlanRequest,
    spec: &BoxSpec,
    axis: usize,
    sign: f64,
    reps: usize,
    tol: f64,
) -> objmodel::Result<SpeedReport> {
    let p0 = plan(tree, req)?;
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..reps.max(1) {
        acc += plan(tree, req).map(|p| p.tilt).unwrap_or(0.0);
    }
    let plan_s = t.elapsed().as_secs_f64() / reps.max(1) as f64;
    std::hint::black_box(acc);
    let rate = 4f64.to_radians();
    let t = Instant::now();
    let (mut lo, mut hi) = (0.0f64, 45f64.to_radians());
    let mut probes = 0;
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        probes += 1;
        if probe(spec, axis, sign, mid, rate) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let search_s = t.elapsed().as_secs_f64();
    Ok(SpeedReport {
        plan_us: plan_s * 1e6,
        plan_phi_deg: p0.phi.to_degrees(),
        search_s,
        probes,
        search_phi_deg: (0.5 * (lo + hi)).to_degrees(),
        ratio: search_s / plan_s,
    })
}
