//! A wall of blocks confined between two frictionless side walls and pressed on top
//! (`cases::wall`): many floating bodies, contact across horizontal and vertical lines at once,
//! non-matching meshes on every interface. The reference is the closed form of the uniform stress
//! (σ_yy = −q; the lateral pressure from the confinement, with the penalty's overlaps or without),
//! independent of the solver.

use contactdd::cases::{self, WALL_Q};
use contactdd::ddm::{
    prepare, solve, solve_monolithic, Enforcement, GapProfile, Hooks, Model, Settings, Solution,
};

const NU: f64 = 0.3;

fn run(model: &Model) -> Solution {
    run_with(
        model,
        Settings {
            tol: 1e-9,
            ..Settings::default()
        },
    )
}

fn run_with(model: &Model, settings: Settings) -> Solution {
    let prepared = prepare(model).unwrap();
    let sol = solve(model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{}: {:?}", model.name, sol.message);
    sol
}

/// The largest deviation of the pressed points' pressures from −q on the horizontal interfaces
/// and from −`lateral` on the vertical ones, relative to q.
fn deviation(model: &Model, sol: &Solution, lateral: f64) -> f64 {
    let mut worst = 0.0f64;
    for (pair, result) in model.pairs.iter().zip(&sol.contact) {
        let exact = if pair.boundaries[0] == "top" {
            WALL_Q
        } else {
            lateral
        };
        for &p in result.pressure.iter().filter(|p| **p != 0.0) {
            worst = worst.max((p + exact).abs() / WALL_Q);
        }
    }
    worst
}

/// The lateral pressure of the penalty wall with `columns` columns: q ν/(1 − ν) / (1 + 2c (n − 1)/n),
/// softened by the overlaps of the n − 1 vertical interfaces.
fn penalty_lateral(columns: usize, c: f64) -> f64 {
    let n = columns as f64;
    WALL_Q * NU / (1.0 - NU) / (1.0 + 2.0 * c * (n - 1.0) / n)
}

/// The penalty formulation has the closed-form stress.
#[test]
fn the_penalty_wall_has_the_closed_form_stress() {
    for (columns, rows, c) in [(3, 3, 0.05), (4, 5, 0.5)] {
        let model = cases::wall(columns, rows, c);
        let sol = run(&model);
        let error = deviation(&model, &sol, penalty_lateral(columns, c));
        assert!(error <= 1e-8, "{}, c = {c}: {error:e}", model.name);
    }
}

/// The exact contact (augmented Lagrangian): the lateral pressure q ν/(1 − ν), for any penalty.
#[test]
fn the_exact_wall_has_the_confined_stress() {
    for c in [0.5, 0.005] {
        let mut model = cases::wall(4, 3, c);
        for pair in &mut model.pairs {
            pair.enforcement = Enforcement::Augmented;
        }
        let sol = run(&model);
        let error = deviation(&model, &sol, WALL_Q * NU / (1.0 - NU));
        assert!(error <= 1e-6, "c = {c}: {error:e}");
    }
}

/// Rows that start 1e−3 apart, and a start with nothing closed (u⁰ = 0): the side walls and the
/// neighbours hold every block sideways, but nothing holds a column of blocks against the load
/// that pushes it down until the rows close. The uniform gaps change no stress.
/// The 4 × 5 wall (c = 0.05) with its rows 1e−3 apart.
fn rows_apart() -> Model {
    let mut model = cases::wall(4, 5, 0.05);
    for pair in model.pairs.iter_mut().filter(|p| p.boundaries[0] == "top") {
        pair.profile = Some(GapProfile::Uniform { value: 1e-3 });
    }
    model
}

#[test]
fn a_wall_held_only_sideways_at_the_start_closes() {
    let lateral = penalty_lateral(4, 0.05);
    let apart = rows_apart();
    let error = deviation(&apart, &run(&apart), lateral);
    assert!(error <= 1e-8, "rows apart: {error:e}");

    let model = cases::wall(4, 5, 0.05);
    let settings = Settings {
        tol: 1e-9,
        u0: 0.0,
        u_prev: 0.0,
        ..Settings::default()
    };
    let error = deviation(&model, &run_with(&model, settings), lateral);
    assert!(error <= 1e-8, "u0 = 0: {error:e}");
}

/// The monolithic reference, which shares no solver code with the decomposition, solves the wall
/// whose rows start apart too, to the same pressures.
#[test]
fn the_monolithic_reference_agrees_on_the_wall_with_rows_apart() {
    let model = rows_apart();
    let dd = run(&model);
    let reference = solve_monolithic(&model).unwrap();
    assert!(reference.converged, "{:?}", reference.message);
    for (a, b) in dd.contact.iter().zip(&reference.contact) {
        for (p, q) in a.pressure.iter().zip(&b.pressure) {
            assert!(
                (p - q).abs() <= 1e-8 * WALL_Q,
                "{}: {p} against {q}",
                a.name
            );
        }
    }
}
