//! `contactdd plot`: the figures of a solved example exist, are SVG with their labels, and draw
//! the pressures of contact.csv; PNG is a real image; a sweep CSV gets its figure; a folder that
//! is not a result, a malformed file in it or a listed name that is not a regular file, is an
//! error naming it; `-o`, `-q` and a summary.json path work as in the other commands.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-plot-{name}-{}", std::process::id()));
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

/// Asserts exit 0, showing stderr otherwise.
fn succeeded(o: &Output) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// Solves the notch example into `dir/out` and returns that folder.
fn solved_notch(dir: &Path) -> PathBuf {
    let out = dir.join("out");
    let file = example("notch.toml");
    let o = contactdd(&["solve", path(&file), "--out", path(&out), "--quiet"]);
    succeeded(&o);
    out
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Checks the root element and returns the text.
fn svg(p: &Path) -> String {
    let text = read(p);
    assert!(
        text.starts_with("<svg "),
        "{}: not an SVG root",
        p.display()
    );
    assert!(
        text.trim_end().ends_with("</svg>"),
        "{}: unterminated",
        p.display()
    );
    assert_eq!(
        text.matches("<svg").count(),
        1,
        "{}: one root element",
        p.display()
    );
    text
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

/// The pressures p ≥ 0 of `body` in contact.csv, sorted along x (the notch's contact line).
fn pressures(csv: &str, body: &str) -> Vec<(f64, f64)> {
    let mut rows: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[1] == body).then(|| (f[2].parse().unwrap(), f[5].parse::<f64>().unwrap()))
        })
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    rows
}

#[test]
fn a_solved_example_gets_its_figures() {
    let dir = temp("notch");
    let out = solved_notch(&dir);
    let plots = dir.join("plots");
    let notch = example("notch.toml");
    let o = contactdd(&[
        "plot",
        path(&out),
        "--out",
        path(&plots),
        "--format",
        "svg",
        "--problem",
        path(&notch),
    ]);
    succeeded(&o);
    for name in [
        "pressure-notch.svg",
        "gap-notch.svg",
        "history.svg",
        "bodies.svg",
    ] {
        assert!(
            String::from_utf8_lossy(&o.stdout).contains(name),
            "{name} not reported"
        );
        svg(&plots.join(name));
    }
    assert!(
        !plots.join("history.png").exists(),
        "--format svg wrote a PNG"
    );

    let pressure = svg(&plots.join("pressure-notch.svg"));
    // Units come from the problem's `units = "cm, N/cm^2"`.
    for label in ["contact pressure p (N/cm^2)", "x (cm)", "lower", "upper"] {
        assert!(pressure.contains(label), "pressure figure lacks '{label}'");
    }
    let history = svg(&plots.join("history.svg"));
    for label in [
        "iteration k",
        "tol = 1e-3",
        "stop test: relative change",
        "lower",
        "upper",
    ] {
        assert!(history.contains(label), "history figure lacks '{label}'");
    }
    // Every element of both bodies (32 × 16 × 2 triangles each) is a coloured polygon.
    let bodies = svg(&plots.join("bodies.svg"));
    assert_eq!(bodies.matches("<polygon").count(), 2 * 1024);
    for label in ["von Mises (N/cm^2)", "displacements ×", "y (cm)"] {
        assert!(bodies.contains(label), "bodies figure lacks '{label}'");
    }
    let gap = svg(&plots.join("gap-notch.svg"));
    for label in ["gap d − s (cm)", "closed", "open"] {
        assert!(gap.contains(label), "gap figure lacks '{label}'");
    }
}

