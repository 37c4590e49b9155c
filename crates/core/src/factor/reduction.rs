//! The supports eliminated from a body's stiffness: the reduced numbering of the free DOFs (one
//! tangential unknown per node on an inclined support) and the pattern of the reduced matrix's
//! lower triangle.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

use crate::geometry::{component_of, node_of};
use crate::supports::Constraints;

/// The reduced index of a prescribed DOF, and the gather index of a lower entry summing several
/// terms.
pub(super) const NONE: usize = usize::MAX;

/// The reduced DOF numbering of a body's supports.
pub(super) struct Reduction {
    pub reduced: Vec<usize>,
    pub coef: Vec<f64>,
    pub free: Vec<usize>,
    pub fixed: Vec<(usize, f64)>,
}

impl Reduction {
    /// Numbers the free DOFs in DOF order; both DOFs of a node on an inclined support share the
    /// number of its tangential unknown, with the tangent's components as coefficients.
    pub(super) fn new(ndof: usize, constraints: &Constraints) -> Reduction {
        let inclined: std::collections::HashMap<usize, ([f64; 2], f64)> = constraints
            .inclined()
            .map(|(v, n, g)| (v, (n, g)))
            .collect();
        let mut reduced = vec![NONE; ndof];
        let mut coef = if inclined.is_empty() {
            Vec::new()
        } else {
            vec![1.0; ndof]
        };
        let mut free = Vec::with_capacity(ndof);
        let mut fixed = Vec::new();
        for (dof, r) in reduced.iter_mut().enumerate() {
            let c = component_of(dof);
            match (constraints.get(dof), inclined.get(&node_of(dof))) {
                (Some(v), _) => fixed.push((dof, v)),
                (None, Some(&(n, g))) => {
                    // The x DOF opens the node's unknown, the y DOF (next) shares it.
                    if c == 0 || free.last() != Some(&(dof - 1)) {
                        free.push(dof);
                    }
                    *r = free.len() - 1;
                    coef[dof] = [-n[1], n[0]][c];
                    fixed.push((dof, g * n[c]));
                }
                (None, None) => {
                    *r = free.len();
                    free.push(dof);
                }
            }
        }
        Reduction {
            reduced,
            coef,
            free,
            fixed,
        }
    }
}

/// Lower triangle of the reduced matrix without inclined supports, and for each entry its index
/// in `k`'s values (the reduced map is monotone, so rows stay sorted).
pub(super) fn plain_lower(
    k: &SparseColMat<usize, f64>,
    reduced: &[usize],
    free: &[usize],
) -> (SymbolicSparseColMat<usize>, Vec<usize>) {
    let n = free.len();
    let (col_ptr, row_idx) = (k.symbolic().col_ptr(), k.symbolic().row_idx());
    let mut l_ptr = Vec::with_capacity(n + 1);
    let mut l_rows = Vec::new();
    let mut gather = Vec::new();
    l_ptr.push(0);
    for &j in free {
        for (p, &i) in row_idx
            .iter()
            .enumerate()
            .take(col_ptr[j + 1])
            .skip(col_ptr[j])
        {
            if i >= j && reduced[i] != NONE {
                l_rows.push(reduced[i]);
                gather.push(p);
            }
        }
        l_ptr.push(l_rows.len());
    }
    let lower = SymbolicSparseColMat::new_checked(n, n, l_ptr, None, l_rows);
    (lower, gather)
}

/// Lower triangle of Tᵀ K T with inclined supports: entry (R, C) sums c_i c_j K_ij over the DOFs
/// i of R and j of C. Entries of one term with coefficient 1 are gathered as in [`plain_lower`],
/// the others listed as (entry, index in `k`'s values, coefficient).
pub(super) fn reduced_lower_pattern(
    k: &SparseColMat<usize, f64>,
    reduced: &[usize],
    coef: &[f64],
    free: &[usize],
) -> (
    SymbolicSparseColMat<usize>,
    Vec<usize>,
    Vec<(usize, usize, f64)>,
) {
    let n = free.len();
    let (col_ptr, row_idx) = (k.symbolic().col_ptr(), k.symbolic().row_idx());
    let mut l_ptr = Vec::with_capacity(n + 1);
    let (mut l_rows, mut gather, mut mixed) = (Vec::new(), Vec::new(), Vec::new());
    let mut terms: Vec<(usize, usize, f64)> = Vec::new();
    l_ptr.push(0);
    for (col, &j0) in free.iter().enumerate() {
        terms.clear();
        // K is stored in full, so the columns of both DOFs of the unknown hold every term.
        let cols = (j0..reduced.len()).take_while(|&j| reduced[j] == col);
        for j in cols {
            for p in col_ptr[j]..col_ptr[j + 1] {
                let i = row_idx[p];
                if reduced[i] != NONE && reduced[i] >= col {
                    terms.push((reduced[i], p, coef[i] * coef[j]));
                }
            }
        }
        terms.sort_by_key(|t| t.0);
        for group in terms.chunk_by(|a, b| a.0 == b.0) {
            let e = l_rows.len();
            l_rows.push(group[0].0);
            match group {
                [(_, p, c)] if *c == 1.0 => gather.push(*p),
                _ => {
                    gather.push(NONE);
                    mixed.extend(group.iter().map(|&(_, p, c)| (e, p, c)));
                }
            }
        }
        l_ptr.push(l_rows.len());
    }
    let lower = SymbolicSparseColMat::new_checked(n, n, l_ptr, None, l_rows);
    (lower, gather, mixed)
}
