use super::*;
use crate::face::SUPPORT_LEVEL_SIGMA_RAD;
use nalgebra::Unit;
use rand::{rngs::StdRng, Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};

const ALPHA: f64 = 1e-3;

/// The vertical the rests show where it contradicts `up`.
fn contradiction(rests: &[Rest], up: &Vector3<f64>, alpha: f64, level: f64) -> Option<Vertical> {
    shown(rests, up, alpha, level).filter(|v| v.contradicts)
}

fn unit(rng: &mut StdRng) -> Vector3<f64> {
    let v: Vector3<f64> = Vector3::from_fn(|_, _| StandardNormal.sample(rng));
    v.normalize()
}

/// A rest of a box (faces ±x, ±y, ±z of the object frame) on `face` of a support whose normal
/// is `up`, turned by `heading` about it, tracked with `sigma` \[rad\] per axis.
fn rest(face: usize, up: &Vector3<f64>, heading: f64, sigma: f64, rng: &mut StdRng) -> Rest {
    let mut n = Vector3::zeros();
    n[face % 3] = if face < 3 { 1.0 } else { -1.0 };
    // world_from_object takes the face's outward normal to down.
    let onto = UnitQuaternion::rotation_between(&n, &-up).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    let turn = UnitQuaternion::from_axis_angle(&Unit::new_normalize(*up), heading);
    let noise = UnitQuaternion::from_scaled_axis(Vector3::from_fn(|_, _| {
        sigma * {
            let x: f64 = StandardNormal.sample(rng);
            x
        }
    }));
    Rest {
        rotation: noise * turn * onto,
        sigma_rad: sigma,
    }
}

/// A lab: a support tilted from `up` by about a degree, `n` rests of a box on random faces at
/// random headings.
fn lab(n: usize, up: &Vector3<f64>, sigma: f64, rng: &mut StdRng) -> Vec<Rest> {
    let tilt = UnitQuaternion::from_scaled_axis(Vector3::from_fn(|_, _| {
        SUPPORT_LEVEL_SIGMA_RAD * {
            let x: f64 = StandardNormal.sample(rng);
            x
        }
    }));
    let normal = tilt * up;
    (0..n)
        .map(|_| {
            let face = rng.random_range(0..6);
            let heading = rng.random_range(0.0..std::f64::consts::TAU);
            rest(face, &normal, heading, sigma, rng)
        })
        .collect()
}

#[test]
fn rests_at_any_heading_agree_with_the_right_vertical() {
    let mut rng = StdRng::seed_from_u64(1);
    let mut found = 0;
    for _ in 0..200 {
        let up = unit(&mut rng);
        let sigma = rng.random_range(1e-4..0.01);
        let rests = lab(rng.random_range(4..40), &up, sigma, &mut rng);
        found += contradiction(&rests, &up, ALPHA, SUPPORT_LEVEL_SIGMA_RAD).is_some() as usize;
    }
    // The support's tilt is a draw of the level allowed (1° per axis): the χ²₂ test at 1e-3
    // flags about one lab in a thousand.
    assert!(
        found <= 2,
        "{found} of 200 labs contradicted the right vertical"
    );
}

