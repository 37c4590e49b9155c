//! The `.vtu` files of tetrahedral bodies (`contactdd_io::solid_vtu`) and the planar files
//! beside them.

use std::path::{Path, PathBuf};

use contactdd_core::gmsh::read_msh;
use contactdd_core::mesh::Mesh;
use contactdd_io::vtu::{vtu_bytes, vtu_pieces_bytes, Field, VtuData, VtuFormat};

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
