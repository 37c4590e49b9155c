//! `examples/cylinder_plates.toml`: a cylinder between two plates (three bodies in one Gmsh
//! file, P2, two curved non-matching contacts) in five load steps, against Hertz: at every step
//! the contact half-width of each side of each pair, a = sqrt(4 P R / (π E*)) for the load P of
//! the step, the lower plate's equilibrium with its support and its reaction against the applied
//! load (1e-8), and every pair's force balance.

use contactdd::ddm::solution::PairResult;
use contactdd::ddm::steps::solve_steps;
use contactdd::ddm::{prepare, Hooks};
use contactdd::io::load_file;
use contactdd::io::reactions::reactions;

/// Full load per unit thickness through each contact, and E* of two steel bodies.
const P: f64 = 900.0;
const R: f64 = 1.0;

/// The half-width of one side's pressure: Hertz's p² = p0² (1 − x²/a²) is linear in x², so a
/// least-squares line through (x², p²) over the points above 30 % of the peak gives a² = −p0²/slope.
fn half_width(pair: &PairResult, side: usize) -> f64 {
    let points: Vec<(f64, f64)> = (0..pair.x.len())
        .filter(|&i| pair.side[i] == side && pair.pressure[i] < 0.0)
        .map(|i| (pair.x[i] * pair.x[i], pair.pressure[i] * pair.pressure[i]))
        .collect();
    let peak = points.iter().fold(0.0f64, |m, p| m.max(p.1));
    let fit: Vec<&(f64, f64)> = points.iter().filter(|p| p.1 > 0.09 * peak).collect();
    let n = fit.len() as f64;
    let (sx, sy) = fit.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
    let (sxx, sxy) = fit
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0 * p.0, b + p.0 * p.1));
    let slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let intercept = (sy - slope * sx) / n;
    (-intercept / slope).sqrt()
}

#[test]
fn every_load_step_matches_hertz() {
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cylinder_plates.toml");
    let loaded = load_file(&file).unwrap();
    let factors = loaded.steps.clone().unwrap();
    assert_eq!(factors.len(), 5);
    let model = &loaded.model;
    let mut prepared = prepare(model).unwrap();
    let steps = solve_steps(
        model,
        &mut prepared,
        &loaded.settings,
        &factors,
        Hooks::default(),
        &mut |_, _, _| (),
    )
    .unwrap();
    assert_eq!(steps.len(), 5);
    let e_star = 2.1e5 / (2.0 * (1.0 - 0.3f64 * 0.3));
    for (factor, sol) in &steps {
        assert!(sol.converged, "factor {factor}: {:?}", sol.message);
        let hertz = (4.0 * P * factor * R / (std::f64::consts::PI * e_star)).sqrt();
        for pair in &sol.contact {
            for side in 0..2 {
                let a = half_width(pair, side);
                let error = (a - hertz).abs() / hertz;
                assert!(
                    error <= 0.03,
                    "factor {factor}, {} side {side}: a = {a:.5}, Hertz {hertz:.5}",
                    pair.name
                );
            }
        }
        // The lower plate (body 0) is in equilibrium with its clamped bottom: reaction plus
        // contact force vanish.
        let support = reactions(model, &sol.bodies, &sol.contact)[0].total;
        let contact = sol.contact[0].force_on(0);
        let residual = (support[0] + contact[0]).hypot(support[1] + contact[1]);
        assert!(
            residual <= 1e-8 * P * factor,
            "factor {factor}: residual {residual:e}"
        );
        // The pairs are balanced (the default forces): the lower plate's support carries the
        // applied load, and every pair's two sides carry equal and opposite forces with no
        // tangential resultant on this symmetric problem.
        assert!(
            (support[1] - P * factor).abs() <= 1e-8 * P * factor,
            "factor {factor}: reaction {support:?}"
        );
        for pair in &sol.contact {
            let (a, b) = (pair.force_on(0), pair.force_on(1));
            let imbalance = (a[0] + b[0]).hypot(a[1] + b[1]);
            assert!(
                imbalance <= 1e-10 * P * factor,
                "{}: {a:?} {b:?}",
                pair.name
            );
            assert!(
                a[0].abs() <= 1e-10 * P * factor,
                "{}: tangential {a:?}",
                pair.name
            );
        }
    }
}