#[test]
fn the_pressure_curve_is_contact_csv() {
    let dir = temp("values");
    let out = solved_notch(&dir);
    let o = contactdd(&["plot", path(&out), "--format", "svg"]);
    succeeded(&o);
    let figure = svg(&out.join("plots/pressure-notch.svg"));
    let lower = pressures(&read(&out.join("contact.csv")), "lower");
    assert!(lower.len() > 10);
    // The lower side is the solid line: one polyline through all its points.
    let line = polylines(&figure)
        .into_iter()
        .find(|l| l.len() == lower.len())
        .expect("a polyline with as many points as the lower side");
    // Pixels are an affine map of the data: fit it on the two extremes of each axis, then every
    // point must land within a pixel.
    let fit = |data: &[f64], px: &[f64]| {
        let (i, j) = extremes(data);
        let (d0, p0) = (data[i], px[i]);
        let slope = (px[j] - p0) / (data[j] - d0);
        move |v: f64| p0 + slope * (v - d0)
    };
    let (dx, dp): (Vec<f64>, Vec<f64>) = lower.iter().copied().unzip();
    let (px, py): (Vec<f64>, Vec<f64>) = line.iter().copied().unzip();
    let (to_x, to_y) = (fit(&dx, &px), fit(&dp, &py));
    for k in 0..lower.len() {
        assert!(
            (to_x(dx[k]) - px[k]).abs() <= 1.0,
            "point {k}: x {} vs pixel {}",
            dx[k],
            px[k]
        );
        assert!(
            (to_y(dp[k]) - py[k]).abs() <= 1.0,
            "point {k}: p {} vs pixel {}",
            dp[k],
            py[k]
        );
    }
    // Larger pressure is higher up (smaller pixel y).
    let (lo, hi) = extremes(&dp);
    assert!(py[hi] < py[lo]);
}

/// Indices of the smallest and largest value.
fn extremes(v: &[f64]) -> (usize, usize) {
    let by = |f: fn(f64, f64) -> bool| {
        (0..v.len())
            .reduce(|a, b| if f(v[b], v[a]) { b } else { a })
            .unwrap()
    };
    (by(|a, b| a < b), by(|a, b| a > b))
}

#[test]
fn png_is_an_image() {
    let dir = temp("png");
    let out = solved_notch(&dir);
    let o = contactdd(&["plot", path(&out), "--format", "png"]);
    succeeded(&o);
    let bytes = std::fs::read(out.join("plots/pressure-notch.png")).expect("the PNG");
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    // 800 × 500 in the IHDR chunk.
    assert_eq!(&bytes[16..24], &[0, 0, 3, 32, 0, 0, 1, 244]);
    assert!(
        bytes.len() > 5_000,
        "a nearly blank image: {} bytes",
        bytes.len()
    );
    assert!(!out.join("plots/pressure-notch.svg").exists());
}

#[test]
fn load_steps_get_the_load_displacement_curve() {
    let dir = temp("steps");
    let text = read(&example("notch.toml"));
    let body = text.split("[solver]").next().expect("a solver table");
    let file = dir.join("steps.toml");
    let solver = "[solver]\nload-steps = 3\nmonitor = { body = \"upper\", boundary = \"top\" }\n";
    std::fs::write(&file, format!("{body}{solver}")).expect("write");
    let out = dir.join("out");
    let o = contactdd(&["solve", path(&file), "--out", path(&out), "--quiet"]);
    succeeded(&o);
    let o = contactdd(&[
        "plot",
        path(&out),
        "--format",
        "svg",
        "--units",
        "cm, N/cm^2",
    ]);
    succeeded(&o);
    let curve = svg(&out.join("plots/load-displacement.svg"));
    for label in [
        "monitored displacement −u_y (cm)",
        "|F| (N/cm)",
        "pair notch",
    ] {
        assert!(
            curve.contains(label),
            "load–displacement figure lacks '{label}'"
        );
    }
    // The bodies of the last step.
    assert!(svg(&out.join("plots/bodies.svg")).contains("<polygon"));
    let forces = svg(&out.join("plots/steps-force.svg"));
    assert!(forces.contains("load factor"));
    // Three steps after the unloaded state: a polyline through four points, the first at the
    // axes' origin (both axes start at 0).
    let line = polylines(&forces)
        .into_iter()
        .find(|l| l.len() == 4)
        .expect("a polyline through (0, 0) and three steps");
    let curve_line = polylines(&curve)
        .into_iter()
        .find(|l| l.len() == 4)
        .expect("the load–displacement curve from (0, 0)");
    for l in [&line, &curve_line] {
        // The origin is the leftmost and lowest point (largest pixel y).
        assert!(l.iter().all(|p| p.0 >= l[0].0 && p.1 <= l[0].1), "{l:?}");
    }
    // The history is the last step's, and says so.
    assert!(svg(&out.join("plots/history.svg")).contains("load step 3 (the last)"));

    // With the problem file, the monitored boundary is named.
    let o = contactdd(&[
        "plot",
        path(&out),
        "--format",
        "svg",
        "--problem",
        path(&file),
    ]);
    succeeded(&o);
    let curve = svg(&out.join("plots/load-displacement.svg"));
    for label in ["monitored: top of upper", "mean −u_y on top of upper (cm)"] {
        assert!(curve.contains(label), "load–displacement lacks '{label}'");
    }
}

