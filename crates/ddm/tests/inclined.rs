//! A contact problem with inclined `normal` supports, solved by the domain decomposition and
//! compared with the same problem built axis-parallel (the plain elimination of the supports):
//! a quarter disc on a block, both cut by the symmetry line through the contact zone, so that the
//! first contact node of each body lies on its inclined symmetry support.

use contactdd_core::{
    dof, Component, Constraints, Diagonal, ElasticBody, Load, Material, Mesh, Order, Plane,
    Rectangle, Vector,
};
use contactdd_ddm::*;

fn rotation(angle_deg: f64) -> impl Fn(Vector) -> Vector + Copy {
    let (s, c) = angle_deg.to_radians().sin_cos();
    move |[x, y]| [c * x - s * y, s * x + c * y]
}

fn rect(nx: usize, ny: usize) -> Mesh {
    Rectangle {
        origin: [0.0, 0.0],
        corner: [1.0, 1.0],
        nx,
        ny,
        diagonal: Diagonal::Right,
        mirror: false,
        order: Order::P1,
    }
    .mesh()
    .unwrap()
}

fn graded(x: f64, beta: f64) -> f64 {
    (beta * x).sinh() / beta.sinh()
}

/// The quarter of a disc of radius 1 centred at (0, 1) with x ≥ 0 and y ≤ 1, less a small hole
/// at the centre. Boundaries: "left" the symmetry line x = 0, "right" the flat top y = 1,
/// "bottom" the arc touching y = 0 at the origin, "top" the hole.
fn quarter_disc() -> Mesh {
    let hole = 0.05;
    rect(40, 12)
        .map_nodes(|[s, q]| {
            let rad = 1.0 - (1.0 - hole) * graded(q, 3.0);
            let t = std::f64::consts::FRAC_PI_2 * (graded(s, 3.0) - 1.0);
            [rad * t.cos(), 1.0 + rad * t.sin()]
        })
        .unwrap()
}

fn body(name: &str, mesh: Mesh, supports: &[&str], loads: &[Load]) -> ElasticBody {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for b in supports {
        constraints.fix(&mesh, b, Component::Normal, 0.0).unwrap();
    }
    let load = contactdd_core::loads::load_vector(&mesh, loads).unwrap();
    ElasticBody {
        name: name.into(),
        mesh,
        material: Material::new(1000.0, 0.3).unwrap(),
        plane: Plane::Strain,
        constraints,
        load,
    }
}

/// The block [0, 1.5] × [−1, 0] on a sliding floor, the quarter disc pressed onto it, both held
/// by `normal` supports on the symmetry line x = 0; everything turned by `angle` degrees.
fn model(angle: f64) -> Model {
    let rot = rotation(angle);
    let block = rect(30, 12)
        .map_nodes(|[x, y]| rot([1.5 * x * x, y - 1.0]))
        .unwrap();
    let disc = quarter_disc().map_nodes(rot).unwrap();
    let block = body("block", block, &["left", "bottom"], &[]);
    let disc = body(
        "disc",
        disc,
        &["left"],
        &[Load::Pressure {
            boundary: "right".into(),
            value: 2.0,
        }],
    );
    Model {
        name: "quarter".into(),
        plane: Plane::Strain,
        bodies: vec![block, disc],
        pairs: vec![ContactPair {
            name: "quarter".into(),
            bodies: [0, 1],
            boundaries: ["top".into(), "bottom".into()],
            penalty: Penalty::Theta(1e-4),
            profile: None,
            enforcement: Enforcement::Penalty,
            // The paper's formulation: the axis-parallel and turned problems follow the same
            // sweeps; Anderson on the sparse path loses the contact on the turned balanced
            // problem (tests/balance.rs covers balanced pairs).
            forces: Forces::OwnSide,
            friction: Default::default(),
        }],
        remote: Vec::new(),
    }
}

