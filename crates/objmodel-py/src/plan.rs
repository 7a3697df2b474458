//! `objmodel.plan`: the toppling skill's parameters from a learnt tree
//! ([`objmodel::skill::plan`]), as `objmodel plan --json` gives them.

use crate::config::{vec3, Gravity};
use crate::error::{err, lib};
use crate::inputs::{input, prepare, Input, Prepared};
use crate::json::to_python;
use crate::poses::{poses, QuatOrder};
use crate::tree::tree_arg;
use nalgebra::{Isometry3, Vector3};
use objmodel::format::read_trajectory;
use objmodel::skill::{plan as skill_plan, PlanRequest};
use pyo3::prelude::*;
use pyo3::types::PyList;

/// `palm_from_object` from a 7-vector `x y z qx qy qz qw` (in `order`) or a 4x4 matrix.
fn pose(obj: &Bound<'_, PyAny>, order: QuatOrder) -> PyResult<Isometry3<f64>> {
    if let Ok(s) = obj.extract::<String>() {
        return objmodel::args::pose_xyz_xyzw(&s).map_err(|e| err(e.0));
    }
    let np = obj.py().import("numpy")?;
    let a = np.call_method1("asarray", (obj, "float64"))?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    // One pose at time 0: the row or matrix layout of `poses`.
    let one = match shape.as_slice() {
        [7] => {
            let v: Vec<f64> = a.call_method0("tolist")?.extract()?;
            let row: Vec<f64> = std::iter::once(0.0).chain(v).collect();
            PyList::new(obj.py(), [row])?.into_any()
        }
        [4, 4] => a.call_method1("reshape", ((1, 4, 4),))?,
        _ => {
            return Err(err(format!(
                "object_in_palm: shape {shape:?}; expected 7 numbers x y z qx qy qz qw or a \
                 4x4 matrix"
            )))
        }
    };
    let times = (shape.len() == 2)
        .then(|| numpy_zero(obj.py()))
        .transpose()?;
    let p = poses(&one, times.as_ref(), order, "object_in_palm")?;
    Ok(p[0].pose)
}

/// `numpy.zeros(1)`.
fn numpy_zero(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    py.import("numpy")?.call_method1("zeros", (1,))
}

/// `palm_from_object` and gravity in the palm frame at the first poses of an instrumented
/// demonstration, gravity being `gravity` in the tracking frame (as `objmodel plan
/// --from-demo`).
fn at_first_poses(
    demo: &Prepared,
    gravity: &Vector3<f64>,
) -> PyResult<(Isometry3<f64>, Vector3<f64>)> {
    let (object, palm) = match demo {
        Prepared::Files { object, palm } => {
            let Some(palm) = palm else {
                return Err(err(format!(
                    "{}: no palm file beside it (NAME.palm.tum); give palm=",
                    object.display()
                )));
            };
            (
                read_trajectory(object).map_err(lib)?,
                read_trajectory(palm).map_err(lib)?,
            )
        }
        Prepared::Take { path, object, palm } => {
            let Some(palm) = palm else {
                return Err(err(format!(
                    "{}: no palm's rigid body named; give rigid_bodies=(object, palm)",
                    path.display()
                )));
            };
            let read = |body: &str| -> PyResult<Vec<objmodel::StampedPose>> {
                let file = objmodel::format::PoseFile {
                    path,
                    rigid_body: Some(body),
                };
                file.open()
                    .and_then(|r| r.collect::<objmodel::Result<Vec<_>>>())
                    .map_err(lib)
            };
            (read(object)?, read(palm)?)
        }
        Prepared::Memory(d) => match &d.palm {
            Some(p) => (d.object.clone(), p.clone()),
            None => return Err(err(format!("{}: no palm given; give palm=", d.name))),
        },
    };
    let (Some(object), Some(world_from_palm)) = (object.first(), palm.first()) else {
        return Err(err(format!("{}: no poses", demo.label())));
    };
    Ok((
        world_from_palm.pose.inverse() * object.pose,
        world_from_palm.pose.rotation.inverse() * gravity,
    ))
}

