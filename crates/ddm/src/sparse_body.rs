//! The sparse path of a condensed body: the operations of the iteration done with the body's
//! sparse factor alone, never forming the dense m × m blocks (`docs/sparse-path.md`).
//!
//! The body keeps the Cholesky factor of K₀ = K + N D₀ Nᵀ in a fill-reducing order (no dense
//! trailing block) and the columns of N as (reduced DOF, normal component) lists. Then
//! - C₀ v = Nᵀ K₀⁻¹ N v costs one sparse forward/backward solve;
//! - the Robin problem (K + N D Nᵀ) ũ = f + N r is solved directly: its matrix has the pattern of
//!   K₀, so a change of φ costs one numeric refactorisation with the kept symbolic analysis, into a
//!   second set of factor values, and every sweep one solve;
//! - the interface Newton step couples the bodies' sparse matrices instead of their dense B blocks
//!   ([`SparseContact::push_body_rows`]).

use faer::sparse::Triplet;

use contactdd_core::rigid::Holding;
use contactdd_core::{dof, BodyError, ElasticBody, FactorValues, FactoredBody, Vector, DIM};

use crate::error::Singular;

/// Relative residual at which the conjugate gradients of [`SparseContact::initial_load`] stop.
const CG_TOL: f64 = 1e-12;
/// Conjugate gradient steps at most. C₀ is badly conditioned on fine meshes (its eigenvalues
/// run from 1/D₀ down to the inverse stiffness of a node), so the starting load is only
/// approximate; the iteration starts from the state it reproduces exactly
/// ([`crate::condensed::CondensedBody::initial_state`]).
const CG_MAX: usize = 30;

/// A body's contact points in the reduced numbering of its sparse factor.
pub struct SparseContact {
    /// Per contact point, its reduced unknowns carrying a normal component: (reduced index,
    /// Σ n_c × coefficient), one entry per unknown (a node on an inclined support has one).
    dofs: Vec<Vec<(usize, f64)>>,
    /// Per contact point, n_j · (prescribed displacement of its node), at load factor 1.
    fixed: Vec<f64>,
    /// The reduced right-hand side of the body's load and prescribed values at load factor 1.
    rhs0: Vec<f64>,
    /// What holds the body (supports and contact springs): a Robin matrix whose springs leave a
    /// rigid motion free is singular, which its factorisation need not show.
    holding: Holding,
}

/// The reduced unknowns of node `v`'s normal displacement n·u and their coefficients, the terms of
/// one unknown merged (both DOFs of a node on an inclined support share one).
fn point_terms(op: &FactoredBody, v: usize, n: Vector) -> Vec<(usize, f64)> {
    let mut terms: Vec<(usize, f64)> = Vec::with_capacity(DIM);
    for c in (0..DIM).filter(|&c| n[c] != 0.0) {
        if let Some((r, k)) = op.reduced_index(dof(v, c)) {
            match terms.iter_mut().find(|t| t.0 == r) {
                Some(t) => t.1 += n[c] * k,
                None => terms.push((r, n[c] * k)),
            }
        }
    }
    terms
}

/// The Robin factor of the last φ on the sparse path.
#[derive(Default)]
pub struct RobinFactor {
    phi: Vec<f64>,
    values: FactorValues,
    ok: bool,
}

impl SparseContact {
    /// Maps the contact points (`nodes`, `normals`) of `body` to the reduced numbering of its
    /// factor `op`.
    pub fn new(op: &FactoredBody, body: &ElasticBody, nodes: &[usize], normals: &[Vector]) -> Self {
        let springs: Vec<(usize, Vector)> = nodes.iter().copied().zip(normals.to_vec()).collect();
        let load = &body.load;
        let dofs = nodes
            .iter()
            .zip(normals)
            .map(|(&v, n)| point_terms(op, v, *n))
            .collect();
        let fixed = nodes
            .iter()
            .zip(normals)
            .map(|(&v, n)| {
                (0..DIM)
                    .map(|c| n[c] * op.prescribed_value(dof(v, c)))
                    .sum()
            })
            .collect();
        SparseContact {
            dofs,
            fixed,
            rhs0: op.reduced_load(load),
            holding: Holding::new(&body.mesh, &body.constraints, &springs),
        }
    }

