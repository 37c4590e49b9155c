//! The linear solves of the Newton step: sparse LU with a kept analysis and iterative
//! refinement, or dense LU for systems whose blocks fill most of the matrix.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::FaerError;
use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};
use faer::{Conj, Index, Mat, Par};

/// Iterative refinement steps at most after a sparse-path LU solve.
pub(super) const MAX_REFINE: usize = 4;

/// Solves the Newton system (given by its triplets) in place by sparse LU: the dense blocks per
/// body go through faer's supernodal kernels. Sequential, so the same on any number of threads.
///
/// With `refine` (the sparse path: the residual of the true system at a solution), iterative
/// refinement follows, at most [`MAX_REFINE`] steps while each halves the residual. `cache` keeps
/// the LU's analysis between calls.
///
/// The numeric factorisation is the peak of memory of a Newton step on the sparse path, so the
/// triplets (consumed) and the last step's pattern are freed before it: only the matrix, the
/// factor and faer's workspace are then alive. The factor's values are not kept for the next step
/// either: alive while the next step's triplets and matrix are built, they would make that moment
/// the run's peak, and the pattern changes nothing in them but their buffers' capacity.
pub(super) fn sparse_solve(
    trip: Vec<Triplet<usize, usize, f64>>,
    n: usize,
    rhs: &mut Mat<f64>,
    cache: Option<&mut LuCache>,
    mut refine: Option<&mut (dyn FnMut(&Mat<f64>) -> Option<Mat<f64>> + '_)>,
) -> Option<()> {
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).ok()?;
    drop(trip);
    let mut fresh = LuCache::default();
    let kept = cache.unwrap_or(&mut fresh);
    // 32-bit indices shrink the index arrays of the matrix, of its transpose in faer's workspace
    // and of the LU: about 60 MB of the 1 GB peak on the 4000 × 16 strip, with the same values.
    // A factor whose positions do not fit in them is factorised with 64-bit indices.
    let a = match narrow(a) {
        Ok(a) => match lu_solve(a, &mut kept.narrow, rhs, refine.as_deref_mut()) {
            Ok(solved) => return solved,
            Err(a) => widen(a),
        },
        Err(a) => a,
    };
    lu_solve(a, &mut kept.wide, rhs, refine).unwrap_or(None)
}

/// [`sparse_solve`] with the matrix `a` and the kept analysis of its index type: `None` if the
/// LU fails, `Err(a)` if its positions overflow the index type `I`.
fn lu_solve<I: Index>(
    a: SparseColMat<I, f64>,
    kept: &mut LuIndexCache<I>,
    rhs: &mut Mat<f64>,
    mut refine: Option<&mut (dyn FnMut(&Mat<f64>) -> Option<Mat<f64>> + '_)>,
) -> Result<Option<()>, SparseColMat<I, f64>> {
    // Dense blocks per body: the supernodal factorisation uses dense kernels on them.
    let params = LuSymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let same = kept.pattern.as_ref().is_some_and(|p| {
        p.col_ptr() == a.symbolic().col_ptr() && p.row_idx() == a.symbolic().row_idx()
    });
    // The matrix's own pattern replaces the kept one after the factorisation.
    kept.pattern = None;
    if !same || kept.symbolic.is_none() {
        kept.symbolic = None;
        match factorize_symbolic_lu(a.symbolic(), params) {
            Ok(s) => kept.symbolic = Some(s),
            Err(FaerError::IndexOverflow) => return Err(a),
            Err(_) => return Ok(None),
        }
    }
    let Some(symbolic) = kept.symbolic.as_ref() else {
        return Ok(None);
    };
    let mut numeric = NumericLu::new();
    let Ok(mut mem) = MemBuffer::try_new(
        symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
    ) else {
        return Ok(None);
    };
    let lu = match symbolic.factorize_numeric_lu(
        &mut numeric,
        a.as_ref(),
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    ) {
        Ok(lu) => lu,
        Err(LuError::Generic(FaerError::IndexOverflow)) => {
            kept.symbolic = None;
            return Err(a);
        }
        Err(_) => return Ok(None),
    };
    let Ok(mut mem) = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
    else {
        return Ok(None);
    };
    lu.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, MemStack::new(&mut mem));
    // r = b − A x, then x += A⁻¹ r, while that halves ‖r‖.
    let mut last = f64::INFINITY;
    let passes = if refine.is_some() { MAX_REFINE } else { 0 };
    for _ in 0..passes {
        let Some(mut r) = refine.as_mut().and_then(|f| f(rhs)) else {
            break;
        };
        let size = r.norm_l2();
        if size.is_nan() || size >= 0.5 * last {
            break;
        }
        last = size;
        lu.solve_in_place_with_conj(Conj::No, r.as_mut(), Par::Seq, MemStack::new(&mut mem));
        for i in 0..rhs.nrows() {
            rhs[(i, 0)] += r[(i, 0)];
        }
    }
    kept.pattern = Some(a.into_parts().0);
    Ok(Some(()))
}

