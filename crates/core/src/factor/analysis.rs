//! How a body's factor is computed and applied: the symbolic analysis of the reduced matrix,
//! by this crate's supernodal factorisation without interface DOFs, by faer's with the interface
//! DOFs ordered last.

use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SymbolicSparseColMat;
use faer::Side;

use crate::incremental_cholesky::SupernodalTree;
use crate::ordering::node_amd;

/// How a body's factor is computed and applied.
pub(super) enum Analysis {
    /// faer's numeric factorisation and solve: with interface DOFs (ordered last, so that the
    /// Schur factor is read off the supernodes).
    Faer(SymbolicCholesky<usize>),
    /// This crate's supernodal factorisation and solve (`incremental_cholesky`): without interface
    /// DOFs (the sparse path). On the thin bodies of long contact zones faer picks its simplicial
    /// factor, whose numeric factorisation and solve take about twice as long.
    Own(SupernodalTree),
}

impl Analysis {
    pub(super) fn symbolic(&self) -> &SymbolicCholesky<usize> {
        match self {
            Analysis::Faer(symbolic) => symbolic,
            Analysis::Own(tree) => tree.symbolic(),
        }
    }

    /// The symbolic analysis of the reduced lower triangle `lower` (`n` unknowns) with the reduced
    /// indices `interface` ordered last; the error is the message of the failure.
    pub(super) fn new(
        lower: &SymbolicSparseColMat<usize>,
        interface: &[usize],
        n: usize,
    ) -> Result<Analysis, String> {
        // With no interface AMD on the nodes' graph is the ordering; otherwise AMD on the interior
        // and the interface last.
        if interface.is_empty() {
            let order = node_amd(lower.as_ref()).ok_or("no fill-reducing order")?;
            let tree = SupernodalTree::analyse(lower.as_ref(), (&order.0, &order.1)).ok_or(
                "the symbolic analysis failed (out of memory, or 2³² stiffness entries or more)",
            )?;
            Ok(Analysis::Own(tree))
        } else {
            let perm = last_ordering(lower, interface).ok_or("no fill-reducing order")?;
            let inv = inverse(&perm);
            let ordering =
                SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&perm, &inv, n));
            let params = CholeskySymbolicParams {
                // The Schur factor is read off supernodes; small bodies would otherwise go simplicial.
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            };
            let symbolic =
                factorize_symbolic_cholesky(lower.as_ref(), Side::Lower, ordering, params)
                    .map_err(|e| format!("{e:?}"))?;
            Ok(Analysis::Faer(symbolic))
        }
    }
}

/// The AMD order of the whole matrix on its nodes ([`node_amd`]) with the interface DOFs moved to
/// the end (in the given order), the rest keeping their order; `None` if the ordering fails.
/// Measured on a body of 1000 × 500 cells with a 1001-node contact line: 5 % more factor values
/// than [`node_amd`] without an interface. faer's AMD on the DOFs, then the interface last, gave
/// 39 % more (`docs/sparse-path.md`).
fn last_ordering(lower: &SymbolicSparseColMat<usize>, interface: &[usize]) -> Option<Vec<usize>> {
    let mut is_interface = vec![false; lower.ncols()];
    for &r in interface {
        is_interface[r] = true;
    }
    let (fwd, _) = node_amd(lower.as_ref())?;
    let mut order: Vec<usize> = fwd.into_iter().filter(|&r| !is_interface[r]).collect();
    order.extend_from_slice(interface);
    Some(order)
}

fn inverse(perm: &[usize]) -> Vec<usize> {
    let mut inv = vec![0; perm.len()];
    for (i, &p) in perm.iter().enumerate() {
        inv[p] = i;
    }
    inv
}
