//! The space dimension as one named choice: [`DIM`], the numbering of displacement degrees of
//! freedom ([`dof`], [`node_of`], [`component_of`]) and the [`Point`] / [`Vector`] types.
//!
//! Degrees of freedom are interleaved by node: node `v` owns DOFs `DIM * v .. DIM * v + DIM`, one
//! per displacement component. Code that needs the numbering goes through these functions rather
//! than writing the `2` so that another dimension can come later without a hunt.

/// The space dimension: the number of coordinates of a point and of displacement components per
/// node.
pub const DIM: usize = 2;

/// A point of the plane (coordinates `x`, `y`).
pub type Point = [f64; DIM];

/// A vector of the plane: a displacement, a force, a normal.
pub type Vector = [f64; DIM];

/// Global index of displacement component `component` (`0..DIM`) of node `node`.
#[inline]
pub const fn dof(node: usize, component: usize) -> usize {
    DIM * node + component
}

/// The node a degree of freedom belongs to (inverse of [`dof`]).
#[inline]
pub const fn node_of(dof: usize) -> usize {
    dof / DIM
}

/// The displacement component a degree of freedom stands for (inverse of [`dof`]).
#[inline]
pub const fn component_of(dof: usize) -> usize {
    dof % DIM
}

/// Number of degrees of freedom of `num_nodes` nodes.
#[inline]
pub const fn num_dofs(num_nodes: usize) -> usize {
    DIM * num_nodes
}

/// The vector of node `node` in an interleaved DOF vector `values` (see [`dof`]).
///
/// # Panics
/// If `values` has fewer than `num_dofs(node + 1)` entries.
#[inline]
pub fn node_vector(values: &[f64], node: usize) -> Vector {
    std::array::from_fn(|c| values[dof(node, c)])
}

/// Scalar product `a · b`, summed in component order.
#[inline]
pub fn dot(a: Vector, b: Vector) -> f64 {
    (1..DIM).fold(a[0] * b[0], |s, c| s + a[c] * b[c])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dof_numbering_round_trips() {
        for node in 0..5 {
            for c in 0..DIM {
                let d = dof(node, c);
                assert_eq!((node_of(d), component_of(d)), (node, c));
            }
        }
        assert_eq!(num_dofs(3), dof(2, DIM - 1) + 1);
        assert_eq!(node_vector(&[1.0, 2.0, 3.0, 4.0], 1), [3.0, 4.0]);
        assert_eq!(dot([1.0, 2.0], [3.0, -4.0]), -5.0);
    }
}