/// Plan a topple on the palm: the tilt axis and angle, in the palm frame (origin on the palm's
/// surface, z its normal).
///
/// `tree`: a Tree or a tree file. The object's pose on the palm, `palm_from_object`: either
/// `object_in_palm` (7 numbers `x y z qx qy qz qw`, quaternion order `quat_order`, or a 4x4
/// matrix) with `gravity_in_palm` (default (0, 0, -1), a level palm), or `from_demo` (an
/// instrumented demonstration: a file with NAME.palm.* beside it or `palm`, or arrays as for
/// `learn` with `palm` and `times`) whose first poses give it, with `gravity` in the tracking
/// frame. `towards`: preferred toppling direction in the palm frame (default: the edge easiest
/// to topple). `margin`: past φ [rad] (default 2° + 3 σ_φ).
///
/// Returns a dict: the JSON of `objmodel plan --json` (`edge`, `axis_point`,
/// `axis_direction`, `tilt`, `phi`, ..., `predicted`: True when no one demonstrated the edge and
/// φ is the one the shape and the CoM predict, with its `phi_sigma`).
#[pyfunction]
#[pyo3(
    signature = (tree, *, object_in_palm=None, gravity_in_palm=None, from_demo=None, palm=None, times=None, gravity=Gravity::default(), towards=None, margin=None, quat_order="xyzw"),
    text_signature = "(tree, *, object_in_palm=None, gravity_in_palm=None, from_demo=None, palm=None, times=None, gravity=(0, 0, -1), towards=None, margin=None, quat_order='xyzw')"
)]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    tree: &Bound<'_, PyAny>,
    object_in_palm: Option<&Bound<'_, PyAny>>,
    gravity_in_palm: Option<&Bound<'_, PyAny>>,
    from_demo: Option<&Bound<'_, PyAny>>,
    palm: Option<&Bound<'_, PyAny>>,
    times: Option<&Bound<'_, PyAny>>,
    gravity: Gravity,
    towards: Option<&Bound<'_, PyAny>>,
    margin: Option<f64>,
    quat_order: &str,
) -> PyResult<Py<PyAny>> {
    let order = crate::poses::quat_order(quat_order)?;
    let tree = tree_arg(tree)?;
    let (palm_from_object, gravity_in_palm) = match (from_demo, object_in_palm) {
        (Some(_), Some(_)) => return Err(err("give object_in_palm or from_demo, not both")),
        (Some(_), _) if gravity_in_palm.is_some() => {
            return Err(err(
                "gravity_in_palm goes with object_in_palm; with from_demo give gravity (in the \
                 tracking frame)",
            ))
        }
        (Some(d), None) => {
            let object = input(d, times, order, "from_demo")?;
            let palm: Option<Input> = palm.map(|p| input(p, times, order, "palm")).transpose()?;
            let g = gravity
                .0
                .ok_or_else(|| err("from_demo needs gravity in the tracking frame"))?;
            at_first_poses(&prepare(object, palm, false, "from_demo".into())?, &g)?
        }
        (None, Some(p)) => (
            pose(p, order)?,
            gravity_in_palm
                .map(|g| vec3(g, "gravity_in_palm"))
                .transpose()?
                .unwrap_or_else(|| Vector3::new(0.0, 0.0, -1.0)),
        ),
        (None, None) => return Err(err("give object_in_palm or from_demo")),
    };
    let req = PlanRequest {
        palm_from_object,
        towards: towards.map(|t| vec3(t, "towards")).transpose()?,
        gravity_in_palm,
        margin,
    };
    let p = skill_plan(&tree, &req).map_err(lib)?;
    to_python(
        py,
        &serde_json::to_value(&p).map_err(|e| err(e.to_string()))?,
    )
}
