//! The monolithic reference in space (`contactdd::ddm::solid_monolithic`) and the decomposition
//! (`solid_dd`, where both bodies are held) against closed forms: two boxes stacked with a gap,
//! the upper one's top moved down.
//!
//! The lower box (height H_A, modulus E_A) rests on rollers on its floor, the upper box (height
//! H_B, modulus E_B, its bottom a gap g above the lower box's top) has its top moved down by δ;
//! both have rollers on their x− and y− faces and are free on x+ and y+. The state is uniaxial
//! and linear in both bodies, so the discrete solution is exact: no contact while δ ≤ g, and
//! otherwise the uniform pressure p = (δ − g)/(θ + H_A/E_A + H_B/E_B).

use contactdd_core::solid::assembly::add_face_traction;
use contactdd_core::solid::element::elasticity_matrix;
use contactdd_core::solid::{dof, BoxMesh, SolidMesh, TetOrder};
use contactdd_ddm::solid_dd::solve_solid_dd;
use contactdd_ddm::solid_monolithic::{solve_solid_monolithic, SolidBodySpec, SolidPairSpec};

const MATERIALS: [(f64, f64); 2] = [(2.1e5, 0.3), (7.0e4, 0.33)];
const HEIGHTS: [f64; 2] = [1.0, 0.7];

fn boxes(cells: [[usize; 3]; 2], order: TetOrder, gap: f64) -> [SolidMesh; 2] {
    let make = |origin, h: f64, cells| {
        BoxMesh {
            origin,
            size: [1.0, 1.0, h],
            cells,
            order,
        }
        .mesh()
        .unwrap()
    };
    [
        make([0.0, 0.0, -HEIGHTS[0]], HEIGHTS[0], cells[0]),
        make([0.0, 0.0, gap], HEIGHTS[1], cells[1]),
    ]
}

/// The DOFs of `component` on face `name`, each prescribed to `value`.
fn on_face(mesh: &SolidMesh, name: &str, component: usize, value: f64) -> Vec<(usize, f64)> {
    let mut nodes = mesh.face(name).unwrap().to_vec();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
        .into_iter()
        .map(|v| (dof(v, component), value))
        .collect()
}

/// The stack with the upper top moved by −δ (or pressed by `pressure` when given instead).
fn stack(meshes: &[SolidMesh; 2], delta: Option<f64>, pressure: f64) -> Vec<SolidBodySpec<'_>> {
    let mut specs = Vec::new();
    for (b, mesh) in meshes.iter().enumerate() {
        let (e, nu) = MATERIALS[b];
        let mut prescribed = on_face(mesh, "x-", 0, 0.0);
        prescribed.extend(on_face(mesh, "y-", 1, 0.0));
        let mut load = vec![0.0; 3 * mesh.num_nodes()];
        match (b, delta) {
            (0, _) => prescribed.extend(on_face(mesh, "z-", 2, 0.0)),
            (_, Some(d)) => prescribed.extend(on_face(mesh, "z+", 2, -d)),
            (_, None) => {
                add_face_traction(mesh, "z+", |_, _| [0.0, 0.0, -pressure], &mut load).unwrap()
            }
        }
        specs.push(SolidBodySpec {
            mesh,
            elasticity: elasticity_matrix(e, nu).unwrap(),
            prescribed,
            load,
        });
    }
    specs
}

fn pair(theta: f64) -> Vec<SolidPairSpec> {
    vec![SolidPairSpec {
        reference: (0, "z+".into()),
        partner: (1, "z-".into()),
        theta,
        search: 0.5,
        enforcement: Default::default(),
        friction: Default::default(),
    }]
}

