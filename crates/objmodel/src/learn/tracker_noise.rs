//! Whether the noise a classification used measures the tracker, and what to classify with
//! where it does not: the noise of a rest where the first frames measured the motion, the
//! long-run noise where the tracker's noise is correlated from frame to frame
//! ([`crate::noise_correlation`]), and, where no frame of a demonstration measures it, the noise
//! that the demonstrations learnt with it measure together ([`crate::shared_noise`]).
//! `Learner::checked` and `Learner::share_noise` (the parent module) classify again with what
//! these find.

use crate::classify::{Classification, Config};
use crate::noise::NoiseModel;
use crate::noise_correlation::TrackerCorrelations;
use crate::observation::Observation;
use crate::recording::{RecordedFrame, Recording};
use crate::shared_noise::{shared_noise, SharedNoise};

/// Whether the noise the classification `c` used measures the tracker: estimated (none
/// given) from first frames whose motion dominates their second differences
/// ([`noise_unmeasurable`]), it may be the motion's (10 mm for 1 mm at 30 Hz, for
/// a thrown object whose file starts in flight), and then every test passes everything, a
/// 3-frame "topple" among them. The longest rest measures it if it lasts the rest test's
/// window, or if, shorter, the frames of its second half are at least one
/// [`crate::noise::SCATTER_WINDOW`] (a tracker at 100-250 Hz; 30 Hz needs the window);
/// otherwise the noise is unmeasurable. Its first half window (or first half) is dropped:
/// with the motion's noise a motion's end is found late or early, and its last frames may
/// still be in the "rest". Where the first frames' estimate exceeds the rest's beyond
/// their sampling errors ([`crate::noise::exceeds`]), the rest's is the noise. Otherwise
/// the first frames' estimate stands (a demonstration shorter than the warm-up holds its
/// motion among the first frames, and its rests keep the estimate at the noise).
pub(super) fn noise_check(
    config: &Config,
    c: &Classification,
    recording: &Recording,
) -> NoiseCheck {
    if !noise_unmeasurable(config, recording) {
        return NoiseCheck::Measured;
    }
    let robust = &config.robust;
    let window = robust.rest_window_s;
    let Some((t0, t1)) = longest_rest(c, recording) else {
        return NoiseCheck::Unmeasurable;
    };
    let measured = (t0 + 0.5 * window.min(t1 - t0), t1);
    let samples: Vec<crate::noise::PoseSample> = measuring(config, recording)
        .filter(|f| f.t > measured.0 && f.t < measured.1)
        .map(RecordedFrame::sample)
        .collect();
    if t1 - t0 < window && samples.len() < crate::noise::SCATTER_WINDOW {
        return NoiseCheck::Unmeasurable;
    }
    let tolerance = (robust.edge_tolerance_m, robust.edge_tolerance_rad);
    let first_frames = recording.object.len().min(robust.warmup_frames.max(3));
    match (crate::noise::estimate(&samples), c.noise) {
        (Some(noise), Some(first))
            if !crate::noise::motion_dominated(&samples, robust.alpha, tolerance)
                && crate::noise::exceeds(
                    &first,
                    first_frames,
                    &noise,
                    samples.len(),
                    robust.alpha,
                ) =>
        {
            NoiseCheck::OnRest(RestNoise {
                noise,
                first,
                measured,
                given: None,
                palm: None,
            })
        }
        _ => NoiseCheck::Measured,
    }
}