/// `a` with 32-bit indices, or `a` itself if its dimensions or entries do not fit in them.
fn narrow(a: SparseColMat<usize, f64>) -> Result<SparseColMat<u32, f64>, SparseColMat<usize, f64>> {
    // faer checks positions against the signed maximum of the index type.
    let fits = |x: usize| x <= i32::MAX as usize;
    if !(fits(a.nrows()) && fits(a.ncols()) && fits(a.val().len())) {
        return Err(a);
    }
    let (symbolic, val) = a.into_parts();
    let (nrows, ncols, col_ptr, _, row_idx) = symbolic.into_parts();
    // Every index is below the dimension or the number of entries, checked above.
    let to32 = |v: Vec<usize>| v.into_iter().map(|x| x as u32).collect();
    let symbolic =
        SymbolicSparseColMat::new_checked(nrows, ncols, to32(col_ptr), None, to32(row_idx));
    Ok(SparseColMat::new(symbolic, val))
}

/// `a` with 64-bit indices again.
fn widen(a: SparseColMat<u32, f64>) -> SparseColMat<usize, f64> {
    let (symbolic, val) = a.into_parts();
    let (nrows, ncols, col_ptr, _, row_idx) = symbolic.into_parts();
    let to64 = |v: Vec<u32>| v.into_iter().map(|x| x as usize).collect();
    let symbolic =
        SymbolicSparseColMat::new_checked(nrows, ncols, to64(col_ptr), None, to64(row_idx));
    SparseColMat::new(symbolic, val)
}

/// The dense n × n matrix of the Newton system given by its triplets (duplicates summed), for a
/// system whose blocks fill most of it.
pub(super) fn dense_matrix(trip: &[Triplet<usize, usize, f64>], n: usize) -> Mat<f64> {
    let mut a = Mat::<f64>::zeros(n, n);
    for t in trip {
        a[(t.row, t.col)] += t.val;
    }
    a
}

/// Solves `a x = rhs` in place of `rhs` by LU with partial pivoting, sequentially (the same bits on
/// any number of threads); `None` if the workspace cannot be allocated.
pub(crate) fn lu_solve_in_place(a: Mat<f64>, rhs: &mut Mat<f64>) -> Option<()> {
    DenseLu::new(a)?.solve(rhs)
}

/// Solves `a x = rhs` as [`lu_solve_in_place`], then refines x by `sweeps` steps of iterative
/// refinement against `a` (the residual in working precision), which leaves each equation's
/// residual small against its own terms however unevenly the rows are scaled (Skeel).
pub(crate) fn lu_solve_refined(a: Mat<f64>, rhs: &mut Mat<f64>, sweeps: usize) -> Option<()> {
    let lu = DenseLu::new(a.clone())?;
    let b = rhs.clone();
    lu.solve(rhs)?;
    for _ in 0..sweeps {
        let mut r = b.clone();
        faer::linalg::matmul::matmul(
            r.as_mut(),
            faer::Accum::Add,
            a.as_ref(),
            rhs.as_ref(),
            -1.0,
            Par::Seq,
        );
        lu.solve(&mut r)?;
        *rhs += &r;
    }
    Some(())
}

