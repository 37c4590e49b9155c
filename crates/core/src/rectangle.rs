//! Structured meshes of a rectangle `[x0, x1] × [y0, y1]` with `nx × ny` cells, each split into two
//! triangles. Boundaries are named `left`, `right`, `bottom`, `top`.

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

impl Rectangle {
    /// Builds the mesh.
    pub fn mesh(&self) -> Result<Mesh, MeshError> {
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
        let id = |i: usize, j: usize| j * (nx + 1) + i;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            for i in 0..=nx {
                let t = j as f64 / ny as f64;
                // In a mirrored mesh, row j sits where row ny - j of the plain mesh would.
                let t = if self.mirror { 1.0 - t } else { t };
                nodes.push([x0 + (x1 - x0) * i as f64 / nx as f64, y0 + (y1 - y0) * t]);
            }
        }
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
                    if self.mirror {
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
        let boundaries = BTreeMap::from([
            ("bottom".to_string(), row(bottom_row).collect()),
            ("top".to_string(), row(top_row).collect()),
            ("left".to_string(), col(0).collect()),
            ("right".to_string(), col(nx).collect()),
        ]);
        let mesh = Mesh::new(nodes, Order::P1, cells, boundaries, BTreeMap::new())?;
        Ok(match self.order {
            Order::P1 => mesh,
            Order::P2 => mesh.to_p2(),
        })
    }
}
