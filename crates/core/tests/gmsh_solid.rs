//! Reading tetrahedral Gmsh meshes (`gmsh::read_solid_msh`): a hand-written cube in MSH 4.1 and
//! 2.2 against the cube's volume and face areas, P1 and P2 box meshes written as MSH 4.1 (half of
//! their tetrahedra negatively oriented) and read back against the mesher's own mesh, a curved P2 tetrahedron against the ball's volume, and the
//! typed errors.

use contactdd_core::error::GmshError;
use contactdd_core::gmsh::{parse_msh, parse_solid_msh, read_solid_msh};
use contactdd_core::solid::{BoxMesh, Point3, SolidError, SolidMesh, TetOrder};

/// The unit cube cut into the six tetrahedra of its main diagonal (node 1 at the origin, node 8
/// at (1, 1, 1)); the odd paths are written negatively oriented, as a hand-made file may be.
/// Physical surfaces "bottom" (z = 0) and "top" (z = 1), physical volume "cube".
const CUBE_41: &str = r#"$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
2 1 "bottom"
2 2 "top"
3 3 "cube"
$EndPhysicalNames
$Entities
0 0 2 1
1 0 0 0 1 1 0 1 1 0
2 0 0 1 1 1 1 1 2 0
1 0 0 0 1 1 1 1 3 0
$EndEntities
$Nodes
1 8 1 8
3 1 0 8
1
2
3
4
5
6
7
8
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
$EndNodes
$Elements
3 10 1 10
2 1 2 2
1 1 2 4
2 1 3 4
2 2 2 2
3 5 6 8
4 5 7 8
3 1 4 6
5 1 2 4 8
6 1 3 7 8
7 1 5 6 8
8 1 2 6 8
9 1 5 7 8
10 1 3 4 8
$EndElements
"#;

/// [`CUBE_41`] in MSH 2.2.
const CUBE_22: &str = r#"$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
2 1 "bottom"
2 2 "top"
3 3 "cube"
$EndPhysicalNames
$Nodes
8
1 0 0 0
2 1 0 0
3 0 1 0
4 1 1 0
5 0 0 1
6 1 0 1
7 0 1 1
8 1 1 1
$EndNodes
$Elements
10
1 2 2 1 1 1 2 4
2 2 2 1 1 1 3 4
3 2 2 2 2 5 6 8
4 2 2 2 2 5 7 8
5 4 2 3 1 1 2 4 8
6 4 2 3 1 1 3 7 8
7 4 2 3 1 1 5 6 8
8 4 2 3 1 1 2 6 8
9 4 2 3 1 1 5 7 8
10 4 2 3 1 1 3 4 8
$EndElements
"#;

fn volume(mesh: &SolidMesh) -> f64 {
    (0..mesh.num_tets())
        .map(|e| mesh.geometry(e).volume())
        .sum()
}

/// The sum of `(b − a) × (c − a) / 2` over the triangles of face `name`: its area times its
/// outward normal, for a plane face.
fn area_vector(mesh: &SolidMesh, name: &str) -> [f64; 3] {
    let npf = mesh.order().nodes_per_face();
    let x = mesh.nodes();
    let mut sum = [0.0; 3];
    for t in mesh.face(name).unwrap().chunks(npf) {
        let (a, b, c) = (x[t[0]], x[t[1]], x[t[2]]);
        let u: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
        let v: [f64; 3] = std::array::from_fn(|k| c[k] - a[k]);
        sum[0] += 0.5 * (u[1] * v[2] - u[2] * v[1]);
        sum[1] += 0.5 * (u[2] * v[0] - u[0] * v[2]);
        sum[2] += 0.5 * (u[0] * v[1] - u[1] * v[0]);
    }
    sum
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() < 1e-14)
}

