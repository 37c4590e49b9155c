//! The dense Newton system solved by its bodies' blocks. A point's row of J reads its own body's
//! responses only, unless the point sees a partner (closed, sticking or slipping, or a balanced
//! unknown that gathers such points), whose row also reads the partner's. With the rows of each
//! body b split into its coupling rows K_b and the others N_b, and the unknowns ordered
//! N_1, …, N_nb, K, J has the arrowhead form
//!   [A_1        E_1]
//!   [     ⋱      ⋮ ]
//!   [F_1   …    J_KK]
//! (A_b = J[N_b, N_b], E_b = J[N_b, K] nonzero in the columns K_b only, F_b = J[K, N_b]), and
//! block elimination leaves the Schur complement S = J_KK − Σ_b F_b A_b⁻¹ E_b on the k coupling
//! unknowns. Its cost is the LUs of the A_b, k_b solves with each and the k × k LU of S: far below
//! the LU of J when few points are closed, as in most contact zones.
//!
//! This restricts the LU's pivots to the blocks, so an A_b can be singular or ill-conditioned
//! where J is not: the solution is refined against J itself and accepted only if its residual
//! meets the caller's tolerance; otherwise the caller factorises J whole.

use std::ops::Range;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use rayon::prelude::*;

use super::linear::DenseLu;

/// Refinement passes at most against J.
const MAX_REFINE: usize = 3;

/// Solves `a x = rhs` in place of `rhs` by the blocks `groups` (disjoint ranges covering
/// `0..n`): `None` when that does not take fewer than half the flops of the LU of `a` (the other
/// half pays for gathering the blocks and the refinement), or when the refined solution's
/// residual is above `tol`·‖rhs‖; the caller then factorises `a`. The blocks are factorised in
/// parallel, each sequentially: the same bits on any number of threads.
pub(super) fn block_solve(
    a: &Mat<f64>,
    groups: &[Range<usize>],
    rhs: &mut Mat<f64>,
    tol: f64,
) -> Option<()> {
    // A body without contact points has no rows to factorise.
    let groups: Vec<Range<usize>> = groups.iter().filter(|g| !g.is_empty()).cloned().collect();
    let split = Split::new(a, &groups);
    if split.flops() >= 0.5 * lu_flops(a.nrows()) {
        return None;
    }
    let solver = Arrow::new(a, split)?;
    let b = rhs.clone();
    let size = b.norm_l2();
    let mut x = solver.apply(&b)?;
    for _ in 0..=MAX_REFINE {
        let mut r = b.clone();
        matmul(&mut r, Accum::Add, a, &x, -1.0, Par::Seq);
        let residual = r.norm_l2();
        if !residual.is_finite() {
            return None;
        }
        if residual <= tol * size {
            *rhs = x;
            return Some(());
        }
        x += solver.apply(&r)?;
    }
    None
}

/// The flops of the LU of an n × n matrix.
fn lu_flops(n: usize) -> f64 {
    2.0 / 3.0 * (n as f64).powi(3)
}

/// The rows of every group split into those with an entry outside the group (coupling) and the
/// others.
struct Split {
    /// N_b per group.
    inner: Vec<Vec<usize>>,
    /// K: the coupling rows of every group, in order.
    coupling: Vec<usize>,
    /// The range of each group's coupling rows in `coupling`.
    own: Vec<Range<usize>>,
}

impl Split {
    fn new(a: &Mat<f64>, groups: &[Range<usize>]) -> Split {
        let n = a.ncols();
        let (mut inner, mut coupling, mut own) = (Vec::new(), Vec::new(), Vec::new());
        for g in groups {
            let start = coupling.len();
            let mut rows = Vec::new();
            for i in g.clone() {
                let outside = (0..g.start).chain(g.end..n).any(|c| a[(i, c)] != 0.0);
                if outside {
                    coupling.push(i);
                } else {
                    rows.push(i);
                }
            }
            inner.push(rows);
            own.push(start..coupling.len());
        }
        Split {
            inner,
            coupling,
            own,
        }
    }

    /// The flops of the block elimination: the LUs of the A_b, A_b⁻¹ E_b, F_b (A_b⁻¹ E_b) and
    /// the LU of S.
    fn flops(&self) -> f64 {
        let k = self.coupling.len() as f64;
        let per_block: f64 = (self.inner.iter().zip(&self.own))
            .map(|(rows, own)| {
                let (m, kb) = (rows.len() as f64, own.len() as f64);
                lu_flops(rows.len()) + 2.0 * m * m * kb + 2.0 * k * m * kb
            })
            .sum();
        per_block + lu_flops(self.coupling.len())
    }
}

/// The factorised block elimination.
struct Arrow {
    split: Split,
    /// LU of A_b.
    blocks: Vec<DenseLu>,
    /// F_b = J[K, N_b].
    lower: Vec<Mat<f64>>,
    /// A_b⁻¹ E_b restricted to the columns K_b.
    reduced: Vec<Mat<f64>>,
    /// LU of S.
    schur: DenseLu,
}

