//! Timing of the notch benchmark scaled to two bodies of about 1e6 DOFs each (1000 × 500 cells per
//! body): the full DD solve against the baseline "assemble + factorise + one solve of both bodies".
//!
//! Run: `cargo run --release --example large_two_bodies [-- NX NY]` (default 1000 500).

use std::time::Instant;

use contactdd_core::factor::FactoredBody;
use contactdd_ddm::benchmark::Notch;
use contactdd_ddm::{prepare, solve, Gamma, Hooks, Method, Settings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let (nx, ny) = (
        args.first().copied().unwrap_or(1000),
        args.get(1).copied().unwrap_or(500),
    );
    let model = Notch {
        nx,
        ny,
        ..Notch::default()
    }
    .model()?;
    let dofs: Vec<usize> = model
        .bodies
        .iter()
        .map(|b| 2 * b.mesh.num_nodes())
        .collect();
    println!("two bodies, {nx} x {ny} cells each, DOFs {dofs:?}");

    // Baseline: both bodies assembled, factorised (faer AMD, no contact ordering) and solved once,
    // in parallel over bodies like the DD setup. Each body is held by springs on its contact
    // line (the reference operator), so that the factorisation exists.
    let t = Instant::now();
    let baseline: Result<Vec<()>, Box<dyn std::error::Error + Send + Sync>> = {
        use rayon::prelude::*;
        model
            .bodies
            .par_iter()
            .map(|body| {
                let k = body.stiffness();
                let mut op = FactoredBody::new(&body.name, k, &body.constraints, &[])?;
                let springs: Vec<(usize, usize, f64)> = body
                    .mesh
                    .boundary_nodes(if body.name == "lower" {
                        "top"
                    } else {
                        "bottom"
                    })?
                    .iter()
                    .map(|&v| (2 * v + 1, 2 * v + 1, 1.0))
                    .collect();
                op.factorize(&springs)?;
                op.solve(&body.load)?;
                println!(
                    "  baseline factor of '{}': {} values",
                    body.name,
                    op.factor_len()
                );
                Ok(())
            })
            .collect()
    };
    baseline.map_err(|e| e.to_string())?;
    let t_base = t.elapsed().as_secs_f64();
    println!("baseline (assemble + factorise + solve, both bodies): {t_base:.3} s");

    let t = Instant::now();
    let prepared = prepare(&model)?;
    let t_prep = t.elapsed().as_secs_f64();
    let settings = Settings {
        tol: 1e-3,
        max_iter: 500,
        ..Settings::paper(Method::NewtonKurchatov, Gamma::Constant(0.5))
    };
    let t2 = Instant::now();
    let sol = solve(&model, &prepared, &settings, Hooks::default())?;
    let t_solve = t2.elapsed().as_secs_f64();
    let total = t.elapsed().as_secs_f64();
    println!(
        "DD prepare: {t_prep:.3} s; iterate + recover + post: {t_solve:.3} s; iterations {}",
        sol.iterations
    );
    for body in prepared.bodies.iter().flatten() {
        println!("  DD factor: {} values", body.operator().factor_len());
    }
    for (phase, s) in &sol.timing {
        println!("  {phase}: {s:.3} s");
    }
    println!(
        "total DD solve: {total:.3} s; ratio to baseline: {:.2}",
        total / t_base
    );
    Ok(())
}
