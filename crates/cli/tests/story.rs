//! One story about the solver on every shipped example: `contactdd check`, the console header of
//! `contactdd solve` and `summary.json` describe the same solver settings and name the iteration
//! that ran, and a run that says "converged" ends with its stopping test's measure at or below
//! the tolerance (in the console's closing line and in the history).

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn examples() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the examples folder")
        .map(|e| e.expect("a folder entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

fn stdout_of(args: &[&std::ffi::OsStr]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .output()
        .expect("contactdd runs");
    assert!(out.status.success(), "{args:?}: {out:?}");
    String::from_utf8(out.stdout).expect("UTF-8 output")
}

/// The text after `prefix` on the first line that starts with it.
fn after<'a>(text: &'a str, prefix: &str) -> &'a str {
    let line = text.lines().find(|l| l.starts_with(prefix));
    &line.unwrap_or_else(|| panic!("no line starting with {prefix:?} in\n{text}"))[prefix.len()..]
}

#[test]
fn every_interface_tells_the_same_story_about_the_solver() {
    let out_root = std::env::temp_dir().join(format!("contactdd-story-{}", std::process::id()));
    for file in examples() {
        let stem = file
            .file_stem()
            .expect("a file name")
            .to_string_lossy()
            .into_owned();
        let out = out_root.join(&stem);
        let check = stdout_of(&["check".as_ref(), file.as_os_str()]);
        let solve = stdout_of(&[
            "solve".as_ref(),
            file.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        let summary: Value = serde_json::from_str(
            &std::fs::read_to_string(out.join("summary.json")).expect("summary.json"),
        )
        .expect("JSON");
        let solver = summary["solver"]
            .as_str()
            .expect("summary.json names the solver");
        // check: "solver: <settings>, u0 …"; solve: "solving <name>: …, <settings>".
        assert!(
            after(&check, "solver: ").starts_with(&format!("{solver}, u0 ")),
            "{stem}: check says {:?}, summary.json {solver:?}",
            after(&check, "solver: ")
        );
        let header = match summary["steps"].as_array() {
            Some(steps) => after(
                &solve,
                &format!("solving {stem} in {} load steps: ", steps.len()),
            ),
            None => after(&solve, &format!("solving {stem}: ")),
        };
        assert!(header.ends_with(solver), "{stem}: header {header:?}");
        let iteration = summary["iteration"].as_str().expect("the iteration");
        let newton = solver.starts_with("interface newton");
        assert_eq!(
            iteration == "interface-newton",
            newton,
            "{stem}: {iteration} / {solver}"
        );
        assert_eq!(
            iteration == "robin-sweeps",
            !newton,
            "{stem}: {iteration} / {solver}"
        );

        assert_eq!(summary["converged"], true, "{stem}");
        let tol = summary["tol"].as_f64().expect("tol");
        let history = summary["history"].as_array().expect("history");
        let last = history.last().expect("an iteration")["measure"]
            .as_f64()
            .expect("a finite measure");
        assert!(
            last <= tol,
            "{stem}: converged with measure {last:e} > tol {tol:e}"
        );
        // One closing line, or one per load step, each with the measure that met the tolerance.
        let measure = summary["stop_measure"].as_str().expect("stop_measure");
        let closing: Vec<&str> = solve
            .lines()
            .filter(|l| l.contains("converged in "))
            .collect();
        assert!(!closing.is_empty(), "{stem}: no closing line");
        for line in closing {
            assert!(line.contains(&format!("{measure} ")), "{stem}: {line}");
        }
    }
    let _ = std::fs::remove_dir_all(&out_root);
}
