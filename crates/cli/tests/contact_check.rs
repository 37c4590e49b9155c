//! `check`, `solve` and `monolithic` on contact pairs whose geometry is wrong: boundaries that face
//! away from each other and bodies placed on top of each other are refused (exit 1), a moderate
//! initial overlap and a pair that can never touch are warned about on stderr.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "../../../tests/support/two_blocks.rs"]
mod two_blocks;
use two_blocks::TwoBlocks;

/// Two 4 × 1 blocks; the upper one spans `y` and the pair is `lower.<a>` with `upper.<b>`.
fn pair(y: [f64; 2], a: &'static str, b: &'static str) -> String {
    scaled(1.0, y, a, b)
}

/// [`pair`] with every length multiplied by `s`.
fn scaled(s: f64, y: [f64; 2], a: &'static str, b: &'static str) -> String {
    TwoBlocks {
        width: format!("{}", 4.0 * s),
        lower: ["0.0".into(), format!("{s}")],
        upper: [format!("{}", s * y[0]), format!("{}", s * y[1])],
        mirror: false,
        boundaries: [a, b],
        penalty: ["0.5".into(), format!("{s}")],
        tail: "",
        ..TwoBlocks::default()
    }
    .toml()
}

/// A scratch folder, removed when dropped (also when a test fails).
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh folder holding `problem.toml` with `text`.
fn write(name: &str, text: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("contactdd-check-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("problem.toml"), text).unwrap();
    Scratch(dir)
}

fn contactdd(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Every command refuses the file with exit 1 and a message naming the pair.
fn refused(name: &str, text: &str) {
    let dir = write(name, text);
    for args in [
        &["check", "problem.toml"][..],
        &["solve", "-q", "problem.toml", "--out", "out"],
        &["monolithic", "problem.toml", "--out", "mono"],
    ] {
        let out = contactdd(&dir, args);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains("problem.toml: contact pair 'lower-upper': the bodies start overlapping"),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!dir.join("out").exists() && !dir.join("mono").exists());
}

#[test]
fn boundaries_that_face_away_from_each_other_are_refused() {
    // The upper block sits on the lower one, but the pair names the outer faces.
    refused("away", &pair([1.0, 2.0], "bottom", "top"));
}

#[test]
fn bodies_on_top_of_each_other_are_refused() {
    refused("coincident", &pair([0.0, 1.0], "top", "bottom"));
}

/// `check` and `solve` both succeed (exit 0); their stderr.
fn succeeds(name: &str, text: &str) -> Vec<String> {
    let dir = write(name, text);
    [
        &["check", "problem.toml"][..],
        &["solve", "-q", "problem.toml", "--out", "out"],
    ]
    .into_iter()
    .map(|args| {
        let out = contactdd(&dir, args);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        stderr(&out)
    })
    .collect()
}

#[test]
fn a_moderate_overlap_is_warned_about() {
    // 5 % of the thickness: solved, with a warning.
    for err in succeeds("overlap", &pair([0.95, 1.95], "top", "bottom")) {
        let warning = "warning: problem.toml: contact pair 'lower-upper': the bodies start \
                       overlapping by 5.0000e-2";
        assert!(err.contains(warning), "{err}");
    }
}

#[test]
fn a_pair_that_cannot_touch_is_warned_about() {
    // Coincident boundaries whose normals point the same way: no point faces the partner. The
    // upper body is then held by nothing: its factorisation fails, or the solve diverges, with
    // the warning printed either way.
    let dir = write("tops", &pair([0.0, 1.0], "top", "top"));
    let out = contactdd(&dir, &["check", "problem.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("no contact point faces the other body"));
    let out = contactdd(&dir, &["solve", "-q", "problem.toml", "--out", "out"]);
    assert!(stderr(&out).contains("no contact point faces the other body"));
}

#[test]
fn a_pair_that_touches_gets_no_warning() {
    for err in succeeds("touch", &pair([1.0, 2.0], "top", "bottom")) {
        assert!(!err.contains("warning"), "{err}");
    }
}

#[test]
fn the_verdict_does_not_depend_on_the_unit_of_length() {
    for s in [1e-6, 1e6] {
        let away = write("away-scaled", &scaled(s, [1.0, 2.0], "bottom", "top"));
        let out = contactdd(&away, &["check", "problem.toml"]);
        assert_eq!(out.status.code(), Some(1), "{s}: {}", stderr(&out));
        let overlap = write("overlap-scaled", &scaled(s, [0.95, 1.95], "top", "bottom"));
        let out = contactdd(&overlap, &["check", "problem.toml"]);
        assert_eq!(out.status.code(), Some(0), "{s}: {}", stderr(&out));
        assert!(
            stderr(&out).contains("5.000% of the thinner body"),
            "{}",
            stderr(&out)
        );
        let touch = write("touch-scaled", &scaled(s, [1.0, 2.0], "top", "bottom"));
        let out = contactdd(&touch, &["check", "problem.toml"]);
        assert!(!stderr(&out).contains("warning"), "{s}: {}", stderr(&out));
    }
}
