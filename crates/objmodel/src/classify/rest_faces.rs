//! The rests of a classification and what each teaches: the face rested on, from gravity, when
//! a contact mode shows the support; a landing, when a flight leads to it
//! ([`crate::landing`]); and, at a topple's rest, the support's height ([`crate::support`]).

use super::{analysis, Classification, Label, Part};
use crate::face::FaceObservation;
use crate::noise::NoiseModel;
use crate::rest_place::RestHeight;
use nalgebra::{UnitQuaternion, Vector3};

impl Classification {
    /// The faces the object rested on, from gravity, other than those before and after a
    /// topple (which [`FaceObservation::from_rest`] gives with their offsets): every rest of at
    /// least `MIN_FACE_FRAMES` frames (a tossed object may rest for a tenth of a second at the
    /// end of a file), when gravity is known and not in doubt ([`Self::gravity_doubted`]).
    pub fn rest_faces(&self) -> Vec<FaceObservation> {
        if self.gravity_doubted || self.withheld.is_some() {
            return Vec::new();
        }
        self.rests()
            .into_iter()
            .filter(|r| r.supported && !r.with_edge && r.frames as f64 >= analysis::MIN_FACE_FRAMES)
            .filter_map(|r| {
                let n = r.normal?;
                // Its place, for a support's height the user gives ([`crate::support`]);
                // its height's σ as a landing's ([`crate::landing::Landing::new`]). Not
                // relative to a palm: that height is not the support's.
                let place = r.place.filter(|_| !self.instrumented);
                let rest_height = place.zip(self.noise).map(|(place, noise)| RestHeight {
                    place,
                    sigma_m: noise.sigma_position / (r.frames.max(1) as f64).sqrt(),
                });
                Some(FaceObservation {
                    rest_height,
                    ..FaceObservation::from_gravity(&n, &self.name, r.frames)
                })
            })
            .collect()
    }

    /// Per rest (rest k is the one before segment k; the last, the one after the last
    /// segment): whether it taught the face rested on, from gravity ([`Self::rest_faces`]) or
    /// beside a topple's edge ([`FaceObservation::from_rest`]).
    pub fn resting_faces_taught(&self) -> Vec<bool> {
        self.resting_faces_not_taught()
            .iter()
            .map(Option::is_none)
            .collect()
    }

    /// Per rest (as [`Self::resting_faces_taught`]): why it taught no face (too short, the
    /// demonstration teaches nothing, gravity in doubt or its down unknown, no contact mode
    /// shows it on the support, or a landing, which teaches once another demonstration's
    /// agrees: [`Self::landings`]); `None` where it taught one.
    pub fn resting_faces_not_taught(&self) -> Vec<Option<String>> {
        self.resting_faces_not_taught_among(&self.parts)
    }

    /// [`Self::resting_faces_not_taught`] with the demonstration's `parts` (while they are
    /// being listed).
    pub(crate) fn resting_faces_not_taught_among(&self, parts: &[Part]) -> Vec<Option<String>> {
        let after_flight = |k: usize| {
            k >= 1
                && parts
                    .iter()
                    .any(|p| p.kind == Label::Flight && p.segment == Some(k - 1))
        };
        let world = self.world_noise().is_some();
        self.rests()
            .into_iter()
            .enumerate()
            .map(|(k, r)| {
                if r.with_edge {
                    return None;
                }
                let why = if (r.frames as f64) < analysis::MIN_FACE_FRAMES {
                    format!(
                        "face not taught: {} frame{} of rest, fewer than {}",
                        r.frames,
                        if r.frames == 1 { "" } else { "s" },
                        analysis::MIN_FACE_FRAMES
                    )
                } else if self.withheld.is_some() {
                    "face not taught: the demonstration teaches nothing".into()
                } else if self.gravity_doubted {
                    "face not taught: the gravity given is in doubt".into()
                } else if r.normal.is_none() {
                    "face not taught: which way is down is not known".into()
                } else if r.supported {
                    return None;
                } else if world && after_flight(k) && r.place.is_some() {
                    "a landing: its face is taught once a landing of another demonstration \
                     agrees"
                        .into()
                } else {
                    "face not taught: no slide, topple or roll leaves it or reaches it, so it \
                     may be the object held still"
                        .into()
                };
                Some(why)
            })
            .collect()
    }

    /// The noise, when the demonstration teaches from gravity in the world: it teaches
    /// ([`Self::withheld`]), gravity is known and not in doubt, its poses are the world's (not
    /// a palm's) and its noise is known. Landings and the support's height need all of it.
    fn world_noise(&self) -> Option<NoiseModel> {
        self.noise
            .filter(|_| !self.gravity_doubted && !self.instrumented && self.withheld.is_none())
    }

    /// The rests in the world of at least `MIN_FACE_FRAMES` frames whose orientation is known
    /// (gravity given, poses not a palm's, noise known), each known to the noise's σ over the
    /// square root of its frames: what [`crate::vertical`] compares.
    pub fn world_rests(&self) -> Vec<crate::vertical::Rest> {
        let Some(noise) = self.noise.filter(|_| !self.instrumented) else {
            return Vec::new();
        };
        self.rests()
            .into_iter()
            .filter(|r| r.frames as f64 >= analysis::MIN_FACE_FRAMES)
            .filter_map(|r| {
                Some(crate::vertical::Rest {
                    rotation: r.rotation?,
                    sigma_rad: noise.sigma_rotation / (r.frames as f64).sqrt(),
                })
            })
            .collect()
    }

