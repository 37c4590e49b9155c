//! The monolithic reference with friction in space (docs/three-d.md, "Friction in space"): the
//! decomposition's discrete problem, solved on the coupled system by another algorithm, so that
//! the two check each other.
//!
//! Coulomb's law is met by successive approximations on the bound: each approximation is a
//! Tresca problem with the bounds b_j of the last one's pressures (μ p_j; the Tresca bound where
//! p_j > 0), starting from tangential bonding (b = ∞), until the bounds repeat. A Tresca problem
//! with given bounds minimises the convex energy
//!
//!   ½ uᵀK u − fᵀu + Σ_j (w_j/2θ) max(0, s_j − d_j)² + Σ_j w_j H_b(t_j),
//!   H_b(t) = θ|t|²/2 (|t| ≤ b),  θ(b|t| − b²/2) (|t| > b),
//!
//! t_j = λ_j − (g_j − g₀_j)/θ the trial traction, whose gradient gives the forces −w p a and
//! w P_b(t) along the tangential rows. A semismooth Newton method minimises it, its generalised
//! Hessian K + the closed points' springs + (w/θ) Tᵀ T where a point sticks and (w/θ) Tᵀ M T
//! where it slips (M the derivative of the projection, symmetric), with backtracking on the
//! energy. The decomposition instead linearises Coulomb's law whole, pressures and tractions
//! together, on the contact points.

use contactdd_core::factor::FactoredBody;

use crate::contact3d::disc::{derivative, project, DiscStatus};
use crate::solid_contact::{
    point_dofs, Row, SolidContactError, SolidContactPoint, SolidFrictionPoint, MAX_STEPS,
};
use crate::Friction;

/// The bounds repeat when they change by at most this much of the largest.
const BOUND_TOL: f64 = 1e-12;

/// The most successive approximations of the bounds.
const MAX_UPDATES: usize = 500;

/// A Newton step that changes no status and moves u by at most this much of its size ends the
/// minimisation: the next would move it by about the square of that.
const STEP_TOL: f64 = 1e-9;

/// The most halvings of a Newton step along which the energy does not fall.
const HALVINGS: usize = 40;

/// The displacements of the coupled system, the contact points and the Newton steps taken in
/// all, for the `rows` (which start from the tractions and slips `carried`), from the first
/// closed set `closed`.
pub(crate) fn frictional(
    system: &mut FactoredBody,
    (rows, carried): (&[Row], &[[[f64; 2]; 2]]),
    f: &[f64],
    closed: Vec<bool>,
) -> Result<(Vec<f64>, Vec<SolidContactPoint>, usize), SolidContactError> {
    if rows.iter().any(|r| r.exact) {
        return Err(SolidContactError::Unsupported(
            "the monolithic reference in space takes friction with penalty pairs only; solve augmented frictional pairs with the decomposition".into(),
        ));
    }
    let mut tresca = Tresca {
        system,
        rows,
        carried,
        f,
        steps: 0,
    };
    let mut bounds = vec![f64::INFINITY; rows.len()];
    let mut u = tresca.settle(vec![0.0; f.len()], &bounds, Some(closed))?;
    let mut change = f64::INFINITY;
    for _ in 0..MAX_UPDATES {
        let next: Vec<f64> = rows.iter().map(|r| law_bound(r, read(r, &u).0)).collect();
        let scale = next.iter().fold(f64::MIN_POSITIVE, |a, &b| a.max(b));
        change = (next.iter().zip(&bounds))
            .map(|(a, b)| if a == b { 0.0 } else { (a - b).abs() })
            .fold(0.0, f64::max);
        bounds = next;
        if change <= BOUND_TOL * scale {
            let points = (rows.iter().zip(carried))
                .map(|(r, &c)| point(r, c, &u))
                .collect();
            return Ok((u, points, tresca.steps));
        }
        u = tresca.settle(u, &bounds, None)?;
    }
    Err(SolidContactError::NotEnforced {
        updates: MAX_UPDATES,
        violation: change,
    })
}