    /// The free DOFs of contact point `j` with their normal components.
    pub fn point_dofs(&self, j: usize) -> &[(usize, f64)] {
        &self.dofs[j]
    }

    /// Adds N v to the reduced vector `out`.
    fn spread(&self, v: &[f64], out: &mut [f64]) {
        for (d, &x) in self.dofs.iter().zip(v) {
            for &(r, n) in d {
                out[r] += n * x;
            }
        }
    }

    /// Nᵀ u of the reduced vector `u` (the free part of the normal displacements).
    fn gather(&self, u: &[f64]) -> Vec<f64> {
        self.dofs
            .iter()
            .map(|d| d.iter().map(|&(r, n)| n * u[r]).sum())
            .collect()
    }

    /// C₀ v = Nᵀ K₀⁻¹ N v: one sparse solve.
    pub fn apply_c0(&self, op: &FactoredBody, v: &[f64]) -> Result<Vec<f64>, BodyError> {
        let mut u = vec![0.0; op.num_free()];
        self.spread(v, &mut u);
        op.solve_reduced_in_place(&mut u)?;
        Ok(self.gather(&u))
    }

    /// Solves the Robin problem (K + N D Nᵀ) ũ = λf + g + N r, D = diag(φ_j D₀_j), at load factor
    /// λ = `factor` with `extra` the reduced load g of the other load groups (empty: none); writes ũ_n to `un` and t = r + (1 − φ) D₀ ũ_n to `t` (as the dense path).
    #[allow(clippy::too_many_arguments)]
    pub fn robin_solve(
        &self,
        op: &FactoredBody,
        (nodes, normals, d0): (&[usize], &[Vector], &[f64]),
        (factor, extra): (f64, &[f64]),
        phi: &[f64],
        r: &[f64],
        cache: &mut RobinFactor,
        (un, t): (&mut [f64], &mut [f64]),
    ) -> Result<(), Singular> {
        if !cache.ok || cache.phi.as_slice() != phi {
            cache.phi = phi.to_vec();
            let springs: Vec<f64> = phi.iter().zip(d0).map(|(p, d)| p * d).collect();
            let held = self.holding.free(|j| springs[j] > 0.0).is_empty();
            cache.ok = held
                && op
                    .refactorize(
                        &spring_additions(nodes, normals, &springs),
                        &mut cache.values,
                    )
                    .is_ok();
        }
        if !cache.ok {
            return Err(Singular);
        }
        let mut u: Vec<f64> = self.rhs0.iter().map(|v| factor * v).collect();
        if !extra.is_empty() {
            u.iter_mut().zip(extra).for_each(|(u, g)| *u += g);
        }
        self.spread(r, &mut u);
        op.solve_reduced_with(&cache.values, &mut u)
            .map_err(|_| Singular)?;
        let free = self.gather(&u);
        for j in 0..un.len() {
            un[j] = free[j] + factor * self.fixed[j];
            t[j] = r[j] + (1.0 - phi[j]) * d0[j] * un[j];
        }
        if un.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Singular)
        }
    }

    /// An interface load T⁰ with C₀ T⁰ ≈ `rhs` by at most `CG_MAX` conjugate gradient steps (C₀
    /// is SPD), one sparse solve per step; T⁰ = 0 if they break down.
    pub fn initial_load(&self, op: &FactoredBody, rhs: &[f64]) -> Vec<f64> {
        let m = rhs.len();
        let zero = vec![0.0; m];
        let norm_b = dot(rhs, rhs).sqrt();
        if norm_b == 0.0 {
            return zero;
        }
        let (mut x, mut res, mut p) = (zero.clone(), rhs.to_vec(), rhs.to_vec());
        let mut rr = dot(&res, &res);
        for _ in 0..CG_MAX {
            let Ok(q) = self.apply_c0(op, &p) else {
                return zero;
            };
            let alpha = rr / dot(&p, &q);
            if !alpha.is_finite() {
                return zero;
            }
            x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
            res.iter_mut().zip(&q).for_each(|(r, q)| *r -= alpha * q);
            let next = dot(&res, &res);
            if next.sqrt() <= CG_TOL * norm_b {
                break;
            }
            let beta = next / rr;
            rr = next;
            p.iter_mut().zip(&res).for_each(|(p, r)| *p = r + beta * *p);
        }
        if x.iter().all(|v| v.is_finite()) {
            x
        } else {
            zero
        }
    }

    /// A local estimate of ρ_j = 1 − B_jj, the body's share in the stiffness of point j with its
    /// spring: 1 − D₀_j / (n_jᵀ K₀,jj n_j) from the node's diagonal block of K₀. The interface
    /// Newton method only uses ρ as the scale of its complementarity rule (any ρ > 0 has the same
    /// solution), so the exact diagonal of B, which would take m solves, is not needed.
    pub fn share_estimate(&self, op: &FactoredBody, d0: &[f64]) -> Vec<f64> {
        let k0 = op.reduced_lower();
        let entry = |a: usize, b: usize| {
            let (row, col) = (a.max(b), a.min(b));
            let rows = k0.symbolic().row_idx_of_col_raw(col);
            let start = k0.symbolic().col_ptr()[col];
            rows.binary_search(&row)
                .map_or(0.0, |p| k0.val()[start + p])
        };
        self.dofs
            .iter()
            .zip(d0)
            .map(|(d, &spring)| {
                let k: f64 = d
                    .iter()
                    .flat_map(|&(a, na)| d.iter().map(move |&(b, nb)| (a, na, b, nb)))
                    .map(|(a, na, b, nb)| na * nb * entry(a, b))
                    .sum();
                if k > 0.0 {
                    (1.0 - spring / k).clamp(1e-8, 1.0)
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// Pushes the rows of K₀ δu − N D₀ δτ = 0 (δU = Bδτ without B) into the Newton system: the
    /// body's reduced unknowns are the columns `offset..`, its points' δτ the columns `start..`.
    /// The rows are scaled by 1/max diag K₀ so that they weigh like the interface rows.
    pub fn push_body_rows(
        &self,
        op: &FactoredBody,
        d0: &[f64],
        (offset, start): (usize, usize),
        trip: &mut Vec<Triplet<usize, usize, f64>>,
    ) {
        let k0 = op.reduced_lower();
        let (col_ptr, row_idx, val) = (k0.symbolic().col_ptr(), k0.symbolic().row_idx(), k0.val());
        let mut scale = 0.0f64;
        for col in 0..k0.ncols() {
            for p in col_ptr[col]..col_ptr[col + 1] {
                if row_idx[p] == col {
                    scale = scale.max(val[p].abs());
                }
            }
        }
        let scale = if scale > 0.0 { 1.0 / scale } else { 1.0 };
        for col in 0..k0.ncols() {
            for p in col_ptr[col]..col_ptr[col + 1] {
                let (row, v) = (row_idx[p], scale * val[p]);
                trip.push(Triplet::new(offset + row, offset + col, v));
                if row != col {
                    trip.push(Triplet::new(offset + col, offset + row, v));
                }
            }
        }
        for (j, (d, &spring)) in self.dofs.iter().zip(d0).enumerate() {
            for &(r, n) in d {
                trip.push(Triplet::new(offset + r, start + j, -scale * n * spring));
            }
        }
    }
}

/// The spring entries N diag(`springs`) Nᵀ on the contact nodes, as symmetric additions (lower
/// triangle) to the stiffness.
pub fn spring_additions(
    nodes: &[usize],
    normals: &[Vector],
    springs: &[f64],
) -> Vec<(usize, usize, f64)> {
    let mut additions = Vec::with_capacity(DIM * DIM * nodes.len());
    for ((&v, n), &k) in nodes.iter().zip(normals).zip(springs) {
        let (x, y) = (dof(v, 0), dof(v, 1));
        additions.push((x, x, k * n[0] * n[0]));
        additions.push((y, y, k * n[1] * n[1]));
        additions.push((y, x, k * n[0] * n[1]));
    }
    additions
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