    /// The demonstration's landings ([`crate::landing`]): its rests of at least
    /// `MIN_FACE_FRAMES` frames that a flight leads to (in the motion segment before them) and
    /// that taught no face themselves (no contact mode showed the support, no topple's edge
    /// lies in the face), when gravity is known and not in doubt, the poses are the world's
    /// (not a palm's), the noise is known and the demonstration teaches ([`Self::withheld`]).
    /// Each teaches its face once a landing of another demonstration agrees
    /// ([`crate::tree::Tree::add`]).
    pub fn landings(&self) -> Vec<crate::landing::Landing> {
        let Some(noise) = self.world_noise() else {
            return Vec::new();
        };
        let after_flight = |k: usize| {
            k >= 1
                && self
                    .parts
                    .iter()
                    .any(|p| p.kind == Label::Flight && p.segment == Some(k - 1))
        };
        self.rests()
            .into_iter()
            .enumerate()
            .filter(|(k, r)| {
                after_flight(*k)
                    && !r.supported
                    && !r.with_edge
                    && r.frames as f64 >= analysis::MIN_FACE_FRAMES
            })
            .filter_map(|(_, r)| {
                Some(crate::landing::Landing::new(
                    &self.name, &r.normal?, r.place?, r.frames, &noise,
                ))
            })
            .collect()
    }

    /// The demonstration's measurements of the support's height ([`crate::support`]): each
    /// topple's edge at the rest it starts from (the rest's height less the edge's depth below
    /// the object frame's origin, `h − down · edge point`), and each taught roll's edge; when
    /// gravity is known and not in doubt, the poses are the world's and the demonstration
    /// teaches.
    pub fn support_observations(&self) -> Vec<crate::support::SupportObservation> {
        let Some(noise) = self.world_noise() else {
            return Vec::new();
        };
        let mut out: Vec<crate::support::SupportObservation> = self
            .topples
            .iter()
            .filter_map(|t| {
                let s = &self.segments[*t.segments.first()?];
                let (down, place) = (t.resting_normal_before?, s.resting_place_before?);
                let n = (s.resting_frames_before.max(1)) as f64;
                let depth_var = down.dot(&(t.edge.point_cov * down)).max(0.0);
                Some(crate::support::SupportObservation {
                    demo: self.name.clone(),
                    height: place.height - down.dot(&t.edge.line.point),
                    sigma_m: (noise.sigma_position.powi(2) / n + depth_var).sqrt(),
                    across: place.across,
                    from: "topple".to_string(),
                })
            })
            .collect();
        out.extend(self.rolls.iter().filter_map(|r| r.support.clone()));
        out
    }

    /// The rests of the demonstration, in order (see [`Self::resting_faces_taught`]).
    fn rests(&self) -> Vec<RestSummary> {
        // Rest k is the one before segment k; the rest after segment i is rest i + 1 (the one
        // before segment i + 1 when a rest split them).
        type Rest = (
            Option<Vector3<f64>>,
            u64,
            Option<crate::landing::RestPlace>,
            Option<UnitQuaternion<f64>>,
        );
        let mut rests: Vec<Rest> = Vec::new();
        if let Some(s) = self.segments.first() {
            rests.push((
                s.resting_normal_before,
                s.resting_frames_before,
                s.resting_place_before,
                s.resting_rotation_before,
            ));
        }
        rests.extend(self.segments.iter().map(|s| {
            (
                s.resting_normal_after,
                s.resting_frames_after,
                s.resting_place_after,
                s.resting_rotation_after,
            )
        }));
        // Rest k is on the support when segment k departs from it in a contact mode, or
        // segment k - 1 arrives at it in one: a rest alone could be an object held still.
        let n = self.segments.len();
        let mut with_edge = vec![false; rests.len()];
        for t in &self.topples {
            if let (Some(&a), Some(&b)) = (t.segments.first(), t.segments.last()) {
                with_edge[a] |= t.resting_normal_before.is_some();
                with_edge[b + 1] |= t.resting_normal_after.is_some();
            }
        }
        rests
            .into_iter()
            .enumerate()
            .map(|(k, (normal, frames, place, rotation))| RestSummary {
                normal,
                frames,
                place,
                rotation,
                supported: (k < n && self.segments[k].departs_from_support)
                    || (k >= 1 && self.segments[k - 1].arrives_on_support),
                with_edge: with_edge[k],
            })
            .collect()
    }
}

/// One rest of a demonstration, as [`Classification::rests`] sees it.
struct RestSummary {
    normal: Option<Vector3<f64>>,
    frames: u64,
    place: Option<crate::landing::RestPlace>,
    /// The orientation over it (`world_from_object`), when its down is known.
    rotation: Option<UnitQuaternion<f64>>,
    /// On the support: a contact mode leaves it or reaches it.
    supported: bool,
    /// A topple's edge gives its face.
    with_edge: bool,
}
