//! The gravity given, checked against the demonstrations learnt together: the line of the
//! vertical their rests turn about ([`crate::vertical`]), and the sign along which their
//! flights fall. Where either contradicts the gravity given (a tracker with y up learnt as z
//! up; a gravity given upside down), [`Learner::learn`] adds none of the demonstrations to
//! the model, and each report says what the rests and the flights show: the check tells the
//! user the gravity to give; it does not learn with a gravity it measured (a tilted table would
//! pass its normal for the vertical), nor without gravity (which tells a topple's axis, a
//! slide's plane and a rest's face: the standard data set's pushes learnt without it taught
//! edges off the box). The sign costs up to [`MAX_SIGN_SOURCES`] more analyses, and only where
//! the rests show a vertical (at many headings): a set of 60 motion-capture tosses is learnt in
//! 0.77 s instead of 0.40 s.

use super::{Learner, Source};
use crate::classify::Label;
use crate::observation::Observation;
use crate::Result;
use nalgebra::Vector3;

impl Learner {
    /// This learner with `gravity` in place of the configured one.
    pub(super) fn with_gravity(&self, gravity: Option<Vector3<f64>>) -> Learner {
        let mut config = self.config;
        config.gravity = gravity;
        Learner {
            config,
            ..self.clone()
        }
    }

    /// Check the gravity given against the demonstrations `observed` from `sources` (each
    /// source's in its own list): what every report is told when they contradict it, `None`
    /// when they agree with it or cannot tell. The rests show the vertical's line
    /// ([`crate::vertical::shown`]); the flights show its sign ([`Self::flights_fall`]): where
    /// the rests contradict the line given, along which sign of theirs; where they agree,
    /// whether along the gravity given or against it (given upside down).
    pub(super) fn check_gravity(
        &self,
        sources: &[Source],
        observed: &[Vec<Observation>],
    ) -> Result<Option<String>> {
        let Some(gravity) = self.config.gravity.filter(|g| g.norm() > 0.0) else {
            return Ok(None);
        };
        let up = -gravity.normalize();
        let rests: Vec<_> = observed
            .iter()
            .flatten()
            .flat_map(|o| o.classification.world_rests())
            .collect();
        let Some(shown) = crate::vertical::shown(
            &rests,
            &up,
            self.config.robust.alpha,
            crate::face::SUPPORT_LEVEL_SIGMA_RAD,
        ) else {
            return Ok(None);
        };
        let rests_say = format!(
            "the rests of the demonstrations learnt together turn about ({}) ± {:.3} deg, \
             {:.1} deg from the up given ({}), as rests on one level support do ({} pairs of {} \
             rests at various headings; {} pairs turn about the up given)",
            v(&shown.axis),
            shown.sigma_rad.to_degrees(),
            shown.angle_rad.to_degrees(),
            v(&up),
            shown.pairs,
            shown.rests,
            shown.pairs_about_given,
        );
        let g = gravity.norm();
        if shown.contradicts {
            if let Some(advice) = self.rests_in_other_order(sources, observed, &up) {
                return Ok(Some(format!("{NOT_LEARNT}: {rests_say}; {advice}")));
            }
            let (down, up_along) = (-shown.axis * g, shown.axis * g);
            let fall = self.flights_fall(&down, None, &up_along, sources)?;
            let advice = match fall {
                Fall::Along { first, k, n, p } => format!(
                    "the flights of {k} of {n} demonstrations fall along ({0}) rather than \
                     against it (sign test p = {p:.1e}): give --gravity {0}",
                    v(if first { &down } else { &up_along })
                ),
                Fall::Untold { n } => format!(
                    "give the tracker's gravity, --gravity {} or --gravity {} (the rests do \
                     not tell its sign, and the flights of {n} demonstrations do not either)",
                    v(&down),
                    v(&up_along)
                ),
            };
            return Ok(Some(format!("{NOT_LEARNT}: {rests_say}; {advice}")));
        }
        // The rests agree with the line given: do the flights fall along it, or against it?
        let flipped = self.flights_fall(&gravity, Some(observed), &-gravity, sources)?;
        Ok(match flipped {
            Fall::Along {
                first: false,
                k,
                n,
                p,
            } => Some(format!(
                "{NOT_LEARNT}: the gravity given ({}) points up: {rests_say}, but the flights \
                 of {k} of {n} demonstrations fall against it rather than along it (sign test \
                 p = {p:.1e}): give --gravity {}",
                v(&gravity),
                v(&-gravity)
            )),
            _ => None,
        })
    }

