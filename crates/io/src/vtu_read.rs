//! Reader of the `.vtu` files [`crate::vtu`] writes, in any [`crate::vtu::VtuFormat`]: ASCII
//! arrays, inline base64 arrays (`format="binary"`) and appended raw arrays
//! (`format="appended"`, `<AppendedData encoding="raw">`), uncompressed or, with
//! `compressor="vtkZLibDataCompressor"`, in zlib-compressed blocks; each `Float64`, `Int64` or
//! `UInt8` with `UInt64` byte counts, little-endian.
//!
//! The file is untrusted (a reader of a result folder): every length and offset it declares is
//! checked against the bytes actually there before anything is allocated, so a truncated or
//! lying file is an error ([`VtuReadError`]), never a panic or an allocation larger than the
//! file. A compressed block may expand to at most [`MAX_EXPANSION`] times its compressed size
//! (zlib's own limit is 1032) and at most [`MAX_BLOCK`] bytes, and must expand to exactly the
//! size its header declares: the output of the decompression is bounded before it starts.
//!
//! [`parse_vtu`] and [`parse_vtu_pieces`] give the arrays as they are; [`VtuFile::points`] and
//! [`VtuFile::cells`] give a piece's points and its cells, checked: triangles (types 5 and 22) of
//! a planar body, tetrahedra (types 10 and 24, [`crate::solid_vtu`]) of a 3D body.

/// The largest uncompressed size of a zlib block read, relative to its compressed size (deflate
/// cannot expand data by more than 1032 times, and the stream's few bytes of framing allow a
/// little more for tiny blocks).
pub const MAX_EXPANSION: usize = 1040;

/// The largest uncompressed size of one zlib block read (VTK and contactdd write 32 KiB).
pub const MAX_BLOCK: usize = 1 << 30;

/// The part of a `Piece` an array belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Section {
    /// `PointData`: one item per node.
    PointData,
    /// `CellData`: one item per cell.
    CellData,
    /// `Points`: the node coordinates.
    Points,
    /// `Cells`: `connectivity`, `offsets`, `types`.
    Cells,
}

/// One data array, its values as `f64` (integers are exact up to 2^53).
#[derive(Clone, Debug, PartialEq)]
pub struct VtuArray {
    /// Where the array is.
    pub section: Section,
    /// Its `Name` (empty for the unnamed `Points` array).
    pub name: String,
    /// `NumberOfComponents` (1 when absent).
    pub components: usize,
    /// The values, item-major.
    pub values: Vec<f64>,
}

/// A `.vtu` file that is not one [`crate::vtu`] writes, or is damaged.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct VtuReadError(pub String);

fn bad<T>(message: impl Into<String>) -> Result<T, VtuReadError> {
    Err(VtuReadError(message.into()))
}

/// The arrays of a `.vtu` file, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VtuFile {
    /// Every `DataArray`.
    pub arrays: Vec<VtuArray>,
}

impl VtuFile {
    /// The array named `name` in `section` (`""` for the `Points` array).
    pub fn array(&self, section: Section, name: &str) -> Option<&VtuArray> {
        (self.arrays.iter()).find(|a| a.section == section && a.name == name)
    }
}

/// The VTK cell types a piece's cells are read as ([`VtuFile::cells`]), with their nodes per
/// cell: the triangles of a planar body, 5 (P1, 3 nodes) and 22 (P2, 6), and the tetrahedra of a
/// 3D body, 10 (P1, 4) and 24 (P2, 10).
pub const CELL_TYPES: [(u8, usize); 4] = [(5, 3), (22, 6), (10, 4), (24, 10)];

/// The nodes per cell of the VTK cell type `cell_type`, if it is one of [`CELL_TYPES`].
pub fn nodes_per_cell(cell_type: u8) -> Option<usize> {
    (CELL_TYPES.iter()).find_map(|&(t, n)| (t == cell_type).then_some(n))
}

/// The cells of a piece, checked: each of a type of [`CELL_TYPES`], with its type's number of
/// nodes, each node one of the piece's points.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct VtuCells {
    /// The flat connectivity, in the file's (VTK's) node order.
    pub connectivity: Vec<usize>,
    /// The end of each cell in `connectivity`.
    pub offsets: Vec<usize>,
    /// The VTK type of each cell.
    pub types: Vec<u8>,
}

