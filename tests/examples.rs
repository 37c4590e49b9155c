//! Every shipped example is a test: each `examples/*.toml` is solved through the command line's
//! own entry point ([`contactdd_cli::run`], in-process) into a temporary folder, and the physics in
//! its `summary.json` is checked, so an example can never silently rot:
//!
//! - it converges, within 1..=max-iter iterations;
//! - every contact pair touches, and the total contact forces on its two sides are equal and
//!   opposite (relative difference ≤ 1e-10 for balanced pairs, the default; for own-side pairs
//!   ≤ 1e-6 with matching contact nodes, 1 % otherwise);
//! - in every direction in which a body has no support at all, the contact forces balance the
//!   applied load on that body (the body is held there only by contact);
//! - the penalty penetration of closed points stays below 1 % of the smaller body's size;
//! - the file opens with a header that shows the command to run it;
//! - the iteration count its header quotes (`converged in N iterations`, or `every step converges
//!   in A to B` for load steps) is the one the solve takes, so the documented numbers stay true.

use std::path::{Path, PathBuf};

use serde_json::Value;

use contactdd::io::{load_file, Loaded};
use contactdd_cli::{run, Exit};

/// Relative tolerance of the action = reaction check between the two sides of a balanced pair
/// (equal and opposite by construction, up to round-off).
const SIDES_TOL_BALANCED: f64 = 1e-10;
/// The same for an own-side pair whose contact nodes coincide (matching meshes: both sides
/// integrate the same pressures).
const SIDES_TOL: f64 = 1e-6;
/// The same for non-matching meshes, where each side integrates the penalty pressure with its own
/// nodal quadrature, so the two totals agree only up to the discretisation error.
const SIDES_TOL_NON_MATCHING: f64 = 1e-2;
/// Relative tolerance of a floating body's equilibrium (the DD iterate stops at ε_u, so the
/// interface forces are accurate to about that).
const EQUILIBRIUM_TOL: f64 = 1e-3;
/// Largest penetration of a closed point, relative to the smaller body's size.
const PENETRATION_TOL: f64 = 1e-2;

#[test]
fn every_example_solves_and_its_physics_holds() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no examples in {}", dir.display());
    let out_root = std::env::temp_dir().join(format!("contactdd-examples-{}", std::process::id()));
    let mut failures = Vec::new();
    for file in &files {
        let stem = file.file_stem().unwrap().to_string_lossy().into_owned();
        let start = std::time::Instant::now();
        let result = check_example(file, &stem, &out_root.join(&stem));
        eprintln!("{stem}: {:.2} s", start.elapsed().as_secs_f64());
        if let Err(message) = result {
            failures.push(format!("{stem}: {message}"));
        }
    }
    let _ = std::fs::remove_dir_all(&out_root);
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

fn check_example(file: &Path, stem: &str, out: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(file).map_err(|e| e.to_string())?;
    let command = format!("contactdd solve examples/{stem}.toml");
    if !(text.starts_with('#') && text.contains(&command)) {
        return Err(format!(
            "the file must open with a # header that shows `{command}`"
        ));
    }
    let loaded = load_file(file).map_err(|e| e.to_string())?;
    let exit = run([
        "contactdd".as_ref(),
        "solve".as_ref(),
        file.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    if exit != Exit::Success {
        return Err(format!("`contactdd solve` ended with {exit:?}"));
    }
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("summary.json")).map_err(|e| e.to_string())?,
    )
    .map_err(|e| e.to_string())?;
    check_summary(&loaded, &summary)?;
    check_quoted_count(&text, &summary)
}

/// The header's quoted iteration count against the solve's: `converged in N iterations`, or for
/// load steps `converges in A to B` (the range of the steps' counts).
fn check_quoted_count(text: &str, summary: &Value) -> Result<(), String> {
    let number_after = |key: &str| -> Option<usize> {
        let rest = &text[text.find(key)? + key.len()..];
        rest.split_whitespace().next()?.parse().ok()
    };
    if let Some(steps) = summary["steps"].as_array() {
        let counts: Vec<usize> = steps
            .iter()
            .map(|s| s["iterations"].as_u64().unwrap_or(0) as usize)
            .collect();
        let (lo, hi) = (counts.iter().min(), counts.iter().max());
        let quoted_lo = number_after("converges in ");
        let quoted_hi = number_after(&format!("converges in {} to ", quoted_lo.unwrap_or(0)));
        return match (quoted_lo, quoted_hi) {
            (Some(a), Some(b)) if Some(&a) == lo && Some(&b) == hi => Ok(()),
            _ => Err(format!(
                "the header quotes {quoted_lo:?} to {quoted_hi:?} iterations per step; the steps \
                 took {counts:?}"
            )),
        };
    }
    let iterations = summary["iterations"].as_u64().unwrap_or(0) as usize;
    match number_after("#   converged in ") {
        Some(quoted) if quoted == iterations => Ok(()),
        quoted => Err(format!(
            "the header quotes {quoted:?} iterations; the solve took {iterations}"
        )),
    }
}

