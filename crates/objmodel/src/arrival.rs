//! Whether a rest was on the support, from the motion that reached it.
//!
//! A rest, with gravity known, gives the face the object rests on (its outward normal is
//! "down" in the object frame) — if the object rests on its support. An object held still in
//! a hand or a gripper is at rest too, on nothing. Kinematics alone tell the two apart only
//! through the motion next to the rest: a contact mode measured *from* the rest (a slide on
//! the rested face, a rotation about an edge in it) shows that the face was on the support.
//! The classification finds the motion that leaves a rest (its segment is measured from it);
//! the motion that reaches a rest is measured from the rest before it, which says nothing of
//! this one. Here it is measured from this rest, by running the classifier over the kept frames
//! ([`Recording`]) of the segment and the rest *backwards in time*: a slide or an edge rotation
//! is one in either direction, and reversed, the rest comes first and becomes the reference.
//! A tossed object that slides or rolls over an edge into its final rest thus teaches the face
//! it came to rest on; one put down by a hand (a vertical descent) or held still does not.

use crate::classify::{classify, Classification, Config};
use crate::recording::Recording;
use crate::trajectory::{Demonstration, StampedPose};
use nalgebra::{Isometry3, Translation3};

/// Test the rests that no contact mode of the classification reaches (and that a face could
/// come from: gravity known, at least `MIN_FACE_FRAMES` frames) against the motion that
/// reached them, and mark the segment before each rest that passes
/// (`Segment::arrives_on_support`). Direct demonstrations only: relative to a palm, the
/// support moves with the palm and the palm's own motion is in the poses.
pub fn confirm_arrivals(c: &mut Classification, recording: &Recording, config: &Config) {
    if c.instrumented || c.gravity_doubted || config.gravity.is_none() {
        return;
    }
    let mut reversed_config = *config;
    reversed_config.robust.noise = c.noise.or(config.robust.noise);
    for k in 0..c.segments.len() {
        let s = &c.segments[k];
        if s.arrives_on_support
            || s.resting_normal_after.is_none()
            || (s.resting_frames_after as f64) < crate::classify::MIN_FACE_FRAMES
        {
            continue;
        }
        let (t0, t1) = (
            s.t_start,
            c.segments.get(k + 1).map_or(f64::INFINITY, |n| n.t_start),
        );
        let Some(last) = recording
            .object
            .iter()
            .rev()
            .find(|f| f.t < t1)
            .map(|f| f.t)
        else {
            continue;
        };
        let object: Vec<StampedPose> = recording
            .object
            .iter()
            .rev()
            .filter(|f| f.t >= t0 && f.t < t1)
            .map(|f| {
                StampedPose::new(
                    last - f.t,
                    Isometry3::from_parts(Translation3::from(f.position), f.rotation),
                )
            })
            .collect();
        let demo = Demonstration {
            name: c.name.clone(),
            object,
            palm: None,
        };
        let Ok(back) = classify(&demo, &reversed_config) else {
            continue;
        };
        if back
            .segments
            .first()
            .is_some_and(|b| b.departs_from_support)
        {
            c.segments[k].arrives_on_support = true;
        }
    }
}
