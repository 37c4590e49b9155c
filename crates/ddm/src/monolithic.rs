//! A monolithic reference: the same discrete penalty problem as the domain decomposition, solved
//! for all bodies at once by a semismooth Newton (primal–dual active set) method.
//!
//! With the active set χ_j = [d_j − s_j(u) < 0] fixed, the penalty equations
//!   K u − f − Σ_j (w_j/θ_j) χ_j (d_j − s_j(u)) n_j = 0
//! are linear, with the cross-body terms ∂s_j/∂u = n_j at the point's node plus Σ_k c_jk n_k at its
//! partner's nodes. Each Newton step solves that sparse (for non-matching meshes non-symmetric)
//! system with faer's sparse LU and updates χ, starting from "everything closed", until χ no
//! longer changes. The fixed point of the DD iteration solves exactly these equations.
//!
//! Rigid modes: bodies held only by contact can move together without changing any s_j (the
//! benchmark's two bodies translate vertically together). The rigid motions left free by every
//! body's supports are tested against the assembled matrix; those in its kernel are removed by
//! constraining the solution to be orthogonal to them (a bordered system), and reported.

use std::time::Instant;

use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use nalgebra::{DMatrix, SymmetricEigen};

use contactdd_core::rigid::{describe, free_modes, RigidBasis};
use contactdd_core::{component_of, dof, node_of, num_dofs, DIM};

use crate::contact::Interface;
use crate::error::SetupError;
use crate::model::Model;
use crate::solution::{body_results, pair_results, BodyResult, PairResult};

/// The monolithic reference solution.
#[derive(Clone, Debug)]
pub struct MonolithicSolution {
    /// Newton steps taken.
    pub newton_steps: usize,
    /// Rigid modes of the assembled problem that were fixed by a zero-mean constraint.
    pub rigid_modes: Vec<String>,
    /// Per-body fields.
    pub bodies: Vec<BodyResult>,
    /// Per-pair contact results.
    pub contact: Vec<PairResult>,
    /// Normal displacements of all contact points.
    pub un: Vec<f64>,
    /// Wall time, seconds.
    pub seconds: f64,
}

struct Numbering {
    /// Global index of each (body, dof), or None if prescribed.
    index: Vec<Vec<Option<usize>>>,
    n: usize,
}

