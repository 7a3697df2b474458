//! The frames of a span of a demonstration classified again as a demonstration of their own:
//! from a rest held at one frame's pose, or from a rest of the recording itself; and the
//! palm's pose between its kept poses (an instrumented demonstration is re-measured in a
//! world where the palm stays at its first pose, `P₀ · palm⁻¹ · object`).

use crate::classify::{classify, Classification, Config, MIN_EDGE_FRAMES};
use crate::recording::{RecordedFrame, Recording};
use crate::trajectory::{Demonstration, StampedPose};
use nalgebra::{Isometry3, Translation3};

/// Seconds of rest held at the reference pose before a re-measured part, as a multiple of the
/// classifier's `min_rest_s` (the rest must be long enough to start a segment).
const HELD_REST: f64 = 1.25;

/// The frames from `reference` to `t_end` (exclusive), after a rest held at the reference
/// pose, classified; instrumented ones in the palm's first pose. Frame indices are mapped back
/// to the first pass's; the held rest's frames are dropped from the labels.
pub(super) fn classify_from(
    c: &Classification,
    recording: &Recording,
    config: &Config,
    reference: &RecordedFrame,
    t_end: f64,
) -> Option<Classification> {
    classify_span(c, recording, config, Start::Held(reference), t_end)
}

/// Where a re-measured span starts: a rest held at one frame's pose, then the frames from
/// that frame on; or the kept frames from a time on (a rest of the recording itself, whose
/// mean pose is the reference), the first `skip` of them not re-labelled.
#[derive(Clone, Copy)]
pub(super) enum Start<'a> {
    Held(&'a RecordedFrame),
    Frames { t_from: f64, skip: usize },
}

/// The frames from `start` to `t_end` (exclusive) classified; instrumented ones in the palm's
/// first pose. Frame indices are mapped back to the first pass's; the held rest's frames (or
/// the first `skip` frames) and the reference are dropped from the labels.
pub(super) fn classify_span(
    c: &Classification,
    recording: &Recording,
    config: &Config,
    start: Start,
    t_end: f64,
) -> Option<Classification> {
    let pose = |f: &RecordedFrame| support_pose(recording, f);
    let t_from = match start {
        Start::Held(reference) => reference.t,
        Start::Frames { t_from, .. } => t_from,
    };
    let frames: Vec<&RecordedFrame> = recording
        .object
        .iter()
        .filter(|f| f.t >= t_from && f.t < t_end)
        .collect();
    if frames.len() < 2 * MIN_EDGE_FRAMES as usize {
        return None;
    }
    let dt = (frames.last()?.t - frames[0].t) / (frames.len() - 1) as f64;
    if dt <= 0.0 {
        return None;
    }
    let (mut object, mut index, skip) = match start {
        Start::Held(reference) => {
            let g0 = pose(reference)?;
            let held = (HELD_REST * config.robust.min_rest_s.max(config.robust.rest_window_s) / dt)
                .ceil() as usize;
            let object: Vec<StampedPose> = (0..held)
                .map(|i| StampedPose::new(reference.t - (held - i) as f64 * dt, g0))
                .collect();
            (object, vec![None; held], held + 1)
        }
        Start::Frames { skip, .. } => (Vec::new(), Vec::new(), skip),
    };
    for f in frames {
        if let Some(p) = pose(f) {
            object.push(StampedPose::new(f.t, p));
            index.push(Some((f.index, f.t)));
        }
    }
    let demo = Demonstration {
        name: c.name.clone(),
        object,
        palm: None,
    };
    // The held rest is one frame's pose, with that frame's noise.
    let mut config = *config;
    if let Start::Held(_) = start {
        config.robust.held_rest_frames = Some(1.0);
    }
    let mut sub = classify(&demo, &config).ok()?;
    // Back to the first pass's frame indices, without the held rest and the reference (they
    // keep the first pass's labels).
    sub.labels.retain_mut(|r| {
        if r.last < skip {
            return false;
        }
        let from = r.first.max(skip);
        let (Some(Some((a, ta))), Some(Some((b, tb)))) =
            (index.get(from), index.get(r.last.min(index.len() - 1)))
        else {
            return false;
        };
        r.frames -= (from - r.first) as u64;
        (r.first, r.last, r.t_start, r.t_end) = (*a as usize, *b as usize, *ta, *tb);
        true
    });
    Some(sub)
}

/// For an instrumented demonstration: the config with the noise in force (estimated or given)
/// and that noise; `None` without a palm or a noise model.
pub(super) fn instrumented_config(
    c: &Classification,
    recording: &Recording,
    config: &Config,
) -> Option<(Config, crate::noise::NoiseModel)> {
    let mut config = *config;
    config.robust.noise = c.noise.or(config.robust.noise);
    let noise = config.robust.noise?;
    (!recording.palm.is_empty()).then_some((config, noise))
}

