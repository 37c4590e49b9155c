//! The dense and the sparse condensation (`docs/sparse-path.md`) are two ways to the same
//! answer: every shipped example, and the Anderson sweeps on the notch, solved once with each
//! path forced, give the same displacements to 1e-10 of their size, or, where the problem itself
//! is less well conditioned, within 10 times the change the dense path shows when only its
//! starting value changes; both carry equilibrium residuals below 1e-10. The cost model keeps the
//! paper's benchmark on the dense path and moves a long contact zone to the sparse one.

use std::path::{Path, PathBuf};

use contactdd::ddm::outcome::Breakdown;
use contactdd::ddm::{
    prepare, prepare_with, solve, Accelerator, Condensation, Gamma, Hooks, Method, Model, Settings,
    Solution, Stop,
};
use contactdd::io::load_file;

/// Agreement of the two paths, relative to the largest displacement.
const AGREE: f64 = 1e-10;

fn run(model: &Model, settings: &Settings, condensation: Condensation) -> Solution {
    let prepared = prepare_with(model, condensation).unwrap();
    let sol = solve(model, &prepared, settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{condensation}: {:?}", sol.message);
    // The solution reports the path every body took: the forced one.
    assert!(sol.condensation.iter().all(|&p| p == condensation));
    sol
}

/// Largest difference of the bodies' displacements, relative to the largest displacement.
fn difference(a: &Solution, b: &Solution) -> f64 {
    let (mut diff, mut size) = (0.0f64, 0.0f64);
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        for (u, v) in x.displacement.iter().zip(&y.displacement) {
            diff = diff.max((u - v).abs());
            size = size.max(u.abs());
        }
    }
    diff / size
}

/// Largest equilibrium residual of any body (an independent check of each answer).
fn residual(sol: &Solution) -> f64 {
    sol.equilibrium.iter().fold(0.0, |m: f64, &e| m.max(e))
}

fn agree(name: &str, model: &Model, settings: &Settings) {
    let dense = run(model, settings, Condensation::Dense);
    let sparse = run(model, settings, Condensation::Sparse);
    let d = difference(&dense, &sparse);
    if d > AGREE {
        // The dense path's own spread: the same solve from another starting value.
        let restart = Settings {
            u0: 3.0 * settings.u0,
            ..settings.clone()
        };
        let spread = difference(&dense, &run(model, &restart, Condensation::Dense));
        assert!(
            d <= 10.0 * spread,
            "{name}: the paths differ by {d:e} (dense spread {spread:e})"
        );
    }
    for (path, sol) in [("dense", &dense), ("sparse", &sparse)] {
        let r = residual(sol);
        assert!(r <= 1e-10, "{name}, {path}: equilibrium residual {r:e}");
    }
}

/// Examples whose forced sparse solve takes tens of seconds (large bodies with short contact
/// zones, which the cost model keeps dense); compared only with `CONTACTDD_BENCH_LARGE=1`.
const HEAVY: [&str; 3] = ["hertz.toml", "cylinder_plates.toml", "recess_steps.toml"];

#[test]
fn every_example_gives_the_same_answer_on_both_paths() {
    let heavy = std::env::var("CONTACTDD_BENCH_LARGE").is_ok_and(|v| v == "1");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| heavy || !HEAVY.iter().any(|h| p.ends_with(h)))
        .collect();
    files.sort();
    assert!(files.len() >= 3, "{files:?}");
    for file in files {
        let loaded = load_file(&file).unwrap();
        // A tight tolerance: both paths then stop at the fixed point, not one step short of it.
        let settings = Settings {
            tol: 1e-12,
            equilibrium_tol: 1e-6,
            max_iter: 2000,
            ..loaded.settings.clone()
        };
        agree(&file.display().to_string(), &loaded.model, &settings);
    }
}

#[test]
fn the_anderson_sweeps_give_the_same_answer_on_both_paths() {
    let loaded =
        load_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/notch.toml")).unwrap();
    let model = loaded.model;
    let settings = Settings {
        tol: 1e-11,
        equilibrium_tol: 1e-6,
        max_iter: 2000,
        u0: loaded.settings.u0,
        u_prev: loaded.settings.u_prev,
        ..Settings::anderson()
    };
    assert!(matches!(settings.accelerator, Accelerator::Anderson { .. }));
    agree("non-matching notch, Anderson", &model, &settings);
}

#[test]
fn the_cost_model_keeps_the_benchmark_dense_and_a_long_zone_sparse() {
    let notch = contactdd::ddm::benchmark::Notch::default().model().unwrap();
    let prepared = prepare(&notch).unwrap();
    assert!(prepared
        .bodies
        .iter()
        .flatten()
        .all(|b| b.sparse().is_none()));
    // Two strips 1000 × 2 cells in contact along their whole length: the dense blocks on 1001
    // points would hold far more values than the bodies' sparse factors, and more than the
    // floor below which the dense path is always kept.
    let long = long_strips(1000);
    let prepared = prepare(&long).unwrap();
    assert!(prepared
        .bodies
        .iter()
        .flatten()
        .all(|b| b.sparse().is_some()));
    // The choice is what the solution reports (`bodies[].condensation` in summary.json).
    assert_eq!(prepared.paths, vec![Condensation::Sparse; 2]);
    let sol = solve(&long, &prepared, &Settings::default(), Hooks::default()).unwrap();
    assert_eq!(sol.condensation, vec![Condensation::Sparse; 2]);
    let notch = prepare(&contactdd::ddm::benchmark::Notch::default().model().unwrap()).unwrap();
    assert_eq!(notch.paths, vec![Condensation::Dense; 2]);
}

/// A body that loses all contact makes its Robin problem singular: both paths stop at the same
/// iteration and say so (the sparse factor alone would factorise the singular matrix and let the
/// displacements grow).
#[test]
fn a_body_that_loses_contact_is_diagnosed_alike_on_both_paths() {
    let loaded =
        load_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/three_bodies.toml"))
            .unwrap();
    let settings = Settings {
        u0: loaded.settings.u0,
        u_prev: loaded.settings.u_prev,
        ..Settings::paper(Method::ActiveSet, Gamma::Constant(1.0))
    };
    let stops: Vec<Stop> = [Condensation::Dense, Condensation::Sparse]
        .map(|c| {
            let prepared = prepare_with(&loaded.model, c).unwrap();
            let sol = solve(&loaded.model, &prepared, &settings, Hooks::default()).unwrap();
            sol.stop
        })
        .into();
    assert!(
        matches!(
            stops[0],
            Stop::Diverged {
                reason: Breakdown::LostContact,
                ..
            }
        ),
        "dense: {:?}",
        stops[0]
    );
    assert_eq!(stops[0], stops[1]);
}

fn long_strips(n: usize) -> Model {
    use contactdd::cases::{body, rectangle, top_bottom};
    use contactdd::fem::Component;
    let length = n as f64 / 2.0;
    let lower = body(
        "lower",
        rectangle([0.0, length], [0.0, 1.0], n, 2, false),
        2.1e5,
        &[("bottom", Component::Both)],
        None,
    );
    let upper = body(
        "upper",
        rectangle([0.0, length], [1.0, 2.0], n, 2, true),
        2.1e5,
        &[("left", Component::X)],
        Some(("top", 100.0)),
    );
    Model {
        name: "long strips".into(),
        plane: contactdd::fem::Plane::Strain,
        bodies: vec![lower, upper],
        pairs: vec![top_bottom("strips", 0, 1, 0.05, 1.0)],
        remote: Vec::new(),
    }
}
