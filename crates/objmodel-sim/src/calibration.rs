//! Are the learner's sigmas honest? Every uncertainty the tree reports, checked against the
//! simulator's ground truth: for each learnt quantity, its error divided by its own sigma
//! (a Mahalanobis distance where the quantity has more than one dimension), tabulated per
//! noise level.
//!
//! An honest sigma gives errors whose normalised size follows the χ distribution of the
//! quantity's dimension: a median of 0.674 for a 1-D quantity (φ, a face offset), 1.177 for a
//! 2-D one (an edge's position normal to it, its direction, a face normal), 1.538 for 3-D (the
//! centre of mass), and almost never above 5 (the probability is below 10⁻⁵ in 2-D). A median
//! far above says the sigma leaves something out; far below, that it is pessimistic.
//!
//! Each learnt feature is compared with the nearest true feature of its box (no gate: a
//! feature far from every true one shows as a large error, as it should). Two sets:
//! * `demo`: each demonstration learnt alone (its own tree);
//! * `fused`: every demonstration of a box at one noise level learnt together (the tree a user
//!   gets), which also gives the centre of mass.

use crate::truth::{BoxFeatures, Truth};
use nalgebra::{Matrix3, Vector3};
use objmodel::classify::Config;
use objmodel::learn::Learner;
use objmodel::observation::Observation;
use objmodel::tree::{Edge, Face, Tree};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// A quantity whose sigma is checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// A pendulum's φ (1-D).
    Phi,
    /// φ as the paper measures it, the palm's tilt at the onset of an instrumented topple
    /// (1-D; per demonstration only: the tree fuses it into `Phi` with the fits).
    PhiOnset,
    /// A pendulum's φ that the tree itself reports contradicted by the other pendulums (left
    /// out of its CoM: `Pendulum::com_conflict`), apart: the tree does not vouch for its σ.
    PhiContradicted,
    /// An edge's position normal to it (2-D).
    EdgePoint,
    /// An edge's direction (2-D).
    EdgeDirection,
    /// A face's normal, with slides among its evidence (2-D). Its σ holds the support's
    /// level (1°, `face::SUPPORT_LEVEL_SIGMA_RAD`, a prior on the slide plane): a prior about
    /// the user's table that the simulator's level one does not need, so in simulation the σ
    /// is larger than the errors by design.
    FaceNormal,
    /// A face's normal seen only in rests (2-D): the direction of gravity, whose σ is the
    /// support's level alone.
    RestFaceNormal,
    /// A face's offset (1-D).
    FaceOffset,
    /// The centre of mass (3-D).
    Com,
}

impl Quantity {
    /// Degrees of freedom of the error.
    pub fn dof(self) -> usize {
        match self {
            Quantity::Phi
            | Quantity::PhiOnset
            | Quantity::PhiContradicted
            | Quantity::FaceOffset => 1,
            Quantity::Com => 3,
            _ => 2,
        }
    }

    /// The median of `|error| / sigma` when the sigma is honest (of the χ distribution).
    pub fn honest_median(self) -> f64 {
        match self.dof() {
            1 => 0.674_489_750_196_081_7,
            2 => 1.177_410_022_515_474_6,
            _ => 1.538_172_254_455_584_3,
        }
    }

    /// Its name in the table.
    pub fn as_str(self) -> &'static str {
        match self {
            Quantity::Phi => "phi",
            Quantity::PhiOnset => "phi at the onset (the paper's)",
            Quantity::PhiContradicted => "phi (contradicted: left out)",
            Quantity::EdgePoint => "edge position",
            Quantity::EdgeDirection => "edge direction",
            Quantity::FaceNormal => "face normal (slides)",
            Quantity::RestFaceNormal => "face normal (rests only)",
            Quantity::FaceOffset => "face offset",
            Quantity::Com => "centre of mass",
        }
    }
}

/// One learnt value against its truth.
#[derive(Clone, Debug, Serialize)]
pub struct Sample {
    /// What.
    pub quantity: Quantity,
    /// `demo` (one demonstration learnt alone) or `fused` (a box's demonstrations together).
    pub set: &'static str,
    /// Noise preset.
    pub noise: String,
    /// The demonstration (demo set) or the box (fused set).
    pub source: String,
    /// The size of the error \[m or rad\].
    pub error: f64,
    /// The size of the error in units of its covariance (Mahalanobis distance); infinite when
    /// the reported sigma is zero and the error is not.
    pub z: f64,
}

