//! The vertical that rests turn about: a check of the gravity given against the demonstrations.
//!
//! An object that rests twice on the same face of one level support is turned, from the one
//! rest to the other, about the support's normal: the relative rotation
//! `world_from_object₂ · world_from_object₁⁻¹` has the vertical as its axis, whatever the angle.
//! Rests on different faces are related by rotations about other axes, which scatter. So over
//! the rests of many demonstrations (tosses landing at any heading, boxes pushed and turned on
//! a table) the axes of the pairs' relative rotations pile up at the vertical of the poses'
//! frame, and nowhere else. Nothing in this uses gravity: it measures the vertical the
//! demonstrations show ([`shown`]), and compares it with the one given.
//!
//! Why it is needed: a rest's face is taught from gravity's direction in the object frame
//! ("down"). Given the wrong vertical (a motion-capture frame with y up, learnt with the
//! default z up), downs of rests on different faces can agree by the box's symmetry, and the
//! faces they teach are off the object (tracked with y up and learnt with z up, MuJoCo tosses
//! of three seeds taught 14 of 15 features off the box).
//!
//! Only pairs turned by a *generic* angle count as evidence: at least [`GENERIC_MARGIN_RAD`]
//! from every multiple of a quarter turn. A box's faces are a quarter or half turn apart, so
//! under a wrong vertical its rests agree by coincidence at those angles (and a pair at no
//! angle agrees with any vertical); rests at any heading turn by every angle. A pair's axis is
//! known to `√(σ₁² + σ₂²) / (2 sin(θ/2))` per axis for rests known to `σ₁`, `σ₂` per axis and
//! turned by `θ` (the axis of a rotation by `θ` moves by `δ / (2 sin(θ/2))` for a perturbation
//! `δ` across it).

use nalgebra::{UnitQuaternion, Vector3};

/// How far \[rad\] a pair's angle must be from every multiple of a quarter turn to count (10°).
pub const GENERIC_MARGIN_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Fewest generic pairs about one axis, from at least [`MIN_RESTS`] rests, for the rests to
/// show a vertical at all.
pub const MIN_PAIRS: usize = 6;
/// Fewest rests among those pairs.
pub const MIN_RESTS: usize = 4;
/// Fewest distinct angles (more than [`GENERIC_MARGIN_RAD`] apart) among those pairs: rests at
/// any heading turn by every angle, while an object rolled over parallel edges at one heading
/// (a prism's faces a third of a turn apart) turns about the edges' direction by multiples of
/// one angle only, and shows no vertical.
pub const MIN_ANGLES: usize = 3;
/// Most rests compared (evenly chosen beyond): the pairs grow as the square.
pub const MAX_RESTS: usize = 240;
/// Per-axis standard deviation \[rad\] of a rest's orientation below which no rest is taken to
/// be known (0.01°): a contact settles at this scale however precise the tracker.
pub const MIN_REST_SIGMA_RAD: f64 = 1.745_329_251_994_33e-4;

/// A rest in the frame the poses are given in.
#[derive(Clone, Copy, Debug)]
pub struct Rest {
    /// The object's orientation over the rest, `world_from_object`.
    pub rotation: UnitQuaternion<f64>,
    /// Standard deviation \[rad\] per axis of that orientation.
    pub sigma_rad: f64,
}

/// The vertical the rests show, and whether it contradicts the one given.
#[derive(Clone, Debug, PartialEq)]
pub struct Vertical {
    /// The axis the rests turn about (unit; its sign is not determined by the rests: it is
    /// the one nearer the given up).
    pub axis: Vector3<f64>,
    /// Its angle \[rad\] from the given up.
    pub angle_rad: f64,
    /// Standard deviation \[rad\] per axis of `axis` from the pairs.
    pub sigma_rad: f64,
    /// Generic pairs turned about it, and the rests among them.
    pub pairs: usize,
    /// Rests among those pairs.
    pub rests: usize,
    /// Generic pairs turned about the given up (within their σ and the support's level).
    pub pairs_about_given: usize,
    /// Rests compared.
    pub compared: usize,
    /// Whether it contradicts the given up (see [`shown`]).
    pub contradicts: bool,
}

/// A generic pair's relative rotation: its axis (unit, towards `up`), the σ \[rad\] per axis of
/// that axis, and the two rests.
struct Pair {
    axis: Vector3<f64>,
    sigma: f64,
    angle: f64,
    rests: (usize, usize),
}

/// The generic pairs of `rests`.
fn pairs(rests: &[Rest], up: &Vector3<f64>) -> Vec<Pair> {
    let quarter = std::f64::consts::FRAC_PI_2;
    let mut out = Vec::new();
    for (i, a) in rests.iter().enumerate() {
        for (j, b) in rests.iter().enumerate().skip(i + 1) {
            let Some((axis, angle)) = (b.rotation * a.rotation.inverse()).axis_angle() else {
                continue;
            };
            let off = angle - (angle / quarter).round() * quarter;
            if off.abs() < GENERIC_MARGIN_RAD {
                continue;
            }
            let sa = a.sigma_rad.max(MIN_REST_SIGMA_RAD);
            let sb = b.sigma_rad.max(MIN_REST_SIGMA_RAD);
            let axis = axis.into_inner();
            out.push(Pair {
                axis: if axis.dot(up) < 0.0 { -axis } else { axis },
                sigma: (sa * sa + sb * sb).sqrt() / (2.0 * (angle / 2.0).sin()),
                angle,
                rests: (i, j),
            });
        }
    }
    out
}

