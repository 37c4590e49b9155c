//! End-to-end tests of the `contactdd` binary: exit codes, error messages, the files written and
//! their format. Each test works in its own temporary folder.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

/// A small two-body problem: `lower` is fixed at its bottom, `upper` is pressed onto it and held
/// vertically only by the contact.
#[path = "../../../tests/support/two_blocks.rs"]
mod two_blocks;
use two_blocks::{Text, TwoBlocks};

/// The shared two-block problem with the paper's iteration.
static PAIR: Text = Text::new(|| TwoBlocks::default().toml());

/// A unit square of two triangles in Gmsh 2.2 format, with boundaries `bottom` and `top`.
const SQUARE_MSH: &str = r#"$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "bottom"
1 2 "top"
2 3 "block"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
4
1 1 2 1 1 1 2
2 1 2 2 2 3 4
3 2 2 3 1 1 2 3
4 2 2 3 1 1 3 4
$EndElements
"#;

/// A problem with one body meshed by `square.msh`.
const GMSH_BODY: &str = r#"
plane = "strain"

[materials.steel]
young = 2.1e5
poisson = 0.3

[[bodies]]
name = "block"
material = "steel"
mesh = { kind = "gmsh", file = "square.msh" }
supports = [{ boundary = "bottom", component = "both" }]
loads = [{ kind = "pressure", boundary = "top", value = 1.0 }]
"#;

/// A fresh, empty temporary folder for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn notch_example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml")
}

