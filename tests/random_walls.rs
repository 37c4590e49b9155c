//! Walls of elastic blocks drawn by `scripts/random_walls.py` (seeds 19, 286 and 375, written to
//! `tests/data/walls/` with penalty contact), each a case the default solver failed on:
//!
//! - `wall19` (7 bodies, balanced pairs, some matching node for node): the first Newton step's J
//!   was singular, because a closed point of an own-side pair was counted as holding its partner
//!   body, which only its own points load;
//! - `wall286` (5 bodies, own-side pairs): "nothing holds" a block that its closed neighbours'
//!   points did not in fact hold, for the same reason;
//! - `wall375` (4 bodies): a block 0.045 wide standing on a base whose nodes are 0.4 apart was
//!   rejected as "not positive definite": the base, chosen to carry the balanced pair's
//!   pressure on a tie of flatness, had no node under the block.
//!
//! Each must now converge with the default settings, agree with the monolithic reference (an
//! independent solver of the assembled system) on every pair's pressures, and carry the applied
//! loads: every contact pair's two sides receive equal and opposite forces, and each body's
//! contact forces balance its applied loads and support reactions (the solver's equilibrium
//! check, and the monolithic reference's).

use std::path::Path;

use contactdd::ddm::{prepare, solve, solve_monolithic, Hooks, Settings};
use contactdd::io::setup::load_file;

/// Largest |a − b| relative to the largest |b|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

fn check(seed: usize) {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/walls/wall{seed}.toml"));
    let model = load_file(&file).unwrap().model;
    let prepared = prepare(&model).unwrap();
    let settings = Settings {
        tol: 1e-10,
        ..Settings::default()
    };
    let dd = solve(&model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(dd.converged, "wall{seed}: {:?}", dd.message);
    assert!(
        dd.iterations <= 30,
        "wall{seed}: {} iterations",
        dd.iterations
    );
    let reference = solve_monolithic(&model).unwrap();
    assert!(reference.converged, "wall{seed}: {:?}", reference.message);
    for (pair, refp) in dd.contact.iter().zip(&reference.contact) {
        let err = relative_difference(&pair.pressure, &refp.pressure);
        assert!(
            err <= 1e-8,
            "wall{seed}, {}: pressure off by {err:e}",
            pair.name
        );
    }
    let worst = dd.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
    assert!(worst <= 1e-8, "wall{seed}: equilibrium residual {worst:e}");
}

#[test]
fn an_own_side_pair_closed_on_one_side_does_not_hold_the_other() {
    check(19);
    check(286);
}

#[test]
fn a_narrow_block_on_a_coarse_base_stands() {
    check(375);
}
