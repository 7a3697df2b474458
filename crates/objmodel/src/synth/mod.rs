//! A small kinematic generator of demonstrations with exact ground truth, for tests and for the
//! built-in example data (the physics simulator lives in `objmodel-sim`).
//!
//! A box with half extents `h` rests on a level table (z up). The tracked tag frame sits on the
//! box's top face, off centre and turned about the face normal, so the learner never sees the
//! box's own frame. Motions:
//!
//! * **topple**: rest; a slow rotation about a bottom edge up to the tipping angle; a fast fall to
//!   90°; optionally the pivot slips along the table during the last part of the fall (as a real
//!   box does after 45-60°); rest;
//! * **instrumented topple**: the box rides on a palm plate that tilts about a horizontal axis;
//!   when the tilt reaches the tipping angle the box topples about its downhill edge, relative
//!   to the palm; both box tag and palm are tracked;
//! * **slide**: the box translates and turns on its bottom face;
//! * **general**: the box is lifted, turned about changing axes, and put down;
//! * **compounds** ([`slide_then_topple`], [`topple_then_slide`], [`drop_then_slide`]): a
//!   push that slides the box and then tips it over its leading edge, a topple whose landing
//!   slides on, and a box that drops onto the table and slides into its rest, with no rest
//!   between the parts;
//! * **toss** ([`toss`]): a hand lifts the box and throws it; it flies on an exact parabola
//!   with spin, bounces, flies again, lands and rests (the truth: the flights and the centre
//!   of mass).
//!
//! Tracking noise ([`SynthNoise`]): Gaussian position and orientation noise, dropped frames,
//! quaternion sign flips, and single-frame tag flips (the orientation jumps by 30-60° about an
//! axis in the tag plane for one frame, like a planar tag's mirror solution).
//!
//! How far a learnt edge or face is from the box's own: [`SynthBox::off_edge`],
//! [`SynthBox::off_face`].

mod compound;
mod creep;
mod off_box;
mod toss;

pub use compound::{drop_then_slide, slide_then_topple, topple_then_slide};
pub use creep::{instrumented_creep_topple, instrumented_topple, CreepSlip};
pub use toss::{toss, SynthToss, TOSS_G};

use crate::classify::Kind;
use crate::geometry::Line;
use crate::se3::so3_exp;
use crate::trajectory::{Demonstration, StampedPose};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};
use rand_distr::StandardNormal;
use std::f64::consts::FRAC_PI_2;

/// Tracking noise of the generator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SynthNoise {
    /// Position noise per axis \[m\].
    pub sigma_position: f64,
    /// Orientation noise per axis \[rad\].
    pub sigma_rotation: f64,
    /// Probability that a frame is dropped.
    pub drop: f64,
    /// Probability that a frame's quaternion is negated.
    pub sign_flip: f64,
    /// Probability that a frame is a tag flip.
    pub tag_flip: f64,
}

impl SynthNoise {
    /// Exact poses.
    pub const CLEAN: Self = Self {
        sigma_position: 0.0,
        sigma_rotation: 0.0,
        drop: 0.0,
        sign_flip: 0.0,
        tag_flip: 0.0,
    };
    /// A real AprilTag tracker: 1 mm, 0.5° per axis, 3% dropped frames, 5% sign flips,
    /// 1% tag flips.
    pub const REAL: Self = Self {
        sigma_position: 1e-3,
        sigma_rotation: 0.008_726_646_259_971_648,
        drop: 0.03,
        sign_flip: 0.05,
        tag_flip: 0.01,
    };
}

/// What really happened in a synthetic demonstration, in the tag (object) frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthTruth {
    /// The kind of motion.
    pub kind: Kind,
    /// The edge toppled about (topples).
    pub edge: Option<Line>,
    /// The outward normal and offset of the face slid on (slides), or rested on first.
    pub face: Option<(Vector3<f64>, f64)>,
    /// The tipping angle \[rad\] (topples).
    pub phi: Option<f64>,
}

