//! The null space of a sparse symmetric positive semidefinite matrix G: the rigid motions that
//! the closed contact points leave free, for many bodies at the cost of G's band instead of a
//! dense eigensolver of all modes (`docs/interface-newton.md`, "Rigid motions").
//!
//! An LDLᵀ factorisation in G's envelope, without pivoting, eliminates the modes whose pivot is
//! a fair share of their own diagonal term (at least [`SAFE`] of it): G's semidefiniteness then
//! bounds every term of L by that diagonal, so rounding stays at its own size. The other modes
//! are deferred: free modes (whose pivot vanishes), and weakly held ones. The null space is
//! that of their Schur complement S = G_DD − G_DE G_EE⁻¹ G_ED (a small dense matrix), by the
//! symmetric eigensolver with the threshold of the dense method; a null vector y of S extends to
//! G's as (−G_EE⁻¹ G_ED y, y). A mode with no entry at all is free by itself.
//!
//! G is semidefinite for balanced pairs (a sum of s sᵀ). An own-side G that happens to be
//! symmetric need not be; its negative pivots are deferred like the small ones, and S's
//! eigensolver, which looks at |λ|, decides as the dense method did.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// A pivot below this fraction of its mode's diagonal term defers the mode to the Schur
/// complement.
const SAFE: f64 = 1e-3;

/// The lower triangle in its envelope: row i holds columns `first[i] ..= i`.
#[derive(Clone)]
struct Envelope {
    first: Vec<usize>,
    rows: Vec<Vec<f64>>,
}

impl Envelope {
    /// The lower triangle of the k × k matrix given by its (row, column, value) entries
    /// (duplicates add up; entries above the diagonal are ignored).
    fn new(k: usize, entries: &[(usize, usize, f64)]) -> Envelope {
        let mut first: Vec<usize> = (0..k).collect();
        for &(a, b, _) in entries.iter().filter(|e| e.1 <= e.0) {
            first[a] = first[a].min(b);
        }
        let mut rows: Vec<Vec<f64>> = (0..k).map(|i| vec![0.0; i - first[i] + 1]).collect();
        for &(a, b, v) in entries.iter().filter(|e| e.1 <= e.0) {
            rows[a][b - first[a]] += v;
        }
        Envelope { first, rows }
    }

    fn len(&self) -> usize {
        self.first.len()
    }

    /// Entry (i, j) of the lower triangle, j ≤ i.
    fn get(&self, i: usize, j: usize) -> f64 {
        if j < self.first[i] {
            0.0
        } else {
            self.rows[i][j - self.first[i]]
        }
    }

    /// Entry (i, j) of the symmetric matrix.
    fn sym(&self, i: usize, j: usize) -> f64 {
        self.get(i.max(j), i.min(j))
    }
}

/// The factor of G_EE: unit lower triangular L in G's envelope and the pivots d; a deferred
/// mode has d = 0 and a zero column in L. A pivot at most the threshold of the null space is
/// deferred whatever its diagonal term: a free mode's terms can be rounding alone.
struct Factor {
    l: Envelope,
    d: Vec<f64>,
}

impl Factor {
    /// The factor of `g`'s modes whose pivot exceeds `tol` and [`SAFE`] of their diagonal term.
    fn new(g: &Envelope, tol: f64) -> Factor {
        let mut f = Factor {
            l: g.clone(),
            d: vec![0.0; g.len()],
        };
        for i in 0..g.len() {
            f.row(i, g.get(i, i), tol);
        }
        f
    }

    /// Row i of L and its pivot (Crout): u_ij = G_ij − Σ_p u_ip L_jp is L_ij d_j, then
    /// L_ij = u_ij / d_j and d_i = G_ii − Σ_j u_ij L_ij.
    fn row(&mut self, i: usize, diagonal: f64, tol: f64) {
        let fi = self.l.first[i];
        let mut row = std::mem::take(&mut self.l.rows[i]);
        for j in fi..i {
            let lo = fi.max(self.l.first[j]);
            let dot: f64 = (lo..j).map(|p| row[p - fi] * self.l.get(j, p)).sum();
            row[j - fi] -= dot;
        }
        let mut pivot = row[i - fi];
        for j in fi..i {
            let lij = if self.d[j] == 0.0 {
                0.0
            } else {
                row[j - fi] / self.d[j]
            };
            pivot -= row[j - fi] * lij;
            row[j - fi] = lij;
        }
        row[i - fi] = 1.0;
        self.d[i] = if pivot >= SAFE * diagonal && pivot > tol {
            pivot
        } else {
            0.0
        };
        self.l.rows[i] = row;
    }