fn check_cube(mesh: &SolidMesh) {
    assert_eq!(mesh.order(), TetOrder::P1);
    assert_eq!(mesh.num_nodes(), 8);
    assert_eq!(mesh.num_tets(), 6);
    assert_eq!(mesh.face_names().collect::<Vec<_>>(), ["bottom", "top"]);
    assert!((volume(mesh) - 1.0).abs() < 1e-14, "{}", volume(mesh));
    // Unit areas, and outward: down at the bottom, up at the top.
    assert!(close(area_vector(mesh, "bottom"), [0.0, 0.0, -1.0]));
    assert!(close(area_vector(mesh, "top"), [0.0, 0.0, 1.0]));
    assert_eq!(mesh.face_nodes("bottom").unwrap(), [0, 1, 2, 3]);
    assert_eq!(mesh.nodes()[7], [1.0, 1.0, 1.0]);
}

#[test]
fn a_hand_written_cube_reads_in_msh_41() {
    check_cube(&parse_solid_msh(CUBE_41, None).unwrap());
    check_cube(&parse_solid_msh(CUBE_41, Some("cube")).unwrap());
    // A named group is chosen by its name, as the planar reader's surfaces.
    let by_tag = parse_solid_msh(CUBE_41, Some("3"));
    assert!(matches!(by_tag, Err(GmshError::Volume(_))), "{by_tag:?}");
}

#[test]
fn a_hand_written_cube_reads_in_msh_22() {
    check_cube(&parse_solid_msh(CUBE_22, None).unwrap());
    check_cube(&parse_solid_msh(CUBE_22, Some("cube")).unwrap());
}

#[test]
fn a_file_reads_from_its_path() {
    let path = std::env::temp_dir().join(format!("gmsh_solid_{}.msh", std::process::id()));
    std::fs::write(&path, CUBE_41).unwrap();
    let mesh = read_solid_msh(&path, None);
    std::fs::remove_file(&path).unwrap();
    check_cube(&mesh.unwrap());
    let missing = read_solid_msh(std::path::Path::new("/nonexistent/cube.msh"), None);
    assert!(matches!(missing, Err(GmshError::Io { .. })), "{missing:?}");
}

#[test]
fn unnamed_groups_are_named_by_their_number() {
    let start = CUBE_41.find("$PhysicalNames").unwrap();
    let end = CUBE_41.find("$Entities").unwrap();
    let text = format!("{}{}", &CUBE_41[..start], &CUBE_41[end..]);
    let mesh = parse_solid_msh(&text, None).unwrap();
    assert_eq!(mesh.face_names().collect::<Vec<_>>(), ["1", "2"]);
    let mesh = parse_solid_msh(&text, Some("3")).unwrap();
    assert!(close(area_vector(&mesh, "2"), [0.0, 0.0, 1.0]));
}

/// The cube with its tetrahedra split into physical volumes "a" (the first three) and "b".
fn two_volumes() -> String {
    let text = CUBE_22.replace("3\n2 1 \"bottom\"", "4\n2 1 \"bottom\"");
    let text = text.replace("3 3 \"cube\"", "3 3 \"a\"\n3 4 \"b\"");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for tag in ["8", "9", "10"] {
        let line = lines
            .iter_mut()
            .find(|l| l.starts_with(&format!("{tag} 4 2 3 ")))
            .unwrap();
        *line = line.replacen(" 4 2 3 1 ", " 4 2 4 1 ", 1);
    }
    lines.join("\n") + "\n"
}

#[test]
fn a_physical_volume_selects_its_tetrahedra_and_its_part_of_each_face() {
    let text = two_volumes();
    match parse_solid_msh(&text, None) {
        Err(GmshError::Volume(m)) => {
            assert!(m.contains("2 bodies") && m.contains("a, b"), "{m}")
        }
        other => panic!("expected a volume error, got {other:?}"),
    }
    match parse_solid_msh(&text, Some("c")) {
        Err(GmshError::Volume(m)) => assert!(m.contains("'c'") && m.contains("a, b"), "{m}"),
        other => panic!("expected a volume error, got {other:?}"),
    }
    // a: paths x-y-z, y-z-x, z-x-y; one bottom triangle (1 2 4) and one top triangle (5 6 8).
    let a = parse_solid_msh(&text, Some("a")).unwrap();
    assert_eq!(a.num_tets(), 3);
    assert!((volume(&a) - 0.5).abs() < 1e-14);
    assert!(close(area_vector(&a, "bottom"), [0.0, 0.0, -0.5]));
    assert!(close(area_vector(&a, "top"), [0.0, 0.0, 0.5]));
    let b = parse_solid_msh(&text, Some("b")).unwrap();
    assert_eq!(b.num_tets(), 3);
    assert!((volume(&a) + volume(&b) - 1.0).abs() < 1e-14);
    assert!(close(area_vector(&b, "bottom"), [0.0, 0.0, -0.5]));
}

