//! `--out/-o` and `--quiet/-q` on every subcommand that writes results.

use std::path::{Path, PathBuf};
use std::process::Command;

fn notch() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml")
}

fn contactdd(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .output()
        .expect("contactdd runs")
}

#[test]
fn short_out_and_quiet_flags_work_on_solve_sweep_and_monolithic() {
    let dir = std::env::temp_dir().join(format!("contactdd-flags-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = notch();
    for (command, out, extra) in [
        ("solve", dir.join("solve"), Vec::<&str>::new()),
        ("monolithic", dir.join("mono"), Vec::new()),
        ("sweep", dir.join("sweep.csv"), vec!["--gamma", "0.5"]),
    ] {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            command.as_ref(),
            file.as_os_str(),
            "-q".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ];
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let run = contactdd(&args);
        assert!(run.status.success(), "{command}: {:?}", run);
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert_eq!(stdout.lines().count(), 1, "{command} -q printed:\n{stdout}");
        assert!(out.exists(), "{command} wrote nothing at {}", out.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
