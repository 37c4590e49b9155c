//! Floating bodies in space: a block without supports pressed into a corner of three walls by
//! pressures on its other three faces. Only the frictionless contacts hold it, along all six
//! rigid motions. The decomposition (the block pinned at six DOFs, the motions' amplitudes in its
//! Newton system) against the monolithic reference and against statics: every wall's normal
//! force equals the pressure times the face's area, the same Newton steps, the same pressures; the
//! independent force balance holds. With the walls a gap away at the start, both first close the
//! block's points of smallest gap until they hold it.

use contactdd_core::solid::assembly::add_face_traction;
use contactdd_core::solid::element::elasticity_matrix;
use contactdd_core::solid::{dof, BoxMesh, SolidMesh, TetOrder};
use contactdd_ddm::solid_balance::solid_balance;
use contactdd_ddm::solid_dd::solve_solid_dd;
use contactdd_ddm::solid_monolithic::{
    solve_solid_monolithic, SolidBodySpec, SolidContactSolution, SolidPairSpec,
};

const PRESSURE: [f64; 3] = [30.0, 20.0, 50.0];

fn boxed(origin: [f64; 3], size: [f64; 3], cells: [usize; 3], order: TetOrder) -> SolidMesh {
    BoxMesh {
        origin,
        size,
        cells,
        order,
    }
    .mesh()
    .unwrap()
}

/// The block [0, 1]³ and the walls behind its faces x-, y-, z-, each `gap` away.
fn meshes(order: TetOrder, gap: f64) -> Vec<SolidMesh> {
    let mut m = vec![boxed([0.0; 3], [1.0; 3], [3, 3, 3], order)];
    for axis in 0..3 {
        let mut origin = [0.0; 3];
        let mut size = [1.0; 3];
        let mut cells = [4, 4, 4];
        origin[axis] = -0.5 - gap;
        size[axis] = 0.5;
        cells[axis] = 2;
        m.push(boxed(origin, size, cells, order));
    }
    m
}

fn problem(m: &[SolidMesh]) -> (Vec<SolidBodySpec<'_>>, Vec<SolidPairSpec>) {
    let faces = [["x-", "x+"], ["y-", "y+"], ["z-", "z+"]];
    let d = elasticity_matrix(2.1e5, 0.3).unwrap();
    let mut load = vec![0.0; 3 * m[0].num_nodes()];
    for (axis, [_, high]) in faces.iter().enumerate() {
        let p = PRESSURE[axis];
        add_face_traction(&m[0], high, |_, n| n.map(|c| -p * c), &mut load).unwrap();
    }
    let mut bodies = vec![SolidBodySpec {
        mesh: &m[0],
        elasticity: d,
        prescribed: Vec::new(),
        load,
    }];
    for (axis, mesh) in m[1..].iter().enumerate() {
        let mut nodes = mesh.face(faces[axis][0]).unwrap().to_vec();
        nodes.sort_unstable();
        nodes.dedup();
        bodies.push(SolidBodySpec {
            mesh,
            elasticity: d,
            prescribed: (nodes.iter())
                .flat_map(|&v| (0..3).map(move |c| (dof(v, c), 0.0)))
                .collect(),
            load: vec![0.0; 3 * mesh.num_nodes()],
        });
    }
    let pairs = (0..3)
        .map(|axis| SolidPairSpec {
            reference: (0, faces[axis][0].into()),
            partner: (axis + 1, faces[axis][1].into()),
            theta: 1e-6,
            search: 0.2,
            enforcement: Default::default(),
            friction: Default::default(),
        })
        .collect();
    (bodies, pairs)
}

/// Each pair's normal force Σ w p: the pressure on the opposite face times its area (1).
fn forces(sol: &SolidContactSolution) -> [f64; 3] {
    std::array::from_fn(|k| {
        (sol.points.iter())
            .filter(|p| p.pair == k)
            .map(|p| p.weight * p.pressure)
            .sum()
    })
}

#[test]
fn a_block_in_a_corner_is_held_by_its_contacts_alone() {
    for (order, gap) in [
        (TetOrder::P1, 0.0),
        (TetOrder::P2, 0.0),
        (TetOrder::P1, 1e-4),
    ] {
        let m = meshes(order, gap);
        let (bodies, pairs) = problem(&m);
        let dd = solve_solid_dd(&bodies, &pairs).unwrap();
        let reference = solve_solid_monolithic(&bodies, &pairs).unwrap();
        assert_eq!(
            dd.newton_steps, reference.newton_steps,
            "{order:?} gap {gap}"
        );
        let peak = dd.points.iter().map(|p| p.pressure).fold(0.0, f64::max);
        for (a, b) in dd.points.iter().zip(&reference.points) {
            assert!(
                (a.pressure - b.pressure).abs() < 1e-8 * peak,
                "{order:?} gap {gap}"
            );
        }
        for (k, f) in forces(&dd).into_iter().enumerate() {
            assert!(
                (f - PRESSURE[k]).abs() < 1e-9 * PRESSURE[k],
                "{order:?} {k}: {f}"
            );
        }
        let check = solid_balance(&bodies, &pairs, &dd).unwrap();
        assert!(check.worst() < 1e-10, "{order:?}: {:?}", check.bodies);
        assert!(check.contact_law < 1e-8, "{order:?}: {}", check.contact_law);
        eprintln!("{order:?} gap {gap}: {} Newton steps", dd.newton_steps);
    }
}

/// Without the wall behind z-, nothing resists the block's motion along z: the decomposition
/// names the body instead of dividing by zero.
#[test]
fn a_block_nothing_holds_is_named() {
    let m = meshes(TetOrder::P1, 0.0);
    let (bodies, mut pairs) = problem(&m);
    pairs.pop();
    let err = solve_solid_dd(&bodies, &pairs).unwrap_err().to_string();
    assert!(
        err.contains("body 0") && err.contains("do not hold it"),
        "{err}"
    );
}
