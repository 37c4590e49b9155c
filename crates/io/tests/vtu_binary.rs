//! The binary VTU encoding against the ASCII one and against the arrays given: both read back
//! (by `contactdd_io::vtu_read`) to the same values bit for bit; a damaged binary file is an
//! error, never a panic; the `[output] vtu` key and its errors.

use std::path::{Path, PathBuf};

use contactdd_core::gmsh::read_msh;
use contactdd_core::mesh::Mesh;
use contactdd_io::vtu::{vtu_bytes, Field, VtuData, VtuFormat};
use contactdd_io::vtu_read::{parse_vtu, Section, VtuFile};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

/// Values of every kind: signed zeros, subnormals, extremes and non-finite values.
fn awkward(k: usize) -> f64 {
    const SPECIAL: [f64; 8] = [
        0.0,
        -0.0,
        5e-324,
        f64::MAX,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -1.234_567_890_123_456_7e-7,
    ];
    SPECIAL
        .get(k % 13)
        .copied()
        .unwrap_or((k as f64).sin() * 1e3)
}

/// Both encodings of `mesh` with a displacement, a 9-component, a scalar (with NaN) and a cell
/// field; the arrays given.
fn both(mesh: &Mesh) -> [(VtuFile, Vec<u8>); 2] {
    let n = mesh.num_nodes();
    let u: Vec<f64> = (0..2 * n).map(|k| (k as f64 * 0.37).cos()).collect();
    let tensor: Vec<f64> = (0..9 * n).map(awkward).collect();
    let scalar: Vec<f64> = (0..n).map(|k| awkward(k + 4)).collect();
    let cell: Vec<f64> = (0..mesh.num_cells()).map(|k| k as f64 / 3.0).collect();
    let points = [
        Field {
            name: "stress",
            components: 9,
            values: &tensor,
        },
        Field {
            name: "gap <&\"'>",
            components: 1,
            values: &scalar,
        },
    ];
    let cells = [Field {
        name: "element_von_mises",
        components: 1,
        values: &cell,
    }];
    let arrays = VtuData {
        displacement: Some(&u),
        points: &points,
        cells: &cells,
    };
    [VtuFormat::Ascii, VtuFormat::Binary].map(|format| {
        let bytes = vtu_bytes(mesh, arrays, format).expect("valid arrays");
        (parse_vtu(&bytes).expect("reads back"), bytes)
    })
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

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn both_encodings_read_back_to_the_arrays_given() {
    for (file, order_nodes) in [("square.msh", 3), ("square_p2.msh", 6)] {
        let mesh = read_msh(&data(file)).expect("test mesh");
        let n = mesh.num_nodes();
        let [(ascii, _), (binary, bytes)] = both(&mesh);
        assert_eq!(ascii.arrays.len(), binary.arrays.len());
        for (a, b) in ascii.arrays.iter().zip(&binary.arrays) {
            assert_eq!(
                (a.section, &a.name, a.components),
                (b.section, &b.name, b.components)
            );
            assert_eq!(bits(&a.values), bits(&b.values), "{}", a.name);
        }
        // Against the arrays given (padded displacement, the tensor's non-finite values).
        let u = binary.array(Section::PointData, "displacement").expect("u");
        assert_eq!(u.components, 3);
        assert_eq!(u.values[2], 0.0);
        assert_eq!(u.values[3], (2.0 * 0.37f64).cos());
        let tensor = binary.array(Section::PointData, "stress").expect("tensor");
        let expected: Vec<f64> = (0..9 * n).map(awkward).collect();
        assert_eq!(bits(&tensor.values), bits(&expected));
        assert!(binary.array(Section::PointData, "gap <&\"'>").is_some());
        let conn = binary.array(Section::Cells, "connectivity").expect("cells");
        let given: Vec<f64> = mesh.cells().iter().map(|&v| v as f64).collect();
        assert_eq!(conn.values, given);
        let offsets = binary.array(Section::Cells, "offsets").expect("offsets");
        assert_eq!(
            offsets.values.last(),
            Some(&((order_nodes * mesh.num_cells()) as f64))
        );
        let types = binary.array(Section::Cells, "types").expect("types");
        let vtk = if order_nodes == 3 { 5.0 } else { 22.0 };
        assert!(types.values.iter().all(|&t| t == vtk));
        let points = binary.array(Section::Points, "").expect("points");
        assert_eq!(
            points.values[3..5],
            [mesh.nodes()[1][0], mesh.nodes()[1][1]]
        );
        // The layout, decoded by hand: the first block (offset 0) is the displacement, its
        // UInt64 byte count then the values.
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("<AppendedData encoding=\"raw\">"));
        assert!(text.contains(
            "Name=\"displacement\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>"
        ));
        let start = appended_start(&bytes);
        let word = |k: usize| {
            let mut w = [0u8; 8];
            w.copy_from_slice(&bytes[start + 8 * k..start + 8 * k + 8]);
            w
        };
        assert_eq!(u64::from_le_bytes(word(0)), 24 * n as u64);
        assert_eq!(f64::from_le_bytes(word(4)), u.values[3]);
        assert!(bytes.ends_with(b"\n  </AppendedData>\n</VTKFile>\n"));
    }
}

