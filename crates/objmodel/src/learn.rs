//! The learning pipeline: the one entry point that the command line, the simulator's task loop
//! and evaluation, and the tests call, so that the same demonstrations give the same model
//! wherever they come from.
//!
//! ```text
//! source ─▶ classify (Algorithm 1, 2: segments, edges, faces) ─┐
//!        └▶ recorder (the frames, bounded) ────────────────────┴▶ arrivals ─▶ dynamics ─▶ Observation ─▶ Tree::add
//! ```
//!
//! One pass over each file: while the stream is classified, a [`Recorder`] keeps its frames
//! (all of them up to its capacity, evenly thinned beyond: see [`crate::recording`]); once the
//! classification is known, the rests that a motion reached are tested against that motion
//! measured back from them (were they on the support? [`crate::arrival`]), the dynamics of
//! each topple are fitted to the kept frames
//! ([`crate::dynamics::analyse`]), and the demonstration's geometry and pendulums enter the
//! tree together ([`Tree::add`]), under the identity of its poses (the kept frames'
//! fingerprint, not its name). Gravity comes from the [`Config`]: without it the topples'
//! dynamics cannot be measured (their angles are from the vertical), which the report says.
//! A demonstration without motion teaches nothing and is not added.
//!
//! ```no_run
//! use objmodel::learn::{Config, Learner, Source};
//! use objmodel::tree::Tree;
//! # fn main() -> objmodel::Result<()> {
//! let learner = Learner::new(Config::default());
//! let mut tree = Tree::default();
//! let reports = learner.learn(
//!     &mut tree,
//!     &[Source::file("demo1.tum"), Source::instrumented("demo2.tum", "demo2.palm.tum")],
//! )?;
//! for r in &reports {
//!     println!("{}: {}", r.classification.name, r.classification.kind.as_str());
//! }
//! # Ok(())
//! # }
//! ```

pub use crate::classify::Config;
use crate::classify::{classify, Classification};
use crate::observation::Observation;
use crate::recording::{Recorder, Recording, DEFAULT_CAPACITY};
use crate::trajectory::Demonstration;
use crate::tree::Tree;
use crate::Result;
use std::path::Path;

/// Where a demonstration comes from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// Pose files (TUM or CSV) of the object and, for an instrumented demonstration, of the
    /// palm; read once, streaming. The demonstration is named after the object file.
    Files {
        /// The object's poses, `world_from_object`.
        object: &'a Path,
        /// The palm's poses, `world_from_palm`.
        palm: Option<&'a Path>,
    },
    /// Poses held in memory.
    Memory(&'a Demonstration),
}

impl<'a> Source<'a> {
    /// A direct demonstration's file.
    pub fn file(object: &'a (impl AsRef<Path> + ?Sized)) -> Self {
        Source::Files {
            object: object.as_ref(),
            palm: None,
        }
    }

    /// An instrumented demonstration's files.
    pub fn instrumented(
        object: &'a (impl AsRef<Path> + ?Sized),
        palm: &'a (impl AsRef<Path> + ?Sized),
    ) -> Self {
        Source::Files {
            object: object.as_ref(),
            palm: Some(palm.as_ref()),
        }
    }
}

/// The learning pipeline, configured once.
#[derive(Clone, Debug)]
pub struct Learner {
    config: Config,
    capacity: usize,
}

impl Learner {
    /// A learner with this configuration (method, thresholds, gravity).
    pub fn new(config: Config) -> Self {
        Self {
            config,
            capacity: DEFAULT_CAPACITY,
        }
    }

