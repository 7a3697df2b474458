//! An edge of the object in the tree: the information-weighted mean line of its
//! per-demonstration observations (see the [tree documentation](super)).

use super::{angle, rows, Pendulum, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};
use crate::edge::EdgeObservation;
use crate::geometry::{Line, LineStats};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// An edge of the object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Edge {
    /// Identifier, `e0`, `e1`, ...
    pub id: String,
    /// Point of the edge line closest to the object-frame origin \[m\].
    pub point: Vector3<f64>,
    /// Unit direction of the edge line.
    pub direction: Vector3<f64>,
    /// Covariance of `point` \[m²\], rows.
    pub point_cov: [[f64; 3]; 3],
    /// Covariance of `direction` \[rad²\], rows.
    pub direction_cov: [[f64; 3]; 3],
    /// RMS standard deviation of `point` normal to the line \[m\].
    pub sigma_point_m: f64,
    /// RMS standard deviation of `direction` \[rad\].
    pub sigma_direction_rad: f64,
    /// Names of the demonstrations that show this edge.
    pub support: Vec<String>,
    /// Number of supporting demonstrations.
    pub n_support: usize,
    /// Faces adjacent to this edge (ids), from the rests before and after topples.
    pub faces: Vec<String>,
    /// Dynamic models (pendulums), one per resting face.
    pub pendulums: Vec<Pendulum>,
    /// The per-demonstration observations.
    pub observations: Vec<EdgeObservation>,
    /// Standard deviation \[m\] per axis of the scatter of the edges about the faces the
    /// landings show beyond the edges' own σ (a random effect, `tree/landing_edges.rs`),
    /// included in `point_cov` and `sigma_point_m`; absent where no landed face tests the edge.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub between_sigma_m: Option<f64>,
}

impl Edge {
    pub(super) fn new(id: String, obs: EdgeObservation) -> Self {
        let mut e = Self {
            id,
            point: obs.line.point,
            direction: obs.line.direction,
            point_cov: [[0.0; 3]; 3],
            direction_cov: [[0.0; 3]; 3],
            sigma_point_m: 0.0,
            sigma_direction_rad: 0.0,
            support: Vec::new(),
            n_support: 0,
            faces: Vec::new(),
            pendulums: Vec::new(),
            observations: vec![obs],
            between_sigma_m: None,
        };
        e.refit();
        e
    }

    /// The edge as a line.
    pub fn line(&self) -> Line {
        Line {
            point: self.point,
            direction: self.direction,
        }
    }

    /// Recompute the estimate from the observations.
    pub(super) fn refit(&mut self) {
        let first = self.observations[0].line.direction;
        let mut s = LineStats::default();
        for o in &self.observations {
            let w = 1.0 / (o.sigma_point().powi(2) + 1e-12);
            let a = 1.0 / (o.sigma_direction().powi(2) + 1e-12);
            s.add(&o.line.point, &o.line.direction, w, a, 0.0);
        }
        let line = s
            .mean()
            .expect("an edge has at least one observation")
            .aligned_with(&first);
        let (cp, cd) = s.covariances(&line);
        self.point = line.point;
        self.direction = line.direction;
        self.point_cov = rows(&cp);
        self.direction_cov = rows(&cd);
        self.sigma_point_m = (cp.trace() / 2.0).sqrt();
        self.between_sigma_m = None;
        self.sigma_direction_rad = (cd.trace() / 2.0).sqrt();
        self.support = self.observations.iter().map(|o| o.demo.clone()).collect();
        self.support.dedup();
        self.n_support = self.support.len();
    }

    /// Add the scatter `sigma` \[m\] per axis between the edges (normal to the line) to the
    /// point's covariance ([`Edge::between_sigma_m`]); [`Edge::refit`] takes it out.
    pub(super) fn add_between(&mut self, sigma: f64) {
        let u = self.direction;
        let cp = Matrix3::from_fn(|i, j| self.point_cov[i][j])
            + (Matrix3::identity() - u * u.transpose()) * sigma * sigma;
        self.point_cov = rows(&cp);
        self.sigma_point_m = (cp.trace() / 2.0).sqrt();
        self.between_sigma_m = Some(sigma);
    }

    /// χ² (4 dof) of an observation against this edge.
    pub(super) fn match_chi2(&self, o: &EdgeObservation) -> f64 {
        let u = self.direction;
        let p = Matrix3::identity() - u * u.transpose();
        let d = p * (o.line.point - self.point);
        let var_p =
            self.sigma_point_m.powi(2) + o.sigma_point().powi(2) + SYSTEMATIC_POINT_M.powi(2);
        let ang = angle(&u, &o.line.direction);
        let ang = ang.min(std::f64::consts::PI - ang);
        let var_d = self.sigma_direction_rad.powi(2)
            + o.sigma_direction().powi(2)
            + SYSTEMATIC_DIRECTION_RAD.powi(2);
        d.norm_squared() / var_p + ang * ang / var_d
    }
}
