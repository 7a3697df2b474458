//! The learnt mass properties and predictions against the data set's truth: per box and noise
//! level (all demonstrations of a box learnt together), the CoM's error along each eigen-axis
//! of its covariance in its sigmas, the inertia about the CoM against the true box's, the
//! friction bound against the true coefficient, and each predicted pendulum's φ against the
//! true box's, in its sigmas.
//!
//! ```text
//! cargo run --release -p objmodel-sim --example mass_check -- DATA_DIR
//! ```
//!
//! With `DUMP="real   brick"` (a prefix of a box's line), that box's CoM planes are printed
//! beside the truth on standard error.

use anyhow::Result;
use nalgebra::{Matrix3, Vector3};
use objmodel_sim::claims::{learn_boxes, truth_body, DemoSet};
use std::path::PathBuf;

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<()> {
    let data = PathBuf::from(std::env::args().nth(1).expect("DATA_DIR"));
    for noise in ["clean", "mocap", "real", "noisy"] {
        let (mut z_all, mut zphi_all, mut zlp_all) = (Vec::new(), Vec::new(), Vec::new());
        for (spec, tree, demos) in learn_boxes(&data, noise, DemoSet::All)? {
            if demos == 0 {
                continue;
            }
            let truth = truth_body(&spec);
            let mut line = format!("{noise:6} {:9} {demos:3} demos:", spec.name);
            match &tree.com {
                Some(c) => {
                    let z = c.standardised_error(&truth.com).unwrap_or_default();
                    line += &format!(
                        " CoM err {:5.1} mm, sigma {:5.1} mm, chi2/dof {}, |z| {:.2} {:.2} {:.2} ({} planes)",
                        (c.point - truth.com).norm() * 1e3,
                        c.sigma_m.unwrap_or(f64::NAN) * 1e3,
                        c.chi2_per_dof.map_or("-".into(), |x| format!("{x:.1}")),
                        z.x.abs(),
                        z.y.abs(),
                        z.z.abs(),
                        c.pendulums
                    );
                    z_all.extend(z.iter().map(|x| x.abs()));
                }
                None => line += " no CoM",
            }
            println!("{line}");
            if std::env::var("DUMP").is_ok_and(|d| line.contains(&d)) {
                dump(&tree, &truth.com);
            }
            // Predicted pendulums against the true box with its true CoM.
            let true_pred = objmodel::prediction::pendulums(&truth.shape, &truth.com);
            for p in &tree.predictions {
                let Some(t) = true_pred.iter().min_by(|a, b| {
                    let d = |q: &objmodel::prediction::PredictedPendulum| {
                        (q.edge_point - p.edge_point).norm()
                            + (q.edge_direction - p.edge_direction).norm()
                            + (q.resting_normal - p.resting_normal).norm()
                    };
                    d(a).total_cmp(&d(b))
                }) else {
                    continue;
                };
                if let Some(s) = p.phi_sigma.filter(|s| *s > 0.0) {
                    zphi_all.push(((p.phi - t.phi) / s).abs());
                }
                if let Some(s) = p.l_p_sigma.filter(|s| *s > 0.0) {
                    zlp_all.push(((p.l_p - t.l_p) / s).abs());
                }
            }
            if let Some(i) = &tree.inertia {
                let want = truth.inertia / truth.mass_kg;
                let got = Matrix3::from_fn(|r, c| i.per_kg[r][c]);
                let ev = |m: &Matrix3<f64>| {
                    let mut e: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
                    e.sort_by(f64::total_cmp);
                    Vector3::new(e[0], e[1], e[2]) * 1e4
                };
                println!(
                    "       inertia ({:?}): principal {:.2?} cm², true {:.2?} cm², |ΔI|/|I| {:.3}",
                    i.source,
                    ev(&got).as_slice(),
                    ev(&want).as_slice(),
                    (got - want).norm() / want.norm()
                );
            }
            if let Some(i) = &tree.inertia {
                let want = truth.inertia / truth.mass_kg;
                for a in &i.axes {
                    let t = (a.direction.transpose() * want * a.direction)[0];
                    println!(
                        "         axis {:.2?}: {:.2} ± {:.2} cm² from {} (true {:.2})",
                        a.direction.as_slice(),
                        a.moment_per_kg * 1e4,
                        a.sigma_per_kg.unwrap_or(f64::NAN) * 1e4,
                        a.pendulums,
                        t * 1e4
                    );
                }
            }
            if let Some(f) = &tree.friction {
                println!(
                    "       friction: lower bound {:?}, estimate {:?}, true {:.2}",
                    f.lower_bound, f.estimate, spec.friction
                );
            }
        }
        let n = z_all.len();
        println!(
            "{noise}: CoM |z| median {:.2}, max {:.2} over {n} axes; predicted phi |z| median {:.2}, max {:.2} (n {}); l_p |z| median {:.2}, max {:.2}",
            median(z_all.clone()),
            z_all.iter().copied().fold(0.0, f64::max),
            median(zphi_all.clone()),
            zphi_all.iter().copied().fold(0.0, f64::max),
            zphi_all.len(),
            median(zlp_all.clone()),
            zlp_all.iter().copied().fold(0.0, f64::max),
        );
    }
    Ok(())
}

/// Debug: the planes of one box's tree against the truth.
#[allow(dead_code)]
pub fn dump(tree: &objmodel::tree::Tree, truth: &nalgebra::Vector3<f64>) {
    let fit = tree.com.as_ref().unwrap().point;
    eprintln!(
        "  fit {:.4?} truth {:.4?}",
        fit.as_slice(),
        truth.as_slice()
    );
    for p in tree.com_planes() {
        let (m, d) = p.plane();
        let r = p.residual_variance(truth).sqrt();
        let ax = p.axis;
        let x = truth - p.point;
        let x = x - ax * ax.dot(&x);
        let w = ax.cross(&p.normal);
        let true_phi = x.dot(&w).atan2(-x.dot(&p.normal));
        eprintln!(
            "  phi {:7.2} ± {:5.2} deg (true {:7.2}), resid at truth {:6.1} mm, sigma {:5.1} mm, at fit {:6.1} ± {:5.1} mm, axis {:.3?} normal {:.3?} point {:.3?}",
            p.phi.to_degrees(), p.phi_sigma.to_degrees(), true_phi.to_degrees(),
            (m.dot(truth) - d) * 1e3, r * 1e3, (m.dot(&fit) - d) * 1e3, p.residual_variance(&fit).sqrt() * 1e3, ax.as_slice(), p.normal.as_slice(), p.point.as_slice()
        );
    }
}
