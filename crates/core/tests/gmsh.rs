//! Reading Gmsh meshes (`gmsh`).

use std::path::{Path, PathBuf};

use contactdd_core::error::GmshError;
use contactdd_core::gmsh::{parse_msh, parse_msh_surface, read_msh, read_msh_surface};
use contactdd_core::mesh::{Mesh, Order};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

fn square_text() -> String {
    std::fs::read_to_string(data("square.msh")).expect("test data square.msh")
}

fn square() -> Mesh {
    read_msh(&data("square.msh")).expect("square.msh reads")
}

/// The node at `p`, which must exist.
fn node_at(mesh: &Mesh, p: [f64; 2]) -> usize {
    mesh.nodes()
        .iter()
        .position(|q| (q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12)
        .unwrap_or_else(|| panic!("no node at {p:?}"))
}

fn signed_area2(mesh: &Mesh, e: usize) -> f64 {
    let c = mesh.cell(e);
    let [p0, p1, p2] = [mesh.nodes()[c[0]], mesh.nodes()[c[1]], mesh.nodes()[c[2]]];
    (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1])
}

/// The 1-based line of a parse error, or a panic describing the unexpected result.
fn parse_error_line(result: Result<Mesh, GmshError>) -> usize {
    match result {
        Err(GmshError::Parse { line, .. }) => line,
        other => panic!("expected a parse error, got {other:?}"),
    }
}

fn is_unsupported(result: Result<Mesh, GmshError>) -> bool {
    matches!(result, Err(GmshError::Unsupported(_)))
}

/// `text` with line `index` (0-based) replaced.
fn replace_line(text: &str, index: usize, new: &str) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    lines[index] = new;
    lines.join("\n") + "\n"
}

fn line_index(text: &str, line: &str) -> usize {
    text.lines()
        .position(|l| l == line)
        .unwrap_or_else(|| panic!("no line '{line}'"))
}

#[test]
fn square_counts_names_and_sets() {
    let mesh = square();
    assert_eq!(mesh.order(), Order::P1);
    // 10 nodes in the file, of which the geometry point (2, 2) is used by no triangle.
    assert_eq!(mesh.num_nodes(), 9);
    assert_eq!(mesh.num_cells(), 8);
    let names: Vec<&str> = mesh.boundaries().keys().map(String::as_str).collect();
    assert_eq!(names, ["bottom", "left", "right", "top"]);
    for edges in mesh.boundaries().values() {
        assert_eq!(edges.len(), 2);
    }
    let corner = node_at(&mesh, [0.0, 0.0]);
    assert_eq!(mesh.node_sets().get("corner"), Some(&vec![corner]));
    // The surface's name is not a boundary or node set.
    assert!(mesh.boundary("body").is_err());
    // The clockwise triangle of the file was reoriented.
    for e in 0..mesh.num_cells() {
        assert!(signed_area2(&mesh, e) > 0.0);
    }
    // Nodes keep the file order: tags 1, 2, 3, 4 are the corners.
    assert_eq!(
        mesh.nodes()[..4],
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    );
}

#[test]
fn square_boundaries_lie_on_the_sides_with_outward_normals() {
    let mesh = square();
    let sides = [
        ("bottom", 1, 0.0, [0.0, -1.0]),
        ("top", 1, 1.0, [0.0, 1.0]),
        ("left", 0, 0.0, [-1.0, 0.0]),
        ("right", 0, 1.0, [1.0, 0.0]),
    ];
    for (name, axis, value, normal) in sides {
        let edges = mesh.boundary(name).expect("boundary exists");
        let mut length = 0.0;
        for edge in edges {
            for v in edge.nodes() {
                assert!((mesh.nodes()[v][axis] - value).abs() < 1e-12, "{name}");
            }
            let (n, len) = mesh.edge_normal(edge);
            assert!((n[0] - normal[0]).abs() < 1e-12 && (n[1] - normal[1]).abs() < 1e-12);
            length += len;
        }
        assert!((length - 1.0).abs() < 1e-12, "{name} has length {length}");
    }
}

