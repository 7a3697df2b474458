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
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// How far \[m\] a learnt edge may be from the object's edge to be that edge: the 5 mm
/// within which `bench/precision.py` counts an edge the object's.
pub const EDGE_MATCH_M: f64 = 5e-3;

/// How far \[rad\] a learnt edge's direction may be from the object's edge's: 3°.
pub const EDGE_MATCH_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// The largest standard deviations (point \[m\], direction \[rad\], per axis normal to the
/// edge) of an edge located within [`EDGE_MATCH_M`] and [`EDGE_MATCH_RAD`] of its estimate
/// but with probability `alpha`: a 2-D normal error of σ per axis exceeds `r` with probability
/// `exp(−r² / 2σ²)`, so `σ ≤ r / √(2 ln(1/α))` (at α = 10⁻³: 1.3 mm and 0.8°). A roll teaches
/// its edge only so located (`crate::roll`).
pub fn max_sigmas(alpha: f64) -> (f64, f64) {
    let k = (2.0 * (1.0 / alpha).ln()).sqrt();
    (EDGE_MATCH_M / k, EDGE_MATCH_RAD / k)
}

/// Why `edge` is not taught, where its standard deviations exceed `max` (point \[m\],
/// direction \[rad\]): [`max_sigmas`] for a roll; [`EDGE_MATCH_M`] and [`EDGE_MATCH_RAD`] for a
/// part measured from its onset, whose edge is then not located even to the distance within
/// which an edge is counted the object's (a slide, a rest and a topple taken for one part,
/// measured from one frame, located an edge to ±23 mm). `who` names the kind of part ("a roll")
/// in the reason.
pub fn unlocated(edge: &EdgeObservation, max: (f64, f64), who: &str) -> Option<String> {
    let (sp, sd) = (edge.sigma_point(), edge.sigma_direction());
    (sp > max.0 || sd > max.1).then(|| {
        format!(
            "edge not taught: it is located to ±{:.1} mm and ±{:.1}° only ({who} teaches \
             within ±{:.1} mm and ±{:.1}°)",
            sp * 1e3,
            sd.to_degrees(),
            max.0 * 1e3,
            max.1.to_degrees()
        )
    })
}

/// The distance \[m\] and angle \[rad\] from a line of unit direction `u` within which the
/// true line lies with probability `p`, by the covariances of its point and direction: the 2-D
/// normal error of the largest standard deviation normal to the line, `σ √(2 ln(1/(1-p)))`
/// (at 95%: 2.45 σ), which bounds it whatever the covariances' shape.
pub fn line_bounds(
    u: &Vector3<f64>,
    point_cov: &Matrix3<f64>,
    direction_cov: &Matrix3<f64>,
    p: f64,
) -> (f64, f64) {
    let k = (2.0 * (1.0 / (1.0 - p)).ln()).sqrt();
    let across = Matrix3::identity() - u * u.transpose();
    let worst = |c: &Matrix3<f64>| {
        let c = across * c * across;
        ((c + c.transpose()) * 0.5)
            .symmetric_eigenvalues()
            .max()
            .max(0.0)
            .sqrt()
    };
    (k * worst(point_cov), k * worst(direction_cov))
}

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
    /// The part of `point_cov` \[m²\] common to every observation of this edge on one support:
    /// the contact's depth ([`EdgeObservation::add_contact_depth_var`]). It is the same error
    /// in each topple about the edge, so it does not average down when they are fused.
    #[serde(default = "zero3")]
    pub common_point_cov: Matrix3<f64>,
}

