//! Writing VTK unstructured grids (`vtu`), on the Gmsh test meshes of `contactdd-core` (copied to
//! `tests/data`).

use std::path::{Path, PathBuf};

use contactdd_core::gmsh::read_msh;
use contactdd_core::mesh::Mesh;
use contactdd_io::vtu::{vtu_string, write_vtu, Field, VtuData};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

/// Point data only: the writer's arrays without cell data.
fn arrays<'a>(displacement: Option<&'a [f64]>, points: &'a [Field<'a>]) -> VtuData<'a> {
    VtuData {
        displacement,
        points,
        cells: &[],
    }
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
        Field {
            name: "pressure",
            components: 1,
            values: &pressure,
        },
        Field {
            name: "stress <xx,yy,xy,zz>",
            components: 4,
            values: &stress,
        },
    ];
    let xml = vtu_string(&mesh, arrays(Some(&displacement), &fields)).expect("valid fields");
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
    let xml = vtu_string(&mesh, arrays(None, &[])).expect("no fields");
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
    let fields = [Field {
        name: "gap",
        components: 1,
        values: &gap,
    }];
    let xml = vtu_string(&mesh, arrays(None, &fields)).expect("valid");
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
    let err = vtu_string(&mesh, arrays(Some(&short), &[])).expect_err("short displacement");
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    let values = vec![0.0; mesh.num_nodes()];
    let bad = [Field {
        name: "v",
        components: 2,
        values: &values,
    }];
    assert!(vtu_string(&mesh, arrays(None, &bad)).is_err());
    let zero = [Field {
        name: "v",
        components: 0,
        values: &[],
    }];
    assert!(vtu_string(&mesh, arrays(None, &zero)).is_err());
}