/// Whether the noise the user gave is smaller than the demonstration shows, beyond sampling
/// error (one-sided at `alpha`, [`crate::noise::exceeds`]), in position or rotation: the white
/// noise of its quiet windows ([`crate::noise_correlation::measure`]) or, where they measure
/// none, the first frames' estimate where their motion does not dominate it
/// ([`crate::noise::motion_dominated`]). Then the noise to classify with is the larger of
/// each, and of the long-run noise where the tracker's noise is correlated from frame to frame
/// (and the palm's long-run noise where its noise is not given). A noise given too small
/// makes every test too strict and every σ too small, and rests look like motion, so that a
/// rest cannot be the check: on the standard set's camera scenes (0.7 mm, 0.3° per frame,
/// three times that along the line of sight, correlated from frame to frame), the per-frame
/// noise given taught edges off the box (`bench/precision.py --noise given`: topples 22/25
/// true, palm topples 13/16). Only where the robust method classified every frame with the
/// noise given for the object.
///
/// `given_as` names the noise given in what the classification is told: "the tracking noise
/// given", or where the noise came from others ([`crate::shared_noise`]).
pub(super) fn given_check(
    config: &Config,
    recording: &Recording,
    given_as: &'static str,
) -> Option<RestNoise> {
    let robust = &config.robust;
    let given = robust.noise?;
    if config.method != crate::classify::Method::Robust || recording.object_stride != 1 {
        return None;
    }
    let tolerance = (robust.edge_tolerance_m, robust.edge_tolerance_rad);
    let all: Vec<crate::noise::PoseSample> = measuring(config, recording)
        .map(RecordedFrame::sample)
        .collect();
    let first = &all[..all.len().min(robust.warmup_frames.max(3))];
    // What the data show of the noise, from how many frames, and the noise to test with: the
    // quiet windows' where they measure it (correlated noise looks like motion to the first
    // frames' test), else the first frames' where their motion does not dominate them.
    let (shown, frames, noise) = match crate::noise_correlation::measure(&all) {
        Some(k) => {
            let long_run = if k.matters(tolerance) {
                k.long_run
            } else {
                k.white
            };
            (
                k.white,
                k.windows * crate::noise_correlation::WINDOW,
                long_run,
            )
        }
        None if !crate::noise::motion_dominated(first, robust.alpha, tolerance) => {
            let e = crate::noise::estimate(first)?;
            (e, first.len(), e)
        }
        None => return None,
    };
    if !crate::noise::exceeds(&shown, frames, &given, usize::MAX / 8, robust.alpha) {
        return None;
    }
    let noise = NoiseModel {
        sigma_position: given.sigma_position.max(noise.sigma_position),
        sigma_rotation: given.sigma_rotation.max(noise.sigma_rotation),
    };
    let span = (
        first.first().map_or(0.0, |s| s.0),
        all.last().map_or(0.0, |s| s.0),
    );
    // The palm's noise, where not given, as without a noise given: its long-run noise where
    // correlated (`correlated_noise`), else its own first frames' estimate.
    let palm = palm_correlation(config, recording).map(|k| k.long_run);
    Some(RestNoise {
        noise,
        first: given,
        measured: span,
        given: Some(given_as),
        palm,
    })
}

/// The long-run noise of a tracker whose noise is correlated from frame to frame
/// ([`crate::noise_correlation`]), where the robust method estimates the noise (none given)
/// and every frame was kept: measured on the object's frames and, with a palm whose noise
/// is not given, on the palm's; `None` where the object's long-run noise, at the measured ρ,
/// does not exceed what the same frames give as independent noise by more than the model
/// tolerance that the tests add to the noise anyway (white noise: ρ measured at or near 0;
/// exact poses: the contacts' micro-motion is smooth, and both are the floor).
///
/// The measured ρ is used as it is, without a test of its significance: where a few windows
/// cannot prove a correlation that is there, taking the noise as independent makes every test
/// too strict (a camera's file with held frames left out measured ρ ≈ 0.5 at 3.96 standard
/// errors over 11 windows, where the t test at 10⁻³ asks 4.14; with the short-lag noise its
/// rest on the palm showed motion and an edge was taught 7.7 mm off at ±1.1 mm), while white
/// noise's chance positive ρ only makes them a little laxer (precision first).
pub(super) fn correlated_noise(
    config: &Config,
    recording: &Recording,
) -> Option<TrackerCorrelations> {
    let robust = &config.robust;
    if !estimates_noise(config, recording) {
        return None;
    }
    let object: Vec<crate::noise::PoseSample> = measuring(config, recording)
        .map(RecordedFrame::sample)
        .collect();
    let object = crate::noise_correlation::measure(&object)?;
    let tolerance = (robust.edge_tolerance_m, robust.edge_tolerance_rad);
    if !object.matters(tolerance) {
        return None;
    }
    let palm = palm_correlation(config, recording);
    Some(TrackerCorrelations { object, palm })
}

/// The palm's noise correlation, where its noise is not given, the record kept every palm
/// frame, and the correlation matters beyond the model tolerance
/// ([`crate::noise_correlation::Correlation::matters`]).
fn palm_correlation(
    config: &Config,
    recording: &Recording,
) -> Option<crate::noise_correlation::Correlation> {
    let robust = &config.robust;
    if robust.palm_noise.is_some() || recording.palm_stride != 1 {
        return None;
    }
    let palm: Vec<crate::noise::PoseSample> = recording
        .palm
        .iter()
        .map(|p| (p.t, p.pose.rotation, p.pose.translation.vector))
        .collect();
    let tolerance = (robust.edge_tolerance_m, robust.edge_tolerance_rad);
    crate::noise_correlation::measure(&palm).filter(|k| k.matters(tolerance))
}

