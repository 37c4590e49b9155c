//! Writer of VTK XML unstructured grid files (`.vtu`), for ParaView, VisIt or Python's `meshio`.
//!
//! A `.vtu` file is an XML document `VTKFile` → `UnstructuredGrid` → `Piece` holding:
//!
//! - `Points`: one `x y z` triple per node (`z` = 0 for a planar mesh);
//! - `Cells`: the flat `connectivity`, the `offsets` (end of each cell in `connectivity`) and the
//!   VTK cell `types`: 5 (`VTK_TRIANGLE`) for P1 and 22 (`VTK_QUADRATIC_TRIANGLE`) for P2, whose
//!   node order (vertices, then the mid-side nodes of edges (0,1), (1,2), (2,0)) is the mesh's;
//!   the mid-side nodes are points of their own, so a curved (isoparametric) P2 triangle comes out
//!   with its curved edges (ParaView draws a quadratic triangle's edges through its mid-side nodes);
//!   the tetrahedra of a 3D body are written by [`crate::solid_vtu`] through the same [`Grid`];
//! - `PointData`: one array per nodal field, node-major (all components of node 0 first);
//! - `CellData`: one array per element field, in cell order.
//!
//! A 9-component array is a 3×3 tensor, row-major (`xx xy xz yx yy yz zx zy zz`), which ParaView
//! shows as a tensor (its components, eigenvalues and von Mises in the calculator).
//!
//! Arrays are written in one of three [`VtuFormat`]s. [`VtuFormat::Binary`] stores every array as
//! little-endian raw bytes in one `<AppendedData encoding="raw">` section after the XML, after an
//! underscore: each `DataArray` element is empty and carries `format="appended"` and the `offset`
//! of its block (from the byte after the underscore); a block is the `UInt64` byte count of the
//! data (`header_type="UInt64"`) followed by the data (`Float64`, `Int64` or `UInt8`).
//!
//! [`VtuFormat::Zlib`] writes the same appended section with every block compressed as VTK's
//! `vtkZLibDataCompressor` does (`compressor="vtkZLibDataCompressor"` on `VTKFile`): an array's
//! bytes are cut into blocks of [`ZLIB_BLOCK`] bytes (the last one shorter), each compressed
//! alone as a zlib stream, and its block in the appended section is a header of `UInt64`s (the
//! number of blocks, the uncompressed size of a block, the uncompressed size of the last block
//! when it is shorter (0 otherwise), then the compressed size of each block) followed by the
//! compressed blocks. The blocks are compressed in parallel.
//!
//! [`VtuFormat::Ascii`] writes arrays as text, with one exception: a data array holding a
//! non-finite value (NaN or ±infinity). Older VTK readers (ParaView before VTK 9.3 or so) parse
//! ASCII numbers with C++ streams, which reject `nan` and `inf` and then report the array as too
//! short. Such an array is therefore written as inline base64 binary (`format="binary"`,
//! little-endian `Float64` preceded by a `UInt64` byte count, as declared by
//! `header_type="UInt64"`), which every VTK reader and `meshio` accept, NaN and infinities
//! included.
//!
//! [`crate::vtu_read`] reads all three back.

use std::fmt::Write as _;
use std::io::{Error, ErrorKind};

use std::path::Path;

use contactdd_core::mesh::{Mesh, Order};
use contactdd_core::{Point, DIM};

use crate::atomic::write_atomic;
use crate::number::push_f64;
pub use crate::vtu_options::{
    CollectionOverRanks, UnknownVtuFormat, UnknownVtuLayout, VtuFormat, VtuLayout, VtuOptions,
    COLLECTION_STEM, ZLIB_BLOCK, ZLIB_LEVEL,
};

/// A field to write, per node (point data) or per cell (cell data): `components` values per
/// item, item-major (`values[item * components + c]`).
#[derive(Clone, Copy, Debug)]
pub struct Field<'a> {
    /// Array name shown by ParaView.
    pub name: &'a str,
    /// Number of components per item (2-component fields are written padded to 3, with z = 0).
    pub components: usize,
    /// `items * components` values.
    pub values: &'a [f64],
}