    /// Keep at most `frames` frames per stream for the dynamics (default
    /// [`DEFAULT_CAPACITY`]); longer demonstrations are analysed at a lower rate.
    pub fn with_capacity(mut self, frames: usize) -> Self {
        self.capacity = frames;
        self
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Classify a demonstration (Algorithms 1 and 2, and which rests were on the support),
    /// without its dynamics.
    pub fn classify(&self, source: &Source) -> Result<Classification> {
        Ok(self.classify_recorded(source)?.0)
    }

    /// The classification, with the rests the motion reached tested against it
    /// ([`crate::arrival`]), and the frames kept.
    fn classify_recorded(&self, source: &Source) -> Result<(Classification, Recording)> {
        let (mut classification, recording) = match *source {
            Source::Files { object, palm } => {
                let mut recorder = Recorder::new(self.capacity);
                let c = crate::classify::classify_files_recording(
                    object,
                    palm,
                    &self.config,
                    Some(&mut recorder),
                )?;
                (c, recorder.finish())
            }
            Source::Memory(demo) => (
                classify(demo, &self.config)?,
                Recording::of(demo, self.capacity),
            ),
        };
        if self.noise_unmeasurable(&recording) {
            classification.withhold_all(
                "the tracking noise cannot be estimated from this demonstration: the motion \
                 between its frames exceeds the noise (a fast motion at this frame rate); give \
                 the tracker's noise (--noise) to learn from it",
            );
        }
        crate::arrival::confirm_arrivals(&mut classification, &recording, &self.config);
        Ok((classification, recording))
    }

    /// Whether the robust method estimated the noise (none given) from frames whose motion
    /// dominates their second differences ([`crate::noise::motion_dominated`]): then the
    /// estimate is the motion's, every test passes everything, and features would be taught
    /// with confidence from anything. Tested on the frames the estimate used (the first
    /// `warmup_frames`; all of them when the record kept every frame of those).
    fn noise_unmeasurable(&self, recording: &Recording) -> bool {
        let robust = &self.config.robust;
        if self.config.method != crate::classify::Method::Robust
            || robust.noise.is_some()
            || recording.object_stride > 1
        {
            return false;
        }
        let samples: Vec<crate::noise::PoseSample> = recording
            .object
            .iter()
            .take(robust.warmup_frames.max(3))
            .map(|f| (f.t, f.rotation, f.position))
            .collect();
        crate::noise::motion_dominated(
            &samples,
            robust.alpha,
            (robust.edge_tolerance_m, robust.edge_tolerance_rad),
        )
    }

    /// Analyse a demonstration: its classification and the dynamics of its topples, in one
    /// pass over its files.
    pub fn observe(&self, source: &Source) -> Result<Observation> {
        let gravity = self.config.gravity;
        let (mut classification, recording) = self.classify_recorded(source)?;
        let fingerprint = Some(recording.fingerprint(classification.frames));
        let mut dynamics = Vec::new();
        if !classification.topples.is_empty() {
            match gravity {
                Some(g) => {
                    if recording.object_stride > 1 || recording.palm_stride > 1 {
                        classification.warnings.push(format!(
                            "the topples' dynamics were fitted to one object frame in {}{}: \
                             the demonstration is longer than the {} frames kept for them",
                            recording.object_stride,
                            if recording.palm.is_empty() {
                                String::new()
                            } else {
                                format!(" and one palm pose in {}", recording.palm_stride)
                            },
                            self.capacity
                        ));
                    }
                    dynamics = crate::dynamics::analyse(&recording, &classification, &g);
                }
                None => classification.warnings.push(
                    "gravity is unknown (--gravity none): the topples' dynamics (pendulums, \
                     centre of mass) are not analysed"
                        .to_string(),
                ),
            }
        }
        Ok(Observation {
            classification,
            dynamics,
            fingerprint,
        })
    }

    /// Learn from demonstrations: analyse each and fuse it into `tree`, in order. Returns each
    /// demonstration's report. A demonstration that shows no motion teaches nothing
    /// ([`Observation::teaches_nothing`]): it is not added, and its report says so. On an
    /// error, the demonstrations before the one that failed are in the tree.
    pub fn learn(&self, tree: &mut Tree, sources: &[Source]) -> Result<Vec<Observation>> {
        sources
            .iter()
            .map(|s| {
                let mut o = self.observe(s)?;
                if o.teaches_nothing() {
                    let why = nothing_to_learn(&o.classification);
                    o.classification
                        .warnings
                        .push(format!("{why}; not added to the model"));
                } else {
                    let added = tree.add(&o);
                    o.classification
                        .warnings
                        .extend(added.note(&o.classification.name));
                }
                Ok(o)
            })
            .collect()
    }
}

/// What a demonstration without motion is told.
pub fn nothing_to_learn(c: &Classification) -> String {
    format!(
        "nothing to learn: no motion in its {} frame{} (a single pose, or an object at rest)",
        c.frames,
        if c.frames == 1 { "" } else { "s" }
    )
}
