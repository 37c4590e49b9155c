//! The interface Newton iteration: the penalty problem on the condensed interface, solved for all
//! contact points at once by a semismooth Newton (primal–dual active set) method. The algorithm
//! and its sources are in `docs/interface-newton.md`.
//!
//! Every body is condensed onto its contact points ([`CondensedBody`]): with τ = D₀⁻¹T the
//! interface load in displacement units, its normal displacements are U_b = f₀ + B_b τ_b with
//! B_b = C₀D₀. Point j carries the penetration-like q_j = U_j − τ_j = θ_j p_j (p the contact
//! pressure), and the penalty law q = max(0, s − d) is the complementarity problem
//!   q ≥ 0,  s − d − q ≤ 0,  q (s − d − q) = 0,
//! written as q_j = max(0, q_j + ρ_j (s_j − d_j − q_j)) for any ρ_j > 0. Point j counts as closed
//! when the argument of the max is positive. ρ = 1 would be the penalty's own rule (closed where
//! s > d); ρ_j = 1 − B_jj, the body's share in the stiffness of the point with its spring, is the
//! primal–dual active set rule with the body's own stiffness as scale, which decides on the
//! pressure rather than on a penetration of the size of θ·p and so does not flip points at the
//! edge of the contact zone back and forth when θ is small. For a fixed closed set χ the
//! equations are linear:
//!   R_j = τ_j − U_j − χ_j (d_j − s_j) = 0,
//! and the Jacobian J = I − (I − χA) B (s = A U) has row e_j − B_j· for an open point and
//! e_j + Σ_k c_jk B_k· for a closed one (the point's own B row cancels). J is sparse by bodies:
//! dense blocks of the size of one body's contact zone, coupled only across closed pairs.
//!
//! Each step solves J δ = −R (by LU, or on sparse bodies by the symmetric form of `primal`)
//! and takes the full step. A watchdog keeps the last state whose ‖R̂‖ (R with closed rows
//! scaled by ρ: the complementarity residual) a step decreased enough; when a few full steps in a row do not decrease it below that state's, the run returns
//! there and backtracks along that state's step. Two safeguards keep J regular:
//! - rigid motions that no closed contact resists (two floating bodies moving together) are in
//!   the kernel of J; they are found from the bodies' free rigid modes, and the step is kept
//!   orthogonal to them by a bordered system (their residual is left to the bodies' balance,
//!   which the solver checks);
//! - a floating body with no closed point uses all its partnered points as closed in J and in
//!   the step's residual, which moves it towards its partners; so do the points that would
//!   resist a free rigid motion along which the loads do work (a body held sideways but pushed
//!   down). Such "stranded" states never count as progress or as converged.
//!
//! The bodies' responses B_b τ_b are evaluated in parallel; the factorisation is sequential, so
//! the result does not depend on the number of threads. A process evaluates only the bodies it
//! owns; the [`Exchange`] shares their blocks B_b and responses, and every process then solves
//! the same Newton system (`crate::exchange`).

use std::ops::Range;
use std::sync::atomic::Ordering;
use std::sync::Mutex;
use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::FaerError;
use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};
use faer::{Conj, Index, Mat, Par};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use crate::condensed::CondensedBody;
use crate::contact::{Interface, Role};
use crate::exchange::{share_matrices, share_slices, Exchange};
use crate::iteration::{
    contact_summary, relative_change, starting_values, Hooks, Outcome, Record, Settings, Stop,
};
use crate::robin_sweep::Breakdown;
use crate::shared_rows::{body_parts, BodyPart};
use crate::solver::Prepared;

mod null_space;
mod primal;
use null_space::null_space;
use primal::PrimalCache;

/// The forcing term of the inexact Newton step (Dembo, Eisenstat & Steihaug 1982) as a fraction
/// of the convergence tolerance: a step is refined until ‖Jδ + R‖ ≤ 10⁻³ tol ‖R‖, an error that
/// none of the iteration's decisions can see.
const FORCING: f64 = 1e-3;
/// Full steps the watchdog takes without a sufficient decrease of ‖R̂‖ before it returns to its
/// checkpoint (the window of Grippo, Lampariello & Lucidi's non-monotone rule, 10).
const WINDOW: usize = 10;
/// Halvings of the step at most in the line search.
const MAX_HALVINGS: usize = 12;
/// Sufficient decrease of ‖R‖ per unit step length (Armijo).
const ARMIJO: f64 = 1e-4;
/// The fill (entries / n²) from which the Newton system is factorised as a dense matrix: two
/// bodies in contact fill half of it or more, and then the sparse LU does about the dense flops
/// with more overhead; a chain of bodies stays block-sparse, well below.
const DENSE_FILL: f64 = 1.0 / 3.0;
/// Work of the loads along a free rigid motion, relative to their work along all free modes, above
/// which the motion is loaded: far above the rounding of loads that balance (the paper's notch,
/// two bodies pressed from both sides), far below any imbalance a solution could leave.
const WORK_TOL: f64 = 1e-8;
/// Iterative refinement steps at most after a sparse-path LU solve.
const MAX_REFINE: usize = 4;

