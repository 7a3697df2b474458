//! Compound demonstrations: two contact modes in a row with no rest between them, the motions
//! the paper leaves to future work ("temporal segmentation of demonstrations based on type of
//! motion"). Their truth is the one edge and the faces the box really has: a learner may teach
//! less, never something else.

use super::{
    add_noise, side_edge, smoothstep, times, tipping_angle, topple_angle, topple_motion,
    world_start, SynthBox, SynthDemo, SynthNoise, SynthTruth,
};
use crate::classify::Kind;
use crate::trajectory::{Demonstration, StampedPose};
use nalgebra::{Isometry3, Translation3, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// Duration \[s\] of the slide part.
const SLIDE_S: f64 = 1.2;
/// Duration \[s\] of the slow rotation up to the tipping angle, and of the fall to 90°.
const PUSH_S: f64 = 1.5;
const FALL_S: f64 = 0.35;

/// A push that first slides the box by `slide_m` \[m\] on its bottom face towards the side
/// `side` (0..4: +x, +y, -x, -y of the box) and then, without stopping, tips it over that side's
/// bottom edge to 90°: rest 1 s, slide, topple, rest 1 s. The edge is fixed in the object, but
/// the topple starts where the slide ended, not at the pose before the slide.
pub fn slide_then_topple(
    b: &SynthBox,
    side: usize,
    slide_m: f64,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let (edge, dir, out) = side_edge(&b.half, side);
    let phi = tipping_angle(&b.half, side);
    let rest = 1.0;
    let world0 = world_start(&mut rng, &b.half);
    let ts = times(rate, rest, SLIDE_S + PUSH_S + FALL_S);
    let t0 = ts[0];
    let poses: Vec<StampedPose> = ts
        .iter()
        .map(|&t| {
            let s = t - t0 - rest;
            let slid = out * slide_m * smoothstep(s / SLIDE_S);
            let alpha = topple_angle(s - SLIDE_S, phi, PUSH_S, FALL_S).max(0.0);
            let world_from_box =
                world0 * Translation3::from(slid) * topple_motion(&edge, &dir, &out, alpha, 0.0);
            StampedPose::new(t, world_from_box * b.box_from_tag)
        })
        .collect();
    truth_of(
        b,
        edge,
        dir,
        phi,
        format!("slide_then_topple_{seed}"),
        poses,
        noise,
        &mut rng,
    )
}

/// A topple over the bottom edge of side `side` whose landing slides on: the box turns to 90°
/// and, without stopping, slides `slide_m` \[m\] on the face it landed on, away from where it
/// stood: rest 1 s, topple, slide, rest 1 s.
pub fn topple_then_slide(
    b: &SynthBox,
    side: usize,
    slide_m: f64,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let (edge, dir, out) = side_edge(&b.half, side);
    let phi = tipping_angle(&b.half, side);
    let rest = 1.0;
    let world0 = world_start(&mut rng, &b.half);
    let ts = times(rate, rest, PUSH_S + FALL_S + SLIDE_S);
    let t0 = ts[0];
    let poses: Vec<StampedPose> = ts
        .iter()
        .map(|&t| {
            let s = t - t0 - rest;
            let alpha = topple_angle(s, phi, PUSH_S, FALL_S).max(0.0);
            let slid = out * slide_m * smoothstep((s - PUSH_S - FALL_S) / SLIDE_S);
            let world_from_box = world0
                * Isometry3::from_parts(Translation3::from(slid), Default::default())
                * topple_motion(&edge, &dir, &out, alpha, 0.0);
            StampedPose::new(t, world_from_box * b.box_from_tag)
        })
        .collect();
    truth_of(
        b,
        edge,
        dir,
        phi,
        format!("topple_then_slide_{seed}"),
        poses,
        noise,
        &mut rng,
    )
}

/// A box that falls onto the table turning (a toss's last bounce), lands flat on its bottom
/// face and, without stopping, slides `slide_m` \[m\] towards the side `side` into a rest of
/// 1 s. The file starts in the air: there is no rest before the motion, and the only face the
/// demonstration shows is the one it slides on and rests on.
pub fn drop_then_slide(
    b: &SynthBox,
    side: usize,
    slide_m: f64,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let (edge, dir, out) = side_edge(&b.half, side);
    let world0 = world_start(&mut rng, &b.half);
    let spin = Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    let (fall_s, height) = (0.4, 0.15);
    let ts = times(rate, 0.0, fall_s + SLIDE_S + 1.0);
    let t0 = ts[0];
    let poses: Vec<StampedPose> = ts
        .iter()
        .map(|&t| {
            let s = t - t0;
            // Falling: height and spin go to zero at touchdown, at constant deceleration
            // towards it (a kinematic stand-in for the last bounce).
            let left = ((fall_s - s) / fall_s).clamp(0.0, 1.0);
            let up = Vector3::z() * height * left * left;
            let turn = crate::se3::so3_exp(&(spin * left * left));
            let slid = out * slide_m * smoothstep((s - fall_s) / SLIDE_S);
            let world_from_box = Translation3::from(up + slid)
                * world0
                * Isometry3::from_parts(Default::default(), turn);
            StampedPose::new(t, world_from_box * b.box_from_tag)
        })
        .collect();
    let phi = 0.0;
    truth_of(
        b,
        edge,
        dir,
        phi,
        format!("drop_then_slide_{seed}"),
        poses,
        noise,
        &mut rng,
    )
}

/// The demonstration (noise added) and its truth: the edge, and the bottom face rested on first.
#[allow(clippy::too_many_arguments)]
fn truth_of(
    b: &SynthBox,
    edge: Vector3<f64>,
    dir: Vector3<f64>,
    phi: f64,
    name: String,
    poses: Vec<StampedPose>,
    noise: &SynthNoise,
    rng: &mut StdRng,
) -> SynthDemo {
    let face_n = b.box_from_tag.inverse() * -Vector3::z();
    let face_p = b.box_from_tag.inverse() * nalgebra::Point3::from(edge);
    SynthDemo {
        demo: Demonstration {
            name,
            object: add_noise(&poses, noise, rng),
            palm: None,
        },
        truth: SynthTruth {
            kind: Kind::Topple,
            edge: Some(b.tag_line(edge, dir)),
            face: Some((face_n, face_n.dot(&face_p.coords))),
            phi: Some(phi),
        },
    }
}
