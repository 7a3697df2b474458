//! The angles of a topple over time, about its edge: the object's ψ_obj and, instrumented,
//! the palm's ψ_palm (see the [module documentation](super)).

use crate::geometry::angle_about;
use crate::recording::RecordedFrame;
use crate::trajectory::StampedPose;
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Angles of one topple over time, for analysis and plots.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AngleSeries {
    /// Times \[s\].
    pub t: Vec<f64>,
    /// ψ_obj \[rad\].
    pub object: Vec<f64>,
    /// ψ_palm \[rad\] (instrumented), empty otherwise.
    pub palm: Vec<f64>,
}

/// Unwrap an angle series in place (no jumps of more than π between samples).
fn unwrap(v: &mut [f64]) {
    for i in 1..v.len() {
        let d = v[i] - v[i - 1];
        v[i] -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
    }
}

/// The palm orientation at time `t` (slerp between the palm samples around it).
pub(super) fn palm_at(palm: &[StampedPose], t: f64) -> Option<UnitQuaternion<f64>> {
    let i = palm.partition_point(|p| p.t < t);
    if i < palm.len() && (palm[i].t - t).abs() < 1e-9 {
        return Some(palm[i].pose.rotation);
    }
    if i == 0 || i >= palm.len() {
        return None;
    }
    let (a, b) = (&palm[i - 1], &palm[i]);
    Some(
        a.pose
            .rotation
            .slerp(&b.pose.rotation, (t - a.t) / (b.t - a.t)),
    )
}

/// The resting face's inward normal and the edge in the palm frame, averaged over the rest
/// before the motion (one frame would put its orientation noise into every tilt angle): `n`,
/// `u` in the object frame; the frames before `first_moving - REST_MARGIN_S` that are not
/// `outlier` are the rest.
pub(super) fn palm_reference<'a>(
    palm: &'a [StampedPose],
    frames: &[RecordedFrame],
    outlier: &[bool],
    first_moving: f64,
    n: &Vector3<f64>,
    u: &Vector3<f64>,
) -> Option<(&'a [StampedPose], Vector3<f64>, Vector3<f64>)> {
    let (mut n_sum, mut u_sum) = (Vector3::zeros(), Vector3::zeros());
    let rest = frames
        .iter()
        .enumerate()
        .filter(|(i, f)| !outlier[*i] && f.t < first_moving - super::tolerances::REST_MARGIN_S);
    for (_, f) in rest.take(super::tolerances::MAX_REST_FRAMES) {
        if let Some(qp) = palm_at(palm, f.t) {
            let palm_from_object = qp.inverse() * f.rotation;
            n_sum += palm_from_object * n;
            u_sum += palm_from_object * u;
        }
    }
    if n_sum == Vector3::zeros() {
        let first = frames.iter().enumerate().find(|(i, _)| !outlier[*i])?.1;
        let qp = palm_at(palm, first.t)?;
        let palm_from_object = qp.inverse() * first.rotation;
        return Some((palm, palm_from_object * n, palm_from_object * u));
    }
    Some((palm, n_sum.normalize(), u_sum.normalize()))
}

/// The angles about the edge `u` of the face of outward normal `n` (object frame) at every
/// kept frame that is not an `outlier` (and, instrumented, where the palm has a pose), with
/// `up` against gravity; and the index in `frames` of each.
pub(super) fn angles(
    frames: &[RecordedFrame],
    outlier: &[bool],
    palm_ref: Option<&(&[StampedPose], Vector3<f64>, Vector3<f64>)>,
    u: &Vector3<f64>,
    n: &Vector3<f64>,
    up: &Vector3<f64>,
) -> (AngleSeries, Vec<usize>) {
    let mut series = AngleSeries::default();
    let mut idx = Vec::new();
    for (i, p) in frames.iter().enumerate() {
        if outlier[i] {
            continue;
        }
        let r = p.rotation;
        let obj = angle_about(&(r * u), up, &(r * -n));
        let palm = match palm_ref {
            Some((palm, n_p, u_p)) => match palm_at(palm, p.t) {
                Some(qp) => Some(angle_about(&(qp * u_p), up, &(qp * -n_p))),
                None => continue,
            },
            None => None,
        };
        series.t.push(p.t);
        series.object.push(obj);
        series.palm.extend(palm);
        idx.push(i);
    }
    unwrap(&mut series.object);
    unwrap(&mut series.palm);
    (series, idx)
}