/// The arrays of a `.vtu` file besides the mesh.
#[derive(Clone, Copy, Debug, Default)]
pub struct VtuData<'a> {
    /// Nodal displacement (2 values per node of a planar mesh, 3 of a tetrahedral one), written
    /// as the 3-component vector `"displacement"`, the active vectors.
    pub displacement: Option<&'a [f64]>,
    /// Nodal fields.
    pub points: &'a [Field<'a>],
    /// Element fields.
    pub cells: &'a [Field<'a>],
}

/// The mesh of a `Piece`: its points, its cells and their VTK cell type. [`Grid::planar`] gives
/// a planar mesh's, [`crate::solid_vtu::solid_grid`] a tetrahedral mesh's.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a> {
    pub(crate) points: GridPoints<'a>,
    /// `nodes_per_cell` (> 0) indices of `points` per cell, all in range.
    pub(crate) cells: &'a [usize],
    pub(crate) nodes_per_cell: usize,
    pub(crate) cell_type: u8,
    /// Cell `c` is written as the nodes `c[node_order[k]]` (as `c` without `node_order`).
    pub(crate) node_order: Option<&'a [usize]>,
}

/// The points of a [`Grid`]: in the plane (written with z = 0) or in space.
#[derive(Clone, Copy, Debug)]
pub(crate) enum GridPoints<'a> {
    Plane(&'a [Point]),
    Space(&'a [[f64; 3]]),
}

impl<'a> Grid<'a> {
    /// The grid of a planar mesh: triangles of type 5 (P1) or 22 (P2) in the mesh's node order.
    pub fn planar(mesh: &'a Mesh) -> Grid<'a> {
        let cell_type = match mesh.order() {
            Order::P1 => 5,
            Order::P2 => 22,
        };
        Grid {
            points: GridPoints::Plane(mesh.nodes()),
            cells: mesh.cells(),
            nodes_per_cell: mesh.order().nodes_per_cell(),
            cell_type,
            node_order: None,
        }
    }

    /// Number of points.
    pub fn num_points(&self) -> usize {
        match self.points {
            GridPoints::Plane(p) => p.len(),
            GridPoints::Space(p) => p.len(),
        }
    }

    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.cells.len() / self.nodes_per_cell
    }

    /// Displacement components per node: 2 in the plane, 3 in space.
    pub fn displacement_components(&self) -> usize {
        match self.points {
            GridPoints::Plane(_) => DIM,
            GridPoints::Space(_) => 3,
        }
    }
}

/// Writes `mesh` as an ASCII `.vtu` file at `path` with the arrays of `data`
/// ([`write_vtu_as`] with [`VtuFormat::Ascii`]).
pub fn write_vtu(path: &Path, mesh: &Mesh, data: VtuData<'_>) -> std::io::Result<()> {
    write_vtu_as(path, mesh, data, VtuFormat::Ascii)
}

/// Writes `mesh` as a `.vtu` file at `path` with the arrays of `data`, encoded as `format`.
///
/// The file is written by [`write_atomic`], so that a reader never sees a half-written file.
/// Mismatched field lengths are [`ErrorKind::InvalidInput`] errors; see [`vtu_bytes`].
pub fn write_vtu_as(
    path: &Path,
    mesh: &Mesh,
    data: VtuData<'_>,
    format: VtuFormat,
) -> std::io::Result<()> {
    write_atomic(path, &vtu_bytes(mesh, data, format)?)
}

/// The text of the ASCII `.vtu` file that [`write_vtu`] writes.
///
/// Errors ([`ErrorKind::InvalidInput`]) if the displacement does not hold 2 values per node, or a
/// field has zero components or not `components` values per node (per cell).
pub fn vtu_string(mesh: &Mesh, data: VtuData<'_>) -> std::io::Result<String> {
    let out = document(
        &[(Grid::planar(mesh), data)],
        Arrays::new(VtuFormat::Ascii, 0),
    )?;
    Ok(out.text)
}

/// The bytes of the `.vtu` file that [`write_vtu_as`] writes: [`vtu_string`] for
/// [`VtuFormat::Ascii`]; for [`VtuFormat::Binary`] and [`VtuFormat::Zlib`] the same XML with
/// every `DataArray` empty (`format="appended"` and the `offset` of its block), followed by the
/// appended section.
pub fn vtu_bytes(mesh: &Mesh, data: VtuData<'_>, format: VtuFormat) -> std::io::Result<Vec<u8>> {
    vtu_pieces_bytes(&[(mesh, data)], format)
}

/// The bytes of a `.vtu` file holding one `Piece` per mesh of `pieces`, in order, each with its
/// arrays, encoded as `format` (the appended arrays of every piece share one appended section).
/// With one piece, the bytes of [`vtu_bytes`]. VTK and ParaView read the pieces of such a file
/// as one grid, their points and cells one after the other.
pub fn vtu_pieces_bytes(
    pieces: &[(&Mesh, VtuData<'_>)],
    format: VtuFormat,
) -> std::io::Result<Vec<u8>> {
    let grids: Vec<(Grid<'_>, VtuData<'_>)> = (pieces.iter())
        .map(|(mesh, data)| (Grid::planar(mesh), *data))
        .collect();
    grid_pieces_bytes(&grids, format)
}

/// The bytes of a `.vtu` file holding one `Piece` per grid of `pieces` (planar or tetrahedral,
/// mixed as they come), in order, each with its arrays, encoded as `format`: the file of
/// [`vtu_pieces_bytes`] for any [`Grid`]. Errors ([`ErrorKind::InvalidInput`]) if a displacement
/// does not hold [`Grid::displacement_components`] values per node, or a field has zero
/// components or not `components` values per node (per cell).
pub fn grid_pieces_bytes(
    pieces: &[(Grid<'_>, VtuData<'_>)],
    format: VtuFormat,
) -> std::io::Result<Vec<u8>> {
    // The appended bytes: per node the points and the fields, per cell its connectivity.
    let capacity = pieces
        .iter()
        .map(|(mesh, data)| {
            let per_node = 3
                + data
                    .points
                    .iter()
                    .map(|f| f.components.max(3))
                    .sum::<usize>()
                + 3;
            let per_cell = 2 + mesh.nodes_per_cell + data.cells.len();
            8 * (per_node * mesh.num_points() + per_cell * mesh.num_cells())
        })
        .sum();
    let out = document(pieces, Arrays::new(format, capacity))?;
    let Some(appended) = out.appended else {
        return Ok(out.text.into_bytes());
    };
    if format == VtuFormat::Zlib {
        return zlib_file(&out.text, appended, &out.pending);
    }
    let mut bytes = out.text.into_bytes();
    bytes.reserve(appended.len() + 64);
    bytes.extend_from_slice(APPENDED_OPEN);
    bytes.extend_from_slice(&appended);
    bytes.extend_from_slice(APPENDED_CLOSE);
    Ok(bytes)
}

/// The start of the appended section, through the underscore.
const APPENDED_OPEN: &[u8] = b"  <AppendedData encoding=\"raw\">\n   _";
/// The end of the appended section and of the file.
const APPENDED_CLOSE: &[u8] = b"\n  </AppendedData>\n</VTKFile>\n";

/// The [`VtuFormat::Zlib`] file: the XML `text` with the offset of each array of `pending`
/// filled in, then the appended section: per array its header and its compressed blocks. `raw`
/// holds the arrays' bytes back to back; it is dropped once compressed, so that the file is
/// assembled from the compressed blocks alone.
fn zlib_file(text: &str, raw: Vec<u8>, pending: &[Pending]) -> std::io::Result<Vec<u8>> {
    use rayon::prelude::*;
    let blocks: Vec<&[u8]> = pending
        .iter()
        .flat_map(|p| raw[p.data.clone()].chunks(ZLIB_BLOCK))
        .collect();
    let compressed = blocks
        .par_iter()
        .map(|block| compress_block(block))
        .collect::<std::io::Result<Vec<Vec<u8>>>>()?;
    drop(blocks);
    drop(raw);
    // The offsets: each array's header and blocks follow the previous array's.
    let counts: Vec<usize> = pending
        .iter()
        .map(|p| p.data.len().div_ceil(ZLIB_BLOCK))
        .collect();
    let mut filled = String::with_capacity(text.len() + 12 * pending.len());
    let (mut copied, mut offset, mut first) = (0, 0, 0);
    for (p, &count) in pending.iter().zip(&counts) {
        filled.push_str(&text[copied..p.at]);
        copied = p.at;
        let _ = write!(filled, "{offset}");
        let packed: usize = compressed[first..first + count].iter().map(Vec::len).sum();
        offset += 8 * (3 + count) + packed;
        first += count;
    }
    filled.push_str(&text[copied..]);
    let mut bytes = filled.into_bytes();
    bytes.reserve(offset + APPENDED_OPEN.len() + APPENDED_CLOSE.len());
    bytes.extend_from_slice(APPENDED_OPEN);
    let mut next = compressed.into_iter();
    for (p, &count) in pending.iter().zip(&counts) {
        let len = p.data.len();
        for word in [count, ZLIB_BLOCK, len % ZLIB_BLOCK] {
            bytes.extend_from_slice(&(word as u64).to_le_bytes());
        }
        let mine: Vec<Vec<u8>> = next.by_ref().take(count).collect();
        for block in &mine {
            bytes.extend_from_slice(&(block.len() as u64).to_le_bytes());
        }
        mine.iter().for_each(|block| bytes.extend_from_slice(block));
    }
    bytes.extend_from_slice(APPENDED_CLOSE);
    Ok(bytes)
}

/// `bytes` as one zlib stream at [`ZLIB_LEVEL`].
fn compress_block(bytes: &[u8]) -> std::io::Result<Vec<u8>> {
    use flate2::{Compress, FlushCompress, Status};
    thread_local! {
        // One compressor per thread, reset per block: a new one allocates and clears its
        // window and hash tables (hundreds of kB), which would cost more than compressing a
        // small body's array.
        static COMPRESSOR: std::cell::RefCell<Option<Compress>> = const { std::cell::RefCell::new(None) };
    }
    let failed = |e: flate2::CompressError| std::io::Error::other(e.to_string());
    COMPRESSOR.with(|cell| {
        let mut cell = cell.borrow_mut();
        let z =
            cell.get_or_insert_with(|| Compress::new(flate2::Compression::new(ZLIB_LEVEL), true));
        z.reset();
        let mut out = Vec::with_capacity(bytes.len() / 2 + 64);
        // As a zlib encoder writes: the input without flushing, then the end of the stream.
        let mut input = bytes;
        while !input.is_empty() {
            out.reserve(64.max(input.len() / 2));
            let before = z.total_in();
            z.compress_vec(input, &mut out, FlushCompress::None)
                .map_err(failed)?;
            input = &input[(z.total_in() - before) as usize..];
        }
        loop {
            out.reserve(64.max(out.len() / 8));
            if z.compress_vec(&[], &mut out, FlushCompress::Finish)
                .map_err(failed)?
                == Status::StreamEnd
            {
                return Ok(out);
            }
        }
    })
}

/// The XML of the file through `</UnstructuredGrid>` (and `</VTKFile>` for ASCII), one `Piece`
/// per mesh of `pieces`, with the appended bytes of a binary file.
fn document(pieces: &[(Grid<'_>, VtuData<'_>)], mut out: Arrays) -> std::io::Result<Arrays> {
    for (mesh, data) in pieces {
        check_lengths(&node_fields(mesh, data), mesh.num_points(), "nodes")?;
        check_lengths(data.cells, mesh.num_cells(), "cells")?;
    }
    out.open_file();
    out.text.push_str("  <UnstructuredGrid>\n");
    for (mesh, data) in pieces {
        piece(mesh, *data, &mut out);
    }
    out.text.push_str("  </UnstructuredGrid>\n");
    if out.appended.is_none() {
        out.text.push_str("</VTKFile>\n");
    }
    Ok(out)
}

/// Writes the `Piece` of `mesh` with the arrays of `data`, whose lengths are checked.
fn piece(mesh: &Grid<'_>, data: VtuData<'_>, out: &mut Arrays) {
    let n = mesh.num_points();
    let arrays = node_fields(mesh, &data);
    let _ = writeln!(
        out.text,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{}\">",
        mesh.num_cells()
    );
    // Marking the displacement as the active vectors lets ParaView's "Warp By Vector" use it.
    if data.displacement.is_some() {
        out.text
            .push_str("      <PointData Vectors=\"displacement\">\n");
    } else {
        out.text.push_str("      <PointData>\n");
    }
    field_arrays(out, &arrays);
    out.text.push_str("      </PointData>\n");
    if !data.cells.is_empty() {
        out.text.push_str("      <CellData>\n");
        field_arrays(out, data.cells);
        out.text.push_str("      </CellData>\n");
    }

    out.text.push_str("      <Points>\n");
    match mesh.points {
        GridPoints::Plane(p) => out.float_array(None, 3, p.iter().flat_map(|p| [p[0], p[1], 0.0])),
        GridPoints::Space(p) => out.float_array(None, 3, p.iter().flat_map(|p| *p)),
    }
    out.text.push_str("      </Points>\n");

    let (npc, cell_type) = (mesh.nodes_per_cell, mesh.cell_type);
    out.text.push_str("      <Cells>\n");
    // One cell per line.
    let cells = mesh.cells;
    match mesh.node_order {
        None => out.int_array(Int::Int64, "connectivity", npc, cells.iter().copied()),
        Some(order) => {
            let nodes = (cells.chunks_exact(npc)).flat_map(|c| order.iter().map(move |&k| c[k]));
            out.int_array(Int::Int64, "connectivity", npc, nodes);
        }
    }
    out.int_array(
        Int::Int64,
        "offsets",
        12,
        (1..=mesh.num_cells()).map(|e| e * npc),
    );
    out.int_array(
        Int::UInt8,
        "types",
        24,
        (0..mesh.num_cells()).map(|_| usize::from(cell_type)),
    );
    out.text.push_str("      </Cells>\n");

    out.text.push_str("    </Piece>\n");
}

/// The nodal arrays of `data` on `mesh`: the displacement (if any), then the point fields.
fn node_fields<'a>(mesh: &Grid<'_>, data: &VtuData<'a>) -> Vec<Field<'a>> {
    let mut arrays: Vec<Field<'a>> = Vec::with_capacity(data.points.len() + 1);
    if let Some(values) = data.displacement {
        arrays.push(Field {
            name: "displacement",
            components: mesh.displacement_components(),
            values,
        });
    }
    arrays.extend_from_slice(data.points);
    arrays
}

/// Errors unless every field has `components` > 0 values for each of the `count` items.
fn check_lengths(fields: &[Field<'_>], count: usize, items: &str) -> std::io::Result<()> {
    for field in fields {
        if field.components == 0 || Some(field.values.len()) != count.checked_mul(field.components)
        {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "field '{}': {} values for {count} {items} and {} components each",
                    field.name,
                    field.values.len(),
                    field.components
                ),
            ));
        }
    }
    Ok(())
}

/// Writes one data array per field; 2D vectors are padded with z = 0 so that ParaView treats
/// them as vectors.
fn field_arrays(out: &mut Arrays, fields: &[Field<'_>]) {
    for field in fields {
        let padded = if field.components == 2 {
            3
        } else {
            field.components
        };
        let values = field.values.chunks(field.components).flat_map(|item| {
            item.iter()
                .copied()
                .chain(std::iter::repeat(0.0).take(padded - field.components))
        });
        out.float_array(Some(field.name), padded, values);
    }
}

/// The integer types of the `Cells` arrays.
#[derive(Clone, Copy)]
enum Int {
    Int64,
    UInt8,
}

/// The XML text being written and, for [`VtuFormat::Binary`], the appended bytes; for
/// [`VtuFormat::Zlib`], the arrays' uncompressed bytes and where their offsets go.
struct Arrays {
    text: String,
    appended: Option<Vec<u8>>,
    /// Zlib: the arrays whose offset is known once their blocks are compressed.
    pending: Vec<Pending>,
    zlib: bool,
}

/// An array of a [`VtuFormat::Zlib`] file: where its offset goes in the XML text and its bytes
/// in the uncompressed buffer.
struct Pending {
    at: usize,
    data: std::ops::Range<usize>,
}

impl Arrays {
    fn new(format: VtuFormat, capacity: usize) -> Arrays {
        Arrays {
            text: String::new(),
            appended: match format {
                VtuFormat::Ascii => None,
                VtuFormat::Binary | VtuFormat::Zlib => Some(Vec::with_capacity(capacity)),
            },
            pending: Vec::new(),
            zlib: format == VtuFormat::Zlib,
        }
    }

    /// Opens an appended block: the empty element with its offset and, for a binary file, a byte
    /// count to fill in ([`Arrays::close_block`]). Returns where the data start.
    fn open_block(&mut self, attributes: std::fmt::Arguments<'_>) -> Option<usize> {
        let appended = self.appended.as_mut()?;
        let _ = write!(
            self.text,
            "        <DataArray {attributes} format=\"appended\" offset=\""
        );
        if self.zlib {
            self.pending.push(Pending {
                at: self.text.len(),
                data: appended.len()..appended.len(),
            });
            self.text.push_str("\"/>\n");
            return Some(appended.len());
        }
        let _ = writeln!(self.text, "{}\"/>", appended.len());
        appended.extend_from_slice(&[0; 8]);
        Some(appended.len())
    }

    /// Ends the block whose data start at `start`: writes its byte count (binary) or the end of
    /// its data (zlib).
    fn close_block(&mut self, start: usize) {
        if let Some(appended) = self.appended.as_mut() {
            if self.zlib {
                if let Some(p) = self.pending.last_mut() {
                    p.data.end = appended.len();
                }
                return;
            }
            let len = (appended.len() - start) as u64;
            appended[start - 8..start].copy_from_slice(&len.to_le_bytes());
        }
    }

    /// Writes the XML declaration and the `VTKFile` tag (with the `compressor` of a zlib file).
    fn open_file(&mut self) {
        let compressor = if self.zlib {
            " compressor=\"vtkZLibDataCompressor\""
        } else {
            ""
        };
        self.text.push_str("<?xml version=\"1.0\"?>\n");
        let _ = writeln!(
            self.text,
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
             header_type=\"UInt64\"{compressor}>",
        );
    }

    /// Writes a `Float64` data array: appended for a binary file; else ASCII if all values are
    /// finite, base64 binary otherwise.
    fn float_array(
        &mut self,
        name: Option<&str>,
        components: usize,
        values: impl Iterator<Item = f64> + Clone,
    ) {
        let named = name.map_or(String::new(), |n| format!(" Name=\"{}\"", xml_escape(n)));
        let tag = format_args!("type=\"Float64\"{named} NumberOfComponents=\"{components}\"");
        if let Some(at) = self.open_block(tag) {
            if let Some(appended) = self.appended.as_mut() {
                values.for_each(|x| appended.extend_from_slice(&x.to_le_bytes()));
            }
            self.close_block(at);
            return;
        }
        float_array(&mut self.text, name, components, values);
    }

    /// Writes an integer array of the `Cells`: appended for a binary file, else ASCII with
    /// `per_row` values per line.
    fn int_array(
        &mut self,
        int: Int,
        name: &str,
        per_row: usize,
        values: impl Iterator<Item = usize>,
    ) {
        let ty = match int {
            Int::Int64 => "Int64",
            Int::UInt8 => "UInt8",
        };
        if let Some(at) = self.open_block(format_args!("type=\"{ty}\" Name=\"{name}\"")) {
            if let Some(appended) = self.appended.as_mut() {
                match int {
                    // Indices and offsets fit: a mesh holds fewer than 2^63 of anything.
                    Int::Int64 => {
                        values.for_each(|v| appended.extend_from_slice(&(v as i64).to_le_bytes()))
                    }
                    Int::UInt8 => values.for_each(|v| appended.push(v as u8)),
                }
            }
            self.close_block(at);
            return;
        }
        let _ = writeln!(
            self.text,
            "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
        );
        write_rows(&mut self.text, values, per_row, push_int);
        self.text.push_str("        </DataArray>\n");
    }
}

/// Writes a `Float64` data array: ASCII if all values are finite, base64 binary otherwise.
fn float_array(
    out: &mut String,
    name: Option<&str>,
    components: usize,
    values: impl Iterator<Item = f64> + Clone,
) {
    let finite = values.clone().all(f64::is_finite);
    let _ = write!(out, "        <DataArray type=\"Float64\"");
    if let Some(name) = name {
        let _ = write!(out, " Name=\"{}\"", xml_escape(name));
    }
    let format = if finite { "ascii" } else { "binary" };
    let _ = writeln!(
        out,
        " NumberOfComponents=\"{components}\" format=\"{format}\">"
    );
    if finite {
        // One node per line for vectors, a few values per line for scalars.
        let per_row = if components >= 2 { components } else { 6 };
        write_rows(out, values, per_row, push_f64);
    } else {
        let mut bytes: Vec<u8> = Vec::new();
        bytes.extend_from_slice(&[0; 8]);
        for x in values {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
        let len = (bytes.len() - 8) as u64;
        bytes[..8].copy_from_slice(&len.to_le_bytes());
        out.push_str("          ");
        base64_encode(out, &bytes);
        out.push('\n');
    }
    out.push_str("        </DataArray>\n");
}

/// Writes `values`, `per_row` per indented line, each preceded by a space and written by `push`.
fn write_rows<T>(
    out: &mut String,
    values: impl Iterator<Item = T>,
    per_row: usize,
    push: impl Fn(&mut String, T),
) {
    let mut column = 0;
    for v in values {
        if column == 0 {
            out.push_str("         ");
        }
        out.push(' ');
        push(out, v);
        column += 1;
        if column == per_row {
            out.push('\n');
            column = 0;
        }
    }
    if column != 0 {
        out.push('\n');
    }
}

fn push_int(out: &mut String, v: usize) {
    let _ = write!(out, "{v}");
}

/// Escapes the XML special characters of an attribute value.
fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Appends the standard (RFC 4648, padded) base64 encoding of `bytes`.
fn base64_encode(out: &mut String, bytes: &[u8]) {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let symbol = |index: u32| char::from(ALPHABET[(index & 63) as usize]);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk.first().copied().unwrap_or(0),
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let word = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        out.push(symbol(word >> 18));
        out.push(symbol(word >> 12));
        out.push(if chunk.len() > 1 {
            symbol(word >> 6)
        } else {
            '='
        });
        out.push(if chunk.len() > 2 { symbol(word) } else { '=' });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_examples() {
        let cases = [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ];
        for (plain, encoded) in cases {
            let mut out = String::new();
            base64_encode(&mut out, plain.as_bytes());
            assert_eq!(out, encoded);
        }
    }

    #[test]
    fn names_are_escaped() {
        assert_eq!(xml_escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
