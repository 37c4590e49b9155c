//! The `mesh` table of a body → a validated mesh: a rectangle built by [`Rectangle::mesh`], a Gmsh
//! file read by [`contactdd_core::gmsh::read_msh_surface`] (relative paths against `base_dir`),
//! scaled, translated and, with `order = "p2"`, promoted by [`Mesh::to_p2`], or inline arrays.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use contactdd_core::gmsh::read_msh_surface;
use contactdd_core::{memory, mesh_memory};
use contactdd_core::{Edge, Layout, Mesh, Order, Point, Rectangle, Vector, DIM};
use contactdd_ddm::SetupError;

use crate::error::{body_error, mesh_error, LoadError};
use crate::number::format_f64 as num;
use crate::problem::{BodySpec, MeshSpec};

/// Largest number of rectangle cells (nx · ny) per body: far beyond what the solver handles, but it
/// keeps absurd inputs from exhausting memory while allocating the mesh.
pub const MAX_RECTANGLE_CELLS: usize = 4_000_000;

/// The `mesh` table of body `body` → a validated mesh; a relative Gmsh path resolves against
/// `base_dir`.
pub fn mesh(body: &str, spec: &MeshSpec, base_dir: &Path) -> Result<Mesh, LoadError> {
    match spec {
        MeshSpec::Rectangle {
            x,
            y,
            nx,
            ny,
            diagonal,
            mirror,
            mirror_x,
            grading,
            order,
        } => {
            let grading = rectangle_grading(body, *x, *y, *nx, *ny, grading.map(|g| [g.x, g.y]))?;
            let needed = mesh_memory::rectangle(*nx, *ny, *order).peak;
            memory::check(
                &format!(
                    "building the mesh of body '{}'",
                    contactdd_core::names::shown(body)
                ),
                needed,
            )
            .map_err(SetupError::from)?;
            let layout = Layout {
                grading,
                mirror_x: *mirror_x,
            };
            Rectangle {
                origin: [x[0], y[0]],
                corner: [x[1], y[1]],
                nx: *nx,
                ny: *ny,
                diagonal: *diagonal,
                mirror: *mirror,
                order: *order,
            }
            .mesh_with(&layout)
            .map_err(|e| mesh_error(body, "mesh", e).into())
        }
        MeshSpec::Gmsh {
            file,
            surface,
            order,
            translate,
            scale,
        } => {
            let path: PathBuf = if file.is_absolute() {
                file.clone()
            } else {
                base_dir.join(file)
            };
            gmsh_mesh(body, &path, surface.as_deref(), *order, *translate, *scale)
        }
        MeshSpec::Inline {
            nodes,
            triangles,
            boundaries,
            node_sets,
        } => Ok(inline_mesh(body, nodes, triangles, boundaries, node_sets)?),
    }
}

/// Refuses a problem whose rectangle meshes, built one after the other and each kept, would need
/// more memory than is available ([`mesh_memory::sequence`] of [`mesh_memory::rectangle`]),
/// before any is built. Rectangles over [`MAX_RECTANGLE_CELLS`] are left to the check of their
/// body, which names the limit.
pub fn check_mesh_memory(bodies: &[BodySpec]) -> Result<(), SetupError> {
    let rectangles: Vec<_> = bodies
        .iter()
        .filter_map(|b| match &b.mesh {
            MeshSpec::Rectangle { nx, ny, order, .. }
                if nx
                    .checked_mul(*ny)
                    .is_some_and(|c| c <= MAX_RECTANGLE_CELLS) =>
            {
                Some(mesh_memory::rectangle(*nx, *ny, *order))
            }
            _ => None,
        })
        .collect();
    let what = match rectangles.len() {
        0 | 1 => return Ok(()),
        n => format!("building the rectangle meshes of {n} bodies"),
    };
    Ok(memory::check(&what, mesh_memory::sequence(rectangles))?)
}

/// Checks the numbers of a rectangle mesh of body `body` (cells, ranges, grading); returns its
/// grading per direction (1 without one).
fn rectangle_grading(
    body: &str,
    x: [f64; 2],
    y: [f64; 2],
    nx: usize,
    ny: usize,
    grading: Option<[f64; DIM]>,
) -> Result<[f64; DIM], SetupError> {
    for (key, n) in [("mesh.nx", nx), ("mesh.ny", ny)] {
        if n == 0 {
            return Err(body_error(body, key, "must be at least 1, got 0"));
        }
    }
    if !matches!(nx.checked_mul(ny), Some(c) if c <= MAX_RECTANGLE_CELLS) {
        return Err(body_error(
            body,
            "mesh",
            format!("{nx} × {ny} cells is more than the limit of {MAX_RECTANGLE_CELLS}"),
        ));
    }
    for (key, r) in [("mesh.x", x), ("mesh.y", y)] {
        if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
            return Err(body_error(
                body,
                key,
                format!(
                    "need a finite range [min, max] with min < max, got [{}, {}]",
                    num(r[0]),
                    num(r[1])
                ),
            ));
        }
    }
    let grading = grading.unwrap_or([1.0; DIM]);
    for (key, g) in [
        ("mesh.grading.x", grading[0]),
        ("mesh.grading.y", grading[1]),
    ] {
        if !(g.is_finite() && g > 0.0) {
            return Err(body_error(
                body,
                key,
                format!("must be a positive number, got {}", num(g)),
            ));
        }
    }
    Ok(grading)
}

