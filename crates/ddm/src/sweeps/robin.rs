//! One parallel Robin sweep: the domain decomposition step as a map of the interface state.
//!
//! Given the normal displacements U^k of all contact points (and their sums s^k, s^{k−1} across
//! each pair), every body computes its Robin coefficients φ^k and right-hand side (docs/method.md §3)
//! and solves its condensed Robin problem. The output is the *unrelaxed* Robin solution: the normal
//! displacements Ũ and the interface loads T̃ (so that the body's field is K₀⁻¹(f + N T̃)). The
//! relaxation and the accelerators of [`crate::sweeps`] combine these outputs.
//!
//! The bodies run in parallel with rayon; each body's arithmetic is sequential and touches only
//! its own slices, so the result does not depend on the number of threads. A process solves only
//! the bodies it owns; the iteration shares their outputs (`crate::exchange`).

use rayon::prelude::*;

use crate::condensed::{CondensedBody, RobinCache};
use crate::contact::{Interface, Role};
use crate::method::Method;
use crate::outcome::Breakdown;

/// Per-body buffers, allocated once per solve.
#[derive(Default)]
struct Scratch {
    cache: RobinCache,
    phi: Vec<f64>,
    r: Vec<f64>,
}

/// The Robin sweep of one solve: the bodies, the method and per-body buffers.
pub struct RobinSweep<'a> {
    interface: &'a Interface,
    /// The bodies this process owns (`None`: another process solves it).
    bodies: &'a [Option<CondensedBody>],
    method: Method,
    /// Retry a singular body with φ = 1 on its partnered points (the accelerated default only).
    safeguard: bool,
    /// Whether some point has friction (the sweep then reads the tangential displacements).
    friction: bool,
    scratch: Vec<Scratch>,
}

impl<'a> RobinSweep<'a> {
    /// Prepares the buffers. With `safeguard`, a body whose Robin problem is singular for the
    /// method's φ (a floating body with no closed point) is solved once more with φ = 1 wherever
    /// it has a partner (the `robin` coefficient), instead of breaking down.
    pub fn new(
        interface: &'a Interface,
        bodies: &'a [Option<CondensedBody>],
        method: Method,
        safeguard: bool,
    ) -> RobinSweep<'a> {
        let scratch = interface
            .body_range
            .iter()
            .map(|range| Scratch {
                phi: vec![0.0; range.len()],
                r: vec![0.0; range.len()],
                ..Scratch::default()
            })
            .collect();
        RobinSweep {
            interface,
            bodies,
            method,
            safeguard,
            friction: interface.has_friction(),
            scratch,
        }
    }

    /// Solves every body's Robin problem for the state `un` = U^k with sums `s` = s^k and
    /// `s_prev` = s^{k−1}; writes Ũ to `un_out` and T̃ to `t_out` for the bodies this process
    /// owns. Returns, per body, whether its Robin problem could be solved (`Ok` for the bodies of
    /// other processes).
    pub fn apply(
        &mut self,
        un: &[f64],
        s: &[f64],
        s_prev: &[f64],
        un_out: &mut [f64],
        t_out: &mut [f64],
    ) -> Vec<Result<(), Breakdown>> {
        let (interface, bodies, method, safeguard) =
            (self.interface, self.bodies, self.method, self.safeguard);
        // The frictional points' tangential displacements at U^k (empty without friction).
        let g = match self.friction {
            true => interface.slip_sums(un),
            false => Vec::new(),
        };
        let outputs = split(interface, &mut *un_out, &mut *t_out);
        self.scratch
            .par_iter_mut()
            .zip(outputs)
            .enumerate()
            .map(|(b, (scratch, (un_b, t_b)))| {
                let Some(body) = &bodies[b] else {
                    return Ok(());
                };
                let range = interface.body_range[b].clone();
                let input = BodyInput {
                    interface,
                    start: range.start,
                    un: &un[range.clone()],
                    s,
                    s_prev,
                    g: &g,
                };
                input.coefficients(method, scratch);
                let solved =
                    body.robin_solve(&scratch.phi, &scratch.r, &mut scratch.cache, un_b, t_b);
                if solved.is_ok() {
                    return Ok(());
                }
                let lost = scratch.phi.iter().all(|&f| f == 0.0);
                if safeguard {
                    input.coefficients(Method::Robin, scratch);
                    if body
                        .robin_solve(&scratch.phi, &scratch.r, &mut scratch.cache, un_b, t_b)
                        .is_ok()
                    {
                        return Ok(());
                    }
                }
                Err(if lost {
                    Breakdown::LostContact
                } else {
                    Breakdown::Singular
                })
            })
            .collect()
    }
}

