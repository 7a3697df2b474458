//! Trees for the tests of the model's pictures: an analytic box (exact faces, eight of its
//! twelve edges learnt as in the paper's Fig. 9a, an offset centre of mass) and a box learnt
//! from simulated topples onto every face.
#![allow(dead_code)]

use nalgebra::Vector3;
use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::shape::reconstruct;
use objmodel::synth::{self, SynthBox, SynthNoise};
use objmodel::tree::{CentreOfMass, Edge, Evidence, Face, Tree};
use objmodel::Demonstration;
use rand::{rngs::StdRng, SeedableRng};

/// Half extents of the analytic box [m] and its centre in the object frame.
pub const HALF: [f64; 3] = [0.06, 0.04, 0.09];
pub const CENTRE: [f64; 3] = [0.01, -0.02, -0.09];
/// The analytic box's centre of mass.
pub const COM: [f64; 3] = [0.02, -0.015, -0.1];

fn face(id: usize, normal: Vector3<f64>, offset: Option<f64>) -> Face {
    Face {
        id: format!("f{id}"),
        normal,
        offset,
        offset_sigma_m: offset.map(|_| 1e-3),
        sigma_normal_rad: 0.01,
        sign_known: true,
        support: vec!["demo".into()],
        n_support: 1,
        evidence: Evidence {
            slide: 0,
            rest: 1,
            landing: 0,
        },
        observations: Vec::new(),
        offset_unlocated: None,
    }
}

fn edge(id: usize, point: Vector3<f64>, direction: Vector3<f64>, faces: [usize; 2]) -> Edge {
    let point = point - direction * direction.dot(&point);
    Edge {
        id: format!("e{id}"),
        point,
        direction,
        point_cov: [[0.0; 3]; 3],
        direction_cov: [[0.0; 3]; 3],
        sigma_point_m: 1e-3,
        sigma_direction_rad: 0.01,
        support: vec![format!("topple{id}"), format!("topple{id}b")],
        n_support: 2,
        faces: faces.iter().map(|f| format!("f{f}")).collect(),
        pendulums: Vec::new(),
        observations: Vec::new(),
        between_sigma_m: None,
        conditioned_on: Vec::new(),
        observed: None,
    }
}

/// The analytic box: six faces (`f{2a}` = +axis a, `f{2a+1}` = -axis a), the eight edges of
/// the faces ±x (the four around each), the CoM at [`COM`]; its shape reconstructed.
/// `offsets = false` leaves face f1's offset unknown (as after a slide only).
pub fn analytic_box(offsets: bool) -> Tree {
    let (c, h) = (Vector3::from(CENTRE), Vector3::from(HALF));
    let mut tree = Tree::default();
    for axis in 0..3 {
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            let n = Vector3::ith(axis, sign);
            let d = n.dot(&c) + h[axis];
            let id = 2 * axis + k;
            tree.faces
                .push(face(id, n, (offsets || id != 1).then_some(d)));
        }
    }
    let mut id = 0;
    for (xk, xs) in [(0usize, 1.0), (1, -1.0)] {
        for (axis, other) in [(1usize, 2usize), (2, 1)] {
            for (sk, s) in [(0usize, 1.0), (1, -1.0)] {
                // The edge along `other` on the face ±x, at ±`axis`.
                let mut p = c;
                p.x += xs * h.x;
                p[axis] += s * h[axis];
                tree.edges
                    .push(edge(id, p, Vector3::ith(other, 1.0), [xk, 2 * axis + sk]));
                id += 1;
            }
        }
    }
    tree.com = Some(CentreOfMass {
        point: Vector3::from(COM),
        rms_residual_m: 5e-4,
        pendulums: 3,
        covariance: None,
        sigma_m: None,
        chi2_per_dof: None,
        ..Default::default()
    });
    tree.shape = reconstruct(&tree.learnt_faces()).ok();
    tree.contradictions = tree.contradictions();
    tree
}

/// A random box toppled onto every face (`synth::topples_over_every_face`) and learnt, with
/// the demonstrations.
pub fn learnt_box(seed: u64, noise: &SynthNoise) -> (SynthBox, Tree, Vec<Demonstration>) {
    let b = SynthBox::random(&mut StdRng::seed_from_u64(seed));
    let learner = Learner::new(Config::default());
    let mut tree = Tree::default();
    let mut demos = Vec::new();
    for d in synth::topples_over_every_face(&b, noise, seed) {
        learner
            .learn(&mut tree, &[Source::Memory(&d.demo)])
            .unwrap();
        demos.push(d.demo);
    }
    (b, tree, demos)
}