/// A synthetic demonstration and its truth.
#[derive(Clone, Debug)]
pub struct SynthDemo {
    /// The (noisy) demonstration.
    pub demo: Demonstration,
    /// Ground truth.
    pub truth: SynthTruth,
}

/// A box and where its tag sits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SynthBox {
    /// Half extents \[m\].
    pub half: Vector3<f64>,
    /// `box_from_tag`: the tag's pose in the box frame (box frame at the box's centre).
    pub box_from_tag: Isometry3<f64>,
}

impl SynthBox {
    /// A box with a tag on its top face, `offset` \[m\] from the face centre, turned by `yaw` \[rad\].
    pub fn new(half: Vector3<f64>, offset: (f64, f64), yaw: f64) -> Self {
        let box_from_tag = Isometry3::from_parts(
            Translation3::new(offset.0, offset.1, half.z),
            UnitQuaternion::from_scaled_axis(Vector3::z() * yaw),
        );
        Self { half, box_from_tag }
    }

    /// A random box (edges 6-20 cm) with a randomly placed tag.
    pub fn random(rng: &mut StdRng) -> Self {
        let half = Vector3::new(
            rng.random_range(0.03..0.08),
            rng.random_range(0.03..0.08),
            rng.random_range(0.04..0.10),
        );
        Self::new(
            half,
            (rng.random_range(-0.01..0.01), rng.random_range(-0.01..0.01)),
            rng.random_range(-3.0..3.0),
        )
    }

    fn tag_line(&self, point_box: Vector3<f64>, dir_box: Vector3<f64>) -> Line {
        let tag_from_box = self.box_from_tag.inverse();
        Line::through(
            (tag_from_box * nalgebra::Point3::from(point_box)).coords,
            tag_from_box * dir_box,
        )
    }
}

/// Timing at `rate` \[Hz\] with rest `rest` \[s\] before and after a motion of `duration` \[s\].
fn times(rate: f64, rest: f64, duration: f64) -> Vec<f64> {
    let n = ((2.0 * rest + duration) * rate).round() as usize + 1;
    (0..n).map(|k| 1_700_000_000.0 + k as f64 / rate).collect()
}

/// The smooth ramp `3x² - 2x³` from 0 (x <= 0) to 1 (x >= 1), with zero slope at both ends.
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

fn gauss3(rng: &mut StdRng, s: f64) -> Vector3<f64> {
    Vector3::new(
        rng.sample::<f64, _>(StandardNormal),
        rng.sample::<f64, _>(StandardNormal),
        rng.sample::<f64, _>(StandardNormal),
    ) * s
}

/// Apply tracking noise to exact poses `world_from_tag`.
pub fn add_noise(poses: &[StampedPose], noise: &SynthNoise, rng: &mut StdRng) -> Vec<StampedPose> {
    let mut out = Vec::with_capacity(poses.len());
    for (k, p) in poses.iter().enumerate() {
        // Never drop the first or last frame (the file's extent stays the truth's).
        if k > 0 && k + 1 < poses.len() && rng.random::<f64>() < noise.drop {
            continue;
        }
        let mut q = so3_exp(&gauss3(rng, noise.sigma_rotation)) * p.pose.rotation;
        let t = p.pose.translation.vector + gauss3(rng, noise.sigma_position);
        if rng.random::<f64>() < noise.tag_flip {
            // Mirror-like flip: turn about an axis in the tag plane by 30-60 degrees.
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let axis = Vector3::new(a.cos(), a.sin(), 0.0);
            q *= so3_exp(&(axis * rng.random_range(0.52..1.05)));
        }
        if rng.random::<f64>() < noise.sign_flip {
            q = UnitQuaternion::new_unchecked(-q.into_inner());
        }
        out.push(StampedPose::new(
            p.t,
            Isometry3::from_parts(Translation3::from(t), q),
        ));
    }
    out
}

