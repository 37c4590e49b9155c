//! The six rigid-body modes of a 3D body: three translations and three rotations about the
//! centroid of its nodes, scaled by its bounding box diameter so that all six have unit size over
//! the body.

use super::mesh::SolidMesh;
use super::{dof, num_dofs, Point3};

/// Number of rigid-body modes in 3D.
pub const NUM_MODES_3D: usize = 6;

/// The rigid-body basis of one 3D body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidModes {
    center: Point3,
    size: f64,
}

impl RigidModes {
    /// The basis of a mesh: rotations about the centroid of its nodes, scaled by its bounding box
    /// diameter.
    pub fn new(mesh: &SolidMesh) -> RigidModes {
        let p = mesh.nodes();
        let n = p.len().max(1) as f64;
        let center = p
            .iter()
            .fold([0.0; 3], |s, x| std::array::from_fn(|c| s[c] + x[c] / n));
        RigidModes {
            center,
            size: mesh.bounding_box_diameter().max(f64::MIN_POSITIVE),
        }
    }

    /// The rotation centre and the scale.
    pub fn parts(&self) -> (Point3, f64) {
        (self.center, self.size)
    }

    /// The six modes at point `x`: row `c` holds displacement component `c` of each mode, in the
    /// order translation x, y, z, rotation about x, y, z (`ω × (x − centre) / size`).
    pub fn at(&self, x: Point3) -> [[f64; NUM_MODES_3D]; 3] {
        let [dx, dy, dz]: [f64; 3] = std::array::from_fn(|c| (x[c] - self.center[c]) / self.size);
        [
            [1.0, 0.0, 0.0, 0.0, dz, -dy],
            [0.0, 1.0, 0.0, -dz, 0.0, dx],
            [0.0, 0.0, 1.0, dy, -dx, 0.0],
        ]
    }

    /// The six modes as DOF vectors of `mesh` (one entry per DOF each).
    pub fn vectors(&self, mesh: &SolidMesh) -> Vec<Vec<f64>> {
        let mut modes = vec![vec![0.0; num_dofs(mesh.num_nodes())]; NUM_MODES_3D];
        for (v, x) in mesh.nodes().iter().enumerate() {
            let r = self.at(*x);
            for (m, mode) in modes.iter_mut().enumerate() {
                for c in 0..3 {
                    mode[dof(v, c)] = r[c][m];
                }
            }
        }
        modes
    }
}

/// The rigid motions of `mesh` that the prescribed DOFs `prescribed` leave free, as DOF vectors:
/// a basis of the combinations of the six modes that vanish on every prescribed DOF (empty for a
/// held body). A combination counts as held when the prescribed DOFs see it at more than 1e-8 of
/// its size over the body (relative eigenvalue of the modes' Gram matrix on those DOFs).
pub fn free_rigid_motions(mesh: &SolidMesh, prescribed: &[usize]) -> Vec<Vec<f64>> {
    let modes = RigidModes::new(mesh);
    let mut gram = nalgebra::Matrix6::<f64>::zeros();
    for &d in prescribed {
        let Some(x) = mesh.nodes().get(d / 3) else {
            continue;
        };
        let row = modes.at(*x)[d % 3];
        for i in 0..NUM_MODES_3D {
            for j in 0..NUM_MODES_3D {
                gram[(i, j)] += row[i] * row[j];
            }
        }
    }
    // Against the Gram matrix of the modes over the whole body: every node's three DOFs.
    let whole = mesh.num_nodes() as f64;
    let eigen = gram.symmetric_eigen();
    let vectors = modes.vectors(mesh);
    (0..NUM_MODES_3D)
        .filter(|&k| eigen.eigenvalues[k] <= 1e-8 * whole)
        .map(|k| {
            let c = eigen.eigenvectors.column(k);
            let mut motion = vec![0.0; num_dofs(mesh.num_nodes())];
            for (m, mode) in vectors.iter().enumerate() {
                motion
                    .iter_mut()
                    .zip(mode)
                    .for_each(|(x, v)| *x += c[m] * v);
            }
            motion
        })
        .collect()
}

/// The number of rigid motions the prescribed DOFs leave free ([`free_rigid_motions`]).
pub fn free_rigid_modes(mesh: &SolidMesh, prescribed: &[usize]) -> usize {
    free_rigid_motions(mesh, prescribed).len()
}

/// One DOF per motion of `motions` (DOF vectors), outside `prescribed`, such that the motions'
/// values there form a well-conditioned square matrix: greedy pivoting, each pick the DOF where
/// what the earlier picks leave of the motions is largest. Prescribing zero there removes the
/// motions from a stiffness matrix and keeps it a generalised inverse for loads that do no work
/// along them (docs/three-d.md, "Floating bodies").
pub fn pin_dofs(motions: &[Vec<f64>], prescribed: &[usize]) -> Vec<usize> {
    let k = motions.len();
    let n = motions.first().map_or(0, Vec::len);
    let mut taken = vec![false; n];
    prescribed
        .iter()
        .filter(|&&d| d < n)
        .for_each(|&d| taken[d] = true);
    // rows[i k..(i + 1) k] = the k values of the motions at DOF i, reduced by the picks so far.
    let mut rows = vec![0.0; n * k];
    for (q, m) in motions.iter().enumerate() {
        m.iter().enumerate().for_each(|(i, v)| rows[i * k + q] = *v);
    }
    let norm = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let mut pins = Vec::with_capacity(k);
    for _ in 0..k {
        let Some(best) = (0..n)
            .filter(|&i| !taken[i])
            .max_by(|&a, &b| norm(&rows[a * k..][..k]).total_cmp(&norm(&rows[b * k..][..k])))
        else {
            break;
        };
        let length = norm(&rows[best * k..][..k]).sqrt();
        if length == 0.0 {
            break;
        }
        let v: Vec<f64> = rows[best * k..][..k].iter().map(|x| x / length).collect();
        for r in rows.chunks_mut(k) {
            let d: f64 = r.iter().zip(&v).map(|(a, b)| a * b).sum();
            r.iter_mut().zip(&v).for_each(|(a, b)| *a -= d * b);
        }
        taken[best] = true;
        pins.push(best);
    }
    pins
}
