//! `objmodel.Tree`: the object description tree, its file, its features as numpy arrays, and
//! its export as a simulation model (MJCF, URDF) through [`objmodel::export`].

use crate::error::{err, lib};
use crate::json::text_to_python;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use objmodel::export::{mjcf::mjcf, urdf::urdf, Body};
use objmodel::format::write_atomic;
use objmodel::tree::Tree;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// An object description tree: edges, faces, their pendulums, the centre of mass and the
/// shape, in the object frame (the tracked frame whose poses the demonstrations give), SI units.
///
/// `Tree()` is empty; `Tree.load(path)` reads a file written by `save` or `objmodel learn -o`.
/// The arrays (`edges`, `faces`, `pendulums`, `com`, `vertices`) are copies; `to_dict()` is
/// everything, as the tree file's JSON (docs/tree-schema.md).
#[pyclass(name = "Tree", module = "objmodel")]
#[derive(Clone)]
pub struct PyTree {
    /// The library's tree.
    pub tree: Tree,
}

impl From<Tree> for PyTree {
    fn from(tree: Tree) -> Self {
        PyTree { tree }
    }
}

/// `rows` (each `k` values) as a `(len, k)` array.
fn array2<'py>(
    py: Python<'py>,
    rows: Vec<Vec<f64>>,
    k: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    let flat: Vec<f64> = rows.into_iter().flatten().collect();
    PyArray1::from_vec(py, flat).reshape([n, k])
}

/// The stem of `path`, for a model's name.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or("object".into(), |s| s.to_string_lossy().into_owned())
}

impl PyTree {
    /// The body to export, its notes being the command line's.
    fn body(&self, mass: f64, friction: Option<f64>) -> PyResult<Body> {
        Body::from_tree(&self.tree, mass, friction).map_err(lib)
    }
}

#[pymethods]
impl PyTree {
    /// Column names of `edges`: a point of the edge line (the one closest to the object
    /// origin) and its unit direction.
    #[classattr]
    const EDGE_COLUMNS: (
        &'static str,
        &'static str,
        &'static str,
        &'static str,
        &'static str,
        &'static str,
    ) = ("px", "py", "pz", "dx", "dy", "dz");
    /// Column names of `faces`: the unit normal and the offset of the plane n·x = offset
    /// (NaN when the data do not give it, e.g. a face seen only in a slide).
    #[classattr]
    const FACE_COLUMNS: (&'static str, &'static str, &'static str, &'static str) =
        ("nx", "ny", "nz", "offset");
    /// Column names of `pendulums`: the row of its edge in `edges`, the resting face's outward
    /// normal, the toppling axis, φ [rad] (the tipping angle from the vertical), its standard
    /// deviation, l_p [m] and the inertia ratio [m] (NaN when unknown).
    #[classattr]
    const PENDULUM_COLUMNS: [&'static str; 11] = [
        "edge",
        "nx",
        "ny",
        "nz",
        "ax",
        "ay",
        "az",
        "phi",
        "phi_sigma",
        "l_p",
        "inertia_ratio_m",
    ];

    /// An empty tree.
    #[new]
    fn new() -> Self {
        PyTree::from(Tree::default())
    }

