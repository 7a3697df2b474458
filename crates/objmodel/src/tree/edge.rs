//! An edge of the object in the tree: the information-weighted mean line of its
//! per-demonstration observations (see the [tree documentation](super)).

use super::{angle, matrix, rows, Pendulum, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};
use crate::edge::EdgeObservation;
use crate::geometry::{Line, LineStats};
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};
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
    /// The faces whose planes (their offsets as the other demonstrations measure them) `point`,
    /// `direction` and their covariances are conditioned on (`tree/edge_faces.rs`); empty where
    /// the edge is its observations' estimate alone.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub conditioned_on: Vec<String>,
    /// The estimate from the edge's own observations alone, where `conditioned_on` is not
    /// empty. The tree's tests of its features against each other use it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observed: Option<EdgeEstimate>,
}

/// A line estimate with its covariances (as [`Edge`] keeps them).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdgeEstimate {
    /// Point of the line closest to the object-frame origin \[m\].
    pub point: Vector3<f64>,
    /// Unit direction.
    pub direction: Vector3<f64>,
    /// Covariance of `point` \[m²\], rows.
    pub point_cov: [[f64; 3]; 3],
    /// Covariance of `direction` \[rad²\], rows.
    pub direction_cov: [[f64; 3]; 3],
    /// RMS standard deviation of `point` normal to the line \[m\].
    pub sigma_point_m: f64,
    /// RMS standard deviation of `direction` \[rad\].
    pub sigma_direction_rad: f64,
}

impl Edge {
    /// The distance \[m\] and angle \[rad\] from `point` and `direction` within which the
    /// edge lies with probability `p` ([`crate::edge::line_bounds`]).
    pub fn bounds(&self, p: f64) -> (f64, f64) {
        crate::edge::line_bounds(
            &self.direction,
            &matrix(&self.point_cov),
            &matrix(&self.direction_cov),
            p,
        )
    }

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
            conditioned_on: Vec::new(),
            observed: None,
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

    /// The estimate from the edge's own observations (before any conditioning on its faces).
    pub fn own(&self) -> EdgeEstimate {
        self.observed.clone().unwrap_or(EdgeEstimate {
            point: self.point,
            direction: self.direction,
            point_cov: self.point_cov,
            direction_cov: self.direction_cov,
            sigma_point_m: self.sigma_point_m,
            sigma_direction_rad: self.sigma_direction_rad,
        })
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
        let (_, cd) = s.covariances(&line);
        let (point, cp) = fuse_points(&self.observations, &line.direction);
        self.point = point;
        self.direction = line.direction;
        self.point_cov = rows(&cp);
        self.direction_cov = rows(&cd);
        self.sigma_point_m = (cp.trace() / 2.0).sqrt();
        self.between_sigma_m = None;
        self.conditioned_on.clear();
        self.observed = None;
        self.sigma_direction_rad = (cd.trace() / 2.0).sqrt();
        self.support = self.observations.iter().map(|o| o.demo.clone()).collect();
        self.support.dedup();
        self.n_support = self.support.len();
    }

    /// Add the scatter `sigma` \[m\] per axis between the edges (normal to the line) to the
    /// point's covariance ([`Edge::between_sigma_m`]); [`Edge::refit`] takes it out.
    pub(super) fn add_between(&mut self, sigma: f64) {
        let u = self.direction;
        let cp =
            matrix(&self.point_cov) + (Matrix3::identity() - u * u.transpose()) * sigma * sigma;
        self.point_cov = rows(&cp);
        self.sigma_point_m = (cp.trace() / 2.0).sqrt();
        self.between_sigma_m = Some(sigma);
    }

    /// The part of [`Edge::point_cov`] common to its observations, which their number does not
    /// average down: the contact's depth ([`EdgeObservation::common_point_cov`]), their mean
    /// normal to the line.
    pub(super) fn common_point_cov(&self) -> Matrix3<f64> {
        common_part(&self.observations, &self.direction)
    }

    /// χ² (4 dof) of an observation against this edge.
    /// Against the edge's own estimate ([`Edge::own`]).
    pub(super) fn match_chi2(&self, o: &EdgeObservation) -> f64 {
        let own = self.own();
        let u = own.direction;
        let p = Matrix3::identity() - u * u.transpose();
        let d = p * (o.line.point - own.point);
        let var_p =
            own.sigma_point_m.powi(2) + o.sigma_point().powi(2) + SYSTEMATIC_POINT_M.powi(2);
        let ang = angle(&u, &o.line.direction);
        let ang = ang.min(std::f64::consts::PI - ang);
        let var_d = own.sigma_direction_rad.powi(2)
            + o.sigma_direction().powi(2)
            + SYSTEMATIC_DIRECTION_RAD.powi(2);
        d.norm_squared() / var_p + ang * ang / var_d
    }
}

