//! Rigid-body motions of a 2D body as a numeric basis: two translations and a rotation about the
//! centroid of the nodes, scaled so that all three have unit size over the body.
//!
//! One basis serves the support check ([`free_rigid_modes`]), the monolithic reference and the
//! coarse correction of the domain decomposition: a free mode is a combination `Σ_i v_i R_i` of
//! the basis with coefficient vector `v`. A [`RigidSpan`] makes the free modes orthonormal on a
//! set of DOFs, to split a displacement into its rigid part and the rest.

use nalgebra::{Matrix3, SymmetricEigen};

use crate::geometry::{component_of, dot, node_of, Point, Vector, DIM};
use crate::mesh::Mesh;
use crate::supports::Constraints;

/// Number of rigid-body modes in 2D.
pub const NUM_MODES: usize = 3;

/// The rigid-body basis of one body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBasis {
    center: Point,
    size: f64,
}

impl RigidBasis {
    /// The basis of a mesh: rotation about the centroid of its nodes, scaled by its bounding box
    /// diameter.
    pub fn new(mesh: &Mesh) -> RigidBasis {
        let p = mesh.nodes();
        let n = p.len().max(1) as f64;
        let center = p
            .iter()
            .fold([0.0; DIM], |s, x| std::array::from_fn(|c| s[c] + x[c] / n));
        RigidBasis {
            center,
            size: mesh.bounding_box_diameter().max(f64::MIN_POSITIVE),
        }
    }

    /// The basis rotating about `center`, scaled by `size` (the values [`RigidBasis::parts`]
    /// returns: how a basis travels between processes).
    pub fn from_parts(center: Point, size: f64) -> RigidBasis {
        RigidBasis { center, size }
    }

    /// The rotation centre and the scale.
    pub fn parts(&self) -> (Point, f64) {
        (self.center, self.size)
    }

    /// The three modes at point `x`: row `c` holds displacement component `c` of each mode.
    pub fn at(&self, x: Point) -> [[f64; NUM_MODES]; DIM] {
        let (dx, dy) = (
            (x[0] - self.center[0]) / self.size,
            (x[1] - self.center[1]) / self.size,
        );
        [[1.0, 0.0, -dy], [0.0, 1.0, dx]]
    }

    /// The displacement at `x` of the combination with coefficients `v`.
    pub fn motion(&self, x: Point, v: &[f64; NUM_MODES]) -> Vector {
        let m = self.at(x);
        std::array::from_fn(|c| (0..NUM_MODES).map(|i| m[c][i] * v[i]).sum())
    }
}

/// A free mode in words: the basis modes it mostly consists of, e.g. "translation in y".
pub fn describe(v: &[f64; NUM_MODES]) -> String {
    let names = ["translation in x", "translation in y", "rotation"];
    (0..NUM_MODES)
        .filter(|&i| v[i].abs() > 0.3)
        .map(|i| names[i])
        .collect::<Vec<_>>()
        .join(" + ")
}

/// Rigid-body modes of a body that neither its supports nor the given normal springs remove.
/// `springs` are (node, unit direction) pairs of springs of any positive stiffness. Returns a
/// human readable description of each free mode (empty if the body is held).
pub fn free_rigid_modes(
    mesh: &Mesh,
    constraints: &Constraints,
    springs: &[(usize, Vector)],
) -> Vec<String> {
    free_modes(mesh, constraints, springs)
        .iter()
        .map(describe)
        .collect()
}

/// The rigid motions that supports and springs (node, unit direction) leave free, as orthonormal
/// coefficient vectors of the [`RigidBasis`] of `mesh` (empty if the body is held).
pub fn free_modes(
    mesh: &Mesh,
    constraints: &Constraints,
    springs: &[(usize, Vector)],
) -> Vec<[f64; NUM_MODES]> {
    Holding::new(mesh, constraints, springs).free(|_| true)
}

/// What holds a body against rigid motion: its supports, and springs (node, unit direction) that
/// may be switched on and off — asked once per set of active springs (a Robin problem's φ)
/// without going over the supports again.
#[derive(Clone, Debug, PartialEq)]
pub struct Holding {
    /// Gram matrix of the supports' constrained values of the rigid basis.
    supports: Matrix3<f64>,
    /// Each spring's values of the rigid basis along its direction.
    springs: Vec<[f64; NUM_MODES]>,
}

impl Holding {
    /// The supports of `constraints` on `mesh`, and `springs`.
    pub fn new(mesh: &Mesh, constraints: &Constraints, springs: &[(usize, Vector)]) -> Holding {
        let basis = RigidBasis::new(mesh);
        let p = mesh.nodes();
        let mut supports = Matrix3::<f64>::zeros();
        for (dof, _) in constraints.fixed() {
            add(&mut supports, basis.at(p[node_of(dof)])[component_of(dof)]);
        }
        // An inclined normal support removes the motion along its normal, as a spring would.
        for (v, n, _) in constraints.inclined() {
            add(&mut supports, along(&basis, p[v], n));
        }
        Holding {
            supports,
            springs: springs
                .iter()
                .map(|&(v, dir)| along(&basis, p[v], dir))
                .collect(),
        }
    }

