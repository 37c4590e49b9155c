//! Structured meshes of a rectangle `[x0, x1] × [y0, y1]` with `nx × ny` cells, each split into two
//! triangles. Boundaries are named `left`, `right`, `bottom`, `top`.
//!
//! Cells may be graded ([`Layout::grading`]): along an axis with `n` cells and grading `g`, the
//! cell sizes form a geometric progression whose last cell (at x1, or y1) is `g` times the first
//! (at x0, or y0); the ratio of neighbouring cells is `q = g^(1/(n−1))` and node `i` sits at
//! `x0 + (x1 − x0) · (qⁱ − 1)/(qⁿ − 1)`; `g = 1` is the uniform mesh. `g > 1` makes the cells fine
//! near x0, `g < 1` near x1. Mirroring ([`Rectangle::mirror`], [`Layout::mirror_x`]) reflects the
//! graded mesh, so a mirrored body with the same grading is fine at the other side.

use std::collections::BTreeMap;

use crate::error::MeshError;
use crate::geometry::Point;
use crate::mesh::{Edge, Mesh, Order};

/// Which diagonal splits each cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Diagonal {
    /// From bottom-left to top-right ("/").
    #[default]
    Right,
    /// From top-left to bottom-right ("\").
    Left,
    /// Alternating "/" and "\" in a checkerboard.
    Alternate,
}

/// A structured rectangle mesh description.
#[derive(Clone, Debug, PartialEq)]
pub struct Rectangle {
    /// Lower-left corner.
    pub origin: Point,
    /// Upper-right corner.
    pub corner: Point,
    /// Cells in x.
    pub nx: usize,
    /// Cells in y.
    pub ny: usize,
    /// Cell diagonal.
    pub diagonal: Diagonal,
    /// Mirror the mesh about the horizontal centre line `y = (y0 + y1)/2`: used for the upper
    /// body of a vertical stack, so that two bodies sharing a horizontal contact line are mirror
    /// images and the discrete problem is exactly symmetric.
    pub mirror: bool,
    /// Element order.
    pub order: Order,
}

/// Grading and mirroring in x of a [`Rectangle`], beyond its uniform cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    /// Size of the last cell over that of the first, in x and y (> 0; 1 = uniform). See the
    /// module documentation for the node positions.
    pub grading: [f64; 2],
    /// Mirror the mesh about its vertical centre line `x = (x0 + x1)/2` (after grading): `left`
    /// and `right` swap places and the cell diagonals their direction. Used for the right one of
    /// two bodies side by side, so that the two meshes are mirror images about a vertical
    /// contact line.
    pub mirror_x: bool,
}

impl Default for Layout {
    fn default() -> Self {
        Layout {
            grading: [1.0, 1.0],
            mirror_x: false,
        }
    }
}

/// Fraction `t ∈ [0, 1]` of the way from the first to the last node of node `i` of `n` cells
/// graded by `g` (see the module documentation).
pub fn graded_fraction(i: usize, n: usize, g: f64) -> f64 {
    if g == 1.0 || n < 2 || i == n {
        return i as f64 / n as f64;
    }
    // (qⁱ − 1)/(qⁿ − 1) with q = e^a, written with expm1 so that g near 1 loses no digits.
    let a = g.ln() / (n - 1) as f64;
    (a * i as f64).exp_m1() / (a * n as f64).exp_m1()
}

impl Rectangle {
    /// Builds the mesh.
    pub fn mesh(&self) -> Result<Mesh, MeshError> {
        self.mesh_with(&Layout::default())
    }

    /// Builds the mesh with grading and mirroring in x.
    pub fn mesh_with(&self, layout: &Layout) -> Result<Mesh, MeshError> {
        self.check(layout)?;
        let (nx, ny) = (self.nx, self.ny);
        let ([x0, y0], [x1, y1]) = (self.origin, self.corner);
        let [gx, gy] = layout.grading;
        let id = |i: usize, j: usize| j * (nx + 1) + i;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            for i in 0..=nx {
                let s = graded_fraction(i, nx, gx);
                let t = graded_fraction(j, ny, gy);
                // In a mirrored mesh, row j sits where row ny - j of the plain mesh would (and
                // column i where column nx - i would, when mirrored in x).
                let t = if self.mirror { 1.0 - t } else { t };
                let x = match (layout.mirror_x, gx == 1.0) {
                    (true, _) => x0 + (x1 - x0) * (1.0 - s),
                    (false, false) => x0 + (x1 - x0) * s,
                    // The uniform mesh keeps its node coordinates to the last bit (the
                    // benchmarks' iteration counts depend on them).
                    (false, true) => x0 + (x1 - x0) * i as f64 / nx as f64,
                };
                nodes.push([x, y0 + (y1 - y0) * t]);
            }
        }
        // One reflection reverses the orientation of every triangle, two restore it.
        let flipped = self.mirror != layout.mirror_x;
        let mut cells = Vec::with_capacity(6 * nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                let slash = match self.diagonal {
                    Diagonal::Right => true,
                    Diagonal::Left => false,
                    Diagonal::Alternate => (i + j) % 2 == 0,
                };
                let tris = if slash {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for t in tris {
                    // Mirroring flips orientation: restore counter-clockwise order.
                    if flipped {
                        cells.extend_from_slice(&[t[0], t[2], t[1]]);
                    } else {
                        cells.extend_from_slice(&t);
                    }
                }
            }
        }
        let row = |j: usize| (0..nx).map(move |i| Edge::new(id(i, j), id(i + 1, j)));
        let col = |i: usize| (0..ny).map(move |j| Edge::new(id(i, j), id(i, j + 1)));
        let (bottom_row, top_row) = if self.mirror { (ny, 0) } else { (0, ny) };
        let (left_col, right_col) = if layout.mirror_x { (nx, 0) } else { (0, nx) };
        let boundaries = BTreeMap::from([
            ("bottom".to_string(), row(bottom_row).collect()),
            ("top".to_string(), row(top_row).collect()),
            ("left".to_string(), col(left_col).collect()),
            ("right".to_string(), col(right_col).collect()),
        ]);
        let mesh = Mesh::new(nodes, Order::P1, cells, boundaries, BTreeMap::new())?;
        Ok(match self.order {
            Order::P1 => mesh,
            Order::P2 => mesh.to_p2(),
        })
    }

    /// Checks the sizes, the corners and the grading.
    fn check(&self, layout: &Layout) -> Result<(), MeshError> {
        let (nx, ny) = (self.nx, self.ny);
        let ([x0, y0], [x1, y1]) = (self.origin, self.corner);
        if nx == 0 || ny == 0 {
            return Err(MeshError::BadRectangle(format!(
                "nx and ny must be at least 1 (got {nx} × {ny})"
            )));
        }
        let finite = [x0, x1, y0, y1].iter().all(|v| v.is_finite());
        if !finite || x1 <= x0 || y1 <= y0 {
            return Err(MeshError::BadRectangle(format!(
                "need x0 < x1 and y0 < y1, got [{x0}, {x1}] × [{y0}, {y1}]"
            )));
        }
        let [gx, gy] = layout.grading;
        if !(gx.is_finite() && gx > 0.0 && gy.is_finite() && gy > 0.0) {
            return Err(MeshError::BadRectangle(format!(
                "grading must be positive and finite, got x = {gx}, y = {gy}"
            )));
        }
        Ok(())
    }
}
