//! JSON values as Python objects (dicts, lists, floats, ...), through Python's `json` module:
//! exactly what `json.loads` of the command line's output gives.

use pyo3::prelude::*;

/// `json.loads` of `v`'s text.
pub fn to_python(py: Python<'_>, v: &serde_json::Value) -> PyResult<Py<PyAny>> {
    text_to_python(py, &v.to_string())
}

/// `json.loads(text)`.
pub fn text_to_python(py: Python<'_>, text: &str) -> PyResult<Py<PyAny>> {
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}
