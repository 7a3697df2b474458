//! Errors and warnings as Python sees them: [`ObjmodelError`] (a `ValueError`) with the text the
//! command line prints after `objmodel: error: `, and warnings through Python's `warnings`
//! module as [`ObjmodelWarning`] (a `UserWarning`).

use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    objmodel,
    ObjmodelError,
    PyValueError,
    "Bad input or data that cannot give what was asked; the message is the command line's."
);
pyo3::create_exception!(
    objmodel,
    ObjmodelWarning,
    PyUserWarning,
    "What the command line prints as `warning: NAME: ...` on standard error."
);

/// An error's message with its causes, `a: b: c`, as the command line prints it (`{:#}`).
pub fn message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut s = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        s.push_str(": ");
        s.push_str(&c.to_string());
        cause = c.source();
    }
    s
}

/// An [`ObjmodelError`] with this message.
pub fn err(msg: impl Into<String>) -> PyErr {
    ObjmodelError::new_err(msg.into())
}

/// A library error as an [`ObjmodelError`].
pub fn lib(e: objmodel::Error) -> PyErr {
    err(message(&e))
}

/// Issue `warning: NAME: text` (without `warning: `) as an [`ObjmodelWarning`].
pub fn warn(py: Python<'_>, name: &str, text: &str) -> PyResult<()> {
    let category = py.get_type::<ObjmodelWarning>();
    let msg = std::ffi::CString::new(format!("{name}: {text}"))
        .unwrap_or_else(|_| c"(a warning with a NUL byte)".to_owned());
    PyErr::warn(py, &category, &msg, 1)
}