impl VtuCells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.types.len()
    }

    /// Whether there is no cell.
    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// The nodes of cell `k`, if there is such a cell.
    pub fn cell(&self, k: usize) -> Option<&[usize]> {
        let end = *self.offsets.get(k)?;
        let start = if k == 0 { 0 } else { self.offsets[k - 1] };
        self.connectivity.get(start..end)
    }
}

impl VtuFile {
    /// The points of the piece, `x y z` each: an error if the `Points` array is missing or
    /// does not hold 3 components.
    pub fn points(&self) -> Result<Vec<[f64; 3]>, VtuReadError> {
        let Some(points) = self.array(Section::Points, "") else {
            return bad("no Points array");
        };
        if points.components != 3 || points.values.len() % 3 != 0 {
            return bad("the Points array does not hold x y z triples");
        }
        Ok((points.values.chunks_exact(3))
            .map(|p| [p[0], p[1], p[2]])
            .collect())
    }

    /// The cells of the piece (whose arrays `self` holds), checked against its points: the
    /// `connectivity`, `offsets` and `types` arrays, each cell of a type of [`CELL_TYPES`] with
    /// that type's number of nodes, every node an index of a point.
    pub fn cells(&self) -> Result<VtuCells, VtuReadError> {
        let array = |name: &str| {
            self.array(Section::Cells, name)
                .map(|a| &a.values)
                .ok_or_else(|| VtuReadError(format!("no Cells array '{name}'")))
        };
        let (conn, offsets, types) = (array("connectivity")?, array("offsets")?, array("types")?);
        let points = self
            .array(Section::Points, "")
            .map_or(0, |p| p.values.len() / 3);
        let index = |v: f64, limit: usize| {
            (v >= 0.0 && v.fract() == 0.0 && v < limit as f64).then_some(v as usize)
        };
        if offsets.len() != types.len() {
            return bad(format!(
                "{} offsets for {} cell types",
                offsets.len(),
                types.len()
            ));
        }
        let mut cells = VtuCells::default();
        let mut start = 0;
        for (k, (&end, &ty)) in offsets.iter().zip(types).enumerate() {
            let ty = index(ty, 256).map(|t| t as u8);
            let Some((ty, n)) = ty.and_then(|t| Some((t, nodes_per_cell(t)?))) else {
                return bad(format!("cell {k}: its type is not one of 5, 22, 10, 24"));
            };
            if index(end, conn.len() + 1) != Some(start + n) {
                return bad(format!("cell {k}: its offset does not end {n} nodes on"));
            }
            for &v in &conn[start..start + n] {
                let node = index(v, points)
                    .ok_or_else(|| VtuReadError(format!("cell {k}: node {v} is not a point")))?;
                cells.connectivity.push(node);
            }
            start += n;
            cells.offsets.push(start);
            cells.types.push(ty);
        }
        if start != conn.len() {
            return bad("the connectivity holds nodes after the last cell");
        }
        Ok(cells)
    }
}

/// Reads the arrays of the `.vtu` file `bytes`, those of every `Piece` one after the other.
pub fn parse_vtu(bytes: &[u8]) -> Result<VtuFile, VtuReadError> {
    let arrays = parse_vtu_pieces(bytes)?
        .into_iter()
        .flat_map(|piece| piece.arrays)
        .collect();
    Ok(VtuFile { arrays })
}

/// Reads the arrays of each `Piece` of the `.vtu` file `bytes`, in file order: one per body of
/// a file of [`crate::vtu::VtuLayout::Collection`], one for a body's own file (arrays outside
/// any `Piece` count as a piece of their own).
pub fn parse_vtu_pieces(bytes: &[u8]) -> Result<Vec<VtuFile>, VtuReadError> {
    let head_end = find(bytes, b"<AppendedData").unwrap_or(bytes.len());
    let Ok(head) = std::str::from_utf8(&bytes[..head_end]) else {
        return bad("the XML part is not UTF-8 text");
    };
    let appended = appended_data(&bytes[head_end..])?;
    let mut pieces: Vec<VtuFile> = Vec::new();
    // Whether an array goes into a new piece: before the first, and after each `<Piece>` tag.
    let mut new_piece = true;
    let mut section = None;
    let mut zlib = false;
    let mut rest = head;
    while let Some(at) = rest.find('<') {
        rest = &rest[at..];
        let Some(end) = rest.find('>') else {
            return bad("an XML tag is not closed");
        };
        let tag = &rest[1..end];
        let name = tag.split(|c: char| c.is_whitespace() || c == '/').next();
        match name {
            Some("VTKFile") => zlib = compressed(tag)?,
            Some("Piece") => {
                new_piece = true;
                section = None;
            }
            Some("PointData") => section = Some(Section::PointData),
            Some("CellData") => section = Some(Section::CellData),
            Some("Points") => section = Some(Section::Points),
            Some("Cells") => section = Some(Section::Cells),
            Some("DataArray") => {
                let Some(section) = section else {
                    return bad("a DataArray outside PointData, CellData, Points and Cells");
                };
                let body = &rest[end + 1..];
                let appended = appended.map(|raw| (raw, zlib));
                let (array, used) = data_array(section, tag, body, appended)?;
                if std::mem::take(&mut new_piece) {
                    pieces.push(VtuFile::default());
                }
                if let Some(piece) = pieces.last_mut() {
                    piece.arrays.push(array);
                }
                rest = &body[used..];
                continue;
            }
            _ => {}
        }
        rest = &rest[end + 1..];
    }
    Ok(pieces)
}