/// The Gmsh file `path` (its `surface`, or all) as the mesh of body `body`: scaled about the
/// origin, then translated, at the `order` asked for.
fn gmsh_mesh(
    body: &str,
    path: &Path,
    surface: Option<&str>,
    order: Option<Order>,
    translate: Option<Vector>,
    scale: Option<f64>,
) -> Result<Mesh, LoadError> {
    let scale = scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(body_error(
            body,
            "mesh.scale",
            format!("must be a positive number, got {}", num(scale)),
        )
        .into());
    }
    let shift = translate.unwrap_or([0.0; DIM]);
    if !shift.iter().all(|x| x.is_finite()) {
        return Err(body_error(
            body,
            "mesh.translate",
            format!("must be finite, got [{}, {}]", num(shift[0]), num(shift[1])),
        )
        .into());
    }
    let mut mesh = read_msh_surface(path, surface).map_err(|source| LoadError::Gmsh {
        body: contactdd_core::names::shown(body),
        path: path.display().to_string(),
        source,
    })?;
    if scale != 1.0 || shift != [0.0; DIM] {
        mesh = mesh
            .map_nodes(|p| std::array::from_fn(|c| scale * p[c] + shift[c]))
            .map_err(|e| mesh_error(body, "mesh", e))?;
    }
    gmsh_order(body, mesh, order, &path.display().to_string())
}

/// A mesh read from Gmsh (`source` names it in messages) at the `order` asked for: P1 triangles
/// are promoted to P2 for `p2`; P2 triangles cannot be read as `p1`.
pub fn gmsh_order(
    body: &str,
    mesh: Mesh,
    order: Option<Order>,
    source: &str,
) -> Result<Mesh, LoadError> {
    match (order, mesh.order()) {
        (Some(Order::P2), Order::P1) => Ok(mesh.to_p2()),
        (Some(Order::P1), Order::P2) => Err(body_error(
            body,
            "mesh.order",
            format!(
                "'{source}' has P2 triangles; they cannot be read as p1 (use order = \"p2\" or \
                 leave order out)"
            ),
        )
        .into()),
        _ => Ok(mesh),
    }
}

/// An inline mesh table (`kind = "inline"`) → a validated mesh of body `body`: the order follows
/// from the triangles' length (3 or 6 nodes, the same for all), the rest is [`mesh_from_arrays`].
fn inline_mesh(
    body: &str,
    nodes: &[Point],
    triangles: &[Vec<usize>],
    boundaries: &BTreeMap<String, Vec<[usize; 2]>>,
    node_sets: &BTreeMap<String, Vec<usize>>,
) -> Result<Mesh, SetupError> {
    let width = triangles.first().map_or(3, Vec::len);
    let order = match width {
        3 => Order::P1,
        6 => Order::P2,
        n => {
            return Err(body_error(
                body,
                "mesh.triangles",
                format!("a triangle has 3 (P1) or 6 (P2) nodes, got {n}"),
            ))
        }
    };
    if let Some(i) = triangles.iter().position(|t| t.len() != width) {
        return Err(body_error(
            body,
            "mesh.triangles",
            format!(
                "triangle {i} has {} nodes, the first has {width}",
                triangles[i].len()
            ),
        ));
    }
    let edges = boundaries
        .iter()
        .map(|(name, e)| {
            (
                name.clone(),
                e.iter().map(|&[a, b]| Edge::new(a, b)).collect(),
            )
        })
        .collect();
    let cells = triangles.iter().flatten().copied().collect();
    mesh_from_arrays(body, nodes.to_vec(), order, cells, edges, node_sets.clone())
}

/// A mesh given as arrays (nodes, the node indices of each triangle, named boundary edges and
/// node sets) → a validated mesh of body `body`, with the errors of a mesh read from a file;
/// clockwise triangles are reordered as the Gmsh reader does.
pub fn mesh_from_arrays(
    body: &str,
    nodes: Vec<Point>,
    order: Order,
    mut cells: Vec<usize>,
    boundaries: BTreeMap<String, Vec<Edge>>,
    node_sets: BTreeMap<String, Vec<usize>>,
) -> Result<Mesh, SetupError> {
    // Clockwise triangles are reordered, as the Gmsh reader does.
    contactdd_core::mesh::counter_clockwise(&nodes, order, &mut cells);
    Mesh::new(nodes, order, cells, boundaries, node_sets).map_err(|e| mesh_error(body, "mesh", e))
}
