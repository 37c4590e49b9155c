//! Phases of the finite element core on structured P1 squares: assembly (pattern + values),
//! symbolic analysis, numeric factorisation and one solve, at about 1e4 and 1e5 DOFs, and 1e6 DOFs
//! when `CONTACTDD_BENCH_LARGE=1` is set.
//!
//! Each phase is also measured for faer's own high-level sparse Cholesky on the same matrix
//! (`faer_symbolic`, `faer_numeric`, `faer_solve`), the baseline the core must stay within 20 % of.
//!
//! Run: `cargo bench --bench core` (add `CONTACTDD_BENCH_LARGE=1` for the 1e6 case).

use contactdd_core::assembly::Pattern;
use contactdd_core::factor::FactoredBody;
use contactdd_core::loads::load_vector;
use contactdd_core::{
    Component, Constraints, Diagonal, Load, Material, Mesh, Order, Plane, Rectangle,
};
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use faer::prelude::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::SparseColMat;
use faer::{Mat, Side};

fn square(n: usize) -> Mesh {
    Rectangle {
        origin: [0.0, 0.0],
        corner: [1.0, 1.0],
        nx: n,
        ny: n,
        diagonal: Diagonal::Right,
        mirror: false,
        order: Order::P1,
    }
    .mesh()
    .expect("valid rectangle")
}

fn sizes() -> Vec<usize> {
    // (n + 1)² nodes × 2 DOFs ≈ 1e4, 1e5, 1e6.
    let mut s = vec![70, 223];
    if std::env::var("CONTACTDD_BENCH_LARGE").is_ok_and(|v| v == "1") {
        s.push(706);
    }
    s
}

/// `k` with the constrained rows and columns replaced by identity rows.
fn identity_rows(
    k: &SparseColMat<usize, f64>,
    constraints: &Constraints,
) -> SparseColMat<usize, f64> {
    let (cp, ri) = (k.symbolic().col_ptr(), k.symbolic().row_idx());
    let mut val = k.val().to_vec();
    for j in 0..k.ncols() {
        for p in cp[j]..cp[j + 1] {
            if constraints.get(j).is_some() || constraints.get(ri[p]).is_some() {
                val[p] = if ri[p] == j { 1.0 } else { 0.0 };
            }
        }
    }
    SparseColMat::new(k.symbolic().to_owned().expect("pattern"), val)
}

fn phases(c: &mut Criterion) {
    faer::set_global_parallelism(faer::Par::rayon(0));
    let material = Material::new(1.0, 0.3).expect("valid material");
    let d = material.elasticity(Plane::Strain);
    for n in sizes() {
        let mesh = square(n);
        let dofs = 2 * mesh.num_nodes();
        let mut group = c.benchmark_group(format!("core/{dofs}dofs"));
        group.sample_size(10);
        let mut constraints = Constraints::new(mesh.num_nodes());
        constraints
            .fix(&mesh, "left", Component::Both, 0.0)
            .expect("boundary");
        let load = load_vector(
            &mesh,
            &[Load::Pressure {
                boundary: "right".into(),
                value: 1.0,
            }],
        )
        .expect("boundary");
        group.bench_function(BenchmarkId::new("assembly", dofs), |b| {
            b.iter(|| Pattern::new(&mesh).stiffness(&mesh, &d))
        });
        let k = Pattern::new(&mesh).stiffness(&mesh, &d);
        // The operator takes the matrix by value: clone it outside the timed part.
        group.bench_function(BenchmarkId::new("symbolic", dofs), |b| {
            b.iter_batched(
                || k.clone(),
                |k| FactoredBody::new("b", k, &constraints, &[]).expect("symbolic"),
                BatchSize::LargeInput,
            )
        });
        let mut op = FactoredBody::new("b", k.clone(), &constraints, &[]).expect("symbolic");
        op.set_parallelism(faer::Par::rayon(0));
        group.bench_function(BenchmarkId::new("numeric", dofs), |b| {
            b.iter(|| op.factorize(&[]).expect("numeric"))
        });
        op.factorize(&[]).expect("numeric");
        group.bench_function(BenchmarkId::new("solve", dofs), |b| {
            b.iter(|| op.solve(&load).expect("solve"))
        });

        // The plain-faer reference on the same matrix: supports as identity rows, faer's
        // high-level SymbolicLlt / Llt, so each phase above has a ratio measured in the same run.
        let plain = identity_rows(&k, &constraints);
        group.bench_function(BenchmarkId::new("faer_symbolic", dofs), |b| {
            b.iter(|| SymbolicLlt::try_new(plain.symbolic(), Side::Lower).expect("symbolic"))
        });
        let symbolic = SymbolicLlt::try_new(plain.symbolic(), Side::Lower).expect("symbolic");
        group.bench_function(BenchmarkId::new("faer_numeric", dofs), |b| {
            b.iter(|| {
                Llt::try_new_with_symbolic(symbolic.clone(), plain.as_ref(), Side::Lower)
                    .expect("numeric")
            })
        });
        let llt =
            Llt::try_new_with_symbolic(symbolic, plain.as_ref(), Side::Lower).expect("numeric");
        let rhs = Mat::<f64>::from_fn(plain.ncols(), 1, |i, _| load[i]);
        group.bench_function(BenchmarkId::new("faer_solve", dofs), |b| {
            b.iter(|| llt.solve(&rhs))
        });
        group.finish();
    }
}

criterion_group!(benches, phases);
criterion_main!(benches);
