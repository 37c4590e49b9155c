//! A problem whose factorisations cannot fit in memory is refused before anything big is
//! allocated, with a typed error that states the estimate and the available memory.

use contactdd::cases::{body, rectangle};
use contactdd::ddm::{
    prepare, prepare_with, Condensation, ContactPair, Enforcement, Model, Penalty, SetupError,
};
use contactdd::fem::{memory, Component, Plane};

/// Two strips of `n` × 1 cells in contact along their whole length: m = n + 1 contact points per
/// body, so the dense condensation alone holds m² values per body.
fn strips(n: usize) -> Model {
    let length = n as f64;
    let lower = body(
        "lower",
        rectangle([0.0, length], [0.0, 1.0], n, 1, false),
        2.1e5,
        &[("bottom", Component::Both)],
        None,
    );
    let upper = body(
        "upper",
        rectangle([0.0, length], [1.0, 2.0], n, 1, false),
        2.1e5,
        &[("left", Component::X)],
        Some(("top", 1.0)),
    );
    Model {
        name: "strips".into(),
        plane: Plane::Strain,
        bodies: vec![lower, upper],
        pairs: vec![ContactPair {
            name: "strips".into(),
            bodies: [0, 1],
            boundaries: ["top".into(), "bottom".into()],
            penalty: Penalty::RodModel { c: 0.5, h: 1.0 },
            profile: None,
            enforcement: Enforcement::Penalty,
            forces: Default::default(),
            friction: Default::default(),
        }],
        remote: Vec::new(),
    }
}

#[test]
fn a_problem_too_big_for_the_machine_is_refused_with_both_numbers() {
    let Some(available) = memory::available() else {
        return; // no /proc/meminfo: nothing is checked
    };
    // 2 × 8 m² bytes for the two C₀ blocks alone, beyond any machine this test runs on (the
    // dense path forced: the cost model would take the sparse one, docs/sparse-path.md).
    let n = 70_000;
    let m = (n + 1) as u64;
    let lower_bound = 2 * 8 * m * m;
    assert!(
        lower_bound > available,
        "this machine has {available} bytes"
    );
    let Err(SetupError::Memory(e)) = prepare_with(&strips(n), Condensation::Dense) else {
        panic!("not refused");
    };
    assert!(e.needed >= lower_bound, "{e}");
    assert!(e.available > 0 && e.available < e.needed, "{e}");
    let message = e.to_string();
    assert!(
        message.contains("GiB") && message.contains("available"),
        "{message}"
    );
}

#[test]
fn a_small_problem_is_prepared() {
    assert!(prepare(&strips(20)).is_ok());
}