    /// Read a tree file (its schema and version checked).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        py.detach(|| Tree::load(&path))
            .map(PyTree::from)
            .map_err(lib)
    }

    /// Write the tree to `path` atomically (a reader sees the old file or the new one).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        self.tree.save(&path).map_err(lib)
    }

    /// Edges, an (E, 6) array: `EDGE_COLUMNS` [m].
    #[getter]
    fn edges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows = self
            .tree
            .edges
            .iter()
            .map(|e| {
                vec![
                    e.point.x,
                    e.point.y,
                    e.point.z,
                    e.direction.x,
                    e.direction.y,
                    e.direction.z,
                ]
            })
            .collect();
        array2(py, rows, 6)
    }

    /// Faces, an (F, 4) array: `FACE_COLUMNS`.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows = self
            .tree
            .faces
            .iter()
            .map(|f| {
                vec![
                    f.normal.x,
                    f.normal.y,
                    f.normal.z,
                    f.offset.unwrap_or(f64::NAN),
                ]
            })
            .collect();
        array2(py, rows, 4)
    }

    /// Pendulums (one per edge and resting face), a (P, 11) array: `PENDULUM_COLUMNS`.
    #[getter]
    fn pendulums<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let nan = |x: Option<f64>| x.unwrap_or(f64::NAN);
        let mut rows = Vec::new();
        for (i, e) in self.tree.edges.iter().enumerate() {
            for p in &e.pendulums {
                let (n, a) = (p.resting_face_normal, p.toppling_axis);
                rows.push(vec![
                    i as f64,
                    n.x,
                    n.y,
                    n.z,
                    a.x,
                    a.y,
                    a.z,
                    nan(p.phi),
                    nan(p.phi_sigma),
                    nan(p.l_p),
                    nan(p.inertia_ratio_m),
                ]);
            }
        }
        array2(py, rows, 11)
    }

    /// The centre of mass [m], a (3,) array, or None when neither the pendulums nor the flights
    /// determine it.
    #[getter]
    fn com<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.tree
            .com
            .as_ref()
            .map(|c| PyArray1::from_vec(py, vec![c.point.x, c.point.y, c.point.z]))
    }

    /// The shape's vertices [m], a (V, 3) array, or None when the faces close no shape.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.tree
            .shape
            .as_ref()
            .map(|s| {
                array2(
                    py,
                    s.vertices.iter().map(|v| vec![v.x, v.y, v.z]).collect(),
                    3,
                )
            })
            .transpose()
    }

    /// The names of the demonstrations learnt from, in order.
    #[getter]
    fn demos(&self) -> Vec<String> {
        self.tree.demos.iter().map(|d| d.name.clone()).collect()
    }

    /// The tree as the tree file's JSON text.
    fn to_json(&self) -> String {
        self.tree.to_json()
    }

    /// The tree as a dict: `json.loads` of its file.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        text_to_python(py, &self.tree.to_json())
    }

    /// Write the object as an MJCF model (MuJoCo) to `path`, atomically: its shape (a box or
    /// a mesh), the centre of mass and inertia of the learnt tree, `mass` [kg] (poses cannot
    /// tell it: weigh the object), `friction` (default 0.8). `name`: the body's and model's
    /// name (default the file's stem). Returns the notes of where each property came from.
    #[pyo3(signature = (path, mass, *, friction=None, name=None))]
    fn export_mjcf(
        &self,
        path: PathBuf,
        mass: f64,
        friction: Option<f64>,
        name: Option<String>,
    ) -> PyResult<Vec<String>> {
        let body = self.body(mass, friction)?;
        let name = name.unwrap_or_else(|| stem(&path));
        write_atomic(&path, mjcf(&body, &name).as_bytes()).map_err(lib)?;
        Ok(body.notes)
    }

    /// Write the object as a URDF to `path`, atomically; a shape that is not a box goes to a
    /// mesh NAME.obj beside it. Arguments and result as `export_mjcf`.
    #[pyo3(signature = (path, mass, *, friction=None, name=None))]
    fn export_urdf(
        &self,
        path: PathBuf,
        mass: f64,
        friction: Option<f64>,
        name: Option<String>,
    ) -> PyResult<Vec<String>> {
        let body = self.body(mass, friction)?;
        let name = name.unwrap_or_else(|| stem(&path));
        let mesh = path.with_extension("obj");
        let mesh_name = mesh
            .file_name()
            .map_or("object.obj".into(), |s| s.to_string_lossy().into_owned());
        let (text, obj) = urdf(&body, &name, &mesh_name);
        if let Some(obj) = obj {
            write_atomic(&mesh, obj.as_bytes()).map_err(lib)?;
        }
        write_atomic(&path, text.as_bytes()).map_err(lib)?;
        Ok(body.notes)
    }

    fn __repr__(&self) -> String {
        let t = &self.tree;
        format!(
            "<objmodel.Tree: {} demonstrations, {} edges, {} faces, {} pendulums, CoM {}, shape {}>",
            t.demos.len(),
            t.edges.len(),
            t.faces.len(),
            t.edges.iter().map(|e| e.pendulums.len()).sum::<usize>(),
            if t.com.is_some() { "known" } else { "unknown" },
            if t.shape.is_some() { "closed" } else { "open" }
        )
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.tree == other.tree
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
}

/// A tree argument: a Tree or a tree file's path.
pub fn tree_arg(obj: &Bound<'_, PyAny>) -> PyResult<Tree> {
    if let Ok(t) = obj.cast::<PyTree>() {
        return Ok(t.borrow().tree.clone());
    }
    let path: PathBuf = obj
        .extract()
        .map_err(|_| err("expected a Tree or a tree file's path"))?;
    Tree::load(&path).map_err(lib)
}
