//! A sparse Cholesky factor whose refactorisation recomputes only what a change of values reaches.
//!
//! A left-looking supernodal factorisation computes supernode s from the values of A in its
//! columns and the columns of L of its descendants in the elimination tree. Changed entries in the
//! columns of supernode s therefore change s and its ancestors only: every other supernode keeps
//! its values. When a few entries change between two factorisations (the springs of the contact
//! points whose state changed, between two Newton steps), only that part of the tree is
//! recomputed (`docs/sparse-path.md`, "Partial refactorisation").
//!
//! The supernodal structure is faer's symbolic analysis, in the AMD order of the nodes
//! (`ordering::node_amd`). The numeric factorisation is done here, supernode by supernode, with
//! faer's dense kernels, and so is the solve, with plain loops. Both deal two groups of
//! independent subtrees to two workers when the tree is large enough (`subtrees`).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Accum, MatMut, MatRef, Par, Side};

use crate::ordering::{group_by, node_amd};
use crate::subtrees::Split;
use std::ops::Range;

/// Marks a supernode without a parent (a root of the elimination tree).
const ROOT: usize = usize::MAX;

/// Why a factorisation failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FactorError {
    /// The pivot of this column (in the factor's order) was not positive: the matrix is not
    /// positive definite.
    NotPositiveDefinite(usize),
    /// The work space could not be allocated.
    OutOfMemory,
}

/// The Cholesky factor L Lᵀ = P A Pᵀ of a symmetric positive definite matrix A with a fixed
/// pattern, given by its lower triangle, refactorised incrementally.
pub struct IncrementalCholesky {
    tree: SupernodalTree,
    /// A's values at the last factorisation, and its factor (valid if `factored`).
    values: Vec<f64>,
    l_values: Vec<f64>,
    factored: bool,
}

/// The symbolic analysis of a supernodal Cholesky factorisation (faer's), with what this
/// module's numeric factorisation needs: where A's entries go, the supernodes' tree and who
/// updates whom. The factor's values are kept by the caller, so that one analysis serves
/// several factors.
pub struct SupernodalTree {
    symbolic: SymbolicCholesky<usize>,
    /// Position k of the order holds column `perm_fwd[k]` of A.
    perm_fwd: Vec<usize>,
    /// Per permuted column j, the entries of P A Pᵀ's lower triangle in it: rows of the permuted
    /// matrix and positions in A's value array (`lower_ptr` delimits the columns).
    lower_ptr: Vec<usize>,
    /// 32-bit: these are the largest arrays of the analysis (twice the stiffness's entries).
    lower: Vec<(u32, u32)>,
    /// The supernode of every permuted column, and every supernode's parent (or [`ROOT`]).
    supernode_of: Vec<usize>,
    parent: Vec<usize>,
    /// Per supernode s, the descendants whose pattern has rows in s (`updaters_ptr` delimits).
    updaters_ptr: Vec<usize>,
    updaters: Vec<usize>,
    /// Two groups of subtrees factorised and solved side by side, if the tree gains from it.
    split: Option<Box<Split>>,
}

impl IncrementalCholesky {
    /// Analyses the lower triangle `pattern` of A (fill-reducing AMD order on the nodes,
    /// supernodal structure); `None` if the analysis fails (out of memory, index overflow).
    pub fn analyse(pattern: SymbolicSparseColMatRef<'_, usize>) -> Option<Self> {
        let (fwd, inv) = node_amd(pattern)?;
        let tree = SupernodalTree::analyse(pattern, (&fwd, &inv))?;
        let l_values = vec![0.0; tree.len_val()];
        Some(IncrementalCholesky {
            tree,
            values: Vec::new(),
            l_values,
            factored: false,
        })
    }

    /// Factorises A with the values `values` (in the analysed pattern's order), recomputing only
    /// the supernodes that the values changed since the last factorisation reach (all of them the
    /// first time, or after a failure). Returns the share of supernodes recomputed.
    pub fn factorize(&mut self, values: &[f64]) -> Result<f64, FactorError> {
        let dirty = match self.factored {
            true => self.tree.dirty(&self.values, values),
            false => None,
        };
        self.values.clear();
        self.values.extend_from_slice(values);
        self.factored = false;
        let share = self
            .tree
            .factorize_into(&self.values, &mut self.l_values, dirty.as_deref())?;
        self.factored = true;
        Ok(share)
    }

