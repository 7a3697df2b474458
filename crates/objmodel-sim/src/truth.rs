//! Ground truth of a simulated demonstration, as written to `NAME.truth.json`.
//!
//! Every geometric quantity is expressed in the TAG frame — the only frame the learner sees —
//! unless its name says otherwise (`box_*`). Normals are outward unit vectors. Angles are in
//! radians, with `_deg` copies for people.

use crate::noise::TrackerNoise;
use nalgebra::{Isometry3, Point3, Vector3};
use serde::{Deserialize, Serialize};

/// A pose as JSON: translation \[m\] and unit quaternion `[x, y, z, w]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PoseJson {
    /// Translation \[m\].
    pub translation: [f64; 3],
    /// Rotation as a unit quaternion `[x, y, z, w]`.
    pub quaternion: [f64; 4],
}

impl From<&Isometry3<f64>> for PoseJson {
    fn from(p: &Isometry3<f64>) -> Self {
        let q = p.rotation.quaternion();
        let t = p.translation.vector;
        PoseJson {
            translation: [t.x, t.y, t.z],
            quaternion: [q.i, q.j, q.k, q.w],
        }
    }
}

impl PoseJson {
    /// Back to a nalgebra isometry.
    pub fn to_isometry(&self) -> Isometry3<f64> {
        let [x, y, z, w] = self.quaternion;
        let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
        Isometry3::from_parts(
            nalgebra::Translation3::from(Vector3::from(self.translation)),
            q,
        )
    }
}

/// The edge a box toppled over: the line through `p0` and `p1` (its end points, the two box
/// corners), with unit `direction = (p1 − p0)/|p1 − p0|` and `point` the point of the line
/// closest to the tag origin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EdgeTruth {
    /// First end point \[m\].
    pub p0: [f64; 3],
    /// Second end point \[m\].
    pub p1: [f64; 3],
    /// Unit direction from `p0` to `p1`.
    pub direction: [f64; 3],
    /// Point of the edge line closest to the tag origin \[m\].
    pub point: [f64; 3],
}

impl EdgeTruth {
    /// The edge from two end points.
    pub fn from_points(p0: &Point3<f64>, p1: &Point3<f64>) -> EdgeTruth {
        let u = (p1 - p0).normalize();
        let closest = p0 - u * p0.coords.dot(&u);
        EdgeTruth {
            p0: arr(&p0.coords),
            p1: arr(&p1.coords),
            direction: arr(&u),
            point: arr(&closest.coords),
        }
    }
}

/// The plane a box slid on, fixed to the box: `{x : normal · x = offset}`, `normal` the outward
/// unit normal of the contact face.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FaceTruth {
    /// Outward unit normal.
    pub normal: [f64; 3],
    /// Plane offset \[m\].
    pub offset: f64,
}

/// A labelled time interval.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// "rest", "slide", "topple" or "carry".
    pub label: String,
    /// Start \[s\].
    pub t0: f64,
    /// End \[s\].
    pub t1: f64,
}

