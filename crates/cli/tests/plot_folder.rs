//! `contactdd plot` on a hostile result folder: a listed file that is a symbolic link (to
//! `/dev/zero`, or to a sound file elsewhere), a FIFO, a file over the size limit, a `plots/`
//! that links to another folder, a figure name that links elsewhere, a `summary.json` that is not
//! an object or holds a key of the wrong type, and a summary that lists nothing to draw. Each is
//! exit 1 with a message naming the file, well within a timeout (a hang fails the test instead
//! of blocking it), and nothing is written outside the folder.

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest a run may take before it counts as a hang.
const TIMEOUT: Duration = Duration::from_secs(20);

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-plotdir-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// Exit code (`None` for a signal) and stderr of `contactdd args`, killed after [`TIMEOUT`].
fn run(args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run contactdd");
    let mut stderr = child.stderr.take().expect("stderr");
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("contactdd {args:?} still running after {TIMEOUT:?}: it hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status.code(), reader.join().expect("stderr reader"))
}

/// Solves the notch example into `dir/out` and returns that folder.
fn solved_notch(dir: &Path) -> PathBuf {
    let out = dir.join("out");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml");
    let (code, err) = run(&["solve", path(&file), "--out", path(&out), "--quiet"]);
    assert_eq!(code, Some(0), "{err}");
    out
}

/// Asserts exit 1 with a message holding every one of `words`.
fn refused(args: &[&str], words: &[&str]) {
    let (code, err) = run(args);
    assert_eq!(code, Some(1), "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: message lacks '{w}': {err}");
    }
}

fn replace_with_link(file: &Path, target: &Path) {
    std::fs::remove_file(file).expect("remove");
    std::os::unix::fs::symlink(target, file).expect("symlink");
}

fn mkfifo(file: &Path) {
    let _ = std::fs::remove_file(file);
    let made = Command::new("mkfifo").arg(file).status().expect("mkfifo");
    assert!(made.success(), "mkfifo {}", file.display());
}