/// Parameters of a synthetic topple.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToppleParams {
    /// Which bottom edge: 0..4 for +x, +y, -x, -y sides of the box.
    pub side: usize,
    /// Duration \[s\] of the slow rotation up to the tipping angle.
    pub push_s: f64,
    /// Duration \[s\] of the fall from the tipping angle to 90°.
    pub fall_s: f64,
    /// Angle \[rad\] after which the pivot slips.
    pub slip_from: f64,
    /// How far \[m\] the pivot slips by the time the box lands.
    pub slip: f64,
}

impl Default for ToppleParams {
    fn default() -> Self {
        Self {
            side: 0,
            push_s: 1.5,
            fall_s: 0.35,
            slip_from: 50f64.to_radians(),
            slip: 0.008,
        }
    }
}

/// Edge of side `side` in the box frame: (point, direction such that a positive rotation tips
/// the box outwards over it), and the outward horizontal direction of that side.
fn side_edge(half: &Vector3<f64>, side: usize) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let out = match side % 4 {
        0 => Vector3::x(),
        1 => Vector3::y(),
        2 => -Vector3::x(),
        _ => -Vector3::y(),
    };
    let point = Vector3::new(out.x * half.x, out.y * half.y, -half.z);
    // Rotation about d by +α moves +z towards `out`: d = z × out.
    (point, Vector3::z().cross(&out), out)
}

/// The tipping angle φ \[rad\] of a box of half extents `half` over the bottom edge of side
/// `side` (see [`side_edge`]): the angle from the vertical of its centre seen from that edge.
fn tipping_angle(half: &Vector3<f64>, side: usize) -> f64 {
    let along = if side.is_multiple_of(2) {
        half.x
    } else {
        half.y
    };
    along.atan2(half.z)
}

/// The angle \[rad\] of a topple `s` seconds into it: a slow rotation over `push_s` \[s\] to
/// the tipping angle `phi`, then a fall to 90° over `fall_s`.
fn topple_angle(s: f64, phi: f64, push_s: f64, fall_s: f64) -> f64 {
    if s < push_s {
        phi * smoothstep(s / push_s)
    } else {
        let x = ((s - push_s) / fall_s).clamp(0.0, 1.0);
        phi + (FRAC_PI_2 - phi) * x * x
    }
}

/// The pose `box_from_box(t)` of a topple about a bottom edge by angle `alpha`, with the pivot
/// slipped by `slip` \[m\] along `-out` (in the table plane).
fn topple_motion(
    edge_point: &Vector3<f64>,
    dir: &Vector3<f64>,
    out: &Vector3<f64>,
    alpha: f64,
    slip: f64,
) -> Isometry3<f64> {
    let r = so3_exp(&(dir * alpha));
    Isometry3::from_parts(
        Translation3::from(edge_point - r * edge_point - out * slip),
        r,
    )
}

fn world_start(rng: &mut StdRng, half: &Vector3<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(
            rng.random_range(-0.2..0.2),
            rng.random_range(-0.2..0.2),
            half.z,
        ),
        UnitQuaternion::from_scaled_axis(Vector3::z() * rng.random_range(-3.0..3.0)),
    )
}

/// Direct topples of `b` that rest it on every one of its faces: about its four bottom
/// edges, then, turned upside down, about two more, so that every face's offset follows from an
/// edge in it (what a closed shape needs). Named `topple0` .. `topple5`; seeds from `seed`.
pub fn topples_over_every_face(b: &SynthBox, noise: &SynthNoise, seed: u64) -> Vec<SynthDemo> {
    let flipped = SynthBox {
        half: b.half,
        box_from_tag: Isometry3::rotation(Vector3::x() * std::f64::consts::PI) * b.box_from_tag,
    };
    [(b, 0), (b, 1), (b, 2), (b, 3), (&flipped, 0), (&flipped, 1)]
        .into_iter()
        .enumerate()
        .map(|(k, (bx, side))| {
            let p = ToppleParams {
                side,
                ..Default::default()
            };
            let mut d = topple(bx, &p, noise, 30.0, seed * 10 + k as u64);
            d.demo.name = format!("topple{k}");
            d
        })
        .collect()
}

