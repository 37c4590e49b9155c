//! Exact contact in space (`enforcement = "augmented"`): the Signorini conditions without a
//! penalty overlap, against a closed form, against the penalty solutions as θ → 0, and against
//! the monolithic reference's multiplier updates.

use std::path::Path;

use contactdd::ddm::Enforcement;
use contactdd::io::solid_run::{run_solid, SolidOutcome, SolidSolver};
use contactdd::io::solid_setup::{load_solid_file, SolidModel};

fn example(name: &str) -> SolidModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/space")
        .join(name);
    load_solid_file(&path).unwrap()
}

/// `model` with every pair's θ and enforcement set, solved by the decomposition; it converges.
fn solved(model: &SolidModel, theta: f64, enforcement: Enforcement) -> SolidOutcome {
    let mut model = model.clone();
    for p in &mut model.pairs {
        (p.theta, p.enforcement) = (theta, enforcement);
    }
    let outcome = run_solid(&model, SolidSolver::Decomposition).unwrap();
    assert!(outcome.converged, "{:?}", outcome.reason);
    outcome
}

fn pressures(outcome: &SolidOutcome) -> Vec<f64> {
    outcome.solution.points.iter().map(|p| p.pressure).collect()
}

/// The blocks of `examples/space/blocks.toml` (steel under aluminium, P1 against P2 on
/// non-matching faces, the top moved down by δ): exact contact transmits the uniform pressure
/// p = δ/(h₁/E₁ + h₂/E₂) at every point, whatever θ, with no overlap.
#[test]
fn blocks_carry_the_exact_pressure_for_any_penalty() {
    let model = example("blocks.toml");
    let (delta, h, e1, e2) = (0.001, 0.5, 2.1e5, 7e4);
    let exact = delta / (h / e1 + h / e2);
    for theta in [1e-9, 1e-7, 1e-3, 1.0] {
        let outcome = solved(&model, theta, Enforcement::Augmented);
        for p in pressures(&outcome) {
            assert!(
                (p / exact - 1.0).abs() < 1e-10,
                "θ = {theta}: {p} against {exact}"
            );
        }
        assert!(outcome.balance.gap_violation < 1e-12 * delta);
        assert!(outcome.balance.contact_law < 1e-10);
    }
    // The penalty solution overlaps by θ p instead: its pressure δ/(h₁/E₁ + h₂/E₂ + θ).
    let penalty = solved(&model, 1e-6, Enforcement::Penalty);
    let expected = delta / (h / e1 + h / e2 + 1e-6);
    assert!(pressures(&penalty)
        .iter()
        .all(|p| (p / expected - 1.0).abs() < 1e-8));
}

/// The ball on the block (`sphere_block.toml`, curved P2): the penalty pressures approach the
/// exact ones as θ falls, the error in proportion to θ (the overlap θ p is the only difference),
/// and the exact contact meets the Signorini conditions to rounding.
#[test]
fn penalty_pressures_approach_the_exact_ones_in_proportion_to_theta() {
    let model = example("sphere_block.toml");
    let exact = solved(&model, 1e-9, Enforcement::Augmented);
    let p_exact = pressures(&exact);
    let peak = p_exact.iter().fold(0.0f64, |m, &p| m.max(p));
    assert!(exact.balance.gap_violation < 1e-12);
    let error = |theta: f64| {
        let p = pressures(&solved(&model, theta, Enforcement::Penalty));
        let diff = p.iter().zip(&p_exact).map(|(a, b)| (a - b).abs());
        diff.fold(0.0f64, f64::max) / peak
    };
    // θ of 1e-11 and below is where the penalty itself fails the contact-law check: the
    // overlaps are then at the rounding of the displacements.
    let errors = [1e-8, 1e-9, 1e-10].map(error);
    println!("largest difference from the exact pressures over the peak, θ = 1e-8, 1e-9, 1e-10: {errors:?}");
    for pair in errors.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!((5.0..20.0).contains(&ratio), "{errors:?}: first order in θ");
    }
}

