//! What one demonstration shows: its classification (segments, edges, faces) and the dynamics
//! of its topples. The learning pipeline ([`crate::learn`]) produces it; the tree
//! ([`crate::tree::Tree::add`]) takes it whole.

use crate::classify::Classification;
use crate::dynamics::ToppleDynamics;
use serde::Serialize;

/// One demonstration, analysed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Observation {
    /// Algorithm 1 and 2 on the demonstration: its kind, segments, edges and faces, and the
    /// warnings about its input.
    pub classification: Classification,
    /// The dynamics of each topple of [`Observation::classification`] that could be analysed
    /// (empty when gravity is unknown).
    pub dynamics: Vec<ToppleDynamics>,
    /// What identifies the demonstration's poses whatever its name: a 64-bit FNV-1a hash, in
    /// hex, of its frame count and the bits of every frame the pipeline kept (time,
    /// orientation and position; every frame up to [`crate::recording::DEFAULT_CAPACITY`] per
    /// stream, an even subset beyond: see [`crate::recording::Recording::fingerprint`]).
    /// `None` if unknown.
    pub fingerprint: Option<String>,
    /// The fingerprint as trees written before 2026-12-08 hold it, without the object's
    /// positions ([`crate::recording::Recording::fingerprint_without_positions`]): a stored
    /// demonstration that has it is these poses too.
    #[serde(skip)]
    pub fingerprint_without_positions: Option<String>,
    /// The friction a slide on the tilting palm showed (instrumented demonstrations whose
    /// object slid instead of toppling; [`crate::dynamics::palm_slide`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub palm_slide: Option<crate::dynamics::PalmSlide>,
    /// Why the demonstration was not added to the model although it shows motion: the
    /// demonstrations learnt with it contradict the gravity given
    /// ([`crate::learn::Learner::learn`]). `None` when it was added, or teaches nothing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_learnt: Option<String>,
    /// The windows of its frames that measure the tracker's noise, where it is direct, every
    /// frame was kept and the noise was not given: what it lends to a demonstration learnt
    /// with it that cannot measure its own ([`crate::shared_noise`]). Not serialised.
    #[serde(skip)]
    pub noise_windows: Option<crate::noise_correlation::NoiseWindows>,
}

impl Observation {
    /// Whether the demonstration shows no motion at all (a single pose, or an object that
    /// never moves): it teaches nothing, and [`crate::learn::Learner::learn`] leaves the tree
    /// as it was.
    pub fn teaches_nothing(&self) -> bool {
        self.classification.segments.is_empty()
    }

    /// Whether [`crate::learn::Learner::learn`] added the demonstration to the model: it
    /// shows motion ([`Self::teaches_nothing`]) and was not kept out ([`Self::not_learnt`]).
    pub fn learnt(&self) -> bool {
        !self.teaches_nothing() && self.not_learnt.is_none()
    }

    /// A demonstration's geometry alone, without dynamics.
    pub fn geometry(classification: Classification) -> Self {
        Self {
            classification,
            dynamics: Vec::new(),
            fingerprint: None,
            fingerprint_without_positions: None,
            palm_slide: None,
            not_learnt: None,
            noise_windows: None,
        }
    }
}
