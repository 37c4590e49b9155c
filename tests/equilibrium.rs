//! Never a wrong answer reported as a solution: a solve that stops on the relative-change test
//! while its contact forces are far from balancing the load reports `Stalled`, not `Converged`.
//! The reference is the conservation law itself: the contact forces on the notch benchmark's
//! upper body must equal its applied load 8400.

use contactdd::ddm::benchmark::Notch;
use contactdd::ddm::{prepare, solve, Gamma, Hooks, Method, Settings, Stop};

fn notch_with(gamma: f64) -> contactdd::ddm::Solution {
    let model = Notch::default().model().unwrap();
    let prepared = prepare(&model).unwrap();
    let settings = Settings {
        tol: 1e-3,
        ..Settings::paper(Method::NewtonKurchatov, Gamma::Constant(gamma))
    };
    solve(&model, &prepared, &settings, Hooks::default()).unwrap()
}

fn load_carried(sol: &contactdd::ddm::Solution) -> f64 {
    sol.contact[0].force_on(1)[1]
}

#[test]
fn a_tiny_gamma_that_stops_early_is_reported_as_stalled() {
    for gamma in [1e-9, 1e-3] {
        let sol = notch_with(gamma);
        // The paper's criterion is met ...
        assert!(
            sol.iterations < 500,
            "γ = {gamma}: {} iterations",
            sol.iterations
        );
        // ... but the upper body carries far from its load of 8400,
        assert!(
            (load_carried(&sol) - 8400.0).abs() > 0.05 * 8400.0,
            "γ = {gamma}"
        );
        // so the result is not called a solution.
        assert!(!sol.converged, "γ = {gamma}");
        assert!(
            matches!(sol.stop, Stop::Stalled { .. }),
            "γ = {gamma}: {:?}",
            sol.stop
        );
        assert!(sol
            .message
            .as_deref()
            .is_some_and(|m| m.starts_with("stalled")));
    }
}

#[test]
fn a_converged_solution_balances_its_load() {
    let sol = notch_with(0.5);
    assert!(sol.converged, "{:?}", sol.message);
    let worst = sol.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
    assert!(worst <= Settings::default().equilibrium_tol);
    assert!((load_carried(&sol) - 8400.0).abs() <= 1e-2 * 8400.0);
}