    fn deferred(&self, i: usize) -> bool {
        self.d[i] == 0.0
    }

    /// x = G_EE⁻¹ b on the eliminated modes (0 on the deferred ones).
    fn solve(&self, mut x: Vec<f64>) -> Vec<f64> {
        let k = x.len();
        for i in 0..k {
            if self.deferred(i) {
                x[i] = 0.0;
                continue;
            }
            let fi = self.l.first[i];
            let dot: f64 = (fi..i).map(|j| self.l.rows[i][j - fi] * x[j]).sum();
            x[i] -= dot;
        }
        for i in 0..k {
            if !self.deferred(i) {
                x[i] /= self.d[i];
            }
        }
        for r in (0..k).rev() {
            if self.deferred(r) {
                continue;
            }
            let fr = self.l.first[r];
            for i in fr..r {
                x[i] -= self.l.rows[r][i - fr] * x[r];
            }
        }
        x
    }
}

/// A basis (unit vectors) of the null space of the symmetric positive semidefinite k × k matrix
/// with the lower-triangle `entries`: the directions whose eigenvalue is at most `tol`, as the
/// dense eigensolver of `newton.rs` found them.
pub(super) fn null_space(k: usize, entries: &[(usize, usize, f64)], tol: f64) -> Vec<DVector<f64>> {
    let g = Envelope::new(k, entries);
    let factor = Factor::new(&g, tol);
    // Each mode's nonzero entries of G (both triangles).
    let mut adjacent: Vec<Vec<(usize, f64)>> = vec![Vec::new(); k];
    for i in 0..k {
        for (j, &v) in (g.first[i]..=i).zip(&g.rows[i]).filter(|e| *e.1 != 0.0) {
            adjacent[i].push((j, v));
            if j != i {
                adjacent[j].push((i, v));
            }
        }
    }
    // Deferred modes with entries; a mode without any is free by itself.
    let (mut free, mut deferred) = (Vec::new(), Vec::new());
    for i in (0..k).filter(|&i| factor.deferred(i)) {
        if adjacent[i].is_empty() {
            let mut e = DVector::zeros(k);
            e[i] = 1.0;
            free.push(e);
        } else {
            deferred.push(i);
        }
    }
    // G_EE⁻¹ G_ED, a column per deferred mode, and S = G_DD − G_DE G_EE⁻¹ G_ED.
    let columns: Vec<Vec<f64>> = deferred
        .iter()
        .map(|&q| {
            let mut b = vec![0.0; k];
            adjacent[q].iter().for_each(|&(i, v)| b[i] = v);
            factor.solve(b)
        })
        .collect();
    let r = deferred.len();
    let s = DMatrix::<f64>::from_fn(r, r, |a, b| {
        let coupling: f64 = adjacent[deferred[a]]
            .iter()
            .map(|&(i, v)| v * columns[b][i])
            .sum();
        g.sym(deferred[a], deferred[b]) - coupling
    });
    if r == 0 {
        return free;
    }
    // S's entries carry the rounding of the solves, about ε ‖G‖ ‖x_a‖ ‖x_b‖ for the columns
    // x = G_EE⁻¹ G_ED: an eigenvalue within ten times that is zero as well.
    let largest = columns
        .iter()
        .map(|x| x.iter().map(|v| v * v).sum::<f64>())
        .fold(0.0, f64::max);
    let norm = (0..k).map(|i| g.get(i, i)).fold(0.0, f64::max);
    let tol = tol.max(10.0 * f64::EPSILON * norm * largest);
    let eig = SymmetricEigen::new(s);
    for (q, _) in eig
        .eigenvalues
        .iter()
        .enumerate()
        .filter(|(_, &l)| l.abs() <= tol)
    {
        let y = eig.eigenvectors.column(q);
        let mut x = DVector::<f64>::zeros(k);
        for (a, &p) in deferred.iter().enumerate() {
            x[p] = y[a];
            for (xi, c) in x.iter_mut().zip(&columns[a]) {
                *xi -= y[a] * c;
            }
        }
        x /= x.norm();
        free.push(x);
    }
    free
}

#[cfg(test)]
mod tests {
    use super::*;

