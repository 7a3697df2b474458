//! The centre of mass from the pendulums' planes, with its covariance.
//!
//! Each pendulum (edge, resting face, φ) puts the CoM `x` in the plane through the edge tilted
//! by φ from the face's inward normal: `mᵀ (x - p) = 0`, `m` the plane's unit normal, `p` a
//! point of the edge. Three or more planes of independent normals give `x` by weighted least
//! squares, each plane weighted by `1/σ²` of its residual `r = mᵀ (x - p)` at the solution,
//! propagated to first order from everything the plane is made of:
//!
//! * φ: turning the plane about the edge by δφ moves it by `l δφ` at `x`, `l` the CoM's
//!   distance from the edge (`σ_φ` = the pendulum's `phi_sigma`; [`UNKNOWN_PHI_SIGMA_RAD`] when
//!   it has none);
//! * the edge's point: `r` changes by `-mᵀ δp` (`Edge::point_cov`);
//! * the edge's direction (`Edge::direction_cov`) and the resting face's normal (its
//!   `sigma_normal_own_rad` per axis: the support's level common to every gravity-taught face
//!   is left out, as it would tilt every plane's face alike): by the numerical derivative of
//!   `r` along the two axes normal to each.
//!
//! The errors of different planes are taken as independent (two pendulums of one edge share the
//! edge's error: that correlation is left out). The covariance of `x` is `(Σ m mᵀ/σ²)⁻¹`; with
//! more than three planes it is multiplied by the reduced χ² `Σ r²/σ² / (N - 3)` when that
//! exceeds 1 (the planes disagree more than their sigmas say; it is never shrunk below the
//! propagated one). Three planes always meet in a point (χ² is 0): their covariance is the
//! propagated one alone.
//!
//! The flights measure the CoM directly ([`crate::shared_com`]): that point, with its
//! covariance, enters the same least squares as three more equations ([`com_from`]); with it,
//! any number of planes fixes a point.

use super::{matrix, CONDITION_MIN};
use crate::geometry::normal_axes;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use serde::{Deserialize, Serialize};

/// σ_φ \[rad\] (2°) taken for a pendulum that has no `phi_sigma`.
pub const UNKNOWN_PHI_SIGMA_RAD: f64 = 0.034_906_585_039_886_59;

/// Where the centre of mass is, from the pendulums and the flights (see [`com_from`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CentreOfMass {
    /// The CoM in the object frame \[m\].
    pub point: Vector3<f64>,
    /// RMS residual distance of the CoM from the planes \[m\].
    pub rms_residual_m: f64,
    /// Pendulums used.
    pub pendulums: usize,
    /// Covariance of `point` \[m²\], rows (absent in files written before it was computed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub covariance: Option<[[f64; 3]; 3]>,
    /// Standard deviation \[m\] of `point` along its worst-known direction: the square root of
    /// the covariance's largest eigenvalue.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_m: Option<f64>,
    /// χ² of the planes' residuals per degree of freedom (`N - 3`); absent with three planes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chi2_per_dof: Option<f64>,
    /// Flights whose centres of mass it holds, pooled ([`crate::shared_com`]); 0 where none.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub flights: usize,
    /// The demonstrations those flights came from.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub flight_demonstrations: usize,
    /// χ² (3 degrees of freedom) of the flights' point against the pendulums' CoM, where
    /// both are known (`tree/com.rs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flights_chi2: Option<f64>,
    /// What the flights say the gravity the learner was given is off by (given less the one
    /// they fell with) \[m/s²\], in the poses' frame (`SharedCom::gravity_error`), where
    /// flights are pooled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flights_gravity_error: Option<Vector3<f64>>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// A direct measurement of the centre of mass: the point the flights agree on.
#[derive(Clone, Debug, PartialEq)]
pub struct ComPoint {
    /// The point, object frame \[m\].
    pub point: Vector3<f64>,
    /// Its covariance \[m²\].
    pub covariance: Matrix3<f64>,
}

