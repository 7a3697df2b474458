use super::*;
use crate::tree::com_from_planes;
use crate::tree::MATCH_ALPHA;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use rand::{rngs::StdRng, Rng, SeedableRng};
use rand_distr::StandardNormal;

/// Uncertainties of the synthetic pendulums: φ, edge point (per axis normal to the edge),
/// edge direction and face normal (per axis).
#[derive(Clone, Copy)]
struct Sigmas {
    phi: f64,
    point: f64,
    axis: f64,
    normal: f64,
}

/// A unit vector turned by a random small rotation of `sigma` per axis normal to it.
fn jitter(v: &Vector3<f64>, sigma: f64, rng: &mut StdRng) -> Vector3<f64> {
    let w: Vector3<f64> = Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * sigma);
    let w = w - v * v.dot(&w);
    (UnitQuaternion::from_scaled_axis(w) * v).normalize()
}

/// The pendulums of a box of half extents `h` turned by `rot`, with its CoM at `com` (object
/// frame), over the edges `(face axis, face sign, edge side axis, side sign)`, observed with
/// the noise `s` (`rng`), each plane carrying the sigmas it was observed with.
fn planes(
    h: &Vector3<f64>,
    rot: &UnitQuaternion<f64>,
    com: &Vector3<f64>,
    edges: &[(usize, f64, usize, f64)],
    s: Sigmas,
    rng: &mut StdRng,
) -> Vec<ComPlane> {
    let mut out = Vec::new();
    for &(k, sk, j, sj) in edges {
        let n = rot * Vector3::ith(k, sk);
        let side = rot * Vector3::ith(j, sj);
        let p = n * h[k] + side * h[j];
        let axis = side.cross(&n);
        let r = com - p;
        let r = r - axis * axis.dot(&r);
        let phi = r.dot(&axis.cross(&n)).atan2(-r.dot(&n));
        let perp = Matrix3::identity() - axis * axis.transpose();
        let noise_p: Vector3<f64> =
            Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * s.point);
        out.push(ComPlane {
            phi: phi + rng.sample::<f64, _>(StandardNormal) * s.phi,
            phi_sigma: s.phi,
            point: p + perp * noise_p,
            point_cov: perp * s.point * s.point,
            axis: jitter(&axis, s.axis, rng),
            axis_cov: perp * s.axis * s.axis,
            normal: jitter(&n, s.normal, rng),
            normal_sigma: s.normal,
        });
    }
    out
}

/// Bottom edges of two faces and side edges: five planes of three directions.
const EDGES: [(usize, f64, usize, f64); 5] = [
    (2, -1.0, 0, 1.0),
    (2, -1.0, 1, -1.0),
    (0, 1.0, 1, 1.0),
    (2, -1.0, 0, -1.0),
    (1, -1.0, 2, 1.0),
];

fn random_box(rng: &mut StdRng) -> (Vector3<f64>, UnitQuaternion<f64>, Vector3<f64>) {
    let h = Vector3::from_fn(|_, _| rng.random_range(0.03..0.1));
    let rot = UnitQuaternion::from_euler_angles(
        rng.random_range(-3.0..3.0),
        rng.random_range(-3.0..3.0),
        rng.random_range(-3.0..3.0),
    );
    let com = rot * h.component_mul(&Vector3::from_fn(|_, _| rng.random_range(-0.3..0.3)));
    (h, rot, com)
}

/// Exact pendulums give the CoM exactly, with any number of planes from three.
#[test]
fn exact_pendulums_give_the_centre_of_mass() {
    let mut rng = StdRng::seed_from_u64(1);
    let zero = Sigmas {
        phi: 0.0,
        point: 0.0,
        axis: 0.0,
        normal: 0.0,
    };
    for n in 3..=5 {
        let (h, rot, com) = random_box(&mut rng);
        let p = planes(&h, &rot, &com, &EDGES[..n], zero, &mut rng);
        let c = com_from_planes(&p).expect("a point");
        assert!((c.point - com).norm() < 1e-12, "{n}: {} vs {com}", c.point);
    }
}

