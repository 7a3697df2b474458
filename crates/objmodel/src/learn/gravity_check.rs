//! The gravity given, checked against the demonstrations learnt together: the vertical their
//! rests turn about ([`crate::vertical`]) and, where that contradicts it, the sign along which
//! their flights fall. Where the rests contradict the gravity given, [`Learner::learn`] learns
//! everything again without gravity, and each report says what the rests and the flights show:
//! the check tells the user the gravity to give, it does not learn with a gravity it guessed.

use super::{Learner, Source};
use crate::classify::Label;
use crate::observation::Observation;
use crate::vertical::Contradiction;
use crate::Result;
use nalgebra::Vector3;

impl Learner {
    /// This learner with `gravity` in place of the configured one.
    pub(super) fn with_gravity(&self, gravity: Option<Vector3<f64>>) -> Learner {
        let mut config = self.config;
        config.gravity = gravity;
        Learner {
            config,
            capacity: self.capacity,
        }
    }

    /// Every demonstration of `sources`, each source's in its own list.
    pub(super) fn observe_all_of(&self, sources: &[Source]) -> Result<Vec<Vec<Observation>>> {
        sources.iter().map(|s| self.observe_all(s)).collect()
    }

    /// Whether the rests of `observations` contradict the gravity given
    /// ([`crate::vertical::contradiction`], at the classifier's α, with the support's level
    /// allowed).
    pub(super) fn vertical_contradiction<'o>(
        &self,
        observations: impl Iterator<Item = &'o Observation>,
    ) -> Option<Contradiction> {
        let up = -self.config.gravity?.try_normalize(0.0)?;
        let rests: Vec<_> = observations
            .flat_map(|o| o.classification.world_rests())
            .collect();
        crate::vertical::contradiction(
            &rests,
            &up,
            self.config.robust.alpha,
            crate::face::SUPPORT_LEVEL_SIGMA_RAD,
        )
    }

    /// What the reports are told when the rests contradict the gravity given: the vertical
    /// they show, and the gravity to give along it where the flights tell its sign
    /// ([`Self::falling_sign`]).
    pub(super) fn contradicted_gravity(
        &self,
        c: &Contradiction,
        sources: &[Source],
    ) -> Result<String> {
        let gravity = self.config.gravity.unwrap_or_default();
        let up = -gravity.normalize();
        let v = |v: &Vector3<f64>| {
            let c = |x: f64| if x.abs() < 5e-4 { 0.0 } else { x };
            format!("{:.3},{:.3},{:.3}", c(v.x), c(v.y), c(v.z))
        };
        let shown = format!(
            "learnt without gravity: the rests of the demonstrations learnt together turn about \
             ({}) ± {:.3} deg, {:.1} deg from the up given ({}), as rests on one level support \
             do ({} pairs of {} rests at various headings; {} pairs turn about the up given)",
            v(&c.axis),
            c.sigma_rad.to_degrees(),
            c.angle_rad.to_degrees(),
            v(&up),
            c.pairs,
            c.rests,
            c.pairs_about_given,
        );
        let g = gravity.norm();
        let (down, up_along) = (-c.axis * g, c.axis * g);
        Ok(match self.falling_sign(&c.axis, g, sources)? {
            Fall::Along { down_axis, k, n, p } => {
                let given = if down_axis { down } else { up_along };
                format!(
                    "{shown}; the flights of {k} of {n} demonstrations fall along ({0}) rather \
                     than against it (sign test p = {p:.1e}): give --gravity {0}",
                    v(&given),
                )
            }
            Fall::Untold { n } => format!(
                "{shown}; give the tracker's gravity, --gravity {} or --gravity {} (the rests \
                 do not tell its sign, and the flights of {n} demonstrations do not either)",
                v(&down),
                v(&up_along),
            ),
        })
    }

    /// Along which sign of `axis` the demonstrations' flights fall: each source learnt with
    /// gravity `g` \[m/s²\] along `-axis` and along `axis`, the sign whose flights
    /// ([`crate::flight`]) cover more of its frames counted per source, and the two-sided sign
    /// test over the sources where the two differ, at the classifier's α. (Objects do not fall
    /// upwards; a hand that throws may lift one at about `g` for a few frames.)
    fn falling_sign(&self, axis: &Vector3<f64>, g: f64, sources: &[Source]) -> Result<Fall> {
        let flight_frames = |gravity: Vector3<f64>| -> Result<Vec<u64>> {
            let learner = self.with_gravity(Some(gravity));
            Ok(learner
                .observe_all_of(sources)?
                .iter()
                .map(|obs| {
                    obs.iter()
                        .flat_map(|o| &o.classification.parts)
                        .filter(|p| p.kind == Label::Flight)
                        .map(|p| p.frames)
                        .sum()
                })
                .collect())
        };
        let (down, up) = (flight_frames(-axis * g)?, flight_frames(axis * g)?);
        let differ: Vec<bool> = down
            .iter()
            .zip(&up)
            .filter(|(d, u)| d != u)
            .map(|(d, u)| d > u)
            .collect();
        let n = differ.len() as u64;
        let k_down = differ.iter().filter(|&&d| d).count() as u64;
        let p = crate::stats::sign_test(k_down, n);
        Ok(if p < self.config.robust.alpha {
            let down_axis = 2 * k_down > n;
            Fall::Along {
                down_axis,
                k: if down_axis { k_down } else { n - k_down },
                n,
                p,
            }
        } else {
            Fall::Untold { n }
        })
    }
}

/// Which way the flights fall along the rests' axis.
enum Fall {
    /// Along `-axis` (`down_axis`) or `axis`: in `k` of the `n` sources whose flights differ
    /// between the two, with the sign test's p-value.
    Along {
        down_axis: bool,
        k: u64,
        n: u64,
        p: f64,
    },
    /// Not told, by `n` sources whose flights differ.
    Untold { n: u64 },
}