#[test]
fn out_quiet_and_a_summary_path_work_as_in_the_other_commands() {
    let dir = temp("flags");
    let out = solved_notch(&dir);
    let figures = dir.join("figures");
    let summary = out.join("summary.json");
    let o = contactdd(&[
        "plot",
        path(&summary),
        "-o",
        path(&figures),
        "-q",
        "--format",
        "svg",
    ]);
    succeeded(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    // One line, no line per file.
    assert_eq!(
        stdout.trim_end(),
        format!("wrote 4 figure files to {}", figures.display()),
        "{stdout}"
    );
    for name in ["pressure-notch", "gap-notch", "history", "bodies"] {
        svg(&figures.join(format!("{name}.svg")));
    }
    assert!(!out.join("plots").exists(), "-o was not followed");
    // Without -q, a line per file.
    let o = contactdd(&["plot", path(&summary), "--format", "png"]);
    succeeded(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("wrote ")).count(),
        4
    );
    assert!(out.join("plots/history.png").exists());
    // Another file of the folder is not a sweep: the message says what plot takes.
    let o = contactdd(&["plot", path(&out.join("contact.csv"))]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("not the CSV of a sweep"), "{err}");
}

#[test]
fn a_narrow_stress_range_is_drawn_from_zero_and_the_outline_is_drawn() {
    let dir = temp("uniform");
    let out = dir.join("out");
    let file = example("notch.toml");
    let args = ["solve", path(&file), "--out", path(&out), "--quiet"];
    succeeded(&contactdd(
        &[&args[..], &["--vtu-format", "ascii"]].concat(),
    ));
    // Every element of lower at 88.3 to 88.9: a range of 0.6 next to values near 89.
    let lower = out.join("lower.vtu");
    let text = read(&lower);
    let tag = "Name=\"element_von_mises\" NumberOfComponents=\"1\" format=\"ascii\">";
    let start = text.find(tag).expect("element_von_mises") + tag.len();
    let end = start + text[start..].find("</DataArray>").expect("end");
    let n = text[start..end].split_whitespace().count();
    let values: Vec<String> = (0..n)
        .map(|i| format!("{}", 88.3 + 0.6 * i as f64 / (n - 1) as f64))
        .collect();
    let text = format!("{}{}{}", &text[..start], values.join(" "), &text[end..]);
    std::fs::write(&lower, text).expect("write");
    let upper = out.join("upper.vtu");
    std::fs::copy(&lower, &upper).expect("copy");
    let o = contactdd(&["plot", path(&out), "--format", "svg"]);
    succeeded(&o);
    let bodies = svg(&out.join("plots/bodies.svg"));
    // The bar runs from 0: its ticks are 0, 22.2, 44.5, 66.7 and 88.9.
    for label in [
        "min 88.3",
        "max 88.9",
        "\n22.2\n",
        "\n66.7\n",
        "red: undeformed",
    ] {
        assert!(bodies.contains(label), "bodies figure lacks '{label}'");
    }
    // Each body's undeformed outline: one closed polyline of 2 × (32 + 16) boundary edges.
    let outlines = polylines(&bodies)
        .into_iter()
        .filter(|l| l.len() == 2 * (32 + 16) + 1)
        .count();
    assert_eq!(outlines, 2);
}