fn zero3() -> Matrix3<f64> {
    Matrix3::zeros()
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

    /// Add the contact's depth, a variance `var` \[m²\] along `toward` (normal to the line;
    /// where `None`, along a direction normal to it that is not known: `var / 2` on each axis,
    /// the same total), to the point's covariance, as an error common to every observation of
    /// the edge ([`Self::common_point_cov`]).
    ///
    /// The line an object turns about is where its contact is, not where its faces meet: a
    /// rounded edge puts the pivot inside the object, a compliant contact lets the edge sink
    /// into the support as it takes the weight (on MuJoCo's soft contacts the fitted axes of
    /// pushed topples lie 0.6-2.5 mm outside the edge, along the bisector of its faces). The
    /// frames cannot tell: the offset is the same in all of them. Nor can the rests before and
    /// after: moving the point along the bisector changes its height in both alike. The
    /// direction is the support's normal at the middle of the turn, in the object's frame.
    pub fn add_contact_depth_var(&mut self, toward: Option<Vector3<f64>>, var: f64) {
        if var <= 0.0 {
            return;
        }
        let u = self.line.direction;
        let normal_plane = Matrix3::identity() - u * u.transpose();
        let cov = match toward.map(|b| normal_plane * b).filter(|b| b.norm() > 1e-9) {
            Some(b) => b.normalize() * b.normalize().transpose() * var,
            None => normal_plane * (0.5 * var),
        };
        self.add_common_point_cov(&cov);
    }

    /// Add a common covariance \[m²\] (another observation's [`Self::common_point_cov`], of
    /// the same contact), taken normal to this line.
    pub fn add_common_point_cov(&mut self, cov: &Matrix3<f64>) {
        let u = self.line.direction;
        let normal_plane = Matrix3::identity() - u * u.transpose();
        let cov = normal_plane * cov * normal_plane;
        self.point_cov += cov;
        self.common_point_cov += cov;
    }

    /// RMS standard deviation \[rad\] of the direction, per axis normal to the line.
    pub fn sigma_direction(&self) -> f64 {
        (self.direction_cov.trace() / 2.0).max(0.0).sqrt()
    }

    /// The distance \[m\] and angle \[rad\] within which the edge lies with probability `p`
    /// ([`line_bounds`]).
    pub fn bounds(&self, p: f64) -> (f64, f64) {
        line_bounds(
            &self.line.direction,
            &self.point_cov,
            &self.direction_cov,
            p,
        )
    }

    /// Condition the point on a measurement of it, `c` (a linear Gaussian update): the point
    /// moves along `P g` by the measurement's innovation over its variance, and its covariance
    /// shrinks along `g` only. Only `g`'s part normal to the line counts (the point is the
    /// line's, stored closest to the origin).
    pub fn condition_on(&mut self, c: &PointConstraint) {
        let u = self.line.direction;
        let g = c.g - u * u.dot(&c.g);
        let pg = self.point_cov * g;
        let s = g.dot(&pg) + c.var;
        if s.is_nan() || s <= 0.0 {
            return;
        }
        let point = self.line.point - pg * ((c.offset + c.g.dot(&self.line.point)) / s);
        self.line.point = point - u * u.dot(&point);
        let cov = self.point_cov - pg * pg.transpose() / s;
        self.point_cov = (cov + cov.transpose()) * 0.5;
    }
}

