//! The console report on stdout. A closed pipe (`contactdd sweep … | head`) is not an error: the
//! reader stopped reading, and the results go to files anyway. Any other write error (a full disk,
//! `> /dev/full`) is remembered, so that the command does not exit 0 with its report lost.
//!
//! On a terminal, a long run also shows a live status line on stderr ([`Status`], an `indicatif`
//! bar), which is hidden while a stdout line is written so the two never interleave on screen.

use std::io::{ErrorKind, IsTerminal, Write as _};
use std::sync::Mutex;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The first stdout write error other than a closed pipe, as text.
static FAILURE: Mutex<Option<String>> = Mutex::new(None);

/// Writes one line to stdout and flushes it, remembering a write error. A status bar on screen
/// is hidden meanwhile, so the two never interleave.
pub fn line(args: std::fmt::Arguments<'_>) {
    let write = || {
        let mut out = std::io::stdout().lock();
        let result = writeln!(out, "{args}").and_then(|()| out.flush());
        if let Err(e) = result {
            if e.kind() != ErrorKind::BrokenPipe {
                if let Ok(mut failure) = FAILURE.lock() {
                    failure.get_or_insert_with(|| e.to_string());
                }
            }
        }
    };
    match BAR.lock().ok().and_then(|bar| bar.clone()) {
        Some(bar) => bar.suspend(write),
        None => write(),
    }
}

/// The first stdout write error since the last call, if any (and forgets it).
pub fn take_failure() -> Option<String> {
    FAILURE.lock().ok().and_then(|mut f| f.take())
}

/// The status bar on screen, if any (for [`line`] to hide).
static BAR: Mutex<Option<ProgressBar>> = Mutex::new(None);

/// A live one-line status on stderr (an `indicatif` bar), drawn at most 5 times per second, and
/// only when stderr is a terminal: logs and pipes get the table lines alone.
pub struct Status {
    start: Instant,
    bar: Option<ProgressBar>,
}

impl Status {
    /// A status line whose elapsed time counts from now.
    pub fn new(enabled: bool) -> Status {
        let bar = (enabled && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(5));
            let style = ProgressStyle::with_template("{msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner());
            bar.set_style(style);
            bar
        });
        if let (Some(bar), Ok(mut shown)) = (&bar, BAR.lock()) {
            *shown = Some(bar.clone());
        }
        Status {
            start: Instant::now(),
            bar,
        }
    }

    /// Seconds since [`Status::new`].
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// Sets the status to `text()` and the elapsed time; the bar draws it at most 5 times a
    /// second. `text` is only called on a terminal, so logs pay nothing for it.
    pub fn update(&self, text: impl FnOnce() -> String) {
        if let Some(bar) = &self.bar {
            bar.set_message(format!("{}  {:.1} s", text(), self.elapsed()));
        }
    }

    /// Erases the status line.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
            if let Ok(mut shown) = BAR.lock() {
                *shown = None;
            }
        }
    }
}

impl Drop for Status {
    /// A run that ends by an error leaves no status line behind either.
    fn drop(&mut self) {
        self.finish();
    }
}
