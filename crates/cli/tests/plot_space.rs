//! `contactdd plot` on result folders in space (examples/space/sphere_block.toml, the Hertz ball,
//! and blocks.toml, a uniform pressure), solved here through the binary: the pressure map and
//! the radial profile exist as SVG (well nested) and PNG, draw one disc per contact point in
//! view, a colour bar over [0, the largest pressure of contact.csv], a caption with the force
//! Σ w p and the peak of contact.csv, the profile's points by increasing distance from a centre
//! that the geometry fixes (the touching point of the ball, the middle of the blocks' face); a
//! folder without contact.csv is a clear error.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "contactdd-plot-space-{name}-{}",
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

fn succeeded(o: &Output) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// Solves examples/space/`name` into `dir/out`.
fn solved(dir: &Path, name: &str) -> PathBuf {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/space")
        .join(name);
    let out = dir.join("out");
    succeeded(&contactdd(&["solve", path(&file), "-o", path(&out), "-q"]));
    out
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The SVG text of `p`, checked to be one `<svg>` element whose tags nest: every opened tag is
/// closed by its own name, in order.
fn svg(p: &Path) -> String {
    let text = read(p);
    assert!(
        text.starts_with("<svg "),
        "{}: not an SVG root",
        p.display()
    );
    let mut open: Vec<&str> = Vec::new();
    let mut rest = text.as_str();
    while let Some(at) = rest.find('<') {
        let end = rest[at..].find('>').expect("a closed tag") + at;
        let tag = &rest[at + 1..end];
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(
                open.pop(),
                Some(name),
                "{}: </{name}> closes another",
                p.display()
            );
        } else if !tag.ends_with('/') {
            open.push(tag.split_whitespace().next().expect("a tag name"));
        }
        rest = &rest[end + 1..];
    }
    assert!(open.is_empty(), "{}: unclosed {open:?}", p.display());
    assert!(text.trim_end().ends_with("</svg>"));
    text
}

/// The texts of an SVG, in order.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .map(|t| {
            let body = &t[t.find('>').expect("text tag") + 1..t.find("</text>").expect("closed")];
            body.trim().to_string()
        })
        .collect()
}

/// The centres (cx, cy) of the circles of an SVG, in order.
fn circles(svg: &str) -> Vec<(f64, f64)> {
    let attr = |t: &str, name: &str| -> f64 {
        let from = t.find(&format!(" {name}=\"")).expect("attribute") + name.len() + 3;
        let len = t[from..].find('"').expect("quoted");
        t[from..from + len].parse().expect("a number")
    };
    svg.split("<circle")
        .skip(1)
        .map(|t| (attr(t, "cx"), attr(t, "cy")))
        .collect()
}

/// One row of contact.csv: x, y, z, weight, pressure.
struct Row {
    at: [f64; 3],
    weight: f64,
    pressure: f64,
}

/// The rows of the only pair of `dir/contact.csv`, and its name.
fn contact(dir: &Path) -> (String, Vec<Row>) {
    let text = read(&dir.join("contact.csv"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(
        header,
        ["pair", "body", "node", "x", "y", "z", "weight", "gap", "pressure"]
    );
    let mut name = String::new();
    let rows = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            name = f[0].to_string();
            let n = |i: usize| f[i].parse::<f64>().expect("a number");
            Row {
                at: [n(3), n(4), n(5)],
                weight: n(6),
                pressure: n(8),
            }
        })
        .collect();
    (name, rows)
}

/// The number after `prefix` in `text` (up to the next space or comma).
fn number_after(text: &str, prefix: &str) -> f64 {
    let from = text
        .find(prefix)
        .unwrap_or_else(|| panic!("{prefix:?} in {text:?}"))
        + prefix.len();
    let word: String = text[from..]
        .chars()
        .take_while(|c| !matches!(c, ' ' | ',' | ')'))
        .collect();
    word.parse()
        .unwrap_or_else(|_| panic!("{word:?} in {text:?}"))
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300)
}

