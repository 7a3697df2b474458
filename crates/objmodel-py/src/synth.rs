//! `objmodel.synthetic_topples`: the library's exact synthetic demonstrations
//! ([`objmodel::synth::topples_over_every_face`]) with their truth, to try the package without
//! data.

use crate::error::err;
use nalgebra::Vector3;
use numpy::{PyArray1, PyArrayMethods};
use objmodel::synth::{topples_over_every_face, SynthBox, SynthNoise};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Six kinematic topples of a box (half extents `half` [m]; a tag on its top face,
/// `tag_offset` [m] from its centre, turned by `tag_yaw` [rad]) that rest it on every face:
/// over its four bottom edges, then upside down over two more. `noise`: "clean" (exact poses)
/// or "real" (1 mm, 0.5°, dropped frames, quaternion sign flips and tag flips, from `seed`).
///
/// Returns a list of dicts: `name`, `poses` ((N, 8) rows t x y z qx qy qz qw of the tag,
/// `world_from_object`, z up), and the truth in the tag frame: `edge_point`,
/// `edge_direction`, `face_normal` and `face_offset` (the face it rests on first), `phi`
/// [rad].
#[pyfunction]
#[pyo3(
    signature = (half=(0.05, 0.035, 0.08), *, tag_offset=(0.01, -0.005), tag_yaw=0.7, noise="clean", seed=0),
    text_signature = "(half=(0.05, 0.035, 0.08), *, tag_offset=(0.01, -0.005), tag_yaw=0.7, noise='clean', seed=0)"
)]
pub fn synthetic_topples<'py>(
    py: Python<'py>,
    half: (f64, f64, f64),
    tag_offset: (f64, f64),
    tag_yaw: f64,
    noise: &str,
    seed: u64,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let noise = match noise {
        "clean" => SynthNoise::CLEAN,
        "real" => SynthNoise::REAL,
        n => {
            return Err(err(format!(
                "noise must be \"clean\" or \"real\", not {n:?}"
            )))
        }
    };
    let half = Vector3::new(half.0, half.1, half.2);
    if !half.iter().all(|h| h.is_finite() && *h > 0.0) {
        return Err(err("half extents must be positive numbers of metres"));
    }
    let b = SynthBox::new(half, tag_offset, tag_yaw);
    let vec = |v: &Vector3<f64>| PyArray1::from_vec(py, vec![v.x, v.y, v.z]);
    topples_over_every_face(&b, &noise, seed)
        .into_iter()
        .map(|d| {
            let rows: Vec<f64> = d
                .demo
                .object
                .iter()
                .flat_map(|p| {
                    let (t, q) = (p.pose.translation.vector, p.pose.rotation);
                    [p.t, t.x, t.y, t.z, q.i, q.j, q.k, q.w]
                })
                .collect();
            let n = rows.len() / 8;
            let out = PyDict::new(py);
            out.set_item("name", &d.demo.name)?;
            out.set_item("poses", PyArray1::from_vec(py, rows).reshape([n, 8])?)?;
            if let Some(e) = &d.truth.edge {
                out.set_item("edge_point", vec(&e.point))?;
                out.set_item("edge_direction", vec(&e.direction))?;
            }
            if let Some((n, o)) = &d.truth.face {
                out.set_item("face_normal", vec(n))?;
                out.set_item("face_offset", *o)?;
            }
            out.set_item("phi", d.truth.phi)?;
            Ok(out)
        })
        .collect()
}