/// Point `r`'s approach and pressure, and its slip, read from `u`.
fn read(r: &Row, u: &[f64]) -> (f64, [f64; 2]) {
    let dot = |a: &[(usize, f64)]| a.iter().map(|&(i, x)| x * u[i]).sum::<f64>();
    let s = dot(&r.a);
    let pressure = (s - r.point.gap).max(0.0) / r.theta;
    (pressure, [dot(&r.tangents[0]), dot(&r.tangents[1])])
}

/// The law's bound at pressure `p`: μ p, or the Tresca bound where the point presses.
fn law_bound(r: &Row, p: f64) -> f64 {
    match r.friction {
        Friction::Coulomb { mu } => mu * p,
        Friction::Tresca { bound } if p > 0.0 => bound,
        _ => 0.0,
    }
}

/// The trial traction of point `r` at slip `g`, from the traction and slip `carried`.
fn trial(r: &Row, [lambda, g0]: [[f64; 2]; 2], g: [f64; 2]) -> [f64; 2] {
    [0, 1].map(|c| lambda[c] - (g[c] - g0[c]) / r.theta)
}

/// Point `r` of the solution `u`.
fn point(r: &Row, carried: [[f64; 2]; 2], u: &[f64]) -> SolidContactPoint {
    let (pressure, slip) = read(r, u);
    let friction = r.friction.is_active().then(|| {
        let (traction, status) = project(trial(r, carried, slip), law_bound(r, pressure));
        SolidFrictionPoint {
            tangents: r.frame,
            traction,
            slip,
            carried,
            status: (pressure > 0.0).then_some(status),
        }
    });
    SolidContactPoint {
        pressure,
        friction,
        ..r.point.clone()
    }
}

/// The Tresca problems of the successive approximations on the coupled system.
struct Tresca<'a> {
    system: &'a mut FactoredBody,
    rows: &'a [Row],
    carried: &'a [[[f64; 2]; 2]],
    f: &'a [f64],
    steps: usize,
}

/// A point's status in a Tresca problem: closed or not, and stick or slip where its bound is
/// not zero.
type Status = (bool, Option<DiscStatus>);

