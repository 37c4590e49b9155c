//! The domain decomposition: setup of the notch benchmark, one iteration, a full solve per method,
//! the 45-run γ sweep, an 8-body stack with 1 and 2 threads, columns of floating blocks, the
//! Hertz example at two penalties and with friction, the contact search, and the two condensation paths
//! (`docs/sparse-path.md`: the notch on each path; with `CONTACTDD_BENCH_LARGE=1` also long strips
//! of 1000, 2000 and 4000 contact points and a compact zone of the same DOF count).
//!
//! Run: `cargo bench --bench ddm`.

use contactdd_core::{
    Component, Constraints, Diagonal, ElasticBody, Load, Material, Order, Plane, Rectangle,
};
use contactdd_ddm::benchmark::Notch;
use contactdd_ddm::contact::Interface;
use contactdd_ddm::solver::iterate;
use contactdd_ddm::{
    prepare, prepare_with, solve, sweep, CoarseMode, Condensation, ContactPair, Enforcement,
    Friction, Gamma, Hooks, Method, Model, Penalty, Settings,
};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn settings(method: Method, gamma: f64) -> Settings {
    Settings {
        tol: 1e-3,
        max_iter: 500,
        ..Settings::paper(method, Gamma::Constant(gamma))
    }
}

/// 15 γ values 0.05, 0.1, …, 0.75: with 3 methods, the 45-run sweep of the performance target.
fn gamma_grid() -> Vec<Gamma> {
    (1..=15).map(|i| Gamma::Constant(0.05 * i as f64)).collect()
}

fn stack(n: usize, cells: usize) -> Model {
    let material = Material::new(1000.0, 0.3).expect("material");
    let bodies = (0..n)
        .map(|i| {
            let mesh = Rectangle {
                origin: [0.0, i as f64],
                corner: [2.0, i as f64 + 1.0],
                nx: 2 * cells,
                ny: cells,
                diagonal: Diagonal::Right,
                mirror: i % 2 == 1,
                order: Order::P1,
            }
            .mesh()
            .expect("mesh");
            let mut constraints = Constraints::new(mesh.num_nodes());
            constraints
                .fix(&mesh, "left", Component::X, 0.0)
                .expect("left");
            if i == 0 {
                constraints
                    .fix(&mesh, "bottom", Component::Y, 0.0)
                    .expect("bottom");
            }
            let loads = if i + 1 == n {
                vec![Load::Pressure {
                    boundary: "top".into(),
                    value: 5.0,
                }]
            } else {
                vec![]
            };
            let load = contactdd_core::loads::load_vector(&mesh, &loads).expect("load");
            ElasticBody {
                name: format!("b{i}"),
                mesh,
                material,
                plane: Plane::Strain,
                constraints,
                load,
            }
        })
        .collect();
    let pairs = (1..n)
        .map(|i| ContactPair {
            name: format!("p{i}"),
            bodies: [i - 1, i],
            boundaries: ["top".into(), "bottom".into()],
            penalty: Penalty::RodModel { c: 0.05, h: 1.0 },
            profile: None,
            enforcement: Enforcement::Penalty,
            forces: Default::default(),
            friction: Default::default(),
        })
        .collect();
    Model {
        name: "stack".into(),
        plane: Plane::Strain,
        bodies,
        pairs,
        remote: Vec::new(),
    }
}

fn notch(c: &mut Criterion) {
    let model = Notch::default().model().expect("model");
    let mut group = c.benchmark_group("notch");
    group.bench_function("prepare", |b| b.iter(|| prepare(&model).expect("prepare")));
    let prepared = prepare(&model).expect("prepare");
    let one = Settings {
        max_iter: 1,
        ..settings(Method::NewtonKurchatov, 0.5)
    };
    group.bench_function("one_iteration", |b| {
        b.iter(|| iterate(&prepared, &one, Hooks::default()))
    });
    for (method, gamma) in [
        (Method::ActiveSet, 0.5),
        (Method::NewtonChord, 0.3),
        (Method::NewtonKurchatov, 0.5),
    ] {
        group.bench_function(BenchmarkId::new("solve", method.name()), |b| {
            b.iter(|| {
                solve(
                    &model,
                    &prepared,
                    &settings(method, gamma),
                    Hooks::default(),
                )
                .expect("solve")
            })
        });
    }
    let methods = [
        Method::ActiveSet,
        Method::NewtonChord,
        Method::NewtonKurchatov,
    ];
    let gammas = gamma_grid();
    let base = settings(Method::ActiveSet, 0.5);
    group.bench_function("sweep_45_runs", |b| {
        b.iter(|| sweep(&model, &prepared, &methods, &gammas, &base))
    });
    group.finish();
}

fn threads(c: &mut Criterion) {
    let model = stack(8, 40);
    let mut group = c.benchmark_group("stack8");
    group.sample_size(10);
    for t in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .expect("pool");
        group.bench_function(BenchmarkId::new("prepare_and_solve", t), |b| {
            b.iter(|| {
                pool.install(|| {
                    let prepared = prepare(&model).expect("prepare");
                    solve(
                        &model,
                        &prepared,
                        &settings(Method::ActiveSet, 0.5),
                        Hooks::default(),
                    )
                    .expect("solve")
                })
            })
        });
    }
    group.finish();
}