/// Anderson-accelerated active-set sweeps (the relaxation alone needs tens of thousands of
/// sweeps here) or the interface Newton method.
fn run(model: &Model, accelerator: Accelerator, condensation: Condensation) -> Solution {
    // Own-side pairs on non-matching meshes carry different forces on their two sides: the
    // comparison of the two frames is the subject, not that imbalance.
    let own_side = model.pairs.iter().any(|p| p.forces == Forces::OwnSide);
    let settings = Settings {
        tol: 1e-12,
        max_iter: 2000,
        accelerator,
        condensation,
        balance_tol: own_side.then_some(1.0),
        ..Settings::anderson()
    };
    let prepared = prepare_with(model, condensation).unwrap();
    let sol = solve(model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(
        sol.converged,
        "{accelerator} {condensation:?}: {:?}",
        sol.message
    );
    sol
}

/// Pressure per (side, node) of the pair's points.
fn pressures(sol: &Solution) -> Vec<((usize, usize), f64)> {
    let p = &sol.contact[0];
    let mut v: Vec<_> = (0..p.node.len())
        .map(|i| ((p.side[i], p.node[i]), p.pressure[i]))
        .collect();
    v.sort_by_key(|e| e.0);
    v
}

#[test]
fn contact_with_inclined_symmetry_supports_matches_the_axis_parallel_problem() {
    let reference_model = model(0.0);
    assert!(reference_model
        .bodies
        .iter()
        .all(|b| b.constraints.inclined().count() == 0));
    let anderson = Settings::anderson().accelerator;
    for (accelerator, condensation) in [
        (anderson, Condensation::Dense),
        (anderson, Condensation::Sparse),
        (Accelerator::Newton, Condensation::Dense),
        (Accelerator::Newton, Condensation::Sparse),
    ] {
        let reference = run(&reference_model, accelerator, condensation);
        let p0 = pressures(&reference);
        let peak = p0.iter().fold(0.0f64, |m, e| m.max(e.1.abs()));
        let closed = p0.iter().filter(|e| e.1 < 0.0).count();
        assert!(closed >= 8, "{closed} closed points");
        for angle in [30.0, 117.0] {
            let turned = model(angle);
            // The first contact node of each body is on its inclined symmetry support.
            for (b, body) in turned.bodies.iter().enumerate() {
                let contact = &turned.pairs[0].boundaries[b];
                let on_both = body
                    .mesh
                    .boundary_nodes(contact)
                    .unwrap()
                    .into_iter()
                    .filter(|&v| body.constraints.inclined_normal(v).is_some())
                    .count();
                assert_eq!(on_both, 1, "{}", body.name);
            }
            let sol = run(&turned, accelerator, condensation);
            let p = pressures(&sol);
            assert_eq!(p.len(), p0.len());
            let diff = p
                .iter()
                .zip(&p0)
                .map(|(a, b)| {
                    assert_eq!(a.0, b.0);
                    (a.1 - b.1).abs()
                })
                .fold(0.0, f64::max);
            let rot = rotation(angle);
            let mut udiff = 0.0f64;
            let mut usize_ = 0.0f64;
            for (b0, b1) in reference.bodies.iter().zip(&sol.bodies) {
                let (u0, u1) = (&b0.displacement, &b1.displacement);
                for v in 0..u0.len() / 2 {
                    let e = rot([u0[dof(v, 0)], u0[dof(v, 1)]]);
                    udiff = udiff.max((u1[dof(v, 0)] - e[0]).hypot(u1[dof(v, 1)] - e[1]));
                    usize_ = usize_.max(e[0].hypot(e[1]));
                }
            }
            println!(
                "{accelerator} {condensation:?} {angle}°: {} iterations (axis-parallel {}), \
                 pressure difference {:.2e}, displacement difference {:.2e}",
                sol.iterations,
                reference.iterations,
                diff / peak,
                udiff / usize_
            );
            assert!(diff < 1e-8 * peak, "{angle}°: pressures differ by {diff}");
            assert!(
                udiff < 1e-8 * usize_,
                "{angle}°: displacements differ by {udiff}"
            );
        }
    }
}

#[test]
fn the_monolithic_reference_refuses_a_contact_node_on_an_inclined_support() {
    let err = match solve_monolithic(&model(30.0)) {
        Ok(_) => panic!("the corner must be refused"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("body 'block'") && err.contains("'top'") && err.contains("inclined"),
        "{err}"
    );
}