/// The property that makes the covariance honest: with pendulums observed with known noise,
/// the CoM's error along each eigen-axis of its covariance, in its sigmas, is standard normal
/// (median |z| 0.674, none beyond 5), for three planes (no χ² to lean on) and for five.
#[test]
fn the_covariance_matches_the_error_distribution() {
    let s = Sigmas {
        phi: 0.01,
        point: 1e-3,
        axis: 0.01,
        normal: 0.01,
    };
    for n in [3, 5] {
        let mut rng = StdRng::seed_from_u64(7 + n as u64);
        let mut z = Vec::new();
        for _ in 0..1500 {
            let (h, rot, com) = random_box(&mut rng);
            let p = planes(&h, &rot, &com, &EDGES[..n], s, &mut rng);
            let c = com_from_planes(&p).expect("a point");
            assert!(c.sigma_m.unwrap() > 0.0);
            z.extend(c.standardised_error(&com).unwrap().iter().map(|x| x.abs()));
        }
        z.sort_by(f64::total_cmp);
        let median = z[z.len() / 2];
        let beyond2 = z.iter().filter(|x| **x > 2.0).count() as f64 / z.len() as f64;
        // With five planes the covariance is inflated by χ²/dof when above 1: slightly
        // conservative, never over-confident.
        let lo = if n == 3 { 0.62 } else { 0.55 };
        assert!(median > lo && median < 0.73, "{n} planes: median {median}");
        assert!(beyond2 < 0.07, "{n} planes: {beyond2} beyond 2 sigma");
        assert!(
            z.last().unwrap() < &5.0,
            "{n} planes: max {}",
            z.last().unwrap()
        );
    }
}

/// Sigmas understated three times: with more planes than three, the χ² says so and the
/// covariance grows with it, so that the errors stay within their (inflated) sigmas.
#[test]
fn understated_sigmas_are_inflated_by_the_chi2() {
    let true_s = Sigmas {
        phi: 0.03,
        point: 3e-3,
        axis: 0.03,
        normal: 0.03,
    };
    let mut rng = StdRng::seed_from_u64(3);
    let (mut chi2, mut z) = (Vec::new(), Vec::new());
    for _ in 0..400 {
        let (h, rot, com) = random_box(&mut rng);
        let mut p = planes(&h, &rot, &com, &EDGES, true_s, &mut rng);
        for q in &mut p {
            q.phi_sigma /= 3.0;
            q.point_cov /= 9.0;
            q.axis_cov /= 9.0;
            q.normal_sigma /= 3.0;
        }
        let c = com_from_planes(&p).unwrap();
        chi2.push(c.chi2_per_dof.unwrap());
        z.extend(c.standardised_error(&com).unwrap().iter().map(|x| x.abs()));
    }
    let mean_chi2 = chi2.iter().sum::<f64>() / chi2.len() as f64;
    assert!(mean_chi2 > 6.0 && mean_chi2 < 12.0, "{mean_chi2}");
    z.sort_by(f64::total_cmp);
    // Two degrees of freedom make χ² a noisy scale: wider than a normal, but not 3x.
    assert!(z[z.len() / 2] < 1.2, "median {}", z[z.len() / 2]);
}

/// Planes along one line do not fix a point, whatever their weights.
#[test]
fn planes_through_one_line_fix_no_point() {
    let mut rng = StdRng::seed_from_u64(2);
    let zero = Sigmas {
        phi: 0.01,
        point: 1e-3,
        axis: 0.0,
        normal: 0.0,
    };
    let (h, rot, com) = random_box(&mut rng);
    // Three edges along the box's y axis.
    let edges = [(2, -1.0, 0, 1.0), (2, -1.0, 0, -1.0), (0, 1.0, 2, 1.0)];
    assert!(com_from_planes(&planes(&h, &rot, &com, &edges, zero, &mut rng)).is_none());
}

/// Pendulums known well: 0.3°, 0.3 mm.
const PRECISE: Sigmas = Sigmas {
    phi: 0.005,
    point: 3e-4,
    axis: 0.005,
    normal: 0.005,
};

/// The flights' point as the pooling gives it: `point` with covariance `sigma² I`.
fn flights_at(point: Vector3<f64>, sigma: f64) -> crate::shared_com::SharedCom {
    crate::shared_com::SharedCom {
        point,
        covariance: Matrix3::identity() * sigma * sigma,
        flights: 12,
        flights_seen: 15,
        demonstrations: 9,
        gravity_error: Vector3::zeros(),
    }
}

