//! The interface Newton method (the default) on problems where the Robin sweeps are slow: stiff
//! penalties, unequal bodies, bodies that start apart, and a load that pulls a body away. The
//! references are independent: the monolithic solution, the exact uniform stress of a column,
//! and force balance.

use contactdd::cases;
use contactdd::ddm::benchmark::Notch;
use contactdd::ddm::contact::gap_profile::GapProfile;
use contactdd::ddm::{prepare, solve, solve_monolithic, Hooks, Model, Penalty, Settings, Solution};

fn run(model: &Model, settings: &Settings) -> Solution {
    let prepared = prepare(model).unwrap();
    solve(model, &prepared, settings, Hooks::default()).unwrap()
}

/// Largest |σ_n − σ_n,ref| relative to the largest reference pressure, over all pairs.
fn pressure_error(sol: &Solution, model: &Model) -> f64 {
    let reference = solve_monolithic(model).unwrap();
    let mut worst = 0.0f64;
    for (pair, refp) in sol.contact.iter().zip(&reference.contact) {
        let scale = refp.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        for (p, q) in pair.pressure.iter().zip(&refp.pressure) {
            worst = worst.max((p - q).abs() / scale);
        }
    }
    worst
}

/// A stiff block under a ten times softer loaded one: the count does not grow as the penalty
/// stiffens 100×, and the answer is the monolithic one.
#[test]
fn stiff_penalties_take_a_count_independent_of_the_penalty() {
    let mut counts = Vec::new();
    for c in [0.05, 0.005, 0.0005] {
        let model = cases::stiff_under_soft(c);
        let sol = run(&model, &Settings::default());
        assert!(sol.converged, "c = {c}: {:?}", sol.message);
        assert!(
            sol.iterations <= 30,
            "c = {c}: {} iterations",
            sol.iterations
        );
        let err = pressure_error(&sol, &model);
        assert!(
            err <= 1e-8,
            "c = {c}: pressure off the monolithic by {err:e}"
        );
        counts.push(sol.iterations);
    }
    assert!(
        counts[2] as f64 <= 1.5 * counts[0] as f64,
        "counts for c = 0.05, 0.005, 0.0005: {counts:?}"
    );
}

/// Two large blocks over a recess with a stiff penalty: E₁/E₂ = 2 takes the count of identical
/// materials (within 1.5×).
#[test]
fn material_contrast_does_not_change_the_count() {
    let count = |ratio: f64| {
        let sol = run(&cases::recess(ratio, 0.005, 16), &Settings::default());
        assert!(sol.converged, "E1/E2 = {ratio}: {:?}", sol.message);
        sol.iterations
    };
    let (same, two) = (count(1.0), count(2.0));
    assert!(
        two as f64 <= 1.5 * same as f64,
        "{same} and {two} iterations"
    );
}

/// Columns of 8 to 512 floating blocks, each pair non-matching: a few iterations whatever the
/// length, and the exact uniform pressure p = 100 on every interface. The 512 blocks have 511
/// rigid modes, whose free motions the sparse LDLᵀ of `newton/null_space.rs` finds.
#[test]
fn columns_converge_in_a_few_iterations_with_the_exact_pressure() {
    for n in [8, 64, 512] {
        let sol = run(&cases::column(n, 0.5), &Settings::default());
        assert!(sol.converged, "{n} blocks: {:?}", sol.message);
        assert!(sol.iterations <= 10, "{n} blocks: {}", sol.iterations);
        for pair in &sol.contact {
            for p in &pair.pressure {
                assert!((p + 100.0).abs() <= 1.0, "{n} blocks, {}: {p}", pair.name);
            }
        }
    }
}

