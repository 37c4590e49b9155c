//! Conversions between Python values and the Rust types: plain Python data (dicts, lists,
//! numbers, numpy scalars) into `serde_json` values that deserialize into the problem-file schema
//! of `contactdd_io::problem` (so a support dict is checked exactly like a TOML support table),
//! and flat `Vec`s into numpy arrays.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::Value;

/// Why a Python value cannot become problem data.
pub enum Bad {
    /// A Python error (e.g. a type that cannot be converted): raised as it is.
    Py(PyErr),
    /// A bad value, with its path (`supports[0].value: must be finite, got NaN`): the caller
    /// names the body or pair.
    Value(String),
}

impl From<PyErr> for Bad {
    fn from(e: PyErr) -> Bad {
        Bad::Py(e)
    }
}

/// Converts plain Python data into a JSON value. numpy arrays and scalars are converted through
/// their `tolist()`. Non-finite floats are rejected (`what` is the value's path in the message).
pub fn to_json(obj: &Bound<'_, PyAny>, what: &str) -> Result<Value, Bad> {
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if obj.is_instance_of::<PyBool>() {
        return Ok(Value::Bool(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(Value::String(obj.extract()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut map = serde_json::Map::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("{what}: dictionary keys must be strings"))
            })?;
            let value = to_json(&v, &format!("{what}.{key}"))?;
            map.insert(key, value);
        }
        return Ok(Value::Object(map));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            items.push(to_json(&v?, &format!("{what}[{i}]"))?);
        }
        return Ok(Value::Array(items));
    }
    if obj.is_instance_of::<PyInt>() {
        if let Ok(i) = obj.extract::<i64>() {
            return Ok(Value::from(i));
        }
        return Ok(Value::from(obj.extract::<u64>()?));
    }
    if obj.is_instance_of::<PyFloat>() {
        let x: f64 = obj.extract()?;
        return serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| Bad::Value(format!("{what}: must be finite, got {x}")));
    }
    if obj.hasattr("tolist")? {
        // numpy arrays and scalars
        return to_json(&obj.call_method0("tolist")?, what);
    }
    Err(Bad::Py(PyTypeError::new_err(format!(
        "{what}: cannot use a value of type {}",
        obj.get_type().name()?
    ))))
}

/// Parses a kebab-case name into a schema enum (e.g. `"strain"` into `Plane::Strain`); the error
/// is serde's message (`unknown variant ..., expected ...`).
pub fn from_name<T: serde::de::DeserializeOwned>(name: &str) -> Result<T, String> {
    serde_json::from_value(Value::String(name.to_string())).map_err(|e| e.to_string())
}

/// The kebab-case name of a schema enum value.
pub fn name_of<T: serde::Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(Value::String(s)) => s,
        Ok(other) => other.to_string(),
        Err(e) => e.to_string(),
    }
}

/// A flat row-major vector as an `rows × cols` numpy array.
pub fn array2<'py, T: numpy::Element>(
    py: Python<'py>,
    flat: Vec<T>,
    cols: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let rows = flat.len().checked_div(cols).unwrap_or(0);
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows, cols])?
        .into_any())
}

/// A vector as a 1-D numpy array.
pub fn array1<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}
