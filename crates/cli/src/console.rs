//! The console report on stdout. A closed pipe (`contactdd sweep … | head`) is not an error: the
//! reader stopped reading, and the results go to files anyway. Any other write error (a full disk,
//! `> /dev/full`) is remembered, so that the command does not exit 0 with its report lost.

use std::io::{ErrorKind, Write as _};
use std::sync::Mutex;

/// The first stdout write error other than a closed pipe, as text.
static FAILURE: Mutex<Option<String>> = Mutex::new(None);

/// Writes one line to stdout and flushes it, remembering a write error.
pub fn line(args: std::fmt::Arguments<'_>) {
    let mut out = std::io::stdout().lock();
    let result = writeln!(out, "{args}").and_then(|()| out.flush());
    if let Err(e) = result {
        if e.kind() != ErrorKind::BrokenPipe {
            if let Ok(mut failure) = FAILURE.lock() {
                failure.get_or_insert_with(|| e.to_string());
            }
        }
    }
}

/// The first stdout write error since the last call, if any (and forgets it).
pub fn take_failure() -> Option<String> {
    FAILURE.lock().ok().and_then(|mut f| f.take())
}