/// Whether the arrays of the file whose `VTKFile` tag is `tag` are zlib-compressed: an error
/// for another compressor, or for compressed arrays whose headers are not `UInt64`.
fn compressed(tag: &str) -> Result<bool, VtuReadError> {
    match attribute(tag, "compressor") {
        None => Ok(false),
        Some("vtkZLibDataCompressor") if attribute(tag, "header_type") == Some("UInt64") => {
            Ok(true)
        }
        Some("vtkZLibDataCompressor") => bad("zlib-compressed arrays need header_type=\"UInt64\""),
        Some(other) => bad(format!(
            "compressor '{other}' is not read (only vtkZLibDataCompressor)"
        )),
    }
}

/// The raw bytes after the underscore of an `<AppendedData encoding="raw">` section at the start
/// of `tail` (none when `tail` is empty).
fn appended_data(tail: &[u8]) -> Result<Option<&[u8]>, VtuReadError> {
    if tail.is_empty() {
        return Ok(None);
    }
    let Some(end) = tail.iter().position(|&b| b == b'>') else {
        return bad("the AppendedData tag is not closed");
    };
    let tag = String::from_utf8_lossy(&tail[..end]);
    if attribute(&tag, "encoding") != Some("raw") {
        return bad("appended data is not raw (only encoding=\"raw\" is read)");
    }
    let after = &tail[end + 1..];
    match after.iter().position(|b| !b.is_ascii_whitespace()) {
        Some(u) if after[u] == b'_' => Ok(Some(&after[u + 1..])),
        _ => bad("the appended data does not start with '_'"),
    }
}

/// The array of the `DataArray` tag `tag` (its text between `<` and `>`), whose content starts
/// `body`, and how many bytes of `body` it used (through its end tag). `appended` is the raw
/// appended data, if any, and whether its blocks are zlib-compressed.
fn data_array(
    section: Section,
    tag: &str,
    body: &str,
    appended: Option<(&[u8], bool)>,
) -> Result<(VtuArray, usize), VtuReadError> {
    let name = unescape(attribute(tag, "Name").unwrap_or(""));
    let what = |m: &str| VtuReadError(format!("array '{name}': {m}"));
    let components = match attribute(tag, "NumberOfComponents") {
        None => 1,
        Some(c) => c
            .parse::<usize>()
            .ok()
            .filter(|&c| c > 0)
            .ok_or_else(|| what("bad NumberOfComponents"))?,
    };
    let ty = attribute(tag, "type").unwrap_or("");
    let size = match ty {
        "Float64" | "Int64" => 8,
        "UInt8" => 1,
        _ => return Err(what(&format!("type '{ty}' is not Float64, Int64 or UInt8"))),
    };
    let closed = tag.ends_with('/');
    let (text, used) = if closed {
        ("", 0)
    } else {
        let end = body
            .find("</DataArray>")
            .ok_or_else(|| what("no </DataArray>"))?;
        (&body[..end], end + "</DataArray>".len())
    };
    let values = match attribute(tag, "format") {
        Some("ascii") => text
            .split_whitespace()
            .map(|v| {
                v.parse::<f64>()
                    .map_err(|_| what(&format!("'{v}' is not a number")))
            })
            .collect::<Result<Vec<f64>, VtuReadError>>()?,
        Some("binary") if matches!(appended, Some((_, true))) => {
            return Err(what("compressed inline base64 arrays are not read"))
        }
        Some("binary") => {
            let bytes = base64_decode(text).ok_or_else(|| what("bad base64"))?;
            decode(block(&bytes, 0).map_err(|m| what(&m))?, ty, size).map_err(|m| what(&m))?
        }
        Some("appended") => {
            let (raw, zlib) =
                appended.ok_or_else(|| what("appended, but the file has no AppendedData"))?;
            let offset = attribute(tag, "offset")
                .and_then(|o| o.parse::<usize>().ok())
                .ok_or_else(|| what("no offset"))?;
            if zlib {
                let data = zlib_block(raw, offset).map_err(|m| what(&m))?;
                decode(&data, ty, size).map_err(|m| what(&m))?
            } else {
                decode(block(raw, offset).map_err(|m| what(&m))?, ty, size).map_err(|m| what(&m))?
            }
        }
        _ => return Err(what("format is not ascii, binary or appended")),
    };
    let array = VtuArray {
        section,
        name,
        components,
        values,
    };
    Ok((array, used))
}

