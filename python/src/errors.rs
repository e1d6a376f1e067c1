//! The library's errors as the Python exceptions of `freefloat._errors`: `BadInput` when
//! [`freefloat::Error::is_bad_input`], `NotCertified` for [`freefloat::Error::NotCertified`] (and a
//! plan over a limit or under the clearance),
//! `NoPlan` for everything else; each carries the library's message and its numbers.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::{Value, json};

use crate::compat::InputError;
use crate::convert::json_dict;

/// An error of the bindings: the library's, or an option string that names nothing.
#[derive(Debug)]
pub enum BindingError {
    /// The library's error.
    Library(freefloat::Error),
    /// A string option (`method`, `transform`, `window`) that is none of the accepted names.
    UnknownChoice {
        /// The keyword, e.g. `method`.
        name: &'static str,
        /// What was given.
        value: String,
        /// What is accepted.
        allowed: &'static [&'static str],
    },
    /// Keywords of one method given, with values other than their defaults, to another.
    Misplaced {
        /// The keywords, e.g. `transform`.
        keywords: &'static str,
        /// The method they apply to.
        owner: &'static str,
        /// The method asked for.
        method: &'static str,
    },
    /// A key or keyword that the bindings check themselves (a link's missing or unknown key, a
    /// method `plan_arm` does not have), named as the robot file or the signature names it.
    Key {
        /// The error's kind, e.g. `missing_key`.
        kind: &'static str,
        /// The key, e.g. `link[2].mass`.
        name: String,
        /// The message.
        message: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// A keyword that needs another one (`elbow` without `goal_ee`), or two that exclude each
    /// other (`goal` and `goal_ee`).
    Conflict {
        /// What is wrong, as the message says it.
        message: &'static str,
    },
}

impl From<freefloat::Error> for BindingError {
    fn from(e: freefloat::Error) -> Self {
        BindingError::Library(e)
    }
}

impl From<InputError> for BindingError {
    fn from(e: InputError) -> Self {
        BindingError::Library(e.into())
    }
}

impl BindingError {
    /// The Python exception.
    pub fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            BindingError::Library(e) => library_error(py, &e, None),
            BindingError::UnknownChoice { name, value, allowed } => {
                let message = format!("invalid {name} {value:?}: expected one of {}", allowed.join(", "));
                let details = json!({ "name": name, "value": value, "expected": allowed.join(" | ") });
                raise(py, "BadInput", message, "unknown_choice", &details, None)
            }
            BindingError::Misplaced { keywords, owner, method } => {
                let message = format!("{keywords} apply to method={owner:?}, not to method={method:?}");
                let details = json!({ "name": keywords, "expected": format!("method={owner:?}"), "method": method });
                raise(py, "BadInput", message, "misplaced_option", &details, None)
            }
            BindingError::Key { kind, name, message, expected } => {
                let details = json!({ "name": name, "expected": expected });
                raise(py, "BadInput", format!("{message}: expected {expected}"), kind, &details, None)
            }
            BindingError::Conflict { message } => {
                raise(py, "BadInput", message.to_string(), "conflicting_options", &json!({}), None)
            }
        }
    }
}

/// The exception of a library error; `plan` (a `freefloat.Plan`) is attached to `NotCertified`.
pub fn library_error(py: Python<'_>, e: &freefloat::Error, plan: Option<Bound<'_, PyAny>>) -> PyErr {
    let class = match e {
        e if e.is_bad_input() => "BadInput",
        // A plan that exists but breaks a limit or the clearance is not certified (it is attached).
        freefloat::Error::NotCertified { .. }
        | freefloat::Error::LimitExceeded { .. }
        | freefloat::Error::Collision { .. } => "NotCertified",
        _ => "NoPlan",
    };
    raise(py, class, e.to_string(), &kind(e), &details(e), plan)
}

/// Instantiates `freefloat._errors.<class>(message, kind=..., details=..., plan=...)`.
fn raise(
    py: Python<'_>,
    class: &str,
    message: String,
    kind: &str,
    details: &Value,
    plan: Option<Bound<'_, PyAny>>,
) -> PyErr {
    let build = || -> PyResult<PyErr> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("kind", kind)?;
        let map = details.as_object().cloned().unwrap_or_default();
        kwargs.set_item("details", json_dict(py, &map)?)?;
        if let Some(plan) = plan {
            kwargs.set_item("plan", plan)?;
        }
        let class = py.import("freefloat._errors")?.getattr(class)?;
        Ok(PyErr::from_value(class.call((message,), Some(&kwargs))?))
    };
    build().unwrap_or_else(|e| e)
}

/// The variant's name in snake case (`InvalidParameter` -> `invalid_parameter`), read from its
/// `Debug` form so that variants added later are named too.
fn kind(e: &freefloat::Error) -> String {
    let debug = match e {
        freefloat::Error::Input(inner) => format!("{inner:?}"),
        e => format!("{e:?}"),
    };
    let name = debug.split([' ', '{', '(']).next().unwrap_or_default();
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.extend(c.to_lowercase());
    }
    out
}

/// The numbers of an error, by the names of its fields (radians, seconds): the library's
/// [`freefloat::Error::numbers`], the `numbers` of the CLI's JSON error object.
fn details(e: &freefloat::Error) -> Value {
    e.numbers()
}

/// `Err(library error)` as a Python exception.
pub trait IntoPyResult<T> {
    /// The Python result.
    fn py_result(self, py: Python<'_>) -> PyResult<T>;
}

impl<T, E: Into<BindingError>> IntoPyResult<T> for Result<T, E> {
    fn py_result(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| e.into().into_pyerr(py))
    }
}