/// Runs the binary in `dir` with `args`.
fn contactdd(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// No panic message, no backtrace hint.
fn assert_clean_stderr(out: &Output) {
    let err = stderr(out);
    assert!(
        !err.contains("panicked") && !err.contains("RUST_BACKTRACE"),
        "{err}"
    );
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn solving_the_notch_example_succeeds_and_writes_every_result_file() {
    let dir = temp_dir("notch");
    let notch = notch_example();
    let out = contactdd(&dir, &["solve", notch.to_str().unwrap(), "--out", "res"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_clean_stderr(&out);
    let text = stdout(&out);
    assert!(text.contains("converged in"), "{text}");
    assert!(text.contains("contact force on lower"), "{text}");

    let res = dir.join("res");
    for file in [
        "summary.json",
        "contact.csv",
        "history.csv",
        "lower.vtu",
        "upper.vtu",
    ] {
        assert!(res.join(file).is_file(), "{file} missing");
    }
    let summary = read_json(&res.join("summary.json"));
    assert_eq!(summary["converged"], true);
    assert_eq!(summary["message"], Value::Null);
    assert_eq!(summary["method"], "newton-kurchatov");
    let iterations = summary["iterations"].as_u64().unwrap() as usize;
    assert_eq!(summary["history"].as_array().unwrap().len(), iterations);
    assert_eq!(summary["bodies"][0]["name"], "lower");
    assert!(summary["timing_s"]["iterate"].is_number());
    assert!(summary["version"].is_string());
    let pair = &summary["contact"][0];
    let points = pair["x"].as_array().unwrap().len();
    for key in ["y", "gap", "pressure", "status"] {
        assert_eq!(pair[key].as_array().unwrap().len(), points, "{key}");
    }

    let csv = std::fs::read_to_string(res.join("contact.csv")).unwrap();
    assert!(csv.starts_with("pair,body,x,y,gap,pressure,nodal_traction,status\n"));
    assert_eq!(csv.lines().count(), points + 1);
    let history = std::fs::read_to_string(res.join("history.csv")).unwrap();
    assert!(history.starts_with(
        "k,gamma,measure,rel_change_lower,rel_change_upper,active_lower,active_upper,\
         normal_force_lower,normal_force_upper\n"
    ));
    assert_eq!(history.lines().count(), iterations + 1);
    // The notch names its method and γ: the paper's sweeps ran, and their stopping test held.
    assert_eq!(summary["iteration"], "robin-sweeps");
    assert_eq!(summary["stop_measure"], "relative change");
    let last = summary["history"][iterations - 1]["measure"]
        .as_f64()
        .unwrap();
    assert!(last <= summary["tol"].as_f64().unwrap(), "{last}");

    let nodes = summary["bodies"][0]["nodes"].as_u64().unwrap() as usize;
    check_vtu(&res.join("lower.vtu"), nodes);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The `.vtu` file is well-formed: the right number of points, all the point data arrays, and a
/// displacement array of 3 values per point; read with meshio too when Python has it.
fn check_vtu(path: &Path, nodes: usize) {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.starts_with("<?xml"));
    assert!(text.trim_end().ends_with("</VTKFile>"));
    assert!(
        text.contains(&format!("NumberOfPoints=\"{nodes}\"")),
        "NumberOfPoints"
    );
    let names = [
        "displacement",
        "sigma_xx",
        "sigma_yy",
        "sigma_xy",
        "sigma_zz",
        "von_mises",
        "contact_pressure",
    ];
    let file = contactdd_io::vtu_read::parse_vtu(&bytes).unwrap();
    let point_data = contactdd_io::vtu_read::Section::PointData;
    for name in names {
        assert!(file.array(point_data, name).is_some(), "{name} missing");
    }
    let numbers = &file.array(point_data, "displacement").unwrap().values;
    assert_eq!(numbers.len(), 3 * nodes);
    assert!(numbers.iter().all(|v| v.is_finite()));

    let meshio = Command::new("python3")
        .args(["-c", "import meshio"])
        .output();
    if !matches!(meshio, Ok(ref o) if o.status.success()) {
        eprintln!(
            "meshio not available: skipping the meshio read of {}",
            path.display()
        );
        return;
    }
    let script = format!(
        "import meshio, sys\n\
         m = meshio.read(sys.argv[1])\n\
         assert len(m.points) == {nodes}, len(m.points)\n\
         for n in {names:?}:\n    assert n in m.point_data, n\n\
         assert m.point_data['displacement'].shape == ({nodes}, 3)\n"
    );
    let out = Command::new("python3")
        .args(["-c", &script, path.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success(), "meshio: {}", stderr(&out));
}

#[test]
fn a_diverging_run_exits_2_and_still_writes_its_last_iterate() {
    let dir = temp_dir("diverge");
    let notch = notch_example();
    // With γ = 0.85 the active-set method overshoots until a body loses all contact.
    let out = contactdd(
        &dir,
        &[
            "solve",
            notch.to_str().unwrap(),
            "--method",
            "active-set",
            "--gamma",
            "0.85",
            "--out",
            "res",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_clean_stderr(&out);
    assert!(stdout(&out).contains("NOT converged"));
    let summary = read_json(&dir.join("res/summary.json"));
    assert_eq!(summary["converged"], false);
    let message = summary["message"].as_str().unwrap();
    assert!(message.contains("diverged"), "{message}");
    assert_eq!(summary["method"], "active-set");
    assert_eq!(summary["gamma"], 0.85);
    for file in ["contact.csv", "history.csv", "lower.vtu", "upper.vtu"] {
        assert!(dir.join("res").join(file).is_file(), "{file} missing");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_exits_1_with_one_readable_error() {
    let dir = temp_dir("bad");
    std::fs::write(dir.join("square.msh"), SQUARE_MSH).unwrap();
    let truncated = &SQUARE_MSH[..SQUARE_MSH.find("2 1 0 0").unwrap()];
    std::fs::write(dir.join("truncated.msh"), truncated).unwrap();
    // The intact mesh is valid, so the truncation is what the last case fails on.
    std::fs::write(dir.join("gmsh.toml"), GMSH_BODY).unwrap();
    let out = contactdd(&dir, &["check", "gmsh.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    std::fs::write(dir.join("pair.toml"), &*PAIR).unwrap();
    let out = contactdd(&dir, &["check", "pair.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));

    let floating = PAIR
        .replace("supports = [{ boundary = \"left\", component = \"x\" }]", "")
        .replace(
            "[[contact]]\nbodies = [\"lower\", \"upper\"]\nboundaries = [\"top\", \"bottom\"]\npenalty = { c = 0.05, h = 0.5 }",
            "",
        );
    // (name, file text, a word the message must contain)
    let cases: Vec<(&str, String, &str)> = vec![
        ("not-toml", "this is [ not toml".into(), "TOML"),
        (
            "unknown-key",
            PAIR.replace("tol = 1e-8", "tol = 1e-8\ntolerance = 1"),
            "tolerance",
        ),
        (
            "negative-young",
            PAIR.replace("young = 2.1e5", "young = -2.1e5"),
            "young",
        ),
        (
            "poisson-half",
            PAIR.replace("poisson = 0.3", "poisson = 0.5"),
            "poisson",
        ),
        (
            "unknown-boundary",
            PAIR.replace("boundary = \"top\", value", "boundary = \"tpo\", value"),
            "tpo",
        ),
        (
            "pair-one-body-twice",
            PAIR.replace(
                "bodies = [\"lower\", \"upper\"]",
                "bodies = [\"lower\", \"lower\"]",
            ),
            "twice",
        ),
        (
            "empty-mesh",
            PAIR.replace("nx = 8, ny = 2 }", "nx = 0, ny = 2 }"),
            "nx",
        ),
        (
            "inverted-rectangle",
            PAIR.replace(
                "x = [0.0, 2.0], y = [0.0, 0.5]",
                "x = [2.0, 0.0], y = [0.0, 0.5]",
            ),
            "mesh.x",
        ),
        ("floating-body", floating, "upper"),
        (
            "truncated-gmsh",
            GMSH_BODY.replace("square.msh", "truncated.msh"),
            "truncated.msh",
        ),
    ];
    for (name, text, word) in cases {
        let file = format!("{name}.toml");
        std::fs::write(dir.join(&file), text).unwrap();
        for command in ["check", "solve"] {
            let out = contactdd(&dir, &[command, &file]);
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(1), "{name} ({command}): {err}");
            assert_clean_stderr(&out);
            assert!(err.starts_with("error: "), "{name}: {err}");
            assert!(
                err.contains(&file),
                "{name}: the message names the file: {err}"
            );
            assert!(err.contains(word), "{name}: '{word}' not in: {err}");
        }
    }
    assert!(
        !dir.join("pair-out").exists(),
        "nothing is written for bad input"
    );

    let out = contactdd(&dir, &["solve", "missing.toml"]);
    assert_eq!(out.status.code(), Some(1));
    assert_clean_stderr(&out);
    assert!(stderr(&out).contains("cannot read 'missing.toml'"));
    assert_eq!(
        stderr(&out).matches("No such file").count(),
        1,
        "{}",
        stderr(&out)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_command_lines_exit_1_and_help_exits_0() {
    let dir = temp_dir("args");
    std::fs::write(dir.join("pair.toml"), &*PAIR).unwrap();
    for args in [
        &["solve", "pair.toml", "--gamma", "0"][..],
        &["solve", "pair.toml", "--gamma", "fast"],
        &["solve", "pair.toml", "--method", "newton"],
        &["solve", "pair.toml", "--tol", "-1"],
        &["solve", "pair.toml", "--max-iter", "0"],
        &["solve", "pair.toml", "--threads", "0"],
        &["sweep", "pair.toml", "--gamma", "0.5:0.1:0.1"],
        &["solve"],
        &["frobnicate"],
        &[],
    ] {
        let out = contactdd(&dir, args);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert_clean_stderr(&out);
    }
    for args in [&["--help"][..], &["--version"], &["solve", "--help"]] {
        let out = contactdd(&dir, args);
        assert_eq!(out.status.code(), Some(0), "{args:?}");
    }
    let help = stdout(&contactdd(&dir, &["solve", "--help"]));
    assert!(help.contains("Exit codes"), "{help}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--out` and the results folder never replace a symlink or a FIFO (renaming over it would
/// turn it into a regular file): exit 1, a message naming the path, the link left as it was.
#[cfg(unix)]
#[test]
fn output_paths_that_are_not_regular_files_are_refused() {
    let dir = temp_dir("special-out");
    std::fs::write(dir.join("pair.toml"), &*PAIR).unwrap();
    std::fs::write(dir.join("target.csv"), "keep").unwrap();
    std::os::unix::fs::symlink("target.csv", dir.join("link.csv")).unwrap();
    let mut refused = vec![("link.csv", "symbolic link")];
    // mkfifo may be missing on a minimal system; the symlink cases still run.
    if Command::new("mkfifo")
        .arg(dir.join("fifo.csv"))
        .status()
        .is_ok_and(|s| s.success())
    {
        refused.push(("fifo.csv", "FIFO"));
    }
    for (path, what) in refused {
        let out = contactdd(
            &dir,
            &["sweep", "pair.toml", "--gamma", "0.5", "--out", path],
        );
        assert_eq!(out.status.code(), Some(1), "{path}: {}", stderr(&out));
        assert_clean_stderr(&out);
        let err = stderr(&out);
        assert!(err.contains(path) && err.contains(what), "{err}");
    }
    let link = std::fs::symlink_metadata(dir.join("link.csv")).unwrap();
    assert!(link.file_type().is_symlink());
    assert_eq!(
        std::fs::read_to_string(dir.join("target.csv")).unwrap(),
        "keep"
    );
    // A result file of `solve` that is a symlink is refused the same way.
    std::fs::create_dir_all(dir.join("res")).unwrap();
    std::os::unix::fs::symlink("../target.csv", dir.join("res/summary.json")).unwrap();
    let out = contactdd(&dir, &["solve", "pair.toml", "--out", "res"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("symbolic link"), "{}", stderr(&out));
    assert_eq!(
        std::fs::read_to_string(dir.join("target.csv")).unwrap(),
        "keep"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn command_line_options_override_the_file() {
    let dir = temp_dir("override");
    std::fs::write(dir.join("pair.toml"), &*PAIR).unwrap();
    let out = contactdd(
        &dir,
        &[
            "solve",
            "pair.toml",
            "--method",
            "robin",
            "--gamma",
            "auto",
            "--tol",
            "1e-6",
            "--max-iter",
            "300",
            "--threads",
            "1",
            "--quiet",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out).lines().count(), 1, "--quiet: one line");
    // The default output folder is ./<problem name>-out.
    let summary = read_json(&dir.join("pair-out/summary.json"));
    assert_eq!(summary["method"], "robin");
    assert_eq!(summary["gamma"], "auto");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sweep_writes_the_csv_table() {
    let dir = temp_dir("sweep");
    let notch = notch_example();
    let out = contactdd(
        &dir,
        &[
            "sweep",
            notch.to_str().unwrap(),
            "--method",
            "active-set,newton-kurchatov",
            "--gamma",
            "0.3:0.5:0.1,auto",
            "--out",
            "table.csv",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_clean_stderr(&out);
    let text = stdout(&out);
    assert!(
        text.contains("active-set") && text.contains("auto"),
        "{text}"
    );
    let csv = std::fs::read_to_string(dir.join("table.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("method,gamma,iterations,converged,reason")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 2 * 4, "{csv}");
    assert!(rows.iter().any(|r| r.starts_with("active-set,0.3,")));
    assert!(rows.iter().any(|r| r.starts_with("newton-kurchatov,auto,")));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_describes_the_problem() {
    let dir = temp_dir("check");
    let notch = notch_example();
    let out = contactdd(&dir, &["check", notch.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    for word in [
        "body lower",
        "body upper",
        "561 nodes",
        "contact pair",
        "θ =",
        "solver:",
    ] {
        assert!(text.contains(word), "'{word}' not in:\n{text}");
    }
    assert!(
        std::fs::read_dir(&dir).unwrap().next().is_none(),
        "check writes nothing"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn monolithic_reports_its_newton_steps_and_rigid_modes() {
    let dir = temp_dir("monolithic");
    std::fs::write(dir.join("pair.toml"), &*PAIR).unwrap();
    let out = contactdd(&dir, &["monolithic", "pair.toml", "--out", "mono"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("semismooth Newton steps"), "{text}");
    assert!(text.contains("rigid modes fixed"), "{text}");
    let summary = read_json(&dir.join("mono/summary.json"));
    assert_eq!(summary["solver"], "monolithic");
    assert_eq!(summary["converged"], true);
    assert!(dir.join("mono/upper.vtu").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Cut short, the monolithic solve exits 2, still writes its last iterate marked not converged,
/// and printed one line per Newton step.
#[test]
fn monolithic_cut_short_writes_its_last_iterate_and_exits_2() {
    let dir = temp_dir("monolithic-short");
    let file = notch_example();
    let file = file.to_str().unwrap();
    let out = contactdd(
        &dir,
        &["monolithic", file, "--out", "m", "--max-steps", "1"],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("not converged"), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("NOT converged"), "{text}");
    let steps: Vec<&str> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("1 "))
        .collect();
    assert_eq!(steps.len(), 1, "{text}");
    let summary = read_json(&dir.join("m/summary.json"));
    assert_eq!(summary["converged"], false);
    assert!(summary["message"]
        .as_str()
        .unwrap()
        .contains("did not settle"));
    assert_eq!(summary["history"].as_array().unwrap().len(), 1);
    for name in ["contact.csv", "lower.vtu", "upper.vtu"] {
        assert!(dir.join("m").join(name).is_file(), "{name}");
    }
    // Without the cap it converges; --quiet prints the result line only.
    let out = contactdd(&dir, &["monolithic", file, "--out", "m", "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out).lines().count(), 1, "{}", stdout(&out));
    assert_eq!(read_json(&dir.join("m/summary.json"))["converged"], true);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Load steps that stop below the full load: `summary.json` gives the applied loads of the last
/// step, so that they and the reactions balance; factors that do not increase are refused.
#[test]
fn the_summary_of_load_steps_is_at_the_last_steps_load() {
    let dir = temp_dir("partial-steps");
    // The default solver: with PAIR's own sweeps the first step stops unconverged.
    let newton = PAIR.replace("method = \"newton-kurchatov\"\ngamma = 0.5\n", "");
    let steps = newton.replace("tol = 1e-8", "tol = 1e-8\nload-steps = [0.25, 0.5]");
    std::fs::write(dir.join("pair.toml"), &steps).unwrap();
    let out = contactdd(&dir, &["solve", "pair.toml", "--out", "res", "--quiet"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let summary = read_json(&dir.join("res/summary.json"));
    // The upper block's top (2 long) carries the pressure 100, half of it at the last step.
    let applied = &summary["bodies"][1]["applied_load"];
    assert!(
        (applied[1].as_f64().unwrap() + 100.0).abs() < 1e-9,
        "{applied}"
    );
    let mut net = [0.0f64; 2];
    for b in 0..2 {
        for c in 0..2 {
            net[c] += summary["bodies"][b]["applied_load"][c].as_f64().unwrap();
            net[c] += summary["reactions"][b]["total"][c].as_f64().unwrap();
        }
    }
    assert!(net.iter().all(|f| f.abs() < 1e-6 * 100.0), "{net:?}");

    let unsorted = PAIR.replace("tol = 1e-8", "tol = 1e-8\nload-steps = [0.5, 0.25]");
    std::fs::write(dir.join("unsorted.toml"), unsorted).unwrap();
    let out = contactdd(
        &dir,
        &["solve", "unsorted.toml", "--out", "res2", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("must increase"), "{}", stderr(&out));
    let _ = std::fs::remove_dir_all(&dir);
}
