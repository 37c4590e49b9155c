//! The `contactdd` binary: everything happens in [`contactdd_cli::run`].

use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug in contactdd, never an input problem: say so in one line instead of
    // printing Rust's panic message and backtrace hint.
    std::panic::set_hook(Box::new(|info| {
        let what = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into());
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!("error: internal error (a bug in contactdd, please report it): {what}{at}");
    }));
    // Under `mpirun` (built with `--features mpi`), MPI runs until the command has finished.
    #[cfg(feature = "mpi")]
    let _universe = contactdd_cli::mpi_exchange::init();
    contactdd_cli::run(std::env::args_os()).into()
}
