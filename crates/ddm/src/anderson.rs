//! Anderson acceleration of the interface fixed point, in the IQN-ILS form of partitioned
//! multiphysics coupling (Degroote, Bathe & Vierendeels 2009; Walker & Ni 2011).
//!
//! The DD step is a map x̃ = G(x) of the interface state x (the normal displacements of all
//! contact points), with residual r = G(x) − x. From the differences of the last residuals and
//! outputs, V = `[Δr]`, W = `[Δx̃]` (newest first), the next state is
//!   x^{k+1} = x̃^k + W α,   α = argmin ‖V α + r^k‖,
//! the secant (multi-secant) update that makes the linearised residual vanish on the span of the
//! observed differences. On a linear map with unlimited memory this is GMRES on I − G.
//!
//! - The least-squares problem is solved by a modified Gram–Schmidt QR of V, newest column first.
//!   A column whose orthogonal part is below [`FILTER`] times its own length is nearly dependent on
//!   newer ones and is dropped for good (the QR2 filter of Haelterman et al. 2016): that keeps α
//!   bounded when the iteration stagnates in a few directions.
//! - At most `depth` columns are kept; older ones are dropped.
//! - The interface loads t (which reproduce the bodies' fields) are combined with the same
//!   coefficients, so the affine relation between a body's normal displacements and its loads,
//!   which every output satisfies, also holds for the accelerated state.
//! - Without columns (the first step) the state is relaxed with γ: x^{k+1} = x^k + γ r^k.

use std::collections::VecDeque;

/// Relative size below which a column's orthogonal part counts as dependent.
pub const FILTER: f64 = 1e-3;

/// One stored secant pair: Δr, Δx̃ and Δt̃.
struct Column {
    dr: Vec<f64>,
    dx: Vec<f64>,
    dt: Vec<f64>,
}

/// The accelerator's memory during one solve.
pub struct Anderson {
    depth: usize,
    /// Residual, output and output loads of the previous step.
    last: Option<(Vec<f64>, Vec<f64>, Vec<f64>)>,
    /// Secant columns, newest first.
    columns: VecDeque<Column>,
}

impl Anderson {
    /// An empty memory of at most `depth` columns.
    pub fn new(depth: usize) -> Anderson {
        Anderson {
            depth,
            last: None,
            columns: VecDeque::new(),
        }
    }

    /// Number of columns in use.
    pub fn len(&self) -> usize {
        self.columns.len()
    }

    /// True if no column is stored.
    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// Forgets every secant pair (after a change that makes them meaningless).
    pub fn reset(&mut self) {
        self.last = None;
        self.columns.clear();
    }

    /// From the state (`x`, `t`) and the map's outputs (`xt`, `tt`), writes the next state into
    /// `x` and `t`.
    pub fn advance(&mut self, x: &mut [f64], t: &mut [f64], xt: &[f64], tt: &[f64], gamma: f64) {
        let r: Vec<f64> = xt.iter().zip(x.iter()).map(|(a, b)| a - b).collect();
        if let Some((r0, x0, t0)) = self.last.take() {
            self.columns.push_front(Column {
                dr: difference(&r, &r0),
                dx: difference(xt, &x0),
                dt: difference(tt, &t0),
            });
            self.columns.truncate(self.depth);
        }
        self.last = Some((r.clone(), xt.to_vec(), tt.to_vec()));
        let alpha = self.least_squares(&r);
        if self.columns.is_empty() {
            for i in 0..x.len() {
                x[i] += gamma * r[i];
                t[i] = gamma * tt[i] + (1.0 - gamma) * t[i];
            }
            return;
        }
        x.copy_from_slice(xt);
        t.copy_from_slice(tt);
        for (col, a) in self.columns.iter().zip(&alpha) {
            axpy(*a, &col.dx, x);
            axpy(*a, &col.dt, t);
        }
    }

    /// α = argmin ‖V α + r‖ by modified Gram–Schmidt, dropping dependent columns.
    fn least_squares(&mut self, r: &[f64]) -> Vec<f64> {
        let mut q: Vec<Vec<f64>> = Vec::with_capacity(self.columns.len());
        let mut rmat: Vec<Vec<f64>> = Vec::with_capacity(self.columns.len());
        let mut kept = Vec::with_capacity(self.columns.len());
        for (i, col) in self.columns.iter().enumerate() {
            let mut v = col.dr.clone();
            let mut proj = Vec::with_capacity(q.len() + 1);
            for qj in &q {
                let h = dot(qj, &v);
                axpy(-h, qj, &mut v);
                proj.push(h);
            }
            let (orth, len) = (norm(&v), norm(&col.dr));
            // Also drops a NaN column: it is not above the filter.
            if orth.partial_cmp(&(FILTER * len)) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            v.iter_mut().for_each(|x| *x /= orth);
            proj.push(orth);
            q.push(v);
            rmat.push(proj);
            kept.push(i);
        }
        let mut index = 0;
        self.columns.retain(|_| {
            let keep = kept.contains(&index);
            index += 1;
            keep
        });
        // R α = −Qᵀ r, R upper triangular with column i in rmat[i].
        let n = q.len();
        let mut alpha: Vec<f64> = q.iter().map(|qi| -dot(qi, r)).collect();
        for i in (0..n).rev() {
            alpha[i] /= rmat[i][i];
            for l in 0..i {
                alpha[l] -= rmat[i][l] * alpha[i];
            }
        }
        alpha
    }
}

fn difference(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    y.iter_mut().zip(x).for_each(|(yi, xi)| *yi += a * xi);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear contraction with n distinct eigenvalues, Anderson with memory ≥ n reaches the
    /// fixed point in about n + 1 steps (it is then GMRES), while the plain iteration crawls.
    #[test]
    fn solves_a_slow_linear_fixed_point_in_few_steps() {
        let n = 6;
        let lambda: Vec<f64> = (0..n).map(|i| 0.999 - 0.1 * i as f64).collect();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let exact: Vec<f64> = (0..n).map(|i| b[i] / (1.0 - lambda[i])).collect();
        let g = |x: &[f64]| -> Vec<f64> { (0..n).map(|i| lambda[i] * x[i] + b[i]).collect() };
        let mut acc = Anderson::new(20);
        let (mut x, mut t) = (vec![0.0; n], vec![0.0; n]);
        let mut steps = 0;
        while steps < 50 {
            let xt = g(&x);
            let err = difference(&xt, &x);
            if norm(&err) <= 1e-9 * norm(&xt) {
                break;
            }
            let tt = xt.clone();
            acc.advance(&mut x, &mut t, &xt, &tt, 1.0);
            steps += 1;
        }
        assert!(steps <= n + 2, "took {steps} steps");
        let err = norm(&difference(&x, &exact)) / norm(&exact);
        assert!(err < 1e-8, "error {err}");
        // The loads follow the same combination as the states.
        assert!(norm(&difference(&t, &x)) <= 1e-9 * norm(&x));
    }
}
