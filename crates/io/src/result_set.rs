//! A result folder written as a set, so that a reader can tell a complete result from an
//! interrupted one: `summary.json` exists only when every file it lists was written, and the
//! previous set stays complete until the new one is.
//!
//! [`ResultSet::begin`] removes what a killed run left (the staging folder [`STAGING`], temporary
//! files of ours) and creates the staging folder, `DIR/.contactdd-staging`. The data files are
//! written into it ([`ResultSet::write`], or [`ResultSet::record`] for files written by another
//! function into [`ResultSet::dir`]), each atomically, and [`ResultSet::finish`] syncs them all
//! to the disk at once, writes the new `summary.json` there last, with the manifest added, then
//! swaps the new set in:
//!
//! 1. the previous `summary.json` is moved into the staging folder (as `PREVIOUS`): from here the
//!    folder no longer claims a complete result;
//! 2. the previous set's files that the new set does not have are removed;
//! 3. each new data file is renamed into the folder (replacing the previous one of its name);
//! 4. the new `summary.json` is renamed in: the new set is complete;
//! 5. the staging folder is removed.
//!
//! Before step 1 nothing of the previous set is touched, and every target of a rename is checked
//! to be a regular file or missing. A failure of the data or of an earlier step removes the
//! staging folder ([`ResultSet::abandon`]) and leaves the previous set as it was. A run killed
//! during steps 1–4 leaves the staging folder, with both manifests in it; the next `begin`
//! removes the files those manifests name from the folder (unless a `summary.json` there claims
//! them), then the staging folder. Only files named in a manifest, our temporary files and the
//! staging folder are ever removed: other files in the folder are the user's.

use std::io::{Error, ErrorKind};
use std::path::{Component, Path, PathBuf};

use serde_json::Value;

use crate::atomic::{check_output_path, is_temp_name, sync_files, write_atomic, write_staged};

/// The file written last, holding the manifest.
pub const SUMMARY: &str = "summary.json";
/// The key of `summary.json` that lists the other files of the set.
pub const MANIFEST_KEY: &str = "files";
/// The folder in the result folder where a set is written before it is swapped in.
pub const STAGING: &str = ".contactdd-staging";
/// The name the previous `summary.json` has in the staging folder during the swap.
pub const PREVIOUS: &str = ".previous-summary.json";
/// Extensions of the files a result set may hold; a manifest name with another one is ignored.
const EXTENSIONS: &[&str] = &["json", "csv", "vtu", "pvd"];

/// The staging folder of the result folder `dir`, where the files of a set are written before
/// it is swapped in (the processes of a distributed solve write their bodies' files there).
pub fn staging_dir(dir: &Path) -> PathBuf {
    dir.join(STAGING)
}

/// The points of [`ResultSet::finish`] at which a test stops it, as a kill would.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    /// The new set is complete in the staging folder; the previous one is untouched.
    Staged,
    /// The previous `summary.json` is in the staging folder.
    SummaryMoved,
    /// The previous set's stale files are removed.
    StaleRemoved,
    /// Some of the new data files are renamed in (one).
    DataMoving,
    /// The new `summary.json` is in place.
    Swapped,
}

/// A result folder being written.
#[derive(Debug)]
pub struct ResultSet {
    /// The result folder.
    target: PathBuf,
    /// Its staging folder, where the files are written.
    staging: PathBuf,
    written: Vec<PathBuf>,
}

impl ResultSet {
    /// Starts a set in `dir` (created if needed): removes what a killed run left and creates the
    /// staging folder. The previous set stays complete until [`ResultSet::finish`] swaps.
    pub fn begin(dir: &Path) -> std::io::Result<ResultSet> {
        std::fs::create_dir_all(dir)?;
        check_output_path(&dir.join(SUMMARY))?;
        let staging = staging_dir(dir);
        clean_staging(dir, &staging)?;
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
        std::fs::create_dir(&staging)?;
        Ok(ResultSet {
            target: dir.to_path_buf(),
            staging,
            written: Vec::new(),
        })
    }

    /// The folder the data files of the set are written into: the staging folder.
    pub fn dir(&self) -> &Path {
        &self.staging
    }

    /// Writes the data file `name` of the set atomically.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> std::io::Result<()> {
        let path = self.staging.join(name);
        write_staged(&path, bytes)?;
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