/// Plots `out` with `--units`, checks both figures of its pair and returns the profile's centre.
fn check_figures(out: &Path, units: &str, force_unit: &str) -> [f64; 3] {
    let o = contactdd(&["plot", path(out), "--units", units]);
    succeeded(&o);
    let (name, rows) = contact(out);
    let plots = out.join("plots");
    for stem in ["pressure-map", "pressure-profile"] {
        let png = std::fs::read(plots.join(format!("{stem}-{name}.png"))).expect("png");
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{stem}: not a PNG");
    }
    let peak = rows.iter().map(|r| r.pressure).fold(0.0, f64::max);
    let force: f64 = rows.iter().map(|r| r.weight * r.pressure).sum();

    // The map: seen along z (both examples press along z), so its axes are x and y.
    let map = svg(&plots.join(format!("pressure-map-{name}.svg")));
    let t = texts(&map);
    let length = units.split(',').next().expect("length").trim();
    assert!(
        t.contains(&format!("x ({length})")) && t.contains(&format!("y ({length})")),
        "{t:?}"
    );
    assert!(
        close(number_after(&t[0], "normal force "), force, 5e-4),
        "{}",
        t[0]
    );
    assert!(t[0].contains(&format!(" {force_unit}, peak ")), "{}", t[0]);
    assert!(close(number_after(&t[0], "peak "), peak, 5e-4), "{}", t[0]);
    // The window: the pressed zone and half its width again on each side, within the points.
    let window = |k: usize| {
        let all = || rows.iter().map(|r| r.at[k]);
        let pressed = || rows.iter().filter(|r| r.pressure > 0.0).map(|r| r.at[k]);
        let (lo, hi) = (
            pressed().fold(f64::MAX, f64::min),
            pressed().fold(f64::MIN, f64::max),
        );
        let (a, b) = (
            all().fold(f64::MAX, f64::min),
            all().fold(f64::MIN, f64::max),
        );
        (lo - 0.5 * (hi - lo)).max(a)..=(hi + 0.5 * (hi - lo)).min(b)
    };
    let (wx, wy) = (window(0), window(1));
    let shown = rows
        .iter()
        .filter(|r| wx.contains(&r.at[0]) && wy.contains(&r.at[1]))
        .count();
    assert_eq!(circles(&map).len(), shown, "one disc per point in view");
    assert!(
        t.contains(&format!("{shown} of {} points", rows.len())),
        "{t:?}"
    );
    // The colour bar: its five ticks run from 0 to the largest pressure.
    let bar = t
        .iter()
        .position(|s| s.starts_with("pressure ("))
        .expect("bar label");
    let ticks: Vec<f64> = t[bar + 1..bar + 6]
        .iter()
        .map(|s| s.parse().expect("tick"))
        .collect();
    assert_eq!(ticks[0], 0.0, "{ticks:?}");
    assert!(close(ticks[4], peak, 5e-3), "{ticks:?} against {peak}");
    assert!(
        close(number_after(&t[bar + 7], "max "), peak, 5e-4),
        "{}",
        t[bar + 7]
    );

    // The profile: one point per contact point up to twice the largest pressed distance, by
    // increasing distance.
    let profile = svg(&plots.join(format!("pressure-profile-{name}.svg")));
    let t = texts(&profile);
    let label = t
        .iter()
        .find(|s| s.starts_with("distance from the centre ("))
        .expect("x label");
    let centre = [
        number_after(label, "centre ("),
        number_after(label, ", "),
        number_after(&label[label.find(", ").expect(",") + 2..], ", "),
    ];
    let r = |row: &Row| (row.at[0] - centre[0]).hypot(row.at[1] - centre[1]);
    let limit = rows
        .iter()
        .filter(|w| w.pressure > 0.0)
        .map(r)
        .fold(0.0, f64::max);
    let points = circles(&profile);
    let expected = rows.iter().filter(|w| r(w) <= 2.0 * limit).count();
    // The centre is printed rounded: a point right at twice the limit may fall either way.
    assert!(
        points.len().abs_diff(expected) <= 2,
        "{} points, {expected} expected",
        points.len()
    );
    assert!(
        points.windows(2).all(|p| p[0].0 <= p[1].0),
        "not by increasing distance"
    );
    centre
}

