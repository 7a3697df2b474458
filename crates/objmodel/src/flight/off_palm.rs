//! An object that flies may have left the palm.
//!
//! An instrumented demonstration is measured relative to the palm: its rests are rests on the
//! palm, and "down" in them is the palm's (the direction gravity had in the palm's frame when
//! the demonstration started, the palm level). That holds while the object is on the palm. A
//! box that topples off the palm, or slides down a steep palm and drops to the table, comes to
//! rest on the table; relative to a palm that has stopped, it is at rest too, and its "rest on
//! the palm" taught a face 20-43° off any face of the box (PyBullet's palm tilts,
//! `bench/pybullet_probe.py`: 6 wrong faces in 24 boxes at motion-capture noise, 1 in 24 at
//! a camera's).
//!
//! The object's own poses are in the world, and there a free flight (its acceleration is
//! gravity's, [`crate::flight`]) says that nothing held it for a moment. That alone does not
//! say it left the palm: a tall box toppling on the palm lifts off its edge before its face
//! lands (rapier's palm topples at 120-240 Hz: flights of 0.1 s, the tag falling 9 cm) and
//! lands on the palm. Where it rests after does: on the palm, or on a table, the rest says the
//! same relative to the palm unless the palm is tilted (the palm's "down" is then not the
//! table's) and still (an object that stays at rest relative to a palm that turns moves with
//! it: it is on it). So after a flight, what is measured relative to the palm (the rest after
//! the segment the object flew in, and every later part) teaches only where, during it, the
//! palm is level ([`LEVEL_RAD`]) at some frame or turns by [`TURNED_RAD`] or more; elsewhere it
//! is withheld. The edge the object toppled about before it flew stays (its rotation was on
//! the palm); so does what was measured before the flight.

use super::{find_flights, FlightFrame, FlightTest};
use crate::classify::SUPPORT_FRAMES;
use crate::classify::{Classification, Config};
use crate::recording::Recording;
use crate::trajectory::StampedPose;
use nalgebra::Vector3;

/// Largest tilt \[rad\] of the palm from its first pose's level at which "down" relative to it
/// is the world's, to the support's level ([`crate::face::SUPPORT_LEVEL_SIGMA_RAD`], 1°),
/// three times.
pub const LEVEL_RAD: f64 = 3.0 * crate::face::SUPPORT_LEVEL_SIGMA_RAD;

/// Turn \[rad\] of the palm over a rest relative to it that shows the object moving with the
/// palm (the palm's own noise is a fraction of it).
pub const TURNED_RAD: f64 = 3.0 * crate::face::SUPPORT_LEVEL_SIGMA_RAD;

/// Withhold what instrumented demonstration `c` measured relative to the palm after its object
/// flew and where the palm does not show it was on it (see the module documentation). Needs
/// gravity and a noise model; direct demonstrations are left as they are.
pub fn withhold_after_leaving_the_palm(
    c: &mut Classification,
    recording: &Recording,
    config: &Config,
) {
    let (Some(g), Some(test)) = (config.gravity, FlightTest::of_world_poses(c, config)) else {
        return;
    };
    if !c.instrumented || recording.palm.is_empty() {
        return;
    }
    let Some(t0) = c.segments.first().map(|s| s.t_start) else {
        return;
    };
    let outlier = c.is_outlier();
    let frames: Vec<FlightFrame> = recording
        .object
        .iter()
        .filter(|f| f.t >= t0 && !outlier(f.index))
        .map(|f| f.into())
        .collect();
    let Some(t_fly) = find_flights(&frames, &test)
        .first()
        .map(|f| frames[f.first].t)
    else {
        return;
    };
    let palm = PalmLevel::new(&recording.palm, &g);
    let why = |what: &str, t: f64| {
        format!(
            "{what} not taught: the object flew freely at {t_fly:.2} s (its poses in the world \
             fall with gravity), and from {t:.2} s the palm is tilted and still, so the object \
             may rest on something else (relative to a still palm a rest on the table is a \
             rest too, and the palm's down is not the table's)"
        )
    };
    let mut changed = false;
    for k in 0..c.segments.len() {
        let next = c.segments.get(k + 1).map_or(f64::INFINITY, |n| n.t_start);
        let prev = k
            .checked_sub(1)
            .map_or(f64::NEG_INFINITY, |j| c.segments[j].t_end);
        let s = &mut c.segments[k];
        if s.t_end < t_fly {
            continue;
        }
        // A part measured after the flight: the segment after it, or its later part measured
        // from an onset after it.
        let measured_from = s
            .onset_frame
            .and_then(|i| recording.object.iter().find(|f| f.index as usize == i))
            .map_or(s.t_start, |f| f.t);
        if measured_from >= t_fly
            && (s.edge.is_some() || s.face.is_some())
            && !palm.shows_on(measured_from, s.t_end)
        {
            s.withheld = Some(why(
                if s.edge.is_some() { "edge" } else { "face" },
                measured_from,
            ));
            s.edge = None;
            s.face = None;
            s.departs_from_support = false;
            c.topples.retain(|t| !t.segments.contains(&k));
            changed = true;
        }
        if s.arrives_on_support && !palm.shows_on(s.t_end, next) {
            s.arrives_on_support = false;
            for t in c
                .topples
                .iter_mut()
                .filter(|t| t.segments.last() == Some(&k))
            {
                t.resting_normal_after = None;
            }
            changed = true;
        }
        // The rest before a segment after the flight.
        if s.t_start >= t_fly && s.departs_from_support && !palm.shows_on(prev, s.t_start) {
            s.departs_from_support = false;
            changed = true;
        }
    }
    if changed {
        if c.topples.is_empty() {
            c.paper_edge = None;
        }
        c.warnings.push(format!(
            "the object flew freely at {t_fly:.2} s (in the world) and may have left the palm: \
             what is measured relative to the palm after it, where the palm is tilted and still, \
             teaches nothing"
        ));
    }
}

/// The palm's tilt from its level, over time.
struct PalmLevel<'a> {
    palm: &'a [StampedPose],
    /// Down in the palm's frame when the demonstration started (unit).
    down: Vector3<f64>,
    /// Down in the world (unit).
    g: Vector3<f64>,
}

impl<'a> PalmLevel<'a> {
    fn new(palm: &'a [StampedPose], g: &Vector3<f64>) -> Self {
        let g = g.normalize();
        // Which way is down relative to the palm, as the classifier takes it.
        let sum: Vector3<f64> = palm
            .iter()
            .take(SUPPORT_FRAMES)
            .map(|p| p.pose.rotation.inverse() * g)
            .sum();
        Self {
            palm,
            down: sum.try_normalize(1e-12).unwrap_or(g),
            g,
        }
    }

    /// Whether the palm shows the object on it over `[t0, t1]` (the nearest pose where no pose
    /// falls in it): level at some pose, or turned by [`TURNED_RAD`] or more.
    fn shows_on(&self, t0: f64, t1: f64) -> bool {
        let mut poses: Vec<&StampedPose> = self
            .palm
            .iter()
            .filter(|p| p.t >= t0 && p.t <= t1)
            .collect();
        if poses.is_empty() {
            let k = self
                .palm
                .partition_point(|p| p.t < t0)
                .min(self.palm.len() - 1);
            poses.push(&self.palm[k]);
        }
        let tilt = |p: &StampedPose| (p.pose.rotation.inverse() * self.g).angle(&self.down);
        let first = poses[0].pose.rotation;
        poses.iter().any(|p| tilt(p) <= LEVEL_RAD)
            || poses
                .iter()
                .any(|p| p.pose.rotation.angle_to(&first) >= TURNED_RAD)
    }
}
