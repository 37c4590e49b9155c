//! Every shipped example in space (`examples/space/*.toml`) is a test: each is solved through
//! the command line's own entry point ([`contactdd_cli::run`], in-process), by the decomposition
//! and by the monolithic reference, and its result folder is checked:
//!
//! - it converges, in the Newton steps its header quotes;
//! - every pair touches, and the contact forces on all bodies sum to zero (≤ 1e-10 of the
//!   largest: every pair is balanced);
//! - every body's loads, contact forces and reactions balance (the summary's imbalance ≤ 1e-10);
//! - the decomposition and the reference agree on every contact pressure to 1e-8 of the peak,
//!   and take the same Newton steps where the pairs are frictionless (with friction the reference
//!   runs another algorithm, successive Tresca problems).
//!
//! `blocks.toml` is also compared with its closed form: a uniform pressure through a non-matching
//! interface.

use std::path::{Path, PathBuf};

use serde_json::Value;

use contactdd_cli::{run, Exit};

/// A scratch folder removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("contactdd-space-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn solve(file: &Path, command: &str, out: &Path) -> Value {
    let exit = run([
        "contactdd",
        command,
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(exit, Exit::Success, "{} {command}", file.display());
    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The pressures of `contact.csv`, in file order.
fn pressures(out: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "pressure").unwrap();
    lines
        .map(|l| l.split(',').nth(col).unwrap().parse().unwrap())
        .collect()
}

fn vector(v: &Value) -> [f64; 3] {
    std::array::from_fn(|c| v[c].as_f64().unwrap())
}

/// The checks of the module docs on one example.
fn check_example(file: &Path, out: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(file).unwrap();
    let dd = solve(file, "solve", &out.join("dd"));
    let reference = solve(file, "monolithic", &out.join("reference"));
    let steps = dd["newton_steps"].as_u64().unwrap();
    let quoted = format!(
        "converged in {steps} Newton step{}",
        if steps == 1 { "" } else { "s" }
    );
    if !text.contains(&quoted) {
        return Err(format!("the header does not say '{quoted}'"));
    }
    let bodies = dd["bodies"].as_array().unwrap();
    for b in bodies {
        let imbalance = b["imbalance"].as_f64().unwrap();
        if imbalance > 1e-10 {
            return Err(format!("body {} imbalance {imbalance:e}", b["name"]));
        }
    }
    for pair in dd["contact"].as_array().unwrap() {
        if pair["closed"].as_u64().unwrap() == 0 {
            return Err(format!("pair {} does not touch", pair["name"]));
        }
    }
    // Every pair's forces on its two bodies cancel, so the bodies' contact forces sum to zero.
    let forces: Vec<[f64; 3]> = bodies.iter().map(|b| vector(&b["contact_force"])).collect();
    let scale = forces.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
    let sum: [f64; 3] = std::array::from_fn(|c| forces.iter().map(|f| f[c]).sum());
    if sum.iter().any(|x| x.abs() > 1e-10 * scale) {
        return Err(format!(
            "the contact forces sum to {sum:?} (largest {scale})"
        ));
    }
    let (p, q) = (
        pressures(&out.join("dd")),
        pressures(&out.join("reference")),
    );
    let peak = p.iter().copied().fold(0.0, f64::max);
    let worst = p
        .iter()
        .zip(&q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    if p.len() != q.len() || worst > 1e-8 * peak {
        return Err(format!(
            "DD and reference differ by {worst:e} (peak {peak})"
        ));
    }
    let frictional =
        (dd["contact"].as_array().unwrap().iter()).any(|p| p.get("friction").is_some());
    if !frictional && reference["newton_steps"] != dd["newton_steps"] {
        return Err(format!(
            "Newton steps: {} against the reference's {}",
            dd["newton_steps"], reference["newton_steps"]
        ));
    }
    Ok(())
}

#[test]
fn every_example_in_space_solves_and_its_physics_holds() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty());
    let root = Scratch::new("all");
    let failures: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let stem = f.file_stem().unwrap().to_string_lossy().into_owned();
            check_example(f, &root.path().join(&stem))
                .err()
                .map(|e| format!("{stem}: {e}"))
        })
        .collect();
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

/// blocks.toml: p = δ / (h₁/E₁ + h₂/E₂ + θ) at every contact point.
#[test]
fn blocks_carry_the_closed_form_pressure() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space/blocks.toml");
    let root = Scratch::new("blocks");
    solve(&file, "solve", root.path());
    let exact = 0.001 / (0.5 / 2.1e5 + 0.5 / 7e4 + 1e-7);
    let p = pressures(root.path());
    assert_eq!(
        p.len(),
        121,
        "the 11 × 11 nodes of the upper block's P2 face"
    );
    for v in p {
        assert!((v - exact).abs() <= 1e-8 * exact, "{v} against {exact}");
    }
}