#[test]
fn a_vtu_linked_to_dev_zero_is_refused_at_once() {
    let dir = temp("zero");
    let out = solved_notch(&dir);
    replace_with_link(&out.join("lower.vtu"), Path::new("/dev/zero"));
    let start = Instant::now();
    refused(&["plot", path(&out)], &["lower.vtu", "symbolic link"]);
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn a_link_to_a_sound_file_is_not_followed_either() {
    let dir = temp("elsewhere");
    let out = solved_notch(&dir);
    // The same bytes, outside the folder: the link, not the content, is refused.
    let outside = dir.join("history-elsewhere.csv");
    std::fs::copy(out.join("history.csv"), &outside).expect("copy");
    replace_with_link(&out.join("history.csv"), &outside);
    refused(&["plot", path(&out)], &["history.csv", "symbolic link"]);
    // summary.json itself, linked, is refused too.
    let summary = dir.join("summary-elsewhere.json");
    std::fs::copy(out.join("summary.json"), &summary).expect("copy");
    replace_with_link(&out.join("summary.json"), &summary);
    refused(&["plot", path(&out)], &["summary.json", "symbolic link"]);
}

#[test]
fn fifos_never_block() {
    let dir = temp("fifo");
    let out = solved_notch(&dir);
    for name in ["upper.vtu", "contact.csv", "summary.json"] {
        let file = out.join(name);
        let keep = std::fs::read(&file).expect("read");
        mkfifo(&file);
        refused(
            &["plot", path(&out), "--format", "svg"],
            &[name, "not a regular file"],
        );
        std::fs::remove_file(&file).expect("remove fifo");
        std::fs::write(&file, keep).expect("restore");
    }
    // Restored, the folder plots again: the refusals were the FIFOs' doing.
    let (code, err) = run(&["plot", path(&out), "--format", "svg"]);
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn files_over_the_size_limit_are_refused_unread() {
    let dir = temp("large");
    let out = solved_notch(&dir);
    // Sparse files: their length is over the limit, no disk is used and nothing is read.
    for (name, limit) in [("contact.csv", 256u64 << 20), ("lower.vtu", 1 << 30)] {
        let file = out.join(name);
        let keep = std::fs::read(&file).expect("read");
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(&file)
            .expect("open");
        f.set_len(limit + 1).expect("grow");
        drop(f);
        refused(
            &["plot", path(&out), "--format", "svg"],
            &[name, "larger than"],
        );
        std::fs::write(&file, keep).expect("restore");
    }
    // Restored, the folder plots again: the refusals were the sizes' doing.
    let (code, err) = run(&["plot", path(&out), "--format", "svg"]);
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn a_plots_link_to_another_folder_gets_nothing() {
    let dir = temp("plotslink");
    let out = solved_notch(&dir);
    let elsewhere = dir.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).expect("mkdir");
    std::os::unix::fs::symlink(&elsewhere, out.join("plots")).expect("symlink");
    refused(&["plot", path(&out)], &["plots", "symbolic link"]);
    let names: Vec<_> = std::fs::read_dir(&elsewhere).expect("read").collect();
    assert!(names.is_empty(), "written outside the folder: {names:?}");
    // The same through --out, and a file where the folder should be.
    refused(
        &["plot", path(&out), "--out", path(&out.join("plots"))],
        &["symbolic link"],
    );
    assert!(std::fs::read_dir(&elsewhere)
        .expect("read")
        .next()
        .is_none());
    std::fs::remove_file(out.join("plots")).expect("unlink");
    std::fs::write(out.join("plots"), "a file").expect("write");
    refused(&["plot", path(&out)], &["plots", "not a folder"]);
}

#[test]
fn a_figure_name_linking_elsewhere_is_not_followed() {
    let dir = temp("figlink");
    let out = solved_notch(&dir);
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots).expect("mkdir");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep").expect("write");
    std::os::unix::fs::symlink(&victim, plots.join("history.svg")).expect("symlink");
    refused(
        &["plot", path(&out), "--format", "svg"],
        &["history.svg", "symbolic link"],
    );
    assert_eq!(std::fs::read_to_string(&victim).expect("read"), "keep");
    assert!(std::fs::symlink_metadata(plots.join("history.svg"))
        .expect("stat")
        .file_type()
        .is_symlink());
}

#[test]
fn a_summary_that_is_not_an_object_is_refused() {
    let dir = temp("array");
    let out = solved_notch(&dir);
    for (text, what) in [
        ("[]", "an array"),
        ("42", "a number"),
        ("\"x\"", "a string"),
        ("null", "null"),
    ] {
        std::fs::write(out.join("summary.json"), text).expect("write");
        refused(
            &["plot", path(&out)],
            &["summary.json", what, "not a JSON object"],
        );
    }
    assert!(
        !out.join("plots").exists(),
        "an empty plots folder was left"
    );
}

#[test]
fn keys_of_the_wrong_type_are_refused() {
    let dir = temp("types");
    let out = solved_notch(&dir);
    let file = out.join("summary.json");
    let sound: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).expect("read")).expect("json");
    for (key, value, words) in [
        (
            "contact",
            serde_json::json!("x"),
            ["\"contact\" is a string", "array"],
        ),
        (
            "contact",
            serde_json::json!([1]),
            ["\"contact\" item 1 is a number", "pair"],
        ),
        (
            "files",
            serde_json::json!({}),
            ["\"files\" is an object", "array"],
        ),
        (
            "files",
            serde_json::json!(["contact.csv", 3]),
            ["\"files\" item 2", "file name"],
        ),
        (
            "bodies",
            serde_json::json!([{"name": 1}]),
            ["\"bodies\" item 1", "\"name\""],
        ),
        (
            "tol",
            serde_json::json!("1e-8"),
            ["\"tol\" is a string", "a number"],
        ),
        (
            "units",
            serde_json::json!(["cm"]),
            ["\"units\" is an array", "a string"],
        ),
        (
            "steps",
            serde_json::json!(3),
            ["\"steps\" is a number", "array"],
        ),
        (
            "monitor",
            serde_json::json!({"body": "upper"}),
            ["\"monitor\"", "\"boundary\""],
        ),
    ] {
        let mut broken = sound.clone();
        broken[key] = value;
        std::fs::write(&file, broken.to_string()).expect("write");
        let mut all = vec!["summary.json"];
        all.extend(words);
        refused(&["plot", path(&out), "--format", "svg"], &all);
    }
    let mut none = sound.clone();
    none.as_object_mut().expect("object").remove("files");
    std::fs::write(&file, none.to_string()).expect("write");
    refused(&["plot", path(&out)], &["summary.json", "'files'"]);
    // null is how the summary writes a value it lacks: no error.
    let mut nulls = sound;
    for key in ["tol", "units", "monitor", "steps"] {
        nulls[key] = serde_json::Value::Null;
    }
    std::fs::write(&file, nulls.to_string()).expect("write");
    let (code, err) = run(&["plot", path(&out), "--format", "svg"]);
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn nothing_to_draw_is_an_error() {
    let dir = temp("nothing");
    let out = solved_notch(&dir);
    let file = out.join("summary.json");
    let mut summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).expect("read")).expect("json");
    // Only results.pvd, which plot does not draw; and an empty list.
    for files in [serde_json::json!(["results.pvd"]), serde_json::json!([])] {
        summary["files"] = files;
        std::fs::write(&file, summary.to_string()).expect("write");
        refused(
            &["plot", path(&out)],
            &["summary.json", "no figure to draw"],
        );
        assert!(
            !out.join("plots").exists(),
            "an empty plots folder was left"
        );
    }
}