impl Tresca<'_> {
    /// Minimises the energy with the `bounds` from `u`, the first step with the closed set
    /// `first` (every point of it sticking) where given.
    fn settle(
        &mut self,
        mut u: Vec<f64>,
        bounds: &[f64],
        mut first: Option<Vec<bool>>,
    ) -> Result<Vec<f64>, SolidContactError> {
        let mut energy = self.energy(&u, bounds);
        for _ in 0..MAX_STEPS {
            self.steps += 1;
            let status: Vec<Status> = match first.take() {
                Some(c) => c
                    .into_iter()
                    .map(|c| (c, Some(DiscStatus::Stick)))
                    .collect(),
                None => self.status(&u, bounds),
            };
            let (additions, rhs) = self.linearised(&u, bounds, &status);
            let step = self.steps;
            let fail = |e: contactdd_core::BodyError| SolidContactError::Factor {
                step,
                message: e.to_string(),
            };
            self.system.factorize(&additions).map_err(fail)?;
            let full = self.system.solve(&rhs).map_err(fail)?;
            let (next, e, whole) = self.search(&u, full, energy, bounds);
            let change = (next.iter().zip(&u)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            let size = next.iter().fold(0.0f64, |m, a| m.max(a.abs()));
            let same = self.status(&next, bounds) == status;
            (u, energy) = (next, e);
            if whole && same && change <= STEP_TOL * size {
                return Ok(u);
            }
        }
        Err(SolidContactError::NotSettled { steps: MAX_STEPS })
    }

    /// Every point's status at `u`.
    fn status(&self, u: &[f64], bounds: &[f64]) -> Vec<Status> {
        (self.rows.iter().zip(self.carried).zip(bounds))
            .map(|((r, &c), &b)| {
                let (p, g) = read(r, u);
                let stick = match (r.friction.is_active(), b) {
                    (false, _) | (_, 0.0) => None,
                    _ => Some(project(trial(r, c, g), b).1),
                };
                (p > 0.0, stick)
            })
            .collect()
    }

    /// The energy at `u` with the `bounds`.
    fn energy(&self, u: &[f64], bounds: &[f64]) -> f64 {
        let k = self.system.stiffness();
        let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        let mut e = 0.0;
        for c in 0..u.len() {
            let ku: f64 = (cp[c]..cp[c + 1]).map(|x| val[x] * u[ri[x]]).sum();
            e += 0.5 * u[c] * ku - self.f[c] * u[c];
        }
        for ((r, &carried), &b) in self.rows.iter().zip(self.carried).zip(bounds) {
            let (p, g) = read(r, u);
            e += 0.5 * r.point.weight * r.theta * p * p;
            if r.friction.is_active() {
                let t = trial(r, carried, g);
                let size = t[0].hypot(t[1]);
                let h = match size <= b {
                    true => 0.5 * size * size,
                    false => b * size - 0.5 * b * b,
                };
                e += r.point.weight * r.theta * h;
            }
        }
        e
    }

    /// The step from `u` towards `full`, halved until the energy falls below `energy` (or
    /// whole where no halving lowers it): the iterate, its energy, whether it is whole.
    fn search(
        &self,
        u: &[f64],
        full: Vec<f64>,
        energy: f64,
        bounds: &[f64],
    ) -> (Vec<f64>, f64, bool) {
        let whole = self.energy(&full, bounds);
        // The energy's own rounding: a step that changes it by less neither helps nor harms.
        if whole <= energy + 1e-14 * energy.abs() {
            return (full, whole, true);
        }
        let mut omega = 1.0;
        for _ in 0..HALVINGS {
            omega /= 2.0;
            let next: Vec<f64> = (u.iter().zip(&full))
                .map(|(a, b)| a + omega * (b - a))
                .collect();
            let e = self.energy(&next, bounds);
            if e < energy {
                return (next, e, false);
            }
        }
        (full, whole, true)
    }

    /// The Hessian's contact additions (each unordered DOF pair once) and the right-hand side
    /// whose solution is the Newton iterate from `u` under the statuses `status`.
    fn linearised(
        &self,
        u: &[f64],
        bounds: &[f64],
        status: &[Status],
    ) -> (Vec<(usize, usize, f64)>, Vec<f64>) {
        let (mut additions, mut rhs) = (Vec::new(), self.f.to_vec());
        for (j, r) in self.rows.iter().enumerate() {
            let dofs = point_dofs(r);
            let local = |row: &[(usize, f64)]| {
                let mut v = vec![0.0; dofs.len()];
                for &(i, x) in row {
                    v[dofs.binary_search(&i).unwrap_or(0)] += x;
                }
                v
            };
            let n = dofs.len();
            let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n]);
            let w = r.point.weight;
            let add = |a: &mut [f64], x: &[f64], y: &[f64], c: f64| {
                (0..n).for_each(|p| (0..n).for_each(|q| a[p * n + q] += c * x[p] * y[q]));
            };
            if status[j].0 {
                let an = local(&r.a);
                add(&mut a, &an, &an, w / r.theta);
                (0..n).for_each(|p| b[p] += w / r.theta * r.point.gap * an[p]);
            }
            if let Some(s) = status[j].1 {
                let t = [local(&r.tangents[0]), local(&r.tangents[1])];
                let [lambda, g0] = self.carried[j];
                let held = [0, 1].map(|c| lambda[c] + g0[c] / r.theta);
                let (m, force) = match s {
                    DiscStatus::Stick => ([[1.0, 0.0], [0.0, 1.0]], held),
                    DiscStatus::Slip => {
                        let tr = trial(r, self.carried[j], read(r, u).1);
                        let (m, dir) = derivative(tr, bounds[j]);
                        let mh = |c: usize| m[c][0] * held[0] + m[c][1] * held[1];
                        (m, [0, 1].map(|c| bounds[j] * dir[c] + mh(c)))
                    }
                };
                for c in 0..2 {
                    for d in 0..2 {
                        add(&mut a, &t[c], &t[d], w / r.theta * m[c][d]);
                    }
                    (0..n).for_each(|p| b[p] += w * force[c] * t[c][p]);
                }
            }
            for p in 0..n {
                rhs[dofs[p]] += b[p];
                for q in 0..=p {
                    if a[p * n + q] != 0.0 {
                        additions.push((dofs[p], dofs[q], a[p * n + q]));
                    }
                }
            }
        }
        (additions, rhs)
    }
}
