//! Conversions between Python values and the Rust types: plain Python data (dicts, lists,
//! numbers, numpy scalars) into `serde_json` values that deserialize into the problem-file schema
//! of `contactdd_io::problem` (so a support dict is checked exactly like a TOML support table),
//! and flat `Vec`s into numpy arrays.

use numpy::{PyArray1, PyArrayMethods};
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
            let key: String = k
                .extract()
                .map_err(|_| Bad::Value(format!("{what}: dictionary keys must be strings")))?;
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
        if let Ok(u) = obj.extract::<u64>() {
            return Ok(Value::from(u));
        }
        return Err(Bad::Value(format!(
            "{what}: the integer {} is out of range",
            shown_int(obj)
        )));
    }
    if obj.is_instance_of::<PyFloat>() {
        let x: f64 = obj.extract()?;
        return serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| Bad::Value(format!("{what}: must be finite, got {}", shown(x))));
    }
    if obj.hasattr("tolist")? {
        // numpy arrays and scalars
        return to_json(&obj.call_method0("tolist")?, what);
    }
    Err(Bad::Value(format!(
        "{what}: cannot use a value of type {}",
        obj.get_type().name()?
    )))
}

/// A number as messages show it: as Rust writes it when that is short (`0.25`, `1e300`, `12`),
/// else in scientific notation with four digits (`4.612e18`), never the hundreds of digits of
/// `{}` for a large float.
pub fn shown(x: f64) -> String {
    let plain = x.to_string();
    if plain.len() <= 12 {
        plain
    } else {
        format!("{x:.3e}")
    }
}

/// A Python integer as messages show it: exact up to 20 digits, else its number of digits.
pub fn shown_int(obj: &Bound<'_, PyAny>) -> String {
    if let Ok(i) = obj.extract::<i64>() {
        return i.to_string();
    }
    if let Ok(u) = obj.extract::<u64>() {
        return u.to_string();
    }
    let bits = obj
        .call_method0("bit_length")
        .and_then(|b| b.extract::<u64>())
        .unwrap_or(0);
    // log10(2) ≈ 0.30103: the digits of a number of `bits` bits, to one.
    let digits = (bits as f64 * std::f64::consts::LOG10_2).floor() as u64 + 1;
    let sign = if obj.lt(0).unwrap_or(false) { "-" } else { "" };
    format!("{sign}<{digits}-digit number>")
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
