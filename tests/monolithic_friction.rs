//! The monolithic reference with Coulomb and Tresca friction against the domain decomposition's
//! interface Newton method (two solvers sharing only the model and the contact geometry), on a
//! block pressed on a foundation and pushed sideways: the same contact points' gaps, tangential
//! displacements, pressures, tangential tractions and stick/slip/open statuses, the same fields,
//! the block's force balance, and a push beyond what friction holds refused as sliding; and on
//! sheared walls of floating blocks, every pair of them frictional.

use contactdd::ddm::*;
use contactdd::fem::Order;
use contactdd::frictional::{block_on_foundation, sheared_wall};

/// The block of [`block_on_foundation`] with `upper` cells of `order` and the paper's penalty
/// factor (the model of tests/friction.rs).
fn block(p: f64, q: f64, friction: Friction, upper: usize, order: Order) -> Model {
    block_on_foundation(p, q, friction, (upper, order), 0.05)
}

const P: f64 = 10.0;
const Q: f64 = 4.0;
/// The agreement asked of the two solvers, relative to the largest value of each quantity.
const TOL: f64 = 1e-8;

fn decomposition(model: &Model) -> Solution {
    let prepared = prepare(model).unwrap_or_else(|e| panic!("{e}"));
    solve(model, &prepared, &Settings::default(), Hooks::default()).expect("a valid model solves")
}

fn monolithic(model: &Model) -> MonolithicSolution {
    solve_monolithic(model).unwrap_or_else(|e| panic!("{e}"))
}

/// max |a − b| / max |b| over the finite entries (a point without partner has an infinite gap:
/// both must have it).
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let finite: Vec<(f64, f64)> = a
        .iter()
        .zip(b)
        .filter(|(x, y)| {
            assert_eq!(x.is_finite(), y.is_finite(), "{x} against {y}");
            y.is_finite()
        })
        .map(|(&x, &y)| (x, y))
        .collect();
    let scale = finite.iter().fold(0.0f64, |m, v| m.max(v.1.abs()));
    let diff = finite.iter().fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    if diff == 0.0 {
        0.0
    } else {
        diff / scale
    }
}

/// Solves `model` both ways, checks that both converge and agree, and returns the largest
/// relative difference found and the monolithic solution.
fn agree(name: &str, model: &Model) -> (f64, MonolithicSolution) {
    let dd = decomposition(model);
    let reference = monolithic(model);
    compare(name, &dd, reference, true)
}

/// Checks that both solutions converged and agree (the gaps, tangential displacements and closed
/// flags too if `flags`: exact contact and exact stick leave gaps and slips of round-off size,
/// which also decide the flags); returns the largest relative difference.
fn compare(
    name: &str,
    dd: &Solution,
    reference: MonolithicSolution,
    flags: bool,
) -> (f64, MonolithicSolution) {
    assert!(dd.converged, "{name}: DD {:?}", dd.message);
    assert!(reference.converged, "{name}: {:?}", reference.message);
    assert!(
        reference.rigid_modes.is_empty(),
        "{name}: {:?}",
        reference.rigid_modes
    );
    assert_eq!(dd.contact.len(), reference.contact.len());
    let mut worst = 0.0f64;
    for (a, b) in dd.contact.iter().zip(&reference.contact) {
        worst = worst.max(same_pair(&format!("{name}, {}", a.name), a, b, flags));
    }
    for (x, y) in dd.bodies.iter().zip(&reference.bodies) {
        let err = relative_difference(&x.displacement, &y.displacement);
        assert!(err <= TOL, "{name} '{}': u off by {err:e}", x.name);
        worst = worst.max(err);
    }
    (worst, reference)
}

/// Checks that one pair's points agree in both solutions; returns the largest relative
/// difference.
fn same_pair(name: &str, a: &solution::PairResult, b: &solution::PairResult, flags: bool) -> f64 {
    assert_eq!(a.node, b.node, "{name}: the same contact points");
    assert_eq!(a.status, b.status, "{name}: stick/slip/open");
    if flags {
        assert_eq!(a.closed, b.closed, "{name}: closed points");
    }
    let mut worst = 0.0f64;
    for (what, x, y) in [
        ("gap d − s", &a.gap, &b.gap),
        ("tangential displacement", &a.total_slip, &b.total_slip),
        ("pressure", &a.pressure, &b.pressure),
        ("tangential traction", &a.tangential, &b.tangential),
        ("fx", &a.fx, &b.fx),
        ("fy", &a.fy, &b.fy),
    ]
    .into_iter()
    .filter(|(what, _, _)| flags || !matches!(*what, "gap d − s" | "tangential displacement"))
    {
        let err = relative_difference(x, y);
        assert!(err <= TOL, "{name}: {what} off by {err:e}");
        worst = worst.max(err);
    }
    worst
}

/// The contact forces on the block balance its loads: 2p down, q along x.
fn balanced(name: &str, sol: &MonolithicSolution) {
    let on_block = sol.contact[0].force_on(1);
    assert!((on_block[0] + Q).abs() < 1e-8 * Q, "{name}: {on_block:?}");
    assert!(
        (on_block[1] - 2.0 * P).abs() < 1e-8 * P,
        "{name}: {on_block:?}"
    );
    let t = sol.contact[0].tangential_force();
    assert!((t.abs() - Q).abs() < 1e-8 * Q, "{name}: {t}");
}

