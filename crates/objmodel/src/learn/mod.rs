//! The learning pipeline: the one entry point that the command line, the simulator's task loop
//! and evaluation, and the tests call, so that the same demonstrations give the same model
//! wherever they come from.
//!
//! ```text
//! source ─▶ classify (Algorithm 1, 2: segments, edges, faces) ─┐
//!        └▶ recorder (the frames, bounded) ────────────────────┴▶ check ─▶ dynamics ─▶ Observation ─▶ Tree::add
//! ```
//!
//! One pass over each file: while the stream is classified, a [`Recorder`] keeps its frames
//! (all of them up to its capacity, evenly thinned beyond: see [`crate::recording`]); once the
//! classification is known, it is checked against the kept frames (was the noise measurable?
//! were the rests that a motion reached on the support? [`crate::arrival`]), the dynamics of
//! each topple are fitted to the kept frames
//! ([`crate::dynamics::analyse`]), and the demonstration's geometry and pendulums enter the
//! tree together ([`Tree::add`]), under the identity of its poses (the kept frames'
//! fingerprint, not its name). A file is read a second time only where its first frames
//! measured the motion rather than the noise and a rest measures the noise
//! (`tracker_noise::noise_check`), or where the tracker's noise is correlated from frame to frame
//! (`tracker_noise::correlated_noise`): it is classified again with that noise; and where no
//! rest measures it, learnt with others at its frame rate, it is read again with the noise that
//! their rests measure together ([`crate::shared_noise`]); and where a thrown object's own
//! flights do not determine its centre of mass, it is read again with the one that the flights
//! of all the demonstrations agree on, which tells its rolls from flights
//! ([`crate::shared_com`]). Gravity comes from the
//! [`Config`]: without it the topples'
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
//!
//! An OptiTrack Motive take holding the object and the palm as two rigid bodies is a source
//! ([`Source::Take`]), read as two files are. A ROS 2 bag is a source too ([`Source::Bag`]):
//! its object and palm streams are read into memory ([`crate::format::bag`]), and may hold
//! several demonstrations when it is split at rests ([`Learner::observe_all`],
//! [`Learner::learn`] take them all).
//!
//! The two clocks ([`Config::clocks`]): the palm's stamps are shifted by
//! [`Clocks::palm_time_offset_s`](crate::classify::Clocks) before anything else, and the stamps
//! of files and in-memory demonstrations in milliseconds, microseconds or nanoseconds are
//! converted to seconds ([`crate::format::detect_time_unit`]), with a warning.

pub use crate::classify::Config;
use crate::classify::{classify, Classification};
use crate::format::bag::{read_bag_demonstrations, BagSelection};
use crate::format::{
    conversion_warning, detect_time_unit_of, to_metres, to_seconds, LengthUnit, PoseFile, TimeUnit,
};
use crate::observation::Observation;
use crate::recording::{Recorder, Recording, DEFAULT_CAPACITY};
use crate::shared_noise::SharedNoise;
use crate::trajectory::Demonstration;
use crate::tree::Tree;
use crate::Result;
use std::borrow::Cow;
use std::path::Path;

mod com_sharing;
mod gravity_check;
mod held_poses;
mod readable;
mod tracker_noise;

pub use gravity_check::NOT_LEARNT;
pub use readable::LeftOut;
use tracker_noise::{say_correlated, with_long_run_noise, NoiseCheck};

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
    /// An OptiTrack Motive take (its CSV export) holding several rigid bodies: the object's
    /// and, for an instrumented demonstration, the palm's, each named; read once each,
    /// streaming. The demonstration is named after the file.
    Take {
        /// The export.
        path: &'a Path,
        /// The object's rigid body.
        object: &'a str,
        /// The palm's rigid body.
        palm: Option<&'a str>,
    },
    /// Poses held in memory.
    Memory(&'a Demonstration),
    /// A ROS 2 bag (an `.mcap` file or a bag folder) and what to take from it: one
    /// demonstration, or several when the selection splits it at rests.
    Bag {
        /// The bag.
        path: &'a Path,
        /// The object's and palm's topics or tf frames, the reference frame, the split.
        selection: &'a BagSelection,
    },
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

    /// The object's and the palm's pose files, for files and takes.
    fn pose_files(&self) -> Option<(PoseFile<'a>, Option<PoseFile<'a>>)> {
        match *self {
            Source::Files { object, palm } => {
                Some((PoseFile::whole(object), palm.map(PoseFile::whole)))
            }
            Source::Take { path, object, palm } => {
                let body = |b| PoseFile {
                    path,
                    rigid_body: Some(b),
                };
                Some((body(object), palm.map(body)))
            }
            Source::Memory(_) | Source::Bag { .. } => None,
        }
    }
}

