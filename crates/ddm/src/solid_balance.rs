//! The independent check of a solution in space: every body's forces balance, and the pressures
//! follow the contact law from the displacements.
//!
//! For body b with the displacement u_b, its stiffness K_b assembled afresh, its loads f_b and
//! the contact forces c_b = −Σ_j w_j p_j a_j of the reported pressures, the residual
//! r_b = K_b u_b − f_b − c_b is the support reaction on the prescribed DOFs and must vanish on the
//! free ones. The net force and moment of r_b over the free DOFs (the moment over the body's size)
//! is the body's imbalance: what its loads, contact forces and reactions leave unbalanced, the
//! measure of the planar force balance (`docs/outputs.md`). It is reported relative to the
//! largest force total of a body. The contact law is read back from the displacements: point j's
//! approach s_j = a_j·u gives max(0, s_j − d_j)/θ, which the reported pressure must equal.

use contactdd_core::solid::assembly::stiffness;
use contactdd_core::solid::rigid::RigidModes;
use contactdd_core::solid::DIM3;
use rayon::prelude::*;

use crate::contact3d::disc::project;
use crate::solid_contact::{
    contact_rows, offsets, Row, SolidBodySpec, SolidContactError, SolidContactSolution,
    SolidFrictionPoint, SolidPairSpec,
};
use crate::Friction;

/// One body's balance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidBodyBalance {
    /// The largest net force or moment (over the body's size) of what the body's loads, contact
    /// forces and reactions leave unbalanced, relative to the largest force total of a body.
    pub imbalance: f64,
    /// The rounding floor of the imbalance, on the same scale: γ Σ_i Σ_j |K_ij u_j|, γ the unit
    /// roundoff times the mean number of terms of a row of K (the bound on the rounding of K u),
    /// which a displacement with large cancelling terms (a stiff body moved rigidly) reaches.
    pub floor: f64,
    /// The sum of the magnitudes of the body's nodal loads, contact forces and reactions.
    pub force_total: f64,
    /// The resultant of the support reactions.
    pub reaction: [f64; 3],
    /// The resultant of the contact forces on the body.
    pub contact: [f64; 3],
}

/// The check of a solution.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidBalance {
    /// Every body's balance.
    pub bodies: Vec<SolidBodyBalance>,
    /// The largest difference between a reported pressure and the contact law read from the
    /// displacements, relative to the largest pressure or, where larger, the largest stress
    /// E·|u|/size the displacements imply (absolute when both are zero).
    pub contact_law: f64,
    /// The largest violation of the Signorini conditions at the points of augmented pairs, a
    /// length: a penetration s − d > 0, or a gap |s − d| under pressure (0 without such points).
    pub gap_violation: f64,
    /// The largest difference between a reported traction and the friction law read from the
    /// displacements, on the scale of `contact_law` (0 without friction).
    pub friction_law: f64,
}

impl SolidBalance {
    /// The largest imbalance of a body.
    pub fn worst(&self) -> f64 {
        self.bodies.iter().map(|b| b.imbalance).fold(0.0, f64::max)
    }

    /// The body whose imbalance exceeds both `tol` and its rounding floor the most, if any.
    pub fn unbalanced(&self, tol: f64) -> Option<usize> {
        (self.bodies.iter().enumerate())
            .filter(|(_, b)| b.imbalance.is_nan() || b.imbalance > tol.max(b.floor))
            .max_by(|x, y| x.1.imbalance.total_cmp(&y.1.imbalance))
            .map(|(b, _)| b)
    }
}