/// A measurement of an edge's point `p`: `g · p + offset` is zero, within a standard deviation
/// of `var.sqrt()` \[m\] (for example, the edge lies on the same support in two rests:
/// `classify::parts` measures the difference of its heights there).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointConstraint {
    /// The direction the point is measured along (not unit: its length scales the measurement).
    pub g: Vector3<f64>,
    /// The measurement's value at the origin \[m\].
    pub offset: f64,
    /// The measurement's own variance \[m²\].
    pub var: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::StandardNormal;

    fn observation(point: Vector3<f64>, point_cov: Matrix3<f64>) -> EdgeObservation {
        EdgeObservation {
            demo: "t".into(),
            line: Line {
                point,
                direction: Vector3::z(),
            },
            point_cov,
            direction_cov: Matrix3::zeros(),
            paper_line: None,
            frames: 10,
            max_angle: 1.0,
            chi2_per_dof: 1.0,
            common_point_cov: Matrix3::zeros(),
        }
    }

    /// An edge is withheld exactly when a standard deviation (per axis normal to the line, the
    /// root of half the covariance's trace) exceeds its bound, and the reason gives both.
    #[test]
    fn an_edge_located_worse_than_its_bound_is_withheld() {
        let max = (EDGE_MATCH_M, EDGE_MATCH_RAD);
        let per_axis = |s: f64| Matrix3::from_diagonal(&Vector3::new(s * s, s * s, 0.0));
        let located = observation(Vector3::zeros(), per_axis(4.9e-3));
        assert_eq!(unlocated(&located, max, "a part"), None);
        let wide = observation(Vector3::zeros(), per_axis(5.1e-3));
        let why = unlocated(&wide, max, "a part").expect("5.1 mm exceeds 5 mm");
        assert!(
            why.contains("±5.1 mm") && why.contains("a part teaches within ±5.0 mm"),
            "{why}"
        );
        let mut turned = located.clone();
        turned.direction_cov = per_axis(3.1f64.to_radians());
        assert!(unlocated(&turned, max, "a part").is_some());
        // A roll's bound at the tests' alpha is the stricter one.
        assert!(unlocated(&located, max_sigmas(1e-3), "a roll").is_some());
    }

    /// An exact measurement along x leaves the point on its plane and no variance along x,
    /// and moves nothing along y; a measurement along the line itself changes nothing.
    #[test]
    fn an_exact_constraint_is_met_and_the_rest_is_untouched() {
        let cov = Matrix3::from_diagonal(&Vector3::new(4e-6, 9e-6, 0.0));
        let mut e = observation(Vector3::new(3e-3, -2e-3, 0.0), cov);
        let c = PointConstraint {
            g: Vector3::new(2.0, 0.0, 0.0),
            offset: -2.0 * 1e-3,
            var: 0.0,
        };
        e.condition_on(&c);
        assert!((e.line.point.x - 1e-3).abs() < 1e-15, "{}", e.line.point);
        assert_eq!(e.line.point.y, -2e-3);
        assert!(e.point_cov[(0, 0)].abs() < 1e-20 && e.point_cov[(1, 1)] == 9e-6);
        let before = e.clone();
        e.condition_on(&PointConstraint {
            g: Vector3::z(),
            offset: 5.0,
            var: 0.0,
        });
        assert_eq!(e, before);
    }

    /// Over many draws (a true point, an estimate with its covariance, a measurement with its
    /// variance): the conditioned point's errors are what its covariance says (mean squared
    /// Mahalanobis distance 2 in the plane normal to the line) and smaller than the estimate's.
    #[test]
    fn the_conditioned_covariance_is_honest_and_smaller() {
        let mut rng = StdRng::seed_from_u64(7);
        let n = 4000;
        let (mut m2, mut before_sq, mut after_sq) = (0.0, 0.0, 0.0);
        for _ in 0..n {
            let a: f64 = rng.random_range(1e-3..4e-3);
            let b: f64 = rng.random_range(1e-3..4e-3);
            let rho: f64 = rng.random_range(-0.8..0.8);
            let cov = Matrix3::new(
                a * a,
                rho * a * b,
                0.0,
                rho * a * b,
                b * b,
                0.0,
                0.0,
                0.0,
                0.0,
            );
            let l = cov.fixed_view::<2, 2>(0, 0).cholesky().unwrap().l();
            let z = nalgebra::Vector2::new(rng.sample(StandardNormal), rng.sample(StandardNormal));
            let truth = Vector3::new(
                rng.random_range(-0.05..0.05),
                rng.random_range(-0.05..0.05),
                0.0,
            );
            let err = l * z;
            let mut e = observation(truth + Vector3::new(err.x, err.y, 0.0), cov);
            let g = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                0.3,
            );
            let var: f64 = rng.random_range(0.2e-3f64..3e-3).powi(2);
            let noise: f64 = rng.sample::<f64, _>(StandardNormal) * var.sqrt();
            let c = PointConstraint {
                g,
                offset: -g.dot(&truth) + noise,
                var,
            };
            e.condition_on(&c);
            let d = (e.line.point - truth).xy();
            let p = e.point_cov.fixed_view::<2, 2>(0, 0).into_owned();
            m2 += d.dot(&(p.try_inverse().unwrap() * d));
            before_sq += err.norm_squared();
            after_sq += d.norm_squared();
        }
        let m2 = m2 / n as f64;
        assert!(
            (m2 - 2.0).abs() < 0.15,
            "mean squared Mahalanobis distance {m2}"
        );
        assert!(after_sq < 0.9 * before_sq, "{after_sq} against {before_sq}");
    }
}
