//! `objmodel.learn` and `objmodel.classify`: the library's one learning pipeline
//! ([`objmodel::learn::Learner`]) on demonstrations given as files or arrays.

use crate::config::{config, Gravity};
use crate::error::{err, lib, warn};
use crate::inputs::{input, items, parallel, prepare, Prepared};
use crate::json::to_python;
use crate::poses::QuatOrder;
use crate::tree::PyTree;
use objmodel::format::is_palm_file;
use objmodel::learn::{nothing_to_learn, Learner, LeftOut, Source};
use objmodel::observation::Observation;
use objmodel::tree::Tree;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// The demonstrations of `learn`'s arguments, in order.
#[allow(clippy::too_many_arguments)]
fn demonstrations(
    demos: &Bound<'_, PyAny>,
    palms: Option<&Bound<'_, PyAny>>,
    times: Option<&Bound<'_, PyAny>>,
    names: Option<&Bound<'_, PyAny>>,
    no_palm: bool,
    order: QuatOrder,
    bodies: Option<&(String, Option<String>)>,
) -> PyResult<Vec<Prepared>> {
    let (items, single) = items(demos)?;
    let n = items.len();
    let explicit_palms = palms.is_some_and(|p| !p.is_none());
    if let Some((object, palm)) = bodies {
        return takes(&items, explicit_palms, object, palm.as_deref());
    }
    let palms = parallel(palms, n, single, "palms")?;
    let times = parallel(times, n, single, "times")?;
    let names = parallel(names, n, single, "names")?;
    let mut out = Vec::new();
    for (i, (((item, palm), t), name)) in items.iter().zip(palms).zip(times).zip(names).enumerate()
    {
        let what = if single {
            "demos".to_string()
        } else {
            format!("demos[{i}]")
        };
        let object = input(item, t.as_ref(), order, &what)?;
        // As on the command line: palm files among the demonstrations are their palms, found
        // beside them, not demonstrations.
        if let crate::inputs::Input::File(f) = &object {
            if !explicit_palms && is_palm_file(f) {
                continue;
            }
        }
        let palm = palm
            .map(|p| {
                let pw = if single {
                    "palms".to_string()
                } else {
                    format!("palms[{i}]")
                };
                input(&p, t.as_ref(), order, &pw)
            })
            .transpose()?;
        let name = match name {
            Some(n) => n.extract::<String>()?,
            None => format!("demo{i}"),
        };
        out.push(prepare(object, palm, no_palm, name)?);
    }
    if out.is_empty() {
        return Err(err("no demonstration files (only palm files were given)"));
    }
    Ok(out)
}

/// Motive takes `items` (files), each read by its rigid bodies `object` and `palm`; a take's
/// palm is one of its bodies, so `palms` may not be given (`explicit_palms`).
fn takes(
    items: &[Bound<'_, PyAny>],
    explicit_palms: bool,
    object: &str,
    palm: Option<&str>,
) -> PyResult<Vec<Prepared>> {
    if explicit_palms {
        return Err(err(
            "rigid_bodies names the palm's body in each take: palms may not be given too",
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, item)| {
            if !crate::inputs::is_path(item) {
                return Err(err(format!(
                    "demos[{i}] is not a file: rigid_bodies names the bodies of Motive takes \
                     (CSV exports)"
                )));
            }
            Ok(Prepared::Take {
                path: item.extract()?,
                object: object.to_string(),
                palm: palm.map(str::to_string),
            })
        })
        .collect()
}

/// Learn `prepared` into `tree` (all of them or, on an error, none; with `keep_going`, those
/// that can be read: [`Learner::learn_readable`], each left out warned of); the reports and
/// the demonstrations they are of.
fn learn_all<'p>(
    py: Python<'_>,
    learner: &Learner,
    tree: &mut Tree,
    prepared: &'p [Prepared],
    keep_going: bool,
) -> PyResult<(Vec<Observation>, Vec<&'p Prepared>)> {
    let sources: Vec<Source> = prepared.iter().map(Prepared::source).collect();
    let (reports, left_out) = py
        .detach(|| learnt(learner, tree, &sources, keep_going))
        .map_err(lib)?;
    Ok((reports, kept(py, prepared, &left_out)?))
}

/// `prepared` but those left out, each of which is warned of.
fn kept<'p>(
    py: Python<'_>,
    prepared: &'p [Prepared],
    left_out: &[LeftOut],
) -> PyResult<Vec<&'p Prepared>> {
    let mut kept = Vec::with_capacity(prepared.len());
    for (k, p) in prepared.iter().enumerate() {
        match left_out.iter().find(|l| l.index == k) {
            Some(l) => warn(
                py,
                &p.label(),
                &format!(
                    "could not be read and was left out (keep_going): {}",
                    l.error
                ),
            )?,
            None => kept.push(p),
        }
    }
    Ok(kept)
}

