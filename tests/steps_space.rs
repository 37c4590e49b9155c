//! Load steps in space (`[solver] load-steps`): the bodies factorised once, one Newton
//! iteration per load factor, against Hertz's force–approach law, the closed form of two blocks
//! that close across a gap, single solves at the same loads, and the monolithic reference.

use std::path::Path;

use contactdd::io::solid_run::{run_solid, SolidOutcome, SolidSolver};
use contactdd::io::solid_setup::{load_solid_file, SolidModel};

/// The example `name` with `extra` appended and its mesh paths made absolute.
fn example_with(name: &str, extra: &str) -> SolidModel {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space");
    let text = std::fs::read_to_string(dir.join(name)).unwrap();
    let meshes = dir.join("../meshes/");
    let text = text.replace("../meshes/", meshes.to_str().unwrap()) + extra;
    let file = std::env::temp_dir().join(format!("steps-space-{}-{name}", std::process::id()));
    std::fs::write(&file, text).unwrap();
    let model = load_solid_file(&file).unwrap();
    let _ = std::fs::remove_file(&file);
    model
}

fn solved(model: &SolidModel, solver: SolidSolver) -> SolidOutcome {
    let outcome = run_solid(model, solver).unwrap();
    assert!(outcome.converged, "{:?}", outcome.reason);
    outcome
}

fn pressures(outcome: &SolidOutcome) -> Vec<f64> {
    outcome.solution.points.iter().map(|p| p.pressure).collect()
}

/// The ball on the block pressed by δ/8, δ/4, δ/2 and δ: Hertz's F ∝ δ^{3/2} between steps,
/// the monitored top face moves by the prescribed amount, and the steps are the single solves
/// at their loads (the last one to the bit).
#[test]
fn the_ball_on_the_block_follows_hertz_from_step_to_step() {
    let steps = "\n[solver]\nload-steps = [0.125, 0.25, 0.5, 1.0]\n\
                 monitor = { body = \"ball\", boundary = \"top\" }\n";
    let model = example_with("sphere_block.toml", steps);
    let outcome = solved(&model, SolidSolver::Decomposition);
    assert_eq!(outcome.steps.len(), 4);
    for pair in outcome.steps.windows(2) {
        let force = pair[1].pair_forces[0] / pair[0].pair_forces[0];
        let slope = force.ln() / (pair[1].factor / pair[0].factor).ln();
        assert!((slope / 1.5 - 1.0).abs() < 0.03, "slope {slope}");
    }
    for s in &outcome.steps {
        let top = s.monitor.unwrap()[2];
        assert!((top + 0.01 * s.factor).abs() < 1e-12, "{top}");
    }
    let single = solved(
        &example_with("sphere_block.toml", ""),
        SolidSolver::Decomposition,
    );
    assert_eq!(pressures(&single), pressures(&outcome));
    // The second step against a single solve of the problem pressed by δ/4.
    let quarter = example_with("sphere_block.toml", "\n[solver]\nload-steps = [0.25]\n");
    let alone = solved(&quarter, SolidSolver::Decomposition);
    let force = alone.steps[0].pair_forces[0];
    assert!((force / outcome.steps[1].pair_forces[0] - 1.0).abs() < 1e-12);
}

/// The blocks of `blocks.toml` started 4e-4 apart and pushed by 2e-4, 5e-4, 6e-4 and 1e-3:
/// open, then p = (push − gap)/(h₁/E₁ + h₂/E₂ + θ) at every point; by both solvers.
#[test]
fn blocks_close_across_a_gap_as_the_closed_form_says() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space/blocks.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let gap = 4e-4;
    let text = text.replace(
        "z = [0.5, 1.0]",
        &format!("z = [{}, {}]", 0.5 + gap, 1.0 + gap),
    ) + "\n[solver]\nload-steps = [0.2, 0.5, 0.6, 1.0]\n";
    let file = std::env::temp_dir().join(format!("steps-space-gap-{}.toml", std::process::id()));
    std::fs::write(&file, text).unwrap();
    let model = load_solid_file(&file).unwrap();
    let _ = std::fs::remove_file(&file);
    let compliance = 0.5 / 2.1e5 + 0.5 / 7e4 + 1e-7;
    for solver in [SolidSolver::Decomposition, SolidSolver::Monolithic] {
        let outcome = solved(&model, solver);
        assert!(outcome.steps.iter().all(|s| s.converged));
        let expected: Vec<f64> = (outcome.steps.iter())
            .map(|s| ((1e-3 * s.factor - gap) / compliance).max(0.0))
            .collect();
        // The last step's pressures, point by point, and every step's resultant (the interface
        // is the unit square).
        for p in pressures(&outcome) {
            assert!(
                (p - expected[3]).abs() < 1e-8 * expected[3],
                "{solver:?}: {p}"
            );
        }
        for (s, e) in outcome.steps.iter().zip(&expected) {
            let f = s.pair_forces[0];
            assert!(
                (f - e).abs() < 1e-8 * expected[3],
                "{solver:?}: {f} against {e}"
            );
        }
    }
}
