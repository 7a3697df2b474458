//! Edges (Algorithm 2): the line an object toppled about, in the object's frame.
//!
//! Two estimates are kept for every topple:
//! * the paper's: the screw axis at the frame of largest rotation (`t_e = argmax |ω(t)|`),
//!   taken over the frames that fit the segment's line (the paper takes all frames; at the end
//!   of a real topple the object leaves its edge, and its largest rotation is often then);
//! * the "more rigorous" one the paper names: the mean over the per-frame lines — directional
//!   mean of the axes (principal axis of `Σ a_k u_k u_kᵀ`) and euclidean mean of the points —
//!   weighted by each frame's inverse variance, over the frames that fit the line only, with its
//!   covariance. This is [`EdgeObservation::line`].
//!
//! Per-frame variances, propagated from the tracking noise σ_p \[m\], σ_r \[rad\]: for rotation θ
//! about a line through r, the axis point moves by `δt⊥ / (2 sin(θ/2))` for a translation error
//! δt, and by `|r| δφ / (2 sin(θ/2))` for a rotation error δφ; the axis direction by `δφ/θ`.

use crate::geometry::Line;
use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

/// One demonstration's estimate of one edge, in the object frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdgeObservation {
    /// The demonstration it comes from.
    pub demo: String,
    /// Mean line: `point` is the point closest to the object origin \[m\]; `direction` is the
    /// axis the object turned about, with the right-hand rule, positive.
    pub line: Line,
    /// Covariance of `line.point` \[m²\] (normal to the line).
    pub point_cov: Matrix3<f64>,
    /// Covariance of `line.direction` \[rad²\] (normal to the line).
    pub direction_cov: Matrix3<f64>,
    /// The paper's Algorithm 2 estimate: the screw axis at the frame of largest rotation.
    pub paper_line: Option<Line>,
    /// Frames that fit the line.
    pub frames: u64,
    /// Largest rotation about the edge \[rad\].
    pub max_angle: f64,
    /// χ² per degree of freedom of the fitted frames (about 1 when the noise model is right).
    pub chi2_per_dof: f64,
}

impl EdgeObservation {
    /// RMS standard deviation \[m\] of the point, per axis normal to the line.
    pub fn sigma_point(&self) -> f64 {
        (self.point_cov.trace() / 2.0).max(0.0).sqrt()
    }

    /// Add a per-axis variance \[m²\] normal to the line to the point's covariance (an error
    /// common to all the frames, which their scatter does not show).
    pub fn add_systematic_point_var(&mut self, var: f64) {
        if var > 0.0 {
            let u = self.line.direction;
            self.point_cov += (nalgebra::Matrix3::identity() - u * u.transpose()) * var;
        }
    }

    /// Add a per-axis variance \[rad²\] normal to the line to the direction's covariance (an
    /// error common to all the frames, which their scatter does not show).
    pub fn add_systematic_direction_var(&mut self, var: f64) {
        if var > 0.0 {
            let u = self.line.direction;
            self.direction_cov += (nalgebra::Matrix3::identity() - u * u.transpose()) * var;
        }
    }

    /// RMS standard deviation \[rad\] of the direction, per axis normal to the line.
    pub fn sigma_direction(&self) -> f64 {
        (self.direction_cov.trace() / 2.0).max(0.0).sqrt()
    }
}