/// The windows of a direct demonstration's rests that measure its tracker's noise
/// ([`crate::noise_correlation::NoiseWindows`], at most [`crate::shared_noise::MAX_WINDOWS`]),
/// where the robust method estimates the noise (none given), every frame was kept, and the
/// noise its rests were found with was measured (not the motion's: then a slow motion passes
/// for a rest). Rests only, each counted back from its end
/// ([`crate::noise_correlation::NoiseWindows::of_rests`]): in a thrown object's frames,
/// windows of a bounce, a slide or a roll are as quiet as the quieter quarter of all its
/// windows, and 98 simulated tosses at 1 mm, 0.5° of white noise measured a lag-one
/// correlation of 0.22 and a long-run noise of 1.62 mm, 0.74° over all their windows.
pub(super) fn noise_windows(
    config: &Config,
    recording: &Recording,
    c: &Classification,
) -> Option<crate::noise_correlation::NoiseWindows> {
    if !estimates_noise(config, recording) || !recording.palm.is_empty() || c.noise_unmeasurable {
        return None;
    }
    let frames: Vec<&RecordedFrame> = measuring(config, recording).collect();
    let runs: Vec<Vec<crate::noise::PoseSample>> = c
        .labels
        .iter()
        .filter(|r| r.label == crate::classify::Label::Rest)
        .map(|r| {
            let lo = frames.partition_point(|f| (f.index as usize) < r.first);
            let hi = frames.partition_point(|f| (f.index as usize) <= r.last);
            frames[lo..hi].iter().map(|f| f.sample()).collect()
        })
        .collect();
    Some(
        crate::noise_correlation::NoiseWindows::of_rests(runs.iter().map(Vec::as_slice))
            .thinned(crate::shared_noise::MAX_WINDOWS),
    )
}

/// Whether a demonstration takes the noise of those learnt with it: direct (an instrumented
/// one's noise is the motion's relative to the palm, with the palm's noise in it), and its
/// frames could not measure its own.
pub(super) fn borrows_noise(o: &Observation) -> bool {
    !o.classification.instrumented && o.classification.noise_unmeasurable
}

/// For each source's demonstrations (a bag's parts), the noise that the rests of all the
/// demonstrations `observed` at its frame rate measure together ([`shared_noise`]), where one
/// of them borrows it ([`borrows_noise`]); `None` where none does or nothing is shared.
pub(super) fn shared_noises(
    config: &Config,
    observed: &[Vec<Observation>],
) -> Vec<Option<SharedNoise>> {
    let robust = &config.robust;
    let learnt: Vec<(f64, &crate::noise_correlation::NoiseWindows)> = observed
        .iter()
        .flatten()
        .filter_map(|o| {
            Some((
                o.classification.frame_interval_s?,
                o.noise_windows.as_ref()?,
            ))
        })
        .collect();
    observed
        .iter()
        .map(|parts| {
            let interval = parts
                .iter()
                .filter(|o| borrows_noise(o))
                .find_map(|o| o.classification.frame_interval_s)?;
            shared_noise(
                interval,
                learnt.iter().copied(),
                (robust.edge_tolerance_m, robust.edge_tolerance_rad),
                robust.alpha,
            )
        })
        .collect()
}

/// Say in a classification made with the noise that the rests of the demonstrations learnt
/// with it measure together where it came from.
pub(super) fn say_shared(c: &mut Classification, shared: &SharedNoise) {
    let k = &shared.measured;
    c.warnings.insert(
        0,
        format!(
            "the tracking noise cannot be measured on this demonstration's frames (the motion \
             between them exceeds the noise, and no rest is long enough): it was learnt with \
             the noise that the rests of the {} demonstrations at its frame rate{} measure \
             together, {:.2} mm, {:.2} deg{} (demonstrations learnt together at one \
             frame rate are taken to be one tracker's: give --noise-position and \
             --noise-rotation otherwise)",
            shared.demonstrations,
            c.frame_interval_s
                .map_or(String::new(), |dt| format!(" ({:.0} Hz)", 1.0 / dt)),
            shared.noise.sigma_position * 1e3,
            shared.noise.sigma_rotation.to_degrees(),
            if shared.noise == k.white {
                format!(" over {} windows", k.windows)
            } else {
                format!(
                    ", long-run (lag-one correlation {:.2} over {} windows; {:.2} mm, {:.2} deg \
                     as independent)",
                    k.rho,
                    k.windows,
                    k.white.sigma_position * 1e3,
                    k.white.sigma_rotation.to_degrees()
                )
            }
        ),
    );
    c.noise_given = false;
    c.noise_shared = Some(*shared);
}