    /// Solves A x = rhs in place with the last factor; `None` if there is none or the solution is
    /// not finite.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Option<()> {
        if !self.factored || !self.tree.solve_in_place(&self.l_values, rhs) {
            return None;
        }
        rhs.iter().all(|v| v.is_finite()).then_some(())
    }
}

impl SupernodalTree {
    /// Analyses the lower triangle `pattern` of A in the order (fwd, inv) (position k holds
    /// column `fwd[k]`; column j sits at `inv[j]`); `None` if the analysis fails.
    pub fn analyse(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        order: (&[usize], &[usize]),
    ) -> Option<Self> {
        Self::analyse_with(pattern, order, None)
    }

    /// [`SupernodalTree::analyse`], splitting the tree for two workers above `min_work` flops
    /// (`None`: the default threshold).
    fn analyse_with(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        (fwd, inv): (&[usize], &[usize]),
        min_work: Option<f64>,
    ) -> Option<Self> {
        let n = pattern.ncols();
        let order = PermRef::new_checked(fwd, inv, n);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            SymmetricOrdering::Custom(order),
            CholeskySymbolicParams {
                // The numeric factorisation and the solve below work on supernodes.
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .ok()?;
        let (perm_fwd, perm_inv) = match symbolic.perm() {
            Some(perm) => (perm.arrays().0.to_vec(), perm.arrays().1.to_vec()),
            None => ((0..n).collect(), (0..n).collect()),
        };
        // The 32-bit positions must hold A's entries (else `None`: the caller takes faer's path).
        u32::try_from(pattern.row_idx().len().max(n)).ok()?;
        let (lower_ptr, lower) = permuted_lower(pattern, &perm_inv);
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            return None;
        };
        let supernode_of = supernode_of(sn);
        let parent: Vec<usize> = (0..sn.n_supernodes())
            .map(|s| {
                sn.supernode(s)
                    .pattern()
                    .first()
                    .map_or(ROOT, |&r| supernode_of[r])
            })
            .collect();
        let (updaters_ptr, updaters) = updaters(sn, &supernode_of);
        // A supernode's flops: its dense factor, its triangular solve and its updates.
        let work: Vec<f64> = (0..sn.n_supernodes())
            .map(|s| {
                let c = (sn.supernode_end()[s] - sn.supernode_begin()[s]) as f64;
                let r = sn.supernode(s).pattern().len() as f64;
                c * c * c / 3.0 + c * c * r + c * r * r
            })
            .collect();
        let cols = |s: usize| sn.supernode_begin()[s]..sn.supernode_end()[s];
        let split = Split::new(&parent, &work, ROOT, cols, min_work).map(Box::new);
        Some(SupernodalTree {
            symbolic,
            perm_fwd,
            lower_ptr,
            lower,
            supernode_of,
            parent,
            updaters_ptr,
            updaters,
            split,
        })
    }

    /// faer's symbolic analysis.
    pub fn symbolic(&self) -> &SymbolicCholesky<usize> {
        &self.symbolic
    }

    /// The number of values of the factor.
    pub fn len_val(&self) -> usize {
        self.symbolic.len_val()
    }

