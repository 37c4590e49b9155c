//! The augmented Lagrangian (`docs/augmented-lagrangian.md`) against the penalty formulation:
//! inner iterations, multiplier updates, peak pressure and largest penetration, on the notch at
//! penalties 1000× apart and on harder cases; and the recess's open half-width against the
//! closed form of two pressed half-planes as the mesh is refined.
//!
//! Run: `cargo run --release --example exact_contact`

use std::time::Instant;

use contactdd::cases;
use contactdd::ddm::benchmark::Notch;
use contactdd::ddm::{prepare, solve, Enforcement, Hooks, Model, Settings, Solution};

fn with(mut model: Model, enforcement: Enforcement) -> Model {
    for pair in &mut model.pairs {
        pair.enforcement = enforcement;
    }
    model
}

fn run(model: &Model) -> Option<(Solution, f64)> {
    let t = Instant::now();
    let prepared = prepare(model).ok()?;
    let sol = solve(model, &prepared, &Settings::default(), Hooks::default()).ok()?;
    Some((sol, t.elapsed().as_secs_f64()))
}

fn row(name: &str, model: Model) {
    for enforcement in [Enforcement::Penalty, Enforcement::Augmented] {
        let Some((sol, seconds)) = run(&with(model.clone(), enforcement)) else {
            println!("{name:<26} {enforcement:<9} setup or settings failed");
            continue;
        };
        let peak = sol
            .contact
            .iter()
            .flat_map(|p| p.pressure.iter())
            .fold(0.0f64, |m, p| m.max(p.abs()));
        let penetration = sol
            .contact
            .iter()
            .map(|p| p.max_penetration())
            .fold(0.0f64, f64::max);
        println!(
            "{name:<26} {enforcement:<9} {:>4} it {:>3} updates  peak {peak:>11.6} penetration {penetration:>9.2e}  {:>7.3} s  {}",
            sol.iterations,
            sol.updates,
            seconds,
            sol.message.as_deref().unwrap_or("converged")
        );
    }
}

/// The open half-width of side 1, from p² extrapolated to zero at the first two closed points.
fn half_width(sol: &Solution) -> f64 {
    let pair = &sol.contact[0];
    let mut points: Vec<(f64, f64)> = (0..pair.x.len())
        .filter(|&i| pair.side[i] == 1)
        .map(|i| (pair.x[i], pair.pressure[i].abs()))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let Some(first) = points.iter().position(|p| p.1 > 0.0) else {
        return f64::NAN;
    };
    let ((x1, p1), (x2, p2)) = (points[first], points[first + 1]);
    x1 - p1 * p1 * (x2 - x1) / (p2 * p2 - p1 * p1)
}

fn main() {
    for c in [0.5, 0.05, 0.005, 0.0005] {
        let notch = Notch {
            c,
            ..Notch::default()
        };
        if let Ok(model) = notch.model() {
            row(&format!("notch c = {c}"), model);
        }
    }
    row("stiff under soft c = 0.05", cases::stiff_under_soft(0.05));
    row("column of 8, c = 0.01", cases::column(8, 0.01));
    row("recess E1/E2 = 2", cases::recess(2.0, 0.05, 32));
    row("non-matching notch", cases::non_matching_notch(0.05));
    let mut own_side = cases::non_matching_notch(0.05);
    own_side.pairs[0].forces = contactdd::ddm::Forces::OwnSide;
    row("non-matching notch, own-side", own_side);

    let e_star = 2.1e5 / (2.0 * (1.0 - 0.3f64.powi(2)));
    let q_star = 3.0 * e_star * cases::RECESS_R0 / (4.0 * cases::RECESS_B);
    let exact = cases::RECESS_B * (1.0 - cases::RECESS_Q / q_star).sqrt();
    println!("recess open half-width, closed form a = {exact:.5}");
    for n in [16, 32, 48, 64, 96, 128] {
        for enforcement in [Enforcement::Penalty, Enforcement::Augmented] {
            let model = with(cases::recess(1.0, 0.05, n), enforcement);
            if let Some((sol, _)) = run(&model) {
                let a = half_width(&sol);
                println!(
                    "  n = {n:<4} {enforcement:<9} a = {a:.5} ({:+.2} %)",
                    100.0 * (a - exact) / exact
                );
            }
        }
    }
}
