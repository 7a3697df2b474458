//! The contact mode of every instant of a scene, found on its full-rate (960 Hz) record: the
//! per-interval ground truth ([`ModeTruth`]) that a segmenting learner is measured against.
//!
//! At each physics sample, relative to the support (the table, or the palm):
//! * a corner of the box touches when it is within [`CONTACT_IN`] of the support's plane, and
//!   stops touching above [`CONTACT_OUT`] (hysteresis against numerical chatter);
//! * the touching corners say what is in contact: a face (3 or 4 corners of one face), an edge
//!   (its 2 corners), a vertex, or nothing;
//! * a face contact whose box tilts (turn rate about a line in the support's plane above
//!   [`TILT_W`] and above its spin about the normal, over ±5 samples) is an edge contact about
//!   the edge of that face that moves least: the start of a topple, or rocking, before a corner has risen
//!   [`CONTACT_IN`];
//! * a face contact is a rest when the box's speed along the support is below [`REST_V`] and its
//!   spin below [`REST_W`] (over ±5 samples; settling along the normal is not motion), else a
//!   slide; an edge contact is a topple while the edge's midpoint slips slower than
//!   [`EDGE_SLIP`] along the support, else general motion;
//! * an impact starts when a corner reaches the support faster than [`IMPACT_SPEED`] (within
//!   the distance it covers in 3 steps: the solver's speculative contacts act that early) and
//!   lasts until every touching corner moves slower than [`SETTLE_SPEED`] along the support's
//!   normal (at least [`MIN_STEPS`] samples, at most [`IMPACT_MAX`]), or until the box has left
//!   the support again (a bounce);
//! * while a hand holds the box (the scene's grasp intervals) the mode is `carried`.
//!
//! Runs of equal (mode, feature) become intervals; a run shorter than [`MIN_STEPS`] samples
//! (chatter at a threshold) is absorbed by the run before it; consecutive impact runs are one
//! impact, whose contact and feature are those at its end (what the box bounced off or settled
//! onto). Boundaries are therefore exact to
//! a few physics steps, apart from the time a corner takes to rise [`CONTACT_IN`] (at the start
//! of a topple, a tilt of about 0.3 mm over the box's width).

use crate::events::{shared_edge, support_from_box};
use crate::scenes::{Sample, SceneOutput};
use crate::spec::{BoxFace, BoxSpec};
use crate::truth::{arr, BoxFeatures, EdgeFeature, EdgeTruth, FaceFeature, ModeTruth};
use nalgebra::{Isometry3, Point3, Vector3};

/// A corner closer than this to the support touches it \[m\].
pub const CONTACT_IN: f64 = 3e-4;
/// A touching corner leaves the support above this height \[m\].
pub const CONTACT_OUT: f64 = 6e-4;
/// Speed at which a corner reaching the support makes an impact \[m/s\].
pub const IMPACT_SPEED: f64 = 0.05;
/// An impact ends once every touching corner moves slower than this along the normal \[m/s\].
pub const SETTLE_SPEED: f64 = 0.01;
/// Longest impact \[s\].
pub const IMPACT_MAX: f64 = 0.05;
/// A box on a face moving slower than this, and turning slower than [`REST_W`], rests \[m/s\].
pub const REST_V: f64 = 2e-3;
/// See [`REST_V`] \[rad/s\].
pub const REST_W: f64 = 0.02;
/// A box on a face tilting faster than this about a line in the support's plane turns about an
/// edge \[rad/s\].
pub const TILT_W: f64 = 0.05;
/// An edge contact whose midpoint slips faster than this is not a topple \[m/s\].
pub const EDGE_SLIP: f64 = 0.01;
/// Shortest run of samples kept as its own interval.
pub const MIN_STEPS: usize = 3;

/// The serialised name of a face (`"neg_z"`, ...).
pub fn face_name(f: BoxFace) -> &'static str {
    match f {
        BoxFace::PosX => "pos_x",
        BoxFace::NegX => "neg_x",
        BoxFace::PosY => "pos_y",
        BoxFace::NegY => "neg_y",
        BoxFace::PosZ => "pos_z",
        BoxFace::NegZ => "neg_z",
    }
}

fn face_index(f: BoxFace) -> usize {
    BoxFace::ALL.iter().position(|&g| g == f).unwrap_or(0)
}

