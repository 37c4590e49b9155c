//! The Newton step: the bordered system [J Z; Zᵀ 0] [δ; μ] = [−R; 0] assembled from the
//! bodies' responses (dense blocks, or the sparse bodies' own rows) and solved by the symmetric
//! form (`super::primal`) where it applies, else by LU (`super::linear`).

use faer::sparse::Triplet;
use faer::Mat;
use rayon::prelude::*;

use super::algebra::{dot, norm, pin_points};
use super::blocks::block_solve;
use super::linear::{dense_matrix, lu_solve_in_place, sparse_solve, LuCache};
use super::primal::PrimalCache;
use super::system::{Evaluation, System};
use crate::contact::Status;
use crate::exchange::share_slices;
use crate::shared_rows::BodyPart;

/// The fill (entries / n²) from which the Newton system is factorised as a dense matrix: two
/// bodies in contact fill half of it or more, and then the sparse LU does about the dense flops
/// with more overhead; a chain of bodies stays block-sparse, well below.
const DENSE_FILL: f64 = 1.0 / 3.0;

/// The sets of a Newton step: the points J treats as closed, the frictional points' statuses
/// and their tangential displacements g (both empty without friction).
pub(super) type Sets<'x> = (&'x [bool], &'x [Status], &'x [f64]);

/// What the Newton steps of one run keep for the next: the LU's analysis, the symmetric form's
/// factor, and the last B δ the bodies computed with its δ (U is affine in τ, U(τ + δ) =
/// U(τ) + B δ, so the full step's state needs no body solve of its own).
#[derive(Default)]
pub(super) struct Caches {
    pub(super) lu: LuCache,
    pub(super) primal: PrimalCache,
    pub(super) applied: Option<(Vec<f64>, Vec<f64>)>,
}

