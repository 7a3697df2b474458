//! Ground-truth events found on the full-rate record of a scene: resting faces, the topple
//! edge and its onset, when the box leaves its edge, and labelled segments.

use crate::scenes::{Sample, SceneOutput};
use crate::spec::{BoxFace, BoxSpec};
use crate::truth::{arr, EdgeTruth, FaceTruth, Segment};
use crate::{Result, SimError};
use nalgebra::{Isometry3, Point3, Vector3};

/// Tilt above which a box is certainly toppling \[rad\] (2°).
const TOPPLE_SURE: f64 = 0.0349;
/// Tilt growth over its baseline that marks the topple's start \[rad\] (0.011°).
const ONSET_TOL: f64 = 2e-4;
/// The baseline is the tilt this long before the topple is certain \[s\]: late enough to include
/// the slow contact-compliance creep as the load shifts to the edge, early enough to precede
/// the onset for tilt rates down to 1°/s.
const BASELINE_LEAD: f64 = 1.5;
/// Edge lift or slip at which the box is said to have left its edge \[m\].
const LEAVE_DIST: f64 = 0.003;

/// `support_from_box` of a sample.
pub fn support_from_box(s: &Sample) -> Isometry3<f64> {
    s.world_from_support.inverse() * s.world_from_box
}

/// The face the box rests on in sample `s`: the one whose outward normal points most nearly
/// along the support's `-z`.
pub fn rest_face(s: &Sample) -> BoxFace {
    let down_in_box = support_from_box(s).rotation.inverse() * -Vector3::z();
    BoxFace::closest_to(&down_in_box)
}

/// Angle between the outward normal `n_box` (box frame) and the support's `-z` in each sample.
pub fn tilt_series(samples: &[Sample], n_box: &Vector3<f64>) -> Vec<f64> {
    samples
        .iter()
        .map(|s| (support_from_box(s).rotation * n_box).angle(&-Vector3::z()))
        .collect()
}

/// Whether the box moves relative to its support at each sample: over a ±5-step window its
/// speed exceeds 2 mm/s or its turn rate 0.02 rad/s.
pub fn moving_series(samples: &[Sample]) -> Vec<bool> {
    let n = samples.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(5), (i + 5).min(n - 1));
            if a == b {
                return false;
            }
            let (pa, pb) = (support_from_box(&samples[a]), support_from_box(&samples[b]));
            let dt = samples[b].t - samples[a].t;
            let v = (pb.translation.vector - pa.translation.vector).norm() / dt;
            let w = pa.rotation.angle_to(&pb.rotation) / dt;
            v > 2e-3 || w > 0.02
        })
        .collect()
}

/// The edge shared by two adjacent faces, box frame: end points ordered along `+e_m`, `m` the
/// third axis.
pub fn shared_edge(spec: &BoxSpec, f0: BoxFace, f1: BoxFace) -> Option<(Point3<f64>, Point3<f64>)> {
    let ((k0, s0), (k1, s1)) = (f0.axis_sign(), f1.axis_sign());
    if k0 == k1 {
        return None;
    }
    let m = 3 - k0 - k1;
    let h = spec.half_extents();
    let mut p = Vector3::zeros();
    p[k0] = s0 * h[k0];
    p[k1] = s1 * h[k1];
    let (mut a, mut b) = (p, p);
    a[m] = -h[m];
    b[m] = h[m];
    Some((Point3::from(a), Point3::from(b)))
}

/// Analytic tipping angle for a box resting on face `f0` and tipping over its edge with `f1`:
/// `φ = atan2(d, h_c)`, `h_c = h_{k0} − s0 c_{k0}` the CoM height above `f0`,
/// `d = h_{k1} − s1 c_{k1}` the distance along `f0` from the edge to the CoM's foot.
pub fn tipping_angle(spec: &BoxSpec, f0: BoxFace, f1: BoxFace) -> f64 {
    let ((k0, s0), (k1, s1)) = (f0.axis_sign(), f1.axis_sign());
    let h = spec.half_extents();
    let c = spec.com_box();
    (h[k1] - s1 * c[k1]).atan2(h[k0] - s0 * c[k0])
}

/// The plane of face `f` in the tag frame.
pub fn face_in_tag(spec: &BoxSpec, f: BoxFace) -> FaceTruth {
    let tag_from_box = spec.tag_from_box();
    let (k, s) = f.axis_sign();
    let mut centre = Vector3::zeros();
    centre[k] = s * spec.half_extents()[k];
    let n = tag_from_box.rotation * f.normal();
    let c = tag_from_box * Point3::from(centre);
    FaceTruth {
        normal: arr(&n),
        offset: n.dot(&c.coords),
    }
}

/// What a topple did.
#[derive(Debug, Clone)]
pub struct ToppleEvents {
    /// Edge in the tag frame.
    pub edge: EdgeTruth,
    /// Tipping angle \[rad\].
    pub phi: f64,
    /// Index and time of onset.
    pub onset: (usize, f64),
    /// Support tilt from level at onset \[rad\].
    pub support_tilt: f64,
    /// Time the pure rotation about the edge ended, and whether the box left its edge first.
    pub pivot_end: Option<(f64, bool)>,
    /// Largest edge-midpoint slip before the box turned `φ + 10°` \[m\].
    pub pivot_slip: f64,
}

