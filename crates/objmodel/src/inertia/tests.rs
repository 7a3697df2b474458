use super::*;
use crate::shape::{reconstruct, tests_support::box_faces};
use crate::tree::{Edge, Pendulum, PendulumObservation};
use nalgebra::UnitQuaternion;

/// A tree with the box's faces and, for each `(axis, ratio)`, an edge along that box axis whose
/// fall gave the ratio `I_e/(m l_p)`.
fn tree_with_edges(edges: &[(Vector3<f64>, Vector3<f64>, f64)]) -> Tree {
    let mut tree = Tree::default();
    for (i, (point, direction, ratio)) in edges.iter().enumerate() {
        let mut e: Edge = serde_json::from_value(serde_json::json!({
            "id": format!("e{i}"), "point": [point.x, point.y, point.z],
            "direction": [direction.x, direction.y, direction.z],
            "point_cov": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], "direction_cov": [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
            "sigma_point_m": 0.0, "sigma_direction_rad": 0.0, "support": [], "n_support": 1,
            "faces": [], "pendulums": [], "observations": []
        }))
        .unwrap();
        e.pendulums.push(Pendulum {
            resting_face_normal: Vector3::z(),
            toppling_axis: *direction,
            phi: Some(0.5),
            l_p: None,
            phi_sigma: Some(0.01),
            inertia_ratio_m: Some(*ratio),
            support: vec![],
            observations: vec![PendulumObservation {
                demo: format!("d{i}"),
                phi: 0.5,
                phi_sigma: 0.01,
                phi_onset: None,
                phi_onset_sigma: None,
                phi_fall: Some(0.5),
                inertia_ratio_m: Some(*ratio),
                onset_t: None,
            }],
            com_conflict: None,
        });
        tree.edges.push(e);
    }
    tree
}

/// The ratio a fall about the edge (point `p`, direction `u`) gives for a body of inertia `j`
/// per kg about its CoM `c`.
fn ratio(j: &Matrix3<f64>, c: &Vector3<f64>, p: &Vector3<f64>, u: &Vector3<f64>) -> f64 {
    let r = c - p;
    let l = (r - u * u.dot(&r)).norm();
    ((u.transpose() * j * u)[0] + l * l) / l
}

/// A turned box whose inertia is not the uniform one (a weight inside along its axes): falls
/// about edges along its three axes give its three principal moments exactly; with two axes,
/// the third is the uniform shape's, and it says so. Falls that scatter, or one fall, or a
/// moment no body inside the shape can have, are not used.
#[test]
fn falls_about_three_box_axes_give_the_principal_moments() {
    let rot = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.9);
    let (centre, size) = (
        Vector3::new(0.01, 0.02, -0.03),
        Vector3::new(0.1, 0.08, 0.2),
    );
    let shape = reconstruct(&box_faces(centre, &rot, &size)).unwrap();
    let com = centre + rot * Vector3::new(0.01, 0.0, -0.02);
    let r = rot.to_rotation_matrix();
    let moments = Vector3::new(3e-3, 2.5e-3, 1.1e-3);
    let j = r.matrix() * Matrix3::from_diagonal(&moments) * r.matrix().transpose();
    let half = size / 2.0;
    // Bottom edges along x and y, a vertical edge along z.
    let corner = |a: f64, b: f64, c: f64| centre + rot * Vector3::new(a, b, c);
    let edges: Vec<(Vector3<f64>, Vector3<f64>, f64)> = [
        (corner(0.0, half.y, -half.z), rot * Vector3::x()),
        (corner(half.x, 0.0, -half.z), rot * Vector3::y()),
        (corner(half.x, half.y, 0.0), rot * Vector3::z()),
    ]
    .iter()
    // Two falls about each (one says nothing of its own uncertainty).
    .flat_map(|(p, u)| [(*p, *u, ratio(&j, &com, p, u)); 2])
    .collect();
    let got = learn(&tree_with_edges(&edges), &shape, &com);
    assert_eq!(got.source, InertiaSource::Pendulums);
    assert!((got.matrix() - j).norm() < 1e-12, "{}", got.matrix());
    let two = learn(&tree_with_edges(&edges[..4]), &shape, &com);
    assert_eq!(two.source, InertiaSource::PendulumsAndUniformDensity);
    let z = rot * Vector3::z();
    let uniform = mass::uniform(&shape).inertia_per_kg;
    assert!(
        ((z.transpose() * two.matrix() * z)[0] - (z.transpose() * uniform * z)[0]).abs() < 1e-12
    );
    let x = rot * Vector3::x();
    assert!(((x.transpose() * two.matrix() * x)[0] - moments.x).abs() < 1e-12);
    let mut scattered = edges.clone();
    scattered[4].2 *= 1.3;
    let s = learn(&tree_with_edges(&scattered), &shape, &com);
    assert_eq!(s.source, InertiaSource::PendulumsAndUniformDensity);
    assert!(s.axes[..]
        .iter()
        .any(|a| a.not_used.as_deref().is_some_and(|w| w.contains("scatter"))));
    let one = learn(&tree_with_edges(&edges[..1]), &shape, &com);
    assert_eq!(one.source, InertiaSource::UniformDensity);
    let mut far = edges.clone();
    far[0].2 *= 10.0;
    far[1].2 *= 10.0;
    let f = learn(&tree_with_edges(&far), &shape, &com);
    assert!(f.axes.iter().any(|a| a
        .not_used
        .as_deref()
        .is_some_and(|w| w.contains("more than any mass"))));
    let none = learn(&Tree::default(), &shape, &com);
    assert_eq!(none.source, InertiaSource::UniformDensity);
    assert!((none.matrix() - uniform).norm() < 1e-15);
}
