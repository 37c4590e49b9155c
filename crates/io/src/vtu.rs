//! Writer of VTK XML unstructured grid files (`.vtu`), for ParaView, VisIt or Python's `meshio`.
//!
//! A `.vtu` file is an XML document `VTKFile` → `UnstructuredGrid` → `Piece` holding:
//!
//! - `Points`: one `x y z` triple per node (`z` = 0 here);
//! - `Cells`: the flat `connectivity`, the `offsets` (end of each cell in `connectivity`) and the
//!   VTK cell `types`: 5 (`VTK_TRIANGLE`) for P1 and 22 (`VTK_QUADRATIC_TRIANGLE`) for P2, whose
//!   node order (vertices, then the mid-side nodes of edges (0,1), (1,2), (2,0)) is the mesh's;
//! - `PointData`: one array per nodal field, node-major (all components of node 0 first);
//! - `CellData`: one array per element field, in cell order.
//!
//! A 9-component array is a 3×3 tensor, row-major (`xx xy xz yx yy yz zx zy zz`), which ParaView
//! shows as a tensor (its components, eigenvalues and von Mises in the calculator).
//!
//! Arrays are written as ASCII text. The one exception is a data array holding a non-finite value
//! (NaN or ±infinity): older VTK readers (ParaView before VTK 9.3 or so) parse ASCII numbers with
//! C++ streams, which reject `nan` and `inf` and then report the array as too short. Such an array
//! is therefore written as inline base64 binary (`format="binary"`, little-endian `Float64`
//! preceded by a `UInt64` byte count, as declared by `header_type="UInt64"`), which every VTK
//! reader and `meshio` accept, NaN and infinities included.

use std::fmt::Write as _;
use std::io::{Error, ErrorKind};
use std::path::Path;

use contactdd_core::mesh::{Mesh, Order};
use contactdd_core::DIM;

use crate::atomic::write_atomic;
use crate::number::push_f64;

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
    /// Nodal displacement (2 values per node), written as the 3-component vector
    /// `"displacement"`, the active vectors.
    pub displacement: Option<&'a [f64]>,
    /// Nodal fields.
    pub points: &'a [Field<'a>],
    /// Element fields.
    pub cells: &'a [Field<'a>],
}

/// Writes `mesh` as a `.vtu` file at `path` with the arrays of `data`.
///
/// The file is written by [`write_atomic`], so that a reader never sees a half-written file.
/// Mismatched field lengths are [`ErrorKind::InvalidInput`] errors; see [`vtu_string`].
pub fn write_vtu(path: &Path, mesh: &Mesh, data: VtuData<'_>) -> std::io::Result<()> {
    let text = vtu_string(mesh, data)?;
    write_atomic(path, text.as_bytes())
}

/// The text of the `.vtu` file that [`write_vtu`] writes.
///
/// Errors ([`ErrorKind::InvalidInput`]) if the displacement does not hold 2 values per node, or a
/// field has zero components or not `components` values per node (per cell).
pub fn vtu_string(mesh: &Mesh, data: VtuData<'_>) -> std::io::Result<String> {
    let n = mesh.num_nodes();
    let mut arrays: Vec<Field<'_>> = Vec::with_capacity(data.points.len() + 1);
    if let Some(values) = data.displacement {
        arrays.push(Field {
            name: "displacement",
            components: DIM,
            values,
        });
    }
    arrays.extend_from_slice(data.points);
    check_lengths(&arrays, n, "nodes")?;
    check_lengths(data.cells, mesh.num_cells(), "cells")?;

    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\"?>\n");
    out.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n",
    );
    out.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        out,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{}\">",
        mesh.num_cells()
    );

    // Marking the displacement as the active vectors lets ParaView's "Warp By Vector" use it.
    if data.displacement.is_some() {
        out.push_str("      <PointData Vectors=\"displacement\">\n");
    } else {
        out.push_str("      <PointData>\n");
    }
    field_arrays(&mut out, &arrays);
    out.push_str("      </PointData>\n");
    if !data.cells.is_empty() {
        out.push_str("      <CellData>\n");
        field_arrays(&mut out, data.cells);
        out.push_str("      </CellData>\n");
    }

    out.push_str("      <Points>\n");
    let points = mesh.nodes().iter().flat_map(|p| [p[0], p[1], 0.0]);
    float_array(&mut out, None, 3, points);
    out.push_str("      </Points>\n");

    let npc = mesh.order().nodes_per_cell();
    let cell_type = match mesh.order() {
        Order::P1 => 5,
        Order::P2 => 22,
    };
    out.push_str("      <Cells>\n");
    out.push_str("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    // One cell per line.
    write_rows(&mut out, mesh.cells().iter().copied(), npc, push_int);
    out.push_str("        </DataArray>\n");
    out.push_str("        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    write_rows(
        &mut out,
        (1..=mesh.num_cells()).map(|e| e * npc),
        12,
        push_int,
    );
    out.push_str("        </DataArray>\n");
    out.push_str("        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    write_rows(
        &mut out,
        (0..mesh.num_cells()).map(|_| cell_type),
        24,
        push_int,
    );
    out.push_str("        </DataArray>\n");
    out.push_str("      </Cells>\n");

    out.push_str("    </Piece>\n");
    out.push_str("  </UnstructuredGrid>\n");
    out.push_str("</VTKFile>\n");
    Ok(out)
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
fn field_arrays(out: &mut String, fields: &[Field<'_>]) {
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
        float_array(out, Some(field.name), padded, values);
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