    /// Adds files already written into the set's folder [`ResultSet::dir`] (e.g. by
    /// [`crate::output::write_body_vtus`]).
    pub fn record(&mut self, paths: impl IntoIterator<Item = PathBuf>) {
        self.written.extend(paths);
    }

    /// Writes `summary` (a JSON object) as `summary.json` with the manifest of the files written
    /// added, last, and swaps the new set in for the previous one (see the module docs). Returns
    /// every path of the set in the result folder, `summary.json` last. On an error before the
    /// swap the staging folder is removed and the previous set is as it was.
    pub fn finish(self, summary: Value) -> std::io::Result<Vec<PathBuf>> {
        self.finish_until(summary, None)
    }

    /// [`ResultSet::finish`], stopped after `stop` as a kill would stop it (nothing cleaned up).
    fn finish_until(
        mut self,
        mut summary: Value,
        stop: Option<Step>,
    ) -> std::io::Result<Vec<PathBuf>> {
        let names: Vec<String> = self
            .written
            .iter()
            .filter_map(|p| Some(p.file_name()?.to_str()?.to_string()))
            .collect();
        let Some(object) = summary.as_object_mut() else {
            self.abandon();
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "the summary is not a JSON object",
            ));
        };
        object.insert(
            MANIFEST_KEY.into(),
            names.iter().map(|n| Value::from(n.as_str())).collect(),
        );
        // The data on the disk before the summary that claims it.
        let staged = sync_files(&self.written)
            .and_then(|()| serde_json::to_string_pretty(&summary).map_err(Error::other))
            .and_then(|mut text| {
                text.push('\n');
                let path = self.staging.join(SUMMARY);
                write_atomic(&path, text.as_bytes())?;
                self.written.push(path);
                Ok(())
            })
            .and_then(|()| {
                // Every rename target must be replaceable before anything is touched.
                (names.iter().map(String::as_str).chain([SUMMARY]))
                    .try_for_each(|n| check_output_path(&self.target.join(n)))
            });
        if let Err(e) = staged {
            self.abandon();
            return Err(e);
        }
        sync_dir(&self.staging);
        if stop == Some(Step::Staged) {
            return Ok(Vec::new());
        }
        self.swap(&names, stop)?;
        Ok(names
            .iter()
            .map(String::as_str)
            .chain([SUMMARY])
            .map(|n| self.target.join(n))
            .collect())
    }

    /// Steps 1 to 5 of the module docs: the staged set (data files `names`) replaces the
    /// previous one.
    fn swap(&self, names: &[String], stop: Option<Step>) -> std::io::Result<()> {
        let previous = previous_manifest(&self.target.join(SUMMARY));
        let old_summary = self.target.join(SUMMARY);
        if std::fs::symlink_metadata(&old_summary).is_ok() {
            std::fs::rename(&old_summary, self.staging.join(PREVIOUS))?;
        }
        sync_dir(&self.target);
        if stop == Some(Step::SummaryMoved) {
            return Ok(());
        }
        for name in previous.iter().filter(|n| !names.contains(n)) {
            remove_if_file(&self.target.join(name))?;
        }
        if stop == Some(Step::StaleRemoved) {
            return Ok(());
        }
        for (k, name) in names.iter().enumerate() {
            if k == 1 && stop == Some(Step::DataMoving) {
                return Ok(());
            }
            std::fs::rename(self.staging.join(name), self.target.join(name))?;
        }
        sync_dir(&self.target);
        std::fs::rename(self.staging.join(SUMMARY), self.target.join(SUMMARY))?;
        sync_dir(&self.target);
        if stop == Some(Step::Swapped) {
            return Ok(());
        }
        // The new set is complete: what is left is the previous summary (best effort).
        let _ = std::fs::remove_dir_all(&self.staging);
        Ok(())
    }

    /// Removes the staging folder with the data files written so far (best effort); the previous
    /// set is untouched.
    pub fn abandon(self) {
        let _ = std::fs::remove_dir_all(&self.staging);
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

/// The largest CSV or JSON file of a result folder a reader (`contactdd plot`,
/// `contactdd.load_results`) reads: 256 MiB, hundreds of times the files of the largest shipped
/// example (a file near it would also make a figure of no use).
pub const TEXT_LIMIT: u64 = 256 << 20;

/// The largest VTU file of a result folder a reader (`contactdd plot`,
/// `contactdd.load_results`) reads: 1 GiB (about 40 million ASCII numbers, meshes of several
/// million nodes).
pub const VTU_LIMIT: u64 = 1 << 30;

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

/// Removes the staging folder a killed run left in `dir`. Killed during the swap, the folder has
/// no `summary.json` and holds a mix of the two sets: the files the staged manifests (the new
/// `summary.json` and the previous one, [`PREVIOUS`]) name are removed from it first. A
/// `STAGING` that is not a folder (a link, a file) is an error, not removed.
fn clean_staging(dir: &Path, staging: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(staging) {
        Err(e) if e.kind() == ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e),
        Ok(meta) if !meta.is_dir() => {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "'{}' is not a folder of contactdd's; refusing to write results beside it",
                    staging.display()
                ),
            ))
        }
        Ok(_) => {}
    }
    if std::fs::symlink_metadata(dir.join(SUMMARY)).is_err() {
        let staged = [SUMMARY, PREVIOUS].map(|n| previous_manifest(&staging.join(n)));
        for name in staged.iter().flatten() {
            remove_if_file(&dir.join(name))?;
        }
    }
    std::fs::remove_dir_all(staging)
}

