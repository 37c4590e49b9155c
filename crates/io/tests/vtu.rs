//! Writing VTK unstructured grids (`vtu`), on the Gmsh test meshes of `contactdd-core` (copied to
//! `tests/data`).

use std::path::{Path, PathBuf};

use contactdd_core::gmsh::read_msh;
use contactdd_core::mesh::Mesh;
use contactdd_io::vtu::{vtu_string, write_vtu, PointField};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

fn square() -> Mesh {
    read_msh(&data("square.msh")).expect("square.msh reads")
}

/// The text between `<tag ...>` and `</tag>` of the first DataArray named `name`.
fn data_array<'a>(xml: &'a str, name: &str) -> (&'a str, &'a str) {
    let start = xml
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no array {name}"));
    let open_start = xml[..start].rfind('<').expect("tag start");
    let open_end = start + xml[start..].find('>').expect("tag end");
    let close = open_end + xml[open_end..].find("</DataArray>").expect("closing tag");
    (&xml[open_start..=open_end], xml[open_end + 1..close].trim())
}

fn numbers(text: &str) -> Vec<f64> {
    text.split_whitespace()
        .map(|t| t.parse().expect("a number"))
        .collect()
}

fn decode_base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let mut out = Vec::new();
    for chunk in text.trim().as_bytes().chunks(4) {
        let digits: Vec<u32> = chunk
            .iter()
            .filter(|&&c| c != b'=')
            .map(|&c| u32::from(value(c)))
            .collect();
        let word = digits.iter().fold(0, |w, d| (w << 6) | d) << (6 * (4 - digits.len()));
        out.extend_from_slice(&word.to_be_bytes()[1..digits.len()]);
    }
    out
}

#[test]
fn vtu_of_p1_mesh() {
    let mesh = square();
    let n = mesh.num_nodes();
    let displacement: Vec<f64> = (0..2 * n).map(|i| i as f64 * 0.25).collect();
    let pressure: Vec<f64> = (0..n).map(|i| -(i as f64)).collect();
    let stress: Vec<f64> = (0..4 * n).map(|i| i as f64 * 1e-20).collect();
    let fields = [
        PointField {
            name: "pressure",
            components: 1,
            values: &pressure,
        },
        PointField {
            name: "stress <xx,yy,xy,zz>",
            components: 4,
            values: &stress,
        },
    ];
    let xml = vtu_string(&mesh, Some(&displacement), &fields).expect("valid fields");
    assert!(xml.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\""));
    assert!(xml.contains("<Piece NumberOfPoints=\"9\" NumberOfCells=\"8\">"));
    for tag in [
        "VTKFile",
        "UnstructuredGrid",
        "Piece",
        "PointData",
        "Points",
        "Cells",
    ] {
        assert_eq!(xml.matches(&format!("<{tag}")).count(), 1, "{tag}");
        assert_eq!(xml.matches(&format!("</{tag}>")).count(), 1, "{tag}");
    }
    assert_eq!(xml.matches("<DataArray").count(), 7);
    assert_eq!(xml.matches("</DataArray>").count(), 7);
    assert!(!xml.contains("format=\"binary\""));

    let (tag, text) = data_array(&xml, "displacement");
    assert!(tag.contains("NumberOfComponents=\"3\"") && tag.contains("Float64"));
    let values = numbers(text);
    assert_eq!(values.len(), 3 * n);
    for (node, xyz) in values.chunks(3).enumerate() {
        assert_eq!(
            xyz,
            [displacement[2 * node], displacement[2 * node + 1], 0.0]
        );
    }
    let (tag, text) = data_array(&xml, "pressure");
    assert!(tag.contains("NumberOfComponents=\"1\""));
    assert_eq!(numbers(text), pressure);
    let (tag, text) = data_array(&xml, "stress &lt;xx,yy,xy,zz&gt;");
    assert!(tag.contains("NumberOfComponents=\"4\""));
    assert_eq!(numbers(text), stress);

    let connectivity = numbers(data_array(&xml, "connectivity").1);
    let expected: Vec<f64> = mesh.cells().iter().map(|&v| v as f64).collect();
    assert_eq!(connectivity, expected);
    assert_eq!(
        numbers(data_array(&xml, "offsets").1),
        [3., 6., 9., 12., 15., 18., 21., 24.]
    );
    assert_eq!(numbers(data_array(&xml, "types").1), [5.0; 8]);

    // The points follow the PointData arrays.
    let points_start = xml.find("<Points>").expect("Points");
    let points_end = xml.find("</Points>").expect("Points end");
    let points_xml = &xml[points_start..points_end];
    let text_start = points_xml.find('>').expect("tag") + 1;
    let text_start = text_start + points_xml[text_start..].find('>').expect("tag") + 1;
    let text_end = points_xml.find("</DataArray>").expect("end");
    let points = numbers(&points_xml[text_start..text_end]);
    let expected: Vec<f64> = mesh
        .nodes()
        .iter()
        .flat_map(|p| [p[0], p[1], 0.0])
        .collect();
    assert_eq!(points, expected);
}

