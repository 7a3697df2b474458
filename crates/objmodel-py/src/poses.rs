//! Poses given as numpy arrays (or anything `numpy.asarray` takes), checked and turned into the
//! library's [`StampedPose`]s.
//!
//! Two layouts, both `world_from_object` (or `world_from_palm`):
//!
//! * `(N, 8)` rows `t x y z qx qy qz qw`: the TUM order, quaternion **x y z w** (scipy's
//!   `Rotation.as_quat()` order). With `quat_order="wxyz"` the rows are `t x y z qw qx qy qz`
//!   (transforms3d, pyquaternion, MuJoCo order).
//! * `(N, 4, 4)` homogeneous matrices `[[R, p], [0 0 0 1]]` with their times, an `(N,)` array.
//!
//! Every row is checked as a line of a pose file is ([`objmodel::format::pose_from_values`]:
//! finite, the quaternion's norm within 1% of 1), a matrix's rotation part must be a rotation
//! (orthonormal within the same 1%, determinant +1) and its last row `0 0 0 1`; the times must
//! strictly increase. Errors name the array (`demos[1]`), the row and the problem.
//!
//! A row whose pose values are all NaN (or all zero), or a matrix all NaN above its last row,
//! is a frame where the tracker lost the object, as in a file (`objmodel::format::SkippedLines`):
//! left out, as a frame not recorded, with an `ObjmodelWarning` that counts them. A row that
//! repeats the row before exactly (its time and pose) is left out likewise, and counted.

use crate::error::{err, warn};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use objmodel::format::{is_copy, is_lost, pose_from_values, QUAT_NORM_TOLERANCE};
use objmodel::StampedPose;
use pyo3::prelude::*;

/// The order of a quaternion's four numbers in a row: the library's, which also reads TUM
/// files written w first.
pub use objmodel::format::QuaternionOrder as QuatOrder;

/// `quat_order`: exactly `"xyzw"` or `"wxyz"`.
pub fn quat_order(s: &str) -> PyResult<QuatOrder> {
    match s {
        "xyzw" => Ok(QuatOrder::Xyzw),
        "wxyz" => Ok(QuatOrder::Wxyz),
        other => Err(err(format!(
            "quat_order must be \"xyzw\" (TUM, ROS, scipy's as_quat) or \"wxyz\" \
             (transforms3d, pyquaternion, MuJoCo), not {other:?}"
        ))),
    }
}

/// A float64 copy of `obj` (any array-like) and its shape.
fn array(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let np = obj.py().import("numpy")?;
    let a = np
        .call_method1("asarray", (obj, "float64"))
        .map_err(|e| err(format!("{what}: not an array of numbers: {e}")))?;
    let a = a.cast::<PyArrayDyn<f64>>()?;
    let shape = a.shape().to_vec();
    let values = a.readonly().as_array().iter().copied().collect();
    Ok((values, shape))
}

/// `(a, b, c)` for messages.
fn shape_text(shape: &[usize]) -> String {
    let parts: Vec<String> = shape.iter().map(|n| n.to_string()).collect();
    if parts.len() == 1 {
        format!("({},)", parts[0])
    } else {
        format!("({})", parts.join(", "))
    }
}