/// A dense LU factorisation with partial pivoting, computed and applied sequentially.
pub(super) struct DenseLu {
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
}

impl DenseLu {
    /// Factorises `a` in place; `None` if the workspace cannot be allocated.
    pub(super) fn new(mut a: Mat<f64>) -> Option<DenseLu> {
        use faer::linalg::lu::partial_pivoting::factor;
        let n = a.nrows();
        let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default());
        let mut mem = MemBuffer::try_new(req).ok()?;
        factor::lu_in_place(
            a.as_mut(),
            &mut perm,
            &mut perm_inv,
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        );
        Some(DenseLu {
            lu: a,
            perm,
            perm_inv,
        })
    }

    /// Solves in place of `rhs`; `None` if the workspace cannot be allocated.
    pub(super) fn solve(&self, rhs: &mut Mat<f64>) -> Option<()> {
        use faer::linalg::lu::partial_pivoting::solve;
        let n = self.lu.nrows();
        let req = solve::solve_in_place_scratch::<usize, f64>(n, rhs.ncols(), Par::Seq);
        let mut mem = MemBuffer::try_new(req).ok()?;
        let p = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        solve::solve_in_place_with_conj(
            self.lu.as_ref(),
            self.lu.as_ref(),
            p,
            Conj::No,
            rhs.as_mut(),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        Some(())
    }
}

/// What the sparse LU of the last Newton step on the sparse path leaves for the next, per index
/// type ([`sparse_solve`]).
#[derive(Default)]
pub(super) struct LuCache {
    narrow: LuIndexCache<u32>,
    wide: LuIndexCache<usize>,
}

/// The pattern and symbolic analysis of the last sparse LU with indices `I`, reused while the
/// pattern stays the same.
struct LuIndexCache<I: Index> {
    pattern: Option<SymbolicSparseColMat<I>>,
    symbolic: Option<SymbolicLu<I>>,
}

impl<I: Index> Default for LuIndexCache<I> {
    fn default() -> Self {
        LuIndexCache {
            pattern: None,
            symbolic: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small nonsymmetric tridiagonal system with a known solution.
    fn system(n: usize) -> (SparseColMat<usize, f64>, Mat<f64>, Vec<f64>) {
        let mut trip = Vec::new();
        for i in 0..n {
            trip.push(Triplet::new(i, i, 4.0 + i as f64));
            if i + 1 < n {
                trip.push(Triplet::new(i, i + 1, -1.0));
                trip.push(Triplet::new(i + 1, i, -2.0));
            }
        }
        let a = SparseColMat::try_new_from_triplets(n, n, &trip).expect("valid triplets");
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut b = Mat::<f64>::zeros(n, 1);
        for t in &trip {
            b[(t.row, 0)] += t.val * x[t.col];
        }
        (a, b, x)
    }

    #[test]
    fn both_index_widths_solve_alike() {
        let (a, b, x) = system(50);
        let mut wide = b.clone();
        let solved = lu_solve(a.clone(), &mut LuIndexCache::default(), &mut wide, None);
        assert!(matches!(solved, Ok(Some(()))));
        let Ok(narrowed) = narrow(a.clone()) else {
            panic!("50 unknowns fit in 32-bit indices");
        };
        assert_eq!(
            widen(narrowed.clone()).symbolic().row_idx(),
            a.symbolic().row_idx()
        );
        let mut thin = b.clone();
        let solved = lu_solve(narrowed, &mut LuIndexCache::default(), &mut thin, None);
        assert!(matches!(solved, Ok(Some(()))));
        for i in 0..x.len() {
            assert_eq!(wide[(i, 0)].to_bits(), thin[(i, 0)].to_bits());
            assert!((wide[(i, 0)] - x[i]).abs() < 1e-12);
        }
    }
}