/// `sources` learnt into `tree` as [`learn_all`] says: the reports and those left out.
fn learnt(
    learner: &Learner,
    tree: &mut Tree,
    sources: &[Source],
    keep_going: bool,
) -> objmodel::Result<(Vec<Observation>, Vec<LeftOut>)> {
    if keep_going {
        return learner.learn_readable(tree, sources, |_| {});
    }
    let mut work = tree.clone();
    let reports = learner.learn(&mut work, sources)?;
    *tree = work;
    Ok((reports, Vec::new()))
}

/// Each report's warnings, as the command line prints them, then each edge of `tree` held
/// back as too loosely located to be taught: the edges array leaves them out, and the warning
/// says why and that another demonstration of the edge would teach it (as `objmodel learn`
/// prints them).
fn warn_reports(
    py: Python<'_>,
    prepared: &[&Prepared],
    reports: &[Observation],
    tree: &Tree,
) -> PyResult<()> {
    // Kept out by the gravity check: an error that says which gravity the demonstrations show.
    if let Some(why) = reports.iter().find_map(|r| r.not_learnt.as_ref()) {
        return Err(err(why.clone()));
    }
    for (p, r) in prepared.iter().zip(reports) {
        for w in &r.classification.warnings {
            warn(py, &p.label(), w)?;
        }
    }
    for w in tree.unlocated_edges() {
        warn(py, "held back", &w.why)?;
    }
    Ok(())
}

/// `learner`, told that the demonstrations given as arrays were read from quaternions in its
/// order where no `times` are given: arrays are then (N, 8) rows `t x y z q q q q`, and the
/// learner checks that order against their motion as it does a TUM file's (matrices, which
/// need times, have no order to check).
fn rows_read_in(learner: Learner, times: Option<&Bound<'_, PyAny>>) -> Learner {
    match times.filter(|t| !t.is_none()) {
        None => learner.with_memory_quaternions(),
        Some(_) => learner,
    }
}

