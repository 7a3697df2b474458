use super::*;
use crate::shape::{reconstruct, tests_support::box_faces};
use nalgebra::UnitQuaternion;
use rand::{rngs::StdRng, Rng, SeedableRng};
use rand_distr::StandardNormal;

/// The Jacobian sigmas of φ and `l_p` agree with Monte Carlo: the faces' offsets and normals
/// and the CoM drawn from their stated distributions, the shape rebuilt and the pendulums
/// predicted again, for every (face, edge) pair of a turned box.
#[test]
fn jacobian_sigmas_match_monte_carlo() {
    let rot = UnitQuaternion::from_euler_angles(0.4, 0.1, -0.7);
    let (centre, size) = (
        Vector3::new(0.02, -0.01, 0.05),
        Vector3::new(0.1, 0.07, 0.16),
    );
    let mut faces = box_faces(centre, &rot, &size);
    // One face known worse, as an inferred one is.
    faces[1].offset_sigma_m = 4e-3;
    faces[1].normal_sigma_rad = 0.02;
    let shape = reconstruct(&faces).unwrap();
    let com = centre + rot * Vector3::new(0.01, 0.005, -0.02);
    let l = Matrix3::new(2e-3, 0.0, 0.0, 0.5e-3, 1.5e-3, 0.0, -0.4e-3, 0.3e-3, 3e-3);
    let com_cov = l * l.transpose();
    let predicted = uncertain(&shape, &com, &com_cov);
    assert_eq!(predicted.len(), 24);
    let mut rng = StdRng::seed_from_u64(5);
    let n = 3000;
    let mut samples: Vec<Vec<(f64, f64)>> = vec![Vec::new(); predicted.len()];
    let gauss = |rng: &mut StdRng| rng.sample::<f64, _>(StandardNormal);
    for _ in 0..n {
        let drawn: Vec<_> = faces
            .iter()
            .map(|f| {
                let w = Vector3::from_fn(|_, _| gauss(&mut rng) * f.normal_sigma_rad);
                let w = w - f.normal * f.normal.dot(&w);
                let mut g = f.clone();
                g.normal = UnitQuaternion::from_scaled_axis(w) * f.normal;
                g.offset = Some(f.offset.unwrap() + gauss(&mut rng) * f.offset_sigma_m);
                g
            })
            .collect();
        let c = com + l * Vector3::from_fn(|_, _| gauss(&mut rng));
        let s = reconstruct(&drawn).unwrap();
        let again = crate::prediction::pendulums(&s, &c);
        for (k, p) in predicted.iter().enumerate() {
            let q = again
                .iter()
                .find(|q| q.resting_face == p.resting_face && q.landing_face == p.landing_face)
                .expect("the same pair");
            samples[k].push((q.phi, q.l_p));
        }
    }
    let sd = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
    };
    for (p, s) in predicted.iter().zip(&samples) {
        let phi: Vec<f64> = s.iter().map(|x| x.0).collect();
        let lp: Vec<f64> = s.iter().map(|x| x.1).collect();
        let (mc_phi, mc_l) = (sd(&phi), sd(&lp));
        let (j_phi, j_l) = (p.phi_sigma.unwrap(), p.l_p_sigma.unwrap());
        assert!(
            (j_phi / mc_phi - 1.0).abs() < 0.08,
            "{}->{}: phi sigma {j_phi} vs Monte Carlo {mc_phi}",
            p.resting_face,
            p.landing_face
        );
        assert!((j_l / mc_l - 1.0).abs() < 0.08, "l_p sigma {j_l} vs {mc_l}");
    }
    // Without any uncertainty, none.
    let exact = uncertain(
        &reconstruct(
            &box_faces(centre, &rot, &size)
                .into_iter()
                .map(|mut f| {
                    f.offset_sigma_m = 0.0;
                    f.normal_sigma_rad = 0.0;
                    f
                })
                .collect::<Vec<_>>(),
        )
        .unwrap(),
        &com,
        &Matrix3::zeros(),
    );
    assert!(exact
        .iter()
        .all(|p| p.phi_sigma == Some(0.0) && p.l_p_sigma == Some(0.0)));
}
