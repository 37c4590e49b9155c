//! A results folder is written as a set: `summary.json` last, with a manifest of the other files,
//! so that an interrupted write never leaves a summary that claims a result; a reused folder loses
//! the files of the previous run (and only those), and keeps them whole when the new run fails.
//! (The crash points of the swap are tested in `crates/io/src/result_set.rs`.)

use std::path::{Path, PathBuf};

use contactdd_ddm::benchmark::Notch;
use contactdd_ddm::{prepare, solve, Hooks, Model, Settings, Solution};
use contactdd_io::output::write_results;
use serde_json::Value;

fn notch() -> (Model, Solution) {
    let model = Notch::default().model().expect("notch");
    let prepared = prepare(&model).expect("prepared");
    let sol = solve(&model, &prepared, &Settings::default(), Hooks::default()).expect("solved");
    (model, sol)
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-set-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn manifest(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary");
    let summary: Value = serde_json::from_str(&text).expect("JSON");
    let mut files: Vec<String> = summary["files"]
        .as_array()
        .expect("a manifest")
        .iter()
        .map(|f| f.as_str().expect("a name").to_string())
        .collect();
    files.sort();
    files
}

#[test]
fn a_failure_mid_set_keeps_the_previous_set() {
    let (model, sol) = notch();
    let dir = temp("failure");
    // A complete earlier result, then a folder where this run's upper.vtu should go.
    write_results(&dir, &model, &sol).expect("first run");
    let before = names(&dir);
    let summary = std::fs::read(dir.join("summary.json")).expect("summary");
    std::fs::remove_file(dir.join("upper.vtu")).expect("remove");
    std::fs::create_dir(dir.join("upper.vtu")).expect("obstacle");

    assert!(write_results(&dir, &model, &sol).is_err());
    // The failure comes before the swap: the previous set's files are as they were (the obstacle
    // in upper.vtu's place), and nothing of the failed run, its staging folder or temporaries is
    // left.
    assert_eq!(names(&dir), before);
    assert!(dir.join("upper.vtu").is_dir());
    assert_eq!(
        std::fs::read(dir.join("summary.json")).expect("summary"),
        summary
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_reused_folder_loses_the_previous_run_and_keeps_user_files() {
    let (model, mut sol) = notch();
    let dir = temp("stale");
    write_results(&dir, &model, &sol).expect("first run");
    // A file of the user's, and the temporary file a run killed mid-write leaves behind.
    std::fs::write(dir.join("notes.txt"), "mine").expect("user file");
    std::fs::write(dir.join("report.vtu"), "mine too").expect("user file");
    std::fs::write(dir.join(".lower.vtu.aZ09xy.tmp"), "partial").expect("temporary");
    // The same, as named by earlier versions.
    std::fs::write(dir.join(".upper.vtu.99999-3.tmp"), "partial").expect("temporary");

    // The second run names its bodies differently: lower.vtu and upper.vtu become stale.
    for (b, body) in sol.bodies.iter_mut().enumerate() {
        body.name = format!("body{b}");
    }
    let written = write_results(&dir, &model, &sol).expect("second run");
    assert_eq!(
        names(&dir),
        [
            "body0.vtu",
            "body1.vtu",
            "contact.csv",
            "history.csv",
            "notes.txt",
            "report.vtu",
            "results.pvd",
            "summary.json"
        ]
    );
    // The manifest lists exactly the other files written, and summary.json came last.
    assert_eq!(
        manifest(&dir),
        [
            "body0.vtu",
            "body1.vtu",
            "contact.csv",
            "history.csv",
            "results.pvd"
        ]
    );
    assert!(written.last().is_some_and(|p| p.ends_with("summary.json")));
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_manifest_never_removes_files_outside_the_folder() {
    let (model, sol) = notch();
    let root = temp("outside");
    let dir = root.join("out");
    std::fs::create_dir(&dir).expect("out");
    std::fs::write(root.join("keep.csv"), "mine").expect("outside file");
    std::fs::write(
        dir.join("summary.json"),
        r#"{"files": ["../keep.csv", "/etc/hostname", "keep.txt"]}"#,
    )
    .expect("forged summary");
    std::fs::write(dir.join("keep.txt"), "mine").expect("user file");
    write_results(&dir, &model, &sol).expect("run");
    assert!(root.join("keep.csv").is_file() && dir.join("keep.txt").is_file());
    std::fs::remove_dir_all(&root).expect("clean up");
}
