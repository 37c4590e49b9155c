//! The independent check of a solution in space (`contactdd::ddm::solid_balance`): on a solved
//! stack of two boxes every body balances to rounding and the pressures follow the contact law;
//! a pressure changed by 1 %, or a displacement moved off the solution, is caught.

use contactdd_core::solid::element::elasticity_matrix;
use contactdd_core::solid::{dof, BoxMesh, SolidMesh, TetOrder};
use contactdd_ddm::solid_balance::solid_balance;
use contactdd_ddm::solid_dd::solve_solid_dd;
use contactdd_ddm::solid_monolithic::{SolidBodySpec, SolidPairSpec};

fn face_dofs(mesh: &SolidMesh, name: &str, c: usize, value: f64) -> Vec<(usize, f64)> {
    let mut nodes = mesh.face(name).unwrap().to_vec();
    nodes.sort_unstable();
    nodes.dedup();
    nodes.into_iter().map(|v| (dof(v, c), value)).collect()
}

fn meshes(order: TetOrder) -> [SolidMesh; 2] {
    let make = |z: f64, n: usize| {
        BoxMesh {
            origin: [0.0, 0.0, z],
            size: [1.0, 1.0, 0.5],
            cells: [n, n, 2],
            order,
        }
        .mesh()
        .unwrap()
    };
    [make(-0.5, 3), make(0.0, 4)]
}

fn specs(m: &[SolidMesh; 2]) -> (Vec<SolidBodySpec<'_>>, Vec<SolidPairSpec>) {
    let bodies = (m.iter().enumerate())
        .map(|(b, mesh)| {
            let mut prescribed = face_dofs(mesh, "x-", 0, 0.0);
            prescribed.extend(face_dofs(mesh, "y-", 1, 0.0));
            let (face, value) = if b == 0 { ("z-", 0.0) } else { ("z+", -1e-3) };
            prescribed.extend(face_dofs(mesh, face, 2, value));
            SolidBodySpec {
                mesh,
                elasticity: elasticity_matrix(2.1e5, 0.3).unwrap(),
                prescribed,
                load: vec![0.0; 3 * mesh.num_nodes()],
            }
        })
        .collect();
    let pairs = vec![SolidPairSpec {
        reference: (0, "z+".into()),
        partner: (1, "z-".into()),
        theta: 1e-6,
        search: 0.2,
        enforcement: Default::default(),
        friction: Default::default(),
    }];
    (bodies, pairs)
}

#[test]
fn a_solution_balances_and_a_changed_one_does_not() {
    for order in [TetOrder::P1, TetOrder::P2] {
        let m = meshes(order);
        let (bodies, pairs) = specs(&m);
        let sol = solve_solid_dd(&bodies, &pairs).unwrap();
        let check = solid_balance(&bodies, &pairs, &sol).unwrap();
        assert!(check.worst() < 1e-12, "{order:?}: {:?}", check.bodies);
        assert!(
            check.contact_law < 1e-10,
            "{order:?}: {}",
            check.contact_law
        );
        // The support reactions carry the contact force: equal and opposite on the two bodies.
        let (r0, r1) = (check.bodies[0].reaction[2], check.bodies[1].reaction[2]);
        assert!(r0 > 0.0 && (r0 + r1).abs() < 1e-10 * r0, "{r0} {r1}");

        let mut wrong = sol.clone();
        wrong.points[0].pressure *= 1.01;
        let check = solid_balance(&bodies, &pairs, &wrong).unwrap();
        assert!(check.contact_law > 1e-3, "{order:?}: {}", check.contact_law);
        assert!(
            check.unbalanced(1e-6).is_some(),
            "{order:?}: {:?}",
            check.bodies
        );

        let mut moved = sol.clone();
        let free = (0..moved.displacements[1].len())
            .find(|i| !bodies[1].prescribed.iter().any(|(d, _)| d == i))
            .unwrap();
        moved.displacements[1][free] += 1e-5;
        let check = solid_balance(&bodies, &pairs, &moved).unwrap();
        assert_eq!(
            check.unbalanced(1e-6),
            Some(1),
            "{order:?}: {:?}",
            check.bodies
        );
    }
}