/// With the flights' point, any number of pendulums gives a CoM (none, one, two: too few
/// alone), and the covariance stays honest: the error along each eigen-axis, in its sigmas,
/// has median |z| near 0.674 and none beyond 5, for points known better and worse than the
/// planes.
#[test]
fn the_flights_point_with_any_pendulums_gives_an_honest_centre_of_mass() {
    let s = Sigmas {
        phi: 0.01,
        point: 1e-3,
        axis: 0.01,
        normal: 0.01,
    };
    for (n, sigma_f) in [(0, 1e-3), (1, 1e-3), (2, 3e-3), (3, 0.3e-3), (5, 2e-3)] {
        let mut rng = StdRng::seed_from_u64(40 + n as u64);
        let mut z = Vec::new();
        for _ in 0..1000 {
            let (h, rot, com) = random_box(&mut rng);
            let p = planes(&h, &rot, &com, &EDGES[..n], s, &mut rng);
            let noise: Vector3<f64> =
                Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * sigma_f);
            let (c, left_out) = com_of(&p, Some(&flights_at(com + noise, sigma_f))).unwrap();
            assert_eq!((c.pendulums + left_out.len(), c.flights), (n, 12));
            z.extend(c.standardised_error(&com).unwrap().iter().map(|x| x.abs()));
        }
        z.sort_by(f64::total_cmp);
        let median = z[z.len() / 2];
        // With more than three planes the covariance is inflated by χ²/dof when above 1.
        let lo = if n > 3 { 0.55 } else { 0.6 };
        assert!(median > lo && median < 0.75, "{n} planes: median {median}");
        assert!(z.last().unwrap() < &5.0, "{n}: max {}", z.last().unwrap());
    }
}

/// A flights' point 20 mm from five pendulums that agree with each other: neither is dropped,
/// the CoM's covariance is widened by their χ² over 3, which the CoM says (`flights_chi2`, the
/// tree's contradiction), and both the pendulums' CoM and the point are within 5 of its σ.
#[test]
fn a_flights_point_that_disagrees_with_the_pendulums_widens_the_centre_of_mass() {
    let mut rng = StdRng::seed_from_u64(11);
    let s = PRECISE;
    let (h, rot, com) = random_box(&mut rng);
    let p = planes(&h, &rot, &com, &EDGES, s, &mut rng);
    let off = com + Vector3::new(0.02, 0.0, 0.0);
    let (c, left_out) = com_of(&p, Some(&flights_at(off, 5e-4))).unwrap();
    assert!(left_out.is_empty(), "{left_out:?}");
    let chi2 = c.flights_chi2.unwrap();
    assert!(
        chi2 > crate::stats::chi2_threshold(3.0, MATCH_ALPHA),
        "{chi2}"
    );
    assert_eq!(c.pendulums, EDGES.len());
    for x in [com, off] {
        let z = c.standardised_error(&x).unwrap();
        assert!(z.amax() < 5.0, "{x:?}: {z:?}");
    }
    // Agreeing, the same point is not widened.
    let (agree, _) = com_of(&p, Some(&flights_at(com, 5e-4))).unwrap();
    assert!(agree.flights_chi2.unwrap() < 16.0);
    assert!(agree.sigma_m.unwrap() < 0.5 * c.sigma_m.unwrap());
}

/// Three pendulums always meet and cannot contradict each other; with the flights' point they
/// can: one φ 15° off is left out, and the CoM is the others' with the point.
#[test]
fn with_the_flights_point_a_wrong_pendulum_among_three_is_left_out() {
    let mut rng = StdRng::seed_from_u64(5);
    let s = PRECISE;
    let (h, rot, com) = random_box(&mut rng);
    let mut p = planes(&h, &rot, &com, &EDGES[..3], s, &mut rng);
    p[1].phi -= 15f64.to_radians();
    let (alone, none) = com_of(&p, None).unwrap();
    assert!(none.is_empty() && (alone.point - com).norm() > 2e-3);
    let (c, left_out) = com_of(&p, Some(&flights_at(com, 5e-4))).unwrap();
    assert_eq!(left_out.len(), 1, "{left_out:?}");
    assert_eq!(left_out[0].0, 1);
    assert!((c.point - com).norm() < 2e-3, "{:?}", c.point);
}
