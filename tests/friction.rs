//! Coulomb and Tresca friction (docs/friction.md): a block pressed on a foundation and pushed
//! sideways against the block's balance, Coulomb's and Tresca's conditions at every point, the
//! threshold of sliding, the exact law of the augmented Lagrangian; the interface Newton
//! method's iteration counts against μ and the penalty; a wall of frictional blocks.

use contactdd::ddm::outcome::Breakdown;
use contactdd::ddm::{
    prepare, solve, Enforcement, Forces, Friction, FrictionStatus, Hooks, Model, Settings,
    Solution, Stop,
};
use contactdd::fem::Order;
use contactdd::frictional::{block_on_foundation, sheared_wall};

/// The block of [`block_on_foundation`] with `upper` P1 cells and the paper's penalty factor.
fn block(p: f64, q: f64, friction: Friction, upper: usize) -> Model {
    block_on_foundation(p, q, friction, (upper, Order::P1), 0.05)
}

/// [`block`] with elements of `order`.
fn block_with(p: f64, q: f64, friction: Friction, upper: usize, order: Order) -> Model {
    block_on_foundation(p, q, friction, (upper, order), 0.05)
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
                reason: Breakdown::Slides,
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

#[test]
fn the_augmented_lagrangian_meets_coulombs_law_exactly_whatever_the_penalty() {
    let (p, q, mu) = (10.0, 4.0, 0.25);
    let solve_with = |c: f64, enforcement: Enforcement| {
        let mut model = block_on_foundation(p, q, Friction::Coulomb { mu }, (11, Order::P1), c);
        model.pairs[0].enforcement = enforcement;
        let sol = run(&model);
        assert!(sol.converged, "{c} {enforcement}: {:?}", sol.message);
        balanced(&sol, p, q);
        sol
    };
    let penalty = solve_with(0.5, Enforcement::Penalty);
    let soft = solve_with(0.5, Enforcement::Augmented);
    let stiff = solve_with(0.002, Enforcement::Augmented);
    let displacement = |sol: &Solution| {
        sol.bodies[1]
            .displacement
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
    };
    let scale = displacement(&stiff);
    // The penalty's sticking points slip elastically; the exact law's do not.
    assert!(penalty.contact[0].slip_violation() > 1e-4 * scale);
    for sol in [&soft, &stiff] {
        assert!(sol.contact[0].slip_violation() <= 1e-5 * scale);
        assert!(sol.contact[0].traction_excess() <= 1e-12);
    }
    // One exact answer whatever θ: the two augmented solves agree.
    let (a, b) = (&soft.contact[0].tangential, &stiff.contact[0].tangential);
    let peak = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(worst <= 1e-5 * peak, "{worst} of {peak}");
}

#[test]
fn zero_friction_is_the_frictionless_answer_to_the_bit() {
    // Held sideways by a support on its left side, the block has a frictionless answer too.
    let held = |friction: Friction| {
        let mut model = block(10.0, 0.0, friction, 11);
        let block = &mut model.bodies[1];
        let mut constraints = contactdd::fem::Constraints::new(block.mesh.num_nodes());
        constraints
            .fix(&block.mesh, "left", contactdd::fem::Component::X, 0.0)
            .expect("the left side exists");
        block.constraints = constraints;
        run(&model)
    };
    let (none, zero) = (held(Friction::None), held(Friction::Coulomb { mu: 0.0 }));
    assert!(none.converged && zero.converged);
    assert_eq!(none.iterations, zero.iterations);
    for (a, b) in none.bodies.iter().zip(&zero.bodies) {
        assert!(a
            .displacement
            .iter()
            .zip(&b.displacement)
            .all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}

#[test]
fn the_block_converges_in_few_newton_steps_from_stick_to_near_sliding() {
    // Q/N = 0.075: μ = 0.1 slips almost everywhere, μ = 1 sticks everywhere. The counts against
    // μ and a stiffer penalty are in docs/friction.md (examples/friction_iterations.rs).
    for mu in [0.1, 0.3, 1.0] {
        let model = block_on_foundation(10.0, 1.5, Friction::Coulomb { mu }, (11, Order::P1), 0.05);
        let sol = run(&model);
        assert!(sol.converged, "{mu}: {:?}", sol.message);
        assert!(sol.iterations <= 30, "{mu}: {}", sol.iterations);
        balanced(&sol, 10.0, 1.5);
        coulomb(&sol, mu);
    }
}

#[test]
fn a_small_sheared_wall_of_floating_blocks_is_held_by_friction() {
    let sol = run(&sheared_wall(2, 0.5, 0.2, 0.05));
    assert!(sol.converged, "{:?}", sol.message);
    assert!(
        sol.equilibrium.iter().all(|&e| e <= 1e-8),
        "{:?}",
        sol.equilibrium
    );
}

#[test]
fn augmented_friction_over_load_steps_keeps_the_block_in_balance() {
    let mut model = block(10.0, 1.5, Friction::Coulomb { mu: 0.3 }, 8);
    model.pairs[0].enforcement = Enforcement::Augmented;
    let mut prepared = prepare(&model).expect("the block prepares");
    let steps = contactdd::ddm::steps::solve_steps(
        &model,
        &mut prepared,
        &Settings::default(),
        &[0.5, 1.0],
        Hooks::default(),
        &mut |_, _, _| (),
    )
    .expect("the steps run");
    for (factor, sol) in &steps {
        println!("{factor}: {:?} {:?}", sol.stop, sol.message);
        assert!(sol.converged, "{factor}: {:?}", sol.message);
        balanced(sol, 10.0 * factor, 1.5 * factor);
    }
}