/// The data of the block at `offset` of `bytes`: a `UInt64` byte count, then that many bytes,
/// all of which must be there.
fn block(bytes: &[u8], offset: usize) -> Result<&[u8], String> {
    let header = offset
        .checked_add(8)
        .and_then(|end| bytes.get(offset..end))
        .ok_or("the block's byte count is past the end of the file")?;
    let mut count = [0u8; 8];
    count.copy_from_slice(header);
    let count = u64::from_le_bytes(count);
    let start = offset + 8;
    usize::try_from(count)
        .ok()
        .and_then(|n| start.checked_add(n))
        .and_then(|end| bytes.get(start..end))
        .ok_or_else(|| format!("the block declares {count} bytes, more than the file holds"))
}

/// The `UInt64` at `at` of `bytes`, if it is there.
fn word_at(bytes: &[u8], at: usize) -> Option<u64> {
    let mut w = [0u8; 8];
    w.copy_from_slice(bytes.get(at..at.checked_add(8)?)?);
    Some(u64::from_le_bytes(w))
}

/// The uncompressed data of the zlib-compressed block at `offset` of `bytes`: a header of
/// `UInt64`s (the number of blocks n, the uncompressed block size, the uncompressed size of a
/// shorter last block or 0, the n compressed sizes), then the n compressed blocks. Every size is
/// checked against the bytes there, [`MAX_EXPANSION`] and [`MAX_BLOCK`] before the output is
/// allocated, and each block must expand to exactly its declared size.
fn zlib_block(bytes: &[u8], offset: usize) -> Result<Vec<u8>, String> {
    use rayon::prelude::*;
    let past = || "the block's header is past the end of the file".to_string();
    let word = |k: usize| -> Result<usize, String> {
        let at = k.checked_mul(8).and_then(|b| offset.checked_add(b));
        let w = at.and_then(|at| word_at(bytes, at)).ok_or_else(past)?;
        usize::try_from(w).map_err(|_| past())
    };
    let (count, size, last) = (word(0)?, word(1)?, word(2)?);
    // The n sizes must be in the file: n is at most the bytes there over 8.
    if count > bytes.len() / 8 {
        return Err(format!(
            "the block declares {count} compressed blocks, more than the file holds"
        ));
    }
    if count > 0 && (size == 0 || size > MAX_BLOCK || last > size) {
        return Err(format!(
            "bad zlib block sizes: {size} bytes per block, {last} in the last"
        ));
    }
    let mut start = offset + 8 * (3 + count);
    let mut blocks = Vec::with_capacity(count);
    let mut total = 0usize;
    for k in 0..count {
        let packed = word(3 + k)?;
        let end = start
            .checked_add(packed)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| {
                format!("compressed block {k} ({packed} bytes) is past the end of the file")
            })?;
        let unpacked = if k + 1 == count && last != 0 {
            last
        } else {
            size
        };
        if unpacked > packed.saturating_mul(MAX_EXPANSION) {
            return Err(format!(
                "compressed block {k} declares {unpacked} bytes from {packed}: more than zlib can expand"
            ));
        }
        blocks.push((&bytes[start..end], total..total + unpacked));
        total += unpacked;
        start = end;
    }
    let mut out = vec![0u8; total];
    let mut pieces: Vec<(&[u8], &mut [u8])> = Vec::with_capacity(count);
    let mut rest = out.as_mut_slice();
    for (packed, range) in &blocks {
        let (piece, tail) = std::mem::take(&mut rest).split_at_mut(range.len());
        pieces.push((packed, piece));
        rest = tail;
    }
    pieces
        .into_par_iter()
        .enumerate()
        .try_for_each(|(k, (packed, piece))| {
            let mut inflate = flate2::Decompress::new(true);
            let status = inflate.decompress(packed, piece, flate2::FlushDecompress::Finish);
            match status {
                Ok(flate2::Status::StreamEnd)
                    if inflate.total_out() == piece.len() as u64
                        && inflate.total_in() == packed.len() as u64 =>
                {
                    Ok(())
                }
                Ok(_) => Err(format!(
                "compressed block {k} is not one zlib stream of the {} bytes its header declares",
                piece.len()
            )),
                Err(e) => Err(format!("compressed block {k} is not zlib data: {e}")),
            }
        })?;
    Ok(out)
}