impl Arrow {
    fn new(a: &Mat<f64>, split: Split) -> Option<Arrow> {
        let gather = |rows: &[usize], cols: &[usize]| {
            Mat::<f64>::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
        };
        let k = &split.coupling;
        let parts = (split.inner.par_iter().zip(&split.own))
            .map(|(rows, own)| {
                let lu = DenseLu::new(gather(rows, rows))?;
                let mut reduced = gather(rows, &k[own.clone()]);
                lu.solve(&mut reduced)?;
                Some((lu, gather(k, rows), reduced))
            })
            .collect::<Option<Vec<_>>>()?;
        let mut schur = gather(k, k);
        for ((_, lower, reduced), own) in parts.iter().zip(&split.own) {
            let cols = schur.subcols_mut(own.start, own.len());
            matmul(cols, Accum::Add, lower, reduced, -1.0, Par::Seq);
        }
        let schur = DenseLu::new(schur)?;
        let (mut blocks, mut lower, mut reduced) = (Vec::new(), Vec::new(), Vec::new());
        for (lu, f, w) in parts {
            blocks.push(lu);
            lower.push(f);
            reduced.push(w);
        }
        Some(Arrow {
            split,
            blocks,
            lower,
            reduced,
            schur,
        })
    }

    /// J⁻¹ y by block elimination and back substitution.
    fn apply(&self, y: &Mat<f64>) -> Option<Mat<f64>> {
        let pick = |rows: &[usize]| Mat::<f64>::from_fn(rows.len(), 1, |i, _| y[(rows[i], 0)]);
        let k = &self.split.coupling;
        let mut inner = Vec::with_capacity(self.blocks.len());
        let mut coupled = pick(k);
        for ((rows, lu), f) in self.split.inner.iter().zip(&self.blocks).zip(&self.lower) {
            let mut z = pick(rows);
            lu.solve(&mut z)?;
            matmul(&mut coupled, Accum::Add, f, &z, -1.0, Par::Seq);
            inner.push(z);
        }
        self.schur.solve(&mut coupled)?;
        let mut x = Mat::<f64>::zeros(y.nrows(), 1);
        for (c, &i) in k.iter().enumerate() {
            x[(i, 0)] = coupled[(c, 0)];
        }
        for (((rows, mut z), w), own) in (self.split.inner.iter().zip(inner))
            .zip(&self.reduced)
            .zip(&self.split.own)
        {
            let xk = coupled.subrows(own.start, own.len());
            matmul(&mut z, Accum::Add, w, xk, -1.0, Par::Seq);
            for (r, &i) in rows.iter().enumerate() {
                x[(i, 0)] = z[(r, 0)];
            }
        }
        Some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two blocks of 40 coupled by three rows of each, against the LU of the whole matrix.
    #[test]
    fn the_blocks_solve_what_the_whole_lu_solves() {
        let n = 80;
        let groups = [0..40, 40..40, 40..80];
        let coupled = [3, 17, 39, 41, 60, 79];
        let a = Mat::<f64>::from_fn(n, n, |i, j| {
            let same = (i < 40) == (j < 40);
            if i == j {
                4.0 + (i as f64).sin()
            } else if same || coupled.contains(&i) {
                ((i * 7 + j * 3) as f64).cos() / 10.0
            } else {
                0.0
            }
        });
        let split = Split::new(&a, &groups);
        assert_eq!(split.coupling, coupled);
        assert!(split.flops() < 0.5 * lu_flops(n));
        let b = Mat::<f64>::from_fn(n, 1, |i, _| (i as f64).cos());
        let mut whole = b.clone();
        DenseLu::new(a.clone()).and_then(|lu| lu.solve(&mut whole));
        let once = Arrow::new(&a, split).and_then(|s| s.apply(&b));
        assert!(once.is_some_and(|y| (&y - &whole).norm_l2() < 1e-12 * whole.norm_l2()));
        let mut x = b.clone();
        assert!(block_solve(&a, &groups, &mut x, 1e-14).is_some());
        assert!((&x - &whole).norm_l2() < 1e-13 * whole.norm_l2());
    }

    /// A regular matrix whose first block is singular (its row 0 reads only the coupling unknown
    /// 19): the refinement cannot meet the tolerance and the solve declines.
    #[test]
    fn a_singular_block_declines() {
        let n = 40;
        let a = Mat::<f64>::from_fn(n, n, |i, j| match (i, j) {
            (0, 19) | (19, 0) => 1.0,
            (19, 25) => 0.5,
            (0, 0) | (19, 19) => 0.0,
            _ if i == j => 1.0,
            _ => 0.0,
        });
        let groups = [0..20, 20..40];
        assert_eq!(Split::new(&a, &groups).coupling, vec![19]);
        let mut x = Mat::<f64>::from_fn(n, 1, |i, _| i as f64 + 1.0);
        assert!(block_solve(&a, &groups, &mut x, 1e-12).is_none());
        let mut whole = Mat::<f64>::from_fn(n, 1, |i, _| i as f64 + 1.0);
        assert!(DenseLu::new(a)
            .and_then(|lu| lu.solve(&mut whole))
            .is_some());
        assert!(whole.norm_l2().is_finite());
    }
}