/// The observations' points fused in the plane normal to `u`, with their covariance: the
/// generalised least-squares mean, each point weighted by its own covariance (its `point_cov`
/// less the part common to every observation of the edge: a point the rests fixed along one
/// axis counts along that axis, not along the other); its covariance the inverse of the summed
/// information, widened by the Birge ratio where the points scatter more than their covariances
/// say; and the common part (the contact's depth,
/// [`EdgeObservation::add_contact_depth_var`]), which does not average down, added back as
/// the observations' mean.
fn fuse_points(observations: &[EdgeObservation], u: &Vector3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
    let basis = Matrix3x2::from_columns(&crate::geometry::normal_axes(u));
    // A point is never known better than a micrometre along any axis (an exact constraint
    // would make the information infinite).
    let floor = Matrix2::identity() * 1e-12;
    let (mut info, mut rhs) = (Matrix2::zeros(), Vector2::zeros());
    let weighted: Vec<(Matrix2<f64>, Vector2<f64>)> = observations
        .iter()
        .map(|o| {
            let own = basis.transpose() * (o.point_cov - o.common_point_cov) * basis;
            let w = (own + floor).try_inverse().unwrap_or(floor);
            let x = basis.transpose() * o.line.point;
            info += w;
            rhs += w * x;
            (w, x)
        })
        .collect();
    let n = observations.len().max(1);
    let own_cov = info.try_inverse().unwrap_or(floor);
    let mean = own_cov * rhs;
    let chi2: f64 = weighted
        .iter()
        .map(|(w, x)| (x - mean).dot(&(w * (x - mean))))
        .sum();
    let birge = if n > 1 {
        (chi2 / (2.0 * (n - 1) as f64)).max(1.0)
    } else {
        1.0
    };
    let cov = basis * own_cov * basis.transpose() * birge + common_part(observations, u);
    (basis * mean, (cov + cov.transpose()) * 0.5)
}

