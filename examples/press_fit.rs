//! The press fit of `contactdd::press_fit` (a quarter shaft of radius 1.005 in a quarter ring of
//! radius 1 to 2, steel, plane strain, both bodies held by symmetry supports) solved by the
//! interface Newton method with the default settings, P1, P2 and curved P2 (mid-side nodes on
//! the circles), penalty and augmented, against
//! the monolithic reference and Lamé's pressure. `cargo run --release --example press_fit [ARCS SHAFT_ARCS RADIAL]` (default 32 32 8;
//! `32 40 8`: non-matching arcs).

use contactdd::ddm::monolithic::solve_monolithic;
use contactdd::ddm::{prepare_with, solve, Enforcement, Hooks, Penalty, Settings};
use contactdd::press_fit::{lame_pressure, press_fit, PressFit, RING_INNER, RING_OUTER};

/// The largest difference of the displacements of two solutions relative to the largest one.
fn difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let (mut d, mut m) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        for (p, q) in x.iter().zip(y) {
            d = d.max((p - q).abs());
            m = m.max(p.abs());
        }
    }
    d / m
}

/// The `i`th command-line argument as a number, or `default`.
fn arg(i: usize, default: usize) -> usize {
    std::env::args()
        .nth(i)
        .and_then(|a| a.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let lame = lame_pressure(0.005, RING_INNER, RING_OUTER);
    println!("order enforcement penalty        shift    converged its  mono  |Δu|/|u|   p/Lamé−1 (min..max, 5°–85°)");
    let penalties = [
        ("c = 0.05", Penalty::RodModel { c: 0.05, h: 1.0 }),
        ("θ = 1e-7", Penalty::Theta(1e-7)),
        ("θ = 1e-8", Penalty::Theta(1e-8)),
    ];
    for (p2, curved) in [(false, false), (true, false), (true, true)] {
        for enforcement in [Enforcement::Penalty, Enforcement::Augmented] {
            for (name, penalty) in penalties {
                for shift in [0.0, 1e-10, 1e-8] {
                    let options = PressFit {
                        arcs: arg(1, 32),
                        shaft_arcs: arg(2, 32),
                        radial: arg(3, 8),
                        p2,
                        curved,
                        penalty,
                        enforcement,
                        shift: [shift, shift],
                        ..PressFit::default()
                    };
                    let model = press_fit(&options).expect("a valid press fit");
                    let settings = Settings::default();
                    let prepared = prepare_with(&model, &settings).expect("prepared");
                    let sol =
                        solve(&model, &prepared, &settings, Hooks::default()).expect("solved");
                    let mono = solve_monolithic(&model).expect("monolithic");
                    let fields = |b: &[contactdd::ddm::solution::BodyResult]| {
                        b.iter().map(|r| r.displacement.clone()).collect::<Vec<_>>()
                    };
                    let du = difference(&fields(&mono.bodies), &fields(&sol.bodies));
                    let pair = &sol.contact[0];
                    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                    for i in 0..pair.x.len() {
                        let phi = (pair.y[i] - shift).atan2(pair.x[i] - shift).to_degrees();
                        if (5.0..=85.0).contains(&phi) {
                            let r = pair.pressure[i].abs() / lame - 1.0;
                            lo = lo.min(r);
                            hi = hi.max(r);
                        }
                    }
                    println!(
                        "{:5} {:11} {:14} {shift:8.0e} {:9} {:3} {:5} {du:9.2e} {:+.4}..{:+.4}  {}",
                        match (p2, curved) {
                            (false, _) => "P1",
                            (true, false) => "P2",
                            (true, true) => "P2c",
                        },
                        enforcement.to_string(),
                        name,
                        sol.converged,
                        sol.iterations,
                        mono.converged,
                        lo,
                        hi,
                        sol.message.as_deref().unwrap_or("")
                    );
                }
            }
        }
    }
}
