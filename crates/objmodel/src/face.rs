//! Faces (eq. 5): the planes an object slid on or rested on, in the object's frame.
//!
//! A face is the plane `{x : n·x = offset}` with `n` its outward normal.
//!
//! **What a slide determines.** A slide is planar motion: every relative motion `g'(t)` rotates
//! about axes parallel to the face normal and translates normal to it. So a slide gives the
//! normal's *direction* (from the rotation axes and from the plane of the translations), but
//! not its offset: the same motion is produced by every plane parallel to the face. It gives
//! the *sign* (which side of the object the face is on) only with gravity: the face touching
//! the support has its outward normal along gravity. The offset is known when an edge is known
//! to lie in the face: a topple about an edge while resting on a face puts that edge in the
//! face, so `offset = n · edge.point`. A slide that does not turn (a straight push) gives even
//! the direction only up to a rotation about the direction of travel; with gravity known and
//! the poses in the world frame, the classifier completes it with a prior, the face slid on
//! facing down within [`SUPPORT_LEVEL_SIGMA_RAD`] (see `PlaneStats::with_normal_prior`).
//!
//! **What a topple determines.** With gravity known, the faces rested on before and after the
//! topple are the downward directions in the object frame at those rests, both containing the
//! edge: normal and offset. The normal is made exactly perpendicular to the edge.

use crate::edge::EdgeObservation;
use crate::rest_place::RestHeight;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Assumed standard deviation \[rad\] of the support's tilt from level (tables and palms at rest
/// are level to about a degree), the accuracy of a face normal taken from gravity at rest.
pub const SUPPORT_LEVEL_SIGMA_RAD: f64 = 0.017_453_292_519_943_295;

/// Where a face observation comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FaceSource {
    /// A face slide (eq. 5).
    Slide,
    /// The face an object rested on before or after a topple, or on the support (gravity).
    Rest,
    /// The face an object rested on after a flight, confirmed by another demonstration's
    /// landing in the same place (gravity; [`crate::landing`]).
    Landing,
}

/// One demonstration's estimate of one face, in the object frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceObservation {
    /// The demonstration it comes from.
    pub demo: String,
    /// Unit normal (outward when `sign_known`).
    pub normal: Vector3<f64>,
    /// Covariance of the normal \[rad²\] (normal to it).
    pub normal_cov: Matrix3<f64>,
    /// Offset \[m\], when known.
    pub offset: Option<f64>,
    /// Variance of the offset \[m²\], when known.
    pub offset_var: Option<f64>,
    /// The part of `offset_var` \[m²\] common to every observation of the face's offset
    /// through one edge: the contact's depth ([`EdgeObservation::common_point_cov`]), which
    /// does not average down when they are fused.
    #[serde(default)]
    pub offset_common_var: f64,
    /// Whether the normal's sign (outward) is known.
    pub sign_known: bool,
    /// Where it comes from.
    pub source: FaceSource,
    /// Frames behind it.
    pub frames: u64,
    /// Where a rest on the support (beside no topple) held the object, and its height's σ
    /// from the tracking noise: a height of the support the user gave makes it the face's
    /// offset ([`crate::support`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rest_height: Option<RestHeight>,
}

impl FaceObservation {
    /// The face an object rested on before or after toppling about `edge`, from the unit
    /// "down" direction in the object frame at rest. The normal is "down" itself, as in
    /// [`Self::from_gravity`]: a measurement of its own, as uncertain as the support is level.
    /// (It was "down" made normal to the edge, so that the face held its edge: an edge a few
    /// degrees off then tilted the face it rested on with it, and the tree could not use that
    /// rest to put the edge right.) The offset is the edge's: the face holds the edge, so its
    /// plane passes through the edge's point (`edge.line.point`, the line's point nearest the
    /// origin, where `n · p` is the same for the plane normal to "down" and for the one through
    /// the whole line, to second order in the angle between them).
    pub fn from_rest(down: &Vector3<f64>, edge: &EdgeObservation) -> Self {
        let n = down.normalize();
        Self {
            offset: Some(n.dot(&edge.line.point)),
            offset_var: Some(n.dot(&(edge.point_cov * n))),
            offset_common_var: n.dot(&(edge.common_point_cov * n)),
            ..Self::from_gravity(&n, &edge.demo, edge.frames)
        }
    }

    /// The face an object rested on, from the unit "down" direction in the object frame
    /// averaged over `frames` frames at rest, with no edge to give its offset. The normal is
    /// as uncertain as the support is level ([`SUPPORT_LEVEL_SIGMA_RAD`]; the rest's own
    /// noise, averaged over its frames, is far smaller).
    pub fn from_gravity(down: &Vector3<f64>, demo: &str, frames: u64) -> Self {
        let n = down.normalize();
        let p = Matrix3::identity() - n * n.transpose();
        Self {
            demo: demo.to_string(),
            normal: n,
            normal_cov: p * SUPPORT_LEVEL_SIGMA_RAD * SUPPORT_LEVEL_SIGMA_RAD,
            offset: None,
            offset_var: None,
            offset_common_var: 0.0,
            sign_known: true,
            source: FaceSource::Rest,
            frames,
            rest_height: None,
        }
    }

    /// RMS standard deviation \[rad\] of the normal, per axis.
    pub fn sigma_normal(&self) -> f64 {
        (self.normal_cov.trace() / 2.0).max(0.0).sqrt()
    }
}
