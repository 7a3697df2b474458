//! A roll's turn is a pendulum's: an object that turns about a fixed edge with nothing but
//! gravity on it (the support's reaction acts at the edge, and has no moment about it) follows
//! `ψ̈ = k sin(ψ − φ)`, whatever its shape and inertia ([`crate::pendulum::fit_swing`]).
//!
//! The fixed-line model ([`super::fit`]) asks only where the frames lie, not how they move
//! between them, and under a camera's noise the frames around a roll pass it too: on 500
//! simulated tosses at 30 Hz, 1 mm and 0.5° (the noise given), a box rolled 55° over an
//! edge, its face struck the table, and it slid and bounced for three more frames; the
//! window of all of them fitted one line 5.7 mm from the edge at σ 1.3 mm, and taught it.
//! Its angle about the line rose by 10.7°, 12.0° and 16.7° per frame, then 2.4° and 3.2°: no
//! pendulum stops so (χ² 214 on 5 degrees of freedom), while the true rolls of that set fit
//! the pendulum at χ² 4.7-14.7 on 6-14.
//!
//! A window's angles about its fitted world line ([`angles_about`]) are tested against the
//! pendulum's least-squares fit, χ² with the rotation noise per frame (the first frame's error
//! along the line is common to all the angles and taken up by the fitted start) on
//! `n − 4` degrees of freedom at the tests' `alpha`. A window the pendulum does not explain is
//! cut to its longest part at its start or its end that it does explain, where the roll
//! began with a landing on the edge or ended with the face's.

use super::fit::{self, RollFit, RollNoise};
use crate::flight::FlightFrame;
use nalgebra::{Rotation3, Vector3};

/// What the test needs of the roll's.
pub(super) struct SwingTest<'a> {
    /// The noise the roll's line is fitted with.
    pub noise: &'a RollNoise,
    /// Significance level.
    pub alpha: f64,
    /// Fewest frames of a roll.
    pub min_frames: usize,
}

/// The frames' angles \[rad\] about the unit world direction `u`, from the first frame's
/// orientation.
pub(super) fn angles_about(window: &[FlightFrame], u: &Vector3<f64>) -> Vec<f64> {
    let Some(first) = window.first() else {
        return Vec::new();
    };
    let r0 = first.rotation;
    window
        .iter()
        .map(|f| {
            let rel = Rotation3::from_matrix_unchecked(f.rotation * r0.transpose());
            rel.scaled_axis().dot(u)
        })
        .collect()
}

/// Whether the pendulum explains the turn of `window` about the unit world direction `u`.
fn swings(window: &[FlightFrame], u: &Vector3<f64>, test: &SwingTest) -> bool {
    let n = window.len();
    if n < test.min_frames.max(5) {
        return false;
    }
    let t: Vec<f64> = window.iter().map(|f| f.t).collect();
    let theta = angles_about(window, u);
    let var = test.noise.noise.sigma_rotation.powi(2);
    crate::pendulum::fit_swing(&t, &theta)
        .is_some_and(|f| f.sse / var <= crate::stats::chi2_threshold((n - 4) as f64, test.alpha))
}

/// The window `start..end` (fitted as `fit`) if the pendulum explains its turn; otherwise its
/// longest part from its start or to its end that the pendulum explains, with at least
/// `test.min_frames` frames, fitted again; `None` when there is none. A window of fewer
/// frames is returned as it is.
pub(super) fn swing_part(
    frames: &[FlightFrame],
    start: usize,
    end: usize,
    fit: RollFit,
    test: &SwingTest,
) -> Option<(usize, usize, RollFit)> {
    let u = fit.world_line.direction;
    // (Too few frames for the pendulum: too few for a roll too, as `judge` says.)
    let min_frames = test.min_frames;
    if end - start < min_frames || swings(&frames[start..end], &u, test) {
        return Some((start, end, fit));
    }
    let head = (start + min_frames..end)
        .rev()
        .find(|&e| swings(&frames[start..e], &u, test))
        .map(|e| (start, e));
    let tail = (start + 1..=end - min_frames)
        .find(|&s| swings(&frames[s..end], &u, test))
        .map(|s| (s, end));
    let (a, b) = [head, tail]
        .into_iter()
        .flatten()
        .max_by_key(|(a, b)| b - a)?;
    let f = fit::fit(&frames[a..b], test.noise)?;
    Some((a, b, f))
}