#[test]
fn square_p2_reads_as_quadratic() {
    let mesh = read_msh(&data("square_p2.msh")).expect("square_p2.msh reads");
    assert_eq!(mesh.order(), Order::P2);
    assert_eq!(mesh.num_nodes(), 25);
    assert_eq!(mesh.num_cells(), 8);
    assert_eq!(mesh.boundaries().len(), 4);
    for edge in mesh.boundary("bottom").expect("bottom") {
        let mid = edge.mid.expect("P2 edges have a mid-side node");
        let [a, b, m] = [edge.a, edge.b, mid].map(|v| mesh.nodes()[v]);
        assert!((0.5 * (a[0] + b[0]) - m[0]).abs() < 1e-12 && m[1] == 0.0);
        assert_eq!(mesh.edge_normal(edge).0, [0.0, -1.0]);
    }
    let corner = node_at(&mesh, [0.0, 0.0]);
    assert_eq!(mesh.node_sets().get("corner"), Some(&vec![corner]));
}

#[test]
fn clockwise_p2_triangle_is_reoriented_with_its_mid_nodes() {
    // One P2 triangle written clockwise: v0 v2 v1 order, mids of (0,2), (2,1), (1,0).
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 6 1 6\n2 1 0 6\n1\n2\n3\n4\n5\n6\n\
                0 0 0\n0 1 0\n1 0 0\n0 0.5 0\n0.5 0.5 0\n0.5 0 0\n$EndNodes\n\
                $Elements\n1 1 1 1\n2 1 9 1\n1 1 2 3 4 5 6\n$EndElements\n";
    let mesh = parse_msh(text).expect("reads");
    assert_eq!(mesh.cell(0), [0, 2, 1, 5, 4, 3]);
    assert!(signed_area2(&mesh, 0) > 0.0);
}

/// The MSH 2.2 file of [`msh22_is_read`].
const MSH22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n\
                     $PhysicalNames\n2\n1 7 \"fixed side\"\n2 9 \"plate\"\n$EndPhysicalNames\n\
                     $Nodes\n4\n1 0 0 0\n2 2 0 0\n3 2 1 0\n4 0 1 0\n$EndNodes\n\
                     $Elements\n5\n1 1 2 7 1 1 2\n2 1 2 8 2 3 4\n3 15 2 0 1 1\n\
                     4 2 2 9 1 1 2 3\n5 2 2 9 1 1 3 4\n$EndElements\n";

#[test]
fn ambiguous_names_versions_and_node_tags_are_rejected() {
    assert!(parse_msh(MSH22).is_ok());
    let names = "2\n1 7 \"fixed side\"\n2 9 \"plate\"";
    let with_names = |new: &str| MSH22.replacen(names, new, 1);
    // One name for two groups of one dimension would merge them.
    let twice = with_names("3\n1 7 \"side\"\n1 8 \"side\"\n2 9 \"plate\"");
    let result = parse_msh(&twice);
    assert!(format!("{result:?}").contains("side"), "{result:?}");
    assert_eq!(parse_error_line(result), 7);
    // One group named twice.
    let renamed = with_names("3\n1 7 \"a\"\n1 7 \"b\"\n2 9 \"plate\"");
    assert_eq!(parse_error_line(parse_msh(&renamed)), 7);
    // A name for a group that no element belongs to (a misspelt tag).
    let ghost = with_names("3\n1 7 \"fixed side\"\n1 5 \"ghost\"\n2 9 \"plate\"");
    let result = parse_msh(&ghost);
    assert!(format!("{result:?}").contains("ghost"), "{result:?}");
    assert_eq!(parse_error_line(result), 7);
    // Only the versions this reader knows.
    for version in ["2.0", "2.1", "2"] {
        let old = MSH22.replacen("2.2 0 8", &format!("{version} 0 8"), 1);
        let result = parse_msh(&old);
        assert!(format!("{result:?}").contains("line 2"), "{result:?}");
        assert!(is_unsupported(result), "{version}");
    }
    // Gmsh node tags start at 1.
    let zero = MSH22.replacen("4 0 1 0\n", "0 0 1 0\n", 1);
    assert_eq!(parse_error_line(parse_msh(&zero)), 14);
}