#[test]
fn binary_is_smaller_than_ascii() {
    let mesh = read_msh(&data("square.msh")).expect("test mesh");
    let [(_, ascii), (_, binary)] = both(&mesh);
    assert!(
        binary.len() < ascii.len(),
        "{} vs {}",
        binary.len(),
        ascii.len()
    );
}

#[test]
fn damaged_binary_files_are_errors_not_panics() {
    let mesh = read_msh(&data("square_p2.msh")).expect("test mesh");
    let [_, (_, bytes)] = both(&mesh);
    // Cut anywhere in the appended data: every block past the cut is refused.
    let start = appended_start(&bytes);
    for cut in (start..bytes.len() - 30).step_by(7) {
        assert!(parse_vtu(&bytes[..cut]).is_err(), "cut at {cut}");
    }
    // Cut or flipped anywhere: an error or arrays, never a panic.
    for at in (0..bytes.len()).step_by(11) {
        let _ = parse_vtu(&bytes[..at]);
        let mut flipped = bytes.clone();
        flipped[at] ^= 0xA5;
        let _ = parse_vtu(&flipped);
    }
    // A byte count that lies (huge, or one more than there is) is refused before allocating.
    for lie in [u64::MAX, 1 << 62, (bytes.len() - start) as u64 - 7] {
        let mut lying = bytes.clone();
        lying[start..start + 8].copy_from_slice(&lie.to_le_bytes());
        let err = parse_vtu(&lying).expect_err("a lying count");
        assert!(err.to_string().contains("displacement"), "{err}");
    }
    // An offset past the end.
    let text = String::from_utf8_lossy(&bytes).replace("offset=\"0\"", "offset=\"99999999999\"");
    let err = parse_vtu(text.as_bytes()).expect_err("offset past the end");
    assert!(err.to_string().contains("past the end"), "{err}");
}

#[test]
fn the_output_table_chooses_the_encoding() {
    let notch = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml"),
    )
    .expect("examples/notch.toml");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let loaded = contactdd_io::load_str(&notch, "notch.toml", &dir).expect("notch");
    assert_eq!(loaded.problem.output.vtu, None);
    let ascii = format!("{notch}\n[output]\nvtu = \"ascii\"\n");
    let loaded = contactdd_io::load_str(&ascii, "notch.toml", &dir).expect("notch, ascii");
    assert_eq!(loaded.problem.output.vtu, Some(VtuFormat::Ascii));
    let zlib = format!("{notch}\n[output]\nvtu = \"zlib\"\n");
    let loaded = contactdd_io::load_str(&zlib, "notch.toml", &dir).expect("notch, zlib");
    assert_eq!(loaded.problem.output.vtu, Some(VtuFormat::Zlib));
    let wrong = format!("{notch}\n[output]\nvtu = \"lzma\"\n");
    let err = contactdd_io::load_str(&wrong, "notch.toml", &dir).expect_err("unknown format");
    let text = err.to_string();
    assert!(
        text.contains("lzma")
            && text.contains("ascii")
            && text.contains("binary")
            && text.contains("zlib"),
        "{text}"
    );
    let unknown = format!("{notch}\n[output]\nvtus = \"ascii\"\n");
    assert!(contactdd_io::load_str(&unknown, "notch.toml", &dir).is_err());
    assert_eq!("binary".parse(), Ok(VtuFormat::Binary));
    assert_eq!("zlib".parse(), Ok(VtuFormat::Zlib));
    let err = "Binary".parse::<VtuFormat>().expect_err("case matters");
    assert_eq!(
        err.to_string(),
        "unknown VTU format 'Binary': expected 'zlib', 'binary' or 'ascii'"
    );
}
