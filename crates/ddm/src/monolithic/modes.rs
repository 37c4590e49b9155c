//! Rigid motions that no closed contact resists.
//!
//! Every body's supports leave it a few free rigid modes (the core's [`free_modes`], at most 3
//! per body, each listed once: an orthonormal basis). A combination of them over all bodies is
//! in the kernel of J_χ when it changes no closed pair sum s_j and no tangential displacement g_j
//! of a frictional point that sticks: then S, which maps a body's rigid motion to zero, and the
//! closed contact and stick terms all vanish on it (a slipping point's term acts through s_j
//! alone, so it does not resist a motion that keeps s_j). The kernel is found from the
//! Gram matrix of those changes, which holds only geometry (normals and mode values), so neither a
//! stiffness contrast nor the penalty's size moves the threshold.

use nalgebra::{DMatrix, SymmetricEigen};

use contactdd_core::rigid::{describe, free_modes, motion_on, NUM_MODES};

use crate::model::Model;

use super::system::ReducedSystem;

/// One free rigid mode of one body.
pub(super) struct Mode {
    pub body: usize,
    /// Coefficients in the body's rigid basis.
    pub coefficients: [f64; NUM_MODES],
    /// Its values on x.
    pub on_x: Vec<f64>,
    /// Its change of every contact point's pair sum.
    pub on_s: Vec<f64>,
    /// Its change of every frictional point's tangential displacement (0 elsewhere).
    pub on_g: Vec<f64>,
    /// The work of the body's applied loads along it.
    pub work: f64,
}

/// A kernel motion: a combination of modes, orthonormal on x.
pub(super) struct Kernel {
    /// Per kernel motion, its values on x.
    pub on_x: Vec<Vec<f64>>,
    /// Per kernel motion, the coefficients of every mode.
    pub weights: Vec<Vec<f64>>,
}

/// The free rigid modes of every body.
pub(super) fn free_rigid_modes(model: &Model, system: &ReducedSystem) -> Vec<Mode> {
    let mut modes = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        for v in free_modes(&body.mesh, &body.constraints, &[]) {
            let mut on_x = vec![0.0; system.n];
            let values = motion_on(&body.mesh, &v, &system.bodies[b].dofs);
            on_x[system.offset[b]..system.offset[b] + values.len()].copy_from_slice(&values);
            let on_s = system
                .s
                .iter()
                .map(|a| a.terms.iter().map(|&(i, c)| c * on_x[i]).sum())
                .collect();
            let on_g = system
                .g
                .iter()
                .map(|row| {
                    row.as_ref()
                        .map_or(0.0, |a| a.terms.iter().map(|&(i, c)| c * on_x[i]).sum())
                })
                .collect();
            let dofs: Vec<usize> = (0..body.load.len())
                .filter(|&d| body.constraints.get(d).is_none())
                .collect();
            let motion = motion_on(&body.mesh, &v, &dofs);
            let work = dofs
                .iter()
                .zip(&motion)
                .map(|(&d, m)| m * body.load[d])
                .sum();
            modes.push(Mode {
                body: b,
                coefficients: v,
                on_x,
                on_s,
                on_g,
                work,
            });
        }
    }
    modes
}

/// The combinations of `modes` that change no pair sum of the points in `chi` and no tangential
/// displacement of the points in `stick` (empty without friction).
pub(super) fn kernel(modes: &[Mode], chi: &[bool], stick: &[bool]) -> Kernel {
    let q = modes.len();
    let mut out = Kernel {
        on_x: Vec::new(),
        weights: Vec::new(),
    };
    if q == 0 {
        return out;
    }
    let mut gram = DMatrix::from_fn(q, q, |a, b| {
        (0..chi.len())
            .filter(|&j| chi[j])
            .map(|j| modes[a].on_s[j] * modes[b].on_s[j])
            .sum::<f64>()
    });
    // Only where some point sticks: a frictionless model's Gram matrix stays the same to the bit.
    if stick.iter().any(|&s| s) {
        gram += DMatrix::from_fn(q, q, |a, b| {
            (0..stick.len())
                .filter(|&j| stick[j])
                .map(|j| modes[a].on_g[j] * modes[b].on_g[j])
                .sum::<f64>()
        });
    }
    let scale = (0..q).map(|a| gram[(a, a)]).fold(0.0, f64::max);
    let eig = SymmetricEigen::new(gram);
    for (k, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda > 1e-10 * scale {
            continue;
        }
        let w: Vec<f64> = eig.eigenvectors.column(k).iter().copied().collect();
        let mut z = vec![0.0; modes[0].on_x.len()];
        for (m, &c) in modes.iter().zip(&w) {
            z.iter_mut().zip(&m.on_x).for_each(|(zi, v)| *zi += c * v);
        }
        for e in &out.on_x {
            let d = dot(e, &z);
            z.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
        }
        let norm = dot(&z, &z).sqrt();
        if norm > 1e-12 {
            z.iter_mut().for_each(|x| *x /= norm);
            out.on_x.push(z);
            out.weights.push(w);
        }
    }
    out
}

/// A kernel motion in words: "translation in y of 'lower' together with translation in y of
/// 'upper'".
pub(super) fn describe_motion(model: &Model, modes: &[Mode], weights: &[f64]) -> String {
    let mut parts = Vec::new();
    for b in 0..model.bodies.len() {
        let mut v = [0.0; NUM_MODES];
        for (m, &w) in modes.iter().zip(weights).filter(|(m, _)| m.body == b) {
            for i in 0..NUM_MODES {
                v[i] += w * m.coefficients[i];
            }
        }
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.1 {
            let v = v.map(|x| x / norm);
            parts.push(format!("{} of '{}'", describe(&v), model.bodies[b].name));
        }
    }
    parts.join(" together with ")
}

/// Removes the components along the orthonormal vectors `basis` from `r`.
pub(super) fn project_out(basis: &[Vec<f64>], r: &mut [f64]) {
    for e in basis {
        let d = dot(e, r);
        r.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
    }
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
