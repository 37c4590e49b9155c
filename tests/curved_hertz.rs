//! Hertz contact on curved (isoparametric) P2 meshes: the shipped Hertz example with the half
//! disc read from `examples/meshes/half_disc_p2.msh` (6-node triangles whose arc mid-side nodes
//! lie on the circle), as shipped. The half-widths and the peak pressure match Hertz's
//! closed form to 1 %, and the pressure profile is smooth: no node's pressure departs from the
//! mean of its two neighbours by more than 2 % of the peak inside the zone.

use contactdd::ddm::solution::PairResult;
use contactdd::ddm::{prepare, solve, Hooks};
use contactdd::hertz::half_width;
use contactdd::io::load_str;

/// Hertz's half-width and peak pressure of the example (P = 900, R = 1, steel on steel).
fn hertz() -> (f64, f64) {
    let e_star = 2.1e5 / (2.0 * (1.0 - 0.3 * 0.3));
    let a = (4.0 * 900.0 / (std::f64::consts::PI * e_star)).sqrt();
    (a, 2.0 * 900.0 / (std::f64::consts::PI * a))
}

/// The example with the disc's mesh `file`, solved as shipped (the penalty θ = 8e-9, whose
/// compliance θE*/a ≈ 0.009 widens the zone by a fraction of a percent).
fn solved(file: &str) -> PairResult {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(dir.join("hertz.toml"))
        .unwrap()
        .replace("meshes/half_disc.msh", file);
    let loaded = load_str(&text, "hertz.toml", &dir).unwrap();
    let prepared = prepare(&loaded.model).unwrap();
    let sol = solve(&loaded.model, &prepared, &loaded.settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{file}: {:?}", sol.message);
    sol.contact[0].clone()
}

/// The largest |p_i − (p_{i−1} + p_{i+1})/2| of one side's pressures in x order, over the nodes
/// within 0.8 a of the centre (the square-root ends of the profile bend sharply by nature).
fn alternation(pair: &PairResult, side: usize, a: f64) -> f64 {
    let mut p: Vec<(f64, f64)> = (0..pair.x.len())
        .filter(|&i| pair.side[i] == side)
        .map(|i| (pair.x[i], -pair.pressure[i]))
        .collect();
    p.sort_by(|u, v| u.0.total_cmp(&v.0));
    p.windows(3)
        .filter(|w| w[1].0.abs() <= 0.8 * a)
        .map(|w| (w[1].1 - 0.5 * (w[0].1 + w[2].1)).abs())
        .fold(0.0, f64::max)
}

#[test]
fn curved_p2_hertz_matches_the_closed_form_with_a_smooth_profile() {
    let (a, p0) = hertz();
    let pair = solved("meshes/half_disc_p2.msh");
    let peak = pair.max_pressure();
    println!("peak {peak:.1} (Hertz {p0:.1})");
    assert!((peak / p0 - 1.0).abs() <= 0.01, "peak {peak} against {p0}");
    for side in [0, 1] {
        let width = half_width(&pair, side);
        let wobble = alternation(&pair, side, a) / p0;
        println!("side {side}: a {width:.5} (Hertz {a:.5}), alternation {wobble:.4} of p0");
        assert!((width / a - 1.0).abs() <= 0.01, "side {side}: a = {width}");
        assert!(wobble <= 0.02, "side {side}: alternation {wobble}");
    }
}