/// Everything that really happened in one demonstration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    /// "topple", "slide", "general" or "compound".
    pub kind: String,
    /// Whether the box stood on a tracked palm (an instrumented topple).
    pub instrumented: bool,
    /// Random seed of the scene (and of the noise).
    pub seed: u64,
    /// Box name.
    pub box_name: String,
    /// Full box edge lengths along the box axes \[m\].
    pub box_dims: [f64; 3],
    /// Mass \[kg\].
    pub mass: f64,
    /// Effective box–support friction coefficient in this demo.
    pub friction: f64,
    /// The tag frame in the box's geometric frame.
    pub box_from_tag: PoseJson,
    /// Centre of mass, tag frame \[m\].
    pub com: [f64; 3],
    /// Centre of mass, box frame \[m\] (offset from the geometric centre).
    pub box_com: [f64; 3],
    /// Outward normal of the face the box rests on at the start, tag frame.
    pub rest_normal_before: [f64; 3],
    /// Outward normal of the face the box rests on at the end, tag frame.
    pub rest_normal_after: [f64; 3],
    /// The edge the box toppled over (topple and compound).
    pub edge: Option<EdgeTruth>,
    /// The face the box slid on (slide and compound).
    pub face: Option<FaceTruth>,
    /// Analytic tipping angle for the resting face and the topple edge \[rad\]:
    /// `φ = atan2(d, h_c)`, `d` the distance along the face from the edge to the CoM's foot,
    /// `h_c` the CoM height above the face.
    pub phi: Option<f64>,
    /// `phi` in degrees.
    pub phi_deg: Option<f64>,
    /// When the box starts to turn about the edge, relative to its support (the palm for an
    /// instrumented demo) \[s\].
    pub topple_start: Option<f64>,
    /// Palm tilt from level at `topple_start` \[rad\] (instrumented only).
    pub palm_tilt_at_start: Option<f64>,
    /// `palm_tilt_at_start` in degrees.
    pub palm_tilt_at_start_deg: Option<f64>,
    /// When the box stops turning purely about the edge \[s\]: it lands on the adjacent face, or
    /// the edge lifts or slips more than 3 mm, whichever comes first.
    pub pivot_end: Option<f64>,
    /// Whether the box left its edge (lifted or slipped > 3 mm) before landing.
    pub left_edge: Option<bool>,
    /// Largest displacement of the edge's midpoint along the support from `topple_start` until
    /// the box had turned `phi + 10°` \[m\]: how well the pivot held.
    pub pivot_slip: Option<f64>,
    /// Labelled intervals: rest, slide, topple, carry.
    pub segments: Vec<Segment>,
    /// Duration of the demo \[s\].
    pub duration: f64,
    /// Output pose rate \[Hz\].
    pub rate_hz: f64,
    /// Physics step rate \[Hz\].
    pub physics_hz: f64,
    /// Tracking noise applied to the written poses.
    pub noise: TrackerNoise,
    /// Scripted random choices (push height \[m\], speed \[m/s\], tilt rate \[rad/s\], ...).
    pub script: std::collections::BTreeMap<String, f64>,
    /// Every face and edge of the box, tag frame, with the ids that [`Truth::modes`] use.
    #[serde(default)]
    pub features: BoxFeatures,
    /// The contact mode of every instant, as consecutive intervals that cover the whole demo
    /// (see [`crate::modes`]).
    #[serde(default)]
    pub modes: Vec<ModeTruth>,
}

/// A face of the box: its id (the [`crate::BoxFace`] name, e.g. `"neg_z"`) and its plane in
/// the tag frame, `{x : normal · x = offset}`, `normal` outward.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FaceFeature {
    /// `"pos_x"`, `"neg_x"`, `"pos_y"`, `"neg_y"`, `"pos_z"` or `"neg_z"` (box frame).
    pub id: String,
    /// Outward unit normal, tag frame.
    pub normal: [f64; 3],
    /// Plane offset \[m\].
    pub offset: f64,
}

/// An edge of the box: its id `"FACE_A/FACE_B"` (the two faces that meet there, in the order
/// of [`crate::BoxFace::ALL`]) and its line in the tag frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EdgeFeature {
    /// `"pos_x/neg_z"` and so on.
    pub id: String,
    /// The two faces that meet at the edge.
    pub faces: [String; 2],
    /// End points, unit direction and the point closest to the tag origin, tag frame.
    #[serde(flatten)]
    pub line: EdgeTruth,
}

/// The 6 faces and 12 edges of the box in the tag frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BoxFeatures {
    /// The faces.
    pub faces: Vec<FaceFeature>,
    /// The edges.
    pub edges: Vec<EdgeFeature>,
}

/// One interval of a single contact mode between the box and its support (the table, or the
/// palm of an instrumented demo).
///
/// `mode` is one of
/// * `"rest"`: a face lies on the support and the box does not move relative to it;
/// * `"slide"`: a face lies on the support and the box moves on it (planar motion, eq. 5);
/// * `"topple"`: only an edge touches the support and that edge does not slip: rotation about
///   a fixed edge (eq. 1-4);
/// * `"flight"`: nothing touches the box (free fall, whatever it spins);
/// * `"impact"`: a corner has just reached the support faster than 5 cm/s, until the touching
///   corners have stopped moving along the support's normal (or the box bounces off);
/// * `"carried"`: a hand holds the box (grasped, or before a throw's release);
/// * `"general"`: any other contact: a corner alone, or an edge that slips.
///
/// `contact` says what touches: `"face"`, `"edge"`, `"vertex"`, `"none"` or `"hand"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeTruth {
    /// The mode (see above).
    pub mode: String,
    /// What touches the support.
    pub contact: String,
    /// Start \[s\].
    pub t0: f64,
    /// End \[s\].
    pub t1: f64,
    /// The face on the support (rest, slide, and an impact or general motion on a face).
    pub face: Option<FaceFeature>,
    /// The edge on the support (topple, and an impact or general motion on an edge).
    pub edge: Option<EdgeFeature>,
    /// Angle the box turned relative to its support over the interval \[deg\].
    pub turn_deg: f64,
    /// Distance the box's centre moved relative to its support over the interval \[m\].
    pub travel: f64,
}

/// `[x, y, z]` of a vector.
pub fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}
