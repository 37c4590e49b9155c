//! The symmetric form of the interface Newton step (`docs/sparse-path.md`, "The symmetric
//! step").
//!
//! With every body on the sparse path, write y = D₀δ for the step's load on the bodies. The rows
//! of J δ = −R read y = (D₀ − P) δU − D₀R, where P holds the closed points' springs:
//! - a closed carrier j of a balanced pair, with gap row a_j (1 on itself, then its partner
//!   coefficients) and spring k_j = w_j/θ_j, loads the unknowns along a_j: k_j a_j a_jᵀ;
//! - a closed own-side point j loads its own unknown only: D₀_j e_j a_jᵀ.
//!
//! The bodies answer K₀ δu = N y and δU = Nᵀδu, so eliminating y leaves
//!   (K + N P Nᵀ) δu = −N D₀ R,   δ = δU − D₀⁻¹ P δU − R,
//! with K = K₀ − N D₀ Nᵀ the bodies' own stiffness: the penalty problem's own Newton matrix.
//! Where P is symmetric (every balanced pair; an own-side pair whose two sides match and are
//! closed alike) it is positive definite on the motions the closed points and supports hold,
//! and its sparse Cholesky factor costs about what the bodies' own factors cost together, much
//! less than the LU of the unsymmetric coupled system. The pattern holds every partnered
//! point's springs, zero where open, so its analysis is done once per solve.
//!
//! Rigid motions that no closed point holds (the kernel Z of J) leave K + N P Nᵀ singular. The
//! bordered system's multipliers μ make the load consistent, Zᵀ D₀ (R + Zμ) = 0; a spring at one
//! pinned point per kernel vector (the LU path's pins) then picks the solution with δU = 0 there,
//! and the step is projected onto Zᵀδ = 0 as on the LU path. Refinement against the true J
//! follows, as on the LU path.

use contactdd_core::incremental_cholesky::IncrementalCholesky;
use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};
use faer::Mat;
use nalgebra::{DMatrix, DVector};

use super::algebra::{dot, norm, pin_points};
use super::linear::MAX_REFINE;
use super::system::System;
use crate::contact::Role;
use crate::shared_rows::stiffness_columns;

/// The n × n lower triangle holding the entries `stiffness` emits (column by column, rows
/// ascending) with the springs' positions added as zeros where the stiffness has none: one merge
/// in column order, no sort. `None` if the stiffness's entries come out of order or leave the
/// matrix.
fn with_springs(
    n: usize,
    stiffness: impl FnOnce(&mut dyn FnMut(usize, usize, f64)),
    springs: &[Triplet<usize, usize, f64>],
) -> Option<SparseColMat<usize, f64>> {
    let mut extra: Vec<(usize, usize)> = springs.iter().map(|t| (t.col, t.row)).collect();
    extra.sort_unstable();
    extra.dedup();
    let mut extra = extra.into_iter().peekable();
    let (mut col_ptr, mut rows, mut values) = (vec![0], Vec::new(), Vec::new());
    let mut last = None;
    let mut push = |(c, r): (usize, usize), v: f64| {
        if last.is_some_and(|l| l >= (c, r)) || c >= n || r >= n {
            return false;
        }
        last = Some((c, r));
        while col_ptr.len() <= c {
            col_ptr.push(rows.len());
        }
        rows.push(r);
        values.push(v);
        true
    };
    let mut ordered = true;
    stiffness(&mut |r, c, v| {
        while let Some(e) = extra.next_if(|&e| e < (c, r)) {
            ordered &= push(e, 0.0);
        }
        extra.next_if_eq(&(c, r));
        ordered &= push((c, r), v);
    });
    for e in extra {
        ordered &= push(e, 0.0);
    }
    if !ordered {
        return None;
    }
    col_ptr.resize(n + 1, rows.len());
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
    Some(SparseColMat::new(pattern, values))
}