    /// The rigid motions left free with the springs that `active` selects (by index), as in
    /// [`free_modes`]: the kernel of the Gram matrix of the constrained values.
    pub fn free(&self, active: impl Fn(usize) -> bool) -> Vec<[f64; NUM_MODES]> {
        let mut gram = self.supports;
        for (_, &row) in self.springs.iter().enumerate().filter(|(j, _)| active(*j)) {
            add(&mut gram, row);
        }
        let scale = gram.trace().max(1.0);
        let eig = SymmetricEigen::new(gram);
        (0..NUM_MODES)
            .filter(|&k| eig.eigenvalues[k] <= 1e-10 * scale)
            .map(|k| {
                let v = eig.eigenvectors.column(k);
                [v[0], v[1], v[2]]
            })
            .collect()
    }
}

/// Adds the outer product of `row` to `gram`.
fn add(gram: &mut Matrix3<f64>, row: [f64; NUM_MODES]) {
    for i in 0..NUM_MODES {
        for j in 0..NUM_MODES {
            gram[(i, j)] += row[i] * row[j];
        }
    }
}

/// The three modes' displacements at `x` along the unit direction `dir`.
fn along(basis: &RigidBasis, x: Point, dir: Vector) -> [f64; NUM_MODES] {
    let m = basis.at(x);
    [0, 1, 2].map(|k| dot(dir, std::array::from_fn(|c| m[c][k])))
}

/// The values on the DOFs `dofs` of the rigid motion with coefficients `v` in the rigid basis of
/// `mesh`.
pub fn motion_on(mesh: &Mesh, v: &[f64; NUM_MODES], dofs: &[usize]) -> Vec<f64> {
    let basis = RigidBasis::new(mesh);
    dofs.iter()
        .map(|&d| basis.motion(mesh.nodes()[node_of(d)], v)[component_of(d)])
        .collect()
}

/// An orthonormal basis of a body's free rigid motions on some of its DOFs, each with its
/// coefficients in the body's rigid basis: a displacement minus its part in this span has the
/// same strains, and far smaller entries when the body mostly moves rigidly (products with the
/// stiffness then lose no digits to that motion).
#[derive(Clone, Debug, PartialEq)]
pub struct RigidSpan {
    /// Per motion, its coefficients in the rigid basis and its values on the DOFs.
    motions: Vec<([f64; NUM_MODES], Vec<f64>)>,
}

impl RigidSpan {
    /// The free rigid motions that `constraints` leave `mesh`, on the DOFs `dofs`.
    pub fn new(mesh: &Mesh, constraints: &Constraints, dofs: &[usize]) -> RigidSpan {
        let mut motions: Vec<([f64; NUM_MODES], Vec<f64>)> = Vec::new();
        for mut v in free_modes(mesh, constraints, &[]) {
            let mut z = motion_on(mesh, &v, dofs);
            for (w, e) in &motions {
                let d = dot_slices(e, &z);
                z.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
                v.iter_mut().zip(w).for_each(|(x, y)| *x -= d * y);
            }
            let norm = dot_slices(&z, &z).sqrt();
            if norm > 0.0 {
                z.iter_mut().for_each(|x| *x /= norm);
                motions.push((v.map(|x| x / norm), z));
            }
        }
        RigidSpan { motions }
    }

    /// Splits `u` (on the span's DOFs) into its rigid part's coefficients and the rest, in place.
    pub fn split(&self, u: &mut [f64]) -> [f64; NUM_MODES] {
        let mut c = [0.0; NUM_MODES];
        for (w, e) in &self.motions {
            let d = dot_slices(e, u);
            u.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
            c.iter_mut().zip(w).for_each(|(x, y)| *x += d * y);
        }
        c
    }
}

fn dot_slices(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rectangle::{Diagonal, Rectangle};
    use crate::supports::Component;

    fn square() -> Mesh {
        Rectangle {
            origin: [0.0, 0.0],
            corner: [2.0, 1.0],
            nx: 4,
            ny: 2,
            diagonal: Diagonal::Right,
            mirror: false,
            order: crate::mesh::Order::P1,
        }
        .mesh()
        .unwrap()
    }

    #[test]
    fn a_free_body_has_three_orthonormal_modes() {
        let mesh = square();
        let modes = free_modes(&mesh, &Constraints::new(mesh.num_nodes()), &[]);
        assert_eq!(modes.len(), 3);
        for a in &modes {
            for b in &modes {
                let d: f64 = (0..3).map(|i| a[i] * b[i]).sum();
                assert!((d - f64::from(u8::from(a == b))).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_symmetry_line_leaves_only_the_translation_along_it() {
        let mesh = square();
        let mut c = Constraints::new(mesh.num_nodes());
        c.fix(&mesh, "left", Component::Normal, 0.0).unwrap();
        let modes = free_modes(&mesh, &c, &[]);
        assert_eq!(modes.len(), 1);
        // The free motion is a vertical translation: zero x-displacement everywhere.
        let basis = RigidBasis::new(&mesh);
        for &x in mesh.nodes() {
            let u = basis.motion(x, &modes[0]);
            assert!(u[0].abs() < 1e-12 && (u[1].abs() - 1.0).abs() < 1e-12);
        }
    }
}
