//! The equilibrium check of a monolithic result, on the assembled system itself: the nodal
//! residual K u − f − (contact forces) of every body on its free DOFs, with the original sparse
//! stiffness (not the factorisation that produced u). It is zero at a solution of the discrete
//! penalty problem; on a floating body it says that the contact forces carry the applied load.
//!
//! Along a rigid motion that no contact resists, the Newton steps were held still by a
//! constraint on the contact DOFs, whose reaction is the only residual left there: it is removed
//! before the norm, and the net force it represents along the motion is reported separately. The
//! applied loads must balance along such a motion by themselves (up to the difference of the two
//! sides' integrations on non-matching meshes).

use contactdd_core::rigid::{RigidBasis, RigidSpan};
use contactdd_core::{component_of, node_of};

use crate::model::Model;

use super::modes::{dot, project_out, Kernel, Mode};
use super::system::{ReducedSystem, Sparse};

/// The residuals of a result, relative to the size of the applied and contact forces.
pub(super) struct Balance {
    /// Per body, ‖residual‖₂ off the unresisted motions.
    pub bodies: Vec<f64>,
    /// Per unresisted motion, the net force along it, relative to the work of the applied and
    /// contact forces along it.
    pub motions: Vec<f64>,
}

/// Checks displacements `u` under contact forces `contact` (per body, full numbering);
/// `stiffness` per body; `kernel` the unresisted motions of the final closed set.
pub(super) fn balance(
    model: &Model,
    system: &ReducedSystem,
    u: &[Vec<f64>],
    contact: &[Vec<f64>],
    modes: &[Mode],
    kernel: &Kernel,
) -> Balance {
    let mut residual: Vec<Vec<f64>> = Vec::with_capacity(u.len());
    let mut scale = 0.0;
    for (b, body) in model.bodies.iter().enumerate() {
        let k = system.bodies[b].stiffness();
        let mut r: Vec<f64> = (0..u[b].len())
            .map(|d| -body.load[d] - contact[b][d])
            .collect();
        // K annihilates rigid motions: apply it to the deformation only.
        let all: Vec<usize> = (0..u[b].len()).collect();
        let mut deformation = u[b].clone();
        RigidSpan::new(&body.mesh, &body.constraints, &all).split(&mut deformation);
        let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        for j in 0..k.ncols() {
            for p in cp[j]..cp[j + 1] {
                r[ri[p]] += val[p] * deformation[j];
            }
        }
        body.constraints.remove_prescribed(&mut r);
        scale += dot(&body.load, &body.load) + dot(&contact[b], &contact[b]);
        residual.push(r);
    }
    let scale = scale.sqrt().max(f64::MIN_POSITIVE);
    let motions = kernel
        .weights
        .iter()
        .map(|w| net_force(model, modes, w, &residual, contact))
        .collect();
    // The constraint's reaction: the kernel vectors on the contact DOFs.
    let offsets: Vec<usize> = residual
        .iter()
        .scan(0, |start, r| {
            let o = *start;
            *start += r.len();
            Some(o)
        })
        .collect();
    let shapes: Vec<Sparse> = (kernel.on_x.iter())
        .map(|z| {
            z.iter()
                .map(|&(i, v)| {
                    let b = system.offset.partition_point(|&o| o <= i) - 1;
                    (offsets[b] + system.bodies[b].dofs[i - system.offset[b]], v)
                })
                .collect()
        })
        .collect();
    let mut flat: Vec<f64> = residual.concat();
    project_out(&shapes, &mut flat);
    let bodies = residual
        .iter()
        .zip(&offsets)
        .map(|(r, &o)| {
            let part = &flat[o..o + r.len()];
            dot(part, part).sqrt() / scale
        })
        .collect();
    Balance { bodies, motions }
}

/// The net force `residual` exerts along the rigid motion with mode weights `w` (its largest
/// displacement 1), relative to the work of the applied and contact forces along it.
fn net_force(
    model: &Model,
    modes: &[Mode],
    w: &[f64],
    residual: &[Vec<f64>],
    contact: &[Vec<f64>],
) -> f64 {
    let mut motion: Vec<Vec<f64>> = model
        .bodies
        .iter()
        .map(|b| vec![0.0; b.load.len()])
        .collect();
    for (m, &c) in modes.iter().zip(w) {
        let body = &model.bodies[m.body];
        let basis = RigidBasis::new(&body.mesh);
        for (d, zd) in motion[m.body].iter_mut().enumerate() {
            if body.constraints.get(d).is_none() {
                let x = body.mesh.nodes()[node_of(d)];
                *zd += c * basis.motion(x, &m.coefficients)[component_of(d)];
            }
        }
    }
    let size = motion
        .iter()
        .flatten()
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let (mut net, mut work) = (0.0, 0.0);
    for (b, z) in motion.iter().enumerate() {
        net += dot(z, &residual[b]) / size;
        work += (dot(z, &model.bodies[b].load).abs() + dot(z, &contact[b]).abs()) / size;
    }
    if net == 0.0 {
        0.0
    } else {
        net.abs() / work.max(f64::MIN_POSITIVE)
    }
}
