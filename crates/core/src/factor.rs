//! The factorised operator of one body: supports eliminated, sparse Cholesky (faer) with the
//! symbolic analysis done once, numeric factorisation into kept buffers, in-place solves.
//!
//! Interface DOFs (the contact nodes' DOFs) can be ordered last. The trailing block `L₂₂` of the
//! Cholesky factor `L` of `P A Pᵀ` is then the Cholesky factor of the Schur complement of `A` on the
//! interface, `S = A₂₂ − A₂₁ A₁₁⁻¹ A₁₂ = L₂₂ L₂₂ᵀ`. This is what lets the domain decomposition
//! iterate on contact quantities only: `(A⁻¹)₂₂ = S⁻¹`, read off the factor at no extra cost.
//! The other DOFs keep their order by approximate minimum degree (AMD) on the nodes
//! ([`crate::ordering::node_amd`]).
//!
//! A node held along an inclined normal n only ([`Constraints::inclined`]) keeps one unknown, its
//! tangential displacement q = u·t (t = n turned counter-clockwise): u = g n + t q. Its two DOFs
//! then map to the same reduced index with the coefficients t_x and t_y, the reduced matrix is
//! Tᵀ K T and loads are Tᵀ f. Everything public stays in global x/y components; only the maps
//! [`FactoredBody::reduced_index`] and [`FactoredBody::interface_index`] carry the coefficient.
//! Without inclined supports every coefficient is 1 and the arithmetic is the plain elimination.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{supernodal::SupernodalLltRef, LltRef, SymbolicCholeskyRaw};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Mat, MatMut, Par, Side};

use crate::error::BodyError;
use crate::incremental_cholesky::FactorError;
use crate::supports::Constraints;

mod analysis;
mod reduction;

use analysis::Analysis;
use reduction::{plain_lower, reduced_lower_pattern, Reduction, NONE};

/// The values of a second numeric factorisation sharing a body's symbolic analysis
/// ([`FactoredBody::refactorize`]).
#[derive(Default)]
pub struct FactorValues {
    values: Vec<f64>,
    l_values: Vec<f64>,
    factored: bool,
}

/// A body's stiffness with supports eliminated, factorised by sparse Cholesky.
pub struct FactoredBody {
    name: String,
    k: SparseColMat<usize, f64>,
    /// Reduced index of each DOF, or `NONE` if prescribed.
    reduced: Vec<usize>,
    /// Coefficient of each DOF on its reduced unknown; empty when all are 1 (no inclined
    /// supports).
    coef: Vec<f64>,
    /// Full DOF of each reduced index (the x DOF for a node on an inclined support).
    free: Vec<usize>,
    /// The prescribed part of each DOF that has one, sorted by DOF: the value of a prescribed
    /// DOF, g n_c on a node of an inclined support.
    fixed: Vec<(usize, f64)>,
    /// Lower triangle of the reduced matrix (reduced numbering).
    lower: SymbolicSparseColMat<usize>,
    /// For each lower entry, its index in `k`'s values (`NONE` if it sums several, see `mixed`).
    gather: Vec<usize>,
    /// (lower entry, index in `k`'s values, coefficient) of the entries summing several terms
    /// (those of nodes on inclined supports).
    mixed: Vec<(usize, usize, f64)>,
    values: Vec<f64>,
    analysis: Analysis,
    l_values: Vec<f64>,
    /// Reduced indices of the interface DOFs, in the order given (prescribed ones dropped).
    interface: Vec<usize>,
    factored: bool,
    par: Par,
}