/// Relative asymmetry of P below which the symmetric step takes its lower triangle (the two
/// sides of a matching pair interpolate each other with coefficients equal up to round-off).
const SYMMETRY_TOL: f64 = 1e-12;
/// The smallest relative residual of J δ = −R that refinement aims for: the step's round-off.
const STEP_TOL: f64 = 1e-13;
/// Relative residual of J δ = −R above which the symmetric step, after refinement, is not
/// trusted and the LU path takes the step.
const ACCEPT_TOL: f64 = 1e-8;

/// The symmetric step's matrix, analysis and factor, kept between steps.
#[derive(Default)]
pub(super) struct PrimalCache {
    /// The pattern of K + N P Nᵀ with the bodies' stiffness as values (the springs zero): built
    /// and analysed at the first step, since only the springs change.
    stiffness: Option<SparseColMat<usize, f64>>,
    /// Its factor: a step recomputes only the supernodes that the changed springs reach.
    factor: Option<IncrementalCholesky>,
    values: Vec<f64>,
}

impl PrimalCache {
    /// Factorises the bodies' stiffness (`stiffness` emits its lower triangle column by column,
    /// called at the first step only) plus the `springs` (lower-triangle entries of N P Nᵀ, the
    /// same positions at every step); false if the sum is not positive definite, memory fails or
    /// the entries come out of order.
    fn factor(
        &mut self,
        stiffness: impl FnOnce(&mut dyn FnMut(usize, usize, f64)),
        springs: &[Triplet<usize, usize, f64>],
        n: usize,
    ) -> bool {
        if self.stiffness.is_none() {
            let Some(a) = with_springs(n, stiffness, springs) else {
                return false;
            };
            self.factor = IncrementalCholesky::analyse(a.symbolic());
            self.stiffness = Some(a);
        }
        let (Some(a), Some(factor)) = (&self.stiffness, &mut self.factor) else {
            return false;
        };
        self.values.clear();
        self.values.extend_from_slice(a.val());
        let (col_ptr, row_idx) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        for t in springs {
            let rows = &row_idx[col_ptr[t.col]..col_ptr[t.col + 1]];
            match rows.binary_search(&t.row) {
                Ok(p) => self.values[col_ptr[t.col] + p] += t.val,
                Err(_) => return false,
            }
        }
        factor.factorize(&self.values).is_ok()
    }

    /// Solves in place with the last factor.
    fn solve(&self, rhs: &mut [f64]) -> Option<()> {
        self.factor.as_ref()?.solve_in_place(rhs)
    }
}

