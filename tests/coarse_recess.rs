//! The two-level sweeps never cost more iterations than the one-level sweeps on a recess between
//! two blocks that only the contact holds vertically (both blocks pressed by opposite pressures,
//! nothing else holds them vertically), with `active-set` and `gamma = "auto"`, where a correction
//! of every floating body stalls without the guard (docs/two-level.md, "Which bodies" and "The
//! guard"). The
//! results are checked against the applied load: the contact carries q · 20 = 2000 on each side.

use contactdd::cases;
use contactdd::ddm::{prepare, solve, CoarseMode, Gamma, Hooks, Method, Model, Settings, Solution};

fn sweeps(coarse: CoarseMode) -> Settings {
    Settings {
        coarse,
        max_iter: 3000,
        ..Settings::paper(Method::ActiveSet, Gamma::Auto)
    }
}

fn run(model: &Model, settings: &Settings) -> Solution {
    let prepared = prepare(model).unwrap();
    let sol = solve(model, &prepared, settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{}: {:?}", settings.coarse, sol.message);
    // The contact carries the applied load: 2000 on each block, opposite.
    let pair = &sol.contact[0];
    for side in 0..2 {
        let fy = pair.force_on(side)[1];
        let expected = if side == 0 { -2000.0 } else { 2000.0 };
        assert!(
            (fy - expected).abs() <= 1e-3 * 2000.0,
            "{}: force on side {side} = {fy}",
            settings.coarse
        );
    }
    sol
}

/// With a stiff penalty (c = 0.005, θ·E* ≈ 0.01) the one-level sweeps converge in a few tens
/// of iterations; the two-level sweeps (the coarse correction of chains, which the method and
/// `auto` select) need at most 1.2 times as many.
#[test]
fn the_coarse_correction_costs_no_iterations_on_a_floating_recess() {
    for (ratio, c) in [(1.0, 0.005), (1.0, 0.0005)] {
        let model = cases::floating_recess(ratio, c, 8);
        let one_level = run(&model, &sweeps(CoarseMode::Off)).iterations;
        let two_level = run(&model, &sweeps(CoarseMode::Chains)).iterations;
        assert!(
            two_level as f64 <= 1.2 * one_level as f64,
            "E1/E2 = {ratio}, c = {c}: {two_level} two-level against {one_level} one-level"
        );
    }
}

/// `coarse = "all"` does move the two floating blocks; the guard switches the correction off
/// once a corrected sweep's update grows and the sweep without it is smaller, so the iteration
/// converges (it stalled at the iteration cap without the guard).
#[test]
fn the_guard_switches_off_a_correction_that_hurts() {
    let model = cases::floating_recess(1.0, 0.005, 8);
    let one_level = run(&model, &sweeps(CoarseMode::Off)).iterations;
    let all = run(&model, &sweeps(CoarseMode::All)).iterations;
    assert!(
        all as f64 <= 1.2 * one_level as f64,
        "{all} with coarse all against {one_level} one-level"
    );
}