#[test]
fn hertz_ball_on_a_block() {
    let dir = temp("hertz");
    let out = solved(&dir, "sphere_block.toml");
    let centre = check_figures(&out, "mm, MPa", "N");
    // The ball touches the block at the origin: the centre of the pressure is there, within the
    // mesh's cells (0.02 at the contact).
    assert!(centre.iter().all(|c| c.abs() <= 0.01), "{centre:?}");
    // Hertz: the pressure falls from its peak at the centre to 0 at the edge.
    let profile = read(&out.join("plots/pressure-profile-ball-block.svg"));
    let points = circles(&profile);
    let mean = |p: &[(f64, f64)]| p.iter().map(|c| c.1).sum::<f64>() / p.len() as f64;
    let (first, last) = (mean(&points[..10]), mean(&points[points.len() - 10..]));
    assert!(
        first + 300.0 < last,
        "higher pressure (smaller cy) first: {first} {last}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn blocks_uniform_pressure() {
    let dir = temp("blocks");
    let out = solved(&dir, "blocks.toml");
    let centre = check_figures(&out, "m, MPa", "MN");
    // A uniform pressure on the face [0, 1]² at z = 0.5: its centre is the middle of the face.
    assert_eq!(centre, [0.5, 0.5, 0.5]);
    // Every point is drawn, and all at the same height.
    let profile = read(&out.join("plots/pressure-profile-upper-lower.svg"));
    let points = circles(&profile);
    assert_eq!(points.len(), 121);
    assert!(points.iter().all(|p| p.1 == points[0].1));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn options_without_meaning_in_space_are_ignored_with_a_note() {
    let dir = temp("notes");
    let out = solved(&dir, "blocks.toml");
    let o = contactdd(&["plot", path(&out), "--tol", "1e-6", "-q", "--format", "svg"]);
    succeeded(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("note: --tol is ignored"), "{err}");
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains("wrote 2 figure files"), "{said}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_folder_in_space_without_contact_csv_is_a_clear_error() {
    let dir = temp("missing");
    let out = solved(&dir, "blocks.toml");
    std::fs::remove_file(out.join("contact.csv")).expect("remove contact.csv");
    let o = contactdd(&["plot", path(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("contact.csv' is missing"), "{err}");
    assert!(err.contains("result in space"), "{err}");
    assert!(
        !out.join("plots").exists(),
        "an empty plots folder was left behind"
    );
    // Not listed at all: named too.
    let summary = read(&out.join("summary.json"));
    let unlisted = summary.replace("\"contact.csv\",", "");
    assert_ne!(summary, unlisted);
    std::fs::write(out.join("summary.json"), unlisted).expect("write summary");
    let o = contactdd(&["plot", path(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("names no contact.csv"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A load history in space: the blocks pushed in four steps with their top face monitored; the
/// load–displacement curve and the forces against the load factor exist, one marker per step
/// and the unloaded state, with the force in MN (the file's units "m, MPa": MPa × m²) and the
/// displacement in m.
#[test]
fn a_load_history_in_space_draws_its_curves() {
    let dir = temp("steps");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/space/blocks.toml");
    let text = read(&file)
        + "\n[solver]\nload-steps = 4\nmonitor = { body = \"upper\", boundary = \"z+\" }\n";
    let steps = dir.join("steps.toml");
    std::fs::write(&steps, text).expect("write");
    let out = dir.join("out");
    succeeded(&contactdd(&["solve", path(&steps), "-o", path(&out), "-q"]));
    assert_eq!(read(&out.join("steps.csv")).lines().count(), 5);
    succeeded(&contactdd(&["plot", path(&out)]));
    let curve = svg(&out.join("plots/load-displacement.svg"));
    // The unloaded state, the four steps and the legend's marker.
    assert_eq!(circles(&curve).len(), 6, "{curve}");
    let labels = texts(&curve).join("|");
    assert!(
        labels.contains("|F| (MN)") && labels.contains("(m)"),
        "{labels}"
    );
    assert!(out.join("plots/steps-force.png").is_file());
}