/// Learn (or update) an object description tree from demonstrations.
///
/// `demos`: a list of demonstrations (or one alone), each a pose file (str or os.PathLike,
/// TUM or CSV; NAME.palm.* beside it is its palm, as on the command line) or a numpy array of
/// `world_from_object` poses: (N, 8) rows `t x y z qx qy qz qw` (quaternion x y z w, as TUM
/// files and scipy's `as_quat()`; `quat_order="wxyz"` for `t x y z qw qx qy qz`, in arrays
/// and in TUM files written w first: rows or a TUM file whose motion turns about an edge only
/// in the other order teach nothing, with a warning that names it) or (N, 4, 4)
/// homogeneous matrices with `times`. A row whose pose values are all NaN (or all zero), or a
/// matrix NaN above its last row, is a frame where the tracker lost the object: left out,
/// with a warning.
/// `palms`: one per demonstration (None: none, or NAME.palm.* for a file), the palm's
/// `world_from_palm` poses the same way; palm matrices take their demonstration's times.
/// `times`: one (N,) array per demonstration given as matrices. `names`: names of
/// demonstrations given as arrays (default `demo0`, `demo1`, ...; a file's is its name).
/// `gravity`: in the tracking frame, default (0, 0, -1) (z up); None if unknown.
/// `into`: a Tree to fuse into (changed in place and returned) or a tree file (read, updated
/// and written back atomically under a lock, as `objmodel learn --into`; left as it was when
/// nothing is learnt). `method`: "robust" (default) or "paper"; `gravity_check`: check the
/// gravity given against the demonstrations (their rests' vertical, their flights' fall) and
/// raise, naming the gravity they show, where they contradict it (False: learn anyway, as
/// `--no-gravity-check`); `rigid_bodies`: for OptiTrack Motive takes (CSV exports) holding
/// several rigid bodies, the object's, `"box"`, or the object's and the palm's, `("box",
/// "hand")`, read from each file of `demos` (as `--object box --palm hand`);
/// `support_height`: the support's height [m] along -gravity in the tracking frame, when it
/// is known (as `--support-height`: the rests then give their faces offsets), known to
/// `support_sigma` [m] (default 0.001); `**options`:
/// the command line's thresholds (`alpha`, `min_rest`,
/// `noise_position`, ...) and `length_unit` ("m", "cm" or "mm": the unit of the positions
/// given as arrays, and of files that do not declare theirs; default metres, checked).
///
/// Returns the Tree. Warnings are ObjmodelWarning (among them each edge held back as too
/// loosely located to be taught); errors ObjmodelError, with the command
/// line's messages. All demonstrations are learnt or, on an error, none; with
/// `keep_going=True`, a demonstration whose file cannot be read is left out with an
/// ObjmodelWarning that gives its error, and the others are learnt (as `objmodel learn
/// --keep-going`).
#[pyfunction]
#[pyo3(
    signature = (demos, *, palms=None, times=None, names=None, gravity=Gravity::default(), into=None, no_palm=false, quat_order="xyzw", method="robust", gravity_check=true, rigid_bodies=None, support_height=None, support_sigma=1e-3, keep_going=false, **options),
    text_signature = "(demos, *, palms=None, times=None, names=None, gravity=(0, 0, -1), into=None, no_palm=False, quat_order='xyzw', method='robust', gravity_check=True, rigid_bodies=None, support_height=None, support_sigma=0.001, keep_going=False, **options)"
)]
#[allow(clippy::too_many_arguments)]
pub fn learn(
    py: Python<'_>,
    demos: &Bound<'_, PyAny>,
    palms: Option<&Bound<'_, PyAny>>,
    times: Option<&Bound<'_, PyAny>>,
    names: Option<&Bound<'_, PyAny>>,
    gravity: Gravity,
    into: Option<&Bound<'_, PyAny>>,
    no_palm: bool,
    quat_order: &str,
    method: &str,
    gravity_check: bool,
    rigid_bodies: Option<&Bound<'_, PyAny>>,
    support_height: Option<f64>,
    support_sigma: f64,
    keep_going: bool,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyTree>> {
    let order = crate::poses::quat_order(quat_order)?;
    let bodies = rigid_bodies
        .filter(|b| !b.is_none())
        .map(crate::inputs::rigid_bodies)
        .transpose()?;
    let learner = Learner::new(config(gravity, method, options)?.with_quaternion_order(order));
    let learner = rows_read_in(learner, times);
    let learner = if gravity_check {
        learner
    } else {
        learner.without_gravity_check()
    };
    let learner = match support_height {
        Some(h) => learner.with_support(h, support_sigma).map_err(|e| {
            err(format!(
                "support_height {h}, support_sigma {support_sigma}: {e}"
            ))
        })?,
        None => learner,
    };
    let prepared = demonstrations(demos, palms, times, names, no_palm, order, bodies.as_ref())?;
    match into {
        None => {
            let mut tree = Tree::default();
            let (reports, kept) = learn_all(py, &learner, &mut tree, &prepared, keep_going)?;
            warn_reports(py, &kept, &reports, &tree)?;
            Py::new(py, PyTree::from(tree))
        }
        Some(t) if t.is_instance_of::<PyTree>() => {
            let t = t.cast::<PyTree>()?;
            let (reports, kept) = learn_all(
                py,
                &learner,
                &mut t.borrow_mut().tree,
                &prepared,
                keep_going,
            )?;
            warn_reports(py, &kept, &reports, &t.borrow().tree)?;
            Ok(t.clone().unbind())
        }
        Some(path) => {
            let path: PathBuf = path
                .extract()
                .map_err(|_| err("into must be a Tree or a tree file's path"))?;
            let sources: Vec<Source> = prepared.iter().map(Prepared::source).collect();
            let (reports, left_out, tree) = py
                .detach(|| {
                    Tree::update(&path, |tree| {
                        let (reports, left_out) = learnt(&learner, tree, &sources, keep_going)?;
                        let changed = reports.iter().any(|r| r.learnt());
                        Ok(((reports, left_out, tree.clone()), changed))
                    })
                })
                .map_err(lib)?;
            warn_reports(py, &kept(py, &prepared, &left_out)?, &reports, &tree)?;
            Py::new(py, PyTree::from(tree))
        }
    }
}

/// Classify one demonstration: topple, slide or general, and why (Algorithms 1 and 2).
///
/// `demo`, `palm`, `times`: as one demonstration of `learn` (a file, or an (N, 8) or
/// (N, 4, 4) array); `name` names an array's demonstration (default `demo`); `no_palm`
/// ignores NAME.palm.* beside a file. `gravity`, `quat_order`, `method`, `rigid_bodies`,
/// `**options`: as for `learn`. Returns a dict: the JSON of `objmodel classify --json` (`kind`, `segments`,
/// `edges`, `faces`, `warnings`, ..., `file` and `palm_file`, None for arrays).
#[pyfunction]
#[pyo3(
    signature = (demo, *, palm=None, times=None, name=None, gravity=Gravity::default(), no_palm=false, quat_order="xyzw", method="robust", rigid_bodies=None, **options),
    text_signature = "(demo, *, palm=None, times=None, name=None, gravity=(0, 0, -1), no_palm=False, quat_order='xyzw', method='robust', rigid_bodies=None, **options)"
)]
#[allow(clippy::too_many_arguments)]
pub fn classify(
    py: Python<'_>,
    demo: &Bound<'_, PyAny>,
    palm: Option<&Bound<'_, PyAny>>,
    times: Option<&Bound<'_, PyAny>>,
    name: Option<String>,
    gravity: Gravity,
    no_palm: bool,
    quat_order: &str,
    method: &str,
    rigid_bodies: Option<&Bound<'_, PyAny>>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let order = crate::poses::quat_order(quat_order)?;
    let learner = Learner::new(config(gravity, method, options)?.with_quaternion_order(order));
    let times = times.filter(|t| !t.is_none());
    let learner = rows_read_in(learner, times);
    let palm = palm.filter(|p| !p.is_none());
    let prepared = match rigid_bodies.filter(|b| !b.is_none()) {
        Some(b) => {
            let (object, palm_body) = crate::inputs::rigid_bodies(b)?;
            takes(
                std::slice::from_ref(demo),
                palm.is_some(),
                &object,
                palm_body.as_deref(),
            )?
            .remove(0)
        }
        None => {
            let object = input(demo, times, order, "demo")?;
            let palm = palm.map(|p| input(p, times, order, "palm")).transpose()?;
            prepare(object, palm, no_palm, name.unwrap_or_else(|| "demo".into()))?
        }
    };
    let c = py
        .detach(|| learner.classify(&prepared.source()))
        .map_err(lib)?;
    if c.segments.is_empty() {
        return Err(err(format!(
            "{}: {}",
            prepared.label(),
            nothing_to_learn(&c)
        )));
    }
    for w in &c.warnings {
        warn(py, &prepared.label(), w)?;
    }
    let mut v = serde_json::to_value(&c).map_err(|e| err(e.to_string()))?;
    let (file, palm_file) = prepared.files();
    v["file"] = serde_json::json!(file);
    v["palm_file"] = serde_json::json!(palm_file);
    to_python(py, &v)
}
