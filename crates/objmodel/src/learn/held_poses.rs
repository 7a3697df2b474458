//! Whether the object's tracker held its last pose: frames that repeat the pose before them
//! exactly, from a tracker whose noise makes an exact repeat all but impossible
//! ([`crate::clean::held`]), or a logger that samples the tracker faster than it measures.
//! `Learner::checked` (the parent module) then classifies again with those frames left out.
//!
//! The test. At rest, two frames of a tracker with position noise σ per axis differ by
//! N(0, 2σ²) per axis; written to a resolution of `r` (the file's last decimal), they read the
//! same with probability about `r / (2 √π σ)` per axis (the density of the difference at 0
//! times the width of one step), at most 1. A position that repeats on all three axes has the
//! product of the three. Where that is below the tests' `alpha`, with σ measured on the
//! quiet windows of frames that are not repeats (see `noise_of_tracker`) and above the floor that
//! the learner treats as exact poses ([`crate::noise::MIN_SIGMA_POSITION_M`]), every repeat is
//! the tracker's, not the object's. A simulator's exact poses repeat wherever the object is
//! still, and measure no noise at rest: kept. A coarse resolution (millimetres for a
//! 0.1 mm tracker) repeats by chance: kept.

use crate::classify::{Classification, Config, Method};
use crate::noise::{PoseSample, MIN_SIGMA_POSITION_M, SCATTER_WINDOW};
use crate::recording::{RecordedFrame, Recording};
use nalgebra::Vector3;

/// Repeats found, and why they are the tracker's.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct HeldPosesFound {
    /// Frames that repeat the pose before them.
    pub frames: usize,
    /// Runs of them.
    pub runs: usize,
    /// The longest run \[s\], from the frame it repeats to its last.
    pub longest_s: f64,
    /// The position noise measured on the frames that are not repeats \[m\] per axis.
    pub sigma: f64,
    /// The resolution the positions are written to \[m\], per axis.
    pub resolution: Vector3<f64>,
    /// The probability of a repeat by chance at rest.
    pub chance: f64,
}

impl HeldPosesFound {
    /// `config` with the repeats left out.
    pub(super) fn config(&self, config: &Config) -> Config {
        let mut config = *config;
        config.robust.repeats_are_held = true;
        config
    }

    /// Say in the classification made without them what was left out, and why.
    pub(super) fn say(&self, c: &mut Classification) {
        c.held_frames = self.frames as u64;
        c.warnings.insert(
            0,
            format!(
                "{} object frames ({} {}, the longest {:.2} s) repeat the pose before them \
                 exactly, which this tracker does not do by chance (its noise is \
                 {:.3} mm per axis; at the file's resolution a repeat has probability {:.0e}): \
                 not measurements (a tracker holding its last pose while it lost the object, or \
                 a logger sampling it faster than it measures), left out as glitches are",
                self.frames,
                self.runs,
                if self.runs == 1 { "run" } else { "runs" },
                self.longest_s,
                self.sigma * 1e3,
                self.chance
            ),
        );
    }
}

/// Whether the recorded frame `k` repeats the one before it.
pub(super) fn is_repeat(frames: &[RecordedFrame], k: usize) -> bool {
    k > 0 && {
        let (a, b) = (&frames[k - 1], &frames[k]);
        crate::clean::held::repeats(&b.rotation, &b.position, &a.rotation, &a.position)
    }
}