/// sphere_block.toml against Hertz: from the computed force F (four quarters), the contact
/// radius a = (3FR/(4E*))^(1/3) against the one of the pressures' second moment
/// (∫p r² dA = (2/5) a² F for Hertz's p), within 2 %, and the peak pressure against
/// p₀ = 3F/(2πa²), within 3 %.
#[test]
fn ball_on_block_follows_hertz() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space/sphere_block.toml");
    let root = Scratch::new("hertz");
    solve(&file, "solve", root.path());
    let text = std::fs::read_to_string(root.path().join("contact.csv")).unwrap();
    let (mut force, mut moment, mut peak) = (0.0, 0.0, 0.0f64);
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line
            .split(',')
            .skip(3)
            .map(|x| x.parse().unwrap())
            .collect();
        let (r2, w, p) = (v[0] * v[0] + v[1] * v[1], v[3], v[5]);
        force += w * p;
        moment += w * p * r2;
        peak = peak.max(p);
    }
    let (young, poisson, radius) = (2.1e5, 0.3, 1.0);
    let e_star = young / (2.0 * (1.0 - poisson * poisson));
    let total = 4.0 * force;
    let a = (3.0 * total * radius / (4.0 * e_star)).cbrt();
    let p0 = 3.0 * total / (2.0 * std::f64::consts::PI * a * a);
    let a_pressures = (2.5 * moment / force).sqrt();
    eprintln!("a {a_pressures} against {a}, peak {peak} against {p0}");
    assert!(
        (a_pressures / a - 1.0).abs() < 0.02,
        "a {a_pressures} against {a}"
    );
    assert!((peak / p0 - 1.0).abs() < 0.03, "peak {peak} against {p0}");
}

/// stack.toml: seven floating blocks on a floor under a pressure of 100: every contact pressure
/// is 100 (a uniform σ_zz = −100 in every block).
#[test]
fn the_stack_carries_the_pressure_through_every_interface() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space/stack.toml");
    let root = Scratch::new("stack");
    let summary = solve(&file, "solve", root.path());
    assert_eq!(summary["contact"].as_array().unwrap().len(), 7);
    let p = pressures(root.path());
    assert_eq!(p.len(), 4 * 16 + 3 * 25, "the reference faces' nodes");
    for v in p {
        assert!((v - 100.0).abs() <= 1e-8 * 100.0, "{v}");
    }
}

/// cylinder_block.toml, a slice in plane strain, against examples/hertz.toml solved in the plane
/// and against Hertz: the peak pressure within 1 % of both, the half-width of the pressures'
/// second moment (∫x² p = a²/4 ∫p for Hertz's p) within 1 % of Hertz's a.
#[test]
fn the_slice_reproduces_the_planar_hertz_example() {
    let root = Scratch::new("slice");
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    solve(
        &examples.join("space/cylinder_block.toml"),
        "solve",
        &root.path().join("space"),
    );
    let planar = root.path().join("plane");
    solve(&examples.join("hertz.toml"), "solve", &planar);
    let text = std::fs::read_to_string(root.path().join("space/contact.csv")).unwrap();
    let (mut force, mut moment, mut peak) = (0.0, 0.0, 0.0f64);
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line
            .split(',')
            .skip(3)
            .map(|x| x.parse().unwrap())
            .collect();
        force += v[3] * v[5];
        moment += v[3] * v[5] * v[0] * v[0];
        peak = peak.max(v[5]);
    }
    let plane = std::fs::read_to_string(planar.join("contact.csv")).unwrap();
    let mut lines = plane.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "pressure").unwrap();
    let planar_peak = lines
        .map(|l| l.split(',').nth(col).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    let e_star = 2.1e5 / (2.0 * (1.0 - 0.09));
    let a = (4.0 * 900.0 / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * 900.0 / (std::f64::consts::PI * a);
    let a_pressures = (4.0 * moment / force).sqrt();
    eprintln!("peak {peak} (plane {planar_peak}, Hertz {p0}), a {a_pressures} (Hertz {a})");
    assert!(
        (peak / planar_peak - 1.0).abs() < 0.01,
        "{peak} against {planar_peak}"
    );
    assert!((peak / p0 - 1.0).abs() < 0.01, "{peak} against {p0}");
    assert!(
        (a_pressures / a - 1.0).abs() < 0.01,
        "{a_pressures} against {a}"
    );
}

/// friction_block.toml: the foundation carries the block's loads, the normal force p and the
/// tangential force q along the shear, and Coulomb's law holds at every point.
#[test]
fn the_friction_block_carries_its_loads_within_the_coulomb_disc() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space/friction_block.toml");
    let root = Scratch::new("friction-block");
    let summary = solve(&file, "solve", root.path());
    let pair = &summary["contact"][0];
    let (p, shear) = (40.0, [5.942416, 4.065426]);
    assert!((pair["normal_force"].as_f64().unwrap() - p).abs() < 1e-8 * p);
    let t = vector(&pair["tangential_force"]);
    assert!(
        (t[0] - shear[0]).abs() < 1e-8 * p && (t[1] - shear[1]).abs() < 1e-8 * p,
        "{t:?}"
    );
    assert!(pair["stick"].as_u64().unwrap() > 0 && pair["slip"].as_u64().unwrap() > 0);
    let text = std::fs::read_to_string(root.path().join("contact.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let num = |name: &str| f[col(name)].parse::<f64>().unwrap();
        let traction = num("traction_x")
            .hypot(num("traction_y"))
            .hypot(num("traction_z"));
        let bound = 0.3 * num("pressure");
        assert!(traction <= bound * (1.0 + 1e-12), "{line}");
        if f[col("status")] == "slip" {
            assert!((traction - bound).abs() < 1e-10 * p, "{line}");
        }
    }
}
