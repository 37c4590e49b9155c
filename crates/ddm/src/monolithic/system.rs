//! The reduced penalty equations on the contact DOFs of all bodies, x, and their semismooth
//! Newton linearisation.
//!
//! With the interior eliminated ([`super::reduced`]), the assembled equations read
//!   F(x, λ) = S x − g + Σ_j λ_j n_j = 0,   λ_j = k_j (s_j(x) − d_j)⁺,   k_j = w_j/θ_j,
//! where λ_j is the nodal contact force of point j, n_j acts on the contact DOFs of its node and
//! s_j(x) = u_n,j + Σ_k c_jk u_n,k is the pair sum (affine in x: prescribed DOFs give a constant).
//! The penalty law is written as the complementarity function
//!   Φ_j = λ_j − max(0, λ_j + ρ_j (k_j (s_j − d_j) − λ_j)),   ρ_j = b_j / (b_j + k_j),
//! with b_j the body's own stiffness at the point (the diagonal of S along n_j): the primal–dual
//! active set rule decides on the force scaled by the body's stiffness, and the closed rows of Φ
//! are of the size of the body's forces rather than the penalty's, so a stiff penalty does not
//! let a point at the zone's edge dominate the merit. At a solution λ_j = k_j (s_j − d_j)⁺, the
//! penalty law itself.
//!
//! For a closed set χ, eliminating δλ (closed: δλ_j = k_j ∂s_j δx + k_j (s_j − d_j) − λ_j; open:
//! δλ_j = −λ_j) leaves J_χ δx = rhs with J_χ = S + Σ_{j∈χ} k_j n_j ∂s_jᵀ: dense blocks per body
//! coupled only across closed pairs, non-symmetric for non-matching meshes.
//!
//! A carrier j of a frictional pair adds its tangential force: with g_j(x) = Σ_k c_jk u_k its
//! tangential row (affine in x like s_j) and σ_t,j = proj_[−b_j, b_j](λ_t − (g_j − g₀)/θ_t) its
//! traction (b_j = μ p_j or the Tresca bound, p_j = (s_j − d_j + θλ_j)/θ where positive),
//!   F gains −w_j σ_t,j ∂g_j,
//! a function of x alone. Its semismooth derivative adds to J_χ the stick spring
//! (w_j/θ_t) ∂g_j ∂g_jᵀ, or on the slip edge of Coulomb's disc −(w_j μ sign/θ) ∂g_j ∂s_jᵀ (not
//! symmetric); Tresca's slip and open points add nothing.

use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

use contactdd_core::rigid::RigidSpan;
use contactdd_core::{dof, DIM};

use crate::contact::{Interface, Status};
use crate::model::Model;

use super::reduced::ReducedBody;

/// A kernel motion's values on x: (index, value), ascending, on its bodies' parts of x only.
pub(super) type Sparse = Vec<(usize, f64)>;

/// An affine function of x: Σ coef·x[index] + constant.
#[derive(Clone, Debug, Default)]
pub(super) struct Affine {
    pub terms: Vec<(usize, f64)>,
    pub constant: f64,
}

impl Affine {
    pub fn at(&self, x: &[f64]) -> f64 {
        self.constant + self.terms.iter().map(|&(i, c)| c * x[i]).sum::<f64>()
    }
}

/// The reduced system of a model.
pub(super) struct ReducedSystem<'a> {
    pub interface: &'a Interface,
    pub bodies: &'a [ReducedBody],
    /// First x index of every body.
    pub offset: Vec<usize>,
    /// Size of x.
    pub n: usize,
    /// The normal displacement u_n,j of every contact point.
    pub un: Vec<Affine>,
    /// The pair sum s_j of every contact point.
    pub s: Vec<Affine>,
    /// The tangential displacement g_j of every frictional point (`None` elsewhere).
    pub g: Vec<Option<Affine>>,
    /// True if some point has friction.
    pub friction: bool,
    /// ρ_j of every contact point.
    rho: Vec<f64>,
    /// Bounding box diameter of every body.
    pub size: Vec<f64>,
    /// Per body, an orthonormal basis of its free rigid motions on its part of x.
    pub rigid: Vec<RigidSpan>,
}

/// F, Φ and the closed set at one (x, λ).
#[derive(Clone)]
pub(super) struct Evaluation {
    pub s: Vec<f64>,
    pub closed: Vec<bool>,
    pub f: Vec<f64>,
    pub phi: Vec<f64>,
    /// The tangential displacement g_j of every point (0 without friction; empty for a
    /// frictionless model, as are `traction` and `status`).
    pub g: Vec<f64>,
    /// The tangential traction σ_t,j of every point.
    pub traction: Vec<f64>,
    /// Where every point is on its friction disc.
    pub status: Vec<Status>,
}

