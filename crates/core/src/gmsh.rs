//! Reader of Gmsh `.msh` files (ASCII MSH 4.1, and the older ASCII MSH 2.2): planar triangle
//! meshes into a [`Mesh`] ([`read_msh`]), tetrahedral meshes into a [`SolidMesh`]
//! ([`read_solid_msh`]).
//!
//! A `.msh` file is a sequence of sections, each opened by a line `$Name` and closed by a line
//! `$EndName`; within a section, values are separated by white space. This reader uses:
//!
//! - `$MeshFormat`: `version file-type data-size`; only ASCII (`file-type` 0) versions 4.1 and 2.2
//!   are read, binary files are reported as [`GmshError::Unsupported`].
//! - `$PhysicalNames`: `count`, then `dim tag "name"` lines. A group named twice, one name for two
//!   groups of one dimension, or a name for a group without elements is an error at its line.
//! - `$Entities` (4.1 only): the geometric points, curves, surfaces and volumes with their
//!   physical tags. In 4.1 elements refer to an entity, and the entity to its physical groups.
//! - `$Nodes`: in 4.1, blocks of `dim entity parametric count` followed by the node tags, then one
//!   `x y z [u [v]]` line per node; in 2.2, `count` then `tag x y z` lines. Node tags start at 1.
//! - `$Elements`: in 4.1, blocks of `dim entity type count` followed by `tag node...` lines; in 2.2,
//!   `count` then `tag type ntags tag... node...` lines (the first tag is the physical group).
//!
//! Other sections (`$Comments`, `$NodeData`, `$Periodic`, ...) are skipped.
//!
//! Element types read: 2 (3-node triangle, P1), 9 (6-node triangle, P2: vertices then the mid-side
//! nodes of edges (0,1), (1,2), (2,0), as [`crate::mesh::Order::P2`]), 1 (2-node line), 8 (3-node
//! line: ends, then middle) and 15 (point); the 3D reader also reads 4 (4-node tetrahedron) and
//! 11 (10-node tetrahedron, Gmsh's order as [`crate::solid::element`]). Quadrilaterals,
//! higher-order elements and other 3D elements are unsupported, and so are tetrahedra in the
//! planar reader.
//!
//! # Planar meshes
//!
//! The mesh is a set of triangles: those of one physical surface (2D physical group) when
//! [`read_msh_surface`] names one, otherwise all of them, which is an error if the triangles
//! belong to several physical surfaces (several bodies). Node tags are renumbered `0..n` in file
//! order, keeping only nodes used by a chosen triangle; clockwise triangles are reoriented. Every
//! physical group of dimension 1 becomes a named boundary (named by `$PhysicalNames`, or by its
//! tag number), every physical group of dimension 0 a named node set. With a chosen surface, a
//! line or point belongs to the body when all its nodes are nodes of the body, so a physical
//! curve running along two bodies gives each its own part.
//! All coordinates must share one `z` (the mesh lies in a plane parallel to `xy`). Curved 6-node
//! triangles (Gmsh's default for `SetOrder(2)` on curved geometry: a mid-side node off its edge's
//! midpoint) are read as they are and used isoparametrically ([`crate::element::Geometry`]); one
//! whose quadratic map folds (a Jacobian not positive everywhere) is reported as
//! [`GmshError::Unsupported`] at its line.
//!
//! # Tetrahedral meshes
//!
//! The body is a set of tetrahedra: those of one physical volume (3D physical group) when
//! [`read_solid_msh`] names one, otherwise all of them, which is an error
//! ([`GmshError::Volume`], listing the volumes) if they belong to several physical volumes. They
//! share one order ([`GmshError::MixedTetrahedra`]); negatively oriented ones are reoriented.
//! Node tags are renumbered `0..n` in file order, keeping only nodes of a chosen tetrahedron.
//! Every physical surface (2D physical group, named by `$PhysicalNames` or by its tag number)
//! becomes a face of the [`SolidMesh`] made of its triangles: 3-node ones for 4-node tetrahedra,
//! 6-node ones for 10-node tetrahedra ([`GmshError::FaceOrder`]), each a boundary face of exactly
//! one tetrahedron with the same mid-edge nodes ([`GmshError::NotABoundaryFace`]). With a chosen
//! volume, the triangles that are no face of its tetrahedra belong to another body and are left
//! out. Lines and points are read and left out. [`SolidMesh::new`] checks the result; its
//! error comes as [`GmshError::Solid`], with the file line of the tetrahedron it names.
//!
//! The reader runs in three steps: `tokens` splits the text, `raw` reads the sections, and
//! `build` (planar) or `solid` (tetrahedral) assembles the mesh.
//!
//! Why this reader lives in the numerical core while every other file format lives in
//! `contactdd-io`: it is a mesh source like [`crate::rectangle`], not a front end. It needs no
//! dependency, builds its result only through the public [`Mesh::new`] (no crate internals), and
//! reports [`GmshError`]; so an MPI driver, a benchmark or a Rust user can read a Gmsh mesh
//! without linking the TOML and JSON code. Nothing else in the core reads or writes files.

