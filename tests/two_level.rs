//! The two-level iteration (rigid-body coarse correction) and the Anderson accelerator on cases
//! beyond the paper's symmetric notch, against independent references: the exact uniform stress
//! of a column of blocks, force balance, the monolithic solution, and the same answer on one and
//! two threads.

use contactdd::cases;
use contactdd::ddm::{
    prepare, solve, solve_monolithic, CoarseMode, Hooks, Model, Settings, Solution,
};

fn run(model: &Model, settings: &Settings) -> Solution {
    let prepared = prepare(model).unwrap();
    solve(model, &prepared, settings, Hooks::default()).unwrap()
}

/// A column of N blocks held only by their contacts: with the default settings the iteration
/// count does not grow with N (8 → 64 blocks), and every interface carries the exact uniform
/// pressure p = 100. The one-level iteration needs hundreds of iterations at N = 8 and loses
/// contact from N = 16 on.
#[test]
fn columns_of_floating_blocks_converge_in_a_count_independent_of_their_length() {
    let mut counts = Vec::new();
    for n in [8, 16, 32, 64] {
        let model = cases::column(n, 0.5);
        let sol = run(&model, &Settings::two_level());
        assert!(sol.converged, "{n} blocks: {:?}", sol.message);
        assert!(
            sol.iterations <= 40,
            "{n} blocks: {} iterations",
            sol.iterations
        );
        for pair in &sol.contact {
            for (i, p) in pair.pressure.iter().enumerate() {
                assert!(
                    (p + 100.0).abs() <= 1.0,
                    "{n} blocks, pair {}, point {i}: σ_n = {p}",
                    pair.name
                );
            }
        }
        counts.push(sol.iterations);
    }
    assert!(
        counts[3] as f64 <= 1.5 * counts[0] as f64,
        "counts for 8, 16, 32, 64 blocks: {counts:?}"
    );
}

/// The one-level iteration on the same 16-block column does not reach a solution: the coarse
/// correction is what makes the difference. The message names the way out (the interface Newton
/// method).
#[test]
fn the_one_level_iteration_fails_where_the_two_level_one_converges() {
    let model = cases::column(16, 0.5);
    let one_level = Settings {
        coarse: CoarseMode::Off,
        ..Settings::two_level()
    };
    let sol = run(&model, &one_level);
    assert!(!sol.converged);
    let message = sol.message.unwrap_or_default();
    assert!(message.contains("accelerator = \"newton\""), "{message}");
}

/// Every accelerator and coarse mode, and the interface Newton default, converges to the monolithic penalty solution.
#[test]
fn two_level_and_anderson_agree_with_the_monolithic_solution() {
    let models = [
        cases::column(4, 0.5),
        cases::stiff_under_soft(0.05),
        contactdd::ddm::benchmark::Notch::default().model().unwrap(),
    ];
    let variants = [
        Settings::default(),
        Settings::two_level(),
        Settings {
            coarse: CoarseMode::All,
            ..Settings::two_level()
        },
        Settings::anderson(),
    ];
    for model in &models {
        let reference = solve_monolithic(model).unwrap();
        for settings in &variants {
            let settings = Settings {
                tol: 1e-11,
                max_iter: 20_000,
                ..settings.clone()
            };
            let sol = run(model, &settings);
            assert!(sol.converged, "{}: {:?}", model.name, sol.message);
            for (pair, refp) in sol.contact.iter().zip(&reference.contact) {
                let scale = refp.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
                for (p, q) in pair.pressure.iter().zip(&refp.pressure) {
                    assert!(
                        (p - q).abs() <= 1e-8 * scale,
                        "{} ({} / {}): σ_n {p} against {q}",
                        model.name,
                        settings.accelerator,
                        settings.coarse
                    );
                }
            }
        }
    }
}

/// Bodies solve in parallel; the coarse problem, the accelerator and the interface Newton
/// factorisation are sequential: the result is
/// the same to the last bit on one and on two threads.
#[test]
fn two_level_and_anderson_give_the_same_bits_on_one_and_two_threads() {
    let model = cases::column(12, 0.5);
    for settings in [
        Settings::default(),
        Settings::two_level(),
        Settings::anderson(),
    ] {
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| run(&model, &settings))
        };
        let (one, two) = (on(1), on(2));
        assert_eq!(one.iterations, two.iterations);
        for (a, b) in one.bodies.iter().zip(&two.bodies) {
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.displacement), bits(&b.displacement), "{}", a.name);
        }
    }
}

/// The coarse correction balances every floating body exactly and keeps the interface loads
/// consistent with the displacements (the recovered field has the corrected normal
/// displacements).
#[test]
fn the_coarse_correction_balances_floating_bodies_and_keeps_the_state_consistent() {
    let model = cases::column(5, 0.5);
    let prepared = prepare(&model).unwrap();
    let iface = &prepared.interface;
    let m = iface.len();
    let mut un = vec![1e-4; m];
    let mut t: Vec<f64> = Vec::with_capacity(m);
    for (b, body) in prepared.bodies.iter().flatten().enumerate() {
        t.extend(body.initial_load(&un[iface.body_range[b].clone()]));
    }
    let steps = prepared.coarse.correct(
        CoarseMode::Chains,
        iface,
        &*prepared.exchange,
        &mut un,
        &mut t,
    );
    assert!(steps >= 1);
    let mut s = vec![0.0; m];
    iface.sum_normal(&un, &mut s);
    // Blocks 1..4 float: their contact forces balance the applied load (100 · 2 on the top one).
    for b in 1..5 {
        let force: f64 = iface
            .of_body(b)
            .iter()
            .zip(&s[iface.body_range[b].clone()])
            .map(|(p, &sj)| p.weight * p.pressure(sj) * p.normal[1])
            .sum();
        let load: f64 = model.bodies[b].load.iter().skip(1).step_by(2).sum();
        assert!(
            (force + load).abs() <= 1e-9 * 200.0,
            "block {b}: contact force {force}, load {load}"
        );
    }
    for (b, body) in prepared.bodies.iter().flatten().enumerate() {
        let u = body.recover(&t[iface.body_range[b].clone()]).unwrap();
        for (p, &unj) in iface
            .of_body(b)
            .iter()
            .zip(&un[iface.body_range[b].clone()])
        {
            let normal = p.normal[0] * u[2 * p.node] + p.normal[1] * u[2 * p.node + 1];
            assert!(
                (normal - unj).abs() <= 1e-9 * unj.abs().max(1e-6),
                "block {b}"
            );
        }
    }
}
