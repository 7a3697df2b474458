//! A thrown demonstration's rolls told from its flights by the centre of mass that the flights
//! of all the demonstrations learnt with it measure together ([`crate::shared_com`]).

use super::{tracker_noise, Learner, Source};
use crate::classify::Classification;
use crate::flight::ComEstimate;
use crate::observation::Observation;
use crate::shared_com::{shared_com, SharedCom};
use crate::support::{SupportHeight, SupportObservation};
use crate::tree::{Tree, MATCH_ALPHA};
use crate::Result;

impl Learner {
    /// Where a direct demonstration flew and its own flights do not determine the centre of
    /// mass (a roll of it is then not told from a flight: `crate::roll`), observe it again
    /// with the centre of mass that the flights of all the demonstrations `observed` agree on
    /// ([`shared_com`]), with those of the demonstrations in `tree` already (but for any the
    /// same poses replace): its flights are then flights of that point
    /// ([`crate::flight::FlightTest::with_known_com`]: a flight's own point can take in the
    /// frames of a roll right after it), and its rolls' alternative is the fall of that point.
    /// Keep that observation where it teaches more rolls, each of them
    /// on the support that the demonstrations (and those in `tree`) measured without it, saying
    /// so. Nothing is shared where the centre of mass is given already, where the flights do
    /// not agree, or where no support is known (none given, and the demonstrations'
    /// measurements of it are fewer than two or disagree).
    ///
    /// Why the support: a rotation about a fixed point (a box spinning on one corner) passes
    /// for a rotation about a fixed line over a few frames, and where the centre of mass rules
    /// out the flight, nothing else of the demonstration tells the two apart; the line through
    /// the corner is not on the support (on the brick's 100 motion-capture tosses, such a
    /// "roll" 20 mm above the table, 34° off every edge). A roll that lies on the support is
    /// an edge resting on it.
    ///
    /// A demonstration that borrowed the noise (`share_noise`) is observed with it again; a
    /// bag whose parts borrowed it in part is not observed again.
    pub(super) fn share_com(
        &self,
        sources: &[Source],
        observed: &mut [Vec<Observation>],
        tree: &Tree,
    ) -> Result<()> {
        if self.config.robust.com.is_some() {
            return Ok(());
        }
        let mut flights: Vec<(usize, ComEstimate)> = observed
            .iter()
            .flatten()
            .enumerate()
            .flat_map(|(k, o)| {
                o.classification
                    .flight_coms_taught()
                    .iter()
                    .map(move |e| (k, e.clone()))
            })
            .collect();
        let replaced = replaced_in(tree, observed);
        flights.extend(earlier_flights(tree, &replaced, observed));
        let Some(shared) = shared_com(&flights) else {
            return Ok(());
        };
        let measured: Vec<SupportObservation> = observed
            .iter()
            .flatten()
            .flat_map(|o| o.classification.support_observations())
            .chain(self.support.clone())
            .chain(
                tree.supports
                    .iter()
                    .filter(|o| !replaced.contains(&o.demo))
                    .cloned(),
            )
            .collect();
        let Some(support) = SupportHeight::fuse(&measured, MATCH_ALPHA) else {
            return Ok(());
        };
        for (source, parts) in sources.iter().zip(observed.iter_mut()) {
            if !parts.iter().any(|o| needs_com(&o.classification)) {
                continue;
            }
            let noise = parts
                .iter()
                .map(|o| o.classification.noise_shared)
                .collect::<Vec<_>>();
            if noise.iter().any(Option::is_some) && noise.iter().any(Option::is_none) {
                continue;
            }
            let mut config = self.config;
            config.robust.com = Some(shared);
            if let Some(n) = noise[0] {
                config.robust.noise = Some(n.noise);
            }
            let learner = Learner {
                config,
                shared: noise[0],
                ..self.clone()
            };
            let again = learner.observe_all(source)?;
            if again.len() != parts.len() {
                continue;
            }
            for (part, mut o) in parts.iter_mut().zip(again) {
                if taught_rolls(&o.classification) <= taught_rolls(&part.classification)
                    || !rolls_on(&o.classification, &support)
                {
                    continue;
                }
                if let Some(n) = part.classification.noise_shared {
                    tracker_noise::say_shared(&mut o.classification, &n);
                }
                say_com_shared(&mut o.classification, &shared);
                *part = o;
            }
        }
        Ok(())
    }
}

/// The names of the demonstrations in `tree` whose poses are `observed` again (they will be
/// replaced).
fn replaced_in(tree: &Tree, observed: &[Vec<Observation>]) -> Vec<String> {
    let again: Vec<&String> = observed
        .iter()
        .flatten()
        .filter_map(|o| o.fingerprint.as_ref())
        .collect();
    tree.demos
        .iter()
        .filter(|d| d.fingerprint.as_ref().is_some_and(|f| again.contains(&f)))
        .map(|d| d.name.clone())
        .collect()
}

/// The flights of the demonstrations learnt into `tree` before, but for the `replaced` ones
/// (observed again: the same poses replace them), each with an index of its demonstration past
/// `observed`'s.
fn earlier_flights(
    tree: &Tree,
    replaced: &[String],
    observed: &[Vec<Observation>],
) -> Vec<(usize, ComEstimate)> {
    let first = observed.iter().map(Vec::len).sum::<usize>();
    tree.flights
        .iter()
        .filter(|f| !replaced.contains(&f.demo))
        .map(|f| {
            let k = tree.demos.iter().position(|d| d.name == f.demo);
            (first + k.unwrap_or(tree.demos.len()), f.estimate())
        })
        .collect()
}

/// Whether a demonstration's rolls would be told from its flights by a shared centre of mass:
/// direct, it flew, and its own flights determined no centre of mass.
fn needs_com(c: &Classification) -> bool {
    !c.instrumented && c.flew() && c.parts.iter().all(|p| p.com_estimate.is_none())
}

/// How many of a classification's rolls taught their edge.
fn taught_rolls(c: &Classification) -> usize {
    c.rolls.iter().filter(|r| r.taught).count()
}

/// Whether every roll of a classification that taught its edge measured the support's height
/// within the `support` the demonstrations agree on.
fn rolls_on(c: &Classification, support: &SupportHeight) -> bool {
    c.rolls.iter().filter(|r| r.taught).all(|r| {
        r.support
            .as_ref()
            .is_some_and(|s| support.holds(s, MATCH_ALPHA))
    })
}

/// Say in a classification whose rolls the shared centre of mass told from flights where it
/// came from.
fn say_com_shared(c: &mut Classification, shared: &SharedCom) {
    let sigma = shared
        .covariance
        .diagonal()
        .map(|v| v.max(0.0).sqrt() * 1e3);
    c.warnings.push(format!(
        "its rolls were told from flights by the centre of mass that {} flights of {} \
         demonstrations learnt with it agree on (of {} flights that measured one), ({:.1}, \
         {:.1}, {:.1}) mm ± ({:.2}, {:.2}, {:.2}) mm in the object frame (demonstrations \
         learnt together are taken to be of one object)",
        shared.flights,
        shared.demonstrations,
        shared.flights_seen,
        shared.point.x * 1e3,
        shared.point.y * 1e3,
        shared.point.z * 1e3,
        sigma.x,
        sigma.y,
        sigma.z,
    ));
    c.com_shared = Some(*shared);
}
