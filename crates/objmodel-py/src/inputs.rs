//! What `learn` and `classify` are given, turned into the library's sources: each
//! demonstration a pose file (`str` or `os.PathLike`, TUM or CSV) or an array of poses
//! ([`crate::poses`]), with its palm, its matrices' times and its name.
//!
//! Files stay files when object and palm both are ([`Source::Files`]: read once, streaming, as
//! the command line reads them); anything else is gathered in memory ([`Source::Memory`]).
//! Without an explicit palm, a file's palm is `NAME.palm.*` beside it, as on the command line.
//! An OptiTrack Motive take holding several rigid bodies is read by their names
//! (`rigid_bodies`, [`Source::Take`]).

use crate::error::{err, lib};
use crate::poses::{poses, QuatOrder};
use objmodel::format::{palm_path_for, read_trajectory};
use objmodel::learn::Source;
use objmodel::{Demonstration, StampedPose};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyString, PyTuple};
use std::path::PathBuf;

/// One trajectory: a pose file or poses in memory.
pub enum Input {
    /// A TUM or CSV file.
    File(PathBuf),
    /// Checked poses.
    Poses(Vec<StampedPose>),
}

/// Whether `obj` names a file: a `str` or an `os.PathLike`.
pub fn is_path(obj: &Bound<'_, PyAny>) -> bool {
    obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__").unwrap_or(false)
}

/// The trajectory `obj` (a path or an array; `times` for matrices); `what` names it in errors.
pub fn input(
    obj: &Bound<'_, PyAny>,
    times: Option<&Bound<'_, PyAny>>,
    order: QuatOrder,
    what: &str,
) -> PyResult<Input> {
    if is_path(obj) {
        if times.is_some_and(|t| !t.is_none()) {
            return Err(err(format!(
                "{what} is a file, which has its own times; times go with (N, 4, 4) arrays"
            )));
        }
        return Ok(Input::File(obj.extract()?));
    }
    Ok(Input::Poses(poses(obj, times, order, what)?))
}

/// A demonstration ready for the library.
pub enum Prepared {
    /// Object and (optional) palm files.
    Files {
        /// The object's file.
        object: PathBuf,
        /// The palm's file.
        palm: Option<PathBuf>,
    },
    /// Rigid bodies of an OptiTrack Motive take: the object's and (optional) the palm's.
    Take {
        /// The take's CSV export.
        path: PathBuf,
        /// The object's rigid body.
        object: String,
        /// The palm's rigid body.
        palm: Option<String>,
    },
    /// In memory.
    Memory(Demonstration),
}

/// The rigid bodies `rigid_bodies` names (`"box"`, or `("box", "hand")` with the palm's, or
/// `("box", None)`), for Motive takes.
pub fn rigid_bodies(obj: &Bound<'_, PyAny>) -> PyResult<(String, Option<String>)> {
    if let Ok(object) = obj.extract::<String>() {
        return Ok((object, None));
    }
    obj.extract::<(String, Option<String>)>().map_err(|_| {
        err(
            "rigid_bodies must name the object's rigid body, \"box\", or the object's and \
             the palm's, (\"box\", \"hand\")",
        )
    })
}

impl Prepared {
    /// Its [`Source`].
    pub fn source(&self) -> Source<'_> {
        match self {
            Prepared::Files { object, palm } => Source::Files {
                object,
                palm: palm.as_deref(),
            },
            Prepared::Take { path, object, palm } => Source::Take {
                path,
                object,
                palm: palm.as_deref(),
            },
            Prepared::Memory(d) => Source::Memory(d),
        }
    }

    /// Its name in warnings, as the command line writes it: the object file as given, or the
    /// demonstration's name.
    pub fn label(&self) -> String {
        match self {
            Prepared::Files { object, .. } => object.display().to_string(),
            Prepared::Take { path, .. } => path.display().to_string(),
            Prepared::Memory(d) => d.name.clone(),
        }
    }

    /// The object and palm files, if they are files (for `classify`'s `file`, `palm_file`).
    pub fn files(&self) -> (Option<String>, Option<String>) {
        match self {
            Prepared::Files { object, palm } => (
                Some(object.display().to_string()),
                palm.as_ref().map(|p| p.display().to_string()),
            ),
            Prepared::Take { path, palm, .. } => (
                Some(path.display().to_string()),
                palm.as_ref().map(|_| path.display().to_string()),
            ),
            Prepared::Memory(_) => (None, None),
        }
    }
}

