//! The second stage: the observations of all the demonstrations learnt together share what
//! one of them cannot measure alone (the tracking noise, a thrown object's centre of mass),
//! are checked against gravity, and enter the tree.

use super::{tracker_noise, Learner, Source};
use crate::classify::Classification;
use crate::observation::Observation;
use crate::tree::Tree;
use crate::Result;

impl Learner {
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
    pub(super) fn fuse_observed(
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
