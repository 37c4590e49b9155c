//! The paper's Robin sweeps with friction (the tangential Robin term, docs/friction.md) against
//! the interface Newton method, a second solver of the same discrete problem: the same
//! stick/slip statuses and the same tractions, on a block held by its top and on a block that
//! only friction holds; and the coarse correction, which balances by normal forces only, refused.

use contactdd::ddm::*;
use contactdd::fem::Order;
use contactdd::frictional::{block_on_foundation, sheared_block};

fn sweeps(method: Method, gamma: Gamma) -> Settings {
    Settings {
        method,
        gamma,
        accelerator: Accelerator::None,
        coarse: CoarseMode::Off,
        tol: 1e-12,
        max_iter: 5000,
        ..Settings::default()
    }
}

/// Solves `model` by the sweeps of `settings` and by the Newton method; checks that both
/// converge to the same statuses, pressures and tractions (to 1e-7 of the largest of each, far
/// above what the sweeps' tolerance leaves) and that some point sticks and some slips.
fn agrees(name: &str, model: &Model, settings: &Settings) {
    let prepared = prepare(model).unwrap_or_else(|e| panic!("{e}"));
    let newton = solve(model, &prepared, &Settings::default(), Hooks::default()).expect("solves");
    let swept = solve(model, &prepared, settings, Hooks::default()).expect("solves");
    assert!(newton.converged, "{name}: {:?}", newton.message);
    assert!(swept.converged, "{name}: {:?}", swept.message);
    let (a, b) = (&swept.contact[0], &newton.contact[0]);
    assert_eq!(a.status, b.status, "{name}: stick/slip/open");
    for (what, x, y) in [
        ("pressure", &a.pressure, &b.pressure),
        ("tangential traction", &a.tangential, &b.tangential),
    ] {
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = x
            .iter()
            .zip(y)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(
            diff <= 1e-7 * scale,
            "{name}: {what} off by {:e}",
            diff / scale
        );
    }
    let count = |s: FrictionStatus| b.status.iter().filter(|&&x| x == s).count();
    assert!(
        count(FrictionStatus::Stick) > 0 && count(FrictionStatus::Slip) > 0,
        "{name}"
    );
    eprintln!(
        "{name}: {} sweeps, {} Newton steps",
        swept.iterations, newton.iterations
    );
}

#[test]
fn sweeps_with_friction_agree_with_the_newton_method() {
    for mu in [0.1, 0.3] {
        let model = sheared_block(Friction::Coulomb { mu }, (0.01, 0.004));
        for (method, gamma) in [
            (Method::ActiveSet, Gamma::Auto),
            (Method::Robin, Gamma::Constant(1.0)),
            (Method::NewtonKurchatov, Gamma::Constant(0.5)),
        ] {
            let name = format!("held block, mu = {mu}, {method}, gamma {gamma}");
            agrees(&name, &model, &sweeps(method, gamma));
        }
    }
}

#[test]
fn sweeps_hold_a_block_that_only_friction_holds() {
    let model = block_on_foundation(
        10.0,
        4.0,
        Friction::Coulomb { mu: 0.3 },
        (8, Order::P1),
        0.05,
    );
    agrees("free block", &model, &sweeps(Method::Robin, Gamma::Auto));
}

#[test]
fn the_coarse_correction_is_refused_with_friction() {
    let model = sheared_block(Friction::Coulomb { mu: 0.3 }, (0.01, 0.004));
    let prepared = prepare(&model).unwrap_or_else(|e| panic!("{e}"));
    let settings = Settings {
        coarse: CoarseMode::Chains,
        ..sweeps(Method::ActiveSet, Gamma::Auto)
    };
    let err = solve(&model, &prepared, &settings, Hooks::default()).expect_err("refused");
    assert!(err.to_string().contains("coarse = \"off\""), "{err}");
}