    /// The structure: `analyse` keeps supernodal analyses only.
    fn supernodal(&self) -> &SymbolicSupernodalCholesky<usize> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => sn,
            SymbolicCholeskyRaw::Simplicial(_) => unreachable!("analysed as supernodal"),
        }
    }

    /// Computes the factor of A with the values `values` into `l_values` (`len_val` of them):
    /// only the supernodes marked in `dirty` (from [`SupernodalTree::dirty`]; the others keep
    /// their values), or all of them. Returns the share recomputed.
    pub fn factorize_into(
        &self,
        values: &[f64],
        l_values: &mut [f64],
        dirty: Option<&[bool]>,
    ) -> Result<f64, FactorError> {
        let sn = self.supernodal();
        let n_super = sn.n_supernodes();
        let scratch = || Scratch::new(sn).ok_or(FactorError::OutOfMemory);
        let count = match &self.split {
            None => self.factor_all((values, l_values, 0), 0..n_super, dirty, &mut scratch()?)?,
            Some(split) => {
                let [a, b] = carve(sn, l_values, &split.groups);
                let group = |slices: Vec<(Range<usize>, &mut [f64])>| {
                    let mut scratch = scratch()?;
                    slices.into_iter().try_fold(0, |count, (range, slice)| {
                        let offset = sn.col_ptr_for_val()[range.start];
                        let at = (values, slice, offset);
                        Ok(count + self.factor_all(at, range, dirty, &mut scratch)?)
                    })
                };
                let (ca, cb) = rayon::join(|| group(a), || group(b));
                let rest = split.rest.iter().copied();
                let at = (values, l_values, 0);
                ca? + cb? + self.factor_all(at, rest, dirty, &mut scratch()?)?
            }
        };
        Ok(count as f64 / n_super.max(1) as f64)
    }

    /// Factorises the `supernodes` (in order, those marked in `dirty`, or all) into `l_values`,
    /// which holds the factor's values from position `offset` on; returns how many.
    fn factor_all(
        &self,
        (values, l_values, offset): (&[f64], &mut [f64], usize),
        supernodes: impl Iterator<Item = usize>,
        dirty: Option<&[bool]>,
        scratch: &mut Scratch,
    ) -> Result<usize, FactorError> {
        let sn = self.supernodal();
        let mut count = 0;
        for s in supernodes.filter(|&s| dirty.map_or(true, |d| d[s])) {
            self.factor_supernode(sn, s, (values, &mut *l_values, offset), scratch)?;
            count += 1;
        }
        Ok(count)
    }

    /// The supernodes to recompute when A's values change from `old` to `new`: those with a
    /// changed value in their columns, and their ancestors; `None` (all of them) if the lengths
    /// differ.
    pub fn dirty(&self, old: &[f64], new: &[f64]) -> Option<Vec<bool>> {
        if old.len() != new.len() {
            return None;
        }
        let mut dirty = vec![false; self.parent.len()];
        for (j, column) in self.lower_ptr.windows(2).enumerate() {
            let changed = self.lower[column[0]..column[1]]
                .iter()
                .any(|&(_, p)| new[p as usize].to_bits() != old[p as usize].to_bits());
            let mut s = if changed { self.supernode_of[j] } else { ROOT };
            while s != ROOT && !dirty[s] {
                dirty[s] = true;
                s = self.parent[s];
            }
        }
        Some(dirty)
    }

    /// Solves A x = rhs in place with the factor `l_values`; false (and `rhs` unchanged) if the
    /// sizes do not match.
    pub fn solve_in_place(&self, l_values: &[f64], rhs: &mut [f64]) -> bool {
        let sn = self.supernodal();
        if rhs.len() != sn.nrows() || l_values.len() != self.len_val() {
            return false;
        }
        // y = P rhs, L Lᵀ x = y, rhs = Pᵀ x.
        let mut x: Vec<f64> = self.perm_fwd.iter().map(|&i| rhs[i]).collect();
        let n_super = sn.n_supernodes();
        match &self.split {
            None => {
                forward(sn, l_values, &mut x, 0..n_super);
                backward(sn, l_values, &mut x, (0..n_super).rev());
            }
            Some(split) => split_solve(sn, split, l_values, &mut x),
        }
        for (&i, v) in self.perm_fwd.iter().zip(&x) {
            rhs[i] = *v;
        }
        true
    }

    /// Computes the columns of L of supernode `s` from A and its descendants' columns.
    fn factor_supernode(
        &self,
        sn: &SymbolicSupernodalCholesky<usize>,
        s: usize,
        (values, l_values, offset): (&[f64], &mut [f64], usize),
        scratch: &mut Scratch,
    ) -> Result<(), FactorError> {
        let (start, end) = (sn.supernode_begin()[s], sn.supernode_end()[s]);
        let pattern = sn.supernode(s).pattern();
        let ncols = end - start;
        for (i, &row) in pattern.iter().enumerate() {
            scratch.local[row] = ncols + i;
        }
        let val_ptr = sn.col_ptr_for_val();
        let (head, tail) = l_values.split_at_mut(val_ptr[s] - offset);
        let rows = ncols + pattern.len();
        let block = &mut tail[..val_ptr[s + 1] - val_ptr[s]];
        block.fill(0.0);
        for j in start..end {
            let column = &mut block[(j - start) * rows..(j - start + 1) * rows];
            for &(i, p) in &self.lower[self.lower_ptr[j]..self.lower_ptr[j + 1]] {
                let (i, p) = (i as usize, p as usize);
                column[if i < end { i - start } else { scratch.local[i] }] += values[p];
            }
        }
        for &d in &self.updaters[self.updaters_ptr[s]..self.updaters_ptr[s + 1]] {
            update(
                sn,
                d,
                (head, offset),
                (start, end),
                (&mut *block, rows),
                scratch,
            );
        }
        let ls = MatMut::from_column_major_slice_mut(block, rows, ncols);
        let (mut top, mut bottom) = ls.split_at_row_mut(ncols);
        cholesky_in_place(
            top.as_mut(),
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut scratch.mem),
            Default::default(),
        )
        .map_err(|e| match e {
            LltError::NonPositivePivot { index } => FactorError::NotPositiveDefinite(start + index),
        })?;
        solve_lower_triangular_in_place(top.as_ref(), bottom.as_mut().transpose_mut(), Par::Seq);
        for &row in pattern {
            scratch.local[row] = usize::MAX;
        }
        Ok(())
    }
}