#[test]
fn only_the_nodes_of_the_chosen_tetrahedra_are_kept_in_file_order() {
    // One tetrahedron of the cube (1 2 4 8): nodes 1, 2, 4, 8 become 0, 1, 2, 3.
    let text = CUBE_22.replace("3 3 \"cube\"", "3 3 \"one\"\n3 4 \"rest\"");
    let text = text.replace("3\n2 1", "4\n2 1");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for line in lines.iter_mut().filter(|l| l.contains(" 4 2 3 1 ")) {
        if !line.starts_with("5 ") {
            *line = line.replacen(" 4 2 3 1 ", " 4 2 4 1 ", 1);
        }
    }
    let mesh = parse_solid_msh(&(lines.join("\n") + "\n"), Some("one")).unwrap();
    assert_eq!(mesh.num_nodes(), 4);
    assert_eq!(
        mesh.nodes(),
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 1.0]
        ]
    );
    assert_eq!(mesh.tets(), [0, 1, 2, 3]);
    assert_eq!(mesh.face_names().collect::<Vec<_>>(), ["bottom"]);
}

/// A small MSH 4.1 writer: nodes (tags 1..), physical groups and blocks of elements (0-based
/// node indices). Each block is its own entity carrying one physical group (or none).
struct Msh41 {
    nodes: Vec<Point3>,
    /// (dimension, physical tag, name).
    names: Vec<(u8, i64, String)>,
    /// (dimension, physical tag or 0, Gmsh element type, elements).
    blocks: Vec<(u8, i64, usize, Vec<Vec<usize>>)>,
}

impl Msh41 {
    fn text(&self) -> String {
        let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
        s += &format!("$PhysicalNames\n{}\n", self.names.len());
        for (dim, tag, name) in &self.names {
            s += &format!("{dim} {tag} \"{name}\"\n");
        }
        s += "$EndPhysicalNames\n$Entities\n";
        // Entity k + 1 of its dimension for block k.
        let count = |d: u8| self.blocks.iter().filter(|b| b.0 == d).count();
        s += &format!("{} {} {} {}\n", count(0), count(1), count(2), count(3));
        for d in 0..4u8 {
            for (k, b) in self.blocks.iter().enumerate().filter(|(_, b)| b.0 == d) {
                let physicals = if b.1 == 0 {
                    "0".to_string()
                } else {
                    format!("1 {}", b.1)
                };
                let bounds = if d == 0 { "0 0 0" } else { "0 0 0 1 1 1" };
                let bounding = if d == 0 { "" } else { " 0" };
                s += &format!("{} {bounds} {physicals}{bounding}\n", k + 1);
            }
        }
        s += "$EndEntities\n";
        let n = self.nodes.len();
        s += &format!("$Nodes\n1 {n} 1 {n}\n3 1 0 {n}\n");
        for tag in 1..=n {
            s += &format!("{tag}\n");
        }
        for p in &self.nodes {
            s += &format!("{:e} {:e} {:e}\n", p[0], p[1], p[2]);
        }
        let total: usize = self.blocks.iter().map(|b| b.3.len()).sum();
        s += &format!(
            "$EndNodes\n$Elements\n{} {total} 1 {total}\n",
            self.blocks.len()
        );
        let mut tag = 0;
        for (k, (dim, _, ty, elements)) in self.blocks.iter().enumerate() {
            s += &format!("{dim} {} {ty} {}\n", k + 1, elements.len());
            for e in elements {
                tag += 1;
                s += &tag.to_string();
                for v in e {
                    s += &format!(" {}", v + 1);
                }
                s += "\n";
            }
        }
        s + "$EndElements\n"
    }