/// A direct topple (no palm) of `b` about the bottom edge `p.side`.
pub fn topple(
    b: &SynthBox,
    p: &ToppleParams,
    noise: &SynthNoise,
    rate: f64,
    seed: u64,
) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let (edge, dir, out) = side_edge(&b.half, p.side);
    let phi = tipping_angle(&b.half, p.side);
    let rest = 1.0;
    let world0 = world_start(&mut rng, &b.half);
    let ts = times(rate, rest, p.push_s + p.fall_s);
    let t0 = ts[0];
    let poses: Vec<StampedPose> = ts
        .iter()
        .map(|&t| {
            let s = t - t0 - rest;
            let alpha = topple_angle(s, phi, p.push_s, p.fall_s);
            let slip = p.slip
                * ((alpha - p.slip_from) / (FRAC_PI_2 - p.slip_from))
                    .clamp(0.0, 1.0)
                    .powi(2);
            StampedPose::new(
                t,
                world0 * topple_motion(&edge, &dir, &out, alpha, slip) * b.box_from_tag,
            )
        })
        .collect();
    let face_n = b.box_from_tag.inverse() * -Vector3::z();
    SynthDemo {
        demo: Demonstration {
            name: format!("topple_{seed}"),
            object: add_noise(&poses, noise, &mut rng),
            palm: None,
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

/// A slide: over `duration` \[s\] the box translates by up to 15 cm and turns by up to ±60°
/// about a vertical axis through a random point, on its bottom face.
pub fn slide(b: &SynthBox, noise: &SynthNoise, rate: f64, seed: u64) -> SynthDemo {
    slide_turning(b, noise, rate, seed, true)
}

/// A straight push: the box slides on its bottom face by 5 to 21 cm (the translation drawn as
/// in [`slide`], lengthened to at least 5 cm) without turning, so that the motion leaves the
/// face normal undetermined about the direction of travel; it pitches by up to 4e-4 rad about
/// the horizontal axis across the push, as pushed boxes do in physics engines with soft contacts
/// (MuJoCo, `bench/mujoco_probe.py`), which pulls a fitted normal towards that axis.
pub fn straight_slide(b: &SynthBox, noise: &SynthNoise, rate: f64, seed: u64) -> SynthDemo {
    slide_turning(b, noise, rate, seed, false)
}

/// Largest pitch \[rad\] of a straight push about the horizontal axis across the push.
const PUSH_PITCH_RAD: f64 = 4e-4;

/// [`slide`], or with `turn` false [`straight_slide`].
fn slide_turning(b: &SynthBox, noise: &SynthNoise, rate: f64, seed: u64, turn: bool) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let world0 = world_start(&mut rng, &b.half);
    let mut shift: Vector3<f64> = Vector3::new(
        rng.random_range(-0.15..0.15),
        rng.random_range(-0.15..0.15),
        0.0,
    );
    if !turn && shift.norm() < 0.05 {
        shift *= 0.05 / shift.norm().max(1e-9);
    }
    let yaw: f64 = rng.random_range(0.3..1.0) * if rng.random::<bool>() { 1.0 } else { -1.0 };
    let yaw = if turn { yaw } else { 0.0 };
    let pivot = Vector3::new(
        rng.random_range(-0.1..0.1),
        rng.random_range(-0.1..0.1),
        0.0,
    );
    let (rest, duration) = (1.0, rng.random_range(1.5..3.0));
    let ts = times(rate, rest, duration);
    let t0 = ts[0];
    let poses: Vec<StampedPose> = ts
        .iter()
        .map(|&t| {
            let x = smoothstep((t - t0 - rest) / duration);
            // Translation and rotation progress at different rates: a non-stationary axode.
            let r = so3_exp(&(Vector3::z() * yaw * x));
            let move_world = Isometry3::from_parts(
                Translation3::from(pivot - r * pivot + shift * x.powf(1.7)),
                r,
            );
            let w0 = world0.translation.vector;
            let to_origin = Isometry3::translation(-w0.x, -w0.y, 0.0);
            let world_from_box = to_origin.inverse() * move_world * to_origin * world0;
            if turn {
                return StampedPose::new(t, world_from_box * b.box_from_tag);
            }
            // A pushed box pitches a little about the horizontal axis across the push (soft
            // contacts, friction torque): 0.02° at most, about its bottom centre.
            let bottom = world_from_box * nalgebra::Point3::new(0.0, 0.0, -b.half.z);
            let across = Vector3::z().cross(&shift).normalize();
            let pitch = PUSH_PITCH_RAD * (std::f64::consts::PI * x).sin();
            let rock = Isometry3::translation(bottom.x, bottom.y, bottom.z)
                * Isometry3::rotation(across * pitch)
                * Isometry3::translation(-bottom.x, -bottom.y, -bottom.z);
            StampedPose::new(t, rock * world_from_box * b.box_from_tag)
        })
        .collect();
    let n = b.box_from_tag.inverse() * -Vector3::z();
    let bottom = b.box_from_tag.inverse() * nalgebra::Point3::new(0.0, 0.0, -b.half.z);
    SynthDemo {
        demo: Demonstration {
            name: format!("{}slide_{seed}", if turn { "" } else { "straight_" }),
            object: add_noise(&poses, noise, &mut rng),
            palm: None,
        },
        truth: SynthTruth {
            kind: Kind::Slide,
            edge: None,
            face: Some((n, n.dot(&bottom.coords))),
            phi: None,
        },
    }
}

/// A general motion: lifted 10-20 cm while turning about two changing axes, and put down.
pub fn general(b: &SynthBox, noise: &SynthNoise, rate: f64, seed: u64) -> SynthDemo {
    let mut rng = StdRng::seed_from_u64(seed);
    let world0 = world_start(&mut rng, &b.half);
    let a1 = gauss3(&mut rng, 1.0).normalize() * rng.random_range(0.6..1.2);
    let a2 = gauss3(&mut rng, 1.0).normalize() * rng.random_range(0.6..1.2);
    let lift = Vector3::new(
        rng.random_range(-0.1..0.1),
        rng.random_range(-0.1..0.1),
        rng.random_range(0.1..0.2),
    );
    let (rest, duration) = (1.0, 2.5);
    let ts = times(rate, rest, duration);
    let t0 = ts[0];
    let poses: Vec<StampedPose> = ts
        .iter()
        .map(|&t| {
            let x = ((t - t0 - rest) / duration).clamp(0.0, 1.0);
            let up = (std::f64::consts::PI * x).sin();
            let r =
                so3_exp(&(a1 * smoothstep(2.0 * x))) * so3_exp(&(a2 * smoothstep(2.0 * x - 1.0)));
            let m = Isometry3::from_parts(
                Translation3::from(lift * up + Vector3::new(0.05, 0.0, 0.0) * x),
                r,
            );
            StampedPose::new(
                t,
                Isometry3::from_parts(world0.translation, UnitQuaternion::identity())
                    * m
                    * Isometry3::from_parts(Translation3::identity(), world0.rotation)
                    * b.box_from_tag,
            )
        })
        .collect();
    SynthDemo {
        demo: Demonstration {
            name: format!("general_{seed}"),
            object: add_noise(&poses, noise, &mut rng),
            palm: None,
        },
        truth: SynthTruth {
            kind: Kind::General,
            edge: None,
            face: None,
            phi: None,
        },
    }
}
