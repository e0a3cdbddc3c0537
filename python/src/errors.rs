//! The library's errors as Python exceptions: the class of
//! `loopkin.errors` named after each kind, with the library's message and
//! the name and value at fault as attributes.

use kinematics_core::Error;
use pyo3::prelude::*;

/// The exception for `e`: the class of `loopkin.errors` named after its
/// kind, with the library's message, and the name and value at fault as
/// attributes where the error has them.
pub(crate) fn error(py: Python<'_>, e: &Error) -> PyErr {
    let (class, name, value): (&str, Option<&str>, Option<f64>) = match e {
        Error::NotConverged { .. } => ("NotConvergedError", None, None),
        Error::Singular { .. } => ("SingularError", None, None),
        Error::NonFinite { name, value, .. } => ("NonFiniteError", Some(name), Some(*value)),
        Error::InvalidGeometry { .. } => ("InvalidGeometryError", None, None),
        Error::WrongBranch { .. } => ("WrongBranchError", None, None),
        Error::CannotAssemble { .. } => ("CannotAssembleError", None, None),
        Error::Output { .. } => ("OutputError", None, None),
        Error::InvalidParameter { name, value, .. } => {
            ("InvalidParameterError", Some(name), Some(*value))
        }
        Error::InvalidOption { .. } => ("InvalidOptionError", None, None),
        Error::WrongLength { .. } => ("WrongLengthError", None, None),
        Error::InvalidDynamics { .. } => ("InvalidDynamicsError", None, None),
        _ => ("KinematicsError", None, None),
    };
    raise(py, class, &e.to_string(), |inst| {
        if let Some(name) = name {
            inst.setattr("name", name)?;
        }
        if let Some(value) = value {
            inst.setattr("value", value)?;
        }
        Ok(())
    })
}

/// An instance of the exception class `class` of `loopkin.errors` with the
/// message `message`, its attributes set by `attributes`.
pub(crate) fn raise(
    py: Python<'_>,
    class: &str,
    message: &str,
    attributes: impl FnOnce(&Bound<'_, PyAny>) -> PyResult<()>,
) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let cls = py.import("loopkin.errors")?.getattr(class)?;
        let inst = cls.call1((message,))?;
        attributes(&inst)?;
        Ok(PyErr::from_value(inst))
    })();
    made.unwrap_or_else(|e| e)
}
