//! The first stage: a demonstration observed, alone. Its classification (Algorithms 1 and 2)
//! from one pass over its files, checked against the frames kept (`checks.rs`), then the
//! dynamics of its topples fitted to those frames: an [`Observation`].

use super::{tracker_noise, Config, Learner, Source};
use crate::classify::{classify, Classification};
use crate::format::bag::read_bag_demonstrations;
use crate::observation::Observation;
use crate::recording::{Recorder, Recording};
use crate::Result;
use std::borrow::Cow;

impl Learner {
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
    /// ([`Learner::check`]) and against the other quaternion order
    /// ([`Learner::order_checked`]), and those frames.
    fn classify_recorded(&self, source: &Source) -> Result<(Classification, Recording)> {
        let (c, recording) = self.classify_recorded_in_order(source)?;
        Ok((self.order_checked(source, c)?, recording))
    }

    /// [`Learner::classify_recorded`] in the configured quaternion order alone.
    pub(super) fn classify_recorded_in_order(
        &self,
        source: &Source,
    ) -> Result<(Classification, Recording)> {
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
}