/// The monolithic reference meets the same conditions by another algorithm (the method of
/// multipliers around its penalty Newton method): both agree to 1e-9 of the peak pressure, on
/// the blocks and on the floating ball.
#[test]
fn the_monolithic_reference_agrees_by_multiplier_updates() {
    for name in ["blocks.toml", "ball_between_plates.toml"] {
        let mut model = example(name);
        model
            .pairs
            .iter_mut()
            .for_each(|p| p.enforcement = Enforcement::Augmented);
        let dd = run_solid(&model, SolidSolver::Decomposition).unwrap();
        let reference = run_solid(&model, SolidSolver::Monolithic).unwrap();
        assert!(dd.converged && reference.converged, "{name}");
        let (a, b) = (pressures(&dd), pressures(&reference));
        let peak = a.iter().fold(0.0f64, |m, &p| m.max(p));
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9 * peak, "{name}: {worst:e} of {peak}");
        assert!(reference.balance.gap_violation < 1e-12, "{name}");
    }
}

/// The floating ball between two plates (`ball_between_plates.toml`): held by contact alone, it
/// meets the Signorini conditions exactly, both pairs press, and the independent check balances
/// every body, the ball included.
#[test]
fn a_floating_ball_meets_the_conditions_exactly() {
    let model = example("ball_between_plates.toml");
    let outcome = solved(&model, model.pairs[0].theta, Enforcement::Augmented);
    assert!(outcome.balance.gap_violation < 1e-12);
    assert!(outcome.balance.worst() < 1e-10);
    let force = |pair: usize| -> f64 {
        (outcome.solution.points.iter())
            .filter(|p| p.pair == pair)
            .map(|p| p.weight * p.pressure)
            .sum()
    };
    assert!(force(0) > 0.0 && force(1) > 0.0);
}

/// `blocks.toml` with the upper block moved down by `shift` and its top held at `push`
/// (instead of moved 0.001): the blocks overlap where `shift` > 0 (an interference fit), or
/// start `-shift` apart.
fn shifted_blocks(shift: f64, push: f64) -> SolidModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/space/blocks.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let z = format!("z = [{}, {}]", 0.5 - shift, 1.0 - shift);
    let text = text
        .replace("z = [0.5, 1.0]", &z)
        .replace("value = -0.001", &format!("value = {}", -push));
    let file =
        std::env::temp_dir().join(format!("exact-space-{}-{shift}.toml", std::process::id()));
    std::fs::write(&file, text).unwrap();
    let model = load_solid_file(&file).unwrap();
    let _ = std::fs::remove_file(&file);
    model
}

/// Hard cases of the kinds a press fit and a near-coincident mesh make: an interference of
/// 1e-3 with nothing pushed carries the closed form's pressure shift/(h₁/E₁ + h₂/E₂) exactly;
/// so does a push across a gap of 1e-10 (the pressure of the push less the gap), and a gap
/// larger than the push leaves every point open at zero pressure. The reference agrees.
#[test]
fn interference_and_near_coincident_blocks_are_exact() {
    let compliance = 0.5 / 2.1e5 + 0.5 / 7e4;
    for (shift, push, expected) in [
        (1e-3, 0.0, 1e-3 / compliance),
        (-1e-10, 1e-3, (1e-3 - 1e-10) / compliance),
        (-2e-3, 1e-3, 0.0),
    ] {
        let mut model = shifted_blocks(shift, push);
        model.pairs[0].enforcement = Enforcement::Augmented;
        for solver in [SolidSolver::Decomposition, SolidSolver::Monolithic] {
            let outcome = run_solid(&model, solver).unwrap();
            assert!(
                outcome.converged,
                "{shift} {solver:?}: {:?}",
                outcome.reason
            );
            for p in pressures(&outcome) {
                let error = (p - expected).abs();
                assert!(error <= 1e-9 * expected.max(1.0), "{shift} {solver:?}: {p}");
            }
        }
    }
}