/// The id of the edge where faces `a` and `b` meet: `"A/B"` in the order of [`BoxFace::ALL`].
pub fn edge_id(a: BoxFace, b: BoxFace) -> String {
    let (a, b) = if face_index(a) <= face_index(b) {
        (a, b)
    } else {
        (b, a)
    };
    format!("{}/{}", face_name(a), face_name(b))
}

/// Every face and edge of `spec`'s box in the tag frame.
pub fn box_features(spec: &BoxSpec) -> BoxFeatures {
    let tag_from_box = spec.tag_from_box();
    let h = spec.half_extents();
    let faces = BoxFace::ALL
        .iter()
        .map(|&f| {
            let (k, s) = f.axis_sign();
            let mut c = Vector3::zeros();
            c[k] = s * h[k];
            let n = tag_from_box.rotation * f.normal();
            FaceFeature {
                id: face_name(f).into(),
                normal: arr(&n),
                offset: n.dot(&(tag_from_box * Point3::from(c)).coords),
            }
        })
        .collect();
    let mut edges = Vec::new();
    for (i, &a) in BoxFace::ALL.iter().enumerate() {
        for &b in &BoxFace::ALL[i + 1..] {
            if let Some((p0, p1)) = shared_edge(spec, a, b) {
                edges.push(EdgeFeature {
                    id: edge_id(a, b),
                    faces: [face_name(a).into(), face_name(b).into()],
                    line: EdgeTruth::from_points(&(tag_from_box * p0), &(tag_from_box * p1)),
                });
            }
        }
    }
    BoxFeatures { faces, edges }
}

/// Corner `j` (bits: x, y, z sign) of a box of half extents `h`, box frame.
fn corner(h: &Vector3<f64>, j: usize) -> Point3<f64> {
    let s = |bit: usize| if j >> bit & 1 == 1 { 1.0 } else { -1.0 };
    Point3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z)
}

/// What touches the support in one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Contact {
    None,
    Face(BoxFace),
    Edge(BoxFace, BoxFace),
    Vertex,
}

/// The edge contact where faces `a` and `b` meet, faces in the order of [`BoxFace::ALL`].
fn edge_contact(a: BoxFace, b: BoxFace) -> Contact {
    if face_index(a) <= face_index(b) {
        Contact::Edge(a, b)
    } else {
        Contact::Edge(b, a)
    }
}

/// The contact of a set of touching corners (bit mask over the 8 corners).
fn contact_of(touch: u8) -> Contact {
    let n = touch.count_ones();
    if n == 0 {
        return Contact::None;
    }
    // A face: 3 or 4 of its corners touch.
    for f in BoxFace::ALL {
        let (k, s) = f.axis_sign();
        let on = (0..8)
            .filter(|&j| touch >> j & 1 == 1 && ((j >> k & 1 == 1) == (s > 0.0)))
            .count();
        if on >= 3 {
            return Contact::Face(f);
        }
    }
    if n == 2 {
        let js: Vec<usize> = (0..8).filter(|&j| touch >> j & 1 == 1).collect();
        let diff = js[0] ^ js[1];
        if diff.count_ones() == 1 {
            let m = diff.trailing_zeros() as usize;
            let mut faces = (0..3).filter(|&k| k != m).map(|k| {
                let s = if js[0] >> k & 1 == 1 { 1.0 } else { -1.0 };
                BoxFace::from_axis_sign(k, s)
            });
            let (a, b) = (faces.next().unwrap(), faces.next().unwrap());
            return edge_contact(a, b);
        }
    }
    Contact::Vertex
}

/// Whether a hand holds the box at time `t` (the scene's carry and grasp intervals).
fn held(out: &SceneOutput, t: f64) -> bool {
    out.script
        .carry
        .iter()
        .chain(out.script.grasps.iter())
        .any(|&(a, b)| t >= a - 1e-9 && t < b - 1e-9)
}

