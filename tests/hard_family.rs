//! Cases of the random hard family (`scripts/random_walls.py --hard`) on which the decomposition
//! once failed where the monolithic reference converged, in `tests/data/hard/`.
//!
//! `column18`: a column of five blocks held sideways, the stiffest pair's θ = 2.6e-11 (1e-2 of the
//! rod model's, between moduli of 1.4e7 and 3.8e7). One Newton step meets the stopping test
//! ‖R̂‖ ≤ tol ‖U‖, but the contact forces are q/θ with q = θp some 1e-3 of U, so that residual
//! leaves a body out of balance by 2.7e-6; the solver continues the Newton run to a tighter
//! tolerance and reports the balanced result. The references are independent of the solver:
//! the statics of the column (each pair carries the vertical loads above it) and the monolithic
//! reference.

use std::path::Path;

use contactdd::ddm::monolithic::solve_monolithic;
use contactdd::ddm::{prepare, solve, Hooks, Stop};
use contactdd::io::setup::load_file;

/// The top pressure, the body force of block 2 and that block's height (from column18.toml).
const TOP: f64 = 0.01951661951186412;
const BODY_FORCE: f64 = 0.2801850373823221;
const HEIGHT_2: f64 = 0.42708333333333326 - 0.29166666666666663;
const WIDTH: f64 = 0.5;

#[test]
fn a_stiff_penalty_column_converges_and_balances() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/hard/column18.toml");
    let loaded = load_file(&file).unwrap();
    let prepared = prepare(&loaded.model).unwrap();
    let sol = solve(&loaded.model, &prepared, &loaded.settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{:?}", sol.message);
    assert_eq!(sol.stop, Stop::Converged);
    // The continuation's records follow the first run's.
    let ks: Vec<usize> = sol.history.iter().map(|r| r.k).collect();
    assert_eq!(ks, (1..=sol.iterations).collect::<Vec<_>>());

    // Statics: pairs 3 and 2 carry the top pressure, pairs 1 and 0 also block 2's weight.
    let top = TOP * WIDTH;
    let carried = [top + BODY_FORCE * WIDTH * HEIGHT_2; 2];
    let expected = [carried[0], carried[1], top, top];
    for ((pair, result), exact) in loaded.model.pairs.iter().zip(&sol.contact).zip(expected) {
        let up = result.force_on(1)[1];
        let down = -result.force_on(0)[1];
        for f in [up, down] {
            let err = (f - exact).abs() / exact;
            assert!(err <= 1e-8, "{}: {f} against {exact} ({err:e})", pair.name);
        }
    }

    let reference = solve_monolithic(&loaded.model).unwrap();
    assert!(reference.converged, "{:?}", reference.message);
    let peak = (reference.contact.iter())
        .flat_map(|p| p.pressure.iter())
        .fold(0.0f64, |m, p| m.max(p.abs()));
    for (dd, mono) in sol.contact.iter().zip(&reference.contact) {
        for (a, b) in dd.pressure.iter().zip(&mono.pressure) {
            assert!((a - b).abs() <= 1e-6 * peak, "{}: {a} against {b}", dd.name);
        }
    }
}