/// Every block of a column starts 1e−3 away from the next one: the method must move the
/// floating blocks (which no closed contact holds at the start) into contact. The answer is the
/// same uniform pressure.
#[test]
fn blocks_that_start_apart_are_brought_into_contact() {
    let mut model = cases::column(6, 0.5);
    for pair in &mut model.pairs {
        pair.profile = Some(GapProfile::Uniform { value: 1e-3 });
    }
    let sol = run(&model, &Settings::default());
    assert!(sol.converged, "{:?}", sol.message);
    assert!(sol.iterations <= 30, "{} iterations", sol.iterations);
    for pair in &sol.contact {
        for p in &pair.pressure {
            assert!((p + 100.0).abs() <= 1.0, "{}: {p}", pair.name);
        }
    }
}

/// A load that pulls the top block of a column away has no equilibrium: the solve must not
/// report a solution.
#[test]
fn a_block_pulled_away_is_not_reported_as_a_solution() {
    let mut model = cases::column(3, 0.5);
    let top = model.bodies.last_mut().unwrap();
    top.load.iter_mut().for_each(|f| *f = -*f);
    let sol = run(&model, &Settings::default());
    assert!(!sol.converged, "reported converged: {:?}", sol.stop);
    // It says so early: a block has lost its hold.
    assert!(sol.iterations < 100, "{} iterations", sol.iterations);
    let message = sol.message.unwrap_or_default();
    assert!(message.contains("no closed contact point"), "{message}");
}

/// The paper's notch with its loads reversed: both blocks pulled apart, held vertically only by
/// the contact. Along their separation no contact point can push back (every gap opens), so the
/// loads have no equilibrium, whatever the closed set: the solve must say so at once, naming a
/// block. It ran 100 Newton steps to "stopped reducing the residual" before.
#[test]
fn blocks_pulled_apart_are_reported_at_once() {
    let mut model = Notch::default().model().unwrap();
    for body in &mut model.bodies {
        body.load.iter_mut().for_each(|f| *f = -*f);
    }
    let sol = run(&model, &Settings::default());
    assert!(!sol.converged, "reported converged: {:?}", sol.stop);
    assert!(sol.iterations <= 1, "{} iterations", sol.iterations);
    let message = sol.message.unwrap_or_default();
    assert!(message.contains("nothing holds body"), "{message}");
}

/// The Hertz example (stiff penalty θ·E*/a ≈ 0.01, non-matching P2 meshes): at most 40
/// iterations, both bodies in equilibrium.
#[test]
fn the_hertz_example_takes_at_most_forty_iterations() {
    let loaded = contactdd::io::load_file(std::path::Path::new("examples/hertz.toml")).unwrap();
    let sol = run(&loaded.model, &loaded.settings);
    assert!(sol.converged, "{:?}", sol.message);
    assert!(sol.iterations <= 40, "{} iterations", sol.iterations);
    let load: f64 = 900.0;
    let carried = sol.contact[0].force_on(1)[1].abs();
    assert!(
        (carried - load).abs() <= 1e-6 * load,
        "block carries {carried}"
    );
}

/// The start does not decide the answer: from u⁰ = 0 no point is closed and the block, held
/// vertically only by the contact, floats; with a penalty 1000× stiffer than the example's the
/// residual there is tiny (it leaves out the block's balance). The solve still converges, to the
/// pressures of the default start.
#[test]
fn a_start_with_nothing_closed_reaches_the_same_answer() {
    let loaded = contactdd::io::load_file(std::path::Path::new("examples/hertz.toml")).unwrap();
    let mut model = loaded.model;
    model.pairs[0].penalty = Penalty::Theta(8e-12);
    let default = run(&model, &loaded.settings);
    assert!(default.converged, "{:?}", default.message);
    for u0 in [0.0, 1e-9] {
        let settings = Settings {
            u0,
            u_prev: u0,
            ..loaded.settings.clone()
        };
        let sol = run(&model, &settings);
        assert!(sol.converged, "u0 = {u0}: {:?}", sol.message);
        let (a, b) = (&sol.contact[0], &default.contact[0]);
        let scale = a.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        for (p, q) in a.pressure.iter().zip(&b.pressure) {
            assert!((p - q).abs() <= 1e-6 * scale, "u0 = {u0}: {p} against {q}");
        }
    }
}
