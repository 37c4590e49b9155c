//! Atomic file writes: a file is written to a temporary file in its folder and then renamed over
//! the target, so a reader (or a crash mid-write) sees either the old file or the complete new one,
//! never a half-written one. Every result file of contactdd is written this way.
//!
//! Only a missing path or a regular file is ever replaced ([`check_output_path`]): the rename would
//! otherwise turn a symlink, a FIFO or a device (as root, even `/dev/null`) into a regular file.

use std::io::{Error, ErrorKind, Write as _};
use std::path::Path;

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

/// True if `name` is the name of a temporary file of [`write_atomic`] (`.<name>.<random>.tmp`, or
/// `.<name>.<pid>-<n>.tmp` of earlier versions)
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
    // `<pid>-<n>`: the names of contactdd versions before the `tempfile` crate.
    let id_ok = (id.len() == RANDOM_CHARS && id.bytes().all(|b| b.is_ascii_alphanumeric()))
        || id
            .split_once('-')
            .is_some_and(|(p, n)| digits(p) && digits(n));
    let ext_ok = target
        .rsplit_once('.')
        .is_some_and(|(stem, ext)| !stem.is_empty() && extensions.contains(&ext));
    id_ok && ext_ok
}

/// Random characters in a temporary file's name (the `tempfile` crate's default).
const RANDOM_CHARS: usize = 6;

/// A new temporary file `.<file_name>.<random>.tmp` in `dir`, removed when dropped unless
/// persisted, with the permissions of a newly created file.
fn temp_file(dir: &Path, file_name: &std::ffi::OsStr) -> std::io::Result<tempfile::NamedTempFile> {
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(file_name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder
        .prefix(&prefix)
        .suffix(".tmp")
        .rand_bytes(RANDOM_CHARS);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// Writes `bytes` to `path` through a temporary file `.<name>.<random>.tmp` in the same folder
/// (the `tempfile` crate: created new, synced, then persisted by a rename over `path`), so that
/// `path` is either the old file or the complete new one. The temporary file is removed if
/// anything fails. The file gets the permissions of a newly created file (0666 less the umask on
/// Unix), not a temporary file's 0600. A `path` without a file name, or one that
/// [`check_output_path`] refuses, is an [`ErrorKind::InvalidInput`] error.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    through_temp(path, bytes, true)
}

/// [`write_atomic`] without the sync: for the data files of a result set, which
/// [`crate::result_set::ResultSet`] syncs together ([`sync_files`]) before its `summary.json`
/// claims them. Readers still see the old file or the complete new one.
pub(crate) fn write_staged(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    through_temp(path, bytes, false)
}

/// Syncs the files `paths` to the disk, several at a time: the file system then commits them
/// together, where one file after the other waits for a commit each. The first error, if any.
/// (Opened for writing, which Windows needs to flush a file; nothing is written.)
pub(crate) fn sync_files(paths: &[std::path::PathBuf]) -> std::io::Result<()> {
    const AT_ONCE: usize = 16;
    let chunk = paths.len().div_ceil(AT_ONCE).max(1);
    std::thread::scope(|scope| {
        let handles: Vec<_> = paths
            .chunks(chunk)
            .map(|part| {
                scope.spawn(move || {
                    part.iter().try_for_each(|p| {
                        std::fs::OpenOptions::new().write(true).open(p)?.sync_all()
                    })
                })
            })
            .collect();
        handles.into_iter().try_for_each(|h| {
            h.join()
                .unwrap_or_else(|_| Err(Error::other("a sync thread panicked")))
        })
    })
}

/// Writes `bytes` to `path` through a temporary file, synced first if `sync`.
fn through_temp(path: &Path, bytes: &[u8], sync: bool) -> std::io::Result<()> {
    check_output_path(path)?;
    let file_name = path.file_name().ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidInput,
            format!("'{}' is not a file path", path.display()),
        )
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut temp = temp_file(dir, file_name)?;
    temp.write_all(bytes)?;
    if sync {
        temp.as_file().sync_all()?;
    }
    temp.persist(path).map_err(|e| e.error)?;
    Ok(())
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

    #[test]
    fn staged_files_are_complete_and_a_missing_one_fails_the_sync() {
        let dir = std::env::temp_dir().join(format!("contactdd-staged-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let paths: Vec<_> = (0..40).map(|i| dir.join(format!("f{i}.csv"))).collect();
        for (i, p) in paths.iter().enumerate() {
            write_staged(p, format!("{i}").as_bytes()).unwrap();
        }
        sync_files(&paths).unwrap();
        for (i, p) in paths.iter().enumerate() {
            assert_eq!(std::fs::read_to_string(p).unwrap(), format!("{i}"));
        }
        let mut with_missing = paths.clone();
        with_missing.insert(17, dir.join("missing.csv"));
        assert!(sync_files(&with_missing).is_err());
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
        let dir = std::env::temp_dir().join(format!("contactdd-tempname-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let temp = temp_file(&dir, "x.vtu".as_ref()).unwrap();
        let made = temp
            .path()
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .to_string();
        assert!(is_temp_name(&made, &["vtu"]), "{made}");
        assert!(!is_temp_name(&made, &["csv"]));
        drop(temp);
        std::fs::remove_dir_all(&dir).unwrap();
        for other in [
            "x.vtu",
            ".x.vtu.tmp",
            ".x.vtu.12-a.tmp",
            ".x.vtu.abc.tmp",
            ".x.vtu.abc-12.tmp",
            ".x.vtu.-12.tmp",
            "..vtu.1-2.tmp",
            ".notes.1-2.tmp",
        ] {
            assert!(!is_temp_name(other, &["vtu"]), "{other}");
        }
    }

    /// A result file gets the permissions of any new file (the umask's), not a temporary's 0600.
    #[cfg(unix)]
    #[test]
    fn written_files_have_a_new_files_permissions() {
        use std::os::unix::fs::PermissionsExt as _;
        let dir = std::env::temp_dir().join(format!("contactdd-mode-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (atomic, plain) = (dir.join("a.csv"), dir.join("b.csv"));
        write_atomic(&atomic, b"x").unwrap();
        std::fs::write(&plain, b"x").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&atomic), mode(&plain));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_path_is_invalid_input() {
        let err = write_atomic(Path::new("/"), b"x").unwrap_err();
        assert_eq!(err.kind(), ErrorKind::InvalidInput);
    }
}
