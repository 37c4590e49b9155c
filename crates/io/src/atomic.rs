//! Atomic file writes: a file is written to a temporary file in its folder and then renamed over
//! the target, so a reader (or a crash mid-write) sees either the old file or the complete new one,
//! never a half-written one. Every result file of contactdd is written this way.
//!
//! Only a missing path or a regular file is ever replaced ([`check_output_path`]): the rename would
//! otherwise turn a symlink, a FIFO or a device (as root, even `/dev/null`) into a regular file.

use std::io::{Error, ErrorKind, Write as _};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Checks that a file may be written at `path`: nothing is there, or a regular file. Anything else
/// (a symbolic link, a folder, a FIFO, a device, a socket) is an [`ErrorKind::InvalidInput`] error
/// naming the path and what is there; the link itself is judged, not its target.
pub fn check_output_path(path: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_file() => Ok(()),
        Ok(meta) => Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "'{}' is {}, not a regular file; refusing to replace it",
                path.display(),
                describe(meta.file_type())
            ),
        )),
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

/// What a file that is not a regular file is, for messages.
fn describe(kind: std::fs::FileType) -> &'static str {
    if kind.is_symlink() {
        return "a symbolic link";
    }
    if kind.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

/// True if `name` is the name of a temporary file of [`write_atomic`] (`.<name>.<pid>-<n>.tmp`)
/// whose target name ends in one of `extensions` (given without the dot). A run killed mid-write
/// leaves such a file behind; the next result set written in that folder removes it.
pub fn is_temp_name(name: &str, extensions: &[&str]) -> bool {
    let Some(inner) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
        return false;
    };
    let Some((target, id)) = inner.rsplit_once('.') else {
        return false;
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let id_ok = id
        .split_once('-')
        .is_some_and(|(p, n)| digits(p) && digits(n));
    let ext_ok = target
        .rsplit_once('.')
        .is_some_and(|(stem, ext)| !stem.is_empty() && extensions.contains(&ext));
    id_ok && ext_ok
}

/// `.<name>.<pid>-<n>.tmp`: unique per process and call, so that concurrent writers never share a
/// temporary file.
fn temp_name(file_name: &std::ffi::OsStr) -> std::ffi::OsString {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let mut temp = std::ffi::OsString::from(".");
    temp.push(file_name);
    temp.push(format!(
        ".{}-{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    temp
}

/// Writes `bytes` to `path` through a temporary file `.<name>.<pid>-<n>.tmp` in the same folder
/// (synced, then renamed to `path`), so that `path` is either the old file or the complete new
/// one. The temporary file is removed if anything fails. A `path` without a file name, or one
/// that [`check_output_path`] refuses, is an [`ErrorKind::InvalidInput`] error.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    check_output_path(path)?;
    let file_name = path.file_name().ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidInput,
            format!("'{}' is not a file path", path.display()),
        )
    })?;
    let temp = path.with_file_name(temp_name(file_name));
    let result = (|| {
        // create_new: never write through something already lying at the temporary name.
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temp, path)
    })();
    if result.is_err() {
        // Best effort: the original error is the one worth reporting.
        let _ = std::fs::remove_file(&temp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("contactdd-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.txt");
        write_atomic(&path, b"old").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["a.txt"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn symlinks_and_fifos_are_never_replaced() {
        let dir = std::env::temp_dir().join(format!("contactdd-special-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("target.txt");
        std::fs::write(&target, b"keep").unwrap();
        let link = dir.join("link.txt");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let err = write_atomic(&link, b"new").unwrap_err();
        assert_eq!(err.kind(), ErrorKind::InvalidInput);
        assert!(err.to_string().contains("symbolic link"), "{err}");
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"keep");

        let fifo = dir.join("fifo");
        // mkfifo may be missing on a minimal system; the symlink case above still ran.
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success());
        if made {
            use std::os::unix::fs::FileTypeExt as _;
            let err = write_atomic(&fifo, b"new").unwrap_err();
            assert_eq!(err.kind(), ErrorKind::InvalidInput);
            assert!(err.to_string().contains("FIFO"), "{err}");
            assert!(std::fs::symlink_metadata(&fifo)
                .unwrap()
                .file_type()
                .is_fifo());
        }
        let err = write_atomic(&dir, b"new").unwrap_err();
        assert!(err.to_string().contains("folder"), "{err}");
        // Only the files made here remain: no temporary was left behind.
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        let expected: &[&str] = if made {
            &["fifo", "link.txt", "target.txt"]
        } else {
            &["link.txt", "target.txt"]
        };
        assert_eq!(names, expected);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn temporary_names_are_recognised() {
        let made = temp_name("x.vtu".as_ref()).into_string().unwrap();
        assert!(is_temp_name(&made, &["vtu"]));
        assert!(!is_temp_name(&made, &["csv"]));
        for other in [
            "x.vtu",
            ".x.vtu.tmp",
            ".x.vtu.12-a.tmp",
            "..vtu.1-2.tmp",
            ".notes.1-2.tmp",
        ] {
            assert!(!is_temp_name(other, &["vtu"]), "{other}");
        }
    }

    #[test]
    fn a_folder_path_is_invalid_input() {
        let err = write_atomic(Path::new("/"), b"x").unwrap_err();
        assert_eq!(err.kind(), ErrorKind::InvalidInput);
    }
}