    /// Where the rests contradict the up given: whether, read in the other quaternion order
    /// (the demonstrations read in the configured one: see `quaternion_check.rs`), they turn
    /// about it; then the advice to give that order. (Read in the wrong order, rests on one
    /// face at various headings turn about a fixed line that is not the vertical, and the check
    /// would otherwise ask for that line as gravity.)
    fn rests_in_other_order(
        &self,
        sources: &[Source],
        observed: &[Vec<Observation>],
        up: &Vector3<f64>,
    ) -> Option<String> {
        let order = self.config.quaternion_order;
        let reread: Vec<bool> = sources
            .iter()
            .map(|s| self.read_in_configured_order(s))
            .collect();
        let n_reread = reread.iter().filter(|&&r| r).count();
        if n_reread == 0 {
            return None;
        }
        let rests: Vec<_> = reread
            .iter()
            .zip(observed)
            .flat_map(|(&other, observations)| {
                observations
                    .iter()
                    .flat_map(|o| o.classification.world_rests())
                    .map(move |mut r| {
                        if other {
                            r.rotation = order.read_in_other(&r.rotation);
                        }
                        r
                    })
            })
            .collect();
        let shown = crate::vertical::shown(
            &rests,
            up,
            self.config.robust.alpha,
            crate::face::SUPPORT_LEVEL_SIGMA_RAD,
        )?;
        (!shown.contradicts).then(|| {
            format!(
                "read in {} order, they turn about the up given ({} pairs do): the \
                 quaternions of the {n_reread} demonstration(s) read in {} order look written \
                 so; give --quat-order {} (in Python, quat_order=\"{}\"; TUM's own order is \
                 x y z w)",
                order.other().spelled(),
                shown.pairs_about_given,
                order.spelled(),
                order.other(),
                order.other(),
            )
        })
    }

    /// Which of `first` and `second` (gravity, \[m/s²\] or a unit direction) the flights of
    /// the demonstrations fall along: at most [`MAX_SIGN_SOURCES`] of `sources` (evenly
    /// chosen) analysed with each (or taken from `first_observed`, already analysed with
    /// `first`); in each, the one whose flights ([`crate::flight`]) cover more frames wins; the
    /// two-sided sign test over those where the two differ decides, at the classifier's α.
    /// (Objects do not fall upwards; a hand that throws lifts one at about g for a few frames,
    /// so the wrong sign finds short flights too.)
    fn flights_fall(
        &self,
        first: &Vector3<f64>,
        first_observed: Option<&[Vec<Observation>]>,
        second: &Vector3<f64>,
        sources: &[Source],
    ) -> Result<Fall> {
        let chosen: Vec<usize> = if sources.len() > MAX_SIGN_SOURCES {
            (0..MAX_SIGN_SOURCES)
                .map(|k| k * sources.len() / MAX_SIGN_SOURCES)
                .collect()
        } else {
            (0..sources.len()).collect()
        };
        let frames = |obs: &[Observation]| -> u64 {
            obs.iter()
                .flat_map(|o| &o.classification.parts)
                .filter(|p| p.kind == Label::Flight)
                .map(|p| p.frames)
                .sum()
        };
        let with = |gravity: &Vector3<f64>| -> Result<Vec<u64>> {
            let learner = self.with_gravity(Some(*gravity));
            chosen
                .iter()
                .map(|&k| Ok(frames(&learner.observe_all(&sources[k])?)))
                .collect()
        };
        let a = match first_observed {
            Some(observed) => chosen.iter().map(|&k| frames(&observed[k])).collect(),
            None => with(first)?,
        };
        let b = with(second)?;
        let differ: Vec<bool> = a
            .iter()
            .zip(&b)
            .filter(|(x, y)| x != y)
            .map(|(x, y)| x > y)
            .collect();
        let n = differ.len() as u64;
        let k_first = differ.iter().filter(|&&d| d).count() as u64;
        let p = crate::stats::sign_test(k_first, n);
        Ok(if p < self.config.robust.alpha {
            let first = 2 * k_first > n;
            Fall::Along {
                first,
                k: if first { k_first } else { n - k_first },
                n,
                p,
            }
        } else {
            Fall::Untold { n }
        })
    }
}

/// How the report of a demonstration kept out of the model by the check starts.
pub const NOT_LEARNT: &str = "not learnt, the gravity given contradicts the demonstrations";

/// Most demonstrations analysed again to tell the sign of gravity from their flights (evenly
/// chosen beyond): 11 that agree already pass the sign test at α = 10⁻³.
pub const MAX_SIGN_SOURCES: usize = 32;

/// A vector as the command line takes it (`--gravity x,y,z`).
fn v(v: &Vector3<f64>) -> String {
    let c = |x: f64| if x.abs() < 5e-4 { 0.0 } else { x };
    format!("{:.3},{:.3},{:.3}", c(v.x), c(v.y), c(v.z))
}

/// Which of two gravities the flights fall along.
enum Fall {
    /// Along the first (`first`) or the second: in `k` of the `n` demonstrations whose flights
    /// differ between the two, with the sign test's p-value.
    Along { first: bool, k: u64, n: u64, p: f64 },
    /// Not told, by `n` demonstrations whose flights differ.
    Untold { n: u64 },
}
