//! The paper's Robin sweeps with friction (docs/friction.md, "The Robin sweeps with friction"):
//! iterations of the five methods against γ and Coulomb's μ on the block held by its top,
//! pressed and sheared by prescribed displacements, one-level (no coarse correction), and the
//! largest difference of the tangential tractions from the interface Newton method's.
//!
//! Run: `cargo run --release --example friction_sweeps`

use contactdd::ddm::{
    prepare, solve, Accelerator, CoarseMode, Friction, Gamma, Hooks, Method, Settings, Solution,
};
use contactdd::frictional::sheared_block;

/// The block's top moved 0.01 down and 0.004 sideways.
const MOVE: (f64, f64) = (0.01, 0.004);

/// The sweeps' tolerance on the relative change.
const TOL: f64 = 1e-8;

fn sweeps(method: Method, gamma: Gamma) -> Settings {
    Settings {
        method,
        gamma,
        accelerator: Accelerator::None,
        coarse: CoarseMode::Off,
        tol: TOL,
        max_iter: 3000,
        ..Settings::default()
    }
}

/// The largest |σ_t| difference between two solutions, relative to the largest |σ_t|.
fn traction_difference(a: &Solution, b: &Solution) -> f64 {
    let (x, y) = (&a.contact[0].tangential, &b.contact[0].tangential);
    let scale = y
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    x.iter()
        .zip(y)
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
        / scale
}

fn main() {
    let mus = [0.0, 0.1, 0.3, 1.0];
    let gammas = [Gamma::Constant(0.5), Gamma::Constant(1.0), Gamma::Auto];
    println!("Block held by its top, moved {MOVE:?}: Robin sweeps to a relative change of {TOL:e}");
    println!("(iterations; in brackets the largest difference of σ_t from the Newton method's)");
    println!();
    let head: Vec<String> = mus.iter().map(|mu| format!("μ = {mu}")).collect();
    println!("| method | γ | {} |", head.join(" | "));
    println!("|---|---|{}", "---|".repeat(mus.len()));
    let models: Vec<_> = (mus.iter())
        .map(|&mu| sheared_block(Friction::Coulomb { mu }, MOVE))
        .collect();
    let prepared: Vec<_> = (models.iter())
        .map(|m| prepare(m).expect("the case prepares"))
        .collect();
    let newton: Vec<Solution> = (models.iter().zip(&prepared))
        .map(|(m, p)| solve(m, p, &Settings::default(), Hooks::default()).expect("it solves"))
        .collect();
    for method in Method::ALL.into_iter().skip(1) {
        for gamma in gammas {
            let cells: Vec<String> = (0..mus.len())
                .map(|i| {
                    let sol = solve(
                        &models[i],
                        &prepared[i],
                        &sweeps(method, gamma),
                        Hooks::default(),
                    )
                    .expect("it solves");
                    match sol.converged {
                        true => format!(
                            "{} ({:.0e})",
                            sol.iterations,
                            traction_difference(&sol, &newton[i])
                        ),
                        false => format!("{} (not converged)", sol.iterations),
                    }
                })
                .collect();
            println!("| {method} | {gamma} | {} |", cells.join(" | "));
        }
    }
    let steps: Vec<String> = newton.iter().map(|s| s.iterations.to_string()).collect();
    println!("| interface Newton | | {} |", steps.join(" | "));
}
