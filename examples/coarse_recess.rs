//! Iteration counts of the `active-set` sweeps with `gamma = "auto"` without the coarse
//! correction, with the correction of chains (what the method and `auto` select) and with
//! `coarse = "all"`, on floating recesses (two blocks pressed by opposite pressures, held only by
//! the contact vertically), columns resting on a floor and two shipped examples: the table of
//! docs/two-level.md, "Which bodies".
//!
//! Run: `cargo run --release --example coarse_recess [filter]`

use contactdd::cases;
use contactdd::ddm::{prepare, solve, CoarseMode, Gamma, Hooks, Method, Model, Settings};
use contactdd::io::load_file;

/// The count of one run, or why it did not converge.
fn count(model: &Model, coarse: CoarseMode) -> String {
    let settings = Settings {
        coarse,
        tol: 1e-6,
        max_iter: 3000,
        ..Settings::paper(Method::ActiveSet, Gamma::Auto)
    };
    let prepared = match prepare(model) {
        Ok(p) => p,
        Err(e) => return format!("setup failed: {e}"),
    };
    match solve(model, &prepared, &settings, Hooks::default()) {
        Ok(sol) if sol.converged => sol.iterations.to_string(),
        Ok(sol) => format!("not converged ({})", sol.iterations),
        Err(e) => format!("failed: {e}"),
    }
}

fn main() {
    let filter = std::env::args().nth(1).unwrap_or_default();
    let mut list: Vec<(String, Box<dyn Fn() -> Model>)> = Vec::new();
    for ratio in [1.0, 2.0] {
        for c in [0.05, 0.005, 0.0005] {
            for n in [8, 16] {
                list.push((
                    format!("floating recess, E₁/E₂ = {ratio}, c = {c}, n = {n}"),
                    Box::new(move || cases::floating_recess(ratio, c, n)),
                ));
            }
        }
    }
    for c in [0.5, 0.05, 0.005] {
        for n in [4, 8] {
            list.push((
                format!("column of {n} blocks, c = {c}"),
                Box::new(move || cases::column(n, c)),
            ));
        }
    }
    for file in ["examples/stack.toml", "examples/three_bodies.toml"] {
        list.push((
            format!("`{file}`"),
            Box::new(move || {
                load_file(std::path::Path::new(file))
                    .expect("a shipped example")
                    .model
            }),
        ));
    }
    println!("| case | off | chains | all |\n|---|---|---|---|");
    for (name, build) in list.iter().filter(|(n, _)| n.contains(&filter)) {
        let model = build();
        let [off, chains, all] =
            [CoarseMode::Off, CoarseMode::Chains, CoarseMode::All].map(|m| count(&model, m));
        println!("| {name} | {off} | {chains} | {all} |");
    }
}