/// Find the topple that starts after time `t_ref` in `out`, from face `f0` to face `f1`.
///
/// Its onset is the last instant before the tilt exceeds its baseline by 2° at which it was
/// still within 2·10⁻⁴ rad of the baseline, the tilt 1.5 s before that 2° crossing.
pub fn topple_events(
    spec: &BoxSpec,
    out: &SceneOutput,
    t_ref: f64,
    f0: BoxFace,
    f1: BoxFace,
) -> Result<ToppleEvents> {
    let s = &out.samples;
    let (a, b) = shared_edge(spec, f0, f1).ok_or_else(|| {
        SimError::Scene(format!(
            "the box went from face {f0:?} to {f1:?}, which share no edge"
        ))
    })?;
    let tilt = tilt_series(s, &f0.normal());
    let i_ref = s.iter().position(|x| x.t >= t_ref).unwrap_or(0);
    let base = tilt[i_ref];
    let sure = (i_ref..s.len())
        .find(|&i| tilt[i] > base + TOPPLE_SURE)
        .ok_or_else(|| SimError::Scene("the box never tipped".into()))?;
    let t_base = s[sure].t - BASELINE_LEAD;
    let i_base = (i_ref..sure).find(|&i| s[i].t >= t_base).unwrap_or(i_ref);
    let base = tilt[i_base];
    let onset = (i_base..sure)
        .rev()
        .find(|&i| tilt[i] <= base + ONSET_TOL)
        .unwrap_or(i_base);
    let phi = tipping_angle(spec, f0, f1);
    let support_tilt = (s[onset].world_from_support.rotation * Vector3::z()).angle(&Vector3::z());

    let mid = Point3::from((a.coords + b.coords) * 0.5);
    let at = |i: usize, p: &Point3<f64>| support_from_box(&s[i]) * p;
    let m0 = at(onset, &mid);
    let down = -Vector3::z();
    let mut pivot_end = None;
    let mut pivot_slip: f64 = 0.0;
    for i in onset..s.len() {
        let (pa, pb, pm) = (at(i, &a), at(i, &b), at(i, &mid));
        let slip = (pm - m0).xy().norm();
        if tilt[i] < phi + 10f64.to_radians() {
            pivot_slip = pivot_slip.max(slip);
        }
        if pa.z.max(pb.z) > LEAVE_DIST || slip > LEAVE_DIST {
            pivot_end = Some((s[i].t, true));
            break;
        }
        let n1 = support_from_box(&s[i]).rotation * f1.normal();
        if n1.angle(&down) < 1f64.to_radians() {
            pivot_end = Some((s[i].t, false));
            break;
        }
    }
    let tag_from_box = spec.tag_from_box();
    let edge = EdgeTruth::from_points(&(tag_from_box * a), &(tag_from_box * b));
    Ok(ToppleEvents {
        edge,
        phi,
        onset: (onset, s[onset].t),
        support_tilt,
        pivot_end,
        pivot_slip,
    })
}

/// Labelled segments. `topple_onset` splits off a topple; `second_phase` (compound) ends the
/// slide; `carry` marks a grasp.
pub fn segments(out: &SceneOutput, kind: &str, topple_onset: Option<f64>) -> Vec<Segment> {
    let s = &out.samples;
    let moving = moving_series(s);
    let t_end = s.last().map(|x| x.t).unwrap_or(0.0);
    let t_motion = out.script.motion_start;
    let first = (0..s.len())
        .find(|&i| moving[i] && s[i].t >= t_motion)
        .map(|i| s[i].t);
    let last = (0..s.len()).rev().find(|&i| moving[i]).map(|i| s[i].t);
    let mut segs = Vec::new();
    let mut push = |label: &str, t0: f64, t1: f64| {
        if t1 > t0 {
            segs.push(Segment {
                label: label.into(),
                t0,
                t1,
            });
        }
    };
    let (Some(first), Some(last)) = (first, last) else {
        push("rest", 0.0, t_end);
        return segs;
    };
    match kind {
        "general" => {
            let (g, _) = out.script.carry.unwrap_or((first, last));
            push("rest", 0.0, g);
            push("carry", g, last);
        }
        "slide" => {
            push("rest", 0.0, first);
            push("slide", first, last);
        }
        "compound" => {
            let onset = topple_onset.unwrap_or(last);
            let t2 = out.script.second_phase.unwrap_or(onset);
            let slide_end = (0..s.len())
                .rev()
                .find(|&i| moving[i] && s[i].t < t2)
                .map(|i| s[i].t)
                .unwrap_or(first);
            push("rest", 0.0, first);
            push("slide", first, slide_end);
            push("rest", slide_end, onset);
            push("topple", onset, last);
        }
        _ => {
            let onset = topple_onset.unwrap_or(first);
            push("rest", 0.0, onset);
            push("topple", onset, last);
        }
    }
    push("rest", last, t_end);
    segs
}