    /// `mesh` as one physical volume "box" and a physical surface per face, plus an extra node
    /// (a physical point "far") no tetrahedron uses.
    fn of(mesh: &SolidMesh) -> Msh41 {
        let (tet_type, tri_type) = match mesh.order() {
            TetOrder::P1 => (4, 2),
            TetOrder::P2 => (11, 9),
        };
        let npt = mesh.order().nodes_per_tet();
        let npf = mesh.order().nodes_per_face();
        let mut nodes = mesh.nodes().to_vec();
        nodes.push([9.0, 9.0, 9.0]);
        let mut names = vec![(3, 100, "box".to_string()), (0, 200, "far".to_string())];
        let mut blocks = vec![
            (
                3,
                100,
                tet_type,
                mesh.tets().chunks(npt).map(<[_]>::to_vec).collect(),
            ),
            (0, 200, 15, vec![vec![nodes.len() - 1]]),
        ];
        for (k, name) in mesh.face_names().enumerate() {
            let tag = k as i64 + 1;
            names.push((2, tag, name.to_string()));
            let tris = mesh.face(name).unwrap().chunks(npf).map(<[_]>::to_vec);
            blocks.push((2, tag, tri_type, tris.collect()));
        }
        Msh41 {
            nodes,
            names,
            blocks,
        }
    }
}

fn box_mesh(order: TetOrder) -> SolidMesh {
    BoxMesh {
        origin: [-1.0, 0.5, 2.0],
        size: [2.0, 1.0, 1.5],
        cells: [2, 1, 3],
        order,
    }
    .mesh()
    .unwrap()
}

/// Tetrahedron `tet` with vertices 1 and 2 swapped; for 10 nodes, each mid-edge node (Gmsh's
/// edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1) is the node of `tet` at the midpoint of its edge.
fn swapped(x: &[Point3], tet: &[usize]) -> Vec<usize> {
    let mut out = vec![tet[0], tet[2], tet[1], tet[3]];
    if tet.len() == 10 {
        for [a, b] in [[0, 1], [1, 2], [2, 0], [3, 0], [3, 2], [3, 1]] {
            let m: Point3 = std::array::from_fn(|c| 0.5 * (x[out[a]][c] + x[out[b]][c]));
            let node = tet[4..].iter().find(|&&v| x[v] == m).unwrap();
            out.push(*node);
        }
    }
    out
}

#[test]
fn a_box_mesh_written_as_msh_41_reads_back_the_same() {
    for order in [TetOrder::P1, TetOrder::P2] {
        let mesh = box_mesh(order);
        let mut msh = Msh41::of(&mesh);
        // Every other tetrahedron written negatively oriented (vertices 1 and 2 swapped, and
        // its mid-edge nodes found again by position): the reader turns it back.
        for tet in msh.blocks[0].3.iter_mut().skip(1).step_by(2) {
            *tet = swapped(mesh.nodes(), tet);
        }
        let read = parse_solid_msh(&msh.text(), None).unwrap();
        assert_eq!(read.order(), order);
        // The extra node is dropped; the others keep their numbers (all used, in file order).
        assert_eq!(read.nodes(), mesh.nodes());
        assert_eq!(read.tets(), mesh.tets());
        let names: Vec<&str> = mesh.face_names().collect();
        assert_eq!(read.face_names().collect::<Vec<_>>(), names);
        for name in names {
            assert_eq!(read.face(name).unwrap(), mesh.face(name).unwrap(), "{name}");
        }
        assert!((volume(&read) - 3.0).abs() < 1e-13);
    }
}