/// The learning pipeline, configured once.
#[derive(Clone, Debug)]
pub struct Learner {
    config: Config,
    capacity: usize,
    /// Whether [`Learner::learn`] checks the gravity given against the demonstrations.
    gravity_checked: bool,
    /// The support's height the user gave, if any ([`Learner::with_support`]).
    support: Option<crate::support::SupportObservation>,
    /// Where the config's noise is shared by other demonstrations ([`crate::shared_noise`]):
    /// what they measured.
    shared: Option<SharedNoise>,
}

impl Learner {
    /// A learner with this configuration (method, thresholds, gravity).
    pub fn new(config: Config) -> Self {
        Self {
            config,
            capacity: DEFAULT_CAPACITY,
            gravity_checked: true,
            support: None,
            shared: None,
        }
    }

    /// Learn with the support's height known: `height` \[m\] along −gravity in the frame the
    /// poses are given in, to `sigma_m` ([`crate::support::SupportObservation::given`]). Every
    /// rest on the support then gives its face an offset, without an edge on the support. An
    /// error unless the height is finite and its σ finite and positive.
    pub fn with_support(mut self, height: f64, sigma_m: f64) -> crate::Result<Self> {
        self.support = Some(crate::support::SupportObservation::given(height, sigma_m)?);
        Ok(self)
    }