impl FactoredBody {
    /// Eliminates the prescribed DOFs from `k` and runs the symbolic analysis, ordering the free
    /// DOFs among `interface_dofs` last (in the given order).
    pub fn new(
        name: &str,
        k: SparseColMat<usize, f64>,
        constraints: &Constraints,
        interface_dofs: &[usize],
    ) -> Result<FactoredBody, BodyError> {
        let ndof = k.ncols();
        let fail = |message: String| BodyError::Factorization {
            body: name.to_string(),
            message,
        };
        let Reduction {
            reduced,
            coef,
            free,
            fixed,
        } = Reduction::new(ndof, constraints);
        let n = free.len();
        if n == 0 {
            return Err(fail(
                "every DOF is prescribed; there is nothing to solve".into(),
            ));
        }
        let (lower, gather, mixed) = if coef.is_empty() {
            let (lower, gather) = plain_lower(&k, &reduced, &free);
            (lower, gather, Vec::new())
        } else {
            reduced_lower_pattern(&k, &reduced, &coef, &free)
        };

        // Both DOFs of a node on an inclined support share one reduced index: keep it once.
        let mut seen = std::collections::HashSet::new();
        let interface: Vec<usize> = interface_dofs
            .iter()
            .filter_map(|&d| (reduced[d] != NONE).then_some(reduced[d]))
            .filter(|&r| seen.insert(r))
            .collect();
        let analysis = Analysis::new(&lower, &interface, n).map_err(fail)?;
        // The factor's values are allocated by the first factorisation, once the caller had the
        // chance to compare `memory_estimate` with the available memory.
        let l_values = Vec::new();
        let values = vec![0.0; gather.len()];
        Ok(FactoredBody {
            name: name.to_string(),
            k,
            reduced,
            coef,
            free,
            fixed,
            lower,
            gather,
            mixed,
            values,
            analysis,
            l_values,
            interface,
            factored: false,
            par: Par::Seq,
        })
    }

    /// Sets faer's parallelism for factorisations and solves of this body.
    pub fn set_parallelism(&mut self, par: Par) {
        self.par = par;
    }

    /// The full stiffness matrix (supports not eliminated).
    pub fn stiffness(&self) -> &SparseColMat<usize, f64> {
        &self.k
    }

    /// Number of DOFs (2 per node).
    pub fn num_dofs(&self) -> usize {
        self.reduced.len()
    }

    /// Number of stored values of the Cholesky factor (a measure of fill-in).
    pub fn factor_len(&self) -> usize {
        self.analysis.symbolic().len_val()
    }

    /// Bytes the numeric factorisation allocates: the factor's values and faer's workspace.
    pub fn memory_estimate(&self) -> u64 {
        let scratch = self
            .analysis
            .symbolic()
            .factorize_numeric_llt_scratch::<f64>(self.par, Default::default())
            .size_bytes();
        let values = self.factor_len().saturating_mul(size_of::<f64>());
        (values as u64).saturating_add(scratch as u64)
    }

    /// Numeric factorisation of `K + Σ additions` where `additions` are `(row, col, value)`
    /// entries (full DOF numbering) inside the stiffness pattern, added symmetrically: an entry with
    /// `row ≠ col` is added at both `(row, col)` and `(col, row)`.
    pub fn factorize(&mut self, additions: &[(usize, usize, f64)]) -> Result<(), BodyError> {
        self.allocate_factor()?;
        self.factored = false;
        let mut values = FactorValues {
            values: std::mem::take(&mut self.values),
            l_values: std::mem::take(&mut self.l_values),
            factored: false,
        };
        let result = self.factorize_values(additions, &mut values);
        (self.values, self.l_values) = (values.values, values.l_values);
        result?;
        self.factored = true;
        Ok(())
    }

    /// Numeric factorisation of `K + Σ additions` (as in [`FactoredBody::factorize`]) into
    /// `values`, kept apart from the body's own factor: the same symbolic analysis serves a
    /// second operator (a Robin operator whose springs change during an iteration).
    pub fn refactorize(
        &self,
        additions: &[(usize, usize, f64)],
        values: &mut FactorValues,
    ) -> Result<(), BodyError> {
        let len = self.factor_len();
        if values.l_values.len() != len {
            values.l_values = try_zeros(len).ok_or_else(|| BodyError::Factorization {
                body: self.name.clone(),
                message: format!("out of memory for the {len} values of the factor"),
            })?;
        }
        values.factored = false;
        self.factorize_values(additions, values)?;
        values.factored = true;
        Ok(())
    }

