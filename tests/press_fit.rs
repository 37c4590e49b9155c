//! The press fit of `contactdd::press_fit` (a quarter shaft of radius 1.005 in a quarter ring of
//! radius 1 to 2, steel, plane strain, both bodies held by symmetry supports): the default solve
//! converges, agrees with the monolithic reference and with Lamé's closed form; a stiff penalty,
//! a near-coincident shifted mesh and a problem without data give no false verdict.

use contactdd::ddm::monolithic::solve_monolithic;
use contactdd::ddm::solution::BodyResult;
use contactdd::ddm::{prepare_with, solve, Enforcement, Hooks, Model, Penalty, Settings, Solution};
use contactdd::press_fit::{
    lame_pressure, press_fit, PressFit, RING_INNER, RING_OUTER, SHAFT_RADIUS,
};

fn run(model: &Model) -> Solution {
    let settings = Settings::default();
    let prepared = prepare_with(model, &settings).unwrap();
    solve(model, &prepared, &settings, Hooks::default()).unwrap()
}

/// The largest displacement difference over the largest displacement.
fn difference(a: &[BodyResult], b: &[BodyResult]) -> f64 {
    let (mut d, mut m) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        for (p, q) in x.displacement.iter().zip(&y.displacement) {
            d = d.max((p - q).abs());
            m = m.max(p.abs());
        }
    }
    d / m
}

/// The smallest and largest nodal pressure between 5° and 85° relative to `reference`, minus 1.
fn spread(sol: &Solution, reference: f64) -> (f64, f64) {
    let pair = &sol.contact[0];
    (0..pair.x.len())
        .filter(|&i| (5.0..=85.0).contains(&pair.y[i].atan2(pair.x[i]).to_degrees()))
        .map(|i| pair.pressure[i].abs() / reference - 1.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        })
}

/// Lamé's pressure of the fit, and of the penalty problem with θ (the pair's compliance θ adds
/// to the bodies': δ = p (δ/p_Lamé + θ)).
fn reference(options: &PressFit, model: &Model) -> f64 {
    let delta = SHAFT_RADIUS - RING_INNER;
    let lame = lame_pressure(delta, RING_INNER, RING_OUTER);
    match options.enforcement {
        Enforcement::Augmented => lame,
        Enforcement::Penalty => {
            let theta = model.pairs[0]
                .penalty
                .theta(&model.bodies[0], &model.bodies[1]);
            delta / (delta / lame + theta)
        }
    }
}

/// P1, P2 (promoted: the arcs are polygons) and curved P2 (the arcs' mid-side nodes on the
/// circles), penalty and augmented, with the default settings, on matching arcs and (curved P2)
/// on non-matching ones: converged, the DD agrees with the monolithic reference to 1e-8, the
/// resultant on the shaft with Lamé's p R to 1 %, and every nodal pressure between 5° and 85°
/// with Lamé (the penalty's Lamé for the penalty) to ±5 %, ±3 % on curved P2.
#[test]
fn press_fit_converges_and_matches_lame() {
    let meshes = [
        ("P1", false, false, 64),
        ("P2", true, false, 64),
        ("P2 curved", true, true, 64),
        ("P2 curved, non-matching", true, true, 80),
    ];
    for (name, p2, curved, shaft_arcs) in meshes {
        for enforcement in [Enforcement::Penalty, Enforcement::Augmented] {
            let options = PressFit {
                arcs: 64,
                shaft_arcs,
                radial: 12,
                p2,
                curved,
                enforcement,
                ..PressFit::default()
            };
            let model = press_fit(&options).unwrap();
            let sol = run(&model);
            let case = format!("{name} {enforcement}");
            assert!(sol.converged, "{case}: {:?}", sol.message);
            let mono = solve_monolithic(&model).unwrap();
            assert!(mono.converged, "{case}: monolithic {:?}", mono.message);
            let du = difference(&mono.bodies, &sol.bodies);
            let p = reference(&options, &model);
            let (lo, hi) = spread(&sol, p);
            let fx: f64 = (0..sol.contact[0].x.len())
                .filter(|&i| sol.contact[0].side[i] == 1)
                .map(|i| sol.contact[0].fx[i])
                .sum();
            let resultant = fx.abs() / (p * RING_INNER) - 1.0;
            println!(
                "{case}: {} iterations, DD vs monolithic {du:.2e}, p/p_ref − 1 in [{lo:+.4}, {hi:+.4}] \
                 (p_ref {p:.2}), resultant/(p_ref R) − 1 = {resultant:+.4}",
                sol.iterations
            );
            assert!(du <= 1e-8, "{case}: DD and monolithic differ by {du:.2e}");
            assert!(
                resultant.abs() <= 0.01,
                "{case}: resultant off by {resultant:+.4}"
            );
            let bound = if curved { 0.03 } else { 0.05 };
            assert!(
                lo >= -bound && hi <= bound,
                "{case}: pressures in [{lo}, {hi}]"
            );
        }
    }
}

/// A stiff penalty on P2 (θ = 1e-8, the case whose u⁰ start carried loads of 1e17 along the
/// directions the symmetry supports hold), also on meshes shifted by 1e-10 and 1e-8: converged
/// within a few steps, as the monolithic reference.
#[test]
fn stiff_penalty_and_shifted_meshes_converge() {
    for shift in [0.0, 1e-10, 1e-8] {
        for enforcement in [Enforcement::Penalty, Enforcement::Augmented] {
            let options = PressFit {
                p2: true,
                penalty: Penalty::Theta(1e-8),
                enforcement,
                shift: [shift, shift],
                ..PressFit::default()
            };
            let model = press_fit(&options).unwrap();
            let sol = run(&model);
            assert!(
                sol.converged,
                "shift {shift}, {enforcement}: {:?}",
                sol.message
            );
            let mono = solve_monolithic(&model).unwrap();
            let du = difference(&mono.bodies, &sol.bodies);
            assert!(
                du <= 1e-8,
                "shift {shift}: DD and monolithic differ by {du:.2e}"
            );
        }
    }
}

/// No interference (a clearance of 1e-3) and no load: the zero solution in one iteration,
/// converged (which includes the force balance check), for the penalty and the augmented pairs,
/// P1 and P2. (A shaft of radius exactly 1 overlaps the ring by the rounding of the node
/// coordinates, about 1e-16: a problem with data, which takes its Newton steps.)
#[test]
fn no_data_gives_zero_at_once() {
    for p2 in [false, true] {
        for enforcement in [Enforcement::Penalty, Enforcement::Augmented] {
            let options = PressFit {
                shaft_radius: RING_INNER - 1e-3,
                p2,
                enforcement,
                ..PressFit::default()
            };
            let model = press_fit(&options).unwrap();
            let sol = run(&model);
            assert!(sol.converged, "{:?}", sol.message);
            assert!(sol.iterations <= 1, "{} iterations", sol.iterations);
            for body in &sol.bodies {
                assert!(body.displacement.iter().all(|&u| u == 0.0));
            }
            assert!(sol.contact[0].pressure.iter().all(|&p| p == 0.0));
        }
    }
    // Lamé's pressure by hand: E δ / ((1 + ν) b [(1 − 2ν) + ((1 − 2ν) b² + c²)/(c² − b²)]) with
    // E = 2e5, ν = 0.3, δ = 0.005, b = 1, c = 2: 1000 / (1.3 (0.4 + 4.4/3)) = 412.088.
    let p = lame_pressure(0.005, 1.0, 2.0);
    assert!((p - 412.088).abs() < 1e-3, "{p}");
}