impl CentreOfMass {
    /// What it was learnt from, in words: "3 pendulums", "12 flights of 8 demonstrations",
    /// or both.
    pub fn learnt_from(&self) -> String {
        let pendulums = (self.pendulums > 0).then(|| {
            format!(
                "{} pendulum{}",
                self.pendulums,
                if self.pendulums == 1 { "" } else { "s" }
            )
        });
        let flights = (self.flights > 0).then(|| {
            format!(
                "{} flights of {} demonstrations",
                self.flights, self.flight_demonstrations
            )
        });
        match (pendulums, flights) {
            (Some(p), Some(f)) => format!("{p} and {f}"),
            (p, f) => p.or(f).unwrap_or_else(|| "nothing".to_string()),
        }
    }

    /// The covariance as a matrix, if known.
    pub fn covariance_matrix(&self) -> Option<Matrix3<f64>> {
        self.covariance.as_ref().map(matrix)
    }

    /// The error of the CoM against a true `point`, along each eigen-axis of the covariance in
    /// its standard deviations (an honest covariance gives independent standard normals: median
    /// |value| 0.674). `None` without a covariance or with a degenerate one.
    pub fn standardised_error(&self, truth: &Vector3<f64>) -> Option<Vector3<f64>> {
        let eig = SymmetricEigen::new(self.covariance_matrix()?);
        if eig.eigenvalues.min() <= 0.0 {
            return None;
        }
        let e = self.point - truth;
        Some(Vector3::from_fn(|k, _| {
            eig.eigenvectors.column(k).dot(&e) / eig.eigenvalues[k].sqrt()
        }))
    }
}

/// One pendulum's plane and what it is made of, with their uncertainties.
#[derive(Clone, Debug, PartialEq)]
pub struct ComPlane {
    /// φ \[rad\] and its standard deviation.
    pub phi: f64,
    /// Standard deviation of φ \[rad\].
    pub phi_sigma: f64,
    /// A point of the edge \[m\] and its covariance \[m²\].
    pub point: Vector3<f64>,
    /// Covariance of `point` \[m²\].
    pub point_cov: Matrix3<f64>,
    /// The toppling axis (unit edge direction; `axis × normal` points into the face).
    pub axis: Vector3<f64>,
    /// Covariance of `axis` \[rad²\].
    pub axis_cov: Matrix3<f64>,
    /// Outward unit normal of the resting face.
    pub normal: Vector3<f64>,
    /// Standard deviation of `normal` per axis \[rad\].
    pub normal_sigma: f64,
}

impl ComPlane {
    /// The plane's unit normal `m` for the given axis and face normal.
    fn plane_normal(&self, axis: &Vector3<f64>, normal: &Vector3<f64>) -> Vector3<f64> {
        let w = axis.cross(normal).normalize();
        let d = -normal * self.phi.cos() + w * self.phi.sin();
        axis.cross(&d).normalize()
    }

    /// `(m, mᵀp)`: the plane `mᵀx = mᵀp`.
    pub fn plane(&self) -> (Vector3<f64>, f64) {
        let m = self.plane_normal(&self.axis, &self.normal);
        (m, m.dot(&self.point))
    }

    /// Variance \[m²\] of the plane's residual at `x` (see the module documentation).
    pub fn residual_variance(&self, x: &Vector3<f64>) -> f64 {
        let m = self.plane_normal(&self.axis, &self.normal);
        let r = x - self.point;
        let l = (r - self.axis * self.axis.dot(&r)).norm();
        let mut var = (l * self.phi_sigma).powi(2) + (m.transpose() * self.point_cov * m)[0];
        // Derivatives along the two axes normal to a unit vector, by central differences.
        let h = 1e-6;
        let resid = |axis: &Vector3<f64>, normal: &Vector3<f64>| {
            self.plane_normal(&axis.normalize(), &normal.normalize())
                .dot(&r)
        };
        let g: Vec<Vector3<f64>> = normal_axes(&self.axis)
            .iter()
            .map(|a| {
                let d = (resid(&(self.axis + a * h), &self.normal)
                    - resid(&(self.axis - a * h), &self.normal))
                    / (2.0 * h);
                a * d
            })
            .collect();
        let j = g[0] + g[1];
        var += (j.transpose() * self.axis_cov * j)[0];
        for a in normal_axes(&self.normal) {
            let d = (resid(&self.axis, &(self.normal + a * h))
                - resid(&self.axis, &(self.normal - a * h)))
                / (2.0 * h);
            var += (d * self.normal_sigma).powi(2);
        }
        var
    }
}

