//! `contactdd plot` with friction, on result folders written by hand in the format of
//! docs/outputs.md: a frictional pair gets `friction-<pair>` with σ_t of contact.csv and the bound
//! ±μp (Coulomb) or ±bound where p > 0 (Tresca) computed here from the pressures; load steps with
//! `<pair>_tangential_force` get `steps-tangential-force`; the same folder without the friction
//! columns gets no friction figure; malformed friction data is an error naming the file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "contactdd-plot-friction-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn contactdd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .output()
        .expect("run contactdd")
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// Plots `dir` as SVG into `dir/plots`; returns the names of the files written.
fn plot(dir: &Path) -> Vec<String> {
    let o = contactdd(&["plot", path(dir), "--format", "svg"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let mut names: Vec<String> = std::fs::read_dir(dir.join("plots"))
        .expect("plots")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Plots `dir` expecting exit 1; returns stderr.
fn refused(dir: &Path) -> String {
    let o = contactdd(&["plot", path(dir), "--format", "svg"]);
    assert_eq!(o.status.code(), Some(1), "plot accepted a malformed folder");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The point lists of the SVG's polylines, in pixels.
fn polylines(svg: &str) -> Vec<Vec<(f64, f64)>> {
    svg.split("<polyline")
        .skip(1)
        .filter_map(|s| {
            let start = s.find("points=\"")? + 8;
            let end = start + s[start..].find('"')?;
            let pts = s[start..end]
                .split_whitespace()
                .filter_map(|xy| {
                    let (x, y) = xy.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect();
            Some(pts)
        })
        .collect()
}

/// The reference side `base`: 11 points on y = 0 from x = 0 to 1; pressed (p = 10) from 0.2 to
/// 0.8, sticking inside 0.4..0.6 and slipping at μp = 3 (Coulomb, μ = 0.3) from there to the
/// edges of the pressed zone. As (x, p, σ_t, status).
fn base() -> Vec<(f64, f64, f64, &'static str)> {
    (0..=10)
        .map(|i| {
            let x = f64::from(i) / 10.0;
            let p = if (2..=8).contains(&i) { 10.0 } else { 0.0 };
            let (t, status) = match i {
                4..=6 => (5.0 * (x - 0.5), "stick"),
                2 | 3 | 7 | 8 => (if i < 5 { -3.0 } else { 3.0 }, "slip"),
                _ => (0.0, "open"),
            };
            (x, p, t, status)
        })
        .collect()
}

/// contact.csv of the pair `block-base`: base's points (above) and the block's, which read the
/// pressure and carry no tangential traction; with the four friction columns if `friction`.
fn contact_csv(friction: bool) -> String {
    let mut text = "pair,body,x,y,gap,pressure,nodal_traction,status".to_string();
    if friction {
        text += ",tangential_traction,slip,total_slip,friction";
    }
    text += "\n";
    for (body, points) in [("block", base()), ("base", base())] {
        for (x, p, t, status) in points {
            let (gap, closed) = if p > 0.0 {
                (-1e-4, "closed")
            } else {
                (0.01, "open")
            };
            let t = if body == "base" { t } else { 0.0 };
            let status = if body == "base" { status } else { "open" };
            text += &format!("block-base,{body},{x},0,{gap},{p},{},{closed}", -p);
            if friction {
                text += &format!(",{t},{},{},{status}", t / 1e4, t / 5e3);
            }
            text += "\n";
        }
    }
    text
}

/// A result folder: summary.json naming `files`, the pair's friction `law` (a JSON object) if
/// given, and contact.csv.
fn folder(name: &str, law: Option<&str>, files: &[&str], friction_columns: bool) -> PathBuf {
    let dir = temp(name);
    let friction = law.map_or_else(String::new, |l| {
        format!(
            r#", "friction": {l}, "tangential_force": 0.0, "stick_length": 0.2, "slip_length": 0.4"#
        )
    });
    let files: Vec<String> = files.iter().map(|f| format!("\"{f}\"")).collect();
    let summary = format!(
        r#"{{"units": "mm, MPa", "files": [{}], "bodies": [{{"name": "block"}}, {{"name": "base"}}],
            "contact": [{{"name": "block-base", "bodies": ["block", "base"]{friction}}}]}}"#,
        files.join(", ")
    );
    std::fs::write(dir.join("summary.json"), summary).expect("write");
    std::fs::write(dir.join("contact.csv"), contact_csv(friction_columns)).expect("write");
    dir
}

const COULOMB: &str = r#"{"law": "coulomb", "mu": 0.3}"#;

/// The data-to-pixel map of the vertical axis, fitted on the smallest and largest values of a
/// curve drawn through `data`.
fn vertical_map(data: &[f64], px: &[(f64, f64)]) -> impl Fn(f64) -> f64 {
    let lo = (0..data.len())
        .min_by(|&a, &b| data[a].total_cmp(&data[b]))
        .unwrap();
    let hi = (0..data.len())
        .max_by(|&a, &b| data[a].total_cmp(&data[b]))
        .unwrap();
    let slope = (px[hi].1 - px[lo].1) / (data[hi] - data[lo]);
    let (d0, p0) = (data[lo], px[lo].1);
    move |v| p0 + slope * (v - d0)
}

/// Checks the friction figure of the hand-made pair: σ_t of contact.csv and the bounds ±`limit(p)`.
fn check_bounds(svg: &str, limit: impl Fn(f64) -> f64) {
    let points = base();
    // The window: the pressed zone and as much again around it, within 0..1 — every point.
    let lines: Vec<Vec<(f64, f64)>> = polylines(svg)
        .into_iter()
        .filter(|l| l.len() == points.len())
        .collect();
    // The upper bound, the lower bound, then σ_t (only base carries it: three curves).
    assert_eq!(lines.len(), 3, "{lines:?}");
    let traction: Vec<f64> = points.iter().map(|p| p.2).collect();
    let to_y = vertical_map(&traction, &lines[2]);
    for (k, &(x, p, t, _)) in points.iter().enumerate() {
        for (line, want) in [
            (&lines[0], limit(p)),
            (&lines[1], -limit(p)),
            (&lines[2], t),
        ] {
            assert!(
                (to_y(want) - line[k].1).abs() <= 1.0,
                "x = {x}: {want} drawn at pixel {} (expected {})",
                line[k].1,
                to_y(want)
            );
        }
    }
}

#[test]
fn a_coulomb_pair_gets_its_friction_figure() {
    let dir = folder("coulomb", Some(COULOMB), &["contact.csv"], true);
    let names = plot(&dir);
    assert_eq!(
        names,
        [
            "friction-block-base.svg",
            "gap-block-base.svg",
            "pressure-block-base.svg"
        ]
    );
    let svg = read(&dir.join("plots/friction-block-base.svg"));
    for label in [
        "tangential traction and friction bound, pair block-base",
        "tangential traction σ_t (MPa)",
        "x (mm)",
        "σ_t on base",
        "Coulomb ±μp, μ = 0.3",
        "stick",
        "slip",
        "open",
    ] {
        assert!(svg.contains(label), "friction figure lacks '{label}'");
    }
    // The block carries no tangential traction: it is not drawn.
    assert!(!svg.contains("σ_t on block"));
    check_bounds(&svg, |p| 0.3 * p);
    // The stick zone (0.35..0.65) and the two slip zones (0.15..0.35, 0.65..0.85) are shaded:
    // filled rectangles in the status colours, see-through.
    let shade = |color: &str| {
        svg.split("<rect")
            .skip(1)
            .map(|r| &r[..r.find('>').unwrap_or(r.len())])
            .filter(|r| r.contains(&format!("fill=\"{color}\"")) && r.contains("opacity=\"0.18\""))
            .count()
    };
    assert_eq!((shade("#009E73"), shade("#E69F00")), (1, 2));
}

#[test]
fn a_tresca_bound_holds_where_the_pair_presses() {
    let dir = folder(
        "tresca",
        Some(r#"{"law": "tresca", "bound": 2.5}"#),
        &["contact.csv"],
        true,
    );
    plot(&dir);
    let svg = read(&dir.join("plots/friction-block-base.svg"));
    assert!(svg.contains("Tresca ±2.5 where p &gt; 0") || svg.contains("Tresca ±2.5 where p > 0"));
    check_bounds(&svg, |p| if p > 0.0 { 2.5 } else { 0.0 });
}

#[test]
fn a_frictionless_folder_gets_no_friction_figure() {
    let dir = folder("frictionless", None, &["contact.csv"], false);
    assert_eq!(
        plot(&dir),
        ["gap-block-base.svg", "pressure-block-base.svg"]
    );
    // The pressure figure is the same as that of the frictional folder: the friction columns
    // change no other figure.
    let frictional = folder("frictional-twin", Some(COULOMB), &["contact.csv"], true);
    plot(&frictional);
    for name in ["pressure-block-base.svg", "gap-block-base.svg"] {
        let (a, b) = (
            dir.join("plots").join(name),
            frictional.join("plots").join(name),
        );
        assert_eq!(read(&a), read(&b), "{name}");
    }
    // Friction columns whose every point is open, and no law in the summary: no figure either.
    let open = folder("all-open", None, &["contact.csv"], true);
    let text = read(&open.join("contact.csv"))
        .replace(",stick\n", ",open\n")
        .replace(",slip\n", ",open\n");
    std::fs::write(open.join("contact.csv"), text).expect("write");
    assert_eq!(
        plot(&open),
        ["gap-block-base.svg", "pressure-block-base.svg"]
    );
}

#[test]
fn malformed_friction_data_is_named() {
    // Each edit of contact.csv's friction columns, and the words its message must hold.
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            ",-3,-0.0003,",
            ",oops,-0.0003,",
            &["tangential_traction", "not a number"],
        ),
        (
            ",-0.0003,-0.0006,slip",
            ",-0.0003,x,slip",
            &["total_slip", "not a number"],
        ),
        (
            ",stick\n",
            ",skid\n",
            &["'skid' is not a friction status (open, stick or slip)"],
        ),
        (
            ",tangential_traction,slip,total_slip,friction",
            ",tangential_traction,sliding,total_slip,friction",
            &["no column 'slip'"],
        ),
    ];
    for (k, (from, to, words)) in cases.into_iter().enumerate() {
        let dir = folder(
            &format!("malformed-{k}"),
            Some(COULOMB),
            &["contact.csv"],
            true,
        );
        let file = dir.join("contact.csv");
        let text = read(&file);
        assert!(text.contains(from), "case {k}: the hand-made file changed");
        std::fs::write(&file, text.replacen(from, to, 1)).expect("write");
        let err = refused(&dir);
        assert!(err.contains("contact.csv"), "case {k}: {err}");
        for w in words {
            assert!(err.contains(w), "case {k}: {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    // A law that is not one.
    for law in [
        r#"{"law": "coulomb"}"#,
        r#"{"law": "coulomb", "mu": -0.3}"#,
        r#"{"law": "stiction", "mu": 0.3}"#,
    ] {
        let dir = folder("bad-law", Some(law), &["contact.csv"], true);
        let err = refused(&dir);
        assert!(
            err.contains("summary.json")
                && err.contains("pair 'block-base'")
                && err.contains("not a friction law"),
            "{law}: {err}"
        );
    }
}

/// steps.csv of three steps (the second not converged), with `block-base_tangential_force` if
/// `friction`.
fn steps_csv(friction: bool) -> String {
    let mut text = "step,factor,converged,iterations,block-base_force_x,block-base_force_y,\
                    block-base_contact_length,block-base_max_pressure"
        .to_string();
    text += if friction {
        ",block-base_tangential_force\n"
    } else {
        "\n"
    };
    for (k, (ok, ft)) in [(true, -0.4), (false, -0.9), (true, -1.2)]
        .into_iter()
        .enumerate()
    {
        let f = (k + 1) as f64;
        text += &format!(
            "{},{},{ok},5,{},{},0.6,{}",
            k + 1,
            f / 3.0,
            0.5 * f,
            -2.0 * f,
            3.0 * f
        );
        if friction {
            text += &format!(",{ft}");
        }
        text += "\n";
    }
    text
}

#[test]
fn load_steps_with_friction_get_the_tangential_force() {
    let dir = folder("steps", Some(COULOMB), &["contact.csv", "steps.csv"], true);
    std::fs::write(dir.join("steps.csv"), steps_csv(true)).expect("write");
    let names = plot(&dir);
    assert!(
        names.contains(&"steps-tangential-force.svg".to_string()),
        "{names:?}"
    );
    assert!(names.contains(&"steps-force.svg".to_string()), "{names:?}");
    let svg = read(&dir.join("plots/steps-tangential-force.svg"));
    for label in [
        "tangential contact force per load step",
        "resultant tangential force F_t (N/mm)",
        "load factor",
        "pair block-base",
        "step not converged",
    ] {
        assert!(
            svg.contains(label),
            "tangential force figure lacks '{label}'"
        );
    }
    // From the unloaded state through the three steps: the forces, signed, on a linear axis.
    let line = polylines(&svg)
        .into_iter()
        .find(|l| l.len() == 4)
        .expect("a polyline through (0, 0) and three steps");
    let forces = [0.0, -0.4, -0.9, -1.2];
    let to_y = vertical_map(&forces, &line);
    for (k, f) in forces.iter().enumerate() {
        assert!((to_y(*f) - line[k].1).abs() <= 1.0, "step {k}: {line:?}");
    }
    // Negative forces lie below the start (larger pixel y).
    assert!(line[3].1 > line[0].1);

    // Without the column: no such figure, the others as before.
    let plain = folder(
        "steps-plain",
        Some(COULOMB),
        &["contact.csv", "steps.csv"],
        true,
    );
    std::fs::write(plain.join("steps.csv"), steps_csv(false)).expect("write");
    let names = plot(&plain);
    assert!(
        !names.contains(&"steps-tangential-force.svg".to_string()),
        "{names:?}"
    );
    let (a, b) = (
        dir.join("plots/steps-force.svg"),
        plain.join("plots/steps-force.svg"),
    );
    assert_eq!(read(&a), read(&b));

    // A force that is not a number is named.
    std::fs::write(
        dir.join("steps.csv"),
        steps_csv(true).replace("-0.9", "n/a"),
    )
    .expect("write");
    let err = refused(&dir);
    assert!(
        err.contains("steps.csv") && err.contains("block-base_tangential_force"),
        "{err}"
    );
}
