//! Reader of Gmsh `.msh` files (ASCII MSH 4.1, and the older ASCII MSH 2.2).
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
//! line: ends, then middle) and 15 (point). Quadrilaterals, higher-order and 3D elements are
//! unsupported.
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
//! The reader runs in three steps: `tokens` splits the text, `raw` reads the sections and
//! `build` assembles the mesh.
//!
//! Why this reader lives in the numerical core while every other file format lives in
//! `contactdd-io`: it is a mesh source like [`crate::rectangle`], not a front end. It needs no
//! dependency, builds its result only through the public [`Mesh::new`] (no crate internals), and
//! reports [`GmshError`]; so an MPI driver, a benchmark or a Rust user can read a Gmsh mesh
//! without linking the TOML and JSON code. Nothing else in the core reads or writes files.

use std::path::Path;

use crate::error::GmshError;
use crate::mesh::Mesh;

mod build;
mod raw;
mod tokens;

use raw::RawMsh;

/// Reads a Gmsh ASCII mesh file (MSH 4.1 or 2.2) holding one body into a validated [`Mesh`].
pub fn read_msh(path: &Path) -> Result<Mesh, GmshError> {
    read_msh_surface(path, None)
}

/// Reads the body of physical surface `surface` (a name, or a tag number for an unnamed group)
/// of a Gmsh ASCII mesh file; `None` reads a file holding one body. See the module documentation.
pub fn read_msh_surface(path: &Path, surface: Option<&str>) -> Result<Mesh, GmshError> {
    let bytes = std::fs::read(path).map_err(|source| GmshError::Io {
        path: path.display().to_string(),
        source,
    })?;
    // Binary files have an ASCII header, so a lossy conversion still lets `parse_msh` see the
    // file type in `$MeshFormat` and report them as unsupported.
    parse_msh_surface(&String::from_utf8_lossy(&bytes), surface)
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
    let raw = RawMsh::parse(text)?;
    raw.build(surface)
}