impl System<'_> {
    /// The evaluation at `next` = τ + δ from the one at τ: U(τ) + B δ where the bodies computed
    /// B δ for this δ (the step's residual), else fresh.
    pub(super) fn evaluate_step(
        &self,
        applied: &Option<(Vec<f64>, Vec<f64>)>,
        next: &[f64],
        at_tau: &Evaluation,
        delta: &[f64],
    ) -> Evaluation {
        let known = applied.as_ref().and_then(|(d, bd)| {
            let same = d.len() == delta.len()
                && d.iter().zip(delta).all(|(a, b)| a.to_bits() == b.to_bits());
            same.then(|| at_tau.u.iter().zip(bd).map(|(u, b)| u + b).collect())
        });
        match known {
            Some(u) => self.evaluation(next, u),
            None => self.evaluate(next),
        }
    }

    /// The Newton step: solves [J Z; Zᵀ 0] [δ; μ] = [−R; 0], by the symmetric form where it
    /// applies (`primal`), else by LU.
    ///
    /// The symmetric form refines its step against the true J until the residual is at most
    /// `eta` ‖R‖ (an inexact Newton step); the LU refines while that halves the residual.
    /// `status`: the frictional points' statuses in J (empty without friction).
    pub(super) fn step(
        &self,
        caches: &mut Caches,
        (chi, status, g): Sets<'_>,
        z: &[Vec<f64>],
        r: &[f64],
        eta: f64,
    ) -> Option<Vec<f64>> {
        let Caches {
            lu,
            primal,
            applied,
        } = caches;
        if self.symmetric {
            if let Some(delta) = self.symmetric_step(primal, applied, chi, z, r, eta * norm(r)) {
                return Some(delta);
            }
        }
        let m = self.len();
        let mut trip = Vec::new();
        let n = self.sparse_body_rows(&mut trip).max(m + z.len());
        let first_sparse = self.sparse_offset.iter().flatten().min().copied();
        self.interface_rows(&mut trip, (chi, status, g), first_sparse.is_some());
        // With sparse bodies a dense row Zᵀδ = 0 would fill the whole sparse LU: pin one point
        // per kernel vector instead and project the step afterwards (J z = 0, so the projected
        // step solves the same system).
        let pins = first_sparse.map(|_| pin_points(z));
        self.kernel_rows(&mut trip, z, pins.as_deref(), first_sparse);
        let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| if i < m { -r[i] } else { 0.0 });
        if trip.len() as f64 >= DENSE_FILL * (n as f64) * (n as f64) {
            let a = dense_matrix(&trip, n);
            drop(trip);
            // Friction: by the bodies' blocks where few points couple them (`blocks`). The
            // frictionless steps keep the whole LU, and with it their bits.
            let groups: Vec<_> = (0..self.interface.body_range.len())
                .map(|b| self.range(b))
                .collect();
            let by_blocks = self.friction && n == m;
            if !(by_blocks && block_solve(&a, &groups, &mut rhs, eta).is_some()) {
                lu_solve_in_place(a, &mut rhs)?;
            }
        } else {
            let cache = pins.as_ref().map(|_| lu);
            // Refinement against the true J (B applied by the bodies' own solves): the coupled
            // matrix's residual is a poor measure of the error in δ.
            let pinned = pins.as_deref();
            let mut residual =
                |x: &Mat<f64>| self.bordered_residual(applied, (chi, status, g), z, pinned, r, x);
            let refine: Option<&mut dyn FnMut(&Mat<f64>) -> Option<Mat<f64>>> =
                pins.as_ref().map(|_| &mut residual as _);
            sparse_solve(trip, n, &mut rhs, cache, refine)?;
        }
        let mut delta: Vec<f64> = (0..m).map(|i| rhs[(i, 0)]).collect();
        if pins.is_some() {
            for e in z {
                let d = dot(e, &delta);
                delta.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
            }
        }
        delta.iter().all(|v| v.is_finite()).then_some(delta)
    }

    /// Pushes the sparse bodies' rows: their reduced unknowns δu and the rows
    /// K₀δu − N D₀ δτ = 0 stand for δU. Returns the columns they take (0 without sparse bodies).
    fn sparse_body_rows(&self, trip: &mut Vec<Triplet<usize, usize, f64>>) -> usize {
        let mut n = 0;
        for (b, part) in self.parts.iter().enumerate() {
            let (Some(offset), Some(free)) = (self.sparse_offset[b], part.sparse_free()) else {
                continue;
            };
            let at = (offset, self.range(b).start);
            match (part, self.bodies[b].as_ref()) {
                (BodyPart::Remote(rows), _) => rows.replay(at, trip),
                (_, Some(body)) => {
                    if let Some(s) = body.sparse() {
                        s.push_body_rows(body.operator(), body.reference_springs(), at, trip);
                    }
                }
                (_, None) => {}
            }
            n = n.max(offset + free);
        }
        n
    }

    /// Pushes the rows of J for the closed set `chi`, with the open entries as zeros too where
    /// `sparse` (the sparse LU's pattern).
    fn interface_rows(
        &self,
        trip: &mut Vec<Triplet<usize, usize, f64>>,
        (chi, status, g): Sets<'_>,
        sparse: bool,
    ) {
        for (j, p) in self.interface.points.iter().enumerate() {
            trip.push(Triplet::new(j, j, 1.0));
            if self.weightless[j] {
                continue;
            }
            if self.balanced[j] {
                let combination = self.balanced_row(j, (chi, status, g), sparse);
                self.push_rows(trip, j, &combination);
            } else if sparse && p.has_partner() {
                // Both the closed and the open entries (one set zero): the pattern, and with it
                // the LU's symbolic analysis, stays the same while the closed set changes.
                let closed = if chi[j] { 1.0 } else { 0.0 };
                for &(k, c) in &p.partner {
                    self.push_row(trip, j, k, closed * c);
                }
                self.push_row(trip, j, j, closed - 1.0);
            } else if chi[j] {
                for &(k, c) in &p.partner {
                    self.push_row(trip, j, k, c);
                }
            } else {
                self.push_row(trip, j, j, -1.0);
            }
        }
    }

    /// Pushes the kernel's border: the columns Z, and either the rows Zᵀ or one pinned point per
    /// kernel vector (`pins`); identity rows for the sparse bodies' unused multiplier columns
    /// (fewer kernel vectors than the bound) keep the system regular.
    fn kernel_rows(
        &self,
        trip: &mut Vec<Triplet<usize, usize, f64>>,
        z: &[Vec<f64>],
        pins: Option<&[usize]>,
        first_sparse: Option<usize>,
    ) {
        let m = self.len();
        for (q, zq) in z.iter().enumerate() {
            for (j, &v) in zq.iter().enumerate().filter(|(_, v)| **v != 0.0) {
                trip.push(Triplet::new(j, m + q, v));
                if pins.is_none() {
                    trip.push(Triplet::new(m + q, j, v));
                }
            }
            if let Some(p) = pins {
                trip.push(Triplet::new(m + q, p[q], 1.0));
            }
        }
        if let Some(first) = first_sparse {
            for q in m + z.len()..first {
                trip.push(Triplet::new(q, q, 1.0));
            }
        }
    }

    /// The residual of the sparse path's bordered system at `x` = [δ; μ; …]: −R − Jδ − Zμ on the
    /// interface rows, −δ_p on the pin rows, zero on the bodies' rows (J applied body by body).
    pub(super) fn bordered_residual(
        &self,
        applied: &mut Option<(Vec<f64>, Vec<f64>)>,
        (chi, status, g): Sets<'_>,
        z: &[Vec<f64>],
        pins: Option<&[usize]>,
        r: &[f64],
        x: &Mat<f64>,
    ) -> Option<Mat<f64>> {
        let m = self.len();
        let delta: Vec<f64> = (0..m).map(|i| x[(i, 0)]).collect();
        // Every process applies its own bodies' B; a failed solve shows as NaN on every process.
        let mut bd: Vec<f64> = (0..self.bodies.len())
            .into_par_iter()
            .flat_map_iter(|b| {
                let range = self.range(b);
                let applied = self.bodies[b]
                    .as_ref()
                    .and_then(|body| body.apply_response(&delta[range.clone()]).ok());
                applied.unwrap_or_else(|| vec![f64::NAN; range.len()])
            })
            .collect();
        share_slices(self.exchange, &self.interface.body_range, &mut bd);
        if !bd.iter().all(|v| v.is_finite()) {
            return None;
        }
        *applied = Some((delta.clone(), bd.clone()));
        let mut res = Mat::<f64>::zeros(x.nrows(), 1);
        for (j, p) in self.interface.points.iter().enumerate() {
            let jd = if self.weightless[j] {
                delta[j]
            } else if self.balanced[j] {
                delta[j]
                    + self
                        .balanced_row(j, (chi, status, g), false)
                        .iter()
                        .map(|&(k, c)| c * bd[k])
                        .sum::<f64>()
            } else if chi[j] {
                delta[j] + p.partner.iter().map(|&(k, c)| c * bd[k]).sum::<f64>()
            } else {
                delta[j] - bd[j]
            };
            let zmu: f64 = z
                .iter()
                .enumerate()
                .map(|(q, zq)| zq[j] * x[(m + q, 0)])
                .sum();
            res[(j, 0)] = -r[j] - jd - zmu;
        }
        for (q, &p) in pins.unwrap_or(&[]).iter().enumerate() {
            res[(m + q, 0)] = -delta[p];
        }
        Some(res)
    }

    /// Row q of J − I for an unknown of a balanced pair as a combination Σ c_k B_k· of rows of
    /// B: −B_q·, plus for every closed point j that loads q with share a, g (B_j· + Σ c_jk B_k·)
    /// with g = a (w_j/θ_j)/D₀_q. With `pattern`, the open points' entries too, as zeros (the
    /// sparse LU's pattern then stays the same while the closed set changes). With friction
    /// (`status`), the tractions of the frictional points that load q too ([`Self::slip_terms`]).
    pub(super) fn balanced_row(
        &self,
        q: usize,
        (chi, status, g): Sets<'_>,
        pattern: bool,
    ) -> Vec<(usize, f64)> {
        let mut row = vec![(q, -1.0)];
        for &(j, a) in &self.interface.carried[q] {
            let p = &self.interface.points[j];
            if !p.has_partner() || !(chi[j] || pattern) {
                continue;
            }
            let g = if chi[j] {
                a * (p.weight / p.theta) / self.d0[q]
            } else {
                0.0
            };
            row.push((j, g));
            row.extend(p.partner.iter().map(|&(k, c)| (k, g * c)));
        }
        if self.friction {
            self.slip_terms(q, (status, g), pattern, &mut row);
        }
        row
    }

    /// Adds to row q of J − I the derivative −(1/D₀_q) Σ b w_j dσ_t,j of the tangential tractions
    /// that load q: where j sticks, dσ_t = −(1/θ_t) (its tangential row)·B; where it slips under
    /// Coulomb's law, dσ_t = (μ sgn/θ) (its gap row)·B (the bound μ p follows the pressure);
    /// nothing where it is open or slips under Tresca's (zeros with `pattern`).
    fn slip_terms(
        &self,
        q: usize,
        (status, g): (&[Status], &[f64]),
        pattern: bool,
        row: &mut Vec<(usize, f64)>,
    ) {
        for &(j, b) in &self.interface.carried_tangential[q] {
            let p = &self.interface.points[j];
            let Some(f) = &p.friction else { continue };
            let share = b * p.weight / self.d0[q];
            let (stick, slip) = match status.get(j) {
                Some(Status::Stick) => (share / f.theta, 0.0),
                Some(Status::Slip) => (0.0, -share * f.slip_slope(g[j]) / p.theta),
                _ => (0.0, 0.0),
            };
            if stick != 0.0 || pattern {
                row.extend(f.row.iter().map(|&(k, c)| (k, stick * c)));
            }
            if slip != 0.0 || pattern {
                row.push((j, slip));
                row.extend(p.partner.iter().map(|&(k, c)| (k, slip * c)));
            }
        }
    }

    /// Pushes Σ c·(row k of B) over `combination` into row j, summed per dense body first (a
    /// balanced row combines many rows of the same bodies).
    pub(super) fn push_rows(
        &self,
        trip: &mut Vec<Triplet<usize, usize, f64>>,
        j: usize,
        combination: &[(usize, f64)],
    ) {
        let mut bodies: Vec<usize> = combination.iter().map(|&(k, _)| self.body_of[k]).collect();
        bodies.sort_unstable();
        bodies.dedup();
        for b in bodies {
            let terms = combination.iter().filter(|&&(k, _)| self.body_of[k] == b);
            let Some(bt) = &self.response_t[b] else {
                for &(k, c) in terms {
                    self.push_row(trip, j, k, c);
                }
                continue;
            };
            let range = self.range(b);
            // Term by term along the rows of B (contiguous in Bᵀ): every entry sums its terms in
            // their order, as a sum over the terms per entry would.
            let mut row = vec![0.0; range.len()];
            for &(k, c) in terms {
                let col = bt.col(k - range.start);
                for (v, &x) in row.iter_mut().zip(col.iter()) {
                    *v += c * x;
                }
            }
            for (v, col) in row.into_iter().zip(range) {
                if v != 0.0 {
                    trip.push(Triplet::new(j, col, v));
                }
            }
        }
    }

    /// Pushes c·(row k of B) into row j: the entries B_k· over k's body; on the sparse path
    /// c·n_kᵀ δu at k's node instead (δU_k, which the body's rows tie to δτ).
    pub(super) fn push_row(
        &self,
        trip: &mut Vec<Triplet<usize, usize, f64>>,
        j: usize,
        k: usize,
        c: f64,
    ) {
        let b = self.body_of[k];
        let range = self.range(b);
        let local = k - range.start;
        let Some(bt) = &self.response_t[b] else {
            if let Some((offset, dofs)) = self.sparse_dofs(k) {
                for &(r, n) in dofs {
                    trip.push(Triplet::new(j, offset + r, c * n));
                }
            }
            return;
        };
        for (&x, col) in bt.col(local).iter().zip(range) {
            let v = c * x;
            if v != 0.0 {
                trip.push(Triplet::new(j, col, v));
            }
        }
    }

    /// The column of the first reduced unknown of point k's body in the Newton system, and the
    /// point's reduced DOFs with their normal components (`None` for a dense body).
    pub(super) fn sparse_dofs(&self, k: usize) -> Option<(usize, &[(usize, f64)])> {
        let b = self.body_of[k];
        let local = k - self.range(b).start;
        let dofs = match (&self.parts[b], self.bodies[b].as_ref()) {
            (BodyPart::Remote(rows), _) => rows.point_dofs(local),
            (_, Some(body)) => body.sparse().map_or(&[][..], |s| s.point_dofs(local)),
            (_, None) => &[],
        };
        Some((self.sparse_offset[b]?, dofs))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::condensed::Condensation;
    use crate::model::Model;
    use crate::solver::prepare_with;

    /// The notch on the sparse path, with `upper` cells in x on the upper body (another count
    /// than the lower body's 12: non-matching), P1 or P2, and the pair's forces.
    fn notch(upper: usize, order: contactdd_core::Order, forces: crate::Forces) -> Model {
        let make = |nx| {
            let notch = crate::benchmark::Notch {
                nx,
                ny: 6,
                order,
                ..Default::default()
            };
            notch.model().expect("the notch builds")
        };
        let mut model = make(12);
        model.bodies[1] = make(upper).bodies.swap_remove(1);
        model.pairs[0].forces = forces;
        // Unequal pressures: the loads do work along the blocks' joint free motion, so the
        // bordered system's multiplier μ is not zero.
        model.bodies[1].load.iter_mut().for_each(|f| *f *= 1.25);
        model
    }

    /// The step by the symmetric form against the LU's at the starting state and after one step
    /// (the joint vertical translation of the two floating blocks is in the kernel of J).
    fn compare_steps(model: &Model) -> usize {
        let prepared = prepare_with(model, Condensation::Sparse).expect("the notch prepares");
        let mut system = System::new(&prepared, &prepared.interface);
        let mut caches = Caches::default();
        assert!(system.symmetric);
        // An arbitrary start: its residual also acts along the kernel (μ ≠ 0).
        let mut tau: Vec<f64> = (0..system.len()).map(|j| 1e-4 * (j as f64).sin()).collect();
        let mut symmetric = 0;
        for _ in 0..2 {
            let eval = system.evaluate(&tau);
            let (chi, status) = system.jacobian_set(&eval);
            let z = system.kernel(&system.free_motions(&chi, &status));
            assert_eq!(z.len(), 1, "one free motion");
            let r = system.residual(&tau, &eval, &chi, &status);
            system.symmetric = false;
            let lu = system
                .step(&mut caches, (&chi, &status, &eval.g), &z, &r, 0.0)
                .expect("the LU step");
            // Unrefined (any accuracy will do): the symmetric form itself must be exact.
            let (primal, applied) = (&mut caches.primal, &mut caches.applied);
            if let Some(sym) = system.symmetric_step(primal, applied, &chi, &z, &r, f64::INFINITY) {
                symmetric += 1;
                let scale = lu.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                for (a, b) in sym.iter().zip(&lu) {
                    assert!(
                        (a - b).abs() <= 1e-9 * scale,
                        "{a} against {b} (scale {scale})"
                    );
                }
            }
            system.symmetric = true;
            tau.iter_mut().zip(&lu).for_each(|(t, d)| *t += d);
        }
        symmetric
    }

    /// J δ (from the bordered residual with no kernel and R = 0) against the change of R with
    /// the sets held fixed, at states along the Newton steps of a frictional notch sheared by
    /// `shear` (its stick, slip and open points all present).
    fn check_jacobian(condensation: Condensation, mu: f64, shear: f64) -> usize {
        let mut model = notch(17, contactdd_core::Order::P1, crate::Forces::Balanced);
        model.pairs[0].friction = crate::Friction::Coulomb { mu };
        // A body force along x on the upper block, freed in x: friction alone holds it.
        let upper = &mut model.bodies[1];
        upper.constraints = contactdd_core::Constraints::new(upper.mesh.num_nodes());
        for x in upper.load.iter_mut().step_by(2) {
            *x += shear;
        }
        let prepared = prepare_with(&model, condensation).expect("the notch prepares");
        let system = System::new(&prepared, &prepared.interface);
        let mut caches = Caches::default();
        let m = system.len();
        let mut tau = vec![0.0; m];
        let mut seen = 0;
        for _ in 0..6 {
            let eval = system.evaluate(&tau);
            let (chi, status) = system.jacobian_set(&eval);
            seen |= status.iter().fold(0, |a, s| a | (1 << (*s as usize)));
            let sets = (chi.as_slice(), status.as_slice(), eval.g.as_slice());
            let delta: Vec<f64> = (0..m).map(|j| 1e-7 * ((j * 7 + 3) as f64).sin()).collect();
            let x = Mat::from_fn(m, 1, |i, _| delta[i]);
            let zero = vec![0.0; m];
            let jd = system
                .bordered_residual(&mut None, sets, &[], None, &zero, &x)
                .expect("the bodies apply B");
            let r0 = system.residual(&tau, &eval, &chi, &status);
            let moved: Vec<f64> = tau.iter().zip(&delta).map(|(t, d)| t + d).collect();
            let next = system.evaluate(&moved);
            let r1 = system.residual_on(&moved, &next.u, (&next.s, &next.g), &chi, &status);
            let scale = (0..m).fold(0.0f64, |a, i| a.max(jd[(i, 0)].abs()));
            for i in 0..m {
                let fd = r1[i] - r0[i];
                assert!(
                    (fd + jd[(i, 0)]).abs() <= 1e-6 * scale,
                    "row {i}: {fd} against {}",
                    -jd[(i, 0)]
                );
            }
            let r = system.residual(&tau, &eval, &chi, &status);
            let z = system.kernel(&system.free_motions(&chi, &status));
            let step = system.step(&mut caches, sets, &z, &r, 0.0).expect("a step");
            tau.iter_mut().zip(&step).for_each(|(t, d)| *t += d);
        }
        seen
    }

    #[test]
    fn the_frictional_jacobian_is_the_derivative_of_the_residual() {
        for condensation in [Condensation::Dense, Condensation::Sparse] {
            let seen = check_jacobian(condensation, 0.3, 15.0);
            assert!(seen & 0b110 == 0b110, "stick and slip seen: {seen:b}");
        }
    }

    #[test]
    fn the_symmetric_step_solves_the_bordered_system_of_the_lu() {
        use crate::Forces::{Balanced, OwnSide};
        use contactdd_core::Order::{P1, P2};
        // Matching own-side, non-matching balanced (P1 and P2): every step symmetric.
        for (upper, order, forces) in [(12, P1, OwnSide), (17, P1, Balanced), (9, P2, Balanced)] {
            assert_eq!(
                compare_steps(&notch(upper, order, forces)),
                2,
                "{upper} {order:?}"
            );
        }
        // Non-matching own-side: each side loads only itself, P is not symmetric, the LU steps.
        assert_eq!(compare_steps(&notch(17, P1, OwnSide)), 0);
    }
}
