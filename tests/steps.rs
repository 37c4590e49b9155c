//! Load steps (`contactdd_ddm::steps`): each step must be the solution of the problem at its
//! load factor. The references: the exact uniform stress of a column of blocks, and direct solves
//! of models whose loads and prescribed displacements are scaled by hand.

use contactdd::cases;
use contactdd::ddm::steps::{equal_steps, solve_steps};
use contactdd::ddm::{prepare, solve, Hooks, Model, Settings, Solution};
use contactdd::fem::Component;

fn steps(model: &Model, factors: &[f64]) -> Vec<(f64, Solution)> {
    let mut prepared = prepare(model).unwrap();
    let settings = Settings::default();
    solve_steps(
        model,
        &mut prepared,
        &settings,
        factors,
        Hooks::default(),
        &mut |_, _, _| (),
    )
    .unwrap()
}

/// The model with every load and prescribed displacement times `factor`.
fn scaled(model: &Model, factor: f64) -> Model {
    let mut model = model.clone();
    for body in &mut model.bodies {
        body.load.iter_mut().for_each(|f| *f *= factor);
        let fixed: Vec<(usize, f64)> = body.constraints.fixed().collect();
        for (d, v) in fixed {
            body.constraints.set(d, Some(factor * v));
        }
    }
    model
}

fn largest_difference(a: &Solution, b: &Solution) -> f64 {
    let scale = b
        .bodies
        .iter()
        .flat_map(|r| r.displacement.iter())
        .fold(0.0f64, |m, u| m.max(u.abs()));
    a.bodies
        .iter()
        .zip(&b.bodies)
        .flat_map(|(x, y)| x.displacement.iter().zip(&y.displacement))
        .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()))
        / scale
}

/// A column of floating blocks under p = 100: every step carries the pressure factor · p at every
/// contact point, exactly.
#[test]
fn every_step_of_a_column_carries_its_share_of_the_load() {
    let model = cases::column(4, 0.01);
    let results = steps(&model, &equal_steps(4));
    assert_eq!(results.len(), 4);
    for (factor, sol) in &results {
        assert!(sol.converged, "factor {factor}: {:?}", sol.message);
        for pair in &sol.contact {
            for &p in &pair.pressure {
                assert!(
                    (p + 100.0 * factor).abs() <= 1e-6 * 100.0,
                    "{p} at factor {factor}"
                );
            }
        }
    }
}

/// The notch, with its lower body pushed up by a prescribed displacement instead of a pressure:
/// every step equals a direct solve of the problem scaled by hand (the contact zone grows with
/// the load, so the answer is not proportional to the factor).
#[test]
fn steps_equal_direct_solves_of_the_scaled_problem() {
    let mut model = contactdd::ddm::benchmark::Notch::default().model().unwrap();
    let lower = &mut model.bodies[0];
    lower.load.iter_mut().for_each(|f| *f = 0.0);
    lower
        .constraints
        .fix(&lower.mesh, "bottom", Component::Y, 0.02)
        .unwrap();
    let factors = [0.3, 0.6, 1.0];
    let results = steps(&model, &factors);
    let mut zones = Vec::new();
    for (factor, sol) in &results {
        assert!(sol.converged, "factor {factor}: {:?}", sol.message);
        let direct_model = scaled(&model, *factor);
        let direct = solve(
            &direct_model,
            &prepare(&direct_model).unwrap(),
            &Settings::default(),
            Hooks::default(),
        )
        .unwrap();
        let diff = largest_difference(sol, &direct);
        assert!(diff <= 1e-8, "factor {factor}: differs by {diff:.2e}");
        zones.push(sol.contact[0].closed.iter().filter(|&&c| c).count());
    }
    assert!(zones[0] < zones[2], "closed points per step: {zones:?}");
}