#[test]
fn the_history_reads_its_columns_by_name() {
    let dir = temp("history");
    let out = solved_notch(&dir);
    // An extra column, before and among the known ones, is ignored.
    let history = out.join("history.csv");
    let text = read(&history);
    let mut lines = text.lines();
    let header = lines.next().expect("a header");
    let mut new = format!("extra,{header},rel_change_max\n");
    for l in lines {
        new += &format!("1e-3,{l},5\n");
    }
    std::fs::write(&history, new).expect("write");
    let o = contactdd(&["plot", path(&out), "--format", "svg"]);
    succeeded(&o);
    let figure = svg(&out.join("plots/history.svg"));
    // The bodies of summary.json, not "max".
    assert!(figure.contains("lower") && figure.contains("upper"));
    assert!(!figure.contains(">max<"), "rel_change_max drawn as a body");
}

#[test]
fn listed_files_that_are_not_regular_files_are_refused() {
    let dir = temp("devices");
    let out = solved_notch(&dir);
    let contact = out.join("contact.csv");
    std::fs::remove_file(&contact).expect("remove");
    std::os::unix::fs::symlink("/dev/zero", &contact).expect("symlink");
    let o = contactdd(&["plot", path(&out), "--format", "svg"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("contact.csv") && err.contains("not a regular file"),
        "{err}"
    );
}

#[test]
fn a_sweep_csv_marks_each_kind_of_failure() {
    let dir = temp("sweep");
    let csv = dir.join("notch-sweep.csv");
    std::fs::write(
        &csv,
        "method,gamma,iterations,converged,reason\n\
         active-set,0.1,20,true,\n\
         active-set,0.5,8,true,\n\
         active-set,0.9,33,false,lower: lost all contact at iteration 33\n\
         newton-chord,0.1,20,true,\n\
         newton-chord,0.5,50,false,max iterations\n\
         newton-chord,0.9,12,false,stalled (out of equilibrium)\n\
         active-set,auto,9,true,\n\
         newton-chord,auto,14,true,\n",
    )
    .expect("write");
    let o = contactdd(&["plot", path(&csv), "--format", "svg"]);
    succeeded(&o);
    let figure = svg(&dir.join("notch-sweep.svg"));
    for label in [
        "relaxation parameter γ",
        "active-set auto: 9",
        "newton-chord auto: 14",
        "diverged",
        "max iterations",
        "stalled",
    ] {
        assert!(figure.contains(label), "sweep figure lacks '{label}'");
    }
}

#[test]
fn a_folder_without_summary_is_refused() {
    let dir = temp("empty");
    let o = contactdd(&["plot", path(&dir)]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no summary.json"), "{err}");
}

#[test]
fn a_malformed_file_is_named() {
    let dir = temp("malformed");
    let out = solved_notch(&dir);
    let contact = out.join("contact.csv");
    let text = read(&contact).replacen("notch,lower,", "notch,lower,oops", 1);
    std::fs::write(&contact, text).expect("write");
    let o = contactdd(&["plot", path(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("contact.csv") && err.contains("not a number"),
        "{err}"
    );

    std::fs::write(out.join("summary.json"), "{ not json").expect("write");
    let o = contactdd(&["plot", path(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("summary.json") && err.contains("not valid JSON"),
        "{err}"
    );
}

#[test]
fn the_bodies_figure_reads_only_sound_vtu() {
    let dir = temp("vtu");
    let out = dir.join("ascii");
    let file = example("notch.toml");
    let args = ["solve", path(&file), "--out", path(&out), "--quiet"];
    succeeded(&contactdd(
        &[&args[..], &["--vtu-format", "ascii"]].concat(),
    ));
    let lower = out.join("lower.vtu");
    let text = read(&lower);
    let ascii = "Name=\"element_von_mises\" NumberOfComponents=\"1\" format=\"ascii\">";
    let at = text
        .find(ascii)
        .expect("the writer changed: update this test")
        + ascii.len();
    // A NaN in a drawn array (the iterate of a failed solve) leaves the figure out, not the
    // command.
    std::fs::write(&lower, format!("{} NaN{}", &text[..at], &text[at..])).expect("write");
    let o = contactdd(&["plot", path(&out), "--format", "svg"]);
    succeeded(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("bodies figure is left out"));
    assert!(!out.join("plots/bodies.svg").exists());
    assert!(out.join("plots/pressure-notch.svg").exists());
    // A cell naming a node that does not exist is an error naming the file.
    let cells = "Name=\"connectivity\" format=\"ascii\">";
    let at = text.find(cells).expect("connectivity") + cells.len();
    let broken = format!("{} 99999{}", &text[..at], &text[at..]);
    std::fs::write(&lower, broken).expect("write");
    let o = contactdd(&["plot", path(&out), "--format", "svg"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("lower.vtu") && err.contains("cells do not fit"),
        "{err}"
    );
}

/// Binary and zlib files draw the same figure as ASCII ones; a binary or zlib file cut short is
/// an error naming it.
#[test]
fn the_bodies_figure_reads_binary_vtu() {
    let dir = temp("vtu-binary");
    let file = example("notch.toml");
    let mut figures = Vec::new();
    for encoding in ["ascii", "binary", "zlib"] {
        let out = dir.join(encoding);
        let args = ["solve", path(&file), "--out", path(&out), "--quiet"];
        succeeded(&contactdd(
            &[&args[..], &["--vtu-format", encoding]].concat(),
        ));
        let head = std::fs::read(out.join("lower.vtu")).expect("lower.vtu");
        let appended = head.windows(13).any(|w| w == b"<AppendedData");
        assert_eq!(appended, encoding != "ascii", "{encoding}");
        let zlib = head.windows(21).any(|w| w == b"vtkZLibDataCompressor");
        assert_eq!(zlib, encoding == "zlib", "{encoding}");
        succeeded(&contactdd(&["plot", path(&out), "--format", "svg"]));
        figures.push(svg(&out.join("plots/bodies.svg")));
    }
    assert_eq!(figures[0], figures[1]);
    assert_eq!(figures[0], figures[2]);
    for encoding in ["binary", "zlib"] {
        let lower = dir.join(encoding).join("lower.vtu");
        let bytes = std::fs::read(&lower).expect("lower.vtu");
        std::fs::write(&lower, &bytes[..bytes.len() - 100]).expect("write");
        let o = contactdd(&["plot", path(&dir.join(encoding)), "--format", "svg"]);
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("lower.vtu") && err.contains("bytes"), "{err}");
    }
}

#[test]
fn every_example_plots() {
    for name in ["notch", "hertz", "stack", "three_bodies"] {
        let dir = temp(&format!("example-{name}"));
        let (file, out) = (example(&format!("{name}.toml")), dir.join("out"));
        let o = contactdd(&["solve", path(&file), "--out", path(&out), "--quiet"]);
        succeeded(&o);
        let o = contactdd(&["plot", path(&out), "--problem", path(&file)]);
        succeeded(&o);
        let stdout = String::from_utf8_lossy(&o.stdout);
        let written: Vec<&str> = stdout
            .lines()
            .filter_map(|l| l.strip_prefix("wrote "))
            .collect();
        // Per pair two figures, the history and the bodies, each as SVG and PNG.
        assert!(written.len() >= 8, "{name}: {written:?}");
        for file in written {
            let bytes = std::fs::read(file).unwrap_or_else(|e| panic!("{file}: {e}"));
            assert!(bytes.len() > 5_000, "{file}: only {} bytes", bytes.len());
            if file.ends_with(".svg") {
                svg(Path::new(file));
            } else {
                assert!(bytes.starts_with(b"\x89PNG"), "{file}: not a PNG");
            }
        }
    }
}
