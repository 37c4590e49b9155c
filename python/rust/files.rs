//! Reading the files of a result folder for `contactdd.load_results`: through
//! [`read_result_file`], the reader `contactdd plot` uses, so that no symbolic link is followed,
//! no FIFO or device is opened and no file is read past its limit.

use std::io::ErrorKind;
use std::path::PathBuf;

use contactdd_io::result_set::{read_result_file, TEXT_LIMIT, VTU_LIMIT};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::error::{input_error, os_error};

/// The bytes of ``path``, a file of a result folder (private: used by ``load_results``).
///
/// ``path`` must itself be a regular file (a symbolic link, a FIFO, a device or a folder is
/// refused before it is opened) of at most the limit of ``kind``: ``"text"`` (summary.json and
/// the CSV files, 256 MiB) or ``"vtu"`` (1 GiB).
///
/// Raises:
///     ContactddIOError: the file cannot be read or is refused; the message names it.
///     ContactddError: ``kind`` is neither ``"text"`` nor ``"vtu"``.
#[pyfunction]
pub fn _read_result_file(py: Python<'_>, path: PathBuf, kind: &str) -> PyResult<Py<PyBytes>> {
    let limit = match kind {
        "text" => TEXT_LIMIT,
        "vtu" => VTU_LIMIT,
        _ => {
            return Err(input_error(format!(
                "kind: expected \"text\" or \"vtu\", got {kind:?}"
            )))
        }
    };
    let bytes = py.detach(|| read_result_file(&path, limit)).map_err(|e| {
        // The reader's messages name the file; its errors carry the kind, not always the
        // OS error number, so the two a caller tests for are set from the kind.
        let errno = e.raw_os_error().or(match e.kind() {
            ErrorKind::NotFound => Some(2),
            ErrorKind::PermissionDenied => Some(13),
            _ => None,
        });
        os_error(py, e.to_string(), errno)
    })?;
    Ok(PyBytes::new(py, &bytes).unbind())
}