/// The squared angle between the lines along unit `a` and unit `b`.
fn angle2(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let s = a.cross(b).norm();
    s.atan2(a.dot(b).abs()).powi(2)
}

/// The pairs turned about `v` (unit): their axis within the χ²₂ quantile `q` of it, with `extra`
/// \[rad\] per axis allowed beside each pair's σ.
fn about<'p>(pairs: &'p [Pair], v: &Vector3<f64>, q: f64, extra: f64) -> Vec<&'p Pair> {
    pairs
        .iter()
        .filter(|p| angle2(&p.axis, v) <= q * (p.sigma * p.sigma + extra * extra))
        .collect()
}

/// Rests among `pairs`.
fn rests_in(pairs: &[&Pair]) -> usize {
    let mut r: Vec<usize> = pairs.iter().flat_map(|p| [p.rests.0, p.rests.1]).collect();
    r.sort_unstable();
    r.dedup();
    r.len()
}

/// Distinct angles among `pairs`: the most of their angles that are pairwise more than
/// [`GENERIC_MARGIN_RAD`] apart (taken greedily from the smallest, which is the most).
fn distinct_angles(pairs: &[&Pair]) -> usize {
    let mut a: Vec<f64> = pairs.iter().map(|p| p.angle).collect();
    a.sort_by(f64::total_cmp);
    let mut last = f64::NEG_INFINITY;
    let mut n = 0;
    for x in a {
        if x - last > GENERIC_MARGIN_RAD {
            n += 1;
            last = x;
        }
    }
    n
}

/// The weighted mean axis of `pairs` (unit, each pair's axis taken with the sign nearer
/// `reference`) and its σ per axis, widened by the pairs' scatter beyond their σ (the Birge
/// ratio) and by the rests they share: `n` pairs among `m` rests hold `m − 1` independent
/// measurements (a spanning tree of the pairs; each rest's error enters all its pairs), so
/// the σ of the pairs' mean is widened by `√(n / (m − 1))`, the design effect of the pairs
/// counted as independent.
fn mean_axis(pairs: &[&Pair], reference: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let w = |p: &Pair| 1.0 / (p.sigma * p.sigma);
    let signed = |p: &Pair| p.axis * p.axis.dot(reference).signum();
    let sum: Vector3<f64> = pairs.iter().map(|p| signed(p) * w(p)).sum();
    let v = sum.normalize();
    let wsum: f64 = pairs.iter().map(|p| w(p)).sum();
    let chi2: f64 = pairs.iter().map(|p| angle2(&p.axis, &v) * w(p)).sum();
    let dof = (2 * pairs.len()).saturating_sub(2).max(1) as f64;
    let birge = (chi2 / dof).max(1.0);
    let shared = pairs.len() as f64 / (rests_in(pairs).max(2) - 1) as f64;
    (v, (birge * shared.max(1.0) / wsum).sqrt())
}

/// The vertical the rests show, if they show one: the axis most generic pairs turn about (at
/// least [`MIN_PAIRS`] of them, from [`MIN_RESTS`] rests, by [`MIN_ANGLES`] distinct angles).
/// It contradicts `up` (unit, against gravity) when its angle from `up` is beyond the χ²₂ test
/// at `alpha` with its own σ and the support's level (`level_sigma_rad` per axis: tables are
/// level to about that), and fewer than half as many pairs turn about `up` itself. `None`
/// when the rests show no vertical (too few rests, or all at one heading).
pub fn shown(
    rests: &[Rest],
    up: &Vector3<f64>,
    alpha: f64,
    level_sigma_rad: f64,
) -> Option<Vertical> {
    let chosen: Vec<Rest> = if rests.len() > MAX_RESTS {
        (0..MAX_RESTS)
            .map(|k| rests[k * rests.len() / MAX_RESTS])
            .collect()
    } else {
        rests.to_vec()
    };
    let pairs = pairs(&chosen, up);
    if pairs.len() < MIN_PAIRS {
        return None;
    }
    let q = crate::stats::chi2_threshold(2.0, alpha);
    // Each pair's axis as a candidate (at most a few hundred of them, evenly chosen).
    let step = (pairs.len() / 400).max(1);
    let best = pairs
        .iter()
        .step_by(step)
        .map(|p| about(&pairs, &p.axis, q, 0.0))
        .max_by_key(|inliers| inliers.len())?;
    let shows = |p: &[&Pair]| {
        p.len() >= MIN_PAIRS && rests_in(p) >= MIN_RESTS && distinct_angles(p) >= MIN_ANGLES
    };
    if !shows(&best) {
        return None;
    }
    let (v0, _) = mean_axis(&best, &best[0].axis);
    let inliers = about(&pairs, &v0, q, 0.0);
    if !shows(&inliers) {
        return None;
    }
    let (axis, sigma) = mean_axis(&inliers, &v0);
    let angle2_up = angle2(&axis, up);
    let given = about(&pairs, up, q, level_sigma_rad).len();
    let contradicts = angle2_up > q * (sigma * sigma + level_sigma_rad * level_sigma_rad)
        && 2 * given < inliers.len();
    Some(Vertical {
        axis: if axis.dot(up) < 0.0 { -axis } else { axis },
        angle_rad: angle2_up.sqrt(),
        sigma_rad: sigma,
        pairs: inliers.len(),
        rests: rests_in(&inliers),
        pairs_about_given: given,
        compared: chosen.len(),
        contradicts,
    })
}

#[cfg(test)]
mod tests;