/// Per-sample label: (mode, contact).
fn label(s: &[Sample], h: &Vector3<f64>, out: &SceneOutput) -> Vec<(&'static str, Contact)> {
    let n = s.len();
    let dt = if n > 1 { s[1].t - s[0].t } else { 1.0 };
    let corners: Vec<Point3<f64>> = (0..8).map(|j| corner(h, j)).collect();
    let sfb: Vec<Isometry3<f64>> = s.iter().map(support_from_box).collect();
    let heights: Vec<[f64; 8]> = sfb
        .iter()
        .map(|sfb| {
            let mut z = [0.0; 8];
            for j in 0..8 {
                z[j] = (sfb * corners[j]).z;
            }
            z
        })
        .collect();
    let mut touch = vec![0u8; n];
    for (i, zs) in heights.iter().enumerate() {
        for (j, &z) in zs.iter().enumerate() {
            let was = i > 0 && touch[i - 1] >> j & 1 == 1;
            if z < CONTACT_IN || (was && z < CONTACT_OUT) {
                touch[i] |= 1 << j;
            }
        }
    }
    let zdot = |i: usize, j: usize, back: bool| {
        let a = i.saturating_sub(2);
        let b = if back { i } else { (i + 2).min(n - 1) };
        if a == b {
            0.0
        } else {
            (heights[b][j] - heights[a][j]) / ((b - a) as f64 * dt)
        }
    };
    // Motion relative to the support over ±5 samples: in-plane speed, spin about the support's
    // normal and tilt rate about a line in its plane.
    let motion = |i: usize| {
        let (a, b) = (i.saturating_sub(5), (i + 5).min(n - 1));
        if a == b {
            return (0.0, 0.0, 0.0);
        }
        let (pa, pb) = (sfb[a], sfb[b]);
        let t = s[b].t - s[a].t;
        let w = (pb.rotation * pa.rotation.inverse()).scaled_axis() / t;
        let v = (pb.translation.vector - pa.translation.vector) / t;
        (v.xy().norm(), w.z.abs(), w.xy().norm())
    };
    // A corner reaching the support: moving down faster than IMPACT_SPEED and within the
    // distance it covers in 3 steps (the solver's speculative contacts act that early).
    let near = |i: usize, j: usize| {
        let v = -zdot(i, j, true);
        v > IMPACT_SPEED && heights[i][j] < CONTACT_IN + 3.0 * v * dt
    };
    let mut labels = Vec::with_capacity(n);
    let mut impact_since: Option<usize> = None;
    for i in 0..n {
        let mut contact = contact_of(touch[i]);
        let (v_plane, spin, tilt) = motion(i);
        if let Contact::Face(f) = contact {
            // A face that tilts about a line on the support turns about the edge of that face
            // that moves least.
            if tilt > TILT_W && tilt > spin {
                let (k, _) = f.axis_sign();
                let (a, b) = (i.saturating_sub(5), (i + 5).min(n - 1));
                let (pa, pb) = (sfb[a], sfb[b]);
                let still = BoxFace::ALL
                    .into_iter()
                    .filter(|g| g.axis_sign().0 != k)
                    .map(|g| {
                        let c = edge_contact(f, g);
                        let (ea, eb) = (edge_corner(f, g, 0), edge_corner(f, g, 1));
                        let mid = Point3::from((corner(h, ea).coords + corner(h, eb).coords) * 0.5);
                        (c, (pb * mid - pa * mid).norm())
                    })
                    .min_by(|x, y| x.1.total_cmp(&y.1));
                if let Some((c, _)) = still {
                    contact = c;
                }
            }
        }
        let arrivals = i > 0 && (0..8).any(|j| near(i, j) && !near(i - 1, j));
        if let Some(i0) = impact_since {
            let touching: Vec<usize> = (0..8).filter(|&j| touch[i] >> j & 1 == 1).collect();
            let settled = !touching.is_empty()
                && touching
                    .iter()
                    .all(|&j| zdot(i, j, false).abs() < SETTLE_SPEED);
            let bounced = touching.is_empty() && (0..8).all(|j| !near(i, j));
            let done =
                (i - i0 >= MIN_STEPS && (settled || bounced)) || s[i].t - s[i0].t > IMPACT_MAX;
            if done && !arrivals {
                impact_since = None;
            }
        }
        if arrivals && impact_since.is_none() {
            impact_since = Some(i);
        }
        let mode = if held(out, s[i].t) {
            "carried"
        } else if impact_since.is_some() {
            "impact"
        } else {
            match contact {
                Contact::None => "flight",
                Contact::Face(_) => {
                    if v_plane > REST_V || spin > REST_W {
                        "slide"
                    } else {
                        "rest"
                    }
                }
                Contact::Edge(a, b) => {
                    let (p0, p1) = (
                        corner(h, edge_corner(a, b, 0)),
                        corner(h, edge_corner(a, b, 1)),
                    );
                    let mid = Point3::from((p0.coords + p1.coords) * 0.5);
                    let (ia, ib) = (i.saturating_sub(2), (i + 2).min(n - 1));
                    let slip = if ia == ib {
                        0.0
                    } else {
                        let (ma, mb) = (sfb[ia] * mid, sfb[ib] * mid);
                        (mb - ma).xy().norm() / (s[ib].t - s[ia].t)
                    };
                    if slip < EDGE_SLIP {
                        "topple"
                    } else {
                        "general"
                    }
                }
                Contact::Vertex => "general",
            }
        };
        // In the hand, what touches the table does not matter.
        let contact = if mode == "carried" {
            Contact::None
        } else {
            contact
        };
        labels.push((mode, contact));
    }
    labels
}

