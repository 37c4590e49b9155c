//! The console report on stdout. A closed pipe (`contactdd sweep … | head`) is not an error: the
//! reader stopped reading, and the results go to files anyway. Any other write error (a full disk,
//! `> /dev/full`) is remembered, so that the command does not exit 0 with its report lost.
//!
//! On a terminal, a long run also shows a live status line on stderr ([`Status`]), which is
//! cleared before every stdout line so the two never interleave on screen.

use std::io::{ErrorKind, IsTerminal, Write as _};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The first stdout write error other than a closed pipe, as text.
static FAILURE: Mutex<Option<String>> = Mutex::new(None);

/// Writes one line to stdout and flushes it, remembering a write error.
pub fn line(args: std::fmt::Arguments<'_>) {
    clear_status();
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

/// Whether a status line is on screen (so the next stdout line must erase it first).
static SHOWN: Mutex<bool> = Mutex::new(false);

/// Erases the status line, if one is shown.
fn clear_status() {
    if let Ok(mut shown) = SHOWN.lock() {
        if *shown {
            eprint!("\r\x1b[2K");
            *shown = false;
        }
    }
}

/// A live one-line status on stderr, redrawn at most a few times per second. It is drawn only
/// when stderr is a terminal: logs and pipes get the table lines alone.
pub struct Status {
    start: Instant,
    last: Mutex<Option<Instant>>,
    live: bool,
}

impl Status {
    /// Redraw interval: fast enough to look alive, slow enough to cost nothing.
    const EVERY: Duration = Duration::from_millis(200);

    /// A status line whose elapsed time counts from now.
    pub fn new(enabled: bool) -> Status {
        Status {
            start: Instant::now(),
            last: Mutex::new(None),
            live: enabled && std::io::stderr().is_terminal(),
        }
    }

    /// Seconds since [`Status::new`].
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// Redraws the status with `text()` (and the elapsed time) unless it was redrawn very
    /// recently; `text` is only called when the line is drawn, so an iteration pays nothing else.
    pub fn update(&self, text: impl FnOnce() -> String) {
        if !self.live {
            return;
        }
        let Ok(mut last) = self.last.lock() else {
            return;
        };
        let now = Instant::now();
        if last.is_some_and(|t| now - t < Self::EVERY) {
            return;
        }
        *last = Some(now);
        if let Ok(mut shown) = SHOWN.lock() {
            eprint!("\r\x1b[2K{}  {:.1} s", text(), self.elapsed());
            let _ = std::io::stderr().flush();
            *shown = true;
        }
    }

    /// Erases the status line.
    pub fn finish(&self) {
        clear_status();
    }
}