/// The file names the manifest of an existing `summary.json` lists: plain names with one of our
/// extensions only (never a path elsewhere). Empty when there is no readable manifest.
fn previous_manifest(summary: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(summary) else {
        return Vec::new();
    };
    // Only the manifest (`files`, [`MANIFEST_KEY`]): the rest of the summary (megabytes with
    // thousands of bodies) is
    // skipped without building its values.
    #[derive(serde::Deserialize)]
    struct Manifest {
        files: Option<Vec<Value>>,
    }
    let Ok(Manifest { files: Some(files) }) = serde_json::from_str::<Manifest>(&text) else {
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

    fn temp(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("contactdd-swap-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The folder's entries, sorted (the staging folder's as `.contactdd-staging/<name>`).
    fn listing(dir: &Path) -> Vec<String> {
        let mut names = Vec::new();
        for e in std::fs::read_dir(dir).unwrap() {
            let name = e.unwrap().file_name().into_string().unwrap();
            if name == STAGING {
                for f in std::fs::read_dir(dir.join(STAGING)).unwrap() {
                    names.push(format!(
                        "{STAGING}/{}",
                        f.unwrap().file_name().to_string_lossy()
                    ));
                }
            } else {
                names.push(name);
            }
        }
        names.sort();
        names
    }

    /// A set of `files` (name, content) with `summary.json` = `{"run": run}` and its manifest,
    /// finished up to `stop`.
    fn set(dir: &Path, run: &str, files: &[(&str, &str)], stop: Option<Step>) {
        let mut set = ResultSet::begin(dir).unwrap();
        for (name, text) in files {
            set.write(name, text.as_bytes()).unwrap();
        }
        set.finish_until(serde_json::json!({ "run": run }), stop)
            .unwrap();
    }

    /// The run named by the folder's `summary.json`, which must list files that all exist with
    /// that run's contents (`None` without a summary).
    fn complete_run(dir: &Path) -> Option<String> {
        let text = std::fs::read_to_string(dir.join(SUMMARY)).ok()?;
        let summary: Value = serde_json::from_str(&text).unwrap();
        let run = summary["run"].as_str().unwrap().to_string();
        for name in summary[MANIFEST_KEY].as_array().unwrap() {
            let content = std::fs::read_to_string(dir.join(name.as_str().unwrap())).unwrap();
            assert!(content.starts_with(&run), "{name}: {content} in run {run}");
        }
        Some(run)
    }

    const OLD: &[(&str, &str)] = &[("a.vtu", "old a"), ("b.vtu", "old b"), ("gone.csv", "old")];
    const NEW: &[(&str, &str)] = &[("a.vtu", "new a"), ("b.vtu", "new b"), ("c.csv", "new c")];

    /// A run stopped at each step of the swap, as a kill would stop it: the folder holds the old
    /// complete set up to the summary's move, no summary (and both manifests staged) until the
    /// new summary is in, then the new complete set; the next run cleans up after each.
    #[test]
    fn every_crash_point_of_the_swap() {
        let user = ("notes.txt", "mine");
        for stop in [
            Step::Staged,
            Step::SummaryMoved,
            Step::StaleRemoved,
            Step::DataMoving,
            Step::Swapped,
        ] {
            let dir = temp(&format!("{stop:?}"));
            std::fs::write(dir.join(user.0), user.1).unwrap();
            set(&dir, "old", OLD, None);
            assert_eq!(
                listing(&dir),
                ["a.vtu", "b.vtu", "gone.csv", "notes.txt", SUMMARY]
            );
            set(&dir, "new", NEW, Some(stop));
            let staged = |names: &[&str]| -> Vec<String> {
                names.iter().map(|n| format!("{STAGING}/{n}")).collect()
            };
            let expected: Vec<String> = match stop {
                Step::Staged => {
                    assert_eq!(complete_run(&dir).as_deref(), Some("old"));
                    let mut e = staged(&["a.vtu", "b.vtu", "c.csv", SUMMARY]);
                    e.extend(
                        ["a.vtu", "b.vtu", "gone.csv", "notes.txt", SUMMARY].map(String::from),
                    );
                    e
                }
                Step::SummaryMoved => {
                    assert_eq!(complete_run(&dir), None);
                    let mut e = staged(&[PREVIOUS, "a.vtu", "b.vtu", "c.csv", SUMMARY]);
                    e.extend(["a.vtu", "b.vtu", "gone.csv", "notes.txt"].map(String::from));
                    e
                }
                Step::StaleRemoved => {
                    assert_eq!(complete_run(&dir), None);
                    let mut e = staged(&[PREVIOUS, "a.vtu", "b.vtu", "c.csv", SUMMARY]);
                    e.extend(["a.vtu", "b.vtu", "notes.txt"].map(String::from));
                    e
                }
                Step::DataMoving => {
                    assert_eq!(complete_run(&dir), None);
                    assert_eq!(std::fs::read_to_string(dir.join("a.vtu")).unwrap(), "new a");
                    assert_eq!(std::fs::read_to_string(dir.join("b.vtu")).unwrap(), "old b");
                    let mut e = staged(&[PREVIOUS, "b.vtu", "c.csv", SUMMARY]);
                    e.extend(["a.vtu", "b.vtu", "notes.txt"].map(String::from));
                    e
                }
                Step::Swapped => {
                    assert_eq!(complete_run(&dir).as_deref(), Some("new"));
                    let mut e = staged(&[PREVIOUS]);
                    e.extend(["a.vtu", "b.vtu", "c.csv", "notes.txt", SUMMARY].map(String::from));
                    e
                }
            };
            let mut expected = expected;
            expected.sort();
            assert_eq!(listing(&dir), expected, "{stop:?}");
            // The next run removes the leftovers (of both sets where none was complete) and
            // writes its set; the user's file stays.
            let mut next = ResultSet::begin(&dir).unwrap();
            let left = listing(&dir);
            let kept: Vec<&str> = match stop {
                Step::Staged => vec!["a.vtu", "b.vtu", "gone.csv", "notes.txt", SUMMARY],
                Step::Swapped => vec!["a.vtu", "b.vtu", "c.csv", "notes.txt", SUMMARY],
                _ => vec!["notes.txt"],
            };
            assert_eq!(left, kept, "{stop:?}");
            next.write("d.vtu", b"next d").unwrap();
            next.finish(serde_json::json!({ "run": "next" })).unwrap();
            assert_eq!(complete_run(&dir).as_deref(), Some("next"));
            assert_eq!(listing(&dir), ["d.vtu", "notes.txt", SUMMARY], "{stop:?}");
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }

    /// Without a stop, the swap leaves the new set and no staging folder; the files' bytes are
    /// those written.
    #[test]
    fn a_finished_swap_leaves_the_new_set_only() {
        let dir = temp("finished");
        set(&dir, "old", OLD, None);
        set(&dir, "new", NEW, None);
        assert_eq!(listing(&dir), ["a.vtu", "b.vtu", "c.csv", SUMMARY]);
        assert_eq!(complete_run(&dir).as_deref(), Some("new"));
        assert_eq!(std::fs::read_to_string(dir.join("c.csv")).unwrap(), "new c");
        std::fs::remove_dir_all(&dir).unwrap();
    }

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
