//! Plain values across the boundary: technique parameters from keyword arguments (by the
//! command line's names, read by the one definition in `gnomon-tools`) and JSON values as
//! Python dicts and lists.

use gnomon::Technique;
use gnomon_tools::TechniqueParams;
use gnomon_tools::params::ParamValue;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};
use serde_json::Value;

use crate::gnomon_error;

/// The technique parameters of keyword arguments: the command line's options with `_` for
/// `-` (`cascade_split="log"`, `stable=True`, `cascades=3`); `None` leaves one at its
/// default and a list of numbers is written comma-separated (`cascade_split=[10, 40]`).
pub(crate) fn params(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<TechniqueParams> {
    // The defaults without building the parser: a frame loop's call stays cheap.
    if kwargs.is_none_or(|d| d.is_empty()) {
        return Ok(TechniqueParams::default());
    }
    let mut values = Vec::new();
    for (key, value) in kwargs.into_iter().flat_map(|d| d.iter()) {
        let name: String = key.extract()?;
        if value.is_none() {
            continue;
        }
        values.push((name.clone(), param_value(&name, &value)?));
    }
    TechniqueParams::from_named(&values).map_err(gnomon_error)
}

fn param_value(name: &str, value: &Bound<'_, PyAny>) -> PyResult<ParamValue> {
    if let Ok(flag) = value.cast::<PyBool>() {
        return Ok(ParamValue::Flag(flag.is_true()));
    }
    if value.is_instance_of::<PyString>()
        || value.is_instance_of::<PyInt>()
        || value.is_instance_of::<PyFloat>()
    {
        return Ok(ParamValue::Text(value.str()?.to_string()));
    }
    if let Ok(items) = value.extract::<Vec<f64>>() {
        let words: Vec<String> = items.iter().map(f64::to_string).collect();
        return Ok(ParamValue::Text(words.join(",")));
    }
    Err(gnomon_error(format!(
        "{name}: expected a number, a string, True or False, or a list of numbers"
    )))
}

/// The technique `name` with the keyword arguments' parameters.
pub(crate) fn technique(name: &str, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Technique> {
    gnomon_tools::map_technique(name, &params(kwargs)?).map_err(gnomon_error)
}

/// A JSON value as Python objects: dicts, lists, numbers, strings, booleans and None.
pub(crate) fn json_to_py<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match (n.as_u64(), n.as_i64()) {
            (Some(u), _) => u.into_pyobject(py)?.into_any(),
            (None, Some(i)) => i.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, json_to_py(py, v)?)?;
            }
            dict.into_any()
        }
    })
}