/// The poses of an array: `(N, 8)` rows, or `(N, 4, 4)` matrices with `times`. `what` names
/// the array in errors (`demos[0]`).
pub fn poses(
    obj: &Bound<'_, PyAny>,
    times: Option<&Bound<'_, PyAny>>,
    order: QuatOrder,
    what: &str,
) -> PyResult<Vec<StampedPose>> {
    let (v, shape) = array(obj, what)?;
    let rows: Vec<[f64; 8]> = match (shape.as_slice(), times) {
        ([_, 8], None) => v
            .chunks_exact(8)
            .map(|r| {
                let mut row: [f64; 8] = r.try_into().expect("8 values");
                if order == QuatOrder::Wxyz {
                    row[4..].rotate_left(1);
                }
                row
            })
            .collect(),
        ([_, 8], Some(_)) => {
            return Err(err(format!(
                "{what}: (N, 8) rows carry their times in column 0; `times` goes with (N, 4, 4) \
                 matrices"
            )))
        }
        ([n, 4, 4], Some(t)) => {
            let (t, tshape) = array(t, &format!("times of {what}"))?;
            if tshape != [*n] {
                return Err(err(format!(
                    "{what}: {n} matrices but times of shape {}; expected ({n},)",
                    shape_text(&tshape)
                )));
            }
            v.chunks_exact(16)
                .zip(&t)
                .enumerate()
                .map(|(i, (m, &t))| match m[..12].iter().all(|x| x.is_nan()) {
                    // Lost: a row of NaN at its time, left out below.
                    true => Ok(std::array::from_fn(|k| if k == 0 { t } else { f64::NAN })),
                    false => matrix_row(m, t).map_err(|e| err(format!("{what}[{i}]: {e}"))),
                })
                .collect::<PyResult<_>>()?
        }
        ([_, 4, 4], None) => {
            return Err(err(format!(
                "{what}: (N, 4, 4) matrices need their times: pass times=[...] (one array of N \
                 seconds per demonstration)"
            )))
        }
        ([_, 7], _) => {
            return Err(err(format!(
                "{what}: shape {}: rows need 8 columns, t x y z qx qy qz qw (is the time \
                 column missing?)",
                shape_text(&shape)
            )))
        }
        _ => {
            return Err(err(format!(
                "{what}: shape {}; expected (N, 8) rows t x y z qx qy qz qw or (N, 4, 4) \
                 matrices",
                shape_text(&shape)
            )))
        }
    };
    if rows.is_empty() {
        return Err(err(format!("{what}: no poses: the array is empty")));
    }
    let mut out = Vec::with_capacity(rows.len());
    let (mut lost, mut copies) = (Vec::new(), Vec::new());
    // The row of the last pose kept.
    let mut prev_row = 0;
    for (i, row) in rows.iter().enumerate() {
        if is_lost(row) {
            lost.push(i);
            continue;
        }
        let p = pose_from_values(row).map_err(|e| {
            let hint = if order == QuatOrder::Xyzw {
                " (rows are t x y z qx qy qz qw)"
            } else {
                " (rows are t x y z qw qx qy qz)"
            };
            err(format!("{what}[{i}]: {e}{hint}"))
        })?;
        if let Some(prev) = out.last().copied() {
            // A row that repeats the last pose exactly (its time and coordinates) is a copy, as
            // a line written twice in a file (`objmodel::format::SkippedLines`).
            if is_copy(&p, &prev) {
                copies.push(i);
                continue;
            }
            if p.t <= prev.t {
                let how = if p.t == prev.t {
                    "repeats"
                } else {
                    "goes back from"
                };
                return Err(err(format!(
                    "{what}[{i}]: timestamp {} {how} timestamp {} of row {prev_row} (timestamps \
                     must strictly increase)",
                    p.t, prev.t
                )));
            }
        }
        out.push(p);
        prev_row = i;
    }
    if out.is_empty() {
        return Err(err(format!(
            "{what}: no poses: every row is a frame where the tracker lost the object (all \
             NaN or zero)"
        )));
    }
    if let (Some(first), Some(last)) = (lost.first(), lost.last()) {
        let s = if lost.len() == 1 { "" } else { "s" };
        warn(
            obj.py(),
            what,
            &format!(
                "the tracker lost the object in {} row{s} (the first {first}, the last {last}): \
                 every pose value NaN or zero; left out, as frames not recorded",
                lost.len()
            ),
        )?;
    }
    if let Some(first) = copies.first() {
        let n = copies.len();
        let (s, verb) = if n == 1 {
            ("", "repeats")
        } else {
            ("s", "repeat")
        };
        warn(
            obj.py(),
            what,
            &format!(
                "{n} row{s} {verb} the row before exactly (the first {first}: the same time and \
                 pose); left out, the frame kept once"
            ),
        )?;
    }
    Ok(out)
}

/// The TUM row (`t x y z qx qy qz qw`) of a 4x4 matrix (row-major) at time `t`.
fn matrix_row(m: &[f64], t: f64) -> Result<[f64; 8], String> {
    let at = |r: usize, c: usize| m[4 * r + c];
    if let Some(k) = m.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "element [{}, {}] is {}; every value must be a finite number",
            k / 4,
            k % 4,
            m[k]
        ));
    }
    let bottom = [at(3, 0), at(3, 1), at(3, 2), at(3, 3)];
    if bottom != [0.0, 0.0, 0.0, 1.0] {
        let transposed = [at(0, 3), at(1, 3), at(2, 3)] == [0.0; 3] && bottom[3] == 1.0;
        return Err(format!(
            "last row is {bottom:?}, expected [0, 0, 0, 1]{}",
            if transposed {
                " (is the matrix transposed, its translation in the last row?)"
            } else {
                ""
            }
        ));
    }
    let r = Matrix3::from_fn(at);
    let off = (r.transpose() * r - Matrix3::identity()).abs().max();
    if off > QUAT_NORM_TOLERANCE {
        return Err(format!(
            "the rotation part is not orthonormal: max |RᵀR - I| = {off}, more than the \
             tolerance {QUAT_NORM_TOLERANCE}"
        ));
    }
    let det = r.determinant();
    if det < 0.0 {
        return Err(format!(
            "the rotation part has determinant {det}: a reflection, not a rotation"
        ));
    }
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix(&r));
    let pose = Isometry3::from_parts(Translation3::new(at(0, 3), at(1, 3), at(2, 3)), q);
    let (p, q) = (pose.translation.vector, pose.rotation);
    Ok([t, p.x, p.y, p.z, q.i, q.j, q.k, q.w])
}
