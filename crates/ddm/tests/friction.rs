//! Coulomb and Tresca friction: a block pressed on a foundation and pushed sideways, against the
//! force balance of the block, the frictionless answer at μ = 0 and the laws' own conditions.

use contactdd_core::{
    Component, Constraints, Diagonal, ElasticBody, Load, Material, Mesh, Order, Plane, Rectangle,
};
use contactdd_ddm::*;

fn rect(x: [f64; 2], y: [f64; 2], nx: usize, ny: usize, order: Order) -> Mesh {
    Rectangle {
        origin: [x[0], y[0]],
        corner: [x[1], y[1]],
        nx,
        ny,
        diagonal: Diagonal::Right,
        mirror: false,
        order,
    }
    .mesh()
    .expect("a valid rectangle")
}

fn body(name: &str, mesh: Mesh, supports: &[(&str, Component)], loads: &[Load]) -> ElasticBody {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for &(b, c) in supports {
        constraints.fix(&mesh, b, c, 0.0).expect("a valid support");
    }
    let load = contactdd_core::loads::load_vector(&mesh, loads).expect("valid loads");
    ElasticBody {
        name: name.into(),
        mesh,
        material: Material::new(1000.0, 0.3).expect("a valid material"),
        plane: Plane::Strain,
        constraints,
        load,
    }
}

/// A 2 × 1 block (`upper` cells in x) on a 4 × 1 foundation clamped at its bottom, pressed by
/// `p` on its top and pushed by the traction `q` (force per length) on its left side; the block
/// has no support, so friction alone holds it sideways.
fn block(p: f64, q: f64, friction: Friction, upper: usize) -> Model {
    block_with(p, q, friction, upper, Order::P1)
}

/// [`block`] with elements of `order`.
fn block_with(p: f64, q: f64, friction: Friction, upper: usize, order: Order) -> Model {
    let lower = body(
        "foundation",
        rect([0.0, 4.0], [0.0, 1.0], 16, 4, order),
        &[("bottom", Component::X), ("bottom", Component::Y)],
        &[],
    );
    let loads = [
        Load::Pressure {
            boundary: "top".into(),
            value: p,
        },
        Load::Traction {
            boundary: "left".into(),
            value: [q, 0.0],
        },
    ];
    let upper = body(
        "block",
        rect([1.0, 3.0], [1.0, 2.0], upper, 4, order),
        &[],
        &loads,
    );
    Model {
        name: "block".into(),
        plane: Plane::Strain,
        bodies: vec![lower, upper],
        pairs: vec![ContactPair {
            name: "joint".into(),
            bodies: [0, 1],
            boundaries: ["top".into(), "bottom".into()],
            penalty: Penalty::RodModel { c: 0.05, h: 1.0 },
            profile: None,
            enforcement: Enforcement::Penalty,
            forces: Forces::Balanced,
            friction,
        }],
        remote: Vec::new(),
    }
}

fn run(model: &Model) -> Solution {
    let prepared = match prepare(model) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    solve(model, &prepared, &Settings::default(), Hooks::default()).expect("a valid model solves")
}

#[test]
fn a_block_that_friction_holds_balances_its_push() {
    let (p, q) = (10.0, 4.0);
    // N = 2 p = 20, Q = 1 · q = 4 < μN = 10.
    let sol = run(&block(p, q, Friction::Coulomb { mu: 0.5 }, 8));
    assert!(sol.converged, "{:?}", sol.message);
    balanced(&sol, p, q);
    // Q/N = 0.2 is far below μ = 0.5: every closed point sticks.
    let (stick, slip) = sol.contact[0].stick_slip_lengths();
    assert_eq!(slip, 0.0);
    assert!((stick - 2.0).abs() < 1e-9, "{stick}");
}

/// The contact forces on the block balance its loads: 2p down, q along x.
fn balanced(sol: &Solution, p: f64, q: f64) {
    let on_block = sol.contact[0].force_on(1);
    assert!((on_block[0] + q).abs() < 1e-8 * q, "{on_block:?}");
    assert!((on_block[1] - 2.0 * p).abs() < 1e-8 * p, "{on_block:?}");
    // The pair's resultant tangential force is the push (the foundation's surface is flat).
    let t = sol.contact[0].tangential_force();
    assert!((t.abs() - q).abs() < 1e-8 * q, "{t}");
}

