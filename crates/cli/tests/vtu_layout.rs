//! `--vtu-layout` of `contactdd solve` and `contactdd monolithic` and `[output] vtu-layout`: the
//! `collection` layout writes one `bodies.vtu` (`bodies-step<k>.vtu` per load step) in the place
//! of the bodies' files, the option overrides the file, and `contactdd plot` draws the same bodies
//! figure from either layout.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-layout-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn contactdd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .output()
        .expect("run contactdd")
}

fn succeeded(o: &Output) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// The `.vtu` names of the folder's manifest, in order.
fn vtu_files(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    let summary: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    (summary["files"].as_array().expect("a manifest").iter())
        .filter_map(|f| f.as_str())
        .filter(|f| f.ends_with(".vtu"))
        .map(str::to_string)
        .collect()
}

#[test]
fn collection_writes_one_file_and_plots_the_same_bodies() {
    let dir = temp("solve");
    let file = example("three_bodies.toml");
    let mut figures = Vec::new();
    for layout in ["per-body", "collection"] {
        let out = dir.join(layout);
        let args = ["solve", path(&file), "--out", path(&out), "--quiet"];
        succeeded(&contactdd(&[&args[..], &["--vtu-layout", layout]].concat()));
        let files = vtu_files(&out);
        if layout == "collection" {
            assert_eq!(files, ["bodies.vtu"]);
        } else {
            assert_eq!(files.len(), 3, "{files:?}");
        }
        succeeded(&contactdd(&["plot", path(&out), "--format", "svg"]));
        let svg = std::fs::read_to_string(out.join("plots/bodies.svg")).expect("bodies.svg");
        figures.push(svg);
    }
    assert_eq!(figures[0], figures[1]);
    // An input error (exit 1) naming the two layouts.
    let o = contactdd(&["solve", path(&file), "--vtu-layout", "single"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("'per-body' or 'collection'"), "{err}");
}

/// The file's `[output] vtu-layout` is followed, the option overrides it; load steps get one file
/// per step; `contactdd monolithic` takes the option too.
#[test]
fn the_file_key_the_option_steps_and_monolithic() {
    let dir = temp("file");
    let text = std::fs::read_to_string(example("recess_steps.toml")).expect("example");
    assert!(!text.contains("[output]"));
    let toml = dir.join("recess.toml");
    std::fs::write(
        &toml,
        format!("{text}\n[output]\nvtu-layout = \"collection\"\n"),
    )
    .expect("w");
    let out = dir.join("file");
    succeeded(&contactdd(&[
        "solve",
        path(&toml),
        "--out",
        path(&out),
        "-q",
    ]));
    let files = vtu_files(&out);
    assert!(!files.is_empty());
    for (k, f) in files.iter().enumerate() {
        assert_eq!(f, &format!("bodies-step{}.vtu", k + 1));
    }
    let out = dir.join("option");
    let args = ["solve", path(&toml), "--out", path(&out), "-q"];
    succeeded(&contactdd(
        &[&args[..], &["--vtu-layout", "per-body"]].concat(),
    ));
    assert!(vtu_files(&out).iter().all(|f| !f.starts_with("bodies")));

    let out = dir.join("monolithic");
    let notch = example("notch.toml");
    let args = ["monolithic", path(&notch), "--out", path(&out), "-q"];
    succeeded(&contactdd(
        &[&args[..], &["--vtu-layout", "collection"]].concat(),
    ));
    assert_eq!(vtu_files(&out), ["bodies.vtu"]);
}
