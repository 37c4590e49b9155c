//! Pickling of the result objects: each pickles as `(cls._from_state, (state,))`, `state` a dict
//! of its attributes by name (numpy arrays, lists, strings and numbers, which pickle by
//! themselves), and `cls._from_state(state)` builds the object again. `contactdd.load_results`
//! builds results from a result folder through the same `_from_state`.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::error::input_error;

/// The pickle reduction of `obj`: `(type(obj)._from_state, (state,))`.
pub fn reduce<'py>(
    obj: &Bound<'py, PyAny>,
    state: Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyTuple>> {
    let py = obj.py();
    let restore = obj.get_type().getattr("_from_state")?;
    PyTuple::new(py, [restore, PyTuple::new(py, [state])?.into_any()])
}

/// The dict of the attributes `names` of `obj`.
pub fn attributes<'py>(obj: &Bound<'py, PyAny>, names: &[&str]) -> PyResult<Bound<'py, PyDict>> {
    let state = PyDict::new(obj.py());
    for name in names {
        state.set_item(name, obj.getattr(*name)?)?;
    }
    Ok(state)
}

/// The entry `key` of a state dict; a missing one is a `ContactddError` naming it.
pub fn get<'py>(state: &Bound<'py, PyDict>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    state
        .get_item(key)?
        .ok_or_else(|| input_error(format!("result state: no '{key}'")))
}