/// A column of floating blocks (`contactdd::cases::column`, c = 0.5, tolerance 1e−6): the solve
/// after setup with the default interface Newton method and with the two-level sweeps, against
/// the one-level iteration where it converges (8 blocks; from 16 blocks on it loses contact).
fn two_level(c: &mut Criterion) {
    let mut group = c.benchmark_group("column");
    group.sample_size(10);
    let one_level = Settings {
        coarse: CoarseMode::Off,
        max_iter: 5000,
        ..Settings::two_level()
    };
    for n in [8, 64] {
        let model = contactdd::cases::column(n, 0.5);
        let prepared = prepare(&model).expect("prepare");
        group.bench_function(BenchmarkId::new("newton_solve", n), |b| {
            b.iter(|| solve(&model, &prepared, &Settings::default(), Hooks::default()))
        });
        group.bench_function(BenchmarkId::new("two_level_solve", n), |b| {
            b.iter(|| solve(&model, &prepared, &Settings::two_level(), Hooks::default()))
        });
        if n == 8 {
            group.bench_function(BenchmarkId::new("one_level_solve", n), |b| {
                b.iter(|| solve(&model, &prepared, &one_level, Hooks::default()))
            });
        }
    }
    group.finish();
}

/// Contact search (projection of every contact point and the covered part of every contact edge)
/// on a long strip: the notch geometry with m − 1 cells along the contact line.
fn contact_search(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact_search");
    group.sample_size(10);
    for m in [1000, 2000, 4000] {
        let model = Notch {
            nx: m - 1,
            ny: 4,
            ..Notch::default()
        }
        .model()
        .expect("model");
        group.bench_function(BenchmarkId::new("interface", m), |b| {
            b.iter(|| Interface::new(&model).expect("interface"))
        });
    }
    group.finish();
}

/// The Hertz example (`examples/hertz.toml`) with the default interface Newton method at its own
/// stiff penalty θ = 8e−9 and at a 100× softer θ = 8e−7: the solve after setup. The iteration
/// count, and so the cost, should not grow with the penalty stiffness.
fn stiff_penalty(c: &mut Criterion) {
    let mut group = c.benchmark_group("hertz");
    group.sample_size(10);
    for theta in [8e-7, 8e-9] {
        let mut model = contactdd::io::load_file(std::path::Path::new("examples/hertz.toml"))
            .expect("the shipped example")
            .model;
        for pair in &mut model.pairs {
            pair.penalty = Penalty::Theta(theta);
        }
        let prepared = prepare(&model).expect("prepare");
        let settings = Settings {
            tol: 1e-9,
            ..Settings::default()
        };
        group.bench_function(BenchmarkId::new("newton_solve", theta), |b| {
            b.iter(|| solve(&model, &prepared, &settings, Hooks::default()))
        });
    }
    group.finish();
}

/// The Hertz example solved frictionless and with Coulomb friction μ = 0.3 on its pair
/// (docs/friction.md: the cost of friction on one problem).
fn friction(c: &mut Criterion) {
    let mut group = c.benchmark_group("friction");
    group.sample_size(10);
    let base = contactdd::io::load_file(std::path::Path::new("examples/hertz.toml"))
        .expect("the shipped example")
        .model;
    for (name, law) in [
        ("frictionless", Friction::None),
        ("coulomb_0.3", Friction::Coulomb { mu: 0.3 }),
    ] {
        let mut model = base.clone();
        model.pairs.iter_mut().for_each(|p| p.friction = law);
        let prepared = prepare(&model).expect("prepare");
        let settings = Settings::default();
        group.bench_function(BenchmarkId::new("hertz_solve", name), |b| {
            b.iter(|| solve(&model, &prepared, &settings, Hooks::default()))
        });
    }
    group.finish();
}

/// Prepare and solve (the default interface Newton method) on the path `condensation`.
fn prepare_and_solve(model: &Model, condensation: Condensation) {
    let prepared = prepare_with(model, condensation).expect("prepare");
    let sol = solve(model, &prepared, &Settings::default(), Hooks::default()).expect("solve");
    assert!(sol.converged, "{:?}", sol.message);
}

/// The notch with nx × ny cells per body (nx + 1 contact points per body).
fn notch_cells(nx: usize, ny: usize) -> Model {
    Notch {
        nx,
        ny,
        ..Notch::default()
    }
    .model()
    .expect("model")
}

fn condensation(c: &mut Criterion) {
    let mut group = c.benchmark_group("condensation");
    let model = Notch::default().model().expect("model");
    for path in [
        Condensation::Dense,
        Condensation::Sparse,
        Condensation::Auto,
    ] {
        group.bench_function(BenchmarkId::new("notch", path), |b| {
            b.iter(|| prepare_and_solve(&model, path))
        });
    }
    if std::env::var("CONTACTDD_BENCH_LARGE").is_ok_and(|v| v == "1") {
        group.sample_size(10);
        // Long strips: m = nx + 1 contact points per body, 16 cells deep.
        for nx in [1000, 2000, 4000] {
            let model = notch_cells(nx, 16);
            group.bench_function(BenchmarkId::new("long_strip", nx), |b| {
                b.iter(|| prepare_and_solve(&model, Condensation::Auto))
            });
        }
        // The same DOF count as the 4000 × 16 strip with a compact contact zone.
        let model = notch_cells(368, 184);
        group.bench_function("compact_368x184", |b| {
            b.iter(|| prepare_and_solve(&model, Condensation::Auto))
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    condensation,
    notch,
    threads,
    two_level,
    stiff_penalty,
    friction,
    contact_search
);
criterion_main!(benches);