/// Checks `sol` against `bodies` and `pairs`: the force balance of every body and the contact
/// law of every point. Errors if the contact rows cannot be rebuilt or the solution does not
/// match the problem (another number of bodies, DOFs or points).
pub fn solid_balance(
    bodies: &[SolidBodySpec<'_>],
    pairs: &[SolidPairSpec],
    sol: &SolidContactSolution,
) -> Result<SolidBalance, SolidContactError> {
    let (offsets, n) = offsets(bodies);
    let rows = contact_rows(bodies, &offsets, pairs)?;
    let mismatch = |what: &str| SolidContactError::Pair {
        pair: 0,
        message: format!("the solution does not match the problem: {what}"),
    };
    if rows.len() != sol.points.len() || sol.displacements.len() != bodies.len() {
        return Err(mismatch("points or bodies"));
    }
    let mut u = Vec::with_capacity(n);
    for (b, d) in bodies.iter().zip(&sol.displacements) {
        if d.len() != DIM3 * b.mesh.num_nodes() || b.load.len() != d.len() {
            return Err(mismatch("a body's DOFs"));
        }
        u.extend_from_slice(d);
    }
    let mut contact = vec![0.0; n];
    let (mut worst_law, mut largest, mut gap_violation) = (0.0f64, 0.0f64, 0.0f64);
    let mut worst_friction = 0.0f64;
    for (r, point) in rows.iter().zip(&sol.points) {
        if r.friction.is_active() {
            let Some(f) = &point.friction else {
                return Err(mismatch("a frictional point without its traction"));
            };
            worst_friction = worst_friction.max(friction_law(r, point.pressure, f, &u));
            largest = largest.max(f.traction[0].hypot(f.traction[1]));
            for (t, tau) in r.tangents.iter().zip(f.traction) {
                t.iter()
                    .for_each(|&(i, x)| contact[i] += point.weight * tau * x);
            }
        }
        let s: f64 = r.a.iter().map(|&(i, x)| x * u[i]).sum();
        let (off, violation) = normal_law(r, point.pressure, s);
        gap_violation = gap_violation.max(violation);
        worst_law = worst_law.max(off);
        largest = largest.max(point.pressure.abs());
        for &(i, x) in &r.a {
            contact[i] -= point.weight * point.pressure * x;
        }
    }
    let mut balances: Vec<SolidBodyBalance> = (bodies.par_iter().zip(&offsets))
        .map(|(b, &at)| body_balance(b, &u[at..], &contact[at..]))
        .collect();
    let scale = balances
        .iter()
        .map(|b| b.force_total)
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    balances.iter_mut().for_each(|b| {
        b.imbalance /= scale;
        b.floor /= scale;
    });
    // Relative to the largest pressure, or to the stresses the displacements imply where that
    // is larger: bodies that just touch carry pressures of rounding size, against which the
    // law's own rounding is not small.
    let stress = (bodies.iter().zip(&sol.displacements))
        .map(|(b, u)| {
            let largest = u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            b.elasticity[0][0] * largest / b.mesh.bounding_box_diameter()
        })
        .fold(0.0f64, f64::max);
    let scale = largest.max(stress);
    let relative = |x: f64| if scale > 0.0 { x / scale } else { x };
    Ok(SolidBalance {
        bodies: balances,
        contact_law: relative(worst_law),
        gap_violation,
        friction_law: relative(worst_friction),
    })
}

/// How far the pressure `p` of point `r` is from its contact law at the approach `s`, and how
/// far it violates the Signorini conditions (an exact point: a penetration s − d > 0, or a gap
/// under pressure; 0 at a penalty point).
fn normal_law(r: &Row, p: f64, s: f64) -> (f64, f64) {
    let gap = r.point.gap;
    // An exact point: the complementarity form of the Signorini conditions, in pressures.
    let law = match r.exact {
        false => (s - gap).max(0.0) / r.theta,
        true => (p + (s - gap) / r.theta).max(0.0),
    };
    let violation = match (r.exact, p <= 0.0) {
        (false, _) => 0.0,
        (true, true) => s - gap,
        (true, false) => (s - gap).abs(),
    };
    ((law - p).abs(), violation)
}

/// How far the traction `f` of frictional point `r` at pressure `p` is from the law's: the
/// projection onto the disc (radius μp, or the Tresca bound where it is closed) of
/// λ − (g − g₀)/θ, g read from `u`, λ the carried traction (the traction itself at an exact
/// point) and g₀ the carried slip.
fn friction_law(r: &Row, p: f64, f: &SolidFrictionPoint, u: &[f64]) -> f64 {
    let g = r
        .tangents
        .clone()
        .map(|t| t.iter().map(|&(i, x)| x * u[i]).sum::<f64>());
    let lambda = if r.exact { f.traction } else { f.carried[0] };
    let trial = [0, 1].map(|c| lambda[c] - (g[c] - f.carried[1][c]) / r.theta);
    let bound = match r.friction {
        Friction::Coulomb { mu } => mu * p,
        Friction::Tresca { bound } if p > 0.0 || f.status.is_some() => bound,
        _ => 0.0,
    };
    let (law, _) = project(trial, bound);
    (law[0] - f.traction[0]).hypot(law[1] - f.traction[1])
}

/// One body's balance (its imbalance still absolute): `u` and `contact` start at its DOFs.
fn body_balance(body: &SolidBodySpec<'_>, u: &[f64], contact: &[f64]) -> SolidBodyBalance {
    let n = body.load.len();
    let k = stiffness(body.mesh, &body.elasticity);
    let (mut r, mut terms) = (vec![0.0; n], 0.0);
    let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for c in 0..n {
        for x in cp[c]..cp[c + 1] {
            r[ri[x]] += val[x] * u[c];
            terms += (val[x] * u[c]).abs();
        }
    }
    let floor = f64::EPSILON / 2.0 * (val.len() as f64 / n.max(1) as f64) * terms;
    let mut prescribed = vec![false; n];
    body.prescribed
        .iter()
        .for_each(|&(d, _)| prescribed[d] = true);
    let (mut reaction, mut resultant) = ([0.0; 3], [0.0; 3]);
    let mut free = vec![0.0; n];
    let mut force_total = 0.0;
    for v in 0..n / DIM3 {
        let mut node = [0.0; 3];
        for c in 0..DIM3 {
            let i = DIM3 * v + c;
            let residual = r[i] - body.load[i] - contact[i];
            resultant[c] += contact[i];
            if prescribed[i] {
                reaction[c] += residual;
                node[c] = body.load[i] + contact[i] + residual;
            } else {
                free[i] = residual;
                node[c] = body.load[i] + contact[i];
            }
        }
        force_total += node.iter().map(|x| x * x).sum::<f64>().sqrt();
    }
    // The net force and moment (over the size) of the free residual: the rigid modes' work.
    let modes = RigidModes::new(body.mesh);
    let imbalance = modes
        .vectors(body.mesh)
        .iter()
        .map(|z| z.iter().zip(&free).map(|(a, b)| a * b).sum::<f64>().abs())
        .fold(0.0, f64::max);
    SolidBodyBalance {
        imbalance,
        floor,
        force_total,
        reaction,
        contact: resultant,
    }
}