#[test]
fn mixed_tetrahedra_are_an_error_at_the_line_of_the_first_of_the_other_order() {
    let mesh = box_mesh(TetOrder::P2);
    let mut msh = Msh41::of(&mesh);
    // The first tetrahedron as a 4-node one in a block of its own, after the others.
    let first = msh.blocks[0].3.remove(0);
    msh.blocks.push((3, 100, 4, vec![first[..4].to_vec()]));
    match parse_solid_msh(&msh.text(), None) {
        Err(
            e @ GmshError::MixedTetrahedra {
                nodes: 4,
                first_nodes: 10,
                ..
            },
        ) => {
            let m = e.to_string();
            assert!(m.contains("has 4 nodes") && m.contains("has 10"), "{m}");
        }
        other => panic!("expected mixed tetrahedra, got {other:?}"),
    }
}

#[test]
fn face_triangles_of_another_order_are_an_error_naming_their_group() {
    let mesh = box_mesh(TetOrder::P2);
    let mut msh = Msh41::of(&mesh);
    let face = msh.blocks.iter_mut().find(|b| b.0 == 2).unwrap();
    face.2 = 2;
    for t in &mut face.3 {
        t.truncate(3);
    }
    match parse_solid_msh(&msh.text(), None) {
        Err(
            e @ GmshError::FaceOrder {
                nodes: 3,
                tet_nodes: 10,
                ..
            },
        ) => {
            assert!(e.to_string().contains("physical surface 'x+'"), "{e}");
        }
        other => panic!("expected a face order error, got {other:?}"),
    }
}

fn not_a_face(text: &str, volume: Option<&str>) -> (usize, String, String) {
    match parse_solid_msh(text, volume) {
        Err(e @ GmshError::NotABoundaryFace { .. }) => {
            let message = e.to_string();
            let GmshError::NotABoundaryFace { line, group, .. } = e else {
                unreachable!()
            };
            (line, group, message)
        }
        other => panic!("expected a triangle that is not a boundary face, got {other:?}"),
    }
}

#[test]
fn a_face_triangle_inside_the_body_or_off_it_is_an_error() {
    // The triangle 1 4 8 lies between the tetrahedra 1 2 4 8 and 1 3 4 8.
    let inside = CUBE_22.replace("4 2 2 2 2 5 7 8", "4 2 2 2 2 1 4 8");
    let (line, group, message) = not_a_face(&inside, None);
    assert_eq!((line, group.as_str()), (26, "top"));
    assert!(message.contains("inside the body"), "{message}");
    // Inside the chosen volume as well.
    let (line, _, _) = not_a_face(&inside, Some("cube"));
    assert_eq!(line, 26);
    // 2 3 5 is no face of any tetrahedron.
    let off = CUBE_22.replace("4 2 2 2 2 5 7 8", "4 2 2 2 2 2 3 5");
    let (line, _, message) = not_a_face(&off, None);
    assert_eq!(line, 26);
    assert!(message.contains("no tetrahedron has it"), "{message}");
    // A P2 face triangle whose mid-edge nodes are not its tetrahedron's.
    let mesh = box_mesh(TetOrder::P2);
    let mut msh = Msh41::of(&mesh);
    let face = msh.blocks.iter_mut().find(|b| b.0 == 2).unwrap();
    face.3[0].swap(3, 4);
    let (_, group, message) = not_a_face(&msh.text(), None);
    assert_eq!(group, "x+");
    assert!(message.contains("mid-edge nodes"), "{message}");
}

#[test]
fn a_file_without_tetrahedra_is_an_error() {
    let text = CUBE_22.replace("\n10\n1 2 2", "\n4\n1 2 2");
    let text: String = text
        .lines()
        .filter(|l| !l.contains(" 4 2 3 1 "))
        .map(|l| format!("{l}\n"))
        .collect();
    // The name of the volume is left without elements: remove it too.
    let text = text
        .replace("3 3 \"cube\"\n", "")
        .replace("3\n2 1", "2\n2 1");
    let result = parse_solid_msh(&text, None);
    assert!(matches!(result, Err(GmshError::NoTetrahedra)), "{result:?}");
    assert!(result.unwrap_err().to_string().contains("Physical Volume"));
}

