//! The interface Newton method's steps on frictional problems (docs/friction.md): the block
//! pressed on a foundation and pushed sideways, against μ, the mesh and a 100× stiffer penalty;
//! the sheared wall of floating blocks against its size, with the frictionless wall's steps
//! and times beside it. Prints the Markdown tables of docs/friction.md.
//!
//! Run: `cargo run --release --example friction_iterations`

use std::time::Instant;

use contactdd::ddm::{prepare, solve, Friction, Hooks, Model, Settings};
use contactdd::fem::Order;
use contactdd::frictional::{block_on_foundation, sheared_wall};

/// Newton steps, whether converged, and the solve's wall time (s) of `model`.
fn run(model: &Model) -> (usize, bool, f64) {
    let t = Instant::now();
    let prepared = prepare(model).expect("the case prepares");
    let sol = solve(model, &prepared, &Settings::default(), Hooks::default()).expect("it solves");
    (sol.iterations, sol.converged, t.elapsed().as_secs_f64())
}

fn cell((steps, converged, _): (usize, bool, f64)) -> String {
    if converged {
        steps.to_string()
    } else {
        format!("{steps} (not converged)")
    }
}

fn main() {
    let mus = [0.1, 0.3, 1.0];
    println!("Block, Q/N = 0.075 (p = 10, q = 1.5): Newton steps");
    println!();
    println!("| mesh of the block | penalty c | μ = 0.1 | μ = 0.3 | μ = 1.0 |");
    println!("|---|---|---|---|---|");
    let meshes = [
        ("8 P1 (matching)", 8, Order::P1),
        ("11 P1", 11, Order::P1),
        ("5 P2", 5, Order::P2),
    ];
    for (name, cells, order) in meshes {
        for c in [0.05, 0.0005] {
            let counts: Vec<String> = mus
                .iter()
                .map(|&mu| {
                    let friction = Friction::Coulomb { mu };
                    cell(run(&block_on_foundation(
                        10.0,
                        1.5,
                        friction,
                        (cells, order),
                        c,
                    )))
                })
                .collect();
            println!("| {name} | {c} | {} |", counts.join(" | "));
        }
    }
    println!();
    println!("Wall of n × n blocks, μ = 0.5, top row pushed by 0.2 q: Newton steps and time (s)");
    println!();
    println!("| n | frictionless | time | μ = 0.5 | time |");
    println!("|---|---|---|---|---|");
    for n in [2, 3, 4, 8] {
        let dry = run(&sheared_wall(n, 0.0, 0.0, 0.05));
        let wet = run(&sheared_wall(n, 0.5, 0.2, 0.05));
        println!(
            "| {n} | {} | {:.2} | {} | {:.2} |",
            cell(dry),
            dry.2,
            cell(wet),
            wet.2
        );
    }
}
