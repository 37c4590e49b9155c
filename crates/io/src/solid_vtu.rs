//! `.vtu` files of tetrahedral bodies ([`SolidMesh`]), written by the writer of [`crate::vtu`]
//! in any [`VtuFormat`], one body per `Piece`, and read back by [`crate::vtu_read`].
//!
//! A piece holds the body's points (`x y z`) and its tetrahedra: VTK type 10 (`VTK_TETRA`) for P1,
//! 24 (`VTK_QUADRATIC_TETRA`) for P2. The vertices keep the mesh's order (a positive volume:
//! vertex 3 lies on the side of the face 0-1-2 that its right-hand normal points to, as VTK
//! wants). A P2 tetrahedron's mid-edge nodes are written in VTK's order, the edges
//! [`VTK_TET_EDGES`] (0,1), (1,2), (2,0), (0,3), (1,3), (2,3), each taken from the mesh's (Gmsh's)
//! order [`TET_EDGES`] by its edge ([`VTK_QUADRATIC_TET_NODES`]). The displacement of
//! [`VtuData`] holds 3 values per node; point and cell fields are as in a planar file (a stress
//! as a 9-component tensor: [`stress_tensors`]).

use std::path::Path;

use contactdd_core::solid::element::TET_EDGES;
use contactdd_core::solid::{SolidMesh, TetOrder};

use crate::atomic::write_atomic;
use crate::vtu::{grid_pieces_bytes, Grid, GridPoints, VtuData, VtuFormat};

/// The VTK cell type of a linear tetrahedron.
pub const VTK_TETRA: u8 = 10;

/// The VTK cell type of a quadratic (10-node) tetrahedron.
pub const VTK_QUADRATIC_TETRA: u8 = 24;

/// The edges of VTK's quadratic tetrahedron, in the order of its mid-edge nodes 4..9.
pub const VTK_TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// The nodes of a VTK quadratic tetrahedron as positions in the mesh's P2 tetrahedron: the
/// vertices 0..4, then for each edge of [`VTK_TET_EDGES`] the mid-edge node 4 + k of the edge k of
/// [`TET_EDGES`] with the same two vertices.
pub const VTK_QUADRATIC_TET_NODES: [usize; 10] = by_edge();

/// [`VTK_QUADRATIC_TET_NODES`], matched edge by edge (a compile-time error if an edge of VTK's
/// is not one of the mesh's).
const fn by_edge() -> [usize; 10] {
    let mut order = [0, 1, 2, 3, 0, 0, 0, 0, 0, 0];
    let mut v = 0;
    while v < 6 {
        let [a, b] = VTK_TET_EDGES[v];
        let mut k = 0;
        while !((TET_EDGES[k][0] == a && TET_EDGES[k][1] == b)
            || (TET_EDGES[k][0] == b && TET_EDGES[k][1] == a))
        {
            k += 1;
            assert!(
                k < 6,
                "an edge of VTK's tetrahedron is not one of the mesh's"
            );
        }
        order[4 + v] = 4 + k;
        v += 1;
    }
    order
}

/// The [`Grid`] of `mesh`: its nodes, its tetrahedra of type [`VTK_TETRA`] (P1) or
/// [`VTK_QUADRATIC_TETRA`] (P2, nodes in VTK's order).
pub fn solid_grid(mesh: &SolidMesh) -> Grid<'_> {
    let (cell_type, order) = match mesh.order() {
        TetOrder::P1 => (VTK_TETRA, None),
        TetOrder::P2 => (VTK_QUADRATIC_TETRA, Some(&VTK_QUADRATIC_TET_NODES[..])),
    };
    Grid {
        points: GridPoints::Space(mesh.nodes()),
        cells: mesh.tets(),
        nodes_per_cell: mesh.order().nodes_per_tet(),
        cell_type,
        node_order: order,
    }
}

/// The bytes of the `.vtu` file of the body `mesh` with the arrays of `data` (a displacement of
/// 3 values per node), encoded as `format`.
///
/// Errors ([`std::io::ErrorKind::InvalidInput`]) if the displacement does not hold 3 values per
/// node, or a field has zero components or not `components` values per node (per cell).
pub fn solid_vtu_bytes(
    mesh: &SolidMesh,
    data: VtuData<'_>,
    format: VtuFormat,
) -> std::io::Result<Vec<u8>> {
    solid_vtu_pieces_bytes(&[(mesh, data)], format)
}

/// The bytes of a `.vtu` file holding one `Piece` per body of `pieces`, in order, each with its
/// arrays, encoded as `format`; with one body, the bytes of [`solid_vtu_bytes`]. Errors as
/// [`solid_vtu_bytes`].
pub fn solid_vtu_pieces_bytes(
    pieces: &[(&SolidMesh, VtuData<'_>)],
    format: VtuFormat,
) -> std::io::Result<Vec<u8>> {
    let grids: Vec<(Grid<'_>, VtuData<'_>)> = (pieces.iter())
        .map(|(mesh, data)| (solid_grid(mesh), *data))
        .collect();
    grid_pieces_bytes(&grids, format)
}

/// Writes the `.vtu` file of [`solid_vtu_bytes`] at `path`, by [`write_atomic`] (a reader never
/// sees a half-written file).
pub fn write_solid_vtu(
    path: &Path,
    mesh: &SolidMesh,
    data: VtuData<'_>,
    format: VtuFormat,
) -> std::io::Result<()> {
    write_atomic(path, &solid_vtu_bytes(mesh, data, format)?)
}

/// Writes the `.vtu` file of [`solid_vtu_pieces_bytes`] at `path`, by [`write_atomic`].
pub fn write_solid_vtu_pieces(
    path: &Path,
    pieces: &[(&SolidMesh, VtuData<'_>)],
    format: VtuFormat,
) -> std::io::Result<()> {
    write_atomic(path, &solid_vtu_pieces_bytes(pieces, format)?)
}

/// Voigt stresses `(σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy)` (as `SolidBody::nodal_stresses` gives
/// them) as the flat 3×3 row-major tensors of a 9-component field
/// (`xx xy xz yx yy yz zx zy zz`), which ParaView shows as tensors.
pub fn stress_tensors(voigt: &[[f64; 6]]) -> Vec<f64> {
    voigt
        .iter()
        .flat_map(|&[xx, yy, zz, yz, xz, xy]| [xx, xy, xz, xy, yy, yz, xz, yz, zz])
        .collect()
}