/// The recorded object frames that measure the tracker: every one, or, where the config takes
/// repeats for the tracker's held poses (`held_poses.rs`), those that are not repeats.
fn measuring<'a>(
    config: &Config,
    recording: &'a Recording,
) -> impl Iterator<Item = &'a RecordedFrame> + 'a {
    let held = config.robust.repeats_are_held;
    let frames = &recording.object;
    frames
        .iter()
        .enumerate()
        .filter_map(move |(k, f)| (!(held && super::held_poses::is_repeat(frames, k))).then_some(f))
}

/// Whether the robust method estimates the noise (none given), and the record kept every
/// object frame (the checks of the noise need consecutive frames).
fn estimates_noise(config: &Config, recording: &Recording) -> bool {
    config.method == crate::classify::Method::Robust
        && config.robust.noise.is_none()
        && recording.object_stride == 1
}

/// Whether the robust method estimated the noise (none given) from frames whose motion
/// dominates their second differences ([`crate::noise::motion_dominated`]): then the
/// estimate is the motion's, every test passes everything, and features would be taught
/// with confidence from anything. Tested on the frames the estimate used (the first
/// `warmup_frames`; all of them when the record kept every frame of those).
fn noise_unmeasurable(config: &Config, recording: &Recording) -> bool {
    let robust = &config.robust;
    if !estimates_noise(config, recording) {
        return false;
    }
    let samples: Vec<crate::noise::PoseSample> = measuring(config, recording)
        .take(robust.warmup_frames.max(3))
        .map(RecordedFrame::sample)
        .collect();
    crate::noise::motion_dominated(
        &samples,
        robust.alpha,
        (robust.edge_tolerance_m, robust.edge_tolerance_rad),
    )
}

/// What [`noise_check`] found.
pub(super) enum NoiseCheck {
    /// The noise was given, or the first frames measured it.
    Measured,
    /// The first frames measured the motion; a rest measured the noise.
    OnRest(RestNoise),
    /// The first frames measured the motion, and no rest measures the noise.
    Unmeasurable,
}

/// The tracking noise measured on a rest, in place of the first frames' estimate, or on all the
/// frames, in place of a noise given smaller than they show ([`given_check`]).
pub(super) struct RestNoise {
    noise: NoiseModel,
    /// The first frames' estimate, or the noise given.
    first: NoiseModel,
    /// The span \[s\] of the frames it was measured on.
    measured: (f64, f64),
    /// Where `first` is a noise given (by the user, or shared by other demonstrations) and
    /// `noise` the larger of it and what the frames show, each: what it is called.
    given: Option<&'static str>,
    /// The palm's long-run noise, where its noise is correlated and not given.
    palm: Option<NoiseModel>,
}

impl RestNoise {
    /// `config` with this noise given.
    pub(super) fn config(&self, config: &Config) -> Config {
        let mut config = *config;
        config.robust.noise = Some(self.noise);
        if self.palm.is_some() {
            config.robust.palm_noise = self.palm;
        }
        config
    }

    /// Say in the classification made with this noise where the noise came from.
    pub(super) fn reclassified(&self, c: &mut Classification) {
        let mm = |n: &NoiseModel| n.sigma_position * 1e3;
        let deg = |n: &NoiseModel| n.sigma_rotation.to_degrees();
        if let Some(given) = self.given {
            c.warnings.insert(
                0,
                format!(
                    "{given} ({:.2} mm, {:.2} deg) is smaller than the frames at {:.2}-{:.2} s \
                     show: the tests use {:.2} mm, {:.2} deg, the larger of each (a noise \
                     too small makes every test too strict and every σ too small)",
                    mm(&self.first),
                    deg(&self.first),
                    self.measured.0,
                    self.measured.1,
                    mm(&self.noise),
                    deg(&self.noise)
                ),
            );
            c.noise_given = false;
            return;
        }
        c.warnings.insert(
            0,
            format!(
                "the tracking noise was measured on the rest at {:.2}-{:.2} s ({:.2} mm, \
                 {:.2} deg): the first frames are motion, and the estimate from them was \
                 {:.2} mm, {:.2} deg",
                self.measured.0,
                self.measured.1,
                mm(&self.noise),
                deg(&self.noise),
                mm(&self.first),
                deg(&self.first)
            ),
        );
        // Measured on the rest, not given by the user.
        c.noise_given = false;
    }
}