/// Coulomb's conditions at every point: the traction within the disc, on its edge exactly where
/// the point slips.
fn coulomb(sol: &Solution, mu: f64) {
    let pair = &sol.contact[0];
    for i in 0..pair.status.len() {
        let (t, sn) = (pair.tangential[i], pair.pressure[i]);
        let bound = mu * (-sn).max(0.0);
        assert!(
            t.abs() <= bound * (1.0 + 1e-12),
            "point {i}: {t} beyond {bound}"
        );
        match pair.status[i] {
            FrictionStatus::Slip => assert!((t.abs() - bound).abs() <= 1e-12 * bound),
            FrictionStatus::Stick => assert!(t.abs() < bound),
            FrictionStatus::Open => assert_eq!(t, 0.0),
        }
    }
}

#[test]
fn partial_slip_keeps_coulombs_law_on_matching_and_non_matching_meshes() {
    let (p, q) = (10.0, 4.0);
    for (upper, order) in [(8, Order::P1), (11, Order::P1), (5, Order::P2)] {
        for mu in [0.21, 0.25, 0.3] {
            let sol = run(&block_with(p, q, Friction::Coulomb { mu }, upper, order));
            assert!(sol.converged, "{upper} {mu}: {:?}", sol.message);
            assert!(sol.iterations <= 30, "{upper} {mu}: {}", sol.iterations);
            balanced(&sol, p, q);
            coulomb(&sol, mu);
            let (stick, slip) = sol.contact[0].stick_slip_lengths();
            assert!(stick > 0.0 && slip > 0.0, "{upper} {mu}: {stick} {slip}");
        }
    }
}

#[test]
fn a_push_beyond_mu_n_slides_and_is_no_solution() {
    // N = 20, μN = 3 < Q = 4.
    let sol = run(&block(10.0, 4.0, Friction::Coulomb { mu: 0.15 }, 8));
    assert!(!sol.converged);
    assert!(
        matches!(
            sol.stop,
            Stop::Diverged {
                body: 1,
                reason: outcome::Breakdown::Slides,
                ..
            }
        ),
        "{:?}",
        sol.stop
    );
    let message = sol.message.unwrap_or_default();
    assert!(message.contains("'block' slides"), "{message}");
}

#[test]
fn tresca_friction_bounds_the_traction_by_its_bound() {
    // The bound 1.5 over the zone's length 2 holds at most 3 < 4: the block slides; 2.5 holds it.
    let sol = run(&block(10.0, 4.0, Friction::Tresca { bound: 1.5 }, 8));
    assert!(!sol.converged);
    let sol = run(&block(10.0, 4.0, Friction::Tresca { bound: 2.5 }, 8));
    assert!(sol.converged, "{:?}", sol.message);
    balanced(&sol, 10.0, 4.0);
    for (t, st) in sol.contact[0].tangential.iter().zip(&sol.contact[0].status) {
        assert!(t.abs() <= 2.5 * (1.0 + 1e-12));
        if *st == FrictionStatus::Slip {
            assert!((t.abs() - 2.5).abs() < 1e-12);
        }
    }
}

#[test]
fn bad_friction_parameters_are_refused_with_the_pair_named() {
    for friction in [
        Friction::Coulomb { mu: -0.1 },
        Friction::Coulomb { mu: f64::NAN },
        Friction::Tresca { bound: -1.0 },
    ] {
        let Err(e) = prepare(&block(10.0, 4.0, friction, 8)) else {
            panic!("{friction:?} accepted");
        };
        assert!(e.to_string().contains("'joint'"), "{e}");
    }
    let mut model = block(10.0, 4.0, Friction::Coulomb { mu: 0.3 }, 8);
    model.pairs[0].forces = Forces::OwnSide;
    let Err(e) = prepare(&model) else {
        panic!("own-side friction accepted");
    };
    assert!(e.to_string().contains("balanced"), "{e}");
}