#[test]
fn msh22_is_read() {
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n\
                $PhysicalNames\n2\n1 7 \"fixed side\"\n2 9 \"plate\"\n$EndPhysicalNames\n\
                $Nodes\n4\n1 0 0 0\n2 2 0 0\n3 2 1 0\n4 0 1 0\n$EndNodes\n\
                $Elements\n5\n1 1 2 7 1 1 2\n2 1 2 8 2 3 4\n3 15 2 0 1 1\n\
                4 2 2 9 1 1 2 3\n5 2 2 9 1 1 3 4\n$EndElements\n";
    let mesh = parse_msh(text).expect("reads");
    assert_eq!(mesh.num_nodes(), 4);
    assert_eq!(mesh.num_cells(), 2);
    // Unnamed physical groups are named by their tag; physical tag 0 means none.
    let names: Vec<&str> = mesh.boundaries().keys().map(String::as_str).collect();
    assert_eq!(names, ["8", "fixed side"]);
    assert!(mesh.node_sets().is_empty());
    let edge = mesh.boundary("8").expect("boundary 8")[0];
    assert_eq!(mesh.edge_normal(&edge).0, [0.0, 1.0]);
}

#[test]
fn half_disc_example_reads() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/meshes/half_disc.msh");
    let mesh = read_msh(&path).expect("half_disc.msh reads");
    assert_eq!(mesh.order(), Order::P1);
    assert!(
        (3000..=8000).contains(&mesh.num_cells()),
        "{}",
        mesh.num_cells()
    );
    for e in 0..mesh.num_cells() {
        assert!(signed_area2(&mesh, e) > 0.0);
    }
    let names: Vec<&str> = mesh.boundaries().keys().map(String::as_str).collect();
    assert_eq!(names, ["arc", "top"]);
    let contact = node_at(&mesh, [0.0, 0.0]);
    let centre = [0.0, 1.0];
    let mut arc_length = 0.0;
    let mut shortest = f64::INFINITY;
    for edge in mesh.boundary("arc").expect("arc") {
        let (n, len) = mesh.edge_normal(edge);
        let p = mesh.nodes()[edge.a];
        assert!(((p[0] - centre[0]).hypot(p[1] - centre[1]) - 1.0).abs() < 1e-12);
        // Outward: along the radius.
        assert!(n[0] * (p[0] - centre[0]) + n[1] * (p[1] - centre[1]) > 0.9);
        arc_length += len;
        if edge.a == contact || edge.b == contact {
            shortest = shortest.min(len);
        }
    }
    assert!(
        (arc_length - std::f64::consts::PI).abs() < 1e-2,
        "{arc_length}"
    );
    assert!(
        shortest < 1.0 / 150.0,
        "edge at the contact point: {shortest}"
    );
    let mut top_length = 0.0;
    for edge in mesh.boundary("top").expect("top") {
        let (n, len) = mesh.edge_normal(edge);
        assert!(n[1] > 1.0 - 1e-12 && mesh.nodes()[edge.a][1] == 1.0);
        top_length += len;
    }
    assert!((top_length - 2.0).abs() < 1e-12);
}

// The `gmsh_*.msh` files were written by gmsh 4.15.2 itself (OpenCASCADE rectangle 2 x 1, mesh
// size 0.3, physical groups named after the sides, physical point "origin", surface "plate").