#[test]
fn full_stick_agrees_with_the_decomposition() {
    let model = block(P, Q, Friction::Coulomb { mu: 0.5 }, 8, Order::P1);
    let (worst, sol) = agree("stick", &model);
    eprintln!("stick: largest relative difference {worst:.1e}");
    balanced("stick", &sol);
    let (stick, slip) = sol.contact[0].stick_slip_lengths();
    assert_eq!(slip, 0.0);
    assert!((stick - 2.0).abs() < 1e-9, "{stick}");
}

#[test]
fn partial_slip_agrees_on_matching_non_matching_and_p2_meshes() {
    for (upper, order) in [(8, Order::P1), (11, Order::P1), (5, Order::P2)] {
        for mu in [0.21, 0.25, 0.3] {
            let name = format!("{upper} cells {order:?}, mu = {mu}");
            let model = block(P, Q, Friction::Coulomb { mu }, upper, order);
            let (worst, sol) = agree(&name, &model);
            eprintln!(
                "{name}: largest relative difference {worst:.1e}, {} Newton steps",
                sol.newton_steps
            );
            balanced(&name, &sol);
            let (stick, slip) = sol.contact[0].stick_slip_lengths();
            assert!(stick > 0.0 && slip > 0.0, "{name}: {stick} {slip}");
        }
    }
}

#[test]
fn tresca_agrees_with_the_decomposition() {
    let model = block(P, Q, Friction::Tresca { bound: 2.5 }, 8, Order::P1);
    let (worst, sol) = agree("tresca", &model);
    eprintln!("tresca: largest relative difference {worst:.1e}");
    balanced("tresca", &sol);
    for (t, st) in sol.contact[0].tangential.iter().zip(&sol.contact[0].status) {
        assert!(t.abs() <= 2.5 * (1.0 + 1e-12));
        if *st == FrictionStatus::Slip {
            assert!((t.abs() - 2.5).abs() < 1e-12);
        }
    }
}

#[test]
fn a_push_beyond_what_friction_holds_slides() {
    // Coulomb: N = 20, μN = 3 < Q = 4. Tresca: the bound 1.5 over the zone's length 2 holds 3.
    for friction in [
        Friction::Coulomb { mu: 0.15 },
        Friction::Tresca { bound: 1.5 },
    ] {
        let sol = monolithic(&block(P, Q, friction, 8, Order::P1));
        assert!(!sol.converged, "{friction}");
        let message = sol.message.unwrap_or_default();
        assert!(message.contains("'block' slides"), "{friction}: {message}");
    }
}

#[test]
fn augmented_contact_with_exact_friction_agrees() {
    // Both Uzawa loops run to a gap tolerance far below the agreement asked for.
    for mu in [0.25, 0.5] {
        let name = format!("augmented, mu = {mu}");
        let mut model = block(P, Q, Friction::Coulomb { mu }, 8, Order::P1);
        model.pairs[0].enforcement = Enforcement::Augmented;
        let prepared = prepare(&model).unwrap_or_else(|e| panic!("{e}"));
        let settings = Settings {
            gap_tol: Some(1e-12),
            ..Settings::default()
        };
        let dd = solve(&model, &prepared, &settings, Hooks::default()).expect("it solves");
        let limits = monolithic::MonolithicSettings {
            gap_tol: Some(1e-12),
            ..Default::default()
        };
        let reference = monolithic::solve_monolithic_with(&model, &limits, None)
            .unwrap_or_else(|e| panic!("{e}"));
        let (worst, sol) = compare(&name, &dd, reference, false);
        eprintln!("{name}: largest relative difference {worst:.1e}");
        balanced(&name, &sol);
        // The exact contact: the gaps of the pressed points vanish, and so do the slips of the
        // sticking ones.
        let pair = &sol.contact[0];
        for (gap, p) in pair.gap.iter().zip(&pair.pressure) {
            assert!(*p == 0.0 || gap.abs() < 1e-10, "{name}: {gap}");
        }
        assert!(
            pair.slip_violation() < 1e-10,
            "{name}: {}",
            pair.slip_violation()
        );
    }
}

/// The Newton steps a frictional solve may take (issue: at most 30 per load step).
const MAX_STEPS: usize = 30;

#[test]
fn sheared_walls_agree_and_take_few_newton_steps() {
    // Walls of n × n floating blocks (matching and non-matching neighbours alternate), every
    // interface frictional, the top row pushed sideways: partial slip over many pairs at once.
    for (n, mu, c) in [
        (2, 0.5, 0.05),
        (3, 0.3, 0.05),
        (4, 0.5, 0.05),
        (4, 0.1, 0.05),
        (4, 0.1, 0.0005),
        (4, 1.0, 0.0005),
    ] {
        let name = format!("wall {n} x {n}, mu = {mu}, c = {c}");
        let model = sheared_wall(n, mu, 0.2, c);
        let dd = decomposition(&model);
        assert!(
            dd.iterations <= MAX_STEPS,
            "{name}: {} steps",
            dd.iterations
        );
        let (worst, _) = compare(&name, &dd, monolithic(&model), true);
        let slipping: usize = (dd.contact.iter())
            .map(|p| {
                p.status
                    .iter()
                    .filter(|&&s| s == FrictionStatus::Slip)
                    .count()
            })
            .sum();
        eprintln!(
            "{name}: {} Newton steps, {slipping} points slip, largest relative difference \
             {worst:.1e}",
            dd.iterations
        );
    }
}

#[test]
fn the_eight_by_eight_wall_converges_in_few_newton_steps() {
    let model = sheared_wall(8, 0.5, 0.2, 0.05);
    let dd = decomposition(&model);
    assert!(dd.converged, "{:?}", dd.message);
    assert!(dd.iterations <= MAX_STEPS, "{} steps", dd.iterations);
}