/// `config` with the long-run noise of correlated trackers given: the object's and, where
/// measured, the palm's ([`crate::noise_correlation`]).
pub(super) fn with_long_run_noise(config: &Config, correlated: &TrackerCorrelations) -> Config {
    let mut config = *config;
    config.robust.noise = Some(correlated.object.long_run);
    if let Some(palm) = &correlated.palm {
        config.robust.palm_noise = Some(palm.long_run);
    }
    config
}

/// Say in the classification made with the long-run noise where the noise came from: that
/// the noise is correlated where its windows prove it (one-sided at `alpha`,
/// [`crate::noise_correlation::Correlation::significant`]), that it may be where they cannot
/// rule it out (the measured ρ is used either way: [`correlated_noise`]).
pub(super) fn say_correlated(c: &mut Classification, correlated: &TrackerCorrelations, alpha: f64) {
    let say = |who: &str, k: &crate::noise_correlation::Correlation| {
        let measured = format!(
            "lag-one correlation {}{:.2}, {:.1} standard errors above white noise's, over {} \
             windows of {} frames",
            if k.at_least { "at least " } else { "" },
            k.rho,
            k.z,
            k.windows,
            crate::noise_correlation::WINDOW,
        );
        let mm_deg = |n: &NoiseModel| (n.sigma_position * 1e3, n.sigma_rotation.to_degrees());
        let (long_mm, long_deg) = mm_deg(&k.long_run);
        if k.significant(alpha) {
            format!(
                "the {who}'s tracking noise is correlated from frame to frame ({measured}): the \
                 tests use its long-run size, {long_mm:.2} mm, {long_deg:.2} deg (a filtering \
                 tracker; give --noise-position and --noise-rotation to override)"
            )
        } else {
            let (white_mm, white_deg) = mm_deg(&k.white);
            format!(
                "the {who}'s tracking noise may be correlated from frame to frame ({measured}: \
                 too few to rule it out): the tests use the long-run size it may have, \
                 {long_mm:.2} mm, {long_deg:.2} deg, not {white_mm:.2} mm, {white_deg:.2} deg \
                 as independent (give --noise-position and --noise-rotation to override)"
            )
        }
    };
    let mut said = vec![say("object", &correlated.object)];
    if let Some(palm) = &correlated.palm {
        said.push(say("palm", palm));
    }
    c.warnings.splice(0..0, said);
    // Measured, not given by the user.
    c.noise_given = false;
    c.noise_correlation = Some(*correlated);
}

/// Why nothing can be learnt with the long-run noise of `correlated`, where a tracker's
/// correlation is beyond what the windows resolve
/// ([`crate::noise_correlation::Correlation::beyond_resolution`] at `alpha`): the long-run σ is
/// then only a lower bound, the tests would be too strict by an unknown factor, and every
/// feature would be taught with too much confidence. `None` otherwise.
pub(super) fn beyond_resolution(correlated: &TrackerCorrelations, alpha: f64) -> Option<String> {
    let who = match (correlated.object.beyond_resolution(alpha), &correlated.palm) {
        (true, _) => "object's",
        (false, Some(p)) if p.beyond_resolution(alpha) => "palm's",
        _ => return None,
    };
    Some(format!(
        "the {who} poses are correlated from frame to frame beyond what ten-frame windows \
         resolve, so the size of their noise is unknown (poses that a logger interpolates \
         between a slower tracker's, as ROS tf lookups do, are so): give the tracker's own \
         stream, or its noise (--noise-position, --noise-rotation, and the palm's)"
    ))
}

/// The longest time \[s\] between the demonstration's motion segments (or before the first,
/// or after the last), as (start, end); `None` without frames.
fn longest_rest(c: &Classification, recording: &Recording) -> Option<(f64, f64)> {
    let (first, last) = (recording.object.first()?, recording.object.last()?);
    let mut bounds = vec![first.t];
    for s in &c.segments {
        bounds.push(s.t_start);
        bounds.push(s.t_end);
    }
    bounds.push(last.t);
    bounds
        .chunks(2)
        .map(|w| (w[0], w[1]))
        .max_by(|a, b| (a.1 - a.0).total_cmp(&(b.1 - b.0)))
}