/// The kept frames (outliers aside) of segment `k` and of the rests around it: from the end of
/// segment `k - 1` to the start of segment `k + 1`.
pub(super) fn frames_around<'r>(
    c: &Classification,
    recording: &'r Recording,
    k: usize,
) -> Vec<&'r RecordedFrame> {
    let t_prev = k
        .checked_sub(1)
        .map_or(f64::NEG_INFINITY, |j| c.segments[j].t_end);
    let t_end = c.segments.get(k + 1).map_or(f64::INFINITY, |n| n.t_start);
    recording
        .object
        .iter()
        .filter(|f| f.t > t_prev && f.t < t_end && !super::adopt::is_outlier(c, f))
        .collect()
}

/// A kept frame's pose in the support's frame: in the world, or, instrumented, in a world
/// where the palm stays at its first pose (`P₀ · palm⁻¹ · object`); `None` outside the palm's
/// poses.
pub(super) fn support_pose(recording: &Recording, f: &RecordedFrame) -> Option<Isometry3<f64>> {
    let object = Isometry3::from_parts(Translation3::from(f.position), f.rotation);
    if recording.palm.is_empty() {
        return Some(object);
    }
    let p0 = recording.palm.first()?.pose;
    Some(p0 * pose_at(&recording.palm, f.t)?.inverse() * object)
}

/// A frame standing for the mean pose of `frames` (in the support's frame: their positions'
/// mean, their orientations' normalised quaternion sum), at the last one's time and index: a
/// reference with the noise of their mean, not of one frame.
pub(super) fn mean_frame(
    recording: &Recording,
    frames: &[&RecordedFrame],
) -> Option<RecordedFrame> {
    let last = frames.last()?;
    let poses: Vec<Isometry3<f64>> = frames
        .iter()
        .filter_map(|f| support_pose(recording, f))
        .collect();
    let first = poses.first()?;
    let n = poses.len() as f64;
    let position = poses
        .iter()
        .map(|p| p.translation.vector)
        .sum::<nalgebra::Vector3<f64>>()
        / n;
    let q0 = first.rotation.coords;
    let sum: nalgebra::Vector4<f64> = poses
        .iter()
        .map(|p| {
            let q = p.rotation.coords;
            if q.dot(&q0) < 0.0 {
                -q
            } else {
                q
            }
        })
        .sum();
    let rotation = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::from(sum));
    let mean = Isometry3::from_parts(Translation3::from(position), rotation);
    // Back to the frame's own world: `support_pose` is `S(t) · object`.
    let support = support_pose(recording, last)?
        * Isometry3::from_parts(Translation3::from(last.position), last.rotation).inverse();
    let object = support.inverse() * mean;
    Some(RecordedFrame {
        index: last.index,
        t: last.t,
        rotation: object.rotation,
        position: object.translation.vector,
    })
}

/// The time of the kept frame in `[reference, t_end)` turned farthest from the reference.
pub(super) fn largest_turn(
    recording: &Recording,
    reference: &RecordedFrame,
    t_end: f64,
) -> Option<f64> {
    let (q0, palm0) = (reference.rotation, palm_rotation(recording, reference.t));
    recording
        .object
        .iter()
        .filter(|f| f.t > reference.t && f.t < t_end)
        .map(|f| {
            // Relative to the palm when there is one.
            let rel = match (palm0, palm_rotation(recording, f.t)) {
                (Some(p0), Some(p)) => (p0.inverse() * q0).inverse() * (p.inverse() * f.rotation),
                _ => q0.inverse() * f.rotation,
            };
            (rel.angle(), f.t)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, t)| t)
}

fn palm_rotation(recording: &Recording, t: f64) -> Option<nalgebra::UnitQuaternion<f64>> {
    if recording.palm.is_empty() {
        return None;
    }
    pose_at(&recording.palm, t).map(|p| p.rotation)
}

/// `world_from_palm` at time `t`, interpolated between the kept palm poses.
fn pose_at(palm: &[StampedPose], t: f64) -> Option<Isometry3<f64>> {
    let i = palm.partition_point(|p| p.t < t);
    if i < palm.len() && (palm[i].t - t).abs() < 1e-9 {
        return Some(palm[i].pose);
    }
    if i == 0 || i >= palm.len() {
        return None;
    }
    let (a, b) = (&palm[i - 1], &palm[i]);
    let s = (t - a.t) / (b.t - a.t);
    Some(Isometry3::from_parts(
        Translation3::from(
            a.pose
                .translation
                .vector
                .lerp(&b.pose.translation.vector, s),
        ),
        a.pose.rotation.slerp(&b.pose.rotation, s),
    ))
}