/// The held poses of the object's stream in `recording`, as classified in `c` with `config`
/// (`None`: no repeats, or repeats an exact or coarsely written tracker makes). Robust method,
/// every frame recorded (the test needs consecutive frames), repeats not left out already. A
/// noise given is not used: the test measures the tracker's own.
pub(super) fn check(
    config: &Config,
    c: &Classification,
    recording: &Recording,
) -> Option<HeldPosesFound> {
    if config.method != Method::Robust
        || config.robust.repeats_are_held
        || recording.object_stride != 1
    {
        return None;
    }
    let frames = &recording.object;
    let repeat: Vec<bool> = (0..frames.len()).map(|k| is_repeat(frames, k)).collect();
    if !repeat.contains(&true) {
        return None;
    }
    let sigma = noise_of_tracker(c, frames, &repeat)?;
    if sigma <= MIN_SIGMA_POSITION_M {
        return None;
    }
    let resolution = Vector3::from_fn(|axis, _| {
        resolution(
            frames
                .iter()
                .zip(&repeat)
                .filter(|(_, r)| !**r)
                .map(|(f, _)| f.position[axis]),
        )
    });
    let chance = resolution
        .iter()
        .map(|r| (r / (2.0 * std::f64::consts::PI.sqrt() * sigma)).min(1.0))
        .product::<f64>();
    if chance >= config.robust.alpha {
        return None;
    }
    // Runs, each timed from the frame it repeats.
    let (mut runs, mut longest_s, mut repeated) = (0, 0.0f64, 0);
    for k in 1..frames.len() {
        if !repeat[k] {
            repeated = k;
            continue;
        }
        if !repeat[k - 1] {
            runs += 1;
        }
        longest_s = longest_s.max(frames[k].t - frames[repeated].t);
    }
    Some(HeldPosesFound {
        frames: repeat.iter().filter(|r| **r).count(),
        runs,
        longest_s,
        sigma,
        resolution,
        chance,
    })
}

/// The position noise \[m\] per axis of the tracker: over windows of [`SCATTER_WINDOW`]
/// consecutive frames that are neither repeats nor outliers, each window's noise with a
/// smooth motion's acceleration removed ([`crate::noise::motion_free`], unfloored), the lower
/// quartile (the quiet windows: a tumble or an impact only adds to a window's). `None` with
/// fewer than [`MIN_WINDOWS`] windows. (Not on the first classification's rests: the repeats
/// make the noise it used look small, and it may have cut the rests into pieces too short to
/// measure.)
fn noise_of_tracker(c: &Classification, frames: &[RecordedFrame], repeat: &[bool]) -> Option<f64> {
    let outlier = c.is_outlier();
    let samples: Vec<PoseSample> = frames
        .iter()
        .zip(repeat)
        .filter(|(f, r)| !**r && !outlier(f.index))
        .map(|(f, _)| f.sample())
        .collect();
    let mut sigmas: Vec<f64> = samples
        .chunks_exact(SCATTER_WINDOW)
        .filter_map(|w| crate::noise::motion_free(w).map(|n| n.sigma_position))
        .collect();
    if sigmas.len() < MIN_WINDOWS {
        return None;
    }
    sigmas.sort_by(f64::total_cmp);
    Some(sigmas[(sigmas.len() - 1) / 4])
}

/// Fewest windows [`noise_of_tracker`] measures on.
const MIN_WINDOWS: usize = 4;

/// The resolution \[m\] `values` are written to: the largest power of ten, down to 10⁻¹²,
/// of which every one is a whole multiple (to the rounding of reading the decimal and of a
/// unit's conversion); 10⁻¹² where none is (values written in full, or computed).
fn resolution(values: impl Iterator<Item = f64> + Clone) -> f64 {
    for k in 0..=12 {
        let scale = 10f64.powi(k);
        let whole = values.clone().all(|v| {
            let x = v * scale;
            (x - x.round()).abs() <= 1e-6 + x.abs() * 1e-12
        });
        if whole {
            return 10f64.powi(-k);
        }
    }
    1e-12
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_is_the_last_decimal_written() {
        let read = |s: &[&str]| resolution(s.iter().map(|x| x.parse::<f64>().unwrap()));
        assert_eq!(read(&["0.108489724", "-0.141040167", "0.069994397"]), 1e-9);
        assert_eq!(read(&["0.1085", "-0.1410", "2.5"]), 1e-4);
        assert_eq!(read(&["1", "-3", "12"]), 1.0);
        // Millimetres converted to metres keep their resolution.
        let mm = ["512.3", "81.6", "-240.9"].map(|x| x.parse::<f64>().unwrap() * 1e-3);
        assert_eq!(resolution(mm.iter().copied()), 1e-4);
        // Computed values, written in full.
        let full = [0.1f64.sqrt(), std::f64::consts::PI / 7.0];
        assert_eq!(resolution(full.iter().copied()), 1e-12);
    }
}
