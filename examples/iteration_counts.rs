//! Iteration counts and wall times of the hard cases of `contactdd::cases` under the paper's
//! relaxed iteration, the two-level sweeps and the interface Newton default.
//!
//! Run: `cargo run --release --example iteration_counts [filter]`

use std::time::Instant;

use contactdd::cases;
use contactdd::ddm::{prepare, solve, CoarseMode, Gamma, Hooks, Method, Model, Settings};
use contactdd::io::load_file;

/// The settings compared: the interface Newton default, the two-level sweeps, the one-level
/// `auto`, the coarse correction on every floating body, and Anderson acceleration.
fn variants() -> Vec<(&'static str, Settings)> {
    let tight = |s: Settings| Settings {
        tol: 1e-6,
        max_iter: 30_000,
        ..s
    };
    let mut v = vec![
        ("default", tight(Settings::default())),
        ("two-level", tight(Settings::two_level())),
        (
            "one-level auto",
            tight(Settings::paper(Method::NewtonKurchatov, Gamma::Auto)),
        ),
        (
            "coarse all",
            tight(Settings {
                coarse: CoarseMode::All,
                ..Settings::two_level()
            }),
        ),
        (
            "anderson+chains",
            tight(Settings {
                coarse: CoarseMode::Chains,
                ..Settings::anderson()
            }),
        ),
        ("anderson", tight(Settings::anderson())),
    ];
    if let Ok(only) = std::env::var("VARIANTS") {
        v.retain(|(n, _)| only.split(',').any(|o| o == *n));
    }
    v
}

fn run(name: &str, model: &Model, variants: &[(&str, Settings)]) {
    let prepared = match prepare(model) {
        Ok(p) => p,
        Err(e) => {
            println!("{name}: setup failed: {e}");
            return;
        }
    };
    for (label, settings) in variants {
        let t = Instant::now();
        match solve(model, &prepared, settings, Hooks::default()) {
            Ok(sol) => {
                let eq = sol.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
                println!(
                    "{name:<28} {label:<18} {:>6} it {:<10} {:>8.3} s  equilibrium {eq:.1e}",
                    sol.iterations,
                    if sol.converged { "converged" } else { "FAILED" },
                    t.elapsed().as_secs_f64()
                );
                if let Some(m) = &sol.message {
                    println!("    {m}");
                }
            }
            Err(e) => println!("{name} {label}: {e}"),
        }
    }
}

fn main() {
    let filter = std::env::args().nth(1).unwrap_or_default();
    let v = variants();
    let mut cases: Vec<(String, Box<dyn Fn() -> Model>)> = Vec::new();
    for c in [0.05, 0.005, 0.0005] {
        cases.push((
            format!("stiff-under-soft c={c}"),
            Box::new(move || cases::stiff_under_soft(c)),
        ));
    }
    for n in [8, 16, 32, 64] {
        cases.push((
            format!("column n={n} c=0.5"),
            Box::new(move || cases::column(n, 0.5)),
        ));
    }
    for ratio in [1.0, 1.01, 2.0] {
        cases.push((
            format!("recess E1/E2={ratio}"),
            Box::new(move || cases::recess(ratio, 0.005, 16)),
        ));
    }
    cases.push((
        "non-matching notch".into(),
        Box::new(|| cases::non_matching_notch(0.05)),
    ));
    for file in [
        "examples/hertz.toml",
        "examples/stack.toml",
        "examples/notch.toml",
        "examples/three_bodies.toml",
    ] {
        let path = std::path::PathBuf::from(file);
        cases.push((
            file.into(),
            Box::new(move || load_file(&path).expect("a shipped example").model),
        ));
    }
    for (name, build) in &cases {
        if name.contains(&filter) {
            run(name, &build(), &v);
        }
    }
}
