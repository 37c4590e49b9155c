//! The notch benchmark of `contactdd_ddm::benchmark::Notch` as a problem-file schema, so that
//! `notch_benchmark()` goes through the resolve step of a problem file and can be written back out
//! by `Problem.to_toml()` like any other problem. The values are those of `Notch::default()` and
//! `examples/notch.toml` (a test of contactdd-io checks that file against `Notch`; the Python
//! tests check this one against the file).

use std::collections::BTreeMap;

use contactdd_core::{Component, Diagonal, Load, Order, Plane};
use contactdd_ddm::benchmark::{Notch, H, L};
use contactdd_ddm::contact::gap_profile::Along;
use contactdd_ddm::Method;
use contactdd_io::problem::{
    BodySpec, ContactSpec, GammaSpec, GapSpec, MaterialSpec, MeshSpec, PenaltySpec, Problem,
    SolverSpec, SupportSpec,
};

/// Depth of the notch (cm).
const NOTCH_DEPTH: f64 = 0.05;

/// One block of the benchmark: `lower` (y from 0) or `upper` (y from H, mirrored).
fn block(notch: &Notch, name: &str, y0: f64, mirror: bool, loaded: &str) -> BodySpec {
    BodySpec {
        name: name.into(),
        material: "steel".into(),
        mesh: MeshSpec::Rectangle {
            x: [0.0, L],
            y: [y0, y0 + H],
            nx: notch.nx,
            ny: notch.ny,
            diagonal: Diagonal::Right,
            mirror,
            mirror_x: false,
            grading: None,
            order: notch.order,
        },
        supports: vec![SupportSpec {
            boundary: "right".into(),
            component: Component::X,
            value: 0.0,
        }],
        loads: vec![Load::Pressure {
            boundary: loaded.into(),
            value: notch.pressure(),
        }
        .into()],
    }
}

/// The benchmark with `nx × ny` cells per block of order `order`, with the solver settings of
/// `examples/notch.toml` (the paper's one-level iteration).
pub fn notch_spec(nx: usize, ny: usize, order: Order) -> Problem {
    let notch = Notch {
        nx,
        ny,
        order,
        ..Notch::default()
    };
    let materials = BTreeMap::from([(
        "steel".to_string(),
        MaterialSpec {
            young: notch.young,
            poisson: notch.poisson,
        },
    )]);
    Problem {
        name: Some("notch".into()),
        plane: Plane::Strain,
        units: Some("cm, N/cm^2".into()),
        materials,
        bodies: vec![
            block(&notch, "lower", 0.0, false, "bottom"),
            block(&notch, "upper", H, true, "top"),
        ],
        contact: vec![ContactSpec {
            name: Some("notch".into()),
            bodies: vec!["lower".into(), "upper".into()],
            boundaries: vec!["top".into(), "bottom".into()],
            penalty: PenaltySpec {
                c: Some(notch.c),
                h: Some(H),
                theta: None,
            },
            gap: Some(GapSpec::Notch {
                r0: NOTCH_DEPTH,
                b: 1.0,
                centre: L,
                power: 1.5,
                along: Along::X,
            }),
            enforcement: None,
            friction: None,
            forces: None,
        }],
        solver: SolverSpec {
            method: Some(Method::NewtonKurchatov),
            gamma: Some(GammaSpec::Value(0.5)),
            tol: Some(1e-3),
            max_iter: Some(500),
            u0: Some(1e-4),
            u_prev: Some(2e-4),
            ..SolverSpec::default()
        },
        steps: Vec::new(),
        output: Default::default(),
    }
}
