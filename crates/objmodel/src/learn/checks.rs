//! What the frames kept say of a classification, before anything is taught: a tracker that
//! held its last pose, noise that the first frames could not measure or that is correlated
//! from frame to frame (each classified again with the right noise), rests that a motion
//! reached, flights, rolls, and lengths that are not metres.

use super::tracker_noise::{self, say_correlated, with_long_run_noise, NoiseCheck};
use super::{held_poses, Config, Learner};
use crate::classify::Classification;
use crate::recording::Recording;
use crate::Result;

impl Learner {
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
    pub(super) fn checked(
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
    /// not be measured (`unmeasurable`, see `tracker_noise::noise_check`), and the rests that a
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
}
