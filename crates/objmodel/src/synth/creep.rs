//! An instrumented topple on a soft, sticky contact, as MuJoCo's tilting palm shows it: while
//! the palm tilts, the box lags it (turns back a little on its downhill edge, then forward
//! again) and creeps down it in stick-slip steps; when the tilt reaches the tipping angle the
//! box falls over its downhill edge, and past `slip_from` the edge slips on the palm.

use super::{
    add_noise, side_edge, smoothstep, so3_exp, times, tipping_angle, topple_motion, SynthBox,
    SynthDemo, SynthNoise, SynthTruth,
};
use crate::classify::Kind;
use crate::trajectory::{Demonstration, StampedPose};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::f64::consts::{FRAC_PI_2, PI};

/// How the contact creeps and slips in [`instrumented_creep_topple`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepSlip {
    /// How far \[m\] the box creeps down the palm during the tilt, in `creep_steps` equal
    /// steps of 0.1 s each.
    pub creep_m: f64,
    /// Number of stick-slip steps of the creep.
    pub creep_steps: usize,
    /// Largest lag \[rad\]: the box turns back by up to this on its downhill edge during the
    /// tilt, and forward again to none at the onset.
    pub lag_rad: f64,
    /// Angle \[rad\] of the fall after which the edge slips on the palm...
    pub slip_from: f64,
    /// ... by this much \[m\] (outwards, growing with the square of the angle past
    /// `slip_from`) by the time the box lands.
    pub slip_m: f64,
}

impl CreepSlip {
    /// No creep, lag or slip: the box rides the palm rigidly until it falls over its edge
    /// ([`super::instrumented_topple`]).
    pub const NONE: CreepSlip = CreepSlip {
        creep_m: 0.0,
        creep_steps: 1,
        lag_rad: 0.0,
        slip_from: 0.0,
        slip_m: 0.0,
    };
}

impl Default for CreepSlip {
    /// MuJoCo's palm topples: 1.5 mm of creep in 3 steps, 0.6° of lag, a 3 mm slip past 45°.
    fn default() -> Self {
        Self {
            creep_m: 1.5e-3,
            creep_steps: 3,
            lag_rad: 0.6f64.to_radians(),
            slip_from: 45f64.to_radians(),
            slip_m: 3e-3,
        }
    }
}

/// An instrumented topple of `b` over its bottom edge `side` on a palm tilting at `tilt_rate`
/// \[rad/s\], with the creep, lag and slip of `cs` (see the module documentation). The truth's
/// edge is the box's own edge: the creep and the slip move the box on the palm, not its edge in
/// the box.
pub fn instrumented_creep_topple(
    b: &SynthBox,
    side: usize,
    tilt_rate: f64,
    cs: &CreepSlip,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
) -> SynthDemo {
    palm_topple(
        b,
        side,
        tilt_rate,
        cs,
        noise,
        rate,
        seed,
        "instrumented_creep",
    )
}

/// An instrumented topple: the box rides on a palm that tilts about a horizontal axis at
/// `tilt_rate` \[rad/s\]; when the tilt reaches φ the box falls over its downhill edge `side`.
pub fn instrumented_topple(
    b: &SynthBox,
    side: usize,
    tilt_rate: f64,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
) -> SynthDemo {
    palm_topple(
        b,
        side,
        tilt_rate,
        &CreepSlip::NONE,
        noise,
        rate,
        seed,
        "instrumented",
    )
}

/// The palm topple of [`instrumented_creep_topple`], named `{name}_{seed}`; with
/// [`CreepSlip::NONE`] it is [`instrumented_topple`].
#[allow(clippy::too_many_arguments)]
pub(super) fn palm_topple(
    b: &SynthBox,
    side: usize,
    tilt_rate: f64,
    cs: &CreepSlip,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
    name: &str,
) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let (edge, dir, out) = side_edge(&b.half, side);
    let phi = tipping_angle(&b.half, side);
    let (rest, fall_s) = (1.0, 0.3);
    let tilt_s = phi / tilt_rate;
    let palm0 = Isometry3::from_parts(
        Translation3::new(0.5, 0.0, 0.3),
        UnitQuaternion::from_scaled_axis(Vector3::z() * rng.random_range(-3.0..3.0)),
    );
    let palm_from_box0 = Isometry3::from_parts(
        Translation3::new(
            rng.random_range(-0.02..0.02),
            rng.random_range(-0.02..0.02),
            b.half.z,
        ),
        UnitQuaternion::from_scaled_axis(Vector3::z() * rng.random_range(-3.0..3.0)),
    );
    // The palm tilts about the box's edge direction (expressed in the palm frame), so that the
    // box's `side` goes downhill.
    let tilt_axis = palm_from_box0.rotation * dir;
    let ts = times(rate, rest, tilt_s + fall_s);
    let t0 = ts[0];
    let steps = cs.creep_steps.max(1);
    let (mut object, mut palm) = (Vec::with_capacity(ts.len()), Vec::with_capacity(ts.len()));
    for &t in &ts {
        let s = t - t0 - rest;
        let beta = tilt_rate * s.clamp(0.0, tilt_s);
        let world_from_palm =
            palm0 * Isometry3::from_parts(Translation3::identity(), so3_exp(&(tilt_axis * beta)));
        // The creep: `steps` steps of 0.1 s, evenly spread over the tilt.
        let creep = (0..steps)
            .map(|k| {
                let start = tilt_s * (k as f64 + 0.5) / steps as f64 - 0.05;
                smoothstep((s - start) / 0.1)
            })
            .sum::<f64>()
            * cs.creep_m
            / steps as f64;
        let x = ((s - tilt_s) / fall_s).clamp(0.0, 1.0);
        // The lag: a turn back about the middle of the bottom face, none at the onset.
        let lag = -cs.lag_rad * (PI * (s / tilt_s).clamp(0.0, 1.0)).sin();
        let centre = Vector3::new(0.0, 0.0, -b.half.z);
        let lagged = topple_motion(&centre, &dir, &out, lag, 0.0);
        let alpha = FRAC_PI_2 * x * x;
        let slip = cs.slip_m
            * ((alpha - cs.slip_from) / (FRAC_PI_2 - cs.slip_from))
                .clamp(0.0, 1.0)
                .powi(2);
        let palm_from_box = palm_from_box0
            * Translation3::from(out * creep)
            * lagged
            * topple_motion(&edge, &dir, &out, alpha, -slip);
        object.push(StampedPose::new(
            t,
            world_from_palm * palm_from_box * b.box_from_tag,
        ));
        palm.push(StampedPose::new(t, world_from_palm));
    }
    let face_n = b.box_from_tag.inverse() * -Vector3::z();
    SynthDemo {
        demo: Demonstration {
            name: format!("{name}_{seed}"),
            object: add_noise(&object, noise, &mut rng),
            palm: Some(add_noise(&palm, noise, &mut rng)),
        },
        truth: SynthTruth {
            kind: Kind::Topple,
            edge: Some(b.tag_line(edge, dir)),
            face: Some((
                face_n,
                face_n.dot(&(b.box_from_tag.inverse() * nalgebra::Point3::from(edge)).coords),
            )),
            phi: Some(phi),
        },
    }
}