#[test]
fn write_vtu_writes_the_file_atomically() {
    let mesh = square();
    let dir = std::env::temp_dir().join(format!("contactdd-vtu-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("square.vtu");
    let displacement = vec![0.0; 2 * mesh.num_nodes()];
    write_vtu(&path, &mesh, arrays(Some(&displacement), &[])).expect("written");
    let written = std::fs::read_to_string(&path).expect("read back");
    assert_eq!(
        written,
        vtu_string(&mesh, arrays(Some(&displacement), &[])).expect("valid")
    );
    // Nothing else is left in the folder, and a bad call leaves the old file alone.
    assert!(write_vtu(&path, &mesh, arrays(Some(&displacement[1..]), &[])).is_err());
    let entries: Vec<_> = std::fs::read_dir(&dir).expect("list").collect();
    assert_eq!(entries.len(), 1);
    assert_eq!(std::fs::read_to_string(&path).expect("read back"), written);
    // A missing folder is an I/O error.
    assert!(write_vtu(&dir.join("missing/x.vtu"), &mesh, arrays(None, &[])).is_err());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// The values of the array `name`, ASCII or base64 binary.
fn array_values(xml: &str, name: &str) -> Vec<f64> {
    let (tag, text) = data_array(xml, name);
    if !tag.contains("format=\"binary\"") {
        return numbers(text);
    }
    let bytes = decode_base64(text);
    bytes[8..]
        .chunks(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect()
}

/// A one-body model: the unit square, 4 × 4 cells of `order`, steel, plane strain, held on the
/// left (x) and the bottom (y).
fn one_body(order: &str) -> contactdd_ddm::Model {
    let text = format!(
        r#"
        plane = "strain"
        [materials.steel]
        young = 2.1e5
        poisson = 0.3
        [[bodies]]
        name = "block"
        material = "steel"
        mesh = {{ kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0], nx = 4, ny = 4, order = "{order}" }}
        supports = [{{ boundary = "left", component = "x" }}, {{ boundary = "bottom", component = "y" }}]
        "#
    );
    contactdd_io::load_str(&text, "block.toml", Path::new("."))
        .expect("valid problem")
        .model
}

/// The body's result fields for the displacement `u(x, y)`, as the solvers build them.
fn fields_of(
    model: &contactdd_ddm::Model,
    u: impl Fn(f64, f64) -> [f64; 2],
) -> contactdd_ddm::solution::BodyResult {
    let body = &model.bodies[0];
    let displacement: Vec<f64> = body
        .mesh
        .nodes()
        .iter()
        .flat_map(|p| u(p[0], p[1]))
        .collect();
    let st = contactdd_core::post::stresses(&body.mesh, &body.material, body.plane, &displacement);
    contactdd_ddm::solution::BodyResult {
        name: body.name.clone(),
        mesh: body.mesh.clone(),
        displacement,
        stress: st.nodal,
        von_mises: st.von_mises,
        contact_pressure: vec![0.0; body.mesh.num_nodes()],
        node_ids: Vec::new(),
    }
}

/// Writes the `.vtu` files of a solution into `dir`, as a set (with an empty summary).
fn write_solution_vtus(
    dir: &Path,
    model: &contactdd_ddm::Model,
    bodies: &[contactdd_ddm::solution::BodyResult],
    contact: &[contactdd_ddm::solution::PairResult],
) {
    let mut set = contactdd_io::result_set::ResultSet::begin(dir).expect("a folder");
    let ascii = contactdd_io::vtu::VtuFormat::Ascii;
    contactdd_io::output::write_solution_vtus_as(&mut set, model, bodies, contact, "", ascii)
        .expect("written");
    set.finish(serde_json::json!({})).expect("swapped in");
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-vtu-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Eigenvalues of a symmetric 3×3 matrix by cyclic Jacobi rotations, descending: a method
/// independent of the writer's closed form.
fn jacobi_eigenvalues(mut a: [[f64; 3]; 3]) -> [f64; 3] {
    for _ in 0..50 {
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = 0.5 * (2.0 * a[p][q]).atan2(a[q][q] - a[p][p]);
            let (s, c) = theta.sin_cos();
            let mut r = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
            for (i, row) in r.iter_mut().enumerate() {
                row[i] = 1.0;
            }
            r[p][p] = c;
            r[q][q] = c;
            r[p][q] = s;
            r[q][p] = -s;
            // a ← rᵀ a r
            let mut t = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    t[i][j] = (0..3).map(|k| a[i][k] * r[k][j]).sum();
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    a[i][j] = (0..3).map(|k| r[k][i] * t[k][j]).sum();
                }
            }
        }
    }
    let mut e = [a[0][0], a[1][1], a[2][2]];
    e.sort_by(|x, y| y.total_cmp(x));
    e
}

#[test]
fn principal_stresses_are_the_eigenvalues_of_the_written_tensor() {
    let model = one_body("p2");
    // A quadratic field: the stress differs from node to node, with shear.
    let body = fields_of(&model, |x, y| {
        [1e-3 * (x * x + 0.5 * y), 1e-3 * (-x * y + 0.3 * y * y)]
    });
    let dir = temp("principal");
    write_solution_vtus(&dir, &model, &[body], &[]);
    let xml = std::fs::read_to_string(dir.join("block.vtu")).expect("read back");
    let (tag, _) = data_array(&xml, "stress");
    assert!(tag.contains("NumberOfComponents=\"9\""));
    let tensors = array_values(&xml, "stress");
    let p: Vec<Vec<f64>> = (1..=3)
        .map(|k| array_values(&xml, &format!("principal_stress_{k}")))
        .collect();
    let n = model.bodies[0].mesh.num_nodes();
    assert_eq!(tensors.len(), 9 * n);
    for (node, t) in tensors.chunks(9).enumerate() {
        let m = [[t[0], t[1], t[2]], [t[3], t[4], t[5]], [t[6], t[7], t[8]]];
        assert_eq!(t[1], t[3], "symmetric");
        let scale = t.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        for (k, e) in jacobi_eigenvalues(m).iter().enumerate() {
            assert!(
                (p[k][node] - e).abs() <= 1e-12 * scale,
                "node {node}, σ{}",
                k + 1
            );
        }
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn element_von_mises_of_a_uniform_stress_field() {
    let model = one_body("p1");
    // Uniform strain ε_xx = 1e-3, ε_yy = -2e-4, γ_xy = 6e-4 (ε_xy = 3e-4).
    let (exx, eyy, exy) = (1e-3, -2e-4, 3e-4);
    let body = fields_of(&model, |x, y| [exx * x + exy * y, exy * x + eyy * y]);
    // Hooke's law in plane strain, by hand.
    let (e, nu) = (2.1e5, 0.3);
    let (lambda, mu) = (
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        e / (2.0 * (1.0 + nu)),
    );
    let (sxx, syy) = (
        lambda * (exx + eyy) + 2.0 * mu * exx,
        lambda * (exx + eyy) + 2.0 * mu * eyy,
    );
    let (sxy, szz) = (2.0 * mu * exy, lambda * (exx + eyy));
    let expected = (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2))
        + 3.0 * sxy * sxy)
        .sqrt();
    let dir = temp("uniform");
    write_solution_vtus(&dir, &model, &[body], &[]);
    let xml = std::fs::read_to_string(dir.join("block.vtu")).expect("read back");
    let cells_xml = &xml[xml.find("<CellData>").expect("cell data")..];
    let von_mises = array_values(cells_xml, "element_von_mises");
    assert_eq!(von_mises.len(), model.bodies[0].mesh.num_cells());
    for v in von_mises {
        assert!(
            (v - expected).abs() <= 1e-10 * expected,
            "{v} vs {expected}"
        );
    }
    let tensor = array_values(&xml, "stress");
    for t in tensor.chunks(9) {
        let want = [sxx, sxy, 0.0, sxy, syy, 0.0, 0.0, 0.0, szz];
        for (a, b) in t.iter().zip(want) {
            assert!((a - b).abs() <= 1e-10 * expected, "{t:?}");
        }
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn contact_point_data_on_the_notch() {
    use contactdd_ddm::{prepare, solve, Hooks, Settings};
    let model = contactdd_ddm::benchmark::Notch::default()
        .model()
        .expect("notch");
    let prepared = prepare(&model).expect("prepared");
    let sol = solve(&model, &prepared, &Settings::default(), Hooks::default()).expect("solved");
    let dir = temp("notch");
    write_solution_vtus(&dir, &model, &sol.bodies, &sol.contact);
    let pair = &sol.contact[0];
    for (b, body) in sol.bodies.iter().enumerate() {
        let xml = std::fs::read_to_string(dir.join(format!("{}.vtu", body.name))).expect("read");
        let gap = array_values(&xml, "gap");
        let status = array_values(&xml, "contact_status");
        let pressure = array_values(&xml, "contact_pressure");
        let sigma_n = array_values(&xml, "sigma_n");
        assert_eq!(sigma_n, body.contact_pressure);
        let mut contact_node = vec![false; body.mesh.num_nodes()];
        for i in (0..pair.side.len()).filter(|&i| pair.side[i] == b) {
            let v = pair.node[i];
            contact_node[v] = true;
            assert_eq!(gap[v], pair.gap[i]);
            assert_eq!(status[v], if pair.closed[i] { 1.0 } else { 0.0 });
            // The notch's pair is own-side (matching meshes): p = −σ_n, positive where closed.
            assert_eq!(pressure[v], (-pair.pressure[i]).max(0.0), "node {v}");
            assert_eq!(pressure[v] > 0.0, pair.closed[i], "node {v}");
        }
        assert!(contact_node.iter().any(|&c| c));
        for v in (0..gap.len()).filter(|&v| !contact_node[v]) {
            assert!(gap[v].is_nan() && status[v].is_nan(), "node {v}");
            assert_eq!(pressure[v], 0.0, "node {v}");
        }
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}