/// Solves the penalty contact problem monolithically.
pub fn solve_monolithic(model: &Model) -> Result<MonolithicSolution, SetupError> {
    let start = Instant::now();
    let interface = Interface::new(model)?;
    let mut index = Vec::new();
    let mut n = 0;
    for body in &model.bodies {
        let idx: Vec<Option<usize>> = (0..num_dofs(body.mesh.num_nodes()))
            .map(|d| {
                body.constraints.get(d).is_none().then(|| {
                    n += 1;
                    n - 1
                })
            })
            .collect();
        index.push(idx);
    }
    let num = Numbering { index, n };
    let stiffness: Vec<SparseColMat<usize, f64>> =
        model.bodies.iter().map(|b| b.stiffness()).collect();

    // The linear part: K restricted to free DOFs and f − K_fd u_d.
    let mut base = Vec::new();
    let mut rhs0 = vec![0.0; num.n];
    for (b, (body, k)) in model.bodies.iter().zip(&stiffness).enumerate() {
        for (d, &f) in body.load.iter().enumerate() {
            if let Some(i) = num.index[b][d] {
                rhs0[i] += f;
            }
        }
        let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        for j in 0..k.ncols() {
            for p in cp[j]..cp[j + 1] {
                match (
                    num.index[b][ri[p]],
                    num.index[b][j],
                    body.constraints.get(j),
                ) {
                    (Some(r), Some(c), _) => base.push(Triplet::new(r, c, val[p])),
                    (Some(r), None, Some(ud)) => rhs0[r] -= val[p] * ud,
                    _ => {}
                }
            }
        }
    }
    let (modes, names) = rigid_candidates(model, &num);
    let mut chi: Vec<bool> = interface.points.iter().map(|p| p.has_partner()).collect();
    let mut fixed_modes: Option<(Vec<Vec<f64>>, Vec<String>)> = None;
    for step in 1..=100 {
        let (trip, rhs) = contact_terms(model, &interface, &num, &chi, &base, &rhs0);
        let (z, z_names) = match &fixed_modes {
            Some(f) => f.clone(),
            None => {
                let f = kernel_modes(&trip, &modes, &names, num.n);
                fixed_modes = Some(f.clone());
                f
            }
        };
        let u = bordered_solve(trip, &rhs, &z, num.n)?;
        let un = normal_displacements(model, &interface, &num, &u);
        let mut s = vec![0.0; un.len()];
        interface.sum_normal(&un, &mut s);
        let new_chi: Vec<bool> = interface
            .points
            .iter()
            .zip(&s)
            .map(|(p, &s)| p.has_partner() && p.gap - s < 0.0)
            .collect();
        if new_chi == chi {
            let displacements = full_displacements(model, &num, &u);
            return Ok(MonolithicSolution {
                newton_steps: step,
                rigid_modes: z_names,
                bodies: body_results(model, &interface, &un, displacements),
                contact: pair_results(model, &interface, &un),
                un,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        chi = new_chi;
    }
    Err(SetupError::Solver(
        "monolithic semismooth Newton: the active set did not settle in 100 steps".into(),
    ))
}

/// Jacobian triplets and right-hand side for a fixed active set.
fn contact_terms(
    model: &Model,
    interface: &Interface,
    num: &Numbering,
    chi: &[bool],
    base: &[Triplet<usize, usize, f64>],
    rhs0: &[f64],
) -> (Vec<Triplet<usize, usize, f64>>, Vec<f64>) {
    let mut trip = base.to_vec();
    let mut rhs = rhs0.to_vec();
    for (j, p) in interface.points.iter().enumerate() {
        if !chi[j] {
            continue;
        }
        let k = p.weight / p.theta;
        // ∂s_j/∂u as (body, node, normal, coefficient).
        let mut terms = vec![(p.body, p.node, p.normal, 1.0)];
        for &(q, c) in &p.partner {
            let pq = &interface.points[q];
            terms.push((pq.body, pq.node, pq.normal, c));
        }
        for a in 0..DIM {
            let Some(row) = num.index[p.body][dof(p.node, a)] else {
                continue;
            };
            rhs[row] += k * p.gap * p.normal[a];
            for &(b, v, n, c) in &terms {
                for e in 0..DIM {
                    let coef = k * p.normal[a] * c * n[e];
                    match num.index[b][dof(v, e)] {
                        Some(col) => trip.push(Triplet::new(row, col, coef)),
                        None => {
                            let ud = model.bodies[b].constraints.get(dof(v, e)).unwrap_or(0.0);
                            rhs[row] -= coef * ud;
                        }
                    }
                }
            }
        }
    }
    (trip, rhs)
}

/// Per body, the rigid motions its supports leave free (the core's rigid basis), as global
/// vectors.
fn rigid_candidates(model: &Model, num: &Numbering) -> (Vec<Vec<f64>>, Vec<String>) {
    let mut out = Vec::new();
    let mut names = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        let basis = RigidBasis::new(&body.mesh);
        for v in free_modes(&body.mesh, &body.constraints, &[]) {
            let mut z = vec![0.0; num.n];
            for (d, idx) in num.index[b].iter().enumerate() {
                if let Some(i) = idx {
                    z[*i] = basis.motion(body.mesh.nodes()[node_of(d)], &v)[component_of(d)];
                }
            }
            out.push(z);
            names.push(format!("{} of '{}'", describe(&v), body.name));
        }
    }
    (out, names)
}

/// The combinations of candidate rigid motions that the assembled matrix maps to zero.
fn kernel_modes(
    trip: &[Triplet<usize, usize, f64>],
    cands: &[Vec<f64>],
    names: &[String],
    n: usize,
) -> (Vec<Vec<f64>>, Vec<String>) {
    let q = cands.len();
    if q == 0 {
        return (Vec::new(), Vec::new());
    }
    let norms: Vec<f64> = cands
        .iter()
        .map(|z| {
            z.iter()
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt()
                .max(f64::MIN_POSITIVE)
        })
        .collect();
    let mut jz = vec![vec![0.0; n]; q];
    let mut jmax: f64 = 0.0;
    for t in trip {
        jmax = jmax.max(t.val.abs());
        for (k, z) in cands.iter().enumerate() {
            jz[k][t.row] += t.val * z[t.col] / norms[k];
        }
    }
    let gram = DMatrix::from_fn(q, q, |a, b| {
        jz[a].iter().zip(&jz[b]).map(|(x, y)| x * y).sum::<f64>()
            / (jmax * jmax).max(f64::MIN_POSITIVE)
    });
    let eig = SymmetricEigen::new(gram);
    let mut modes = Vec::new();
    let mut labels = Vec::new();
    for k in 0..q {
        if eig.eigenvalues[k] > 1e-16 {
            continue;
        }
        let c = eig.eigenvectors.column(k);
        let mut z = vec![0.0; n];
        for (a, cand) in cands.iter().enumerate() {
            for (zi, ci) in z.iter_mut().zip(cand) {
                *zi += c[a] * ci / norms[a];
            }
        }
        let label = (0..q)
            .filter(|&a| c[a].abs() > 0.1)
            .map(|a| names[a].clone())
            .collect::<Vec<_>>()
            .join(" together with ");
        modes.push(z);
        labels.push(format!("{label} (fixed by a zero-mean constraint)"));
    }
    (modes, labels)
}

/// Solves [[J, Z], [Zᵀ, 0]] [u; λ] = [rhs; 0] with faer's sparse LU.
fn bordered_solve(
    mut trip: Vec<Triplet<usize, usize, f64>>,
    rhs: &[f64],
    z: &[Vec<f64>],
    n: usize,
) -> Result<Vec<f64>, SetupError> {
    for (k, zk) in z.iter().enumerate() {
        for (i, &v) in zk.iter().enumerate() {
            if v != 0.0 {
                trip.push(Triplet::new(i, n + k, v));
                trip.push(Triplet::new(n + k, i, v));
            }
        }
    }
    let size = n + z.len();
    let fail = |what: &str| {
        SetupError::Solver(format!(
            "monolithic solve: {what}; a body held only by contact may have lost all contact"
        ))
    };
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &trip)
        .map_err(|e| fail(&format!("{e:?}")))?;
    let lu = a.sp_lu().map_err(|_| fail("the system is singular"))?;
    let b = Mat::<f64>::from_fn(size, 1, |i, _| if i < n { rhs[i] } else { 0.0 });
    let x = lu.solve(&b);
    let u: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
    if u.iter().any(|v| !v.is_finite()) {
        return Err(fail("non-finite solution"));
    }
    Ok(u)
}

fn full_displacements(model: &Model, num: &Numbering, u: &[f64]) -> Vec<Vec<f64>> {
    model
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            (0..num_dofs(body.mesh.num_nodes()))
                .map(|d| match num.index[b][d] {
                    Some(i) => u[i],
                    None => body.constraints.get(d).unwrap_or(0.0),
                })
                .collect()
        })
        .collect()
}

fn normal_displacements(
    model: &Model,
    interface: &Interface,
    num: &Numbering,
    u: &[f64],
) -> Vec<f64> {
    interface
        .points
        .iter()
        .map(|p| {
            (0..DIM)
                .map(|a| {
                    let d = dof(p.node, a);
                    let v = match num.index[p.body][d] {
                        Some(i) => u[i],
                        None => model.bodies[p.body].constraints.get(d).unwrap_or(0.0),
                    };
                    p.normal[a] * v
                })
                .sum()
        })
        .collect()
}
