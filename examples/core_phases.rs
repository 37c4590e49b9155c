//! One-shot timing of the finite element core phases on a structured P1 square (compare with the
//! criterion bench `core`, which repeats them): assembly, symbolic, numeric, solve.
//! Peak memory: run under `/usr/bin/time -v`.
//!
//! Run: `cargo run --release --example core_phases [-- N]` (N × N cells, default 706: ≈ 1e6 DOFs).

use std::time::Instant;

use contactdd_core::assembly::Pattern;
use contactdd_core::factor::FactoredBody;
use contactdd_core::loads::load_vector;
use contactdd_core::{Component, Constraints, Diagonal, Load, Material, Order, Plane, Rectangle};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(706);
    faer::set_global_parallelism(faer::Par::rayon(0));
    let mesh = Rectangle {
        origin: [0.0, 0.0],
        corner: [1.0, 1.0],
        nx: n,
        ny: n,
        diagonal: Diagonal::Right,
        mirror: false,
        order: Order::P1,
    }
    .mesh()?;
    let d = Material::new(1.0, 0.3)?.elasticity(Plane::Strain);
    let mut constraints = Constraints::new(mesh.num_nodes());
    constraints.fix(&mesh, "left", Component::Both, 0.0)?;
    let load = load_vector(
        &mesh,
        &[Load::Pressure {
            boundary: "right".into(),
            value: 1.0,
        }],
    )?;
    println!("{} DOFs", 2 * mesh.num_nodes());
    let t = Instant::now();
    let k = Pattern::new(&mesh).stiffness(&mesh, &d);
    println!("assembly: {:.3} s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let mut op = FactoredBody::new("square", k, &constraints, &[])?;
    println!("symbolic: {:.3} s", t.elapsed().as_secs_f64());
    op.set_parallelism(faer::Par::rayon(0));
    let t = Instant::now();
    op.factorize(&[])?;
    println!("numeric:  {:.3} s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let u = op.solve(&load)?;
    println!(
        "solve:    {:.3} s (max |u| = {:.4e})",
        t.elapsed().as_secs_f64(),
        u.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    );
    Ok(())
}
