//! `contactdd solve` with `[solver] load-steps`: a row per step whose loads follow the factors,
//! with the contact zone growing like a Hertz contact, and a result set that ParaView opens
//! through `results.pvd`.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-steps-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The notch example with its `[solver]` table replaced by `solver`.
fn notch_with(dir: &Path, solver: &str) -> PathBuf {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml");
    let text = std::fs::read_to_string(example).expect("the example");
    let body = text.split("[solver]").next().expect("a solver table");
    let path = dir.join("steps.toml");
    std::fs::write(&path, format!("{body}[solver]\n{solver}\n")).expect("write");
    path
}

fn run(file: &Path, out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .arg("solve")
        .arg(file)
        .arg("--out")
        .arg(out)
        .output()
        .expect("contactdd runs")
}

/// Four steps of the notch: each step's contact force is its factor times the applied 8400, and
/// the result set lists every step's VTU files in `results.pvd` and the manifest.
#[test]
fn load_steps_follow_their_factors_and_write_every_step() {
    let dir = temp("notch");
    let file = notch_with(
        &dir,
        "load-steps = 4\nmonitor = { body = \"upper\", boundary = \"top\" }",
    );
    let out = dir.join("res");
    let run = run(&file, &out);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let steps = summary["steps"].as_array().expect("a steps array");
    assert_eq!(steps.len(), 4);
    let mut last_monitor = 0.0;
    for (k, step) in steps.iter().enumerate() {
        let factor = step["factor"].as_f64().unwrap();
        assert_eq!(factor, (k + 1) as f64 / 4.0);
        let force = step["pairs"][0]["force"][1].as_f64().unwrap();
        assert!(
            (force.abs() - 8400.0 * factor).abs() <= 1e-6 * 8400.0,
            "step {k}: force {force}"
        );
        // The upper body is pushed down further at every step.
        let uy = step["monitor"][1].as_f64().unwrap();
        assert!(uy < last_monitor, "step {k}: monitor {uy}");
        last_monitor = uy;
    }
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    let files = summary["files"].as_array().unwrap();
    for k in 1..=4 {
        for body in ["lower", "upper"] {
            let name = format!("{body}-step{k}.vtu");
            assert!(out.join(&name).is_file(), "{name}");
            assert!(pvd.contains(&name), "{name} not in results.pvd");
            assert!(
                files.iter().any(|f| f == name.as_str()),
                "{name} not in the manifest"
            );
        }
    }
    let csv = std::fs::read_to_string(out.join("steps.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bad step settings are input errors naming the key.
#[test]
fn bad_load_steps_are_refused() {
    let dir = temp("bad");
    for (solver, key) in [
        ("load-steps = 0", "load-steps"),
        ("load-steps = [0.5, -1.0]", "load-steps"),
        (
            "load-steps = 2\nmonitor = { body = \"nobody\", boundary = \"top\" }",
            "monitor",
        ),
        (
            "load-steps = 2\nmonitor = { body = \"upper\", boundary = \"nowhere\" }",
            "monitor",
        ),
    ] {
        let file = notch_with(&dir, solver);
        let run = run(&file, &dir.join("res"));
        assert_eq!(run.status.code(), Some(1), "{solver}");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(stderr.contains(key), "{solver}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `monitor` without `load-steps` or `[[steps]]` has no step to be reported in: `check` warns
/// (and goes on), with load steps it does not.
#[test]
fn a_monitor_without_steps_is_warned_about() {
    let dir = temp("monitor-alone");
    let check = |solver: &str| {
        let file = notch_with(&dir, solver);
        Command::new(env!("CARGO_BIN_EXE_contactdd"))
            .arg("check")
            .arg(&file)
            .output()
            .expect("contactdd runs")
    };
    let alone = check("monitor = { body = \"upper\", boundary = \"top\" }");
    let stderr = String::from_utf8_lossy(&alone.stderr);
    assert!(alone.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("[solver] monitor: 'top' of body 'upper'"),
        "{stderr}"
    );
    let stepped = check("load-steps = 2\nmonitor = { body = \"upper\", boundary = \"top\" }");
    let stderr = String::from_utf8_lossy(&stepped.stderr);
    assert!(
        stepped.status.success() && !stderr.contains("monitor"),
        "{stderr}"
    );
}