/// The forward solve L y = x in place over the `supernodes` (in order). Each supernode's rows
/// below its diagonal block are gathered into `below` once, so that its columns are used as
/// contiguous slices.
fn forward(
    sn: &SymbolicSupernodalCholesky<usize>,
    l_values: &[f64],
    x: &mut [f64],
    supernodes: impl Iterator<Item = usize>,
) {
    let mut below = Vec::new();
    for s in supernodes {
        let (block, rows, cols, pattern) = block(sn, l_values, s);
        let start = sn.supernode_begin()[s];
        below.clear();
        below.resize(pattern.len(), 0.0);
        for j in 0..cols {
            let column = &block[j * rows..(j + 1) * rows];
            let xj = x[start + j] / column[j];
            x[start + j] = xj;
            for i in j + 1..cols {
                x[start + i] -= column[i] * xj;
            }
            for (b, l) in below.iter_mut().zip(&column[cols..]) {
                *b += l * xj;
            }
        }
        for (&row, b) in pattern.iter().zip(&below) {
            x[row] -= b;
        }
    }
}

/// The backward solve Lᵀ z = x in place over the `supernodes` (in reverse order of the tree).
fn backward(
    sn: &SymbolicSupernodalCholesky<usize>,
    l_values: &[f64],
    x: &mut [f64],
    supernodes: impl Iterator<Item = usize>,
) {
    let mut below = Vec::new();
    for s in supernodes {
        let (block, rows, cols, pattern) = block(sn, l_values, s);
        let start = sn.supernode_begin()[s];
        below.clear();
        below.extend(pattern.iter().map(|&row| x[row]));
        for j in (0..cols).rev() {
            let column = &block[j * rows..(j + 1) * rows];
            let mut xj = x[start + j];
            for i in j + 1..cols {
                xj -= column[i] * x[start + i];
            }
            xj -= dot(&column[cols..], &below);
            x[start + j] = xj / column[j];
        }
    }
}

/// The solve with the tree split: forward, the two groups side by side, each on its own buffer
/// holding its columns of x and zeros elsewhere, where its updates of the rest's rows add up;
/// then the rest forward and backward; then the groups backward, side by side, each reading
/// the rest's final values from its own copy of x. The groups' order of arithmetic does not
/// depend on the number of threads.
fn split_solve(
    sn: &SymbolicSupernodalCholesky<usize>,
    split: &Split,
    l_values: &[f64],
    x: &mut [f64],
) {
    let supernodes = |g: usize| split.groups[g].iter().flat_map(Clone::clone);
    let x0: &[f64] = x;
    let down = |g: usize| {
        let mut y: Vec<f64> = (0..x0.len())
            .map(|i| {
                if split.owner[i] == g as u8 + 1 {
                    x0[i]
                } else {
                    0.0
                }
            })
            .collect();
        forward(sn, l_values, &mut y, supernodes(g));
        y
    };
    let (ya, yb) = rayon::join(|| down(0), || down(1));
    for (i, v) in x.iter_mut().enumerate() {
        *v = match split.owner[i] {
            1 => ya[i],
            2 => yb[i],
            _ => (*v + ya[i]) + yb[i],
        };
    }
    forward(sn, l_values, x, split.rest.iter().copied());
    backward(sn, l_values, x, split.rest.iter().rev().copied());
    let x1: &[f64] = x;
    let up = |g: usize| {
        let mut y = x1.to_vec();
        backward(sn, l_values, &mut y, supernodes(g).rev());
        y
    };
    let (ya, yb) = rayon::join(|| up(0), || up(1));
    for (i, v) in x.iter_mut().enumerate() {
        match split.owner[i] {
            1 => *v = ya[i],
            2 => *v = yb[i],
            _ => {}
        }
    }
}

