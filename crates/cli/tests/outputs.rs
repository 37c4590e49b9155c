//! What `contactdd solve` leaves behind: the report on stdout must not be lost silently, and the
//! result folder is complete exactly when `summary.json` is there.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn notch() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml")
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// `contactdd solve notch.toml --out <dir>/res` with stdout sent to `stdout`.
fn solve(dir: &Path, stdout: Stdio) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .arg("solve")
        .arg(notch())
        .arg("--out")
        .arg(dir.join("res"))
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("contactdd runs")
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_stdout_is_an_error() {
    let dir = temp("full");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let out = solve(&dir, Stdio::from(full));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("cannot write to standard output"),
        "{stderr}"
    );
    // The results themselves were written: only the report was lost.
    assert!(dir.join("res").join("summary.json").is_file());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn the_console_reports_reactions_and_names_its_forces() {
    let dir = temp("report");
    let out = solve(&dir, Stdio::piped());
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("normal force Σw|σn|"), "{text}");
    assert!(text.contains("resultant contact force on lower"), "{text}");
    for body in ["lower", "upper"] {
        assert!(
            text.contains(&format!("reactions on {body}: right (")),
            "{text}"
        );
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}
