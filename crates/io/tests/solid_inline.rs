//! A body in space written out in the problem file (`mesh = { kind = "inline", … }`) is the same
//! body as the mesher's: examples/space/blocks.toml with its upper box replaced by the box
//! mesher's nodes, tetrahedra and faces solves to the same pressures, bit for bit; a wrong node
//! count is refused with the body's name.

use std::path::Path;

use contactdd_core::solid::{BoxMesh, TetOrder};
use contactdd_io::solid_problem::SolidProblem;
use contactdd_io::solid_run::{run_solid, SolidSolver};
use contactdd_io::solid_setup::resolve_solid;

fn blocks() -> SolidProblem {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/space/blocks.toml");
    toml::from_str(&std::fs::read_to_string(file).unwrap()).unwrap()
}

/// The upper block's mesh as an inline table (TOML text).
fn inline_upper() -> String {
    let mesh = BoxMesh {
        origin: [0.0, 0.0, 0.5],
        size: [1.0, 1.0, 0.5],
        cells: [5, 5, 3],
        order: TetOrder::P2,
    }
    .mesh()
    .unwrap();
    let list = |v: &[usize]| format!("{v:?}");
    let nodes: Vec<String> = mesh.nodes().iter().map(|p| format!("{p:?}")).collect();
    let tets: Vec<String> = (0..mesh.num_tets()).map(|e| list(mesh.tet(e))).collect();
    let faces: Vec<String> = (mesh.face_names())
        .map(|name| {
            let tris: Vec<String> = mesh.face(name).unwrap().chunks(6).map(list).collect();
            format!("\"{name}\" = [{}]", tris.join(", "))
        })
        .collect();
    format!(
        "kind = \"inline\"\nnodes = [{}]\ntetrahedra = [{}]\n[faces]\n{}\n",
        nodes.join(", "),
        tets.join(", "),
        faces.join("\n")
    )
}

#[test]
fn an_inline_body_is_the_meshers_body() {
    let mut inline = blocks();
    inline.bodies[1].mesh = toml::from_str(&inline_upper()).unwrap();
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let a = resolve_solid(blocks(), base, "a").unwrap();
    let b = resolve_solid(inline, base, "b").unwrap();
    let (ra, rb) = (
        run_solid(&a, SolidSolver::Decomposition).unwrap(),
        run_solid(&b, SolidSolver::Decomposition).unwrap(),
    );
    assert!(ra.converged && rb.converged);
    assert_eq!(ra.solution.points.len(), rb.solution.points.len());
    for (p, q) in ra.solution.points.iter().zip(&rb.solution.points) {
        assert_eq!(p.pressure.to_bits(), q.pressure.to_bits());
    }
}

#[test]
fn a_tetrahedron_of_the_wrong_size_is_refused() {
    let mut problem = blocks();
    problem.bodies[1].mesh = toml::from_str(
        "kind = \"inline\"\nnodes = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\ntetrahedra = [[0, 1, 2, 3], [0, 1, 2]]\n",
    )
    .unwrap();
    let err = resolve_solid(problem, Path::new("."), "x").unwrap_err();
    assert!(
        err.contains("body 'upper'") && err.contains("tetrahedron 1"),
        "{err}"
    );
}