/// Runs the interface Newton iteration on a prepared model with the contact points `interface`,
/// from the interface loads `warm` if given, else from the paper's initial value u⁰.
pub fn iterate(
    prepared: &Prepared,
    interface: &Interface,
    warm: Option<&[f64]>,
    settings: &Settings,
    hooks: Hooks<'_>,
) -> Outcome {
    let start = Instant::now();
    let system = System::new(prepared, interface);
    let mut run = Run::new(&system, prepared, warm, settings);
    let (stop, iterations) = run.solve(settings, hooks);
    let t_load = system.loads(&run.tau);
    Outcome {
        stop,
        iterations,
        un: run.state.u,
        t_load,
        history: run.history,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The condensed interface problem.
struct System<'a> {
    interface: &'a Interface,
    /// The bodies this process owns.
    bodies: &'a [Option<CondensedBody>],
    exchange: &'a dyn Exchange,
    /// B_b = C₀D₀ of every dense body (`None` on the sparse path).
    response: Vec<Option<Mat<f64>>>,
    /// The reference springs D₀ of every point.
    d0: Vec<f64>,
    /// How every body enters the Newton system (dense block, or sparse rows of its own or of
    /// another process).
    parts: Vec<BodyPart>,
    /// Per body on the sparse path, the first column of its reduced unknowns in the Newton
    /// system (after the m interface unknowns and the kernel multipliers).
    sparse_offset: Vec<Option<usize>>,
    /// Free rigid modes of the floating bodies: mode range per body, normal values per point.
    mode_range: &'a [Range<usize>],
    modes: &'a [Vec<f64>],
    /// The work of the bodies' loads along every free mode, and its norm.
    mode_load: &'a [f64],
    mode_load_norm: f64,
    /// Owning body of every point.
    body_of: Vec<usize>,
    /// ρ_j = 1 − B_jj ∈ (0, 1]: the share of the body in the stiffness of point j with its
    /// reference spring; the complementarity rule's scale.
    rho: Vec<f64>,
    /// Points with zero quadrature weight (D₀ = 0): they carry no force, and τ_j = 0.
    weightless: Vec<bool>,
    /// Unknowns of balanced pairs: their contact force gathers the pressures of several points
    /// (`Interface::carried`), and their points close where s > d (ρ = 1).
    balanced: Vec<bool>,
    /// The sparse LU kept between steps (sparse path only).
    lu: Mutex<LuCache>,
    /// Whether the step may take the symmetric form (`primal`), and its kept factor.
    symmetric: bool,
    /// Whether the penalty problem minimises an energy (every pair balanced, or own-side with
    /// matching sides), so that it has one solution whatever the start. Own-side pairs on
    /// non-matching meshes derive from no energy and can have several (a start decides which).
    variational: bool,
    primal: Mutex<PrimalCache>,
    /// The last B δ the bodies computed (for a step's residual), with its δ: U is affine in τ,
    /// U(τ + δ) = U(τ) + B δ, so the full step's state needs no body solve of its own.
    applied: Mutex<Option<(Vec<f64>, Vec<f64>)>>,
}

/// U, s and R at one τ.
#[derive(Clone)]
struct Evaluation {
    u: Vec<f64>,
    s: Vec<f64>,
    r: Vec<f64>,
    /// The points the complementarity rule counts as closed.
    closed: Vec<bool>,
    /// The rigid motions of floating bodies that the closed points leave free (weights of the
    /// free modes), and the body that nothing holds there, if any.
    free: Vec<DVector<f64>>,
    stranded: Option<usize>,
}

impl Evaluation {
    /// R̂: the residual of the complementarity function, whose closed rows are ρ R.
    fn scaled_residual(&self, rho: &[f64]) -> Vec<f64> {
        (0..self.r.len())
            .map(|j| {
                if self.closed[j] {
                    rho[j] * self.r[j]
                } else {
                    self.r[j]
                }
            })
            .collect()
    }
}

impl<'a> System<'a> {
    fn new(prepared: &'a Prepared, interface: &'a Interface) -> System<'a> {
        let (mode_range, modes) = prepared.coarse.floating_modes();
        let exchange = &*prepared.exchange;
        let parts = body_parts(&prepared.bodies, exchange);
        // The dense bodies' responses B_b, shared between processes; sparse bodies have none.
        let dense: Vec<Mat<f64>> = prepared
            .bodies
            .par_iter()
            .map(|b| {
                b.as_ref()
                    .and_then(CondensedBody::load_response)
                    .unwrap_or_else(Mat::new)
            })
            .collect();
        let response: Vec<Option<Mat<f64>>> = share_matrices(exchange, dense)
            .into_iter()
            .zip(&parts)
            .map(|(m, part)| part.sparse_free().is_none().then_some(m))
            .collect();
        let mut d0 = vec![0.0; interface.len()];
        for (b, body) in prepared.bodies.iter().enumerate() {
            if let Some(body) = body {
                d0[interface.body_range[b].clone()].copy_from_slice(body.reference_springs());
            }
        }
        share_slices(exchange, &interface.body_range, &mut d0);
        let balanced: Vec<bool> = interface
            .points
            .iter()
            .map(|p| p.role != Role::OwnSide)
            .collect();
        let mut rho: Vec<f64> = response
            .iter()
            .zip(&prepared.bodies)
            .enumerate()
            .flat_map(|(b, (bm, body))| match (bm, body.as_ref()) {
                (Some(bm), _) => (0..bm.nrows())
                    .map(|j| (1.0 - bm[(j, j)]).clamp(1e-8, 1.0))
                    .collect::<Vec<_>>(),
                (None, Some(body)) => body.sparse().map_or(vec![1.0; body.len()], |s| {
                    s.share_estimate(body.operator(), body.reference_springs())
                }),
                // Another process's sparse body: its owner's estimate is shared below.
                (None, None) => vec![1.0; interface.body_range[b].len()],
            })
            .collect();
        share_slices(exchange, &interface.body_range, &mut rho);
        let rho = rho
            .into_iter()
            .zip(&balanced)
            .map(|(r, &b)| if b { 1.0 } else { r })
            .collect();
        let mut next = interface.len() + modes_bound(mode_range);
        let sparse_offset = parts
            .iter()
            .map(|part| {
                part.sparse_free().map(|free| {
                    let offset = next;
                    next += free;
                    offset
                })
            })
            .collect();
        let mut system = System {
            interface,
            bodies: &prepared.bodies,
            exchange,
            response,
            parts,
            sparse_offset,
            mode_range,
            modes,
            mode_load: prepared.coarse.floating_loads(),
            mode_load_norm: norm(prepared.coarse.floating_loads()),
            body_of: interface.points.iter().map(|p| p.body).collect(),
            rho,
            weightless: d0.iter().map(|&d| d == 0.0).collect(),
            balanced,
            d0,
            lu: Mutex::new(LuCache::default()),
            symmetric: false,
            variational: false,
            primal: Mutex::new(PrimalCache::default()),
            applied: Mutex::new(None),
        };
        system.symmetric = system.every_body_sparse();
        system.variational = system.springs(&vec![true; system.len()]).is_some();
        system
    }

    fn len(&self) -> usize {
        self.interface.len()
    }

    fn range(&self, b: usize) -> Range<usize> {
        self.interface.body_range[b].clone()
    }

    /// U(τ), s(U) and R(τ); the bodies in parallel.
    fn evaluate(&self, tau: &[f64]) -> Evaluation {
        let u = self.displacements(tau);
        self.evaluation(tau, u)
    }

    /// The evaluation at `next` = τ + δ from the one at τ: U(τ) + B δ where the bodies computed
    /// B δ for this δ (the step's residual), else fresh.
    fn evaluate_step(&self, next: &[f64], at_tau: &Evaluation, delta: &[f64]) -> Evaluation {
        let known = self.applied.lock().ok().and_then(|cached| {
            let (d, bd) = cached.as_ref()?;
            let same = d.len() == delta.len()
                && d.iter().zip(delta).all(|(a, b)| a.to_bits() == b.to_bits());
            same.then(|| at_tau.u.iter().zip(bd).map(|(u, b)| u + b).collect())
        });
        match known {
            Some(u) => self.evaluation(next, u),
            None => self.evaluate(next),
        }
    }

    /// U(τ): a solve per sparse body, B τ for a dense one; the bodies in parallel.
    fn displacements(&self, tau: &[f64]) -> Vec<f64> {
        let mut u: Vec<f64> = (0..self.bodies.len())
            .into_par_iter()
            .flat_map_iter(|b| {
                let range = self.range(b);
                let tau_b = &tau[range.clone()];
                let Some(bm) = &self.response[b] else {
                    // A sparse body (one process owns them all). A failed solve shows as
                    // non-finite values, which the run then reports.
                    let u = self.bodies[b].as_ref().map(|body| body.respond(tau_b));
                    return match u {
                        Some(Ok(u)) => u,
                        _ => vec![f64::NAN; range.len()],
                    };
                };
                let f0 = self.bodies[b].as_ref().map(|body| body.free_response());
                (0..range.len())
                    .map(move |i| {
                        // Another process's body: its slot is filled in below.
                        f0.map_or(0.0, |f0| {
                            f0[i]
                                + tau_b
                                    .iter()
                                    .enumerate()
                                    .map(|(j, t)| bm[(i, j)] * t)
                                    .sum::<f64>()
                        })
                    })
                    .collect::<Vec<f64>>()
            })
            .collect();
        share_slices(self.exchange, &self.interface.body_range, &mut u);
        u
    }

    /// s(U), R and the closed set at τ with the displacements `u` = U(τ).
    fn evaluation(&self, tau: &[f64], u: Vec<f64>) -> Evaluation {
        let mut s = vec![0.0; u.len()];
        self.interface.sum_normal(&u, &mut s);
        let points = &self.interface.points;
        let closed: Vec<bool> = (0..u.len())
            .map(|j| {
                let p = &points[j];
                if self.weightless[j] || !p.has_partner() {
                    return false;
                }
                if self.balanced[j] {
                    // Only carriers' pressures act; a follower's own gap is a reading.
                    return p.carries() && s[j] > p.penalty_gap();
                }
                let q = u[j] - tau[j];
                q + self.rho[j] * (s[j] - p.penalty_gap() - q) > 0.0
            })
            .collect();
        // A carrier closes exactly where its overlap is negative (ρ = 1), so its linear penalty
        // force on the closed set is its penalty force.
        let r = self.residual_on(tau, &u, &s, &closed);
        let free = self.free_motions(&closed);
        let stranded = self.stranded(&closed, &free);
        Evaluation {
            u,
            s,
            r,
            closed,
            free,
            stranded,
        }
    }

    /// R at the evaluated state with the points `chi` closed: the residual whose Jacobian the
    /// Newton step uses. It is the state's own R where `chi` is its closed set; where the step
    /// treats more points as closed (a stranded body), their penalty forces count as linear in
    /// s, so that the step solves the equations of that closed set (with the state's R the step
    /// would only move the body along the springs of points that it then finds open again).
    fn residual(&self, tau: &[f64], eval: &Evaluation, chi: &[bool]) -> Vec<f64> {
        if chi == eval.closed {
            return eval.r.clone();
        }
        self.residual_on(tau, &eval.u, &eval.s, chi)
    }

    /// R(τ) for the displacements `u`, pair sums `s` and the points `chi` closed, their penalty
    /// forces linear in s (F_j/w_j = (d − s)/θ).
    fn residual_on(&self, tau: &[f64], u: &[f64], s: &[f64], chi: &[bool]) -> Vec<f64> {
        let points = &self.interface.points;
        let linear = |j: usize| {
            let p = &points[j];
            if chi[j] {
                (p.penalty_gap() - s[j]) / p.theta
            } else {
                0.0
            }
        };
        (0..u.len())
            .map(|j| {
                if self.weightless[j] {
                    tau[j]
                } else if self.balanced[j] {
                    let force: f64 = self.interface.carried[j]
                        .iter()
                        .map(|&(k, a)| a * (points[k].weight * linear(k)))
                        .sum();
                    tau[j] - u[j] - force / self.d0[j]
                } else if chi[j] {
                    tau[j] - u[j] - (points[j].penalty_gap() - s[j])
                } else {
                    tau[j] - u[j]
                }
            })
            .collect()
    }

    /// The interface loads T = D₀τ.
    fn loads(&self, tau: &[f64]) -> Vec<f64> {
        tau.iter().zip(&self.d0).map(|(t, d)| t * d).collect()
    }

    /// The points whose pressure loads body `b`: its own, or the carriers facing it.
    fn loaders(&self, b: usize) -> Vec<usize> {
        self.range(b)
            .flat_map(|q| self.interface.carried[q].iter().map(|&(j, _)| j))
            .collect()
    }

    /// Whether a closed point in `closed` holds body `b` (or supports do: a body without free
    /// rigid modes).
    fn holds(&self, b: usize, closed: &[bool]) -> bool {
        self.mode_range[b].is_empty() || self.loaders(b).iter().any(|&j| closed[j])
    }

    /// The first floating body none of whose loaders is closed in `closed`: nothing holds it.
    fn unheld(&self, closed: &[bool]) -> Option<usize> {
        (0..self.bodies.len()).find(|&b| !self.holds(b, closed))
    }

    /// The points treated as closed in J: the closed points, and every partnered point that loads
    /// a floating body none of whose loading points is closed.
    fn jacobian_set(&self, eval: &Evaluation) -> Vec<bool> {
        let points = &self.interface.points;
        let mut chi = eval.closed.clone();
        for b in 0..self.bodies.len() {
            if self.mode_range[b].is_empty() {
                continue;
            }
            let loaders = self.loaders(b);
            if !loaders.iter().any(|&j| chi[j]) {
                for j in loaders {
                    chi[j] = points[j].has_partner();
                }
            }
        }
        // Bodies that closed points hold, but not along a motion their loads push them in (a
        // column of blocks held sideways by its neighbours, open below): the points that would
        // resist the motion count as closed.
        for _ in 0..self.bodies.len() {
            let found;
            let free = if chi == eval.closed {
                &eval.free
            } else {
                found = self.free_motions(&chi);
                &found
            };
            let Some(v) = self.loaded_motion(free) else {
                break;
            };
            let open: Vec<usize> = self
                .resisting(&v)
                .into_iter()
                .filter(|&j| !chi[j])
                .collect();
            if open.is_empty() {
                break;
            }
            open.into_iter().for_each(|j| chi[j] = true);
        }
        chi
    }

    /// The rigid motions of floating bodies that the closed points `chi` do not resist, as
    /// weights of the free modes: the null space of G = Σ_j l_j s_jᵀ over the closed points, s_j
    /// the change of point j's pair sum per mode and l_j the modes its force acts on. A balanced
    /// carrier loads both sides through its gap row (l_j = s_j); an own-side point loads its own
    /// body only, so a closed point does not hold its partner: with only one side of an own-side
    /// pair closed, the other body moves freely away (before, such a motion counted as resisted
    /// and made J singular).
    fn free_motions(&self, chi: &[bool]) -> Vec<DVector<f64>> {
        let k = modes_bound(self.mode_range);
        if k == 0 {
            return Vec::new();
        }
        // G's terms l_ja s_jb point by point, then summed per entry in the points' order.
        let mut entries = Vec::new();
        // The size of G's diagonal terms, Σ_j |l_ja s_ja| (for balanced pairs, G's diagonal).
        let mut scale = vec![0.0f64; k];
        for j in (0..self.len()).filter(|&j| chi[j]) {
            let (sum, load) = self.mode_entries(j);
            for &(a, l) in &load {
                for &(b, s) in &sum {
                    entries.push((a, b, l * s));
                    if a == b {
                        scale[a] += (l * s).abs();
                    }
                }
            }
        }
        let scale = scale.into_iter().fold(0.0, f64::max);
        let g = merge(entries);
        // Balanced pairs, and own-side pairs closed on both sides, give a symmetric G = Σ s sᵀ:
        // its null space from an LDLᵀ factorisation in its band, whose cost follows the bodies'
        // neighbourhoods (a column of 1024 blocks: a dense eigensolver took 1.1 s per state).
        let symmetric = g.iter().all(|&(a, b, v)| {
            a == b
                || g.binary_search_by(|e| (e.0, e.1).cmp(&(b, a)))
                    .is_ok_and(|i| g[i].2 == v)
        });
        if symmetric {
            let lower: Vec<(usize, usize, f64)> =
                g.iter().copied().filter(|e| e.1 <= e.0).collect();
            return null_space(k, &lower, 1e-10 * scale);
        }
        // The null space from G's own singular values (those of GᵀG would square the rounding).
        let mut dense = DMatrix::<f64>::zeros(k, k);
        for (a, b, v) in g {
            dense[(a, b)] = v;
        }
        let svd = dense.svd(false, true);
        let Some(v_t) = svd.v_t else {
            return Vec::new();
        };
        svd.singular_values
            .iter()
            .enumerate()
            .filter(|(_, &sigma)| sigma <= 1e-10 * scale)
            .map(|(q, _)| v_t.row(q).transpose())
            .collect()
    }

    /// Point j's change of pair sum per free mode, and the modes its force acts on (a balanced
    /// carrier's gap row loads both sides, an own-side point its own body), as (mode, value)
    /// lists in the modes' order.
    fn mode_entries(&self, j: usize) -> (Vec<(usize, f64)>, Vec<(usize, f64)>) {
        let mut sum = Vec::new();
        self.push_modes(j, 1.0, &mut sum);
        for &(q, c) in &self.interface.points[j].partner {
            self.push_modes(q, c, &mut sum);
        }
        sum.sort_by_key(|e| e.0);
        let load = if self.balanced[j] {
            sum.clone()
        } else {
            let mut own = Vec::new();
            self.push_modes(j, 1.0, &mut own);
            own
        };
        (sum, load)
    }

    /// Adds c·ρ_j (the modes of point j's body) to the (mode, value) list `list`.
    fn push_modes(&self, j: usize, c: f64, list: &mut Vec<(usize, f64)>) {
        let b = self.body_of[j];
        for (m, r) in self.mode_range[b].clone().zip(&self.modes[j]) {
            match list.iter_mut().find(|e| e.0 == m) {
                Some(e) => e.1 += c * r,
                None => list.push((m, 0.0 + c * r)),
            }
        }
    }

    /// An orthonormal basis, on the contact points, of the rigid motions `free` (those some closed
    /// points do not resist): motions of the whole interface that keep every closed pair sum.
    fn kernel(&self, free: &[DVector<f64>]) -> Vec<Vec<f64>> {
        let mut basis: Vec<Vec<f64>> = Vec::new();
        for v in free {
            let mut z: Vec<f64> = (0..self.len())
                .map(|j| {
                    let b = self.body_of[j];
                    self.mode_range[b]
                        .clone()
                        .zip(&self.modes[j])
                        .map(|(m, r)| v[m] * r)
                        .sum()
                })
                .collect();
            for e in &basis {
                let d = dot(e, &z);
                z.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
            }
            let n = dot(&z, &z).sqrt();
            if n > 1e-8 {
                z.iter_mut().for_each(|x| *x /= n);
                basis.push(z);
            }
        }
        basis
    }

    /// A rigid motion among `free` (the motions some closed points leave free) along which the
    /// loads do work: no state with these closed points balances them.
    fn loaded_motion(&self, free: &[DVector<f64>]) -> Option<DVector<f64>> {
        let total = self.mode_load_norm;
        if total == 0.0 {
            return None;
        }
        free.iter()
            .find(|v| self.work(v).abs() > WORK_TOL * total)
            .cloned()
    }

    /// The loads' work along the rigid motion `v` (weights of the free modes).
    fn work(&self, v: &DVector<f64>) -> f64 {
        v.iter().zip(self.mode_load).map(|(a, f)| a * f).sum()
    }

    /// The body that moves most along the rigid motion `v`.
    fn moves_most(&self, v: &DVector<f64>) -> Option<usize> {
        let share = |b: usize| self.mode_range[b].clone().map(|m| v[m] * v[m]).sum::<f64>();
        (0..self.bodies.len()).max_by(|&a, &b| share(a).total_cmp(&share(b)))
    }

    /// The body that nothing holds in `closed` (whose free motions are `free`): one none of whose
    /// loaders is closed, else the body that moves most along a loaded free motion.
    fn stranded(&self, closed: &[bool], free: &[DVector<f64>]) -> Option<usize> {
        if let Some(b) = self.unheld(closed) {
            return Some(b);
        }
        let v = self.loaded_motion(free)?;
        self.moves_most(&v)
    }

    /// The points that can close (partnered, weighted, and carriers on balanced pairs) whose
    /// pair sum the rigid motion `v` changes and whose force acts along it (an own-side point on
    /// a body that moves): closed, they would resist it.
    fn resisting(&self, v: &DVector<f64>) -> Vec<usize> {
        self.along_motion(v)
            .into_iter()
            .filter(|&(_, c, a)| c != 0.0 && a != 0.0)
            .map(|(j, _, _)| j)
            .collect()
    }

    /// The body that nothing can ever hold, if the free motions `free` include one along which
    /// the loads do work W and no contact point pushes back: taken the way the loads push, every
    /// point's normal moves away from its partner or along it, so its pressure p ≥ 0 can only do
    /// work ≥ 0 too, and the rigid motion's balance W + Σ (work of p) = 0 has no solution, with
    /// any penalty or with exact contact. The body is the one that moves most along it.
    fn unresisted(&self, free: &[DVector<f64>]) -> Option<usize> {
        let v = self.loaded_motion(free)?;
        let push = self.work(&v).signum();
        let pushed_back = self
            .along_motion(&v)
            .iter()
            .any(|&(_, _, a)| a * push > 0.0);
        if pushed_back {
            return None;
        }
        self.moves_most(&v)
    }

    /// Per point that can close: c, the change of its pair sum along the rigid motion `v`, and
    /// a, the same change seen by the bodies its force acts on (its own body's part for an
    /// own-side point; a = c for a balanced carrier, whose force acts through its gap row), so
    /// that its pressure p does work −p·a along v. Each is 0 below 10⁻⁸ of its largest value
    /// (rounding).
    fn along_motion(&self, v: &DVector<f64>) -> Vec<(usize, f64, f64)> {
        let points = &self.interface.points;
        let along = |row: &[(usize, f64)]| row.iter().map(|&(m, x)| x * v[m]).sum::<f64>();
        let change: Vec<(usize, f64, f64)> = (0..self.len())
            .filter(|&j| {
                let p = &points[j];
                p.has_partner() && !self.weightless[j] && (!self.balanced[j] || p.carries())
            })
            .map(|j| {
                let (sum, load) = self.mode_entries(j);
                (j, along(&sum), along(&load))
            })
            .collect();
        let largest =
            |f: fn(&(usize, f64, f64)) -> f64| change.iter().fold(0.0f64, |m, c| m.max(f(c).abs()));
        let (sums, works) = (largest(|c| c.1), largest(|c| c.2));
        let cut = |x: f64, top: f64| if x.abs() > 1e-8 * top { x } else { 0.0 };
        change
            .into_iter()
            .map(|(j, c, a)| (j, cut(c, sums), cut(a, works)))
            .collect()
    }

    /// The Newton step: solves [J Z; Zᵀ 0] [δ; μ] = [−R; 0], by the symmetric form where it
    /// applies (`primal`), else by LU.
    ///
    /// The symmetric form refines its step against the true J until the residual is at most
    /// `eta` ‖R‖ (an inexact Newton step); the LU refines while that halves the residual.
    fn step(&self, chi: &[bool], z: &[Vec<f64>], r: &[f64], eta: f64) -> Option<Vec<f64>> {
        if self.symmetric {
            if let Some(delta) = self.symmetric_step(chi, z, r, eta * norm(r)) {
                return Some(delta);
            }
        }
        let m = self.len();
        let mut n = m + z.len();
        let mut trip = Vec::new();
        // Sparse bodies: their reduced unknowns δu and the rows K₀δu − N D₀ δτ = 0 stand for δU.
        for (b, part) in self.parts.iter().enumerate() {
            let (Some(offset), Some(free)) = (self.sparse_offset[b], part.sparse_free()) else {
                continue;
            };
            let at = (offset, self.range(b).start);
            match (part, self.bodies[b].as_ref()) {
                (BodyPart::Remote(rows), _) => rows.replay(at, &mut trip),
                (_, Some(body)) => {
                    if let Some(s) = body.sparse() {
                        s.push_body_rows(body.operator(), body.reference_springs(), at, &mut trip);
                    }
                }
                (_, None) => {}
            }
            n = n.max(offset + free);
        }
        let first_sparse = self.sparse_offset.iter().flatten().min().copied();
        for (j, p) in self.interface.points.iter().enumerate() {
            trip.push(Triplet::new(j, j, 1.0));
            if self.weightless[j] {
                continue;
            }
            if self.balanced[j] {
                let combination = self.balanced_row(j, chi, first_sparse.is_some());
                self.push_rows(&mut trip, j, &combination);
            } else if first_sparse.is_some() && p.has_partner() {
                // Both the closed and the open entries (one set zero): the pattern, and with it
                // the LU's symbolic analysis, stays the same while the closed set changes.
                let closed = if chi[j] { 1.0 } else { 0.0 };
                for &(k, c) in &p.partner {
                    self.push_row(&mut trip, j, k, closed * c);
                }
                self.push_row(&mut trip, j, j, closed - 1.0);
            } else if chi[j] {
                for &(k, c) in &p.partner {
                    self.push_row(&mut trip, j, k, c);
                }
            } else {
                self.push_row(&mut trip, j, j, -1.0);
            }
        }
        // With sparse bodies a dense row Zᵀδ = 0 would fill the whole sparse LU: pin one point
        // per kernel vector instead and project the step afterwards (J z = 0, so the projected
        // step solves the same system).
        let pins = first_sparse.map(|_| pin_points(z));
        for (q, zq) in z.iter().enumerate() {
            for (j, &v) in zq.iter().enumerate().filter(|(_, v)| **v != 0.0) {
                trip.push(Triplet::new(j, m + q, v));
                if pins.is_none() {
                    trip.push(Triplet::new(m + q, j, v));
                }
            }
            if let Some(p) = &pins {
                trip.push(Triplet::new(m + q, p[q], 1.0));
            }
        }
        // Unused multiplier columns of the sparse bodies' block (fewer kernel vectors than the
        // bound): identity rows keep the system regular.
        if let Some(first) = first_sparse {
            for q in m + z.len()..first {
                trip.push(Triplet::new(q, q, 1.0));
            }
        }
        let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| if i < m { -r[i] } else { 0.0 });
        if trip.len() as f64 >= DENSE_FILL * (n as f64) * (n as f64) {
            dense_solve(&trip, n, &mut rhs)?;
        } else {
            let cache = pins.as_ref().map(|_| &self.lu);
            // Refinement against the true J (B applied by the bodies' own solves): the coupled
            // matrix's residual is a poor measure of the error in δ.
            let residual = |x: &Mat<f64>| self.bordered_residual(chi, z, pins.as_deref(), r, x);
            let refine: Option<&dyn Fn(&Mat<f64>) -> Option<Mat<f64>>> =
                pins.as_ref().map(|_| &residual as _);
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

    /// The residual of the sparse path's bordered system at `x` = [δ; μ; …]: −R − Jδ − Zμ on the
    /// interface rows, −δ_p on the pin rows, zero on the bodies' rows (J applied body by body).
    fn bordered_residual(
        &self,
        chi: &[bool],
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
        if let Ok(mut cached) = self.applied.lock() {
            *cached = Some((delta.clone(), bd.clone()));
        }
        let mut res = Mat::<f64>::zeros(x.nrows(), 1);
        for (j, p) in self.interface.points.iter().enumerate() {
            let jd = if self.weightless[j] {
                delta[j]
            } else if self.balanced[j] {
                delta[j]
                    + self
                        .balanced_row(j, chi, false)
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
    /// sparse LU's pattern then stays the same while the closed set changes).
    fn balanced_row(&self, q: usize, chi: &[bool], pattern: bool) -> Vec<(usize, f64)> {
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
        row
    }

    /// Pushes Σ c·(row k of B) over `combination` into row j, summed per dense body first (a
    /// balanced row combines many rows of the same bodies).
    fn push_rows(
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
            let Some(bm) = &self.response[b] else {
                for &(k, c) in terms {
                    self.push_row(trip, j, k, c);
                }
                continue;
            };
            let range = self.range(b);
            let terms: Vec<(usize, f64)> = terms.map(|&(k, c)| (k - range.start, c)).collect();
            for (i, col) in range.enumerate() {
                let v: f64 = terms.iter().map(|&(local, c)| c * bm[(local, i)]).sum();
                if v != 0.0 {
                    trip.push(Triplet::new(j, col, v));
                }
            }
        }
    }

    /// Pushes c·(row k of B) into row j: the entries B_k· over k's body; on the sparse path
    /// c·n_kᵀ δu at k's node instead (δU_k, which the body's rows tie to δτ).
    fn push_row(&self, trip: &mut Vec<Triplet<usize, usize, f64>>, j: usize, k: usize, c: f64) {
        let b = self.body_of[k];
        let range = self.range(b);
        let local = k - range.start;
        let Some(bm) = &self.response[b] else {
            if let Some((offset, dofs)) = self.sparse_dofs(k) {
                for &(r, n) in dofs {
                    trip.push(Triplet::new(j, offset + r, c * n));
                }
            }
            return;
        };
        for (i, col) in range.enumerate() {
            let v = c * bm[(local, i)];
            if v != 0.0 {
                trip.push(Triplet::new(j, col, v));
            }
        }
    }

    /// The column of the first reduced unknown of point k's body in the Newton system, and the
    /// point's reduced DOFs with their normal components (`None` for a dense body).
    fn sparse_dofs(&self, k: usize) -> Option<(usize, &[(usize, f64)])> {
        let b = self.body_of[k];
        let local = k - self.range(b).start;
        let dofs = match (&self.parts[b], self.bodies[b].as_ref()) {
            (BodyPart::Remote(rows), _) => rows.point_dofs(local),
            (_, Some(body)) => body.sparse().map_or(&[][..], |s| s.point_dofs(local)),
            (_, None) => &[],
        };
        Some((self.sparse_offset[b]?, dofs))
    }

    /// ‖R‖ with the components along the kernel `z` removed (those are the bodies' balance,
    /// which no step along z changes).
    /// Infinite where a floating body has no closed point: R leaves out its balance (the
    /// kernel), and a state that nothing holds is no solution however small R is there (with the
    /// starting value u⁰ = 0 and a stiff penalty it is tiny).
    fn merit(&self, z: &[Vec<f64>], eval: &Evaluation) -> f64 {
        if eval.stranded.is_some() {
            return f64::INFINITY;
        }
        let mut r = eval.scaled_residual(&self.rho);
        for e in z {
            let d = dot(e, &r);
            r.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
        }
        dot(&r, &r).sqrt()
    }
}

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
/// either: alive while the next step's triplets and matrix are built, they made that moment the
/// run's peak, and the pattern changes nothing in them but their buffers' capacity.
fn sparse_solve(
    trip: Vec<Triplet<usize, usize, f64>>,
    n: usize,
    rhs: &mut Mat<f64>,
    cache: Option<&Mutex<LuCache>>,
    refine: Option<&dyn Fn(&Mat<f64>) -> Option<Mat<f64>>>,
) -> Option<()> {
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).ok()?;
    drop(trip);
    let mut fresh = LuCache::default();
    let mut guard = match cache {
        Some(c) => Some(c.lock().ok()?),
        None => None,
    };
    let kept = guard.as_deref_mut().unwrap_or(&mut fresh);
    // 32-bit indices shrink the index arrays of the matrix, of its transpose in faer's workspace
    // and of the LU: about 60 MB of the 1 GB peak on the 4000 × 16 strip, with the same values.
    // A factor whose positions do not fit in them is factorised with 64-bit indices.
    let a = match narrow(a) {
        Ok(a) => match lu_solve(a, &mut kept.narrow, rhs, refine) {
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
    refine: Option<&dyn Fn(&Mat<f64>) -> Option<Mat<f64>>>,
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
    for _ in 0..refine.map_or(0, |_| MAX_REFINE) {
        let Some(mut r) = refine.and_then(|f| f(rhs)) else {
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

/// Solves the Newton system (given by its triplets) in place by dense LU with partial pivoting,
/// for a system whose blocks fill most of it. Sequential, like [`sparse_solve`].
fn dense_solve(trip: &[Triplet<usize, usize, f64>], n: usize, rhs: &mut Mat<f64>) -> Option<()> {
    use faer::linalg::lu::partial_pivoting::{factor, solve};
    let mut a = Mat::<f64>::zeros(n, n);
    for t in trip {
        a[(t.row, t.col)] += t.val;
    }
    let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
    let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())
        .or(solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq));
    let mut mem = MemBuffer::try_new(req).ok()?;
    let (_, p) = factor::lu_in_place(
        a.as_mut(),
        &mut perm,
        &mut perm_inv,
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    );
    solve::solve_in_place_with_conj(
        a.as_ref(),
        a.as_ref(),
        p,
        Conj::No,
        rhs.as_mut(),
        Par::Seq,
        MemStack::new(&mut mem),
    );
    Some(())
}

/// What the sparse LU of the last Newton step on the sparse path leaves for the next, per index
/// type ([`sparse_solve`]).
#[derive(Default)]
struct LuCache {
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

/// One point per kernel vector where the vectors restricted to these points are regular:
/// Gaussian elimination with complete pivoting on the columns of `z`.
fn pin_points(z: &[Vec<f64>]) -> Vec<usize> {
    let mut cols: Vec<Vec<f64>> = z.to_vec();
    let mut pins: Vec<usize> = Vec::with_capacity(z.len());
    for q in 0..cols.len() {
        let (j, _) = cols[q]
            .iter()
            .enumerate()
            .filter(|(j, _)| !pins.contains(j))
            .fold((0, -1.0), |best, (j, v)| {
                if v.abs() > best.1 {
                    (j, v.abs())
                } else {
                    best
                }
            });
        let pivot = cols[q][j];
        for r in q + 1..cols.len() {
            let f = cols[r][j] / pivot;
            let (head, tail) = cols.split_at_mut(r);
            tail[0]
                .iter_mut()
                .zip(&head[q])
                .for_each(|(x, y)| *x -= f * y);
        }
        pins.push(j);
    }
    pins
}

/// The (row, column, value) entries sorted by position, duplicates summed in their order.
fn merge(mut entries: Vec<(usize, usize, f64)>) -> Vec<(usize, usize, f64)> {
    entries.sort_by_key(|e| (e.0, e.1));
    let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(entries.len());
    for (a, b, v) in entries {
        match merged.last_mut() {
            Some(last) if (last.0, last.1) == (a, b) => last.2 += v,
            _ => merged.push((a, b, v)),
        }
    }
    merged
}

/// The most kernel vectors [`System::kernel`] can return: the number of free rigid modes.
fn modes_bound(mode_range: &[Range<usize>]) -> usize {
    mode_range.iter().map(|r| r.end).max().unwrap_or(0)
}

/// The stop of a solve that broke down at iteration `k` because of `body`.
fn diverged(body: usize, k: usize, reason: Breakdown) -> Stop {
    Stop::Diverged {
        body,
        iteration: k,
        reason,
    }
}

/// Whether ‖R̂‖ = `f` after a step of length `alpha` falls enough below `reference` (Armijo); a
/// state that nothing holds (infinite ‖R̂‖) never does.
fn decreases(f: f64, reference: f64, alpha: f64) -> bool {
    f.is_finite() && f <= (1.0 - ARMIJO * alpha) * reference
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// The state of one Newton run.
struct Run<'s, 'a> {
    system: &'s System<'a>,
    scale: &'s [f64],
    tau: Vec<f64>,
    state: Evaluation,
    history: Vec<Record>,
    /// The last body that a step found pulled away from its partners (see [`Run::watch`]).
    pulled: Option<usize>,
}

/// The watchdog's reference: the last state whose ‖R̂‖ a step decreased enough, with the closed
/// set, kernel and Newton step taken from it.
struct Checkpoint {
    tau: Vec<f64>,
    state: Evaluation,
    /// ‖R̂‖ there, the value that full steps must fall below.
    merit: f64,
    chi: Vec<bool>,
    z: Vec<Vec<f64>>,
    delta: Vec<f64>,
    /// Full steps taken since without that decrease.
    steps: usize,
}

/// One iteration's move: the step length, the closed set and Newton step it went along, and the
/// state it reached.
struct Step {
    alpha: f64,
    chi: Vec<bool>,
    delta: Vec<f64>,
    next: Evaluation,
}

impl<'s, 'a> Run<'s, 'a> {
    /// Starts from the interface loads `warm`, or else from the paper's initial value u⁰ on
    /// every contact point.
    fn new(
        system: &'s System<'a>,
        prepared: &'s Prepared,
        warm: Option<&[f64]>,
        settings: &Settings,
    ) -> Self {
        let mut t = vec![0.0; system.len()];
        for (b, body) in system.bodies.iter().enumerate() {
            let range = system.range(b);
            match (warm, body) {
                (Some(warm), _) => t[range.clone()].copy_from_slice(&warm[range]),
                // Where the penalty problem has one solution, a sparse body starts unloaded:
                // its load for u⁰ takes conjugate gradients that cost more than a Newton step.
                (None, Some(body)) if body.sparse().is_some() && system.variational => {}
                (None, Some(body)) => {
                    let u0 = starting_values(system.interface, range.clone(), settings.u0);
                    t[range].copy_from_slice(&body.initial_load(&u0))
                }
                (None, None) => {}
            }
        }
        if warm.is_none() {
            share_slices(system.exchange, &system.interface.body_range, &mut t);
        }
        let tau: Vec<f64> = t
            .iter()
            .zip(&system.d0)
            .map(|(t, &d)| if d > 0.0 { t / d } else { 0.0 })
            .collect();
        let state = system.evaluate(&tau);
        Run {
            system,
            scale: &prepared.scale,
            tau,
            state,
            history: Vec::new(),
            pulled: None,
        }
    }

    fn solve(&mut self, settings: &Settings, hooks: Hooks<'_>) -> (Stop, usize) {
        let mut watchdog: Option<Checkpoint> = None;
        for k in 1..=settings.max_iter {
            if hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return (Stop::Interrupted, k - 1);
            }
            if let Some(b) = self.system.unresisted(&self.state.free) {
                return (diverged(b, k, Breakdown::LostContact), k);
            }
            let chi = self.system.jacobian_set(&self.state);
            let found;
            let free = if chi == self.state.closed {
                &self.state.free
            } else {
                found = self.system.free_motions(&chi);
                &found
            };
            let z = self.system.kernel(free);
            let r = self.system.residual(&self.tau, &self.state, &chi);
            let Some(delta) = self.system.step(&chi, &z, &r, FORCING * settings.tol) else {
                return (self.failure(k, Breakdown::Singular), k);
            };
            let checkpoint = watchdog.take().unwrap_or_else(|| Checkpoint {
                tau: self.tau.clone(),
                state: self.state.clone(),
                merit: self.system.merit(&z, &self.state),
                chi: chi.clone(),
                z: z.clone(),
                delta: delta.clone(),
                steps: 0,
            });
            let step = match self.watch(k, checkpoint, chi, &z, delta) {
                Ok((step, kept)) => {
                    watchdog = kept;
                    step
                }
                Err(stop) => return (stop, k),
            };
            let record = self.record(k, step.alpha, &step.next);
            if let Some(f) = hooks.on_iteration {
                f(&record);
            }
            let converged = self.converged(&step, &record, settings.tol);
            self.history.push(record);
            self.tau = self.along(&step.delta, step.alpha);
            self.state = step.next;
            if converged {
                return (Stop::Converged, k);
            }
        }
        (Stop::MaxIterations, settings.max_iter)
    }

    /// The watchdog's step `k` along `delta` (with closed set `chi` and kernel `z`): the full
    /// step while `checkpoint` allows it, else back to the checkpoint and along its step. Also
    /// returns the checkpoint to keep (`None` once a step decreased its ‖R̂‖ enough: the next
    /// state is the next checkpoint), or the stop when a body is pulled away or the step fails.
    fn watch(
        &mut self,
        k: usize,
        mut checkpoint: Checkpoint,
        chi: Vec<bool>,
        z: &[Vec<f64>],
        delta: Vec<f64>,
    ) -> Result<(Step, Option<Checkpoint>), Stop> {
        let mut full = (checkpoint.steps < WINDOW)
            .then(|| {
                let next = self.along(&delta, 1.0);
                self.system.evaluate_step(&next, &self.state, &delta)
            })
            .filter(|next| self.check(&next.u).is_none());
        // A body that nothing held, and that the step (which closed all its points) leaves held
        // by none again, is pulled away from its partners. Unless the checkpoint holds every
        // body: the glued step can also strand a pressed body while other bodies' closed sets are
        // still wrong (an own-side wall), so the watchdog goes back there; a failure later names
        // the body.
        let pulled = self
            .state
            .stranded
            .filter(|&b| full.as_ref().is_some_and(|next| next.stranded == Some(b)));
        if let Some(body) = pulled {
            if checkpoint.merit.is_infinite() {
                return Err(diverged(body, k, Breakdown::LostContact));
            }
            self.pulled = Some(body);
            full = None;
        }
        if let Some(next) = full {
            let kept =
                (!decreases(self.system.merit(z, &next), checkpoint.merit, 1.0)).then(|| {
                    checkpoint.steps += 1;
                    checkpoint
                });
            let step = Step {
                alpha: 1.0,
                chi,
                delta,
                next,
            };
            return Ok((step, kept));
        }
        // Back to the checkpoint, and along its step as far as its ‖R̂‖ decreases.
        self.tau = checkpoint.tau;
        self.state = checkpoint.state;
        let Some((alpha, next)) =
            self.line_search(&checkpoint.z, &checkpoint.delta, checkpoint.merit)
        else {
            return Err(self.failure(k, Breakdown::NoDescent));
        };
        if let Some((body, reason)) = self.check(&next.u) {
            return Err(diverged(body, k, reason));
        }
        let step = Step {
            alpha,
            chi: checkpoint.chi,
            delta: checkpoint.delta,
            next,
        };
        Ok((step, None))
    }

    /// Whether `step` ends the solve. A full step that leaves the closed set as it was solved the
    /// (then linear) equations: the primal–dual active set method's own stopping rule, confirmed
    /// by the residual (it keeps any part along the kernel). Otherwise the relative change
    /// decides. A floating body that nothing holds has no determined position: never a solution.
    fn converged(&self, step: &Step, record: &Record, tol: f64) -> bool {
        let next = &step.next;
        let exact = step.chi == self.state.closed
            && next.closed == step.chi
            && norm(&next.scaled_residual(&self.system.rho)) <= tol * norm(&next.u);
        step.alpha == 1.0
            && (exact || record.rel_change.iter().all(|&r| r <= tol))
            && next.stranded.is_none()
    }

    /// τ + α δ.
    fn along(&self, delta: &[f64], alpha: f64) -> Vec<f64> {
        self.tau
            .iter()
            .zip(delta)
            .map(|(t, d)| t + alpha * d)
            .collect()
    }

    /// Backtracks along δ from half a step until ‖R̂‖ falls enough below `merit` (the full step
    /// was tried by the watchdog); the step length and the state there, or `None` when no step
    /// length decreases it.
    fn line_search(&self, z: &[Vec<f64>], delta: &[f64], merit: f64) -> Option<(f64, Evaluation)> {
        let mut alpha = 0.5;
        for _ in 1..=MAX_HALVINGS {
            let eval = self.system.evaluate(&self.along(delta, alpha));
            let f = self.system.merit(z, &eval);
            if decreases(f, merit, alpha) {
                return Some((alpha, eval));
            }
            alpha *= 0.5;
        }
        None
    }

    /// The first body with non-finite or too large normal displacements.
    fn check(&self, u: &[f64]) -> Option<(usize, Breakdown)> {
        (0..self.system.bodies.len()).find_map(|b| {
            let v = &u[self.system.range(b)];
            if !v.iter().all(|x| x.is_finite()) {
                Some((b, Breakdown::NonFinite))
            } else if v.iter().any(|x| x.abs() > self.scale[b]) {
                Some((b, Breakdown::Growth))
            } else {
                None
            }
        })
    }

    /// The body that nothing holds in the current state, if any.
    fn stranded(&self) -> Option<usize> {
        self.state.stranded
    }

    /// The stop when the steps make no progress or J is singular: a body that lost its hold (now,
    /// or at a step the watchdog went back from), or `otherwise`.
    fn failure(&self, k: usize, otherwise: Breakdown) -> Stop {
        match self.stranded().or(self.pulled) {
            Some(b) => diverged(b, k, Breakdown::LostContact),
            None => diverged(0, k, otherwise),
        }
    }

    fn record(&self, k: usize, alpha: f64, next: &Evaluation) -> Record {
        let interface = self.system.interface;
        let (active, contact_force) = contact_summary(interface, &next.s, self.system.bodies.len());
        Record {
            k,
            gamma: alpha,
            rel_change: relative_change(interface, &next.u, &self.state.u),
            active,
            contact_force,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::condensed::Condensation;
    use crate::model::Model;
    use crate::solver::prepare_with;

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
        assert!(system.symmetric);
        // An arbitrary start: its residual also acts along the kernel (μ ≠ 0).
        let mut tau: Vec<f64> = (0..system.len()).map(|j| 1e-4 * (j as f64).sin()).collect();
        let mut symmetric = 0;
        for _ in 0..2 {
            let eval = system.evaluate(&tau);
            let chi = system.jacobian_set(&eval);
            let z = system.kernel(&system.free_motions(&chi));
            assert_eq!(z.len(), 1, "one free motion");
            let r = system.residual(&tau, &eval, &chi);
            system.symmetric = false;
            let lu = system.step(&chi, &z, &r, 0.0).expect("the LU step");
            // Unrefined (any accuracy will do): the symmetric form itself must be exact.
            if let Some(sym) = system.symmetric_step(&chi, &z, &r, f64::INFINITY) {
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
