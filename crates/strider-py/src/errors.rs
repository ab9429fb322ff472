//! Library errors as Python exceptions.

use pyo3::PyErr;
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;

create_exception!(
    _strider,
    StriderError,
    PyValueError,
    "An error of the Strider library, with the one-line message the `strider` command prints."
);

/// `e` as a `StriderError` with the command's one-line message.
pub fn to_py(e: anyhow::Error) -> PyErr {
    StriderError::new_err(strider_experiments::io::error_line(&e))
}

/// A message as a `StriderError`.
pub fn msg(text: impl Into<String>) -> PyErr {
    StriderError::new_err(text.into())
}