/// A demonstration from its object and palm (`None`: `NAME.palm.*` beside an object file,
/// unless `no_palm`); `name` names one in memory unless its object is a file.
pub fn prepare(
    object: Input,
    palm: Option<Input>,
    no_palm: bool,
    name: String,
) -> PyResult<Prepared> {
    let palm = match (palm, &object) {
        (Some(p), _) => Some(p),
        (None, Input::File(f)) if !no_palm => palm_path_for(f).map(Input::File),
        (None, _) => None,
    };
    let read = |i: Input| match i {
        Input::File(f) => read_trajectory(&f).map_err(lib),
        Input::Poses(p) => Ok(p),
    };
    match (object, palm) {
        (Input::File(object), None) => Ok(Prepared::Files { object, palm: None }),
        (Input::File(object), Some(Input::File(palm))) => Ok(Prepared::Files {
            object,
            palm: Some(palm),
        }),
        (object, palm) => {
            let name = match &object {
                Input::File(f) => f
                    .file_name()
                    .map_or(name, |n| n.to_string_lossy().into_owned()),
                Input::Poses(_) => name,
            };
            Ok(Prepared::Memory(Demonstration {
                name,
                object: read(object)?,
                palm: palm.map(read).transpose()?,
            }))
        }
    }
}

/// `obj` as `n` entries parallel to the demonstrations: `None` gives `n` Nones; for a single
/// demonstration given alone (`single`), `obj` is its entry (or a list of its one entry);
/// else `obj` must be a list or tuple of `n` entries (each may be None).
pub fn parallel<'py>(
    obj: Option<&Bound<'py, PyAny>>,
    n: usize,
    single: bool,
    what: &str,
) -> PyResult<Vec<Option<Bound<'py, PyAny>>>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(vec![None; n]);
    };
    if single {
        // Its entry, or a list of that one entry (`palms=[palm]` as for many).
        let one = match obj.cast::<PyList>() {
            Ok(l) if l.len() == 1 => l.get_item(0)?,
            _ => obj.clone(),
        };
        return Ok(vec![Some(one).filter(|o| !o.is_none())]);
    }
    let items: Vec<Bound<'py, PyAny>> =
        if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
            obj.try_iter()?.collect::<PyResult<_>>()?
        } else {
            return Err(err(format!(
                "{what} must be a list with one entry per demonstration (None for none)"
            )));
        };
    if items.len() != n {
        return Err(err(format!(
            "{what} has {} entries for {n} demonstrations",
            items.len()
        )));
    }
    Ok(items
        .into_iter()
        .map(|o| if o.is_none() { None } else { Some(o) })
        .collect())
}

/// The demonstrations argument as a list of items, and whether it was a single one (a path or
/// an array rather than a list of them).
pub fn items<'py>(demos: &Bound<'py, PyAny>) -> PyResult<(Vec<Bound<'py, PyAny>>, bool)> {
    let is_list = demos.is_instance_of::<PyList>() || demos.is_instance_of::<PyTuple>();
    if !is_list {
        return Ok((vec![demos.clone()], true));
    }
    // A list is a list of demonstrations (a demonstration's rows come as a numpy array).
    let v: Vec<Bound<'py, PyAny>> = demos.try_iter()?.collect::<PyResult<_>>()?;
    if v.is_empty() {
        return Err(err("no demonstrations given"));
    }
    Ok((v, false))
}
