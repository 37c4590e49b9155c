//! The condensed interface problem of the Newton method: the bodies' responses, the reference
//! springs, the complementarity rule's scales, and the residual R(τ) with its closed set.

use std::ops::Range;

use faer::Mat;
use nalgebra::DVector;
use rayon::prelude::*;

use super::algebra::{dot, norm};
use crate::condensed::CondensedBody;
use crate::contact::{Interface, Role, Status};
use crate::exchange::{share_matrices, share_slices, Exchange};
use crate::prepared::Prepared;
use crate::shared_rows::{body_parts, BodyPart};

/// The condensed interface problem.
pub(super) struct System<'a> {
    pub(super) interface: &'a Interface,
    /// The bodies this process owns.
    pub(super) bodies: &'a [Option<CondensedBody>],
    pub(super) exchange: &'a dyn Exchange,
    /// B_bᵀ, the transpose of B_b = C₀D₀, of every dense body (`None` on the sparse path): its
    /// columns are the rows of B, which U = Bτ and the Jacobian's rows read.
    pub(super) response_t: Vec<Option<Mat<f64>>>,
    /// The reference springs D₀ of every point.
    pub(super) d0: Vec<f64>,
    /// How every body enters the Newton system (dense block, or sparse rows of its own or of
    /// another process).
    pub(super) parts: Vec<BodyPart>,
    /// Per body on the sparse path, the first column of its reduced unknowns in the Newton
    /// system (after the m interface unknowns and the kernel multipliers).
    pub(super) sparse_offset: Vec<Option<usize>>,
    /// Free rigid modes of the floating bodies: mode range per body, normal values per point.
    pub(super) mode_range: &'a [Range<usize>],
    pub(super) modes: &'a [Vec<f64>],
    /// The work of the bodies' loads along every free mode, and its norm.
    pub(super) mode_load: &'a [f64],
    pub(super) mode_load_norm: f64,
    /// Owning body of every point.
    pub(super) body_of: Vec<usize>,
    /// ρ_j = 1 − B_jj ∈ (0, 1]: the share of the body in the stiffness of point j with its
    /// reference spring; the complementarity rule's scale.
    pub(super) rho: Vec<f64>,
    /// Points with zero quadrature weight (D₀ = 0): they carry no force, and τ_j = 0.
    pub(super) weightless: Vec<bool>,
    /// Unknowns of balanced pairs: their contact force gathers the pressures of several points
    /// (`Interface::carried`), and their points close where s > d (ρ = 1).
    pub(super) balanced: Vec<bool>,
    /// Whether the step may take the symmetric form (`primal`).
    pub(super) symmetric: bool,
    /// Whether some point has friction.
    pub(super) friction: bool,
    /// Whether the penalty problem minimises an energy (every pair balanced, or own-side with
    /// matching sides), so that it has one solution whatever the start. Own-side pairs on
    /// non-matching meshes derive from no energy and can have several (a start decides which).
    pub(super) variational: bool,
}

/// U, s and R at one τ.
#[derive(Clone)]
pub(super) struct Evaluation {
    pub(super) u: Vec<f64>,
    pub(super) s: Vec<f64>,
    pub(super) r: Vec<f64>,
    /// The points the complementarity rule counts as closed.
    pub(super) closed: Vec<bool>,
    /// The tangential displacements g of the frictional points (empty without friction).
    pub(super) g: Vec<f64>,
    /// Where each frictional point is on its friction disc (empty without friction).
    pub(super) status: Vec<Status>,
    /// The closed frictional points' nodal forces (j, w_j σ_t,j) (empty without friction).
    pub(super) tractions: Vec<(usize, f64)>,
    /// The rigid motions of floating bodies that the closed points leave free (weights of the
    /// free modes), and the body that nothing holds there, if any.
    pub(super) free: Vec<DVector<f64>>,
    pub(super) stranded: Option<usize>,
}

