//! A result folder written as a set, so that a reader can tell a complete result from an
//! interrupted one: `summary.json` exists only when every file it lists was written.
//!
//! [`ResultSet::begin`] first removes the previous set: its `summary.json`, then the files its
//! manifest (the `files` key) names, and temporary files of ours left by a killed run. The data
//! files follow ([`ResultSet::write`], or [`ResultSet::record`] for files written by another
//! function), each atomically, and [`ResultSet::finish`] writes `summary.json` last, with the
//! manifest added. A failure in between leaves no `summary.json` and removes the data files of
//! this run ([`ResultSet::abandon`]). Only files named in a manifest or matching our temporary
//! name are ever removed: other files in the folder are the user's.

use std::io::{Error, ErrorKind};
use std::path::{Component, Path, PathBuf};

use serde_json::Value;

use crate::atomic::{check_output_path, is_temp_name, write_atomic};

/// The file written last, holding the manifest.
pub const SUMMARY: &str = "summary.json";
/// The key of `summary.json` that lists the other files of the set.
pub const MANIFEST_KEY: &str = "files";
/// Extensions of the files a result set may hold; a manifest name with another one is ignored.
const EXTENSIONS: &[&str] = &["json", "csv", "vtu", "pvd"];

/// A result folder being written.
#[derive(Debug)]
pub struct ResultSet {
    dir: PathBuf,
    written: Vec<PathBuf>,
}

impl ResultSet {
    /// Starts a set in `dir` (created if needed), removing the previous set first.
    pub fn begin(dir: &Path) -> std::io::Result<ResultSet> {
        std::fs::create_dir_all(dir)?;
        let summary = dir.join(SUMMARY);
        check_output_path(&summary)?;
        let previous = previous_manifest(&summary);
        // The summary goes first: from here on the folder no longer claims a complete result.
        remove_if_file(&summary)?;
        for name in previous {
            remove_if_file(&dir.join(name))?;
        }
        for entry in std::fs::read_dir(dir)? {
            let entry = entry?;
            if entry
                .file_name()
                .to_str()
                .is_some_and(|n| is_temp_name(n, EXTENSIONS))
            {
                remove_if_file(&entry.path())?;
            }
        }
        Ok(ResultSet {
            dir: dir.to_path_buf(),
            written: Vec::new(),
        })
    }