/// Total length of boundary `name`.
fn boundary_length(mesh: &Mesh, name: &str) -> f64 {
    let edges = mesh.boundary(name).expect("boundary exists");
    edges.iter().map(|e| mesh.edge_normal(e).1).sum()
}

#[test]
fn gmsh_files_read() {
    for (file, order) in [
        ("gmsh_rect_v22.msh", Order::P1),
        ("gmsh_plate_hole.msh", Order::P1),
        ("gmsh_rect_p2_clockwise.msh", Order::P2),
    ] {
        let mesh = read_msh(&data(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(mesh.order(), order, "{file}");
        for e in 0..mesh.num_cells() {
            assert!(signed_area2(&mesh, e) > 0.0, "{file}");
        }
        for (name, length) in [("bottom", 2.0), ("top", 2.0), ("left", 1.0), ("right", 1.0)] {
            assert!(
                (boundary_length(&mesh, name) - length).abs() < 1e-12,
                "{file}: {name}"
            );
        }
        let origin = node_at(&mesh, [0.0, 0.0]);
        assert_eq!(
            mesh.node_sets().get("origin"),
            Some(&vec![origin]),
            "{file}"
        );
        for edge in mesh.boundary("bottom").expect("bottom") {
            assert_eq!(mesh.edge_normal(edge).0, [0.0, -1.0], "{file}");
        }
    }
    // The hole (radius 0.2 at (1, 0.5)): outward normals of the body point into the hole.
    let mesh = read_msh(&data("gmsh_plate_hole.msh")).expect("reads");
    for edge in mesh.boundary("hole").expect("hole") {
        let (n, _) = mesh.edge_normal(edge);
        let p = mesh.nodes()[edge.a];
        assert!(((p[0] - 1.0).hypot(p[1] - 0.5) - 0.2).abs() < 1e-9);
        assert!(n[0] * (p[0] - 1.0) + n[1] * (p[1] - 0.5) < -0.15);
    }
}

#[test]
fn truncated_files_are_errors_not_panics() {
    let text = square_text();
    let half = text.len() / 2;
    let line = parse_error_line(parse_msh(&text[..half]));
    assert_eq!(line, text[..half].lines().count() + 1);
    // Every shorter prefix, cut at any character, fails cleanly.
    for cut in 0..text.len() - 1 {
        if text.is_char_boundary(cut) {
            assert!(parse_msh(&text[..cut]).is_err(), "prefix of {cut} bytes");
        }
    }
}

#[test]
fn missing_end_nodes_is_a_parse_error() {
    let text = square_text();
    let text = replace_line(&text, line_index(&text, "$EndNodes"), "");
    let line = parse_error_line(parse_msh(&text));
    assert_eq!(line, line_index(&text, "$Elements") + 1);
}

#[test]
fn bad_numbers_give_their_line() {
    let text = square_text();
    let index = line_index(&text, "0.5 0.5 0");
    let line = parse_error_line(parse_msh(&replace_line(&text, index, "0.5 zero 0")));
    assert_eq!(line, index + 1);
    let line = parse_error_line(parse_msh(&replace_line(&text, index, "0.5 nan 0")));
    assert_eq!(line, index + 1);
    let index = line_index(&text, "13 5 6 20");
    let line = parse_error_line(parse_msh(&replace_line(&text, index, "13 5 6 -20")));
    assert_eq!(line, index + 1);
}

#[test]
fn unknown_node_gives_the_element_line() {
    let text = square_text();
    let index = line_index(&text, "13 5 6 20");
    let line = parse_error_line(parse_msh(&replace_line(&text, index, "13 5 6 999")));
    assert_eq!(line, index + 1);
    // A line element on a node that no triangle uses.
    let index = line_index(&text, "3 5 2");
    let line = parse_error_line(parse_msh(&replace_line(&text, index, "3 5 30")));
    assert_eq!(line, index + 1);
}

#[test]
fn wrong_counts_are_parse_errors() {
    let text = square_text();
    let index = line_index(&text, "10 10 1 30");
    assert_eq!(
        parse_error_line(parse_msh(&replace_line(&text, index, "10 11 1 30"))),
        index + 1
    );
    let index = line_index(&text, "6 17 1 17");
    assert_eq!(
        parse_error_line(parse_msh(&replace_line(&text, index, "6 16 1 17"))),
        index + 1
    );
}

#[test]
fn unsupported_content_is_reported() {
    let text = square_text();
    let format = line_index(&text, "4.1 0 8");
    assert!(is_unsupported(parse_msh(&replace_line(
        &text, format, "4.1 1 8"
    ))));
    assert!(is_unsupported(parse_msh(&replace_line(
        &text, format, "3.0 0 8"
    ))));
    // A node off the z = 0 plane.
    let index = line_index(&text, "0.5 0.5 0");
    assert!(is_unsupported(parse_msh(&replace_line(
        &text,
        index,
        "0.5 0.5 0.1"
    ))));
    // Quadrilaterals and tetrahedra.
    let block = line_index(&text, "2 1 2 8");
    let quads = replace_line(&text, block, "2 1 3 8");
    assert!(is_unsupported(parse_msh(&quads)));
    let tets = replace_line(&text, block, "3 1 4 8");
    assert!(is_unsupported(parse_msh(&tets)));
    // No triangles at all.
    let points_only = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 0 0\n\
                       $EndNodes\n$Elements\n1 1 1 1\n0 1 15 1\n1 1\n$EndElements\n";
    assert!(is_unsupported(parse_msh(points_only)));
}

#[test]
fn mixed_orders_are_rejected() {
    let p2 = std::fs::read_to_string(data("square_p2.msh")).expect("square_p2.msh");
    // Turn the first P2 triangle into a P1 one in its own block.
    let block = line_index(&p2, "2 1 9 8");
    let mut lines: Vec<String> = p2.lines().map(str::to_string).collect();
    lines[block] = "2 1 9 7".to_string();
    let first: Vec<String> = lines[block + 1]
        .split_whitespace()
        .take(4)
        .map(str::to_string)
        .collect();
    lines.remove(block + 1);
    lines.insert(block, format!("2 1 2 1\n{}", first.join(" ")));
    let header = line_index(&p2, "6 17 1 17");
    lines[header] = "7 17 1 17".to_string();
    let text = lines.join("\n") + "\n";
    assert!(is_unsupported(parse_msh(&text)), "{:?}", parse_msh(&text));
}

#[test]
fn comments_and_unknown_sections_are_skipped() {
    let text = square_text().replace(
        "$Nodes",
        "$Comments\nanything \"$Nodes\" here\n$EndComments\n$NodeData\n1\n\"x\"\n$EndNodeData\n$Nodes",
    );
    assert_eq!(parse_msh(&text).expect("reads").num_cells(), 8);
}

#[test]
fn mutated_files_never_panic() {
    let text = square_text();
    let bytes = text.as_bytes();
    let replacements: &[&[u8]] = &[
        b"",
        b"9",
        b"-1",
        b" ",
        b"\n",
        b"$",
        b"1e999",
        b"18446744073709551616",
    ];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move |bound: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % bound as u64) as usize
    };
    for _ in 0..3000 {
        let mut mutated = bytes.to_vec();
        for _ in 0..1 + next(3) {
            let at = next(mutated.len());
            let len = next(4).min(mutated.len() - at);
            let with = replacements[next(replacements.len())];
            mutated.splice(at..at + len, with.iter().copied());
        }
        // Any outcome but a panic is fine.
        let _ = parse_msh(&String::from_utf8_lossy(&mutated));
    }
}