impl Evaluation {
    /// R̂: the residual of the complementarity function, whose closed rows are ρ R.
    pub(super) fn scaled_residual(&self, rho: &[f64]) -> Vec<f64> {
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
    pub(super) fn new(prepared: &'a Prepared, interface: &'a Interface) -> System<'a> {
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
        let response_t: Vec<Option<Mat<f64>>> = share_matrices(exchange, dense)
            .into_iter()
            .zip(&parts)
            .map(|(m, part)| (part.sparse_free().is_none()).then(|| m.transpose().to_owned()))
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
        let rho = scales(prepared, interface, &response_t, &balanced);
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
            response_t,
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
            symmetric: false,
            friction: interface.has_friction(),
            variational: false,
        };
        // Coulomb's slip makes J nonsymmetric: the LU steps.
        system.symmetric = system.every_body_sparse() && !system.friction;
        system.variational = system.springs(&vec![true; system.len()]).is_some();
        system
    }

    pub(super) fn len(&self) -> usize {
        self.interface.len()
    }

    pub(super) fn range(&self, b: usize) -> Range<usize> {
        self.interface.body_range[b].clone()
    }

    /// U(τ), s(U) and R(τ); the bodies in parallel.
    pub(super) fn evaluate(&self, tau: &[f64]) -> Evaluation {
        let u = self.displacements(tau);
        self.evaluation(tau, u)
    }

    /// U(τ): a solve per sparse body, B τ for a dense one; the bodies in parallel.
    pub(super) fn displacements(&self, tau: &[f64]) -> Vec<f64> {
        let mut u: Vec<f64> = (0..self.bodies.len())
            .into_par_iter()
            .flat_map_iter(|b| {
                let range = self.range(b);
                let tau_b = &tau[range.clone()];
                let Some(bt) = &self.response_t[b] else {
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
                                + (bt.col(i).iter())
                                    .zip(tau_b)
                                    .map(|(b, t)| b * t)
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
    pub(super) fn evaluation(&self, tau: &[f64], u: Vec<f64>) -> Evaluation {
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
        let (g, status, tractions) = self.frictional_state(&u, &s);
        // A carrier closes exactly where its overlap is negative (ρ = 1), so its linear penalty
        // force on the closed set is its penalty force.
        let r = self.residual_on(tau, &u, (&s, &g), &closed, &status);
        let free = self.free_motions(&closed, &status);
        let stranded = self.stranded(&closed, &free, &tractions);
        Evaluation {
            u,
            s,
            r,
            closed,
            g,
            status,
            tractions,
            free,
            stranded,
        }
    }

    /// The tangential displacements, the statuses and the closed frictional points' nodal
    /// forces (j, w_j σ_t,j) at the displacements `u` and pair sums `s` (all empty without
    /// friction).
    fn frictional_state(&self, u: &[f64], s: &[f64]) -> (Vec<f64>, Vec<Status>, Vec<(usize, f64)>) {
        if !self.friction {
            return (Vec::new(), Vec::new(), Vec::new());
        }
        let g = self.interface.slip_sums(u);
        let mut tractions = Vec::new();
        let status = (0..u.len())
            .map(|j| {
                let (t, status) = self.interface.traction(j, s, &g);
                if status != Status::Open {
                    tractions.push((j, self.interface.points[j].weight * t));
                }
                status
            })
            .collect();
        (g, status, tractions)
    }

    /// R at the evaluated state with the points `chi` closed: the residual whose Jacobian the
    /// Newton step uses. It is the state's own R where `chi` is its closed set; where the step
    /// treats more points as closed (a stranded body), their penalty forces count as linear in
    /// s, so that the step solves the equations of that closed set (with the state's R the step
    /// would only move the body along the springs of points that it then finds open again).
    /// The frictional points' statuses `status` (as for [`System::residual_on`]).
    pub(super) fn residual(
        &self,
        tau: &[f64],
        eval: &Evaluation,
        chi: &[bool],
        status: &[Status],
    ) -> Vec<f64> {
        if chi == eval.closed && status == eval.status {
            return eval.r.clone();
        }
        self.residual_on(tau, &eval.u, (&eval.s, &eval.g), chi, status)
    }

    /// R(τ) for the displacements `u`, pair sums and tangential displacements `(s, g)`, the
    /// points `chi` closed, their penalty forces linear in s (F_j/w_j = (d − s)/θ), and the
    /// frictional points' tractions by `status` (empty without friction): the trial traction
    /// where they stick, the bound at the linear pressure where they slip.
    pub(super) fn residual_on(
        &self,
        tau: &[f64],
        u: &[f64],
        (s, g): (&[f64], &[f64]),
        chi: &[bool],
        status: &[Status],
    ) -> Vec<f64> {
        let points = &self.interface.points;
        let linear = |j: usize| {
            let p = &points[j];
            if chi[j] {
                (p.penalty_gap() - s[j]) / p.theta
            } else {
                0.0
            }
        };
        let traction = |j: usize| {
            let Some(f) = &points[j].friction else {
                return 0.0;
            };
            match status.get(j) {
                Some(Status::Stick) => f.trial(g[j]),
                Some(Status::Slip) => f.law.bound(-linear(j)).copysign(f.trial(g[j])),
                _ => 0.0,
            }
        };
        (0..u.len())
            .map(|j| {
                if self.weightless[j] {
                    tau[j]
                } else if self.balanced[j] {
                    let mut force: f64 = self.interface.carried[j]
                        .iter()
                        .map(|&(k, a)| a * (points[k].weight * linear(k)))
                        .sum();
                    if self.friction {
                        force += self.interface.carried_tangential[j]
                            .iter()
                            .map(|&(k, b)| b * (points[k].weight * traction(k)))
                            .sum::<f64>();
                    }
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
    pub(super) fn loads(&self, tau: &[f64]) -> Vec<f64> {
        tau.iter().zip(&self.d0).map(|(t, d)| t * d).collect()
    }

    /// The points whose pressure loads body `b`: its own, or the carriers facing it.
    pub(super) fn loaders(&self, b: usize) -> Vec<usize> {
        self.range(b)
            .flat_map(|q| self.interface.carried[q].iter().map(|&(j, _)| j))
            .collect()
    }

    /// Whether a closed point in `closed` holds body `b` (or supports do: a body without free
    /// rigid modes).
    pub(super) fn holds(&self, b: usize, closed: &[bool]) -> bool {
        self.mode_range[b].is_empty() || self.loaders(b).iter().any(|&j| closed[j])
    }

    /// The first floating body none of whose loaders is closed in `closed`: nothing holds it.
    pub(super) fn unheld(&self, closed: &[bool]) -> Option<usize> {
        (0..self.bodies.len()).find(|&b| !self.holds(b, closed))
    }

    /// The points treated as closed in J and the frictional points' statuses there: the closed
    /// points, and every partnered point that loads a floating body none of whose loading points
    /// is closed; frictional points that J treats as closed beyond the state's closed set stick.
    pub(super) fn jacobian_set(&self, eval: &Evaluation) -> (Vec<bool>, Vec<Status>) {
        let points = &self.interface.points;
        let mut chi = eval.closed.clone();
        let mut status = eval.status.clone();
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
        self.stick_where_closed(&chi, &mut status);
        // Bodies that closed points hold, but not along a motion their loads push them in (a
        // column of blocks held sideways by its neighbours, open below; a block whose frictional
        // points all slip): the points that would resist the motion count as closed.
        for _ in 0..self.bodies.len() {
            let found;
            let free = if chi == eval.closed && status == eval.status {
                &eval.free
            } else {
                found = self.free_motions(&chi, &status);
                &found
            };
            let Some(v) = self.loaded_motion(free, &eval.tractions) else {
                break;
            };
            let open: Vec<usize> = self
                .resisting(&v)
                .into_iter()
                .filter(|&j| !chi[j])
                .collect();
            // Of the slipping points that would resist it, the one nearest its disc sticks: one
            // resists the motion, and the others keep their slip.
            let nearest = self
                .resisting_tangentially(&v)
                .into_iter()
                .filter(|&j| status[j] != Status::Stick)
                .min_by(|&a, &b| self.overshoot(eval, a).total_cmp(&self.overshoot(eval, b)));
            if open.is_empty() && nearest.is_none() {
                break;
            }
            open.into_iter().for_each(|j| chi[j] = true);
            if let Some(j) = nearest {
                chi[j] = true;
                status[j] = Status::Stick;
            }
            self.stick_where_closed(&chi, &mut status);
        }
        (chi, status)
    }

    /// How far point j's trial traction lies beyond its disc at `eval`: |trial|/b (infinite
    /// where the point is open, b = 0).
    fn overshoot(&self, eval: &Evaluation, j: usize) -> f64 {
        let p = &self.interface.points[j];
        p.friction.as_ref().map_or(f64::INFINITY, |f| {
            let b = f.law.bound(-p.pressure(eval.s[j]));
            if b > 0.0 {
                f.trial(eval.g[j]).abs() / b
            } else {
                f64::INFINITY
            }
        })
    }

    /// Frictional points closed in `chi` but open in `status` stick (J treats them as closed).
    fn stick_where_closed(&self, chi: &[bool], status: &mut [Status]) {
        for (j, st) in status.iter_mut().enumerate() {
            if chi[j] && *st == Status::Open && self.interface.points[j].friction.is_some() {
                *st = Status::Stick;
            }
        }
    }

    /// ‖R‖ with the components along the kernel `z` removed (those are the bodies' balance,
    /// which no step along z changes).
    /// Infinite where a floating body has no closed point: R leaves out its balance (the
    /// kernel), and a state that nothing holds is no solution however small R is there (with the
    /// starting value u⁰ = 0 and a stiff penalty it is tiny).
    pub(super) fn merit(&self, z: &[Vec<f64>], eval: &Evaluation) -> f64 {
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

/// The most kernel vectors [`System::kernel`] can return: the number of free rigid modes.
pub(super) fn modes_bound(mode_range: &[Range<usize>]) -> usize {
    mode_range.iter().map(|r| r.end).max().unwrap_or(0)
}

/// ρ_j per point: 1 − B_jj of a dense body, the sparse body's estimate of it, and 1 on the
/// balanced pairs' unknowns.
fn scales(
    prepared: &Prepared,
    interface: &Interface,
    response_t: &[Option<Mat<f64>>],
    balanced: &[bool],
) -> Vec<f64> {
    let mut rho: Vec<f64> = response_t
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
    share_slices(&*prepared.exchange, &interface.body_range, &mut rho);
    rho.into_iter()
        .zip(balanced)
        .map(|(r, &b)| if b { 1.0 } else { r })
        .collect()
}
