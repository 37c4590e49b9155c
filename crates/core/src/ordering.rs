//! A fill-reducing order computed on the graph of the nodes rather than of the DOFs.
//!
//! The two DOFs of a node have the same pattern in the stiffness matrix. Merging such columns
//! before the approximate minimum degree ordering (AMD) hands it a graph with half the vertices
//! and a quarter of the edges, and the order of the merged graph, with each node's DOFs kept
//! together, is an order of the same quality: AMD would find those DOFs indistinguishable and
//! eliminate them together anyway.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

/// The AMD order of the symmetric matrix whose lower triangle has the pattern `lower`, computed
/// with consecutive columns of equal pattern merged. Returns (fwd, inv): position k of the order
/// holds column `fwd[k]`, and column j sits at `inv[j]`. `None` if memory or the indices fail.
pub fn node_amd(lower: SymbolicSparseColMatRef<'_, usize>) -> Option<(Vec<usize>, Vec<usize>)> {
    let n = lower.ncols();
    let (adj_ptr, adj) = adjacency(lower);
    let column = |j: usize| &adj[adj_ptr[j]..adj_ptr[j + 1]];
    // Merge column j into the group of column j − 1 when their patterns (with the diagonal) are
    // equal: then each one's pattern holds the other.
    let mut group = vec![0; n];
    let mut first = Vec::with_capacity(n / 2 + 1);
    for j in 0..n {
        if j == 0 || column(j) != column(j - 1) {
            first.push(j);
        }
        group[j] = first.len() - 1;
    }
    let groups = first.len();
    first.push(n);
    let mut ptr = Vec::with_capacity(groups + 1);
    let mut rows = Vec::new();
    ptr.push(0);
    for g in 0..groups {
        let mut last = usize::MAX;
        for &r in column(first[g]) {
            let h = group[r];
            if h >= g && h != last {
                rows.push(h);
                last = h;
            }
        }
        ptr.push(rows.len());
    }
    let nnz = rows.len();
    let graph = SymbolicSparseColMat::new_checked(groups, groups, ptr, None, rows);
    let (mut perm, mut perm_inv) = (vec![0; groups], vec![0; groups]);
    let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(groups, nnz)).ok()?;
    amd::order(
        &mut perm,
        &mut perm_inv,
        graph.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .ok()?;
    let fwd: Vec<usize> = perm.iter().flat_map(|&g| first[g]..first[g + 1]).collect();
    let mut inv = vec![0; n];
    for (k, &j) in fwd.iter().enumerate() {
        inv[j] = k;
    }
    Some((fwd, inv))
}

/// Items grouped by their key in `0..n`, in the order emitted within a key (a counting sort):
/// `emit` is called twice and must emit the same (key, item) pairs both times. Returns the
/// groups' bounds (`ptr`, n + 1 of them) and the items.
pub(crate) fn group_by<T: Copy + Default>(
    n: usize,
    emit: impl Fn(&mut dyn FnMut(usize, T)),
) -> (Vec<usize>, Vec<T>) {
    let mut ptr = vec![0; n + 1];
    emit(&mut |key, _| ptr[key + 1] += 1);
    for k in 0..n {
        ptr[k + 1] += ptr[k];
    }
    let mut next = ptr.clone();
    let mut items = vec![T::default(); ptr[n]];
    emit(&mut |key, item| {
        items[next[key]] = item;
        next[key] += 1;
    });
    (ptr, items)
}

/// Every column's pattern in the full symmetric matrix, with the diagonal, sorted.
fn adjacency(lower: SymbolicSparseColMatRef<'_, usize>) -> (Vec<usize>, Vec<usize>) {
    let n = lower.ncols();
    let (col_ptr, row_idx) = (lower.col_ptr(), lower.row_idx());
    let entries = |c: usize| row_idx[col_ptr[c]..col_ptr[c + 1]].iter().copied();
    let (ptr, mut adj) = group_by(n, |emit| {
        for c in 0..n {
            emit(c, c);
            for r in entries(c).filter(|&r| r != c) {
                emit(c, r);
                emit(r, c);
            }
        }
    });
    // Sorted, so that equal patterns compare equal (the input's columns need not be sorted).
    for j in 0..n {
        adj[ptr[j]..ptr[j + 1]].sort_unstable();
    }
    (ptr, adj)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
    };
    use faer::sparse::SparseColMat;
    use faer::sparse::Triplet;
    use faer::Side;

    /// The lower triangle of a k × k grid of nodes with `dofs` DOFs each, every node coupled to
    /// its 8 neighbours.
    fn grid(k: usize, dofs: usize) -> SparseColMat<usize, f64> {
        let mut trip = Vec::new();
        let at = |i: usize, j: usize, d: usize| (i * k + j) * dofs + d;
        for i in 0..k {
            for j in 0..k {
                for (di, dj) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let (p, q) = (i + di, j + dj);
                    let (Some(q), true) = (Some(q), p < k && q < k) else {
                        continue;
                    };
                    for a in 0..dofs {
                        for b in 0..dofs {
                            let (r, c) = (at(p, q, a), at(i, j, b));
                            if r >= c {
                                trip.push(Triplet::new(r, c, 1.0));
                            }
                        }
                    }
                }
                if i + 1 < k && j > 0 {
                    for a in 0..dofs {
                        for b in 0..dofs {
                            trip.push(Triplet::new(at(i + 1, j - 1, a), at(i, j, b), 1.0));
                        }
                    }
                }
            }
        }
        let n = k * k * dofs;
        SparseColMat::try_new_from_triplets(n, n, &trip).unwrap()
    }

    /// The number of values of the Cholesky factor in the order `ordering`.
    fn fill(a: &SparseColMat<usize, f64>, ordering: SymmetricOrdering<'_, usize>) -> usize {
        factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            ordering,
            CholeskySymbolicParams::default(),
        )
        .unwrap()
        .len_val()
    }

    #[test]
    fn the_node_order_is_a_permutation_as_good_as_amd_on_the_dofs() {
        for dofs in [1, 2] {
            let a = grid(30, dofs);
            let (fwd, inv) = node_amd(a.symbolic()).unwrap();
            let n = a.ncols();
            let mut seen = vec![false; n];
            for (k, &j) in fwd.iter().enumerate() {
                assert!(!seen[j] && inv[j] == k);
                seen[j] = true;
            }
            let perm = faer::perm::PermRef::new_checked(&fwd, &inv, n);
            let node = fill(&a, SymmetricOrdering::Custom(perm));
            let dof = fill(&a, SymmetricOrdering::Amd);
            assert!(
                (node as f64) < 1.15 * dof as f64,
                "{dofs}: {node} against {dof}"
            );
        }
    }
}