    /// The folder of the set.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Writes the data file `name` of the set atomically.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> std::io::Result<()> {
        let path = self.dir.join(name);
        write_atomic(&path, bytes)?;
        self.written.push(path);
        Ok(())
    }

    /// Number of data files written so far.
    pub fn len(&self) -> usize {
        self.written.len()
    }

    /// True if no data file is written yet.
    pub fn is_empty(&self) -> bool {
        self.written.is_empty()
    }

    /// The file names of the data files written after the first `start`.
    pub fn names_since(&self, start: usize) -> Vec<String> {
        self.written
            .iter()
            .skip(start)
            .filter_map(|p| Some(p.file_name()?.to_str()?.to_string()))
            .collect()
    }

    /// Adds files already written into the set's folder (e.g. by [`crate::output::write_body_vtus`]).
    pub fn record(&mut self, paths: impl IntoIterator<Item = PathBuf>) {
        self.written.extend(paths);
    }

    /// Writes `summary` (a JSON object) as `summary.json` with the manifest of the files written
    /// added, last. Returns every path of the set, `summary.json` last.
    pub fn finish(mut self, mut summary: Value) -> std::io::Result<Vec<PathBuf>> {
        let names: Vec<Value> = self
            .written
            .iter()
            .filter_map(|p| p.file_name()?.to_str().map(Value::from))
            .collect();
        let Some(object) = summary.as_object_mut() else {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "the summary is not a JSON object",
            ));
        };
        object.insert(MANIFEST_KEY.into(), Value::Array(names));
        let mut text = serde_json::to_string_pretty(&summary).map_err(Error::other)?;
        text.push('\n');
        self.write(SUMMARY, text.as_bytes())?;
        sync_dir(&self.dir);
        Ok(self.written)
    }

    /// Removes the data files written so far (best effort): they belong to no manifest, so no later
    /// run would know to remove them.
    pub fn abandon(self) {
        for path in &self.written {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// Writes a set: `begin`, the data files by `data`, then `summary` last; on a failure of `data`
/// the set is abandoned and the error returned.
pub fn write_set(
    dir: &Path,
    summary: Value,
    data: impl FnOnce(&mut ResultSet) -> std::io::Result<()>,
) -> std::io::Result<Vec<PathBuf>> {
    let mut set = ResultSet::begin(dir)?;
    match data(&mut set) {
        Ok(()) => set.finish(summary),
        Err(e) => {
            set.abandon();
            Err(e)
        }
    }
}

/// Reads the file `path` of a result folder, which a reader must treat as untrusted: `path` must
/// itself be a regular file (a symbolic link, a FIFO, a device, a socket or a folder is an
/// [`ErrorKind::InvalidInput`] error, checked before opening, so nothing is followed and no open
/// waits for a writer), and a file of more than `limit` bytes is an [`ErrorKind::InvalidData`]
/// error (at most `limit + 1` bytes are ever read, even of a file that grows). On Unix the opened
/// file must be the one checked (same device and inode). Every error message names `path`.
pub fn read_result_file(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read as _;
    let cannot = |e: Error| Error::new(e.kind(), format!("cannot read '{}': {e}", path.display()));
    let meta = std::fs::symlink_metadata(path).map_err(cannot)?;
    let refuse = |what: &str| {
        Error::new(
            ErrorKind::InvalidInput,
            format!(
                "'{}' is {what}, not a regular file; refusing to read it",
                path.display()
            ),
        )
    };
    let kind = meta.file_type();
    if kind.is_symlink() {
        return Err(refuse("a symbolic link"));
    }
    if kind.is_dir() {
        return Err(refuse("a folder"));
    }
    if !kind.is_file() {
        return Err(refuse("a special file (FIFO, device or socket)"));
    }
    let too_large = || {
        Error::new(
            ErrorKind::InvalidData,
            format!(
                "'{}' is larger than {limit} bytes, the limit for this kind of result file; \
                 refusing to read it",
                path.display()
            ),
        )
    };
    if meta.len() > limit {
        return Err(too_large());
    }
    let file = std::fs::File::open(path).map_err(cannot)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let opened = file.metadata().map_err(cannot)?;
        if (opened.dev(), opened.ino()) != (meta.dev(), meta.ino()) || !opened.is_file() {
            let msg = format!(
                "'{}' changed while being opened; refusing to read it",
                path.display()
            );
            return Err(Error::new(ErrorKind::InvalidInput, msg));
        }
    }
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > limit {
        return Err(too_large());
    }
    Ok(bytes)
}

/// The file names the manifest of an existing `summary.json` lists: plain names with one of our
/// extensions only (never a path elsewhere). Empty when there is no readable manifest.
fn previous_manifest(summary: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(summary) else {
        return Vec::new();
    };
    let Ok(value) = serde_json::from_str::<Value>(&text) else {
        return Vec::new();
    };
    let Some(files) = value.get(MANIFEST_KEY).and_then(Value::as_array) else {
        return Vec::new();
    };
    files
        .iter()
        .filter_map(Value::as_str)
        .filter(|name| is_plain_result_name(name))
        .map(str::to_string)
        .collect()
}

/// A single path component (no folder, no `..`) ending in one of [`EXTENSIONS`].
fn is_plain_result_name(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    let plain = matches!(parts.next(), Some(Component::Normal(_))) && parts.next().is_none();
    let ext = Path::new(name).extension().and_then(|e| e.to_str());
    plain && name != SUMMARY && ext.is_some_and(|e| EXTENSIONS.contains(&e))
}

/// Removes `path` if it is a regular file; anything else (missing, a link, a folder) is left.
fn remove_if_file(path: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_file() => std::fs::remove_file(path),
        _ => Ok(()),
    }
}

/// Makes the renames in `dir` durable (best effort: not every platform can open a folder).
fn sync_dir(dir: &Path) {
    if let Ok(f) = std::fs::File::open(dir) {
        let _ = f.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_names_must_be_plain_result_files() {
        assert!(is_plain_result_name("lower.vtu"));
        assert!(is_plain_result_name("history.csv"));
        for bad in [
            "../x.vtu",
            "/etc/x.csv",
            "a/b.vtu",
            "notes.txt",
            "summary.json",
            "",
        ] {
            assert!(!is_plain_result_name(bad), "{bad}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn result_files_are_read_only_as_bounded_regular_files() {
        let dir = std::env::temp_dir().join(format!("contactdd-readres-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.csv");
        std::fs::write(&file, b"12345").unwrap();
        assert_eq!(read_result_file(&file, 5).unwrap(), b"12345");
        let err = read_result_file(&file, 4).unwrap_err();
        assert_eq!(err.kind(), ErrorKind::InvalidData);
        let link = dir.join("b.csv");
        std::os::unix::fs::symlink(&file, &link).unwrap();
        let err = read_result_file(&link, 5).unwrap_err();
        assert!(err.to_string().contains("symbolic link"), "{err}");
        let err = read_result_file(&dir, 5).unwrap_err();
        assert!(err.to_string().contains("folder"), "{err}");
        let err = read_result_file(Path::new("/dev/null"), 5).unwrap_err();
        assert!(err.to_string().contains("special file"), "{err}");
        let err = read_result_file(&dir.join("missing.csv"), 5).unwrap_err();
        assert_eq!(err.kind(), ErrorKind::NotFound);
        assert!(err.to_string().contains("missing.csv"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