/// The factor's values of every range of `groups` (supernode ranges, disjoint), cut out of
/// `l_values` as disjoint slices, per group.
fn carve<'a>(
    sn: &SymbolicSupernodalCholesky<usize>,
    l_values: &'a mut [f64],
    groups: &[Vec<Range<usize>>; 2],
) -> [Vec<(Range<usize>, &'a mut [f64])>; 2] {
    let val_ptr = sn.col_ptr_for_val();
    let mut ranges: Vec<(usize, Range<usize>)> = groups
        .iter()
        .enumerate()
        .flat_map(|(g, rs)| rs.iter().map(move |r| (g, r.clone())))
        .collect();
    ranges.sort_by_key(|(_, r)| r.start);
    let mut out = [Vec::new(), Vec::new()];
    let (mut rest, mut at) = (l_values, 0);
    for (g, r) in ranges {
        let (_, tail) = rest.split_at_mut(val_ptr[r.start] - at);
        let (mine, tail) = tail.split_at_mut(val_ptr[r.end] - val_ptr[r.start]);
        out[g].push((r.clone(), mine));
        (rest, at) = (tail, val_ptr[r.end]);
    }
    out
}

/// Σ a_i b_i, in four interleaved partial sums so that the compiler can use vector
/// instructions (a single running sum fixes the order of the additions, and it cannot).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let rest: f64 = a4
        .remainder()
        .iter()
        .zip(b4.remainder())
        .map(|(x, y)| x * y)
        .sum();
    let mut sums = [0.0; 4];
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            sums[k] += x[k] * y[k];
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + rest
}

/// Supernode s's block of L (column-major), its rows and columns, and its rows below the
/// diagonal block.
fn block<'a>(
    sn: &'a SymbolicSupernodalCholesky<usize>,
    l_values: &'a [f64],
    s: usize,
) -> (&'a [f64], usize, usize, &'a [usize]) {
    let pattern = sn.supernode(s).pattern();
    let cols = sn.supernode_end()[s] - sn.supernode_begin()[s];
    let val_ptr = sn.col_ptr_for_val();
    (
        &l_values[val_ptr[s]..val_ptr[s + 1]],
        cols + pattern.len(),
        cols,
        pattern,
    )
}

/// Subtracts descendant `d`'s contribution L_d[rows ≥ start] L_d[rows in start..end]ᵀ from the
/// block `ls` of the supernode with columns `start..end` (lower triangle only).
fn update(
    sn: &SymbolicSupernodalCholesky<usize>,
    d: usize,
    (l_values, offset): (&[f64], usize),
    (start, end): (usize, usize),
    (ls, ls_rows): (&mut [f64], usize),
    scratch: &mut Scratch,
) {
    let d_ncols = sn.supernode_end()[d] - sn.supernode_begin()[d];
    let d_pattern = sn.supernode(d).pattern();
    let val_ptr = sn.col_ptr_for_val();
    let ld = MatRef::from_column_major_slice(
        &l_values[val_ptr[d] - offset..val_ptr[d + 1] - offset],
        d_ncols + d_pattern.len(),
        d_ncols,
    );
    let first = d_pattern.partition_point(|&r| r < start);
    let rows = &d_pattern[first..];
    let (nr, mid) = (rows.len(), rows.partition_point(|&r| r < end));
    let below = ld.subrows(d_ncols + first, nr);
    let product = &mut scratch.product[..nr * mid];
    matmul(
        MatMut::from_column_major_slice_mut(product, nr, mid),
        Accum::Replace,
        below,
        below.subrows(0, mid).transpose(),
        1.0,
        Par::Seq,
    );
    // Where each of the rows sits in the supernode's block.
    let at = &mut scratch.at;
    at.clear();
    at.extend(rows.iter().map(|&row| {
        if row < end {
            row - start
        } else {
            scratch.local[row]
        }
    }));
    // The lower triangle only: row ii of the product is at or below column jj's row.
    for jj in 0..mid {
        let column = &mut ls[at[jj] * ls_rows..(at[jj] + 1) * ls_rows];
        let src = &product[jj * nr..(jj + 1) * nr];
        for ii in jj..nr {
            column[at[ii]] -= src[ii];
        }
    }
}

