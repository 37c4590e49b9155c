//! The commands on problem files in space (`dimension = 3`): the options of the planar iterations
//! are refused by name, a body its supports do not hold is named, bad values get messages that
//! name the body or pair, `check` describes, the `.vtu` layout option works, and a result folder
//! lists its files.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-space-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn blocks() -> String {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/space/blocks.toml");
    std::fs::read_to_string(file).expect("the example")
}

/// Writes `text` as `name` in `dir` and runs `contactdd args… file --out dir/out`.
fn run(dir: &Path, name: &str, text: &str, args: &[&str]) -> Output {
    let file = dir.join(name);
    std::fs::write(&file, text).expect("write");
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .arg(&file)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .expect("run contactdd")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn planar_options_are_refused_by_name() {
    let dir = temp("options");
    for option in [
        ["--method", "robin"],
        ["--gamma", "0.5"],
        ["--accelerator", "anderson"],
        ["--gap-tol", "1e-9"],
    ] {
        let mut args = vec!["solve"];
        args.extend(option);
        let o = run(&dir, "blocks.toml", &blocks(), &args);
        assert_eq!(o.status.code(), Some(1), "{option:?}");
        assert!(stderr(&o).contains(option[0]), "{}", stderr(&o));
        assert!(stderr(&o).contains("dimension = 3"), "{}", stderr(&o));
    }
}

/// `--friction` (or a pair's `friction` table): the result folder carries the tractions, the
/// summary the law, the tangential force and the statuses; a law without its parameter is an
/// error that names the key.
#[test]
fn friction_solves_and_reports_its_tractions() {
    let dir = temp("friction");
    let o = run(
        &dir,
        "blocks.toml",
        &blocks(),
        &["solve", "-q", "--friction", "coulomb:0.3"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).expect("summary");
    for key in [
        "\"friction_law\"",
        "\"tangential_force\"",
        "\"stick\"",
        "\"mu\": 0.3",
    ] {
        assert!(summary.contains(key), "{key} in {summary}");
    }
    let csv = std::fs::read_to_string(dir.join("out/contact.csv")).expect("contact.csv");
    assert!(csv.starts_with("pair,body,node,x,y,z,weight,gap,pressure,traction_x"));
    let text = blocks().replace(
        "penalty = { theta = 1e-7 }",
        "penalty = { theta = 1e-7 }\nfriction = { law = \"coulomb\" }",
    );
    let o = run(&dir, "bad.toml", &text, &["solve", "-q"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("friction.mu"), "{}", stderr(&o));
}

/// `--enforcement augmented` (or `enforcement = "augmented"` in the file): the decomposition
/// meets the contact exactly and the summary says so; so does the monolithic reference.
#[test]
fn augmented_pairs_solve_exactly() {
    let dir = temp("augmented");
    let o = run(
        &dir,
        "blocks.toml",
        &blocks(),
        &["solve", "-q", "--enforcement", "augmented"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).expect("summary");
    assert!(
        summary.contains("\"enforcement\": \"augmented\""),
        "{summary}"
    );
    assert!(summary.contains("\"gap_violation\""), "{summary}");
    let text = blocks().replace(
        "penalty = { theta = 1e-7 }",
        "penalty = { theta = 1e-7 }\nenforcement = \"augmented\"",
    );
    let o = run(&dir, "exact.toml", &text, &["monolithic", "-q"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).expect("summary");
    assert!(
        summary.contains("\"enforcement\": \"augmented\""),
        "{summary}"
    );
}

#[test]
fn a_body_its_supports_do_not_hold_is_named() {
    let dir = temp("held");
    // The upper block keeps only its pushed face: it may slide and turn about z.
    let text = blocks().replacen(
        "    { boundary = \"z+\", component = \"z\", value = -0.001 },\n    { boundary = \"x-\", component = \"x\" },\n    { boundary = \"y-\", component = \"y\" },",
        "    { boundary = \"z+\", component = \"z\", value = -0.001 },",
        1,
    );
    assert_ne!(text, blocks());
    let o = run(&dir, "free.toml", &text, &["solve"]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("body 'upper' is not held") && err.contains("3 of its 6"),
        "{err}"
    );
}

#[test]
fn bad_values_name_the_body_or_pair() {
    let dir = temp("values");
    let cases = [
        (
            "boundaries = [\"z-\", \"z+\"]",
            "boundaries = [\"z-\", \"roof\"]",
            "contact 'upper-lower'",
        ),
        ("young = 7e4", "young = -7e4", "material 'aluminium'"),
        ("nx = 6,", "nx = 0,", "body 'lower'"),
        ("dimension = 3", "dimension = 4", "dimension = 4"),
        (
            "penalty = { theta = 1e-7 }",
            "penalty = { theta = 0.0 }",
            "penalty.theta",
        ),
    ];
    for (from, to, named) in cases {
        let text = blocks().replacen(from, to, 1);
        assert_ne!(text, blocks(), "{from}");
        let o = run(&dir, "bad.toml", &text, &["solve"]);
        assert_eq!(o.status.code(), Some(1), "{to}");
        assert!(stderr(&o).contains(named), "{to}: {}", stderr(&o));
        assert!(!stderr(&o).contains("internal error"), "{}", stderr(&o));
    }
}

#[test]
fn check_describes_and_collection_writes_one_file() {
    let dir = temp("check");
    let file = dir.join("blocks.toml");
    std::fs::write(&file, blocks()).expect("write");
    let o = Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(["check"])
        .arg(&file)
        .output()
        .expect("run");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("body upper: 847 nodes"), "{out}");
    // The same solver name as the solve's console line and summary.json.
    assert!(
        out.contains("solver: interface newton (decomposition in space)"),
        "{out}"
    );
    let o = run(
        &dir,
        "blocks.toml",
        &blocks(),
        &["solve", "--vtu-layout", "collection", "-q"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("out/summary.json")).expect("summary"),
    )
    .expect("JSON");
    let files: Vec<&str> = (summary["files"].as_array().expect("files").iter())
        .filter_map(|f| f.as_str())
        .collect();
    assert_eq!(files, ["bodies.vtu", "contact.csv", "summary.json"]);
    for f in files {
        assert!(dir.join("out").join(f).is_file(), "{f}");
    }
    assert_eq!(summary["converged"], true);
    assert_eq!(summary["dimension"], 3);
}

#[test]
fn a_solve_reports_its_progress_unless_quiet() {
    let dir = temp("progress");
    let o = run(&dir, "blocks.toml", &blocks(), &["solve"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for line in [
        "contact geometry: 121 points",
        "body lower: factorised",
        "body upper: factorised",
        "Newton step 1: 121 closed",
        "converged in 1 Newton step",
    ] {
        assert!(out.contains(line), "{line}: {out}");
    }
    let o = run(&dir, "blocks.toml", &blocks(), &["solve", "-q"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(out.lines().count(), 1, "{out}");
}
