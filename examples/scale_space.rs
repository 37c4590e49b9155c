//! The decomposition in space at scale: two P1 boxes of about `N`³·3 DOFs each, the upper one
//! (N − 1 cubes per side: non-matching) pressed 1e-3 onto the lower, both on symmetry rollers.
//!
//! - `cargo run --release --example scale_space -- dd N` solves the contact by the decomposition
//!   and prints its phases;
//! - `cargo run --release --example scale_space -- bodies N` factorises both bodies alone (each
//!   with its own supports and a free fill-reducing order, in parallel as the decomposition
//!   does) and solves each once: what the bodies cost without contact.
//!
//! `scripts/scale_space.sh N` runs both in separate processes and reports their wall times and
//! peak resident memory (docs/three-d.md, "Scale").

use std::time::Instant;

use contactdd::fem::solid::SolidBody;
use contactdd::io::solid_run::{run_solid, SolidSolver};
use contactdd::io::solid_setup::{load_solid_file, SolidModel};

/// The problem file of the two boxes.
fn problem(n: usize) -> String {
    let box_body = |name: &str, z: [f64; 2], cells: usize, top: &str| {
        format!(
            "[[bodies]]\nname = \"{name}\"\nmaterial = \"steel\"\n\
             mesh = {{ kind = \"box\", x = [0.0, 1.0], y = [0.0, 1.0], z = [{}, {}], \
             nx = {cells}, ny = {cells}, nz = {cells} }}\n\
             supports = [{{ boundary = \"x-\", component = \"x\" }}, \
             {{ boundary = \"y-\", component = \"y\" }}, {top}]\n\n",
            z[0], z[1]
        )
    };
    format!(
        "name = \"scale\"\ndimension = 3\n\n[materials.steel]\nyoung = 2.1e5\npoisson = 0.3\n\n{}{}\
         [[contact]]\nbodies = [\"upper\", \"lower\"]\nboundaries = [\"z-\", \"z+\"]\n\
         penalty = {{ theta = 1e-7 }}\n",
        box_body("lower", [0.0, 1.0], n, "{ boundary = \"z-\", component = \"z\" }"),
        box_body(
            "upper",
            [1.0, 2.0],
            n - 1,
            "{ boundary = \"z+\", component = \"z\", value = -0.001 }"
        ),
    )
}

fn model(n: usize) -> Result<SolidModel, Box<dyn std::error::Error>> {
    let file = std::env::temp_dir().join(format!("scale-space-{}.toml", std::process::id()));
    std::fs::write(&file, problem(n))?;
    let model = load_solid_file(&file);
    let _ = std::fs::remove_file(&file);
    Ok(model?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mode = std::env::args().nth(1).unwrap_or_else(|| "dd".into());
    let n: usize = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(45);
    let model = model(n)?;
    let dofs: Vec<usize> = model
        .bodies
        .iter()
        .map(|b| 3 * b.mesh.num_nodes())
        .collect();
    println!("{mode}: N = {n}, DOFs per body {dofs:?}");
    let t = Instant::now();
    match mode.as_str() {
        "dd" => {
            let outcome = run_solid(&model, SolidSolver::Decomposition)?;
            for (phase, s) in &outcome.solution.timings {
                println!("  {phase:45} {s:8.2} s");
            }
            println!(
                "  converged {} in {} Newton steps",
                outcome.converged, outcome.solution.newton_steps
            );
        }
        "bodies" => {
            use rayon::prelude::*;
            let factor_values = (model.bodies.par_iter())
                .map(|b| {
                    let body =
                        SolidBody::new(&b.name, b.mesh.clone(), b.material, &constraints_of(b))
                            .map_err(|e| e.to_string())?;
                    body.solve(&b.load).map_err(|e| e.to_string())?;
                    Ok(body.factored().factor_len())
                })
                .collect::<Result<Vec<usize>, String>>()?;
            let bytes: usize = factor_values.iter().map(|v| 8 * v).sum();
            println!(
                "  factor values {factor_values:?}: {:.2} GB in all",
                bytes as f64 / 1e9
            );
        }
        other => return Err(format!("mode '{other}': use dd or bodies").into()),
    }
    println!("  wall time {:.2} s", t.elapsed().as_secs_f64());
    Ok(())
}

/// The supports of a resolved body as the core's constraints.
fn constraints_of(
    b: &contactdd::io::solid_setup::SolidBodyModel,
) -> contactdd::fem::supports::Constraints {
    let mut cons = contactdd::fem::supports::Constraints::for_dofs(3 * b.mesh.num_nodes());
    for &(d, v) in &b.prescribed {
        cons.prescribe(d, v);
    }
    cons
}