/// `a` with its sign turned toward `b`.
fn aligned(a: &Vector3<f64>, b: &Vector3<f64>) -> Vector3<f64> {
    if a.dot(b) < 0.0 {
        -a
    } else {
        *a
    }
}

/// Two unit vectors spanning the plane normal to `d`.
fn normal_basis(d: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let a = if d.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = d.cross(&a).normalize();
    (e1, d.cross(&e1))
}

/// The Mahalanobis distance of the error `e`, restricted to the plane normal to `d`, under the
/// covariance `cov` (also restricted to that plane).
fn planar_z(e: &Vector3<f64>, cov: &Matrix3<f64>, d: &Vector3<f64>) -> f64 {
    let (e1, e2) = normal_basis(d);
    let x = nalgebra::Vector2::new(e.dot(&e1), e.dot(&e2));
    let c = nalgebra::Matrix2::new(
        e1.dot(&(cov * e1)),
        e1.dot(&(cov * e2)),
        e2.dot(&(cov * e1)),
        e2.dot(&(cov * e2)),
    );
    mahalanobis2(&x, &c)
}

fn mahalanobis2(x: &nalgebra::Vector2<f64>, c: &nalgebra::Matrix2<f64>) -> f64 {
    if x.norm() == 0.0 {
        return 0.0;
    }
    match c.try_inverse() {
        Some(inv) if c.determinant() > 0.0 => x.dot(&(inv * x)).max(0.0).sqrt(),
        _ => f64::INFINITY,
    }
}

fn z1(error: f64, sigma: f64) -> f64 {
    if error == 0.0 {
        0.0
    } else if sigma > 0.0 {
        error.abs() / sigma
    } else {
        f64::INFINITY
    }
}