impl Evaluation {
    /// Per point, true where it sticks (empty without friction).
    pub fn sticking(&self) -> Vec<bool> {
        self.status.iter().map(|&s| s == Status::Stick).collect()
    }
}

impl<'a> ReducedSystem<'a> {
    pub fn new(model: &Model, interface: &'a Interface, bodies: &'a [ReducedBody]) -> Self {
        let mut offset = Vec::with_capacity(bodies.len());
        let mut n = 0;
        for b in bodies {
            offset.push(n);
            n += b.dofs.len();
        }
        // Where every free contact DOF sits in x.
        let position: Vec<std::collections::HashMap<usize, usize>> = bodies
            .iter()
            .zip(&offset)
            .map(|(b, &o)| {
                b.dofs
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| (d, o + i))
                    .collect()
            })
            .collect();
        let un: Vec<Affine> = interface
            .points
            .iter()
            .map(|p| {
                let mut a = Affine::default();
                for c in (0..DIM).filter(|&c| p.normal[c] != 0.0) {
                    let d = dof(p.node, c);
                    match position[p.body].get(&d) {
                        Some(&i) => a.terms.push((i, p.normal[c])),
                        None => {
                            let fixed = model.bodies[p.body].constraints.get(d).unwrap_or(0.0);
                            a.constant += p.normal[c] * fixed;
                        }
                    }
                }
                a
            })
            .collect();
        let s = interface
            .points
            .iter()
            .enumerate()
            .map(|(j, p)| {
                let mut a = un[j].clone();
                for &(k, c) in &p.partner {
                    a.terms.extend(un[k].terms.iter().map(|&(i, v)| (i, c * v)));
                    a.constant += c * un[k].constant;
                }
                a
            })
            .collect();
        let rho = stiffness_shares(interface, bodies, &offset, &un);
        let g = tangential_rows(interface, &un);
        ReducedSystem {
            interface,
            bodies,
            offset,
            n,
            un,
            s,
            g,
            friction: interface.has_friction(),
            rho,
            size: model
                .bodies
                .iter()
                .map(|b| b.mesh.bounding_box_diameter())
                .collect(),
            rigid: model
                .bodies
                .iter()
                .zip(bodies)
                .map(|(body, reduced)| RigidSpan::new(&body.mesh, &body.constraints, &reduced.dofs))
                .collect(),
        }
    }

    /// Penalty stiffness k_j = w_j/θ_j.
    pub(super) fn spring(&self, j: usize) -> f64 {
        let p = &self.interface.points[j];
        p.weight / p.theta
    }

    /// s, the closed set, F and Φ at (x, λ).
    pub fn evaluate(&self, x: &[f64], lam: &[f64]) -> Evaluation {
        let points = &self.interface.points;
        let s: Vec<f64> = self.s.iter().map(|a| a.at(x)).collect();
        let closed: Vec<bool> = (0..points.len())
            .map(|j| {
                let (p, k) = (&points[j], self.spring(j));
                // A follower's own gap is a reading: only carried pressures act.
                p.carries()
                    && p.has_partner()
                    && k > 0.0
                    && lam[j] + self.rho[j] * (k * (s[j] - p.penalty_gap()) - lam[j]) > 0.0
            })
            .collect();
        let phi = (0..points.len())
            .map(|j| {
                if closed[j] {
                    self.rho[j] * (self.spring(j) * (s[j] - points[j].penalty_gap()) - lam[j])
                } else {
                    lam[j]
                }
            })
            .collect();
        let mut f = vec![0.0; self.n];
        for (b, (body, &o)) in self.bodies.iter().zip(&self.offset).enumerate() {
            let m = body.dofs.len();
            // S annihilates rigid motions: apply it to the deformation only.
            let mut xb = x[o..o + m].to_vec();
            self.rigid[b].split(&mut xb);
            for i in 0..m {
                f[o + i] = (0..m).map(|k| body.s[(i, k)] * xb[k]).sum::<f64>() - body.g[i];
            }
        }
        for (j, p) in self.interface.points.iter().enumerate() {
            for (q, share) in p.load_row(j) {
                for &(i, c) in &self.un[q].terms {
                    f[i] += lam[j] * share * c;
                }
            }
        }
        let (g, traction, status) = self.tangential(x, &s);
        for (j, row) in self.g.iter().enumerate() {
            let Some(row) = row else { continue };
            let force = points[j].weight * traction[j];
            for &(i, c) in &row.terms {
                f[i] -= force * c;
            }
        }
        Evaluation {
            s,
            closed,
            f,
            phi,
            g,
            traction,
            status,
        }
    }

    /// The tangential displacements, tractions and statuses at x for the pair sums `s` (empty
    /// without friction).
    fn tangential(&self, x: &[f64], s: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<Status>) {
        if !self.friction {
            return (Vec::new(), Vec::new(), Vec::new());
        }
        let g: Vec<f64> = self
            .g
            .iter()
            .map(|row| row.as_ref().map_or(0.0, |a| a.at(x)))
            .collect();
        let (traction, status) = (0..g.len())
            .map(|j| self.interface.traction(j, s, &g))
            .unzip();
        (g, traction, status)
    }

    /// The Newton direction (δx, δλ) for the closed set `chi` and the frictional points'
    /// statuses `status` (empty without friction), with δx orthogonal to the
    /// orthonormal motions `z`; None if the system is singular.
    pub fn direction(
        &self,
        (chi, status): (&[bool], &[Status]),
        z: &[Sparse],
        eval: &Evaluation,
        lam: &[f64],
    ) -> Option<(Vec<f64>, Vec<f64>)> {
        let points = &self.interface.points;
        // The part of δλ that does not depend on δx.
        let lam0: Vec<f64> = (0..points.len())
            .map(|j| {
                if chi[j] {
                    self.spring(j) * (eval.s[j] - points[j].penalty_gap()) - lam[j]
                } else {
                    -lam[j]
                }
            })
            .collect();
        let mut rhs: Vec<f64> = eval.f.iter().map(|v| -v).collect();
        for (j, p) in points.iter().enumerate() {
            for (q, share) in p.load_row(j) {
                for &(i, c) in &self.un[q].terms {
                    rhs[i] -= share * c * lam0[j];
                }
            }
        }
        self.retract_tractions(status, eval, &mut rhs);
        let dx = self.solve((chi, status), z, &eval.g, &rhs)?;
        let dlam = (0..points.len())
            .map(|j| {
                if chi[j] {
                    lam0[j] + self.spring(j) * (self.s[j].at(&dx) - self.s[j].constant)
                } else {
                    lam0[j]
                }
            })
            .collect();
        Some((dx, dlam))
    }

    /// Solves [J_χ Z; Zᵀ 0] [δ; μ] = [rhs; 0] by sparse LU (dense blocks per body; the
    /// frictional terms of `status` at the tangential displacements `g`); None if singular.
    fn solve(
        &self,
        (chi, status): (&[bool], &[Status]),
        z: &[Sparse],
        g: &[f64],
        rhs: &[f64],
    ) -> Option<Vec<f64>> {
        let n = self.n;
        let mut trip = Vec::new();
        for (body, &o) in self.bodies.iter().zip(&self.offset) {
            let m = body.dofs.len();
            for k in 0..m {
                for i in 0..m {
                    let v = body.s[(i, k)];
                    if v != 0.0 {
                        trip.push(Triplet::new(o + i, o + k, v));
                    }
                }
            }
        }
        for j in (0..chi.len()).filter(|&j| chi[j]) {
            let k = self.spring(j);
            for (q, share) in self.interface.points[j].load_row(j) {
                for &(row, a) in &self.un[q].terms {
                    for &(col, b) in &self.s[j].terms {
                        trip.push(Triplet::new(row, col, k * share * a * b));
                    }
                }
            }
        }
        self.friction_terms(status, g, &mut trip);
        for (q, zq) in z.iter().enumerate() {
            for &(i, v) in zq.iter().filter(|(_, v)| *v != 0.0) {
                trip.push(Triplet::new(i, n + q, v));
                trip.push(Triplet::new(n + q, i, v));
            }
        }
        let size = n + z.len();
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(size, size, &trip).ok()?;
        let lu = a.sp_lu().ok()?;
        let b = Mat::<f64>::from_fn(size, 1, |i, _| if i < n { rhs[i] } else { 0.0 });
        let sol = lu.solve(&b);
        let delta: Vec<f64> = (0..n).map(|i| sol[(i, 0)]).collect();
        delta.iter().all(|v| v.is_finite()).then_some(delta)
    }

    /// Where the step's statuses `status` differ from the state's (points it holds), −F takes
    /// their tractions under the step's statuses (the trial traction where they stick), so that
    /// the step solves the linear equations of its own sets, as the decomposition's does.
    fn retract_tractions(&self, status: &[Status], eval: &Evaluation, rhs: &mut [f64]) {
        let points = &self.interface.points;
        for (j, row) in self.g.iter().enumerate() {
            let (Some(row), Some(f)) = (row, points[j].friction.as_ref()) else {
                continue;
            };
            if status[j] == eval.status[j] {
                continue;
            }
            let traction = match status[j] {
                Status::Stick => f.trial(eval.g[j]),
                Status::Slip => f
                    .law
                    .bound(-points[j].pressure(eval.s[j]))
                    .copysign(f.trial(eval.g[j])),
                Status::Open => 0.0,
            };
            let change = points[j].weight * (traction - eval.traction[j]);
            for &(i, c) in &row.terms {
                rhs[i] += change * c;
            }
        }
    }

    /// The friction's part of J for the statuses `status` at the tangential displacements `g`:
    /// the stick spring (w/θ_t) ∂g ∂gᵀ, Coulomb's slip term −(w μ sign/θ) ∂g ∂sᵀ.
    fn friction_terms(
        &self,
        status: &[Status],
        g: &[f64],
        trip: &mut Vec<Triplet<usize, usize, f64>>,
    ) {
        let points = &self.interface.points;
        for (j, row) in self.g.iter().enumerate() {
            let (Some(row), Some(f)) = (row, points[j].friction.as_ref()) else {
                continue;
            };
            let (k, columns) = match status[j] {
                Status::Stick => (points[j].weight / f.theta, &row.terms),
                Status::Slip => (
                    -points[j].weight * f.slip_slope(g[j]) / points[j].theta,
                    &self.s[j].terms,
                ),
                Status::Open => continue,
            };
            if k == 0.0 {
                continue;
            }
            for &(r, a) in &row.terms {
                for &(c, b) in columns {
                    trip.push(Triplet::new(r, c, k * a * b));
                }
            }
        }
    }

    /// The nodal contact forces on every body (full DOF numbering) at the state `eval`: the
    /// pressures of its pair sums and, with friction, its tangential tractions.
    pub fn contact_forces(&self, model: &Model, eval: &Evaluation) -> Vec<Vec<f64>> {
        let s = &eval.s;
        let mut out: Vec<Vec<f64>> = model
            .bodies
            .iter()
            .map(|b| vec![0.0; b.load.len()])
            .collect();
        let points = &self.interface.points;
        for (j, p) in points.iter().enumerate() {
            let force = p.weight * p.pressure(s[j]);
            for (q, share) in p.load_row(j) {
                let (body, node, normal) = (points[q].body, points[q].node, points[q].normal);
                for c in 0..DIM {
                    out[body][dof(node, c)] += share * force * normal[c];
                }
            }
        }
        for (j, p) in points.iter().enumerate().filter(|_| self.friction) {
            let Some(f) = &p.friction else { continue };
            let force = p.weight * eval.traction[j];
            for &(q, c) in &f.row {
                let (body, node, direction) = (points[q].body, points[q].node, points[q].normal);
                for d in 0..DIM {
                    out[body][dof(node, d)] += c * force * direction[d];
                }
            }
        }
        out
    }
}

