//! The plain-faer baseline the core is compared against: the same 1e6-DOF structured P1 square,
//! factorised with faer's high-level sparse Cholesky (`SymbolicLlt` + `Llt`) on the full matrix
//! with the supported DOFs replaced by identity rows. Prints symbolic, numeric and solve times.
//!
//! Run: `cargo run --release --example faer_baseline [-- N]`.

use std::time::Instant;

use contactdd_core::assembly::Pattern;
use contactdd_core::{Diagonal, Material, Order, Plane, Rectangle};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::SparseColMat;
use faer::{Mat, Side};

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
    let k = Pattern::new(&mesh).stiffness(&mesh, &d);
    // Identity rows/columns on the left edge (x = 0) instead of elimination.
    let fixed: Vec<bool> = (0..k.ncols())
        .map(|dof| mesh.nodes()[dof / 2][0] == 0.0)
        .collect();
    let (cp, ri) = (k.symbolic().col_ptr(), k.symbolic().row_idx());
    let mut val = k.val().to_vec();
    for j in 0..k.ncols() {
        for p in cp[j]..cp[j + 1] {
            if fixed[j] || fixed[ri[p]] {
                val[p] = if ri[p] == j { 1.0 } else { 0.0 };
            }
        }
    }
    let a = SparseColMat::new(k.symbolic().to_owned()?, val);
    println!("{} DOFs", a.ncols());
    let t = Instant::now();
    let symbolic = SymbolicLlt::try_new(a.symbolic(), Side::Lower)?;
    println!("symbolic: {:.3} s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let llt = Llt::try_new_with_symbolic(symbolic, a.as_ref(), Side::Lower)?;
    println!("numeric:  {:.3} s", t.elapsed().as_secs_f64());
    let mut rhs = Mat::<f64>::from_fn(a.ncols(), 1, |i, _| if fixed[i] { 0.0 } else { 1e-6 });
    let t = Instant::now();
    faer::linalg::solvers::SolveCore::solve_in_place_with_conj(&llt, faer::Conj::No, rhs.as_mut());
    println!("solve:    {:.3} s", t.elapsed().as_secs_f64());
    Ok(())
}