/// Corner index `which` (0 or 1) of the edge where faces `a` and `b` meet.
fn edge_corner(a: BoxFace, b: BoxFace, which: usize) -> usize {
    let ((ka, sa), (kb, sb)) = (a.axis_sign(), b.axis_sign());
    let m = 3 - ka - kb;
    let bit = |k: usize, s: f64| if s > 0.0 { 1 << k } else { 0 };
    bit(ka, sa) | bit(kb, sb) | (which << m)
}

/// The contact modes of a finished scene, as consecutive intervals from its first sample to its
/// last (see the module documentation).
pub fn contact_modes(spec: &BoxSpec, out: &SceneOutput) -> Vec<ModeTruth> {
    let s = &out.samples;
    if s.is_empty() {
        return Vec::new();
    }
    let h = spec.half_extents();
    let labels = label(s, &h, out);
    // Runs of equal labels: (first sample, label).
    let mut runs: Vec<(usize, (&str, Contact))> = Vec::new();
    for (i, l) in labels.iter().enumerate() {
        if runs.last().is_none_or(|r| r.1 != *l) {
            runs.push((i, *l));
        }
    }
    // Absorb short runs into the run before them (its interval then reaches the next kept
    // run), and join equal neighbours.
    let mut kept: Vec<(usize, (&str, Contact))> = Vec::new();
    for (k, r) in runs.iter().enumerate() {
        let len = runs.get(k + 1).map_or(s.len(), |x| x.0) - r.0;
        let same = kept.last().is_some_and(|x| x.1 == r.1);
        if (len < MIN_STEPS && !kept.is_empty()) || same {
            continue;
        }
        // One impact, whatever touches during it: it takes the contact at its end.
        if let Some(last) = kept
            .last_mut()
            .filter(|x| x.1 .0 == "impact" && r.1 .0 == "impact")
        {
            last.1 = r.1;
            continue;
        }
        kept.push(*r);
    }
    let runs = kept;
    let features = box_features(spec);
    let face = |f: BoxFace| {
        features
            .faces
            .iter()
            .find(|x| x.id == face_name(f))
            .cloned()
    };
    let edge = |a: BoxFace, b: BoxFace| {
        let id = edge_id(a, b);
        features.edges.iter().find(|x| x.id == id).cloned()
    };
    let last = s.len() - 1;
    runs.iter()
        .enumerate()
        .map(|(k, &(i0, (mode, contact)))| {
            let i1 = runs.get(k + 1).map_or(last, |r| r.0);
            let (a, b) = (support_from_box(&s[i0]), support_from_box(&s[i1]));
            let (contact_name, f, e) = match (mode, contact) {
                ("carried", _) => ("hand", None, None),
                (_, Contact::None) => ("none", None, None),
                (_, Contact::Face(f)) => ("face", face(f), None),
                (_, Contact::Edge(x, y)) => ("edge", None, edge(x, y)),
                (_, Contact::Vertex) => ("vertex", None, None),
            };
            ModeTruth {
                mode: mode.into(),
                contact: contact_name.into(),
                t0: s[i0].t,
                t1: s[i1].t,
                face: f,
                edge: e,
                turn_deg: a.rotation.angle_to(&b.rotation).to_degrees(),
                travel: (b.translation.vector - a.translation.vector).norm(),
            }
        })
        .collect()
}