    /// Learn without checking the gravity given against the demonstrations (see
    /// [`Learner::learn`]): for a gravity known to be right that the check doubts (a support
    /// tilted by more than a few degrees, hands that lift objects at about g).
    pub fn without_gravity_check(mut self) -> Self {
        self.gravity_checked = false;
        self
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
    /// without its dynamics. A bag must hold one demonstration (see [`Learner::observe_all`]).
    pub fn classify(&self, source: &Source) -> Result<Classification> {
        match *source {
            Source::Bag { .. } => Ok(self.single(source)?.classification),
            _ => Ok(self.classify_recorded(source)?.0),
        }
    }

    /// Analyse a demonstration: its classification and the dynamics of its topples, in one
    /// pass over its files. A bag must hold one demonstration (see [`Learner::observe_all`]).
    pub fn observe(&self, source: &Source) -> Result<Observation> {
        match *source {
            Source::Bag { .. } => self.single(source),
            _ => {
                let (c, recording) = self.classify_recorded(source)?;
                Ok(self.with_dynamics(c, recording))
            }
        }
    }

    /// The classification of files or poses in memory, checked against the frames kept
    /// ([`Learner::check`]), and those frames.
    fn classify_recorded(&self, source: &Source) -> Result<(Classification, Recording)> {
        let (c, recording) = self.classify_once(source)?;
        let c = self.checked(c, &recording, |config| match *source {
            Source::Files { .. } | Source::Take { .. } => {
                let (object, palm) = source.pose_files().expect("files");
                crate::classify::classify_files_recording(object, palm, config, None)
            }
            Source::Memory(demo) => {
                let (demo, warnings) = self.prepared(demo);
                let mut c = classify(&demo, config)?;
                c.warnings.splice(0..0, warnings);
                c.length_unit = config.length_unit;
                Ok(c)
            }
            Source::Bag { .. } => unreachable!("bags are split first (observe_all)"),
        })?;
        Ok((c, recording))
    }

    /// The classification of files or poses in memory, and the frames kept, with the noise
    /// estimated from the first frames (or given).
    fn classify_once(&self, source: &Source) -> Result<(Classification, Recording)> {
        Ok(match *source {
            Source::Files { .. } | Source::Take { .. } => {
                let (object, palm) = source.pose_files().expect("files");
                let mut recorder = Recorder::new(self.capacity);
                let c = crate::classify::classify_files_recording(
                    object,
                    palm,
                    &self.config,
                    Some(&mut recorder),
                )?;
                (c, recorder.finish())
            }
            Source::Memory(demo) => {
                let (demo, warnings) = self.prepared(demo);
                let mut c = classify(&demo, &self.config)?;
                c.warnings.splice(0..0, warnings);
                c.length_unit = self.config.length_unit;
                (c, Recording::of(&demo, self.capacity))
            }
            Source::Bag { .. } => unreachable!("bags are split first (observe_all)"),
        })
    }

    /// `first`, the classification with the noise estimated from the first frames (or given),
    /// checked against the kept frames ([`Learner::check`]); or, where those frames measured
    /// the motion and a rest measures the noise ([`tracker_noise::noise_check`]), or where the noise
    /// is correlated from frame to frame ([`tracker_noise::correlated_noise`]), the classification
    /// `again` makes with the rest's noise or the long-run noise (which then replaces the
    /// rest's), checked.
    ///
    /// Before all that, where the object's tracker held its last pose
    /// ([`held_poses::check`]), the classification `again` makes with those frames left out
    /// replaces `first`.
    fn checked(
        &self,
        first: Classification,
        recording: &Recording,
        again: impl Fn(&Config) -> Result<Classification>,
    ) -> Result<Classification> {
        if let Some(held) = held_poses::check(&self.config, &first, recording) {
            let learner = Learner {
                config: held.config(&self.config),
                ..self.clone()
            };
            let first = again(&learner.config)?;
            let mut c = learner.checked_noise(first, recording, again)?;
            held.say(&mut c);
            return Ok(c);
        }
        self.checked_noise(first, recording, again)
    }

    /// [`Learner::checked`] past the held poses: the noise's checks.
    fn checked_noise(
        &self,
        first: Classification,
        recording: &Recording,
        again: impl Fn(&Config) -> Result<Classification>,
    ) -> Result<Classification> {
        let correlated = tracker_noise::correlated_noise(&self.config, recording);
        let rest = match tracker_noise::noise_check(&self.config, &first, recording) {
            NoiseCheck::OnRest(rest) => Some(rest),
            NoiseCheck::Measured => {
                let given_as = match self.shared {
                    Some(_) => "the noise that the demonstrations learnt with it measure",
                    None => "the tracking noise given",
                };
                tracker_noise::given_check(&self.config, recording, given_as)
            }
            // Correlated noise grows with the lag as a motion does: first frames whose noise
            // is correlated look like motion to `noise::motion_dominated`, and the long-run
            // noise, measured on the quiet windows of every frame, is the noise to test with.
            NoiseCheck::Unmeasurable if correlated.is_some() => None,
            NoiseCheck::Unmeasurable => {
                let mut c = first;
                self.check(&mut c, recording, true);
                return Ok(c);
            }
        };
        // The config to classify again with, and what the classification is told of it.
        type Say<'a> = Box<dyn Fn(&mut Classification) + 'a>;
        let (config, say): (Config, Say) = match (&correlated, &rest) {
            (Some(k), _) => (
                with_long_run_noise(&self.config, k),
                Box::new(move |c| say_correlated(c, k, self.config.robust.alpha)),
            ),
            (None, Some(r)) => (r.config(&self.config), Box::new(move |c| r.reclassified(c))),
            (None, None) => {
                let mut c = first;
                self.check(&mut c, recording, false);
                return Ok(c);
            }
        };
        let learner = Learner {
            config,
            ..self.clone()
        };
        let mut c = again(&learner.config)?;
        say(&mut c);
        learner.check(&mut c, recording, false);
        if let Some(why) = correlated
            .as_ref()
            .and_then(|k| tracker_noise::beyond_resolution(k, self.config.robust.alpha))
        {
            c.withhold_all(&why);
        }
        Ok(c)
    }

    /// What the kept frames say of a classification: nothing is taught when the noise could
    /// not be measured (`unmeasurable`, see [`Learner::noise_check`]), and the rests that a
    /// motion reached are tested against that motion measured back from them
    /// ([`crate::arrival`]).
    fn check(
        &self,
        classification: &mut Classification,
        recording: &Recording,
        unmeasurable: bool,
    ) {
        classification.frame_interval_s = recording.median_frame_interval();
        classification.noise_unmeasurable = unmeasurable;
        if unmeasurable {
            classification.withhold_all(
                "the tracking noise cannot be estimated from this demonstration: the motion \
                 between its frames exceeds the noise (a fast motion at this frame rate); give \
                 the tracker's noise (--noise-position, --noise-rotation) to learn from it",
            );
        } else {
            // (Withheld, no later part is measured again: it would teach an edge or a face
            // from the same unmeasured noise. On 500 simulated tosses such re-measured edges
            // were 46-59 mm off at camera noise.)
            crate::start_rest::withhold_unrested_start(
                classification,
                recording,
                self.config.robust.rest_window_s,
            );
            crate::start_rest::unlabel_moving_start(
                classification,
                recording,
                self.config.robust.rest_window_s,
                self.config.robust.alpha,
            );
            crate::onset::remeasure_later_parts(classification, recording, &self.config);
            crate::flight::withhold_topples_that_fly(classification, recording, &self.config);
            crate::flight::withhold_after_leaving_the_palm(classification, recording, &self.config);
        }
        // (A demonstration that teaches nothing shows no support either.)
        if !unmeasurable {
            crate::arrival::confirm_arrivals(classification, recording, &self.config);
        }
        classification.fill_parts();
        crate::flight::mark_flights(classification, recording, &self.config);
        classification.mark_rests();
        // A roll is measured without a reference pose, so it does not depend on the rest a
        // demonstration starts with; it does on the noise.
        if !unmeasurable {
            crate::roll::mark_rolls(classification, recording, &self.config);
        }
        crate::length_check::withhold_if_not_metres(classification);
    }

    /// Analyse every demonstration of a source: one for files and memory, one per part of a
    /// bag split at rests.
    pub fn observe_all(&self, source: &Source) -> Result<Vec<Observation>> {
        let Source::Bag { path, selection } = *source else {
            return Ok(vec![self.observe(source)?]);
        };
        let offset = self.config.clocks.palm_time_offset_s;
        let demos = read_bag_demonstrations(path, selection, offset)?;
        demos
            .into_iter()
            .map(|b| {
                // The palm's offset is applied, and bag stamps are seconds (sec, nanosec).
                let demo = self.in_metres(Cow::Borrowed(&b.demo));
                let demo = &*demo;
                let in_file = |e| match e {
                    crate::Error::Data(msg) => crate::Error::File {
                        file: path.to_path_buf(),
                        msg: format!("{}: {msg}", b.demo.name),
                    },
                    e => e,
                };
                let classified = |config: &Config| {
                    let mut c = classify(demo, config).map_err(in_file)?;
                    c.warnings.splice(0..0, b.warnings.iter().cloned());
                    c.length_unit = config.length_unit;
                    Ok(c)
                };
                let recording = Recording::of(demo, self.capacity);
                let c = self.checked(classified(&self.config)?, &recording, classified)?;
                Ok(self.with_dynamics(c, recording))
            })
            .collect()
    }

    /// The one demonstration of a bag source.
    fn single(&self, source: &Source) -> Result<Observation> {
        let mut all = self.observe_all(source)?;
        if all.len() != 1 {
            let path = match source {
                Source::Bag { path, .. } => path.to_path_buf(),
                _ => Default::default(),
            };
            return Err(crate::Error::File {
                file: path,
                msg: format!(
                    "holds {} demonstrations once split: analyse them with observe_all or learn",
                    all.len()
                ),
            });
        }
        Ok(all.remove(0))
    }

    /// `demo` with its palm on the object's clock, its stamps in seconds and its positions in
    /// metres, and the warnings of what was converted.
    fn prepared<'d>(&self, demo: &'d Demonstration) -> (Cow<'d, Demonstration>, Vec<String>) {
        let (demo, warnings) = self.in_seconds(demo);
        let mut demo = self.in_metres(demo);
        let offset = self.config.clocks.palm_time_offset_s;
        if offset != 0.0 {
            if let Some(palm) = demo.to_mut().palm.as_mut() {
                palm.iter_mut().for_each(|p| p.t += offset);
            }
        }
        (demo, warnings)
    }