/// What one body reads of the interface state.
struct BodyInput<'s> {
    interface: &'s Interface,
    /// Global index of the body's first point.
    start: usize,
    /// The body's own normal displacements U^k.
    un: &'s [f64],
    s: &'s [f64],
    s_prev: &'s [f64],
    /// The frictional points' tangential displacements g^k (empty without friction).
    g: &'s [f64],
}

impl BodyInput<'_> {
    /// φ^k and r_j = (w_j/θ_j)(φ_j U^k_j + (d_j − s^k_j)⁻) of every point of the body.
    fn coefficients(&self, method: Method, scratch: &mut Scratch) {
        let points = &self.interface.points[self.start..self.start + self.un.len()];
        for (j, p) in points.iter().enumerate() {
            if p.role != Role::OwnSide {
                (scratch.phi[j], scratch.r[j]) = self.balanced(method, self.start + j);
                continue;
            }
            if !p.has_partner() {
                // Never closes: φ = 0, no contact force.
                (scratch.phi[j], scratch.r[j]) = (0.0, 0.0);
                continue;
            }
            let g = self.start + j;
            let (s, sp) = (self.s[g], self.s_prev[g]);
            scratch.phi[j] = method.phi(p.penalty_gap(), s, sp);
            let kw = p.weight / p.theta;
            scratch.r[j] = kw * (scratch.phi[j] * self.un[j] + p.overlap(s));
        }
    }
}

impl BodyInput<'_> {
    /// φ and r of an unknown of a balanced pair: φ is the average of the Robin coefficients of the
    /// points that load it, weighted like its reference spring D₀ = Σ |a| w_j/θ_j (the lumped
    /// penalty stiffness; a carrier's own φ, as for an own-side point); its load is the contact
    /// force F_q of the state, which gathers the pressures of those points.
    fn balanced(&self, method: Method, q: usize) -> (f64, f64) {
        let p = &self.interface.points[q];
        let mut spring = 0.0;
        for &(i, a) in &self.interface.carried[q] {
            let loader = &self.interface.points[i];
            let k = loader.weight / loader.theta;
            if loader.has_partner() {
                let phi = method.phi(loader.penalty_gap(), self.s[i], self.s_prev[i]);
                spring += a.abs() * k * phi;
            }
        }
        let mut force = self.interface.force(q, self.s);
        if !self.g.is_empty() {
            let (tangential_spring, traction) = self.tangential(method, q);
            spring += tangential_spring;
            force += traction;
        }
        let phi = if p.spring > 0.0 {
            (spring / p.spring).min(1.0)
        } else {
            0.0
        };
        (phi, phi * p.spring * self.un[q - self.start] + force)
    }

    /// The tangential Robin term of unknown q: the springs Σ |b| w_j φ_t,j/θ_t,j and the forces
    /// Σ b w_j σ_t,j of the frictional points whose tractions load it, σ_t,j the return mapping
    /// at the state (with Coulomb's law the slip bound μ p of the state's pressure: the sweep
    /// solves a Tresca problem, and the bound follows the pressure from sweep to sweep).
    fn tangential(&self, method: Method, q: usize) -> (f64, f64) {
        let (mut spring, mut force) = (0.0, 0.0);
        for &(j, b) in &self.interface.carried_tangential[q] {
            let p = &self.interface.points[j];
            let Some(f) = &p.friction else { continue };
            let (traction, status) = self.interface.traction(j, self.s, self.g);
            spring += b.abs() * p.weight / f.theta * method.phi_tangential(status);
            force += b * p.weight * traction;
        }
        (spring, force)
    }
}

/// Splits two interface-sized buffers into per-body slices.
fn split<'b>(
    interface: &Interface,
    mut a: &'b mut [f64],
    mut b: &'b mut [f64],
) -> Vec<(&'b mut [f64], &'b mut [f64])> {
    let mut out = Vec::with_capacity(interface.body_range.len());
    for range in &interface.body_range {
        let (a_b, a_rest) = a.split_at_mut(range.len());
        let (b_b, b_rest) = b.split_at_mut(range.len());
        out.push((a_b, b_b));
        (a, b) = (a_rest, b_rest);
    }
    out
}
