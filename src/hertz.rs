//! The shipped Hertz example (`examples/hertz.toml`: a half disc pressed on a block, curved
//! non-matching P2 meshes) with dissimilar materials: E_disc/E_block = `ratio`, the load scaled
//! with E* so that Hertz's half-width a = sqrt(4PR/(πE*)) is `a_over_r`·R, the penalty given as
//! θE*/a, and the block meshed at 0.0025 along the contact. Used by
//! `examples/hertz_contrast.rs` and `tests/hertz_contrast.rs`.

use crate::ddm::solution::PairResult;
use crate::ddm::{prepare, solve, Hooks};
use crate::io::load_str;

const R: f64 = 1.0;
const NU: f64 = 0.3;
const E_STEEL: f64 = 2.1e5;

/// Where the gap of one side changes sign, interpolated linearly between the outermost closed
/// point and the next open one, averaged over both ends of the zone (NaN if it has none).
pub fn half_width(pair: &PairResult, side: usize) -> f64 {
    let mut v: Vec<(f64, f64)> = (0..pair.x.len())
        .filter(|&i| pair.side[i] == side && pair.gap[i].is_finite())
        .map(|i| (pair.x[i], pair.gap[i]))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let end = |pts: Vec<&(f64, f64)>| {
        let last = pts.iter().rposition(|p| p.1 < 0.0)?;
        let (a, b) = (pts[last], pts.get(last + 1)?);
        Some((a.0 + (b.0 - a.0) * a.1 / (a.1 - b.1)).abs())
    };
    let centre = v.iter().position(|p| p.0 >= 0.0).unwrap_or(v.len());
    match (
        end(v[centre..].iter().collect()),
        end(v[..centre].iter().rev().collect()),
    ) {
        (Some(r), Some(l)) => 0.5 * (l + r),
        _ => f64::NAN,
    }
}

/// Newton steps (or "NOT converged"), and the two sides' half-widths relative to Hertz, for E_disc = ratio·E_block.
pub fn case(
    text: &str,
    ratio: f64,
    stiffness: f64,
    a_over_r: f64,
) -> Result<(String, [f64; 2]), String> {
    let e_star = |e1: f64, e2: f64| 1.0 / ((1.0 - NU * NU) * (1.0 / e1 + 1.0 / e2));
    let e = e_star(E_STEEL * ratio, E_STEEL);
    let a = a_over_r * R;
    let load = a * a * std::f64::consts::PI * e / (4.0 * R);
    let text = text
        .replace(
            "[materials.steel]",
            &format!(
                "[materials.disc]\nyoung = {}\npoisson = {NU}\n\n[materials.steel]",
                E_STEEL * ratio
            ),
        )
        .replacen("material = \"steel\"", "material = \"disc\"", 1)
        .replace("value = 450.0", &format!("value = {}", load / 2.0))
        .replace("theta = 8e-9", &format!("theta = {:e}", stiffness * a / e))
        .replace("max-iter = 20000", "max-iter = 300")
        // Cells of 0.0025 along the contact, graded in depth: 20 P2 nodes or more per half-width.
        .replace(
            "nx = 200, ny = 100,",
            "nx = 800, ny = 40, grading = { y = 0.02 },",
        );
    let loaded = load_str(
        &text,
        "hertz.toml",
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"),
    )
    .map_err(|e| e.to_string())?;
    let prepared = prepare(&loaded.model).map_err(|e| e.to_string())?;
    let sol = solve(&loaded.model, &prepared, &loaded.settings, Hooks::default())
        .map_err(|e| e.to_string())?;
    let state = if sol.converged {
        format!("{} steps", sol.iterations)
    } else {
        "NOT converged".into()
    };
    Ok((
        state,
        [0, 1].map(|s| half_width(&sol.contact[0], s) / a - 1.0),
    ))
}