impl System<'_> {
    /// True if every body is on the sparse path (the symmetric form needs their stiffness).
    pub(super) fn every_body_sparse(&self) -> bool {
        self.parts.iter().all(|p| p.sparse_free().is_some())
    }

    /// P for the closed set `chi` as merged (row, column, value) entries in row-major order, with
    /// zeros where a point is open (the pattern stays); `None` if P is not symmetric. A point
    /// without weight drops its row, as its row of J does.
    pub(super) fn springs(&self, chi: &[bool]) -> Option<Vec<(usize, usize, f64)>> {
        let mut p = Vec::new();
        for (j, point) in self.interface.points.iter().enumerate() {
            if self.weightless[j] || !point.has_partner() {
                continue;
            }
            let row = std::iter::once((j, 1.0)).chain(point.partner.iter().copied());
            match point.role {
                Role::Carrier => {
                    let k = if chi[j] {
                        point.weight / point.theta
                    } else {
                        0.0
                    };
                    for (q, cq) in row.clone() {
                        p.extend(row.clone().map(|(s, cs)| (q, s, k * cq * cs)));
                    }
                }
                Role::OwnSide => {
                    let k = if chi[j] { self.d0[j] } else { 0.0 };
                    p.extend(row.map(|(s, c)| (j, s, k * c)));
                }
                Role::Follower | Role::Tangent => {}
            }
        }
        p.retain(|&(q, _, _)| !self.weightless[q]);
        p.sort_by_key(|&(q, s, _)| (q, s));
        let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(p.len());
        for (q, s, v) in p {
            match merged.last_mut() {
                Some(last) if (last.0, last.1) == (q, s) => last.2 += v,
                _ => merged.push((q, s, v)),
            }
        }
        let find = |q: usize, s: usize| {
            merged
                .binary_search_by_key(&(q, s), |&(a, b, _)| (a, b))
                .map_or(0.0, |i| merged[i].2)
        };
        let symmetric = merged.iter().all(|&(q, s, v)| {
            let w = find(s, q);
            (v - w).abs() <= SYMMETRY_TOL * v.abs().max(w.abs())
        });
        symmetric.then_some(merged)
    }

    /// The Newton step by the symmetric form, with refinement against the true J; `None` where
    /// it does not apply (P not symmetric, the factorisation or the refinement fails): the LU
    /// path then takes the step.
    pub(super) fn symmetric_step(
        &self,
        cache: &mut PrimalCache,
        applied: &mut Option<(Vec<f64>, Vec<f64>)>,
        chi: &[bool],
        z: &[Vec<f64>],
        r: &[f64],
        accuracy: f64,
    ) -> Option<Vec<f64>> {
        let springs = self.springs(chi)?;
        let base = self.sparse_offset.iter().flatten().min().copied()?;
        let mut n = 0;
        for (b, part) in self.parts.iter().enumerate() {
            n = n.max(self.sparse_offset[b]? - base + part.sparse_free()?);
        }
        // Sparse bodies' offsets increase with the body, so their columns come in order.
        let stiffness = |f: &mut dyn FnMut(usize, usize, f64)| {
            for (b, part) in self.parts.iter().enumerate() {
                if let Some(offset) = self.sparse_offset[b] {
                    stiffness_columns(part, self.bodies[b].as_ref(), offset - base, f);
                }
            }
        };
        let pins = pin_points(z);
        let pinned = pins.iter().map(|&p| (p, p, self.d0[p]));
        let mut trip = Vec::new();
        for (q, s, v) in springs.iter().copied().chain(pinned) {
            let ((oq, dq), (os, ds)) = (self.sparse_dofs(q)?, self.sparse_dofs(s)?);
            for &(rq, nq) in dq {
                for &(rs, ns) in ds {
                    let (row, col) = (oq - base + rq, os - base + rs);
                    if row >= col {
                        trip.push(Triplet::new(row, col, v * nq * ns));
                    }
                }
            }
        }
        if !cache.factor(stiffness, &trip, n) {
            return None;
        }
        let cache = &*cache;
        let solve = |r: &[f64]| self.symmetric_solve(cache, &springs, z, (base, n), r);
        let mut x = solve(r)?;
        let m = self.len();
        // Refinement while each pass halves the residual (as on the LU path).
        let mut last = f64::INFINITY;
        for _ in 0..=MAX_REFINE {
            let res = self.bordered_residual(applied, (chi, &[], &[]), z, None, r, &x)?;
            let size = res.norm_l2();
            if size.is_nan() || size >= 0.5 * last || size <= accuracy.max(STEP_TOL * norm(r)) {
                last = last.min(size);
                break;
            }
            last = size;
            // J e + Z ν = res is the step for the residual −res.
            let minus: Vec<f64> = (0..m).map(|i| -res[(i, 0)]).collect();
            x += solve(&minus)?;
        }
        (last <= ACCEPT_TOL * norm(r)).then(|| (0..m).map(|i| x[(i, 0)]).collect())
    }

    /// [δ; μ] from the factor of K + N P Nᵀ (+ the pins' springs) for the residual `r`; the
    /// bodies' unknowns are the columns `base..base + n` of the LU's numbering.
    fn symmetric_solve(
        &self,
        cache: &PrimalCache,
        springs: &[(usize, usize, f64)],
        z: &[Vec<f64>],
        (base, n): (usize, usize),
        r: &[f64],
    ) -> Option<Mat<f64>> {
        let m = self.len();
        let mu = self.consistent_multipliers(z, r)?;
        let load: Vec<f64> = (0..m)
            .map(|q| r[q] + z.iter().zip(&mu).map(|(zq, mu)| zq[q] * mu).sum::<f64>())
            .collect();
        let mut u = vec![0.0; n];
        for q in (0..m).filter(|&q| !self.weightless[q]) {
            let (offset, dofs) = self.sparse_dofs(q)?;
            for &(d, nq) in dofs {
                u[offset - base + d] -= nq * self.d0[q] * load[q];
            }
        }
        cache.solve(&mut u)?;
        let mut du = vec![0.0; m];
        for (q, v) in du.iter_mut().enumerate() {
            let (offset, dofs) = self.sparse_dofs(q)?;
            *v = dofs.iter().map(|&(d, nq)| nq * u[offset - base + d]).sum();
        }
        let mut pdu = vec![0.0; m];
        for &(q, s, v) in springs {
            pdu[q] += v * du[s];
        }
        let mut delta: Vec<f64> = (0..m)
            .map(|q| {
                if self.weightless[q] {
                    -load[q]
                } else {
                    du[q] - pdu[q] / self.d0[q] - load[q]
                }
            })
            .collect();
        for e in z {
            let d = dot(e, &delta);
            delta.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
        }
        let x = Mat::from_fn(
            m + z.len(),
            1,
            |i, _| {
                if i < m {
                    delta[i]
                } else {
                    mu[i - m]
                }
            },
        );
        x.norm_l2().is_finite().then_some(x)
    }

    /// The bordered system's multipliers μ for the residual `r`: the load R + Zμ does no work
    /// along the kernel's motions, Zᵀ D₀ (R + Zμ) = 0.
    fn consistent_multipliers(&self, z: &[Vec<f64>], r: &[f64]) -> Option<Vec<f64>> {
        if z.is_empty() {
            return Some(Vec::new());
        }
        let weighted = |a: &[f64], b: &[f64]| -> f64 {
            a.iter()
                .zip(b)
                .zip(&self.d0)
                .map(|((x, y), d)| x * d * y)
                .sum()
        };
        let k = z.len();
        let gram = DMatrix::from_fn(k, k, |a, b| weighted(&z[a], &z[b]));
        let rhs = DVector::from_fn(k, |a, _| -weighted(&z[a], r));
        let mu = gram.lu().solve(&rhs)?;
        Some(mu.iter().copied().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lower-triangle entries (row, col, value) emitted in the order given.
    fn emit(
        entries: &[(usize, usize, f64)],
    ) -> impl FnOnce(&mut dyn FnMut(usize, usize, f64)) + '_ {
        move |f: &mut dyn FnMut(usize, usize, f64)| entries.iter().for_each(|&(r, c, v)| f(r, c, v))
    }

    #[test]
    fn springs_merge_into_the_stiffness_pattern_as_faer_sums_triplets() {
        // A 5 × 5 lower triangle with an empty column (3) and springs inside and outside it.
        let k = [
            (0, 0, 4.0),
            (2, 0, -1.0),
            (1, 1, 3.0),
            (4, 1, 0.5),
            (2, 2, 5.0),
            (3, 3, 1.0),
            (4, 4, 2.0),
        ];
        let springs: Vec<_> = [(2, 0), (3, 0), (3, 1), (4, 3), (3, 0)]
            .into_iter()
            .map(|(r, c)| Triplet::new(r, c, 7.0))
            .collect();
        let a = with_springs(5, emit(&k), &springs).unwrap();
        let mut trip: Vec<_> = k.iter().map(|&(r, c, v)| Triplet::new(r, c, v)).collect();
        trip.extend(springs.iter().map(|t| Triplet::new(t.row, t.col, 0.0)));
        let b = SparseColMat::<usize, f64>::try_new_from_triplets(5, 5, &trip).unwrap();
        assert_eq!(a.symbolic().col_ptr(), b.symbolic().col_ptr());
        assert_eq!(a.symbolic().row_idx(), b.symbolic().row_idx());
        assert_eq!(a.val(), b.val());
    }

    #[test]
    fn stiffness_out_of_order_is_refused() {
        let k = [(1, 1, 1.0), (0, 0, 1.0)];
        assert!(with_springs(2, emit(&k), &[]).is_none());
        let k = [(0, 0, 1.0), (2, 0, 1.0)];
        assert!(with_springs(2, emit(&k), &[]).is_none());
    }
}