/// Work space of the numeric factorisation, sized for the largest supernode.
struct Scratch {
    /// Position of a row inside the current supernode's block (`usize::MAX` outside it).
    local: Vec<usize>,
    /// A descendant's update before it is scattered, and where its rows go.
    product: Vec<f64>,
    at: Vec<usize>,
    /// faer's work space of the dense Cholesky factorisation.
    mem: MemBuffer,
}

impl Scratch {
    fn new(sn: &SymbolicSupernodalCholesky<usize>) -> Option<Self> {
        let mut rows = 0;
        let mut cols = 0;
        for s in 0..sn.n_supernodes() {
            let ncols = sn.supernode_end()[s] - sn.supernode_begin()[s];
            rows = rows.max(ncols + sn.supernode(s).pattern().len());
            cols = cols.max(ncols);
        }
        let req: StackReq = cholesky_in_place_scratch::<f64>(cols, Par::Seq, Default::default());
        Some(Scratch {
            local: vec![usize::MAX; sn.nrows()],
            product: vec![0.0; rows * cols],
            at: Vec::with_capacity(rows),
            mem: MemBuffer::try_new(req).ok()?,
        })
    }
}

/// The lower triangle of P A Pᵀ by permuted column: (permuted row, position in A's values), both
/// below 2³² (checked by the caller).
fn permuted_lower(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    perm_inv: &[usize],
) -> (Vec<usize>, Vec<(u32, u32)>) {
    let n = pattern.ncols();
    let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
    let permuted = |p: usize, c: usize| {
        let (i, j) = (perm_inv[row_idx[p]], perm_inv[c]);
        (i.max(j), i.min(j))
    };
    group_by(n, |emit| {
        for c in 0..n {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let (i, j) = permuted(p, c);
                emit(j, (i as u32, p as u32));
            }
        }
    })
}

/// The supernode of every (permuted) column.
fn supernode_of(sn: &SymbolicSupernodalCholesky<usize>) -> Vec<usize> {
    let mut of = vec![0; sn.nrows()];
    for s in 0..sn.n_supernodes() {
        of[sn.supernode_begin()[s]..sn.supernode_end()[s]].fill(s);
    }
    of
}

