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

/// The rigid motions of `mesh` that the prescribed DOFs `prescribed` leave free: the number of
/// independent combinations of the six modes that vanish on every prescribed DOF (0 for a held
/// body). A mode counts as held when the prescribed DOFs see it at more than 1e-8 of its size
/// (relative eigenvalue of the modes' Gram matrix on those DOFs).
pub fn free_rigid_modes(mesh: &SolidMesh, prescribed: &[usize]) -> usize {
    let modes = RigidModes::new(mesh);
    let mut gram = nalgebra::Matrix6::<f64>::zeros();
    for &d in prescribed {
        let (v, c) = (d / 3, d % 3);
        let Some(x) = mesh.nodes().get(v) else {
            continue;
        };
        let row = modes.at(*x)[c];
        for i in 0..NUM_MODES_3D {
            for j in 0..NUM_MODES_3D {
                gram[(i, j)] += row[i] * row[j];
            }
        }
    }
    // Against the Gram matrix of the modes over the whole body: every node's three DOFs.
    let whole = mesh.num_nodes() as f64;
    gram.symmetric_eigenvalues()
        .iter()
        .filter(|&&l| l <= 1e-8 * whole)
        .count()
}