    /// `demo` with its positions in metres: scaled by the unit the configuration gives
    /// ([`Config::length_unit`]; poses in memory and bags declare none).
    fn in_metres<'d>(&self, mut demo: Cow<'d, Demonstration>) -> Cow<'d, Demonstration> {
        if let Some(u) = self.config.length_unit.filter(|&u| u != LengthUnit::Metres) {
            let d = demo.to_mut();
            to_metres(&mut d.object, u);
            if let Some(palm) = d.palm.as_mut() {
                to_metres(palm, u);
            }
        }
        demo
    }

    /// `demo` with its stamps in seconds (each stream's unit recognised, if the configuration
    /// asks), and the warnings of what was converted.
    fn in_seconds<'d>(&self, demo: &'d Demonstration) -> (Cow<'d, Demonstration>, Vec<String>) {
        let mut demo = Cow::Borrowed(demo);
        let mut warnings = Vec::new();
        if !self.config.clocks.detect_time_unit {
            return (demo, warnings);
        }
        let object_unit = detect_time_unit_of(&demo.object);
        if object_unit != TimeUnit::Seconds {
            to_seconds(&mut demo.to_mut().object, object_unit);
            warnings.push(conversion_warning("object", object_unit));
        }
        let palm_unit = demo.palm.as_deref().map(detect_time_unit_of);
        if let Some(u) = palm_unit.filter(|&u| u != TimeUnit::Seconds) {
            if let Some(palm) = demo.to_mut().palm.as_mut() {
                to_seconds(palm, u);
            }
            warnings.push(conversion_warning("palm", u));
        }
        (demo, warnings)
    }

    /// The observation of a classified demonstration: the dynamics of its topples fitted to
    /// its recorded frames.
    fn with_dynamics(
        &self,
        mut classification: Classification,
        recording: Recording,
    ) -> Observation {
        let gravity = self.config.gravity;
        let fingerprint = Some(recording.fingerprint(classification.frames));
        let fingerprint_without_positions =
            Some(recording.fingerprint_without_positions(classification.frames));
        let noise_windows = tracker_noise::noise_windows(&self.config, &recording, &classification);
        let mut dynamics = Vec::new();
        let unknown_vertical = classification
            .segments
            .iter()
            .filter(|s| {
                s.withheld
                    .as_deref()
                    .is_some_and(|w| w.contains(crate::classify::UNKNOWN_VERTICAL))
            })
            .count();
        if gravity.is_none() && unknown_vertical > 0 {
            classification.warnings.push(format!(
                "gravity is unknown (--gravity none): {unknown_vertical} rotation(s) about a \
                 fixed line taught no edge (without gravity a topple cannot be told from a \
                 slide turning about a fixed point)"
            ));
        }
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
        let palm_slide = gravity
            .filter(|_| !recording.palm.is_empty())
            .and_then(|g| crate::dynamics::palm_slide(&recording, &classification, &g));
        Observation {
            classification,
            dynamics,
            fingerprint,
            fingerprint_without_positions,
            palm_slide,
            not_learnt: None,
            noise_windows,
        }
    }

    /// Learn from demonstrations: analyse each and fuse it into `tree`, in order. Returns each
    /// demonstration's report. A demonstration that shows no motion teaches nothing
    /// ([`Observation::teaches_nothing`]): it is not added, and its report says so. On an
    /// error, the demonstrations before the one that failed are in the tree.
    ///
    /// Before anything is fused, the gravity given is checked against the vertical that the
    /// rests of all the demonstrations turn about ([`crate::vertical`]) and the sign along
    /// which their flights fall (`gravity_check.rs`): where they contradict it, no
    /// demonstration is added ([`Observation::not_learnt`]: a topple's axis, a slide's plane,
    /// a rest's face, a flight are all told by gravity, and without it pushed demonstrations
    /// teach edges off the object), and each report says why and which gravity to give.
    pub fn learn(&self, tree: &mut Tree, sources: &[Source]) -> Result<Vec<Observation>> {
        self.learn_with_progress(tree, sources, |_| {})
    }

    /// [`Self::learn`], calling `analysed` with each source's index once it is analysed.
    pub fn learn_with_progress(
        &self,
        tree: &mut Tree,
        sources: &[Source],
        mut analysed: impl FnMut(usize),
    ) -> Result<Vec<Observation>> {
        let mut per_source = Vec::new();
        let mut failure = None;
        for (k, s) in sources.iter().enumerate() {
            match self.observe_all(s) {
                Ok(o) => per_source.push(o),
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            }
            analysed(k);
        }
        let observed = &sources[..per_source.len()];
        let out = self.fuse_observed(tree, observed, per_source)?;
        match failure {
            Some(e) => Err(e),
            None => Ok(out),
        }
    }

    /// The second half of [`Self::learn_with_progress`]: the observations of `sources` (each
    /// source's, in order) share their noise and centre of mass, are checked against gravity,
    /// and enter `tree`; the reports.
    fn fuse_observed(
        &self,
        tree: &mut Tree,
        sources: &[Source],
        mut per_source: Vec<Vec<Observation>>,
    ) -> Result<Vec<Observation>> {
        self.share_noise(sources, &mut per_source)?;
        self.share_com(sources, &mut per_source, tree)?;
        let contradicted = if self.gravity_checked {
            self.check_gravity(sources, &per_source)?
        } else {
            None
        };
        let mut out = Vec::new();
        for mut o in per_source.into_iter().flatten() {
            if let Some(why) = &contradicted {
                o.classification.warnings.insert(0, why.clone());
                o.not_learnt = Some(why.clone());
            } else if o.teaches_nothing() {
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
            out.push(o);
        }
        if let (Some(given), None) = (&self.support, &contradicted) {
            tree.give_support(given.clone());
        }
        Ok(out)
    }
}

impl Learner {
    /// Where a demonstration's frames could not measure the tracking noise (and it teaches
    /// nothing), observe it again with the noise that the rests of the demonstrations learnt
    /// with it at its frame rate measure together (`tracker_noise::shared_noises`), checked
    /// against its frames as a noise given is (`tracker_noise::given_check`), and say so. A
    /// bag's parts are observed again together.
    fn share_noise(&self, sources: &[Source], observed: &mut [Vec<Observation>]) -> Result<()> {
        let shares = tracker_noise::shared_noises(&self.config, observed);
        for ((source, parts), shared) in sources.iter().zip(observed.iter_mut()).zip(shares) {
            let Some(shared) = shared else {
                continue;
            };
            let mut config = self.config;
            config.robust.noise = Some(shared.noise);
            let learner = Learner {
                config,
                shared: Some(shared),
                ..self.clone()
            };
            let again = learner.observe_all(source)?;
            if again.len() != parts.len() {
                continue;
            }
            for (part, mut o) in parts.iter_mut().zip(again) {
                if tracker_noise::borrows_noise(part) {
                    tracker_noise::say_shared(&mut o.classification, &shared);
                    *part = o;
                }
            }
        }
        Ok(())
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
