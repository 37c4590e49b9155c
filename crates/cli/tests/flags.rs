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

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("a summary");
    serde_json::from_str(&text).expect("json")
}

fn header(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("contact.csv")).expect("a contact.csv");
    text.lines().next().expect("a header").to_string()
}

/// `--friction` overrides every pair's friction on solve and check; the monolithic reference
/// refuses friction with a message that says how to go without; a frictionless solve's contact.csv
/// has no friction column.
#[test]
fn friction_flag_overrides_every_pair() {
    let dir = std::env::temp_dir().join(format!("contactdd-friction-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let block = example("friction_block.toml");
    let os = |s: &str| std::ffi::OsString::from(s);
    let out = dir.join("tresca");
    let run = contactdd(&[
        &os("solve"),
        block.as_os_str(),
        &os("--friction"),
        &os("tresca:3"),
        &os("-q"),
        &os("-o"),
        out.as_os_str(),
    ]);
    assert!(run.status.success(), "{run:?}");
    let s = summary(&out);
    let pair = &s["contact"][0];
    assert_eq!(
        pair["friction"],
        serde_json::json!({ "law": "tresca", "bound": 3.0 })
    );
    // Tresca's bound 3 over the 2 long zone holds up to 6 > 4: the block is held, and its
    // friction force is the push.
    assert!(
        (pair["tangential_force"].as_f64().unwrap() + 4.0).abs() < 1e-8,
        "{pair}"
    );
    assert!(header(&out).ends_with(",tangential_traction,slip,total_slip,friction"));

    // A frictionless problem made frictional, and the check's description of its pairs.
    let stack = example("stack.toml");
    let run = contactdd(&[
        &os("check"),
        stack.as_os_str(),
        &os("--friction"),
        &os("coulomb:0.2"),
    ]);
    assert!(run.status.success(), "{run:?}");
    let text = String::from_utf8_lossy(&run.stdout);
    assert_eq!(
        text.matches("; friction: Coulomb, mu = 0.2").count(),
        7,
        "{text}"
    );
    let run = contactdd(&[&os("check"), block.as_os_str()]);
    assert!(String::from_utf8_lossy(&run.stdout).contains("; friction: Coulomb, mu = 0.3"));
    let notch = notch();
    let run = contactdd(&[&os("check"), notch.as_os_str()]);
    // A frictionless problem is described as it always was.
    let text = String::from_utf8_lossy(&run.stdout).into_owned();
    assert!(
        text.contains("with a gap profile\n") && !text.contains("friction"),
        "{text}"
    );

    let out = dir.join("notch");
    let run = contactdd(&[
        &os("solve"),
        notch.as_os_str(),
        &os("-q"),
        &os("-o"),
        out.as_os_str(),
    ]);
    assert!(run.status.success(), "{run:?}");
    assert_eq!(
        header(&out),
        "pair,body,x,y,gap,pressure,nodal_traction,status"
    );
    assert!(summary(&out)["contact"][0].get("friction").is_none());

    let out = dir.join("mono");
    let run = contactdd(&[
        &os("monolithic"),
        block.as_os_str(),
        &os("-o"),
        out.as_os_str(),
    ]);
    // The monolithic reference solves the frictional problem too.
    assert_eq!(
        run.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );

    for (bad, says) in [("coulomb:-1", "at least 0"), ("stick", "unknown friction")] {
        let run = contactdd(&[&os("solve"), block.as_os_str(), &os("--friction"), &os(bad)]);
        assert_eq!(run.status.code(), Some(1));
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(err.contains("--friction") && err.contains(says), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Robin sweeps with friction need `coarse = "off"`: `check` and `solve` refuse the default
/// coarse correction of the sweeps alike, naming the fix, and both accept it switched off.
#[test]
fn check_and_solve_agree_on_friction_with_the_sweeps() {
    let dir = std::env::temp_dir().join(format!("contactdd-sweeps-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let text = std::fs::read_to_string(example("friction_block.toml")).expect("the example");
    let os = |s: &str| std::ffi::OsString::from(s);
    for (coarse, accepted) in [("", false), ("coarse = \"off\"\n", true)] {
        let file = dir.join("block.toml");
        let solver = format!("\n[solver]\nmethod = \"active-set\"\n{coarse}");
        std::fs::write(&file, format!("{text}{solver}")).expect("written");
        let out = dir.join("out");
        for args in [
            vec![os("check"), file.clone().into()],
            vec![
                os("solve"),
                file.clone().into(),
                os("-q"),
                os("-o"),
                out.into(),
            ],
        ] {
            let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
            let run = contactdd(&args);
            let err = String::from_utf8_lossy(&run.stderr).into_owned();
            assert_eq!(run.status.success(), accepted, "{args:?}: {err}");
            assert_eq!(err.contains("needs coarse = \"off\""), !accepted, "{err}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