/// Moved by less than the gap, nothing touches; moved further, every point carries the closed
/// form's pressure, on non-matching P1 and P2 meshes at two penalties.
#[test]
fn a_gap_closes_only_when_the_approach_exceeds_it() {
    let gap = 1e-3;
    for (order, theta) in [
        (TetOrder::P1, 1e-5),
        (TetOrder::P1, 1e-8),
        (TetOrder::P2, 1e-6),
    ] {
        let meshes = boxes([[3, 3, 2], [4, 5, 2]], order, gap);
        let open =
            solve_solid_monolithic(&stack(&meshes, Some(0.5 * gap), 0.0), &pair(theta)).unwrap();
        assert!(open.points.iter().all(|p| p.pressure == 0.0));
        assert!(open.newton_steps <= 2, "{} steps", open.newton_steps);
        let delta = 3.0 * gap;
        let compliance = theta + HEIGHTS[0] / MATERIALS[0].0 + HEIGHTS[1] / MATERIALS[1].0;
        let exact = (delta - gap) / compliance;
        let side = if order == TetOrder::P1 { 4 } else { 7 };
        let specs = stack(&meshes, Some(delta), 0.0);
        let mono = solve_solid_monolithic(&specs, &pair(theta)).unwrap();
        let dd = solve_solid_dd(&specs, &pair(theta)).unwrap();
        for sol in [mono, dd] {
            assert_eq!(sol.points.len(), side * side);
            for p in &sol.points {
                assert!(
                    (p.pressure / exact - 1.0).abs() < 1e-9,
                    "{p:?} against {exact}"
                );
                assert!((p.gap - gap).abs() < 1e-15);
            }
            assert!(sol.newton_steps <= 3, "{} steps", sol.newton_steps);
        }
    }
}

/// A floating upper box pressed by P: held only by the contact, every point carries P, on P1
/// and on P2 meshes (whose sides read their own quadratic shape functions through the mortar
/// rows: piecewise-linear multipliers would load a 6-node triangle's corners unlike a uniform
/// pressure does, and the pressures would then spread from 0.94 P to 3.8 P).
#[test]
fn a_pressed_floating_box_carries_the_pressure_exactly() {
    for order in [TetOrder::P1, TetOrder::P2] {
        for cells in [[[5, 4, 2], [3, 3, 3]], [[3, 3, 2], [3, 3, 2]]] {
            let meshes = boxes(cells, order, 0.0);
            let sol = solve_solid_monolithic(&stack(&meshes, None, 3.0), &pair(1e-6)).unwrap();
            for p in &sol.points {
                assert!((p.pressure / 3.0 - 1.0).abs() < 1e-8, "{order:?} {p:?}");
            }
            let force: f64 = sol.points.iter().map(|p| p.pressure * p.weight).sum();
            assert!((force / 3.0 - 1.0).abs() < 1e-10, "{force}");
        }
    }
}

/// A pair naming a face that does not exist is refused with the face's name.
#[test]
fn a_missing_face_is_refused() {
    let meshes = boxes([[2, 2, 1], [2, 2, 1]], TetOrder::P1, 0.0);
    let mut pairs = pair(1e-6);
    pairs[0].partner.1 = "bottom".into();
    let err = solve_solid_monolithic(&stack(&meshes, Some(0.0), 0.0), &pairs).unwrap_err();
    assert!(err.to_string().contains("bottom"), "{err}");
}

/// A press fit: the boxes overlap by o at the start and nothing moves them; both solvers find
/// the closed form's pressure o/(θ + H_A/E_A + H_B/E_B) at every point, P1 and P2.
#[test]
fn an_initial_overlap_is_pressed_apart_by_the_closed_form_pressure() {
    let overlap = 1e-3;
    for order in [TetOrder::P1, TetOrder::P2] {
        let meshes = boxes([[3, 3, 2], [4, 5, 2]], order, -overlap);
        let theta = 1e-6;
        let compliance = theta + HEIGHTS[0] / MATERIALS[0].0 + HEIGHTS[1] / MATERIALS[1].0;
        let exact = overlap / compliance;
        let specs = stack(&meshes, Some(0.0), 0.0);
        let mono = solve_solid_monolithic(&specs, &pair(theta)).unwrap();
        let dd = solve_solid_dd(&specs, &pair(theta)).unwrap();
        for sol in [mono, dd] {
            for p in &sol.points {
                assert!(
                    (p.pressure / exact - 1.0).abs() < 1e-9,
                    "{p:?} against {exact}"
                );
                assert!((p.gap + overlap).abs() < 1e-15);
            }
        }
    }
}
