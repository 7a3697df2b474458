//! The error budget of φ: what a fit's covariance leaves out.
//!
//! A fit's covariance counts the noise of the samples it fits, one by one. φ also carries
//! errors that are the same for every sample of a topple, and so never show in a fit's
//! residuals:
//! * the resting face's normal in the object frame, from the rest before the motion: every
//!   tilt about the edge is measured from it, so its error (per axis `σ_o/√N` over the `N`
//!   rest frames, `σ_o` the object's rotation noise) shifts ψ, and φ with it;
//! * instrumented, the same face in the palm frame (`palm_from_object`, averaged over the same
//!   rest: `(σ_o² + σ_p²)/N`), from which the palm's tilt β is measured;
//! * instrumented, β where the object starts to turn: the palm's tilt is smoothed (local linear
//!   regression over ±[`super::tolerances::SMOOTH_S`]), and its error at one instant, `σ_p/√N_w` over the
//!   `N_w` samples of the window, is one value for the whole onset.
//!
//! The palm's own rotation noise `σ_p` is not measured apart from the object's: the budget
//! takes the palm tracked as well as the object (`σ_p = σ_o`).

/// The noise and sample counts that the offsets common to a topple's samples come from.
#[derive(Clone, Copy, Debug)]
pub(super) struct Budget {
    /// The object's rotation noise per axis \[rad\].
    pub sigma_object: f64,
    /// The palm's \[rad\].
    pub sigma_palm: f64,
    /// Rest frames the reference normals are averaged over.
    pub reference_frames: usize,
}

impl Budget {
    fn n(&self) -> f64 {
        self.reference_frames.max(1) as f64
    }

    /// Variance \[rad²\] of the resting face's normal (object frame) about the edge.
    pub fn resting_normal(&self) -> f64 {
        self.sigma_object.powi(2) / self.n()
    }

    /// Variance \[rad²\] of the resting face's normal in the palm frame about the edge.
    pub fn palm_reference(&self) -> f64 {
        (self.sigma_object.powi(2) + self.sigma_palm.powi(2)) / self.n()
    }

    /// Variance \[rad²\] of the smoothed palm tilt at time `at`, from the samples `t` within the
    /// smoothing window.
    pub fn smoothed_tilt(&self, t: &[f64], at: f64) -> f64 {
        let lo = t.partition_point(|&x| x < at - super::tolerances::SMOOTH_S);
        let hi = t.partition_point(|&x| x <= at + super::tolerances::SMOOTH_S);
        self.sigma_palm.powi(2) / (hi - lo).max(1) as f64
    }

    /// The instrumented offsets together: φ as a palm tilt at time `at`.
    pub fn palm_tilt_at(&self, t: &[f64], at: f64) -> f64 {
        self.resting_normal() + self.palm_reference() + self.smoothed_tilt(t, at)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Offsets average down with the rest's frames; the smoothed tilt with the window's.
    #[test]
    fn variances_fall_with_the_frames_that_average_them() {
        let b = |n| Budget {
            sigma_object: 0.01,
            sigma_palm: 0.02,
            reference_frames: n,
        };
        assert!((b(1).resting_normal() - 1e-4).abs() < 1e-18);
        assert!((b(4).resting_normal() - 0.25e-4).abs() < 1e-18);
        assert!((b(5).palm_reference() - 1e-4).abs() < 1e-18);
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.01).collect();
        // ±0.25 s at 100 Hz: 51 samples.
        assert!((b(1).smoothed_tilt(&t, 0.5) - 4e-4 / 51.0).abs() < 1e-15);
        // At the end of the series only half the window holds samples.
        assert!((b(1).smoothed_tilt(&t, 0.99) - 4e-4 / 26.0).abs() < 1e-15);
    }
}