    /// The numeric factorisation of `K + Σ additions` into the buffers of `out`.
    fn factorize_values(
        &self,
        additions: &[(usize, usize, f64)],
        out: &mut FactorValues,
    ) -> Result<(), BodyError> {
        self.stiffness_values_into(&mut out.values);
        for &(i, j, a) in additions {
            let (ri, rj) = (self.reduced[i], self.reduced[j]);
            if ri == NONE || rj == NONE {
                continue;
            }
            // Tᵀ A T: both coefficients, and an (x, y) pair of one inclined node lands twice on
            // its diagonal (once as (i, j), once as (j, i)).
            let twice = if i != j && ri == rj { 2.0 } else { 1.0 };
            let a = self.coefficient(i) * self.coefficient(j) * twice * a;
            let (row, col) = (ri.max(rj), ri.min(rj));
            let start = self.lower.col_ptr()[col];
            let rows = &self.lower.row_idx()[start..self.lower.col_ptr()[col + 1]];
            let Ok(p) = rows.binary_search(&row) else {
                return Err(BodyError::Factorization {
                    body: self.name.clone(),
                    message: format!("entry ({i}, {j}) is outside the stiffness pattern"),
                });
            };
            out.values[start + p] += a;
        }
        if let Some(i) = out.values.iter().position(|v| !v.is_finite()) {
            return Err(BodyError::NonFinite {
                body: self.name.clone(),
                what: format!("stiffness entry {i}"),
            });
        }
        let not_positive = |pivot| BodyError::NotPositiveDefinite {
            body: self.name.clone(),
            pivot,
        };
        let out_of_memory = || BodyError::Factorization {
            body: self.name.clone(),
            message: "out of memory".into(),
        };
        let symbolic = match &self.analysis {
            Analysis::Faer(symbolic) => symbolic,
            Analysis::Own(tree) => {
                return match tree.factorize_into(&out.values, &mut out.l_values, None) {
                    Ok(_) => Ok(()),
                    Err(FactorError::NotPositiveDefinite(pivot)) => Err(not_positive(pivot)),
                    Err(FactorError::OutOfMemory) => Err(out_of_memory()),
                };
            }
        };
        let req = symbolic.factorize_numeric_llt_scratch::<f64>(self.par, Default::default());
        let mut mem = MemBuffer::try_new(req).map_err(|_| out_of_memory())?;
        let a = SparseColMatRef::new(self.lower.as_ref(), &out.values);
        symbolic
            .factorize_numeric_llt(
                &mut out.l_values,
                a,
                Side::Lower,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                    not_positive(index)
                }
            })?;
        Ok(())
    }

    /// The values of the reduced stiffness K itself (no additions) on the pattern of
    /// [`FactoredBody::reduced_lower`].
    pub fn reduced_stiffness_values(&self) -> Vec<f64> {
        let mut values = Vec::with_capacity(self.gather.len());
        self.stiffness_values_into(&mut values);
        values
    }

    /// Writes the reduced stiffness's lower values into `values` (cleared first).
    fn stiffness_values_into(&self, values: &mut Vec<f64>) {
        let kv = self.k.val();
        values.clear();
        if self.mixed.is_empty() {
            values.extend(self.gather.iter().map(|&p| kv[p]));
        } else {
            values.extend(
                self.gather
                    .iter()
                    .map(|&p| if p == NONE { 0.0 } else { kv[p] }),
            );
            for &(e, p, c) in &self.mixed {
                values[e] += c * kv[p];
            }
        }
    }

    /// Allocates the factor's values on the first factorisation; a failed allocation is an error
    /// rather than an abort.
    fn allocate_factor(&mut self) -> Result<(), BodyError> {
        let len = self.factor_len();
        if self.l_values.len() != len {
            self.l_values = try_zeros(len).ok_or_else(|| BodyError::Factorization {
                body: self.name.clone(),
                message: format!("out of memory for the {len} values of the factor"),
            })?;
        }
        Ok(())
    }

    /// Solves `K u = f` with the prescribed values for `u` on supports; `f` has one entry per DOF
    /// (entries on prescribed DOFs are ignored). Returns the full displacement vector.
    pub fn solve(&self, f: &[f64]) -> Result<Vec<f64>, BodyError> {
        let mut rhs = self.reduced_load(f);
        self.solve_reduced_in_place(&mut rhs)?;
        let u = self.expand(&rhs);
        if let Some(d) = u.iter().position(|v| !v.is_finite()) {
            return Err(BodyError::NonFinite {
                body: self.name.clone(),
                what: format!("the solution (DOF {d})"),
            });
        }
        Ok(u)
    }

    /// The right-hand side of the reduced system for the load `f` (one entry per DOF): `f` on the
    /// free DOFs minus what the prescribed values load them with, `f_f − K_fd u_d`.
    pub fn reduced_load(&self, f: &[f64]) -> Vec<f64> {
        let mut rhs: Vec<f64> = if self.coef.is_empty() {
            self.free.iter().map(|&d| f[d]).collect()
        } else {
            let mut rhs = vec![0.0; self.free.len()];
            for (d, &r) in self.reduced.iter().enumerate() {
                if r != NONE {
                    rhs[r] += self.coef[d] * f[d];
                }
            }
            rhs
        };
        let (col_ptr, row_idx, kv) = (
            self.k.symbolic().col_ptr(),
            self.k.symbolic().row_idx(),
            self.k.val(),
        );
        for &(d, value) in &self.fixed {
            if value == 0.0 {
                continue;
            }
            for p in col_ptr[d]..col_ptr[d + 1] {
                let r = self.reduced[row_idx[p]];
                if r != NONE {
                    rhs[r] -= self.coefficient(row_idx[p]) * kv[p] * value;
                }
            }
        }
        rhs
    }

    /// The full displacement of the reduced solution `q`: u_d = prescribed part + coefficient ×
    /// q of its reduced index.
    fn expand(&self, q: &[f64]) -> Vec<f64> {
        let mut u = vec![0.0; self.num_dofs()];
        if self.coef.is_empty() {
            for (r, &d) in self.free.iter().enumerate() {
                u[d] = q[r];
            }
        } else {
            for (d, &r) in self.reduced.iter().enumerate() {
                if r != NONE {
                    u[d] = self.coef[d] * q[r];
                }
            }
        }
        for &(d, value) in &self.fixed {
            if self.reduced[d] == NONE {
                u[d] = value;
            } else {
                u[d] += value;
            }
        }
        u
    }

    /// The coefficient of DOF `dof` on its reduced unknown (1 unless its node is on an inclined
    /// support).
    fn coefficient(&self, dof: usize) -> f64 {
        self.coef.get(dof).copied().unwrap_or(1.0)
    }

    /// The prescribed part of a DOF: its value if prescribed, g n_c on a node held along an
    /// inclined normal n (u·n = g), 0 for a free DOF. Then
    /// u_dof = prescribed_value(dof) + coefficient × `q[index]` with
    /// [`FactoredBody::reduced_index`].
    pub fn prescribed_value(&self, dof: usize) -> f64 {
        self.fixed
            .binary_search_by_key(&dof, |&(d, _)| d)
            .map_or(0.0, |i| self.fixed[i].1)
    }

    /// Solves in place in the reduced (free DOF) numbering.
    pub fn solve_reduced_in_place(&self, rhs: &mut [f64]) -> Result<(), BodyError> {
        self.solve_with(self.factored, &self.l_values, rhs)
    }

    /// Solves in place in the reduced numbering with a factor of
    /// [`FactoredBody::refactorize`].
    pub fn solve_reduced_with(
        &self,
        values: &FactorValues,
        rhs: &mut [f64],
    ) -> Result<(), BodyError> {
        self.solve_with(values.factored, &values.l_values, rhs)
    }

    fn solve_with(
        &self,
        factored: bool,
        l_values: &[f64],
        rhs: &mut [f64],
    ) -> Result<(), BodyError> {
        if !factored {
            return Err(BodyError::Factorization {
                body: self.name.clone(),
                message: "solve called before a successful factorization".into(),
            });
        }
        let symbolic = match &self.analysis {
            Analysis::Faer(symbolic) => symbolic,
            Analysis::Own(tree) => {
                return match tree.solve_in_place(l_values, rhs) {
                    true => Ok(()),
                    false => Err(BodyError::Factorization {
                        body: self.name.clone(),
                        message: format!(
                            "a load of {} values for {} unknowns",
                            rhs.len(),
                            self.free.len()
                        ),
                    }),
                };
            }
        };
        let n = rhs.len();
        let req = symbolic.solve_in_place_scratch::<f64>(1, self.par);
        let mut mem = MemBuffer::try_new(req).map_err(|_| BodyError::Factorization {
            body: self.name.clone(),
            message: "out of memory".into(),
        })?;
        let llt = LltRef::new(symbolic, l_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut mem),
        );
        Ok(())
    }

    /// Number of free (not prescribed) DOFs: the size of the reduced numbering.
    pub fn num_free(&self) -> usize {
        self.free.len()
    }

    /// The reduced unknown a DOF depends on and its coefficient there, or `None` if the DOF is
    /// prescribed. The coefficient is 1 except on a node of an inclined support, whose two DOFs
    /// share one unknown (the tangential displacement) with the tangent's components.
    pub fn reduced_index(&self, dof: usize) -> Option<(usize, f64)> {
        let r = self.reduced[dof];
        (r != NONE).then(|| (r, self.coefficient(dof)))
    }

    /// The lower triangle of the last factorised matrix (`K + Σ additions` of
    /// [`FactoredBody::factorize`]) in the reduced numbering.
    pub fn reduced_lower(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(self.lower.as_ref(), &self.values)
    }

    /// For each DOF of `interface_dofs` (as given to [`FactoredBody::new`]), its index in the
    /// Schur factor and its coefficient there (as [`FactoredBody::reduced_index`]), or `None` if
    /// the DOF is prescribed.
    pub fn interface_index(&self, interface_dofs: &[usize]) -> Vec<Option<(usize, f64)>> {
        let mut pos = std::collections::HashMap::new();
        for (k, &r) in self.interface.iter().enumerate() {
            pos.insert(r, k);
        }
        interface_dofs
            .iter()
            .map(|&d| {
                let r = self.reduced[d];
                let k = (r != NONE).then(|| pos.get(&r).copied()).flatten();
                k.map(|k| (k, self.coefficient(d)))
            })
            .collect()
    }

    /// The dense lower Cholesky factor `L₂₂` of the Schur complement on the free interface DOFs
    /// (ordered as [`FactoredBody::interface_index`] says); 0 × 0 without interface DOFs.
    ///
    /// Errors if the body is not factorised, or if the factor is not supernodal (the Schur factor
    /// is read off its supernodes; [`FactoredBody::new`] forces that whenever there is an
    /// interface).
    pub fn schur_factor(&self) -> Result<Mat<f64>, BodyError> {
        let m = self.interface.len();
        let n = self.free.len();
        let n0 = n - m;
        let mut l22 = Mat::<f64>::zeros(m, m);
        if m == 0 {
            return Ok(l22);
        }
        let fail = |message: &str| BodyError::Factorization {
            body: self.name.clone(),
            message: message.into(),
        };
        if !self.factored {
            return Err(fail(
                "Schur factor requested before a successful factorization",
            ));
        }
        let SymbolicCholeskyRaw::Supernodal(sym) = self.analysis.symbolic().raw() else {
            return Err(fail(
                "the factor is not supernodal; its Schur block cannot be read",
            ));
        };
        let llt = SupernodalLltRef::new(sym, &self.l_values);
        for s in 0..sym.n_supernodes() {
            let node = llt.supernode(s);
            let start = node.start();
            let val = node.val();
            let ncols = val.ncols();
            if start + ncols <= n0 {
                continue;
            }
            let pattern = node.pattern();
            for jj in 0..ncols {
                let j = start + jj;
                if j < n0 {
                    continue;
                }
                for ii in jj..ncols {
                    l22[(start + ii - n0, j - n0)] = val[(ii, jj)];
                }
                for (k, &r) in pattern.iter().enumerate() {
                    if r >= n0 {
                        l22[(r - n0, j - n0)] = val[(ncols + k, jj)];
                    }
                }
            }
        }
        Ok(l22)
    }
}

/// A vector of `len` zeros, or `None` if the allocation fails (an error rather than an abort).
fn try_zeros(len: usize) -> Option<Vec<f64>> {
    let mut values = Vec::new();
    values.try_reserve_exact(len).ok()?;
    values.resize(len, 0.0);
    Some(values)
}