fn v(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn m(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

/// The true edge nearest to `e` (direction first, then position), as (point, direction).
fn nearest_edge(e: &Edge, truth: &BoxFeatures) -> Option<(Vector3<f64>, Vector3<f64>)> {
    truth
        .edges
        .iter()
        .map(|t| (v(t.line.point), v(t.line.direction)))
        .min_by(|a, b| edge_distance(e, a).total_cmp(&edge_distance(e, b)))
}

/// A distance between a learnt edge and a true line: the angle \[rad\] times 0.1 m plus the
/// learnt point's distance from the line.
fn edge_distance(e: &Edge, (p, d): &(Vector3<f64>, Vector3<f64>)) -> f64 {
    let angle = e.direction.cross(d).norm().atan2(e.direction.dot(d).abs());
    let off = e.point - p;
    0.1 * angle + (off - d * d.dot(&off)).norm()
}

fn edge_samples(e: &Edge, truth: &BoxFeatures, out: &mut Vec<(Quantity, f64, f64)>) {
    let Some((tp, td)) = nearest_edge(e, truth) else {
        return;
    };
    // Position: the learnt point's offset from the true line, normal to the learnt line.
    let off = e.point - tp;
    let perp = off - td * td.dot(&off);
    out.push((
        Quantity::EdgePoint,
        perp.norm(),
        planar_z(&perp, &m(&e.point_cov), &e.direction),
    ));
    let dd = aligned(&td, &e.direction) - e.direction;
    let angle = e
        .direction
        .cross(&td)
        .norm()
        .atan2(e.direction.dot(&td).abs());
    out.push((
        Quantity::EdgeDirection,
        angle,
        planar_z(&dd, &m(&e.direction_cov), &e.direction),
    ));
}

fn face_samples(f: &Face, truth: &BoxFeatures, out: &mut Vec<(Quantity, f64, f64)>) {
    let angle_to = |n: &Vector3<f64>| {
        if f.sign_known {
            f.normal.angle(n)
        } else {
            f.normal.angle(n).min(f.normal.angle(&-n))
        }
    };
    let Some(t) = truth
        .faces
        .iter()
        .min_by(|a, b| angle_to(&v(a.normal)).total_cmp(&angle_to(&v(b.normal))))
    else {
        return;
    };
    let angle = angle_to(&v(t.normal));
    // sigma_normal_rad is the RMS per axis of the normal's 2-D tangent error.
    let quantity = if f.evidence.slide > 0 {
        Quantity::FaceNormal
    } else {
        Quantity::RestFaceNormal
    };
    out.push((quantity, angle, z1(angle, f.sigma_normal_rad)));
    let unlocated = f.offset_unlocated.as_ref().map(|u| (u.offset, u.sigma_m));
    if let Some((offset, sigma)) = f.offset.zip(f.offset_sigma_m).or(unlocated) {
        // The same plane with the normal's sign as learnt.
        let true_offset = if f.normal.dot(&v(t.normal)) < 0.0 {
            -t.offset
        } else {
            t.offset
        };
        let err = offset - true_offset;
        out.push((Quantity::FaceOffset, err.abs(), z1(err, sigma)));
    }
}

/// φ of the true box for a learnt pendulum: the CoM's angle from the vertical through the
/// nearest true edge, resting on the true face nearest the learnt resting face.
pub fn true_phi(edge: &Edge, rest: &Vector3<f64>, truth: &Truth) -> Option<f64> {
    let (tp, td) = nearest_edge(edge, &truth.features)?;
    let n = truth
        .features
        .faces
        .iter()
        .map(|f| v(f.normal))
        .min_by(|a, b| a.angle(rest).total_cmp(&b.angle(rest)))?;
    let c = v(truth.com) - tp;
    let r = c - td * td.dot(&c);
    Some(r.cross(&n).norm().atan2(-r.dot(&n)))
}

/// The samples of `tree`; with `per_demo`, also each pendulum observation's φ at the onset.
fn tree_samples(tree: &Tree, truth: &Truth, per_demo: bool, out: &mut Vec<(Quantity, f64, f64)>) {
    // The estimates withheld as too loose to be taught are estimates still, with their σ.
    for e in tree.edge_estimates() {
        edge_samples(e, &truth.features, out);
        for p in &e.pendulums {
            if per_demo {
                for o in &p.observations {
                    let (Some(phi), Some(sigma)) = (o.phi_onset, o.phi_onset_sigma) else {
                        continue;
                    };
                    if let Some(t) = true_phi(e, &p.resting_face_normal, truth) {
                        out.push((Quantity::PhiOnset, (phi - t).abs(), z1(phi - t, sigma)));
                    }
                }
            }
            let (Some(phi), Some(sigma)) = (p.phi, p.phi_sigma) else {
                continue;
            };
            if let Some(t) = true_phi(e, &p.resting_face_normal, truth) {
                let q = if p.com_conflict.is_some() {
                    Quantity::PhiContradicted
                } else {
                    Quantity::Phi
                };
                out.push((q, (phi - t).abs(), z1(phi - t, sigma)));
            }
        }
    }
    for f in &tree.faces {
        face_samples(f, &truth.features, out);
    }
    if let Some(com) = &tree.com {
        let err = com.point - v(truth.com);
        let z = com_z(com, &err);
        out.push((Quantity::Com, err.norm(), z));
    }
}

/// The centre of mass's error in units of its covariance (the 3-D Mahalanobis distance);
/// infinite without a usable covariance.
fn com_z(com: &objmodel::tree::CentreOfMass, err: &Vector3<f64>) -> f64 {
    if err.norm() == 0.0 {
        return 0.0;
    }
    com.standardised_error(&(com.point - err))
        .map_or(f64::INFINITY, |z| z.norm())
}

/// Every sample of the dataset in `dir` (with `manifest.json`).
pub fn samples(dir: &Path, config: &Config) -> anyhow::Result<Vec<Sample>> {
    let manifest = crate::eval::read_manifest(dir)?;
    let learner = Learner::new(*config);
    let mut out = Vec::new();
    let mut groups: BTreeMap<(String, String), (Vec<Observation>, Truth)> = BTreeMap::new();
    for entry in &manifest.demos {
        let (truth, observation) = crate::eval::observe(dir, &learner, entry)?;
        let mut tree = Tree::default();
        tree.add(&observation);
        let mut found = Vec::new();
        tree_samples(&tree, &truth, true, &mut found);
        out.extend(found.into_iter().map(|(quantity, error, z)| Sample {
            quantity,
            set: "demo",
            noise: entry.noise.clone(),
            source: entry.name.clone(),
            error,
            z,
        }));
        groups
            .entry((entry.r#box.clone(), entry.noise.clone()))
            .or_insert_with(|| (Vec::new(), truth))
            .0
            .push(observation);
    }
    for ((name, noise), (observations, truth)) in groups {
        let mut tree = Tree::default();
        for o in &observations {
            tree.add(o);
        }
        let mut found = Vec::new();
        tree_samples(&tree, &truth, false, &mut found);
        out.extend(found.into_iter().map(|(quantity, error, z)| Sample {
            quantity,
            set: "fused",
            noise: noise.clone(),
            source: name.clone(),
            error,
            z,
        }));
    }
    Ok(out)
}

/// One row of the calibration table.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// `demo` or `fused`.
    pub set: &'static str,
    /// What.
    pub quantity: Quantity,
    /// Noise preset.
    pub noise: String,
    /// Samples.
    pub n: usize,
    /// Median of `|error| / sigma`.
    pub median_z: f64,
    /// What an honest sigma gives.
    pub honest_median_z: f64,
    /// Median `|error|` \[m or rad\].
    pub median_error: f64,
    /// Samples with `|error| / sigma` above 5.
    pub above_5: usize,
    /// The largest `|error| / sigma`, and where.
    pub max_z: f64,
    /// See `max_z`.
    pub worst: String,
}

/// The calibration table: one row per set, quantity and noise level.
pub fn table(samples: &[Sample]) -> Vec<Row> {
    let mut groups: BTreeMap<(&str, Quantity, &str), Vec<&Sample>> = BTreeMap::new();
    for s in samples {
        groups
            .entry((s.set, s.quantity, s.noise.as_str()))
            .or_default()
            .push(s);
    }
    groups
        .into_iter()
        .map(|((set, quantity, noise), g)| {
            let mut z: Vec<f64> = g.iter().map(|s| s.z).collect();
            let mut e: Vec<f64> = g.iter().map(|s| s.error).collect();
            let worst = g
                .iter()
                .max_by(|a, b| a.z.total_cmp(&b.z))
                .expect("a group has a sample");
            Row {
                set,
                quantity,
                noise: noise.to_string(),
                n: g.len(),
                median_z: objmodel::stats::median(&mut z).unwrap_or(f64::NAN),
                honest_median_z: quantity.honest_median(),
                median_error: objmodel::stats::median(&mut e).unwrap_or(f64::NAN),
                above_5: g.iter().filter(|s| s.z > 5.0).count(),
                max_z: worst.z,
                worst: worst.source.clone(),
            }
        })
        .collect()
}

/// The table as Markdown: errors in mm or degrees.
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| set | quantity | noise | n | median \\|err\\|/σ | honest | median \\|err\\| | > 5σ | max \\|err\\|/σ (where) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let (scale, unit) = match r.quantity {
            Quantity::EdgePoint | Quantity::FaceOffset | Quantity::Com => (1e3, "mm"),
            _ => (180.0 / std::f64::consts::PI, "°"),
        };
        s += &format!(
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.2} {} | {} | {:.1} ({}) |\n",
            r.set,
            r.quantity.as_str(),
            r.noise,
            r.n,
            r.median_z,
            r.honest_median_z,
            r.median_error * scale,
            unit,
            r.above_5,
            r.max_z,
            r.worst
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_distr::StandardNormal;

    /// Errors drawn from the covariance they are judged by have the χ medians; errors twice as
    /// large do not.
    #[test]
    fn planar_errors_from_their_own_covariance_have_the_chi_median() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let d = Vector3::new(0.3, -0.5, 0.8).normalize();
        let (e1, e2) = normal_basis(&d);
        let cov = (e1 * e1.transpose()) * 4e-6
            + (e2 * e2.transpose()) * 1e-6
            + (e1 * e2.transpose() + e2 * e1.transpose()) * 1e-6;
        let chol = nalgebra::Matrix2::new(4e-6, 1e-6, 1e-6, 1e-6)
            .cholesky()
            .unwrap();
        let draw = |rng: &mut rand::rngs::StdRng, k: f64| {
            let x = chol.l()
                * nalgebra::Vector2::new(rng.sample(StandardNormal), rng.sample(StandardNormal));
            // A component along d is not part of the planar error.
            (e1 * x[0] + e2 * x[1]) * k + d * rng.random_range(-1.0..1.0)
        };
        for (k, lo, hi) in [(1.0, 1.12, 1.24), (2.0, 2.2, 2.5)] {
            let mut z: Vec<f64> = (0..4000)
                .map(|_| planar_z(&draw(&mut rng, k), &cov, &d))
                .collect();
            let med = objmodel::stats::median(&mut z).unwrap();
            assert!(med > lo && med < hi, "k {k}: median {med}");
        }
    }

    #[test]
    fn a_zero_sigma_with_an_error_is_infinitely_far() {
        assert_eq!(z1(1e-3, 0.0), f64::INFINITY);
        assert_eq!(z1(0.0, 0.0), 0.0);
        assert_eq!(
            planar_z(&Vector3::x(), &Matrix3::zeros(), &Vector3::z()),
            f64::INFINITY
        );
    }
}
