//! The zlib VTU encoding against the ASCII one and against the arrays given: it reads back (by
//! `contactdd_io::vtu_read`) to the same values bit for bit; its blocks, decoded by hand with a
//! second zlib decoder, follow VTK's `vtkZLibDataCompressor` layout; a damaged or lying file is
//! an error, never a panic or an allocation larger than the file allows.

use std::io::Read as _;

use contactdd_core::mesh::{Mesh, Order};
use contactdd_io::vtu::{vtu_bytes, Field, VtuData, VtuFormat, ZLIB_BLOCK};
use contactdd_io::vtu_read::{parse_vtu, Section, VtuFile};

/// A structured grid of `k` × `k` squares cut into two triangles each.
fn grid(k: usize) -> Mesh {
    let nodes = (0..=k)
        .flat_map(|j| (0..=k).map(move |i| [i as f64 / k as f64, (j as f64 / k as f64).sqrt()]))
        .collect();
    let at = |i: usize, j: usize| j * (k + 1) + i;
    let cells = (0..k)
        .flat_map(|j| (0..k).map(move |i| (i, j)))
        .flat_map(|(i, j)| {
            [
                at(i, j),
                at(i + 1, j),
                at(i + 1, j + 1),
                at(i, j),
                at(i + 1, j + 1),
                at(i, j + 1),
            ]
        })
        .collect();
    Mesh::new(
        nodes,
        Order::P1,
        cells,
        Default::default(),
        Default::default(),
    )
    .expect("grid")
}

/// Values of every kind, non-finite ones included.
fn awkward(k: usize) -> f64 {
    const SPECIAL: [f64; 6] = [0.0, -0.0, 5e-324, f64::NAN, f64::INFINITY, f64::MAX];
    SPECIAL
        .get(k % 11)
        .copied()
        .unwrap_or((k as f64 * 0.1).sin() * 1e3)
}

/// The tensor of the files of [`encoded`].
fn tensor(n: usize) -> Vec<f64> {
    (0..9 * n).map(awkward).collect()
}

/// `mesh` with a displacement, a 9-component and a cell field, in `format`.
fn encoded(mesh: &Mesh, format: VtuFormat) -> Vec<u8> {
    let n = mesh.num_nodes();
    let u: Vec<f64> = (0..2 * n).map(|k| (k as f64 * 0.37).cos()).collect();
    let tensor = tensor(n);
    let cell: Vec<f64> = (0..mesh.num_cells()).map(|k| k as f64 / 3.0).collect();
    let points = [Field {
        name: "stress",
        components: 9,
        values: &tensor,
    }];
    let cells = [Field {
        name: "element_von_mises",
        components: 1,
        values: &cell,
    }];
    let data = VtuData {
        displacement: Some(&u),
        points: &points,
        cells: &cells,
    };
    vtu_bytes(mesh, data, format).expect("valid arrays")
}

fn bits(file: &VtuFile) -> Vec<(Section, String, usize, Vec<u64>)> {
    (file.arrays.iter())
        .map(|a| {
            let bits = a.values.iter().map(|v| v.to_bits()).collect();
            (a.section, a.name.clone(), a.components, bits)
        })
        .collect()
}

/// Where the appended data starts: after the underscore that follows `<AppendedData`.
fn appended_start(bytes: &[u8]) -> usize {
    let tag = (bytes.windows(13))
        .position(|w| w == b"<AppendedData")
        .expect("appended data");
    tag + bytes[tag..]
        .iter()
        .position(|&b| b == b'_')
        .expect("underscore")
        + 1
}

fn word(bytes: &[u8], at: usize) -> u64 {
    let mut w = [0u8; 8];
    w.copy_from_slice(&bytes[at..at + 8]);
    u64::from_le_bytes(w)
}

/// The offset of the array `name` in the XML of `bytes`.
fn offset_of(bytes: &[u8], name: &str) -> usize {
    let text = String::from_utf8_lossy(bytes);
    let at = text.find(&format!("Name=\"{name}\"")).expect("array");
    let rest = &text[at..];
    let value = &rest[rest.find("offset=\"").expect("offset") + 8..];
    value[..value.find('"').expect("quote")]
        .parse()
        .expect("a number")
}

#[test]
fn zlib_reads_back_to_the_ascii_and_binary_values() {
    for k in [1, 3, 70] {
        let mesh = grid(k);
        let [ascii, binary, zlib] = [VtuFormat::Ascii, VtuFormat::Binary, VtuFormat::Zlib]
            .map(|format| parse_vtu(&encoded(&mesh, format)).expect("reads back"));
        assert_eq!(bits(&zlib), bits(&ascii), "k = {k}");
        assert_eq!(bits(&zlib), bits(&binary), "k = {k}");
        let stress = zlib.array(Section::PointData, "stress").expect("stress");
        let expected: Vec<u64> = tensor(mesh.num_nodes())
            .iter()
            .map(|v| v.to_bits())
            .collect();
        let read: Vec<u64> = stress.values.iter().map(|v| v.to_bits()).collect();
        assert_eq!(read, expected);
    }
}