use std::path::Path;

use crate::error::GmshError;
use crate::mesh::Mesh;
use crate::solid::SolidMesh;

mod build;
mod raw;
mod solid;
mod tokens;

use raw::{RawMsh, Space};

/// Reads a Gmsh ASCII mesh file (MSH 4.1 or 2.2) holding one body into a validated [`Mesh`].
pub fn read_msh(path: &Path) -> Result<Mesh, GmshError> {
    read_msh_surface(path, None)
}

/// Reads the body of physical surface `surface` (a name, or a tag number for an unnamed group)
/// of a Gmsh ASCII mesh file; `None` reads a file holding one body. See the module documentation.
pub fn read_msh_surface(path: &Path, surface: Option<&str>) -> Result<Mesh, GmshError> {
    parse_msh_surface(&read_text(path)?, surface)
}

/// The text of file `path`. Binary files have an ASCII header, so a lossy conversion still lets
/// the parser see the file type in `$MeshFormat` and report them as unsupported.
fn read_text(path: &Path) -> Result<String, GmshError> {
    let bytes = std::fs::read(path).map_err(|source| GmshError::Io {
        path: path.display().to_string(),
        source,
    })?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// Parses the text of a Gmsh ASCII mesh file (MSH 4.1 or 2.2) holding one body into a validated
/// [`Mesh`].
pub fn parse_msh(text: &str) -> Result<Mesh, GmshError> {
    parse_msh_surface(text, None)
}

/// Parses the body of physical surface `surface` (`None`: the file's only body) of the text of a
/// Gmsh ASCII mesh file into a validated [`Mesh`].
pub fn parse_msh_surface(text: &str, surface: Option<&str>) -> Result<Mesh, GmshError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let raw = RawMsh::parse(text, Space::Planar)?;
    raw.build(surface)
}

/// Reads the tetrahedral body of physical volume `volume` (a name, or a tag number for an
/// unnamed group) of a Gmsh ASCII mesh file (MSH 4.1 or 2.2) into a validated [`SolidMesh`];
/// `None` reads all tetrahedra of a file with at most one physical volume. See the module
/// documentation.
pub fn read_solid_msh(path: &Path, volume: Option<&str>) -> Result<SolidMesh, GmshError> {
    parse_solid_msh(&read_text(path)?, volume)
}

/// Parses the tetrahedral body of physical volume `volume` (`None`: all tetrahedra of a file
/// with at most one physical volume) of the text of a Gmsh ASCII mesh file into a validated
/// [`SolidMesh`].
pub fn parse_solid_msh(text: &str, volume: Option<&str>) -> Result<SolidMesh, GmshError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let raw = RawMsh::parse(text, Space::Solid)?;
    raw.build_solid(volume)
}