/// The little-endian values of type `ty` (`size` bytes each) in `data`.
fn decode(data: &[u8], ty: &str, size: usize) -> Result<Vec<f64>, String> {
    if data.len() % size != 0 {
        return Err(format!(
            "{} bytes is not a whole number of {ty}",
            data.len()
        ));
    }
    let word = |c: &[u8]| {
        let mut w = [0u8; 8];
        w.copy_from_slice(c);
        w
    };
    Ok(match ty {
        "Float64" => data
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(word(c)))
            .collect(),
        "Int64" => data
            .chunks_exact(8)
            .map(|c| i64::from_le_bytes(word(c)) as f64)
            .collect(),
        _ => data.iter().map(|&b| f64::from(b)).collect(),
    })
}

/// The value of the attribute `key` of the tag text `tag` (`key="value"`).
fn attribute<'a>(tag: &'a str, key: &str) -> Option<&'a str> {
    let mut rest = tag;
    while let Some(at) = rest.find(key) {
        let before = rest[..at].chars().next_back();
        let after = &rest[at + key.len()..];
        if before.is_some_and(char::is_whitespace) {
            if let Some(value) = after.strip_prefix("=\"") {
                return value.split('"').next();
            }
        }
        rest = after;
    }
    None
}

/// `text` with the XML entities [`crate::vtu`] writes in names replaced by their characters.
fn unescape(text: &str) -> String {
    (text
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\""))
    .replace("&apos;", "'")
    .replace("&amp;", "&")
}

/// The first position of `needle` in `haystack`.
fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// The bytes of the standard (padded) base64 text `text`, whitespace ignored; `None` if it is
/// not base64.
fn base64_decode(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let symbols: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    if symbols.len() % 4 != 0 {
        return None;
    }
    let mut out = Vec::with_capacity(symbols.len() / 4 * 3);
    let groups = symbols.len() / 4;
    for (g, chunk) in symbols.chunks(4).enumerate() {
        let pad = chunk.iter().rev().take_while(|&&c| c == b'=').count();
        if pad > 2 || (pad > 0 && g + 1 != groups) {
            return None;
        }
        let mut word = 0u32;
        for &c in &chunk[..4 - pad] {
            word = (word << 6) | value(c)?;
        }
        word <<= 6 * pad as u32;
        let bytes = [(word >> 16) as u8, (word >> 8) as u8, word as u8];
        out.extend_from_slice(&bytes[..3 - pad]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips() {
        assert_eq!(base64_decode("Zm9vYmE=").as_deref(), Some(&b"fooba"[..]));
        assert_eq!(base64_decode("Zm9v YmFy").as_deref(), Some(&b"foobar"[..]));
        assert_eq!(base64_decode("Zg=="), Some(b"f".to_vec()));
        for wrong in ["Zg=", "Z===", "Zg==Zm9v", "Zm9*"] {
            assert_eq!(base64_decode(wrong), None, "{wrong}");
        }
    }

    #[test]
    fn attributes_match_whole_keys() {
        let tag = "DataArray type=\"Float64\" Name=\"offset\" offset=\"16\"";
        assert_eq!(attribute(tag, "offset"), Some("16"));
        assert_eq!(attribute(tag, "Name"), Some("offset"));
        assert_eq!(attribute(tag, "format"), None);
    }

    #[test]
    fn blocks_are_bounded_by_the_bytes_there() {
        let mut bytes = 16u64.to_le_bytes().to_vec();
        bytes.extend_from_slice(&[0; 16]);
        assert_eq!(block(&bytes, 0).map(<[u8]>::len), Ok(16));
        assert!(block(&bytes[..20], 0).is_err());
        assert!(block(&bytes, usize::MAX - 3).is_err());
        let lying = u64::MAX.to_le_bytes();
        assert!(block(&lying, 0).is_err());
    }
}