/// The point closest, in the weighted least-squares sense, to the planes, with its covariance
/// (see the module documentation); `None` with fewer than three planes or when their normals
/// are too close to parallel to fix a point ([`CONDITION_MIN`] on `Σ m mᵀ`: the geometry decides
/// whether the planes meet in a point, the weights only how well each is known).
pub fn com_from_planes(planes: &[ComPlane]) -> Option<CentreOfMass> {
    com_from(planes, None)
}

/// [`com_from_planes`] with the flights' `point` among the equations, if given: then any
/// number of planes (none too) gives a point. `chi2_per_dof` stays the planes' own (about the
/// joint point, over `N - 3`); the point's own agreement with the planes is
/// [`CentreOfMass::flights_chi2`], which the caller fills.
pub fn com_from(planes: &[ComPlane], point: Option<&ComPoint>) -> Option<CentreOfMass> {
    let eq: Vec<(Vector3<f64>, f64)> = planes.iter().map(ComPlane::plane).collect();
    let point_info = match point {
        Some(p) => Some((p.covariance.try_inverse()?, p.point)),
        None => {
            if planes.len() < 3 {
                return None;
            }
            let geometry: Matrix3<f64> = eq.iter().map(|(m, _)| m * m.transpose()).sum();
            let eig = geometry.symmetric_eigenvalues();
            if eig.min() < CONDITION_MIN * eig.max() {
                return None;
            }
            None
        }
    };
    let solve = |var: &[f64]| {
        let (mut a, mut b) = (Matrix3::zeros(), Vector3::zeros());
        for ((m, d), v) in eq.iter().zip(var) {
            a += m * m.transpose() / *v;
            b += m * (d / v);
        }
        if let Some((w, x)) = &point_info {
            a += w;
            b += w * x;
        }
        let inv = a.try_inverse()?;
        Some((inv * b, inv))
    };
    // The residuals' variances depend on where the CoM is (its distance from each edge):
    // start from the flights' point or the unweighted planes' one, then re-weight.
    let (mut x, _) = match point {
        Some(p) => (p.point, Matrix3::zeros()),
        None => solve(&vec![1.0; eq.len()])?,
    };
    let mut var = Vec::new();
    let mut cov = Matrix3::zeros();
    for _ in 0..4 {
        var = planes
            .iter()
            .map(|p| p.residual_variance(&x).max(1e-18))
            .collect();
        (x, cov) = solve(&var)?;
    }
    let resid: Vec<f64> = eq.iter().map(|(m, d)| m.dot(&x) - d).collect();
    let rms = if eq.is_empty() {
        0.0
    } else {
        (resid.iter().map(|r| r * r).sum::<f64>() / eq.len() as f64).sqrt()
    };
    let chi2_per_dof = (eq.len() > 3).then(|| {
        resid.iter().zip(&var).map(|(r, v)| r * r / v).sum::<f64>() / (eq.len() - 3) as f64
    });
    if let Some(c) = chi2_per_dof.filter(|c| *c > 1.0) {
        cov *= c;
    }
    let cov = (cov + cov.transpose()) / 2.0;
    Some(CentreOfMass {
        point: x,
        rms_residual_m: rms,
        pendulums: eq.len(),
        covariance: Some(super::rows(&cov)),
        sigma_m: Some(cov.symmetric_eigenvalues().max().max(0.0).sqrt()),
        chi2_per_dof,
        flights: 0,
        flight_demonstrations: 0,
        flights_chi2: None,
        flights_gravity_error: None,
    })
}