/// The tangential row g_j on x of every frictional point: Σ_k c u_k over its row's unknowns.
fn tangential_rows(interface: &Interface, un: &[Affine]) -> Vec<Option<Affine>> {
    interface
        .points
        .iter()
        .map(|p| {
            p.friction.as_ref().map(|f| {
                let mut a = Affine::default();
                for &(k, c) in &f.row {
                    a.terms.extend(un[k].terms.iter().map(|&(i, v)| (i, c * v)));
                    a.constant += c * un[k].constant;
                }
                a
            })
        })
        .collect()
}

/// ρ_j = b_j/(b_j + k_j) = 1 − k_j a_jᵀ (S + Σ_i k_i a_i a_iᵀ)⁻¹ a_j per point (a_j its own
/// normal on x; the sum over its body's points): the body's share of the stiffness at the point
/// when every point carries its penalty spring. 1 where the body's matrix cannot be factorised.
fn stiffness_shares(
    interface: &Interface,
    bodies: &[ReducedBody],
    offset: &[usize],
    un: &[Affine],
) -> Vec<f64> {
    let mut rho = vec![1.0; interface.len()];
    for (b, body) in bodies.iter().enumerate() {
        let range = interface.body_range[b].clone();
        let mut m = body.s.clone();
        for j in range.clone() {
            let k = interface.points[j].weight / interface.points[j].theta;
            for &(r, a) in &un[j].terms {
                for &(c, v) in &un[j].terms {
                    m[(r - offset[b], c - offset[b])] += k * a * v;
                }
            }
        }
        let Ok(llt) = m.llt(faer::Side::Lower) else {
            continue;
        };
        for j in range {
            let p = &interface.points[j];
            let k = p.weight / p.theta;
            let mut a = Mat::<f64>::zeros(m.nrows(), 1);
            for &(r, v) in &un[j].terms {
                a[(r - offset[b], 0)] += v;
            }
            let y = llt.solve(&a);
            let share: f64 = 1.0 - k * (0..m.nrows()).map(|i| a[(i, 0)] * y[(i, 0)]).sum::<f64>();
            if share.is_finite() {
                rho[j] = share.clamp(1e-8, 1.0);
            }
        }
    }
    rho
}