    /// G = Σ s sᵀ over sparse rows s, as lower-triangle entries and as a dense matrix.
    fn gram(k: usize, rows: &[Vec<(usize, f64)>]) -> (Vec<(usize, usize, f64)>, DMatrix<f64>) {
        let mut dense = DMatrix::<f64>::zeros(k, k);
        let mut entries = Vec::new();
        for s in rows {
            for &(a, x) in s {
                for &(b, y) in s {
                    dense[(a, b)] += x * y;
                    if b <= a {
                        entries.push((a, b, x * y));
                    }
                }
            }
        }
        (entries, dense)
    }

    /// Pseudo-random numbers in (−1, 1), reproducible.
    fn numbers(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    /// The null space agrees with the dense eigensolver's (eigenvalues below the same
    /// threshold): the same dimension, and every vector is annihilated by G and lies in the
    /// eigensolver's null space. Returns the dimension.
    fn agrees(k: usize, rows: &[Vec<(usize, f64)>]) -> usize {
        let (entries, dense) = gram(k, rows);
        let scale = (0..k).map(|a| dense[(a, a)]).fold(0.0, f64::max);
        let tol = 1e-10 * scale;
        let found = null_space(k, &entries, tol);
        let eig = SymmetricEigen::new(dense.clone());
        let zero: Vec<DVector<f64>> = (0..k)
            .filter(|&q| eig.eigenvalues[q].abs() <= tol)
            .map(|q| eig.eigenvectors.column(q).into_owned())
            .collect();
        assert_eq!(found.len(), zero.len(), "null space dimension");
        for x in &found {
            let gx = (&dense * x).norm();
            assert!(gx <= 1e-12 * scale.max(1.0), "G x = {gx:e}");
            let mut rest = x.clone();
            for z in &zero {
                rest -= z * z.dot(x);
            }
            assert!(
                rest.norm() <= 1e-9,
                "outside the eigen null space: {}",
                rest.norm()
            );
        }
        found.len()
    }

    #[test]
    fn a_chain_held_at_one_end_has_no_null_space_and_one_freed_link_frees_the_rest() {
        // Modes 0..n of a chain: row i ties mode i to mode i + 1; mode 0 is tied down.
        let n = 200;
        let mut rng = numbers(1);
        let mut rows: Vec<Vec<(usize, f64)>> = vec![vec![(0, 1.0 + rng().abs())]];
        for i in 0..n - 1 {
            rows.push(vec![(i, 1.0 + 0.1 * rng()), (i + 1, -1.0 - 0.1 * rng())]);
        }
        assert_eq!(agrees(n, &rows), 0);
        // Without the link 99–100, modes 100.. move together, freely.
        rows.remove(100);
        assert_eq!(agrees(n, &rows), 1);
    }

    #[test]
    fn a_grid_with_free_blocks_and_coupled_pairs() {
        // 3 modes per block on a 6 × 6 grid of blocks; each link ties two random
        // combinations of neighbours' modes (rank one each); some blocks have no link.
        for seed in 1..=8 {
            grid(seed);
        }
    }

    fn grid(seed: u64) {
        let (side, per) = (6, 3);
        let k = side * side * per;
        let mut rng = numbers(seed);
        let mut rows = Vec::new();
        for bx in 0..side {
            for by in 0..side {
                let a = (bx * side + by) * per;
                if (bx + by) % 5 == 4 {
                    continue;
                }
                for (nx, ny) in [(bx + 1, by), (bx, by + 1)] {
                    if nx < side && ny < side && (nx + ny) % 5 != 4 {
                        let b = (nx * side + ny) * per;
                        for _ in 0..2 {
                            let mut s: Vec<(usize, f64)> =
                                (0..per).map(|m| (a + m, rng())).collect();
                            s.extend((0..per).map(|m| (b + m, rng())));
                            rows.push(s);
                        }
                    }
                }
            }
        }
        assert!(agrees(k, &rows) > 0);
    }

    /// A mode whose entries are rounding alone (a random wall's block, G_11 = 1.5e−31 beside
    /// G_00 = 64) is free, although its pivot is all of its diagonal term.
    #[test]
    fn a_mode_held_by_rounding_alone_is_free() {
        let rows = vec![vec![(0, 8.0), (1, -2.8e-33)], vec![(1, 3.9e-16)]];
        assert_eq!(agrees(2, &rows), 1);
    }

    #[test]
    fn a_zero_matrix_frees_every_mode() {
        assert_eq!(agrees(5, &[]), 5);
    }
}