fn check_summary(loaded: &Loaded, summary: &Value) -> Result<(), String> {
    let model = &loaded.model;
    if summary["converged"] != true {
        return Err(format!("not converged: {}", summary["message"]));
    }
    let iterations = summary["iterations"].as_u64().unwrap_or(0) as usize;
    if !(1..=loaded.settings.max_iter).contains(&iterations) {
        return Err(format!("{iterations} iterations"));
    }

    // Net contact force on every body from all its pairs, and the sum of their magnitudes.
    let mut on_body = vec![[0.0f64; 2]; model.bodies.len()];
    let mut gross = vec![0.0f64; model.bodies.len()];
    for (p, pair) in model.pairs.iter().enumerate() {
        let c = &summary["contact"][p];
        let force = |side: usize| -> [f64; 2] {
            [0, 1].map(|k| c["force"][side][k].as_f64().unwrap_or(f64::NAN))
        };
        let (f0, f1) = (force(0), force(1));
        let scale = norm(f0).max(norm(f1));
        if scale.is_nan() || scale <= 0.0 {
            return Err(format!("pair '{}' carries no force", pair.name));
        }
        let mismatch = norm([f0[0] + f1[0], f0[1] + f1[1]]) / scale;
        let (tol, kind) = if pair.forces == contactdd::ddm::Forces::Balanced {
            (SIDES_TOL_BALANCED, "balanced")
        } else if matching(c) {
            (SIDES_TOL, "matching")
        } else {
            (SIDES_TOL_NON_MATCHING, "non-matching")
        };
        if !within(mismatch, tol) {
            return Err(format!(
                "pair '{}' ({kind}): contact forces {f0:?} and {f1:?} differ by \
                 {mismatch:.1e} (relative) > {tol:e}",
                pair.name
            ));
        }
        for (side, f) in [f0, f1].into_iter().enumerate() {
            let b = pair.bodies[side];
            on_body[b] = [on_body[b][0] + f[0], on_body[b][1] + f[1]];
            gross[b] += norm(f);
        }

        // Penetration of closed points, relative to the smaller body.
        let size = pair
            .bodies
            .iter()
            .map(|&b| smaller_side(model.bodies[b].mesh.nodes()))
            .fold(f64::INFINITY, f64::min);
        let status = c["status"].as_array().cloned().unwrap_or_default();
        let mut deepest: f64 = 0.0;
        for (i, s) in status.iter().enumerate() {
            if s == "closed" {
                let gap = c["gap"][i].as_f64().unwrap_or(f64::NAN);
                deepest = deepest.max(-gap);
            }
        }
        if !within(deepest, PENETRATION_TOL * size) {
            return Err(format!(
                "pair '{}': penetration {deepest:e} > {PENETRATION_TOL} × body size {size}",
                pair.name
            ));
        }
    }

    // Bodies without any support in a direction are held there by contact alone.
    for (b, body) in model.bodies.iter().enumerate() {
        let applied = body
            .load
            .chunks(2)
            .fold([0.0, 0.0], |s, f| [s[0] + f[0], s[1] + f[1]]);
        for (axis, name) in ["x", "y"].into_iter().enumerate() {
            let supported = body.constraints.fixed().any(|(dof, _)| dof % 2 == axis);
            if supported {
                continue;
            }
            let (load, contact) = (applied[axis], on_body[b][axis]);
            let scale = norm(applied).max(gross[b]);
            if scale > 0.0 && !within((load + contact).abs(), EQUILIBRIUM_TOL * scale) {
                return Err(format!(
                    "body '{}' is out of balance in {name}: applied {load:e}, contact {contact:e}",
                    body.name
                ));
            }
        }
    }
    Ok(())
}

/// True if the contact points of the pair's two sides are at the same places.
fn matching(pair: &Value) -> bool {
    let points = |side: &str| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = (0..pair["x"].as_array().map_or(0, Vec::len))
            .filter(|&i| pair["body"][i] == side)
            .map(|i| {
                let x = pair["x"][i].as_f64().unwrap_or(f64::NAN);
                let y = pair["y"][i].as_f64().unwrap_or(f64::NAN);
                (x, y)
            })
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        v
    };
    let (Some(a), Some(b)) = (pair["bodies"][0].as_str(), pair["bodies"][1].as_str()) else {
        return false;
    };
    let (pa, pb) = (points(a), points(b));
    pa.len() == pb.len()
        && pa.iter().zip(&pb).all(|(p, q)| {
            (p.0 - q.0).abs() <= 1e-9 * (1.0 + p.0.abs())
                && (p.1 - q.1).abs() <= 1e-9 * (1.0 + p.1.abs())
        })
}

/// `value ≤ limit`, false for NaN (so a NaN fails every check).
fn within(value: f64, limit: f64) -> bool {
    value <= limit
}

fn norm(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

/// The smaller side of the bounding box of `nodes`.
fn smaller_side(nodes: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).min(hi[1] - lo[1])
}
