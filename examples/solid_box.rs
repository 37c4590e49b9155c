//! One-shot timing of the 3D layer (`contactdd_core::solid`) on a P1 and a P2 box of about 3e5
//! DOFs each: mesh, sparsity pattern, assembly, symbolic analysis (supports eliminated, AMD
//! ordering), numeric Cholesky factorisation and solve, with the factor's size and the memory the
//! numeric factorisation allocates. The box rests on rollers on `x-`, `y-` and `z-` (u_x, u_y,
//! u_z = 0 there) and is pulled by a uniform traction σ on `z+`: the solution is the uniaxial
//! u = (−νσx, −νσy, σz)/E, which the example checks at every node to 1e-8 of its size.
//!
//! Run: `cargo run --release --example solid_box [-- P1_CELLS P2_CELLS]` (cubes per side of a unit
//! cube; defaults 45 and 23: 291 948 and 311 469 DOFs).

use std::time::Instant;

use contactdd_core::solid::assembly::add_face_traction;
use contactdd_core::solid::supports::{constraints, fix};
use contactdd_core::solid::{dof, num_dofs, Axis, BoxMesh, SolidBody, TetOrder};
use contactdd_core::Material;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: usize| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(default)
    };
    faer::set_global_parallelism(faer::Par::rayon(0));
    println!("threads: {}", rayon::current_num_threads());
    for (order, cells) in [(TetOrder::P1, arg(1, 45)), (TetOrder::P2, arg(2, 23))] {
        run(order, cells)?;
    }
    Ok(())
}

/// Builds, factorises and solves one box, printing the phase times.
fn run(order: TetOrder, cells: usize) -> Result<(), Box<dyn std::error::Error>> {
    let t = Instant::now();
    let mesh = BoxMesh {
        origin: [0.0; 3],
        size: [1.0; 3],
        cells: [cells; 3],
        order,
    }
    .mesh()?;
    let t_mesh = t.elapsed();
    let ndof = num_dofs(mesh.num_nodes());
    println!(
        "\n{order:?}: {cells}^3 cubes, {} tetrahedra, {} nodes, {ndof} DOFs",
        mesh.num_tets(),
        mesh.num_nodes()
    );
    let (young, poisson, sigma) = (1.0, 0.3, 1e-3);
    let mut cons = constraints(&mesh);
    for (face, axis) in [("x-", Axis::X), ("y-", Axis::Y), ("z-", Axis::Z)] {
        fix(&mut cons, &mesh, face, &[axis], 0.0)?;
    }
    let mut f = vec![0.0; ndof];
    add_face_traction(&mesh, "z+", |_, _| [0.0, 0.0, sigma], &mut f)?;
    let nodes = mesh.nodes().to_vec();
    let body = SolidBody::new("box", mesh, Material::new(young, poisson)?, &cons)?;
    let t = Instant::now();
    let u = body.solve(&f)?;
    let t_solve = t.elapsed();
    let times = body.timings();
    let factored = body.factored();
    println!("  mesh       {:8.3} s", t_mesh.as_secs_f64());
    println!("  pattern    {:8.3} s", times.pattern.as_secs_f64());
    println!("  assembly   {:8.3} s", times.assembly.as_secs_f64());
    println!("  symbolic   {:8.3} s", times.symbolic.as_secs_f64());
    println!("  numeric    {:8.3} s", times.numeric.as_secs_f64());
    println!("  solve      {:8.3} s", t_solve.as_secs_f64());
    println!("  stiffness entries {}", factored.stiffness().val().len());
    println!(
        "  factor values {} ({:.2} GB), numeric factorisation allocates {:.2} GB",
        factored.factor_len(),
        factored.factor_len() as f64 * 8.0 / 1e9,
        factored.memory_estimate() as f64 / 1e9
    );
    let scale = sigma / young;
    let exact = |x: [f64; 3]| [-poisson * x[0], -poisson * x[1], x[2]].map(|v| v * scale);
    let worst = (nodes.iter().enumerate())
        .flat_map(|(v, x)| (0..3).map(move |c| (v, c, exact(*x)[c])))
        .map(|(v, c, e)| (u[dof(v, c)] - e).abs())
        .fold(0.0, f64::max);
    println!(
        "  largest error against the uniaxial solution {:.2e} (relative)",
        worst / scale
    );
    if worst > 1e-8 * scale {
        return Err(format!("error {worst:e} against the uniaxial solution").into());
    }
    Ok(())
}
