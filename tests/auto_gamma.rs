//! `gamma = "auto"` against the best constant γ of the paper's grid, computed here with the sweep
//! function (issue 6): auto must converge from the standard initial values and take no more than
//! ⌈1.5 × m_best⌉ iterations.

use contactdd_core::Order;
use contactdd_ddm::benchmark::Notch;
use contactdd_ddm::*;

/// The paper's γ grid.
const GRID: [f64; 11] = [0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85];
const METHODS: [Method; 3] = [
    Method::ActiveSet,
    Method::NewtonChord,
    Method::NewtonKurchatov,
];

fn base() -> Settings {
    Settings {
        method: Method::ActiveSet,
        gamma: Gamma::Auto,
        tol: 1e-3,
        max_iter: 1000,
        ..Settings::two_level()
    }
}

/// (method, best constant m, auto m) for a model, with the tolerance and initial values of `base`.
fn compare(model: &Model, base: &Settings) -> Vec<(Method, usize, Option<usize>)> {
    let prepared = prepare(model).unwrap();
    let gammas: Vec<Gamma> = GRID.iter().map(|&g| Gamma::Constant(g)).collect();
    let runs = sweep(model, &prepared, &METHODS, &gammas, base);
    let auto = sweep(model, &prepared, &METHODS, &[Gamma::Auto], base);
    METHODS
        .iter()
        .map(|&m| {
            let best = runs
                .iter()
                .filter(|r| r.method == m && r.converged)
                .map(|r| r.iterations)
                .min()
                .unwrap_or(usize::MAX);
            let a = auto.iter().find(|r| r.method == m).unwrap();
            (m, best, a.converged.then_some(a.iterations))
        })
        .collect()
}

fn check(name: &str, model: &Model) {
    check_with(name, model, &base());
}

fn check_with(name: &str, model: &Model, base: &Settings) {
    for (method, best, auto) in compare(model, base) {
        println!("{name} {method}: best constant m = {best}, auto m = {auto:?}");
        let auto = auto.unwrap_or_else(|| panic!("{name} {method}: auto did not converge"));
        if best < usize::MAX {
            let bound = (1.5 * best as f64).ceil() as usize;
            assert!(
                auto <= bound,
                "{name} {method}: auto {auto} > ⌈1.5 × {best}⌉ = {bound}"
            );
        }
    }
}

#[test]
fn auto_gamma_on_the_notch_benchmark() {
    check("notch", &Notch::default().model().unwrap());
}

#[test]
fn auto_gamma_with_a_ten_times_smaller_penalty() {
    check(
        "notch c=0.005",
        &Notch {
            c: 0.005,
            ..Notch::default()
        }
        .model()
        .unwrap(),
    );
}

/// The shipped examples with a chain of floating bodies (slow: thousands of iterations per run).
#[test]
fn auto_gamma_on_the_three_body_and_stack_examples() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for name in ["three_bodies", "stack"] {
        let loaded = contactdd_io::load_file(&root.join(format!("{name}.toml"))).unwrap();
        let base = Settings {
            max_iter: 20_000,
            ..loaded.settings
        };
        check_with(name, &loaded.model, &base);
    }
}

#[test]
fn auto_gamma_on_p2() {
    check(
        "notch P2",
        &Notch {
            nx: 16,
            ny: 8,
            order: Order::P2,
            ..Notch::default()
        }
        .model()
        .unwrap(),
    );
}