#[test]
fn vtu_of_p2_mesh_uses_quadratic_triangles() {
    let mesh = read_msh(&data("square_p2.msh")).expect("square_p2.msh");
    let xml = vtu_string(&mesh, None, &[]).expect("no fields");
    assert!(xml.contains("<Piece NumberOfPoints=\"25\" NumberOfCells=\"8\">"));
    assert!(xml.contains("<PointData>\n      </PointData>"));
    assert_eq!(numbers(data_array(&xml, "types").1), [22.0; 8]);
    assert_eq!(numbers(data_array(&xml, "offsets").1).last(), Some(&48.0));
    assert_eq!(numbers(data_array(&xml, "connectivity").1).len(), 48);
}

#[test]
fn non_finite_values_are_written_as_binary() {
    let mesh = square();
    let n = mesh.num_nodes();
    let mut gap = vec![1.5; n];
    gap[0] = f64::NAN;
    gap[1] = f64::INFINITY;
    gap[2] = f64::NEG_INFINITY;
    let fields = [PointField {
        name: "gap",
        components: 1,
        values: &gap,
    }];
    let xml = vtu_string(&mesh, None, &fields).expect("valid");
    let (tag, text) = data_array(&xml, "gap");
    assert!(tag.contains("format=\"binary\""));
    assert!(xml.contains("header_type=\"UInt64\""));
    let bytes = decode_base64(text);
    assert_eq!(bytes.len(), 8 + 8 * n);
    let word = |k: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&bytes[8 * k..8 * k + 8]);
        b
    };
    assert_eq!(u64::from_le_bytes(word(0)), 8 * n as u64);
    let values: Vec<f64> = (1..=n).map(|k| f64::from_le_bytes(word(k))).collect();
    assert!(values[0].is_nan());
    assert_eq!(values[1..], gap[1..]);
}

#[test]
fn vtu_rejects_wrong_lengths() {
    let mesh = square();
    let short = vec![0.0; 2 * mesh.num_nodes() - 1];
    let err = vtu_string(&mesh, Some(&short), &[]).expect_err("short displacement");
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    let values = vec![0.0; mesh.num_nodes()];
    let bad = [PointField {
        name: "v",
        components: 2,
        values: &values,
    }];
    assert!(vtu_string(&mesh, None, &bad).is_err());
    let zero = [PointField {
        name: "v",
        components: 0,
        values: &[],
    }];
    assert!(vtu_string(&mesh, None, &zero).is_err());
}

#[test]
fn write_vtu_writes_the_file_atomically() {
    let mesh = square();
    let dir = std::env::temp_dir().join(format!("contactdd-vtu-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("square.vtu");
    let displacement = vec![0.0; 2 * mesh.num_nodes()];
    write_vtu(&path, &mesh, Some(&displacement), &[]).expect("written");
    let written = std::fs::read_to_string(&path).expect("read back");
    assert_eq!(
        written,
        vtu_string(&mesh, Some(&displacement), &[]).expect("valid")
    );
    // Nothing else is left in the folder, and a bad call leaves the old file alone.
    assert!(write_vtu(&path, &mesh, Some(&displacement[1..]), &[]).is_err());
    let entries: Vec<_> = std::fs::read_dir(&dir).expect("list").collect();
    assert_eq!(entries.len(), 1);
    assert_eq!(std::fs::read_to_string(&path).expect("read back"), written);
    // A missing folder is an I/O error.
    assert!(write_vtu(&dir.join("missing/x.vtu"), &mesh, None, &[]).is_err());
    std::fs::remove_dir_all(&dir).expect("clean up");
}