#[test]
fn rests_at_any_heading_contradict_a_wrong_vertical_and_show_the_right_one() {
    let mut rng = StdRng::seed_from_u64(2);
    let mut z = Vec::new();
    for _ in 0..200 {
        let up = unit(&mut rng);
        // Wrong by 5° to 175° (a y-up frame learnt as z up is 90° off; a sign flip, 180°, is
        // the same line and is not seen).
        let off = rng.random_range(5f64..175.0).to_radians();
        let across = up.cross(&unit(&mut rng)).normalize();
        let wrong = UnitQuaternion::from_axis_angle(&Unit::new_normalize(across), off) * up;
        let sigma = rng.random_range(1e-4..0.01);
        let rests = lab(rng.random_range(12..60), &up, sigma, &mut rng);
        let c = contradiction(&rests, &wrong, ALPHA, SUPPORT_LEVEL_SIGMA_RAD)
            .unwrap_or_else(|| panic!("a vertical {:.1}° off was not caught", off.to_degrees()));
        // The axis is the support's normal: up tilted by the lab's level.
        let err = c.axis.cross(&up).norm().asin();
        assert!(
            err < 5.0 * SUPPORT_LEVEL_SIGMA_RAD,
            "axis {:.2}° off",
            err.to_degrees()
        );
        let angle = wrong.cross(&up).norm().atan2(wrong.dot(&up).abs());
        assert!((c.angle_rad - angle).abs() < 5.0 * SUPPORT_LEVEL_SIGMA_RAD);
        assert!(c.pairs >= MIN_PAIRS && c.rests >= MIN_RESTS && c.pairs_about_given * 2 < c.pairs);
        z.push((c.axis.cross(&up).norm().asin(), c.sigma_rad));
    }
    // The axis' σ is from the pairs (the support's tilt is not in it): against the support's
    // normal itself it must be honest. Here against up, with the tilt added.
    let mut ratios: Vec<f64> = z
        .iter()
        .map(|(e, s)| e / (s * s + SUPPORT_LEVEL_SIGMA_RAD.powi(2)).sqrt())
        .collect();
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    // 2-D errors: an honest σ gives a median of 1.18.
    assert!((0.8..1.6).contains(&median), "median |error|/σ {median:.2}");
}

#[test]
fn the_axis_sigma_is_honest_against_the_support_normal() {
    let mut rng = StdRng::seed_from_u64(3);
    let (mut ratios, mut missed) = (Vec::new(), 0);
    for _ in 0..300 {
        let up = unit(&mut rng);
        let wrong = up.cross(&unit(&mut rng)).normalize();
        let sigma = rng.random_range(1e-3..0.01);
        // A level support: the pairs alone decide the axis.
        let rests: Vec<Rest> = (0..rng.random_range(20..40))
            .map(|_| {
                let (face, heading) = (
                    rng.random_range(0..6),
                    rng.random_range(0.0..std::f64::consts::TAU),
                );
                rest(face, &up, heading, sigma, &mut rng)
            })
            .collect();
        let Some(c) = contradiction(&rests, &wrong, ALPHA, SUPPORT_LEVEL_SIGMA_RAD) else {
            missed += 1;
            continue;
        };
        ratios.push(c.axis.cross(&up).norm().asin() / c.sigma_rad);
    }
    assert!(
        missed <= 3,
        "{missed} of 300 wrong verticals 90° off not caught"
    );
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    assert!(
        (0.9..1.5).contains(&median),
        "median |error|/σ {median:.2} (honest: 1.18)"
    );
    assert!(
        ratios[ratios.len() - 1] < 5.0,
        "worst {:.1} σ",
        ratios[ratios.len() - 1]
    );
}

#[test]
fn rests_at_one_heading_show_no_vertical() {
    // Topples from face to face at one heading: a box turned by quarter turns, a prism by
    // thirds of a turn about parallel edges. Neither tells the vertical, and the edges'
    // direction must not pass for it.
    let mut rng = StdRng::seed_from_u64(4);
    let up = Vector3::z();
    let edge = Unit::new_normalize(Vector3::y());
    for step in [90f64, 120.0, 60.0] {
        let mut rests = Vec::new();
        for demo in 0..20 {
            let start = (demo % 3) as f64 * step.to_radians();
            for k in 0..2 {
                let roll =
                    UnitQuaternion::from_axis_angle(&edge, start + k as f64 * step.to_radians());
                let noise = UnitQuaternion::from_scaled_axis(Vector3::from_fn(|_, _| {
                    1e-3 * {
                        let x: f64 = StandardNormal.sample(&mut rng);
                        x
                    }
                }));
                rests.push(Rest {
                    rotation: noise * roll,
                    sigma_rad: 1e-3,
                });
            }
        }
        assert_eq!(
            contradiction(&rests, &up, ALPHA, SUPPORT_LEVEL_SIGMA_RAD),
            None,
            "{step}°"
        );
    }
}

#[test]
fn too_few_rests_say_nothing() {
    let mut rng = StdRng::seed_from_u64(5);
    let up = Vector3::z();
    let rests = lab(3, &up, 1e-3, &mut rng);
    assert_eq!(
        contradiction(&rests, &Vector3::x(), ALPHA, SUPPORT_LEVEL_SIGMA_RAD),
        None
    );
}