/// The mean of the observations' common covariances ([`EdgeObservation::common_point_cov`]),
/// normal to `u`.
fn common_part(observations: &[EdgeObservation], u: &Vector3<f64>) -> Matrix3<f64> {
    let normal_plane = Matrix3::identity() - u * u.transpose();
    let sum: Matrix3<f64> = observations
        .iter()
        .map(|o| normal_plane * o.common_point_cov * normal_plane)
        .sum();
    sum / observations.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::StandardNormal;

    fn observation(
        point: Vector3<f64>,
        own: Matrix3<f64>,
        common: Matrix3<f64>,
    ) -> EdgeObservation {
        EdgeObservation {
            demo: "t".into(),
            line: crate::geometry::Line {
                point,
                direction: Vector3::z(),
            },
            point_cov: own + common,
            direction_cov: Matrix3::identity() * 1e-6,
            paper_line: None,
            frames: 10,
            max_angle: 1.5,
            chi2_per_dof: 1.0,
            common_point_cov: common,
        }
    }

    /// The 95% bounds: the worst axis normal to the line times 2.448 (what lies along the line
    /// does not count), and over 20 000 draws of the covariance they hold at least 95% of the
    /// errors (more, where the other axis is smaller: a bound).
    #[test]
    fn the_bounds_hold_the_errors() {
        let cov = Matrix3::from_diagonal(&Vector3::new(4e-6, 1e-6, 1.0));
        let mut e = fused(vec![observation(Vector3::zeros(), cov, Matrix3::zeros())]);
        e.point_cov = rows(&cov);
        e.direction_cov = rows(&Matrix3::from_diagonal(&Vector3::new(1e-4, 1e-4, 0.0)));
        let (r, a) = e.bounds(0.95);
        let k = (2.0 * 20f64.ln()).sqrt();
        assert!(
            (r - k * 2e-3).abs() < 1e-12 && (a - k * 1e-2).abs() < 1e-12,
            "{r} {a}"
        );
        let mut rng = StdRng::seed_from_u64(4);
        let n = 20_000;
        let within = (0..n)
            .filter(|_| {
                let x: f64 = rng.sample(StandardNormal);
                let y: f64 = rng.sample(StandardNormal);
                (2e-3 * x).hypot(1e-3 * y) <= r
            })
            .count();
        assert!(within as f64 / n as f64 > 0.95, "{within}");
        // Isotropic: exactly 95%, within the sampling's scatter.
        let iso = (0..n)
            .filter(|_| {
                let x: f64 = rng.sample(StandardNormal);
                let y: f64 = rng.sample(StandardNormal);
                (2e-3 * x).hypot(2e-3 * y) <= r
            })
            .count() as f64
            / n as f64;
        assert!((iso - 0.95).abs() < 0.005, "{iso}");
    }

    fn fused(observations: Vec<EdgeObservation>) -> Edge {
        let mut it = observations.into_iter();
        let mut e = Edge::new("e0".into(), it.next().unwrap());
        e.observations.extend(it);
        e.refit();
        e
    }

    /// One edge known along x (the rests measured it there), another along y: the fused point
    /// takes x from the first and y from the second, with the summed information's inverse for
    /// its covariance (analytic; the points agree within their σ, so no Birge widening).
    #[test]
    fn each_observation_counts_along_the_axis_it_measured() {
        let (a, b) = (1e-8, 1e-4);
        let e = fused(vec![
            observation(
                Vector3::new(1e-3, 5e-3, 0.0),
                Matrix3::from_diagonal(&Vector3::new(a, b, 0.0)),
                Matrix3::zeros(),
            ),
            observation(
                Vector3::new(4e-3, 2e-3, 0.0),
                Matrix3::from_diagonal(&Vector3::new(b, a, 0.0)),
                Matrix3::zeros(),
            ),
        ]);
        let (wa, wb) = (1.0 / (a + 1e-12), 1.0 / (b + 1e-12));
        let x = (wa * 1e-3 + wb * 4e-3) / (wa + wb);
        let y = (wb * 5e-3 + wa * 2e-3) / (wa + wb);
        assert!(
            (e.point.x - x).abs() < 1e-12 && (e.point.y - y).abs() < 1e-12,
            "{}",
            e.point
        );
        let var = 1.0 / (wa + wb);
        assert!(
            (e.point_cov[0][0] - var).abs() < 1e-3 * var,
            "{:?}",
            e.point_cov
        );
        assert!(
            (e.point_cov[1][1] - var).abs() < 1e-3 * var,
            "{:?}",
            e.point_cov
        );
    }

    /// Topples about one edge share its contact's depth: an offset along one direction common
    /// to all of them, beside each one's own error. Over 3000 random sets of 2-6 observations
    /// (own covariances random and anisotropic, the common σ 1 mm), the fused point's mean
    /// squared Mahalanobis distance to the truth is 2 (two axes normal to the line): honest.
    /// Counted as independent errors of each observation (no common part), it is far above.
    #[test]
    fn a_common_depth_does_not_average_down() {
        let mut rng = StdRng::seed_from_u64(7);
        let normal = |rng: &mut StdRng| rng.sample::<f64, _>(StandardNormal);
        let (mut honest, mut naive) = (0.0, 0.0);
        let trials = 3000;
        for _ in 0..trials {
            let depth = 1e-3;
            let b = Vector3::new(normal(&mut rng), normal(&mut rng), 0.0).normalize();
            let common = b * b.transpose() * depth * depth;
            let offset = b * depth * normal(&mut rng);
            let n = rng.random_range(2..=6);
            let (mut with, mut without) = (Vec::new(), Vec::new());
            for _ in 0..n {
                let l = nalgebra::Matrix2::from_fn(|_, _| normal(&mut rng) * 5e-4);
                let own2 = l * l.transpose() + nalgebra::Matrix2::identity() * 1e-8;
                let own = Matrix3::new(
                    own2[(0, 0)],
                    own2[(0, 1)],
                    0.0,
                    own2[(1, 0)],
                    own2[(1, 1)],
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                );
                let chol = own2.cholesky().unwrap().l();
                let e2 = chol * nalgebra::Vector2::new(normal(&mut rng), normal(&mut rng));
                let p = offset + Vector3::new(e2.x, e2.y, 0.0);
                with.push(observation(p, own, common));
                without.push(observation(p, own + common, Matrix3::zeros()));
            }
            for (obs, sum) in [(with, &mut honest), (without, &mut naive)] {
                let e = fused(obs);
                let cov = matrix(&e.point_cov);
                let w = cov.pseudo_inverse(1e-18).unwrap();
                *sum += e.point.dot(&(w * e.point));
            }
        }
        let (honest, naive) = (honest / trials as f64, naive / trials as f64);
        eprintln!("mean squared Mahalanobis distance {honest:.3}, counted independent {naive:.3}");
        assert!(
            (honest - 2.0).abs() < 0.15,
            "mean squared Mahalanobis distance {honest:.2}"
        );
        assert!(naive > 2.6, "counted as independent: {naive:.2}");
    }
}