#[test]
fn zlib_blocks_follow_the_vtk_layout() {
    // 71 × 71 nodes: the tensor is 72 bytes per node, several blocks and a shorter last one.
    let mesh = grid(70);
    let n = mesh.num_nodes();
    let bytes = encoded(&mesh, VtuFormat::Zlib);
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.contains("header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">"));
    assert!(text.contains("<AppendedData encoding=\"raw\">"));
    assert!(!text.contains("format=\"ascii\"") && !text.contains("format=\"binary\""));
    let start = appended_start(&bytes);
    let at = start + offset_of(&bytes, "stress");
    let len = 72 * n;
    let count = word(&bytes, at) as usize;
    assert_eq!(count, len.div_ceil(ZLIB_BLOCK));
    assert!(count > 2);
    assert_eq!(word(&bytes, at + 8) as usize, ZLIB_BLOCK);
    assert_eq!(word(&bytes, at + 16) as usize, len % ZLIB_BLOCK);
    // Each block alone, through flate2's streaming reader (not the one vtu_read uses).
    let mut data = Vec::new();
    let mut block = at + 8 * (3 + count);
    for b in 0..count {
        let packed = word(&bytes, at + 8 * (3 + b)) as usize;
        let mut part = Vec::new();
        flate2::read::ZlibDecoder::new(&bytes[block..block + packed])
            .read_to_end(&mut part)
            .expect("a zlib stream");
        let full = b + 1 < count || len % ZLIB_BLOCK == 0;
        assert_eq!(part.len(), if full { ZLIB_BLOCK } else { len % ZLIB_BLOCK });
        data.extend_from_slice(&part);
        block += packed;
    }
    let expected: Vec<u8> = tensor(n).iter().flat_map(|v| v.to_le_bytes()).collect();
    assert_eq!(data, expected);
    // The arrays are back to back: the next one starts where the stress's blocks end.
    let next = ["sigma_xx", "element_von_mises"]
        .iter()
        .filter(|name| text.contains(&format!("Name=\"{name}\"")))
        .map(|name| start + offset_of(&bytes, name))
        .min();
    let points = text.find("<Points>").expect("points");
    let points_offset = text[points..].find("offset=\"").expect("offset") + points + 8;
    let points_offset: usize = text[points_offset..]
        .split('"')
        .next()
        .and_then(|o| o.parse().ok())
        .expect("points offset");
    assert_eq!(next.unwrap_or(start + points_offset), block);
}

#[test]
fn zlib_is_under_a_third_of_ascii_on_smooth_fields() {
    // Smooth fields, as a solve gives (no special values): the compressed file is small.
    let mesh = grid(70);
    let n = mesh.num_nodes();
    let u: Vec<f64> = (0..2 * n).map(|k| (k as f64 * 1e-3).sin()).collect();
    let data = VtuData {
        displacement: Some(&u),
        points: &[],
        cells: &[],
    };
    let ascii = vtu_bytes(&mesh, data, VtuFormat::Ascii).expect("ascii");
    let zlib = vtu_bytes(&mesh, data, VtuFormat::Zlib).expect("zlib");
    assert!(
        3 * zlib.len() < ascii.len(),
        "{} vs {}",
        zlib.len(),
        ascii.len()
    );
}

/// `bytes` with the `UInt64` at `at` replaced by `value`.
fn with_word(bytes: &[u8], at: usize, value: u64) -> Vec<u8> {
    let mut out = bytes.to_vec();
    out[at..at + 8].copy_from_slice(&value.to_le_bytes());
    out
}

#[test]
fn damaged_zlib_files_are_errors_not_panics() {
    let mesh = grid(12);
    let bytes = encoded(&mesh, VtuFormat::Zlib);
    let start = appended_start(&bytes);
    // Cut anywhere in the appended data: the blocks past the cut are refused.
    for cut in (start..bytes.len() - 30).step_by(5) {
        assert!(parse_vtu(&bytes[..cut]).is_err(), "cut at {cut}");
    }
    // Cut or flipped anywhere: an error or arrays, never a panic.
    for at in (0..bytes.len()).step_by(3) {
        let _ = parse_vtu(&bytes[..at]);
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x5A;
        let _ = parse_vtu(&flipped);
    }
    // The displacement's header (offset 0, one block): count, size, last, the compressed size.
    let n = mesh.num_nodes();
    assert_eq!(word(&bytes, start), 1);
    assert_eq!(word(&bytes, start + 16) as usize, 24 * n);
    let packed = word(&bytes, start + 24);
    let lies = [
        (0, u64::MAX, "more than the file holds"),
        (0, 1 << 40, "more than the file holds"),
        (8, 0, "bad zlib block sizes"),
        (8, 1 << 40, "bad zlib block sizes"),
        (16, ZLIB_BLOCK as u64 + 1, "bad zlib block sizes"),
        (16, 24 * n as u64 + 8, "one zlib stream"),
        (16, 24 * n as u64 - 8, "one zlib stream"),
        (24, 3, "more than zlib can expand"),
        (24, u64::MAX, "past the end"),
        (24, packed - 1, "one zlib stream"),
        (24, (bytes.len() - start) as u64, "past the end"),
    ];
    for (at, value, message) in lies {
        let err = parse_vtu(&with_word(&bytes, start + at, value)).expect_err(message);
        let text = err.to_string();
        assert!(
            text.contains("displacement") && text.contains(message),
            "{at} {value}: {text}"
        );
    }
    // Another compressor, or 32-bit headers, are named.
    let text = String::from_utf8_lossy(&bytes);
    let lzma = text.replace("vtkZLibDataCompressor", "vtkLZMADataCompressor");
    let err = parse_vtu(lzma.as_bytes()).expect_err("lzma");
    assert!(err.to_string().contains("vtkLZMADataCompressor"), "{err}");
    let short = bytes_replace(&bytes, b"header_type=\"UInt64\"", b"header_type=\"UInt32\"");
    let err = parse_vtu(&short).expect_err("UInt32 headers");
    assert!(err.to_string().contains("UInt64"), "{err}");
}

fn bytes_replace(bytes: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    let at = (bytes.windows(from.len()))
        .position(|w| w == from)
        .expect("present");
    [&bytes[..at], to, &bytes[at + from.len()..]].concat()
}
