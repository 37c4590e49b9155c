//! The paper's γ study on the notch benchmark is pinned: every method × γ of the grid
//! 0.05:0.85:0.05 must take exactly the iteration count (and end the same way) as the reference
//! table `tests/data/gamma_study.csv`, written by `contactdd sweep` from the paper's one-level
//! iteration before the two-level iteration and the accelerator were added. New defaults and
//! accelerators are additions: this test keeps them from moving the study by one iteration.

use std::path::Path;

use contactdd::ddm::{prepare, sweep, Gamma, Method};
use contactdd::io::load_file;

#[test]
fn the_gamma_study_reproduces_the_pinned_iteration_counts() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let loaded = load_file(&root.join("examples/notch.toml")).unwrap();
    let table = std::fs::read_to_string(root.join("tests/data/gamma_study.csv")).unwrap();
    let rows: Vec<Vec<&str>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let methods: Vec<Method> = Method::ALL.to_vec();
    // The γ values as the table prints them (the command line rounds its ranges the same way).
    let mut gammas: Vec<Gamma> = Vec::new();
    for row in &rows {
        let g = Gamma::Constant(row[1].parse().unwrap());
        if !gammas.contains(&g) {
            gammas.push(g);
        }
    }
    let prepared = prepare(&loaded.model).unwrap();
    let runs = sweep(
        &loaded.model,
        &prepared,
        &methods,
        &gammas,
        &loaded.settings,
    );
    assert_eq!(runs.len(), rows.len());
    for row in &rows {
        let (method, gamma): (Method, f64) = (row[0].parse().unwrap(), row[1].parse().unwrap());
        let run = runs
            .iter()
            .find(|r| r.method == method && r.gamma == Some(gamma))
            .unwrap_or_else(|| panic!("no run for {method} at γ = {gamma}"));
        assert_eq!(
            (run.iterations.to_string(), run.converged.to_string()),
            (row[2].to_string(), row[3].to_string()),
            "{method} at γ = {gamma}"
        );
    }
}