#[test]
fn io_errors_name_the_file() {
    match read_msh(Path::new("/nonexistent/mesh.msh")) {
        Err(GmshError::Io { path, .. }) => assert_eq!(path, "/nonexistent/mesh.msh"),
        other => panic!("expected an I/O error, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Several bodies in one file (two_blocks.msh, written by make_two_blocks.py).

fn two_blocks(surface: Option<&str>) -> Result<Mesh, GmshError> {
    read_msh_surface(&data("two_blocks.msh"), surface)
}

fn names<T>(map: &std::collections::BTreeMap<String, T>) -> Vec<&str> {
    map.keys().map(String::as_str).collect()
}

#[test]
fn a_surface_picks_its_body_and_the_curves_that_touch_it() {
    for (name, y0, curves, sets) in [
        ("lower", 0.0, ["floor", "left", "lower-top"], vec!["origin"]),
        ("upper", 1.0, ["left", "load", "upper-bottom"], vec![]),
    ] {
        let mesh = two_blocks(Some(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        // 4 × 2 cells of two triangles, 5 × 3 nodes, all in the block.
        assert_eq!((mesh.num_cells(), mesh.num_nodes()), (16, 15), "{name}");
        for p in mesh.nodes() {
            assert!(p[1] >= y0 && p[1] <= y0 + 1.0, "{name}: node {p:?}");
        }
        assert_eq!(names(mesh.boundaries()), curves, "{name}");
        assert_eq!(names(mesh.node_sets()), sets, "{name}");
        // "left" spans both bodies in the file; each body gets its own side, of length 1.
        assert!(
            (boundary_length(&mesh, "left") - 1.0).abs() < 1e-12,
            "{name}"
        );
    }
}

#[test]
fn several_surfaces_need_a_choice_and_unknown_ones_are_listed() {
    let message = two_blocks(None).expect_err("two bodies").to_string();
    for part in ["2 bodies", "lower, upper"] {
        assert!(message.contains(part), "{message}");
    }
    let message = two_blocks(Some("disc")).expect_err("no disc").to_string();
    for part in ["'disc'", "lower, upper"] {
        assert!(message.contains(part), "{message}");
    }
    // A file with one physical surface reads as before with or without its name.
    let by_name = read_msh_surface(&data("square.msh"), Some("body")).expect("square by name");
    assert_eq!(by_name.nodes(), square().nodes());
    let message = parse_msh_surface(&square_text(), Some("lower"))
        .expect_err("square has no surface 'lower'")
        .to_string();
    assert!(message.contains("physical surfaces: body"), "{message}");
}

#[test]
fn missing_surfaces_and_boundaries_say_what_to_do() {
    // Physical curves without a physical surface: Gmsh saves no triangles.
    let text = square_text();
    let start = line_index(&text, "2 1 2 8");
    let lines: Vec<&str> = text.lines().collect();
    let mut kept: Vec<&str> = lines[..start].to_vec();
    kept.extend_from_slice(&lines[start + 9..]);
    let text = kept
        .join("\n")
        .replace("6 17 1 17", "5 9 1 9")
        .replace("2 10 \"body\"\n", "");
    let text = text.replace("$PhysicalNames\n6", "$PhysicalNames\n5");
    let message = parse_msh(&text).expect_err("no triangles").to_string();
    assert!(message.contains("Physical Surface"), "{message}");
    // A mesh without named boundaries says where names come from.
    let plain = square();
    let bare = Mesh::new(
        plain.nodes().to_vec(),
        plain.order(),
        plain.cells().to_vec(),
        Default::default(),
        Default::default(),
    )
    .expect("valid");
    let message = bare
        .boundary("bottom")
        .expect_err("no boundaries")
        .to_string();
    assert!(message.contains("physical curves"), "{message}");
}

#[test]
fn curved_p2_triangles_are_read_and_folded_ones_refused_with_their_line() {
    let text = std::fs::read_to_string(data("square_p2.msh")).expect("square_p2.msh");
    // Node 2 is the mid-side node of the bottom edge from (0, 0) to (0.5, 0): bow it outwards, as
    // Gmsh does on a curved boundary.
    let at = line_index(&text, "0.25 0.0 0");
    let bowed = parse_msh(&replace_line(&text, at, "0.25 -0.02 0")).expect("a curved P2 mesh");
    assert!(bowed.is_curved());
    let straight = parse_msh(&text).expect("square_p2.msh");
    assert!(!straight.is_curved());
    // Pulled deep into its triangle, the node folds it.
    let folded = replace_line(&text, at, "0.25 0.45 0");
    let message = match parse_msh(&folded) {
        Err(GmshError::Unsupported(m)) => m,
        other => panic!("expected unsupported, got {other:?}"),
    };
    assert!(message.contains("folded"), "{message}");
    // The reported line holds a triangle that uses node 2.
    let line: usize = message
        .trim_start_matches("line ")
        .split(':')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no line in {message}"));
    let element = text.lines().nth(line - 1).expect("line in file");
    assert!(
        element.split_whitespace().skip(1).any(|n| n == "2"),
        "line {line}: {element}"
    );
}

/// A triangle listed twice (its three vertices again, in any order) would be assembled twice; it
/// is refused with the line of the repeat.
#[test]
fn a_repeated_triangle_is_refused() {
    let text = square_text();
    let i = line_index(&text, "11 1 20 8");
    // Element 10 is the triangle 1 5 20.
    let repeated = replace_line(&text, i, "11 5 20 1");
    assert_eq!(parse_error_line(parse_msh(&repeated)), i + 1);
    match parse_msh(&repeated) {
        Err(e) => assert!(e.to_string().contains("same three vertices"), "{e}"),
        Ok(_) => panic!("accepted"),
    }
    assert!(parse_msh(&text).is_ok());
}

/// A triangle on the same three points as another, through a copy of one of its nodes (node 31
/// at node 1's position), is refused too, naming both element tags.
#[test]
fn a_triangle_repeated_on_copied_nodes_is_refused() {
    let text = square_text()
        .replace("10 10 1 30\n", "10 11 1 31\n")
        .replace(
            "2 1 0 1\n20\n0.5 0.5 0\n",
            "2 1 0 2\n20\n31\n0.5 0.5 0\n0 0 0\n",
        );
    assert!(
        parse_msh(&text).is_ok(),
        "the copied node alone is harmless"
    );
    // Element 11 (1 20 8) becomes 31 5 20: element 10 (1 5 20) again.
    let i = line_index(&text, "11 1 20 8");
    let repeated = replace_line(&text, i, "11 31 5 20");
    assert_eq!(parse_error_line(parse_msh(&repeated)), i + 1);
    let message = parse_msh(&repeated).unwrap_err().to_string();
    assert!(
        message.contains("triangles 10 (line") && message.contains("and 11 have the same"),
        "{message}"
    );
}

/// A physical name with a terminal escape, or of a megabyte, is refused with the name escaped and
/// cut in the message.
#[test]
fn hostile_physical_names_are_refused_and_shown_safely() {
    let text = square_text();
    let i = line_index(&text, "1 1 \"left\"");
    for (name, shown) in [
        ("le\u{1b}[2Jft".to_string(), "le\\u{1b}[2Jft"),
        ("x".repeat(1 << 20), "bytes)"),
    ] {
        let bad = replace_line(&text, i, &format!("1 1 \"{name}\""));
        assert_eq!(parse_error_line(parse_msh(&bad)), i + 1);
        let message = parse_msh(&bad).unwrap_err().to_string();
        assert!(message.contains(shown), "{message}");
        assert!(
            message.len() < 400 && !message.contains('\u{1b}'),
            "{message}"
        );
    }
    // A long unknown token is cut too.
    let junk = replace_line(&text, 0, &"$".repeat(1 << 20));
    let message = parse_msh(&junk).unwrap_err().to_string();
    assert!(message.len() < 400, "{} bytes", message.len());
}
