//! The `.vtu` files of tetrahedral bodies (`contactdd_io::solid_vtu`) and the planar files
//! beside them.

use std::path::{Path, PathBuf};

use contactdd_core::gmsh::read_msh;
use contactdd_core::mesh::Mesh;
use contactdd_core::solid::element::TET_EDGES;
use contactdd_core::solid::{BoxMesh, SolidMesh, TetOrder};
use contactdd_io::solid_vtu::{
    solid_grid, solid_vtu_bytes, solid_vtu_pieces_bytes, stress_tensors, VTK_QUADRATIC_TET_NODES,
};
use contactdd_io::vtu::{
    grid_pieces_bytes, vtu_bytes, vtu_pieces_bytes, Field, Grid, VtuData, VtuFormat,
};
use contactdd_io::vtu_read::{parse_vtu, parse_vtu_pieces, Section, VtuFile};

const FORMATS: [VtuFormat; 3] = [VtuFormat::Ascii, VtuFormat::Binary, VtuFormat::Zlib];

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

/// FNV-1a, 64 bits: a fingerprint of a file's bytes.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The planar arrays of `mesh`: a displacement, a 2-component, a 9-component and a scalar nodal
/// field (the scalar holding a NaN, written as inline base64 in ASCII), and a cell field.
fn planar_bytes(pieces: &[&Mesh], format: VtuFormat) -> Vec<u8> {
    let owned: Vec<[Vec<f64>; 5]> = pieces
        .iter()
        .map(|mesh| {
            let n = mesh.num_nodes();
            let wave = |len: usize, f: f64| (0..len).map(|k| (k as f64 * f).sin()).collect();
            let mut scalar: Vec<f64> = wave(n, 0.7);
            scalar[n / 2] = f64::NAN;
            [
                wave(2 * n, 0.37),
                wave(2 * n, 0.11),
                wave(9 * n, 0.05),
                scalar,
                wave(mesh.num_cells(), 1.3),
            ]
        })
        .collect();
    let fields: Vec<([Field<'_>; 3], [Field<'_>; 1])> = owned
        .iter()
        .map(|[_, v2, v9, s, c]| {
            (
                [
                    Field {
                        name: "vector",
                        components: 2,
                        values: v2,
                    },
                    Field {
                        name: "stress",
                        components: 9,
                        values: v9,
                    },
                    Field {
                        name: "a<b",
                        components: 1,
                        values: s,
                    },
                ],
                [Field {
                    name: "element_von_mises",
                    components: 1,
                    values: c,
                }],
            )
        })
        .collect();
    let list: Vec<(&Mesh, VtuData<'_>)> = pieces
        .iter()
        .zip(&owned)
        .zip(&fields)
        .map(|((mesh, o), (p, c))| {
            let data = VtuData {
                displacement: Some(&o[0]),
                points: p,
                cells: c,
            };
            (*mesh, data)
        })
        .collect();
    if let [(mesh, data)] = list[..] {
        return vtu_bytes(mesh, data, format).expect("valid arrays");
    }
    vtu_pieces_bytes(&list, format).expect("valid arrays")
}

/// The planar files are the bytes they were before solid bodies shared the writer: their
/// lengths and FNV-1a fingerprints, taken from the writer before the change, for P1 and P2,
/// one piece and two, in every encoding.
#[test]
fn planar_files_keep_their_bytes() {
    let p1 = read_msh(&data("square.msh")).expect("square.msh");
    let p2 = read_msh(&data("square_p2.msh")).expect("square_p2.msh");
    let cases: [(&str, Vec<&Mesh>); 3] = [
        ("p1", vec![&p1]),
        ("p2", vec![&p2]),
        ("p1+p2", vec![&p1, &p2]),
    ];
    let mut got = Vec::new();
    for (name, pieces) in &cases {
        for format in FORMATS {
            let bytes = planar_bytes(pieces, format);
            got.push(format!(
                "{name} {format} {} {:016x}",
                bytes.len(),
                fnv1a(&bytes)
            ));
        }
    }
    let expected = [
        "p1 ascii 4436 8d16fa3285e0ee79",
        "p1 binary 3085 8dac854a86ec0c74",
        "p1 zlib 2914 4f99a59ea234f006",
        "p2 ascii 9647 6cea57e4ca7f6ba6",
        "p2 binary 5711 3d16170f32232322",
        "p2 zlib 4806 70c0d74d5b8596ce",
        "p1+p2 ascii 13912 645f8b6f9f9133f2",
        "p1+p2 binary 8574 b70c0b86a11d514d",
        "p1+p2 zlib 7464 4b62d1aaa8cfd70e",
    ];
    assert_eq!(got, expected);
}

/// A box of `[2, 1, 3]` cubes (36 tetrahedra), off the origin, of order `order`.
fn body(order: TetOrder) -> SolidMesh {
    let mesh = BoxMesh {
        origin: [0.5, -1.25, 2.0],
        size: [1.0, 0.75, 3.0],
        cells: [2, 1, 3],
        order,
    };
    mesh.mesh().expect("box mesh")
}

/// VTK's quadratic tetrahedron (vtkQuadraticTetra): its mid-edge nodes 4..9 are those of these
/// edges, written out here from VTK's documentation, not taken from the writer.
const VTK_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// The arrays written with a body: a displacement, a stress tensor, a cell field.
struct Arrays {
    displacement: Vec<f64>,
    stress: Vec<f64>,
    cell: Vec<f64>,
}

impl Arrays {
    fn of(mesh: &SolidMesh) -> Arrays {
        let n = mesh.num_nodes();
        let voigt: Vec<[f64; 6]> = (0..n)
            .map(|v| std::array::from_fn(|c| (v * 6 + c) as f64 / 7.0 - 3.0))
            .collect();
        Arrays {
            displacement: (0..3 * n).map(|k| (k as f64 * 0.37).cos() * 1e-3).collect(),
            stress: stress_tensors(&voigt),
            cell: (0..mesh.num_tets()).map(|e| e as f64 / 3.0).collect(),
        }
    }
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// The file of `bodies`, each with its [`Arrays`], in `format`.
fn solid_file(bodies: &[&SolidMesh], arrays: &[Arrays], format: VtuFormat) -> Vec<u8> {
    let fields: Vec<([Field<'_>; 1], [Field<'_>; 1])> = (arrays.iter())
        .map(|a| {
            let stress = Field {
                name: "stress",
                components: 9,
                values: &a.stress,
            };
            let cell = Field {
                name: "element_von_mises",
                components: 1,
                values: &a.cell,
            };
            ([stress], [cell])
        })
        .collect();
    let pieces: Vec<(&SolidMesh, VtuData<'_>)> = (bodies.iter().zip(arrays).zip(&fields))
        .map(|((mesh, a), (p, c))| {
            let data = VtuData {
                displacement: Some(&a.displacement),
                points: p,
                cells: c,
            };
            (*mesh, data)
        })
        .collect();
    if let [(mesh, data)] = pieces[..] {
        return solid_vtu_bytes(mesh, data, format).expect("valid arrays");
    }
    solid_vtu_pieces_bytes(&pieces, format).expect("valid arrays")
}

/// The piece `file` is `mesh` with `arrays`: the points and the arrays bit for bit, the cells of
/// the right type with the mesh's tetrahedra in VTK's order (for P2: the mesh's vertices, then
/// the mid-edge node of each of [`VTK_EDGES`], found in the mesh's tetrahedron by its edge).
fn check_piece(file: &VtuFile, mesh: &SolidMesh, arrays: &Arrays) {
    let points: Vec<u64> = mesh.nodes().iter().flatten().map(|x| x.to_bits()).collect();
    let read = file.points().expect("points");
    assert_eq!(
        read.iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>(),
        points
    );
    let cells = file.cells().expect("cells");
    assert_eq!(cells.len(), mesh.num_tets());
    let (vtk_type, npt) = match mesh.order() {
        TetOrder::P1 => (10, 4),
        TetOrder::P2 => (24, 10),
    };
    for e in 0..mesh.num_tets() {
        let tet = mesh.tet(e);
        let mut expected = tet[..4].to_vec();
        if npt == 10 {
            for [a, b] in VTK_EDGES {
                let k = (TET_EDGES.iter())
                    .position(|&[i, j]| [i, j] == [a, b] || [j, i] == [a, b])
                    .expect("an edge of the mesh's tetrahedron");
                expected.push(tet[4 + k]);
            }
        }
        assert_eq!(cells.cell(e), Some(&expected[..]), "tetrahedron {e}");
        assert_eq!(cells.types[e], vtk_type);
        assert_eq!(cells.offsets[e], (e + 1) * npt);
    }
    let array = |section, name| &file.array(section, name).expect("array").values;
    let displacement = file.array(Section::PointData, "displacement").expect("u");
    assert_eq!(displacement.components, 3);
    assert_eq!(bits(&displacement.values), bits(&arrays.displacement));
    let stress = array(Section::PointData, "stress");
    assert_eq!(bits(stress), bits(&arrays.stress));
    let cell = array(Section::CellData, "element_von_mises");
    assert_eq!(bits(cell), bits(&arrays.cell));
}

#[test]
fn solid_bodies_read_back_in_every_encoding() {
    for order in [TetOrder::P1, TetOrder::P2] {
        let mesh = body(order);
        let arrays = Arrays::of(&mesh);
        for format in FORMATS {
            let bytes = solid_file(&[&mesh], std::slice::from_ref(&arrays), format);
            let pieces = parse_vtu_pieces(&bytes).expect("reads back");
            assert_eq!(pieces.len(), 1, "{order:?} {format}");
            check_piece(&pieces[0], &mesh, &arrays);
        }
    }
}

#[test]
fn several_bodies_are_pieces_of_one_file() {
    let p1 = body(TetOrder::P1);
    let p2 = body(TetOrder::P2);
    let arrays = [Arrays::of(&p2), Arrays::of(&p1)];
    for format in FORMATS {
        let bytes = solid_file(&[&p2, &p1], &arrays, format);
        let pieces = parse_vtu_pieces(&bytes).expect("reads back");
        assert_eq!(pieces.len(), 2, "{format}");
        check_piece(&pieces[0], &p2, &arrays[0]);
        check_piece(&pieces[1], &p1, &arrays[1]);
    }
}

/// On a straight P2 box, each mid-edge node written lies at the midpoint of its VTK edge: the
/// node order is VTK's, whatever the writer's table says.
#[test]
fn quadratic_mid_edge_nodes_are_at_the_midpoints_of_vtk_edges() {
    let mesh = body(TetOrder::P2);
    let bytes = solid_vtu_bytes(&mesh, VtuData::default(), VtuFormat::Ascii).expect("no arrays");
    let file = parse_vtu(&bytes).expect("reads back");
    let (points, cells) = (file.points().expect("points"), file.cells().expect("cells"));
    assert_eq!(cells.len(), mesh.num_tets());
    for e in 0..cells.len() {
        let c = cells.cell(e).expect("a cell");
        for (k, [a, b]) in VTK_EDGES.iter().enumerate() {
            let (pa, pb, m) = (points[c[*a]], points[c[*b]], points[c[4 + k]]);
            for axis in 0..3 {
                let mid = 0.5 * (pa[axis] + pb[axis]);
                assert!(
                    (m[axis] - mid).abs() < 1e-12,
                    "tetrahedron {e}, edge {a}-{b}"
                );
            }
        }
    }
    // Gmsh's edges 4 (2-3) and 5 (1-3) are VTK's 5 (2-3) and 4 (1-3): the only two that swap.
    assert_eq!(VTK_QUADRATIC_TET_NODES, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]);
}

#[test]
fn a_planar_displacement_on_a_body_is_an_error() {
    let mesh = body(TetOrder::P1);
    let u = vec![0.0; 2 * mesh.num_nodes()];
    let data = VtuData {
        displacement: Some(&u),
        ..VtuData::default()
    };
    let err = solid_vtu_bytes(&mesh, data, VtuFormat::Zlib).expect_err("2 values per node");
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    assert!(err.to_string().contains("displacement"), "{err}");
}

#[test]
fn voigt_stresses_become_symmetric_tensors() {
    let t = stress_tensors(&[[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]]);
    // xx xy xz / yx yy yz / zx zy zz with yz = 4, xz = 5, xy = 6.
    assert_eq!(t, [1.0, 6.0, 5.0, 6.0, 2.0, 4.0, 5.0, 4.0, 3.0]);
}

#[test]
fn planar_cells_read_as_triangles() {
    for (name, ty, n) in [("square.msh", 5, 3), ("square_p2.msh", 22, 6)] {
        let mesh = read_msh(&data(name)).expect("test mesh");
        for format in FORMATS {
            let file = parse_vtu(&planar_bytes(&[&mesh], format)).expect("reads back");
            let cells = file.cells().expect("cells");
            assert_eq!(cells.connectivity, mesh.cells(), "{name} {format}");
            assert!(cells.types.iter().all(|&t| t == ty));
            assert_eq!(cells.cell(0).map(<[usize]>::len), Some(n));
            let points = file.points().expect("points");
            assert!(points
                .iter()
                .zip(mesh.nodes())
                .all(|(p, q)| p == &[q[0], q[1], 0.0]));
        }
    }
}

/// Cells that do not fit their type or the points are errors of [`VtuFile::cells`].
#[test]
fn cells_that_do_not_fit_are_errors() {
    let mesh = body(TetOrder::P1);
    let text = String::from_utf8(
        solid_vtu_bytes(&mesh, VtuData::default(), VtuFormat::Ascii).expect("no arrays"),
    )
    .expect("ASCII");
    let types_at = text.find("Name=\"types\"").expect("types");
    let offsets_at = text.find("Name=\"offsets\"").expect("offsets");
    let conn_at = text.find("Name=\"connectivity\"").expect("connectivity");
    // Changes the first number after the tag at `at`.
    let edit = |at: usize, value: &str| {
        let start = at + text[at..].find('>').expect("tag end") + 1;
        let start = start
            + text[start..]
                .find(|c: char| c.is_ascii_digit())
                .expect("digit");
        let end = start + text[start..].find(char::is_whitespace).expect("end");
        format!("{}{value}{}", &text[..start], &text[end..])
    };
    let points = mesh.num_nodes().to_string();
    let cases = [
        (edit(types_at, "24"), "10 nodes"),
        (edit(types_at, "7"), "type"),
        (edit(offsets_at, "5"), "offset"),
        (edit(conn_at, &points), "not a point"),
        (edit(conn_at, "-1"), "not a point"),
    ];
    for (damaged, message) in cases {
        let file = parse_vtu(damaged.as_bytes()).expect("still parses");
        let err = file.cells().expect_err(message);
        assert!(err.to_string().contains(message), "{err}");
    }
    assert!(parse_vtu(text.as_bytes()).expect("parses").cells().is_ok());
}

/// A planar body and a 3D one as the pieces of one file: each keeps its cells and its
/// displacement's meaning (2 values per node in the plane, padded; 3 in space).
#[test]
fn planar_and_solid_pieces_share_a_file() {
    let square = read_msh(&data("square_p2.msh")).expect("test mesh");
    let solid = body(TetOrder::P2);
    let u2: Vec<f64> = (0..2 * square.num_nodes()).map(|k| k as f64).collect();
    let u3: Vec<f64> = (0..3 * solid.num_nodes()).map(|k| -(k as f64)).collect();
    let with = |u| VtuData {
        displacement: Some(u),
        ..VtuData::default()
    };
    let pieces = [
        (Grid::planar(&square), with(&u2)),
        (solid_grid(&solid), with(&u3)),
    ];
    for format in FORMATS {
        let bytes = grid_pieces_bytes(&pieces, format).expect("valid arrays");
        let files = parse_vtu_pieces(&bytes).expect("reads back");
        let [plane, space] = &files[..] else {
            panic!("two pieces");
        };
        assert!(plane
            .cells()
            .expect("triangles")
            .types
            .iter()
            .all(|&t| t == 22));
        assert!(space
            .cells()
            .expect("tetrahedra")
            .types
            .iter()
            .all(|&t| t == 24));
        let padded: Vec<f64> = u2.chunks(2).flat_map(|u| [u[0], u[1], 0.0]).collect();
        let read = |f: &VtuFile| {
            f.array(Section::PointData, "displacement")
                .expect("u")
                .values
                .clone()
        };
        assert_eq!(read(plane), padded);
        assert_eq!(read(space), u3);
    }
}