/// Per supernode s, the supernodes d < s whose pattern has a row among s's columns, in
/// increasing order (compressed: pointers and indices).
fn updaters(
    sn: &SymbolicSupernodalCholesky<usize>,
    supernode_of: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let n_super = sn.n_supernodes();
    let targets = |d: usize| {
        let mut last = ROOT;
        sn.supernode(d).pattern().iter().filter_map(move |&r| {
            let s = supernode_of[r];
            (s != last).then(|| {
                last = s;
                s
            })
        })
    };
    group_by(n_super, |emit| {
        for d in 0..n_super {
            targets(d).for_each(|s| emit(s, d));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{SparseColMat, Triplet};

    /// The lower triangle of a k × k grid's 5-point Laplacian plus `shift` on the diagonal, with
    /// the extra diagonal values `extra` (node, value).
    fn grid(k: usize, shift: f64, extra: &[(usize, f64)]) -> SparseColMat<usize, f64> {
        let mut trip = Vec::new();
        for i in 0..k {
            for j in 0..k {
                let p = i * k + j;
                let more: f64 = extra.iter().filter(|e| e.0 == p).map(|e| e.1).sum();
                trip.push(Triplet::new(p, p, 4.0 + shift + more));
                if j + 1 < k {
                    trip.push(Triplet::new(p + 1, p, -1.0));
                }
                if i + 1 < k {
                    trip.push(Triplet::new(p + k, p, -1.0));
                }
            }
        }
        SparseColMat::try_new_from_triplets(k * k, k * k, &trip).unwrap()
    }

    /// ‖A x − b‖ / ‖b‖ with A given by its lower triangle.
    fn residual(a: &SparseColMat<usize, f64>, x: &[f64], b: &[f64]) -> f64 {
        let mut ax = vec![0.0; x.len()];
        let (ptr, rows, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
        for c in 0..x.len() {
            for p in ptr[c]..ptr[c + 1] {
                let r = rows[p];
                ax[r] += val[p] * x[c];
                if r != c {
                    ax[c] += val[p] * x[r];
                }
            }
        }
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let diff: Vec<f64> = ax.iter().zip(b).map(|(p, q)| p - q).collect();
        norm(&diff) / norm(b)
    }

    fn solve(f: &IncrementalCholesky, b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        f.solve_in_place(&mut x).unwrap();
        x
    }

    #[test]
    fn a_partial_refactorisation_solves_the_changed_matrix() {
        let k = 40;
        let b: Vec<f64> = (0..k * k).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let a = grid(k, 0.01, &[]);
        let mut f = IncrementalCholesky::analyse(a.symbolic()).unwrap();
        assert_eq!(f.factorize(a.val()), Ok(1.0));
        assert!(residual(&a, &solve(&f, &b), &b) < 1e-12);
        // Stiff springs at a few nodes in one corner: only part of the tree is recomputed.
        let changed = grid(k, 0.01, &[(0, 1e8), (1, 1e8), (k, 3e7)]);
        let share = f.factorize(changed.val()).unwrap();
        assert!(share > 0.0 && share < 0.5, "share {share}");
        let x = solve(&f, &b);
        assert!(residual(&changed, &x, &b) < 1e-10);
        let mut fresh = IncrementalCholesky::analyse(changed.symbolic()).unwrap();
        fresh.factorize(changed.val()).unwrap();
        let y = solve(&fresh, &b);
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(x
            .iter()
            .zip(&y)
            .all(|(p, q)| (p - q).abs() <= 1e-12 * scale));
        // The same values again: nothing to recompute, the same solution.
        assert_eq!(f.factorize(changed.val()), Ok(0.0));
        assert_eq!(solve(&f, &b), x);
        // And back: the factor of the first matrix.
        f.factorize(a.val()).unwrap();
        assert!(residual(&a, &solve(&f, &b), &b) < 1e-12);
    }

    #[test]
    fn a_split_tree_factorises_as_the_whole_one_and_solves_alike() {
        let k = 40;
        let a = grid(k, 0.01, &[]);
        let (fwd, inv) = node_amd(a.symbolic()).unwrap();
        let analyse = |min| SupernodalTree::analyse_with(a.symbolic(), (&fwd, &inv), Some(min));
        let (whole, split) = (analyse(f64::INFINITY).unwrap(), analyse(0.0).unwrap());
        assert!(whole.split.is_none() && split.split.is_some());
        let factor = |tree: &SupernodalTree, values: &[f64], l: &mut Vec<f64>, dirty| {
            l.resize(tree.len_val(), 0.0);
            tree.factorize_into(values, l, dirty).unwrap()
        };
        let (mut lw, mut ls) = (Vec::new(), Vec::new());
        factor(&whole, a.val(), &mut lw, None);
        factor(&split, a.val(), &mut ls, None);
        // Every supernode's arithmetic is the same, whoever does it.
        assert_eq!(lw, ls);
        // So is a partial refactorisation's, with a change in one group and in the rest.
        let changed = grid(k, 0.01, &[(0, 1e8), (k * k - 1, 5e7)]);
        let dirty = whole.dirty(a.val(), changed.val()).unwrap();
        assert!(dirty.iter().any(|d| !d));
        factor(&whole, changed.val(), &mut lw, Some(&dirty));
        factor(&split, changed.val(), &mut ls, Some(&dirty));
        assert_eq!(lw, ls);
        let b: Vec<f64> = (0..k * k).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let (mut xw, mut xs) = (b.clone(), b.clone());
        assert!(whole.solve_in_place(&lw, &mut xw) && split.solve_in_place(&ls, &mut xs));
        assert!(residual(&changed, &xs, &b) < 1e-10);
        let scale = xw.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(xw
            .iter()
            .zip(&xs)
            .all(|(p, q)| (p - q).abs() <= 1e-12 * scale));
    }

    #[test]
    fn an_indefinite_matrix_is_refused_and_the_next_one_factorised_whole() {
        let k = 12;
        let a = grid(k, 0.0, &[]);
        let mut f = IncrementalCholesky::analyse(a.symbolic()).unwrap();
        f.factorize(a.val()).unwrap();
        let indefinite = grid(k, 0.0, &[(5, -50.0)]);
        assert!(matches!(
            f.factorize(indefinite.val()),
            Err(FactorError::NotPositiveDefinite(_))
        ));
        assert!(f.solve_in_place(&mut vec![1.0; k * k]).is_none());
        let b = vec![1.0; k * k];
        assert_eq!(f.factorize(a.val()), Ok(1.0));
        assert!(residual(&a, &solve(&f, &b), &b) < 1e-12);
    }
}