#[test]
fn the_planar_reader_still_refuses_tetrahedra() {
    match parse_msh(CUBE_41) {
        Err(GmshError::Unsupported(m)) => assert!(m.contains("3D element"), "{m}"),
        other => panic!("expected unsupported, got {other:?}"),
    }
    match parse_msh(CUBE_22) {
        Err(GmshError::Unsupported(m)) => assert!(m.starts_with("line 27: element type 4"), "{m}"),
        other => panic!("expected unsupported, got {other:?}"),
    }
}

#[test]
fn other_3d_elements_are_unsupported_in_the_solid_reader() {
    let text = CUBE_22.replace("10 4 2 3 1 1 3 4 8", "10 5 2 3 1 1 2 3 4 5 6 7 8");
    match parse_solid_msh(&text, None) {
        Err(GmshError::Unsupported(m)) => {
            assert!(
                m.contains("element type 5") && m.contains("tetrahedra"),
                "{m}"
            )
        }
        other => panic!("expected unsupported, got {other:?}"),
    }
}

#[test]
fn a_mesh_error_comes_wrapped_with_the_line_of_its_tetrahedron() {
    // An eleventh tetrahedron 2 3 6 7, flat (in the plane x + y = 1).
    let text = CUBE_22.replace("\n10\n1 2 2", "\n11\n1 2 2").replace(
        "10 4 2 3 1 1 3 4 8\n",
        "10 4 2 3 1 1 3 4 8\n11 4 2 3 1 2 3 6 7\n",
    );
    match parse_solid_msh(&text, None) {
        Err(e @ GmshError::Solid { .. }) => {
            assert!(e.to_string().starts_with("line 33: tetrahedron 6"), "{e}");
            let GmshError::Solid { line, source } = e else {
                unreachable!()
            };
            assert_eq!(line, Some(33));
            assert!(matches!(
                source.downcast_ref::<SolidError>(),
                Some(SolidError::DegenerateElement { element: 6 })
            ));
        }
        other => panic!("expected a solid mesh error, got {other:?}"),
    }
    // A duplicated tetrahedron.
    let text = CUBE_22.replace("10 4 2 3 1 1 3 4 8", "10 4 2 3 1 1 8 4 2");
    match parse_solid_msh(&text, None) {
        Err(GmshError::Parse { line, message }) => {
            assert_eq!(line, 32);
            assert!(message.contains("same four vertices"), "{message}");
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// The octant of the unit ball as one P2 tetrahedron: the origin and the three unit points,
/// with the mid-edge nodes of the edges between the unit points on the sphere.
fn octant(curved: bool) -> String {
    let mut nodes: Vec<Point3> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    // Gmsh's edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1.
    for [a, b] in [[0, 1], [1, 2], [2, 0], [3, 0], [3, 2], [3, 1]] {
        let m: Point3 = std::array::from_fn(|c| 0.5 * (nodes[a][c] + nodes[b][c]));
        let r = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        let on_sphere = a != 0 && b != 0;
        nodes.push(if curved && on_sphere {
            m.map(|x| x / r)
        } else {
            m
        });
    }
    Msh41 {
        nodes,
        names: vec![(3, 1, "octant".to_string()), (2, 2, "sphere".to_string())],
        blocks: vec![
            (3, 1, 11, vec![(0..10).collect()]),
            (2, 2, 9, vec![vec![1, 2, 3, 5, 8, 9]]),
        ],
    }
    .text()
}

#[test]
fn a_curved_p2_tetrahedron_is_closer_to_the_ball_than_the_straight_one() {
    let exact = std::f64::consts::PI / 6.0;
    let straight = volume(&parse_solid_msh(&octant(false), None).unwrap());
    let curved_mesh = parse_solid_msh(&octant(true), None).unwrap();
    let curved = volume(&curved_mesh);
    assert!((straight - 1.0 / 6.0).abs() < 1e-14);
    assert!(curved_mesh.geometry(0).is_curved());
    assert!(
        (curved - exact).abs() < 0.5 * (straight - exact).abs(),
        "straight {straight}, curved {curved}, exact {exact}"
    );
    assert_eq!(curved_mesh.face("sphere").unwrap().len(), 6);
}
