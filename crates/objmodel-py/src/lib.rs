//! `objmodel` for Python: learn object description trees from pose demonstrations given as
//! numpy arrays or pose files, classify them, export the learnt object (MJCF, URDF) and plan a
//! topple, through the `objmodel` library's one pipeline ([`objmodel::learn::Learner`]).
//!
//! ```python
//! import objmodel
//! tree = objmodel.learn([poses_a, poses_b], gravity=(0, 0, -1))
//! tree.export_mjcf("box.xml", mass=0.6)
//! ```
//!
//! Poses are `world_from_object`: (N, 8) rows `t x y z qx qy qz qw` (quaternion x y z w, the
//! TUM and scipy order; `quat_order="wxyz"` for `t x y z qw qx qy qz`), or (N, 4, 4) matrices
//! with `times`. See README.md beside this crate.
//!
//! The modules: `error` (ObjmodelError, warnings), `json`, `poses` (arrays to poses),
//! `config` (gravity and thresholds), `inputs` (files or arrays to the library's sources),
//! `tree` (the Tree class and export), `learn` (learn, classify), `plan`, `synth` (example
//! demonstrations).

mod config;
mod error;
mod inputs;
mod json;
mod learn;
mod plan;
mod poses;
mod synth;
mod tree;

use pyo3::prelude::*;

/// Learn object models (edges, faces, how they topple) from 6D pose demonstrations, after
/// Sanan, Bretan & Heck, "Learning Object Models for Non-prehensile Manipulation" (IROS 2019).
#[pymodule(name = "objmodel")]
fn objmodel_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<tree::PyTree>()?;
    m.add_function(wrap_pyfunction!(learn::learn, m)?)?;
    m.add_function(wrap_pyfunction!(learn::classify, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add_function(wrap_pyfunction!(synth::synthetic_topples, m)?)?;
    m.add("ObjmodelError", py.get_type::<error::ObjmodelError>())?;
    m.add("ObjmodelWarning", py.get_type::<error::ObjmodelWarning>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("QUAT_NORM_TOLERANCE", objmodel::format::QUAT_NORM_TOLERANCE)?;
    Ok(())
}
