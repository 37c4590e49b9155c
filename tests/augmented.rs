//! Augmented Lagrangian enforcement (`docs/augmented-lagrangian.md`): the exact unilateral contact
//! for any penalty θ. The references are independent of the solver: the closed form of a recess
//! between two pressed half-planes, force balance, the Signorini conditions themselves, and the
//! same loop around a second inner iteration (the Robin sweeps).

use contactdd::cases;
use contactdd::ddm::benchmark::Notch;
use contactdd::ddm::solution::PairResult;
use contactdd::ddm::{
    prepare_with, solve, Enforcement, Forces, Hooks, Model, Settings, Solution, Stop,
};

/// Prepared for the iteration that `settings` choose (the inner penalty of augmented pairs
/// depends on it).
fn run(model: &Model, settings: &Settings) -> Solution {
    let prepared = prepare_with(model, settings).unwrap();
    solve(model, &prepared, settings, Hooks::default()).unwrap()
}

fn augmented(mut model: Model) -> Model {
    for pair in &mut model.pairs {
        pair.enforcement = Enforcement::Augmented;
    }
    model
}

fn notch(c: f64) -> Model {
    Notch {
        c,
        ..Notch::default()
    }
    .model()
    .unwrap()
}

fn peak(pair: &PairResult) -> f64 {
    pair.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()))
}

/// The contact half-width on side `side`, for a zone that is open near x = 0 and closed beyond:
/// the pressure grows like √(x − a) past the edge a, so p² is extrapolated linearly to zero from
/// the first two closed points.
fn open_half_width(pair: &PairResult, side: usize) -> f64 {
    let mut points: Vec<(f64, f64)> = (0..pair.x.len())
        .filter(|&i| pair.side[i] == side)
        .map(|i| (pair.x[i], pair.pressure[i].abs()))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first = points.iter().position(|p| p.1 > 0.0).unwrap();
    let ((x1, p1), (x2, p2)) = (points[first], points[first + 1]);
    x1 - p1 * p1 * (x2 - x1) / (p2 * p2 - p1 * p1)
}

/// The paper's notch with θ 100× apart (both stiffer than the inner penalty that augmented
/// balanced pairs use at least, so both are used as given): exact mode gives the same peak pressure
/// and closed set to 1e−4, where the penalty solutions differ by percents.
#[test]
fn exact_mode_does_not_depend_on_the_penalty() {
    let settings = Settings::default();
    let solve_at = |c: f64, exact: bool| {
        let model = if exact { augmented(notch(c)) } else { notch(c) };
        let sol = run(&model, &settings);
        assert!(sol.converged, "c = {c}: {:?}", sol.message);
        sol
    };
    let (soft, stiff) = (solve_at(0.005, true), solve_at(0.00005, true));
    let (a, b) = (&soft.contact[0], &stiff.contact[0]);
    let change = (peak(a) - peak(b)).abs() / peak(b);
    assert!(change <= 1e-4, "peak pressure changes by {change:.2e}");
    assert_eq!(a.closed, b.closed, "the closed points differ");
    let (pa, pb) = (solve_at(0.005, false), solve_at(0.00005, false));
    let penalty_change = (peak(&pa.contact[0]) - peak(&pb.contact[0])).abs() / peak(&pb.contact[0]);
    assert!(
        penalty_change > 100.0 * change,
        "the penalty itself changes by only {penalty_change:.2e}"
    );
}

/// The result meets the Signorini conditions to the gap tolerance, carries the applied load, and
/// reports how many multiplier updates it took.
#[test]
fn exact_mode_meets_the_signorini_conditions_and_balances_the_load() {
    let sol = run(&augmented(notch(0.05)), &Settings::default());
    assert!(sol.converged, "{:?}", sol.message);
    let tol = sol.gap_tol.unwrap();
    let pair = &sol.contact[0];
    assert!(pair.max_penetration() <= tol, "{}", pair.max_penetration());
    assert!(pair.complementarity() <= tol, "{}", pair.complementarity());
    assert!(pair.pressure.iter().all(|&p| p <= 0.0));
    for side in 0..2 {
        let f = pair.force_on(side)[1].abs();
        assert!(
            (f - 8400.0).abs() <= 1e-6 * 8400.0,
            "side {side} carries {f}"
        );
    }
    assert!(sol.updates > 1);
    // The penalty solution at the same θ penetrates by θ·p, far above the tolerance.
    let penalty = run(&notch(0.05), &Settings::default());
    assert!(penalty.contact[0].max_penetration() > 1e3 * tol);
}

/// The multiplier updates do not grow with a soft penalty or a finer mesh: the inner penalty of
/// an augmented balanced pair is at least as stiff as the rod model with c = 0.05 and the point's
/// share of the boundary as h, so each update contracts by about the same factor whatever θ and
/// the mesh.
#[test]
fn exact_mode_updates_do_not_grow_with_a_soft_penalty_or_a_finer_mesh() {
    let settings = Settings::default();
    let updates = |c: f64, nx: usize| {
        let model = augmented(
            Notch {
                c,
                nx,
                ny: nx / 2,
                ..Notch::default()
            }
            .model()
            .unwrap(),
        );
        let sol = run(&model, &settings);
        assert!(sol.converged, "c = {c}, nx = {nx}: {:?}", sol.message);
        sol.updates
    };
    let paper = updates(0.05, 32);
    for (c, nx) in [(0.5, 32), (5.0, 32), (0.05, 128), (0.5, 256)] {
        let n = updates(c, nx);
        assert!(
            n <= paper + 1,
            "c = {c}, nx = {nx}: {n} updates against {paper} for the paper's notch"
        );
    }
}

/// With the stiffer inner penalty a pair's gaps close long before its pressures settle: a gap
/// tolerance met at once does not end the loop while the pressures still change by more than
/// `tol` of the peak, and a cap on the updates then reports that, not a solution.
#[test]
fn closed_gaps_with_unsettled_pressures_are_not_a_solution() {
    let settings = Settings {
        gap_tol: Some(1.0),
        max_updates: 2,
        ..Settings::default()
    };
    let sol = run(&augmented(notch(0.5)), &settings);
    assert!(!sol.converged);
    assert!(
        matches!(sol.stop, Stop::Unenforced { .. }),
        "{:?}",
        sol.stop
    );
    let message = sol.message.unwrap_or_default();
    assert!(message.contains("pressures still change"), "{message}");
    let relaxed = Settings {
        max_updates: 100,
        ..settings
    };
    assert!(run(&augmented(notch(0.5)), &relaxed).converged);
}

/// Warm-started Newton solves: every multiplier update after the first inner solve (which is the
/// penalty solve itself) costs at most two Newton iterations on average, where a cold start would
/// cost a whole penalty solve each.
#[test]
fn exact_mode_updates_cost_a_few_newton_steps() {
    let settings = Settings::default();
    let exact = run(&augmented(notch(0.05)), &settings);
    let penalty = run(&notch(0.05), &settings);
    assert!(exact.converged, "{:?}", exact.message);
    assert!(exact.updates > 1);
    assert!(
        exact.iterations - penalty.iterations <= 2 * (exact.updates - 1),
        "{} inner iterations in {} updates, against {} for one penalty solve",
        exact.iterations,
        exact.updates,
        penalty.iterations
    );
}

/// A second inner iteration (the two-level Robin sweeps) reaches the same exact solution.
#[test]
fn the_sweeps_inside_the_loop_reach_the_same_solution() {
    let model = augmented(notch(0.05));
    let newton = run(&model, &Settings::default());
    let sweeps = run(&model, &Settings::two_level());
    assert!(sweeps.converged, "{:?}", sweeps.message);
    let (a, b) = (&newton.contact[0], &sweeps.contact[0]);
    let scale = peak(a);
    for (p, q) in a.pressure.iter().zip(&b.pressure) {
        assert!((p - q).abs() <= 1e-3 * scale, "{p} against {q}");
    }
}

/// A recess between two large pressed blocks: the open half-width is that of two half-planes,
/// a = b √(1 − q/q*), q* = 3 E* r₀ / (4 b), within 1 %.
#[test]
fn exact_mode_opens_the_recess_of_two_half_planes() {
    let model = augmented(cases::recess(1.0, 0.05, 64));
    let sol = run(&model, &Settings::default());
    assert!(sol.converged, "{:?}", sol.message);
    let e_star = 2.1e5 / (2.0 * (1.0 - 0.3f64.powi(2)));
    let q_star = 3.0 * e_star * cases::RECESS_R0 / (4.0 * cases::RECESS_B);
    let exact = cases::RECESS_B * (1.0 - cases::RECESS_Q / q_star).sqrt();
    for side in 0..2 {
        let a = open_half_width(&sol.contact[0], side);
        let error = (a - exact).abs() / exact;
        assert!(error <= 0.01, "side {side}: a = {a}, exact {exact}");
    }
}

/// The non-matching notch in exact mode with own-side forces, solved to the gap tolerance
/// `gap_tol`.
fn own_side_notch(gap_tol: Option<f64>, balance_tol: Option<f64>) -> Solution {
    let mut model = augmented(cases::non_matching_notch(0.05));
    for pair in &mut model.pairs {
        pair.forces = Forces::OwnSide;
    }
    let settings = Settings {
        gap_tol,
        balance_tol,
        ..Settings::default()
    };
    run(&model, &settings)
}

/// A gap tolerance below the rounding of the displacements (1e−20 against displacements of about
/// 1e−2) cannot be reached: the run says so instead of reporting a solution, and returns its last
/// consistent state (fields and pressures of one inner solve, in equilibrium).
#[test]
fn an_exact_contact_out_of_reach_is_reported() {
    let sol = own_side_notch(Some(1e-20), None);
    assert!(!sol.converged);
    assert!(
        matches!(sol.stop, Stop::Unenforced { .. }),
        "{:?}",
        sol.stop
    );
    assert!(sol.message.unwrap().contains("multiplier updates"));
    assert!(
        sol.equilibrium.iter().all(|&e| e <= 1e-2),
        "{:?}",
        sol.equilibrium
    );
}

/// The non-matching notch with own-side forces: every node of both sides closes onto the other
/// side's interpolated surface (the sum of the two piecewise linear boundaries is fixed at the
/// union of their nodes, which either side's kinks can match), so a tight gap tolerance is
/// reached; the two sides' forces then differ, as own-side forces do on non-matching meshes, so
/// the bodies do not balance: the result is a solution only for a balance tolerance that accepts
/// that difference.
#[test]
fn own_side_pairs_reach_exact_contact_on_non_matching_meshes() {
    let strict = own_side_notch(Some(1e-14), None);
    assert!(
        matches!(strict.stop, Stop::Unbalanced { .. }),
        "{:?}",
        strict.stop
    );
    assert!(strict.message.unwrap().contains("own-side"));
    let sol = own_side_notch(Some(1e-14), Some(1e-2));
    assert!(sol.converged, "{:?}", sol.message);
    let pair = &sol.contact[0];
    assert!(pair.max_penetration() <= 1e-14 && pair.complementarity() <= 1e-14);
    let (a, b) = (pair.force_on(0)[1], pair.force_on(1)[1]);
    assert!((a + b).abs() > 1e-4 * a.abs(), "{a} against {b}");
}

/// The same non-matching notch with balanced forces (the default): only the reference side's
/// points enforce the contact, so the tight gap tolerance is reached.
#[test]
fn balanced_pairs_reach_exact_contact_on_non_matching_meshes() {
    let model = augmented(cases::non_matching_notch(0.05));
    let settings = Settings {
        gap_tol: Some(1e-14),
        ..Settings::default()
    };
    let sol = run(&model, &settings);
    assert!(sol.converged, "{:?}", sol.message);
    let pair = &sol.contact[0];
    let (a, b) = (pair.force_on(0), pair.force_on(1));
    assert!((a[0] + b[0]).hypot(a[1] + b[1]) <= 1e-10 * a[0].hypot(a[1]));
}

/// Curved non-matching meshes: the shipped Hertz example (P2 half disc on a block) in exact mode
/// reaches its gap tolerance with the balanced pair, whose two sides stay equal and opposite.
#[test]
fn exact_contact_on_the_curved_non_matching_hertz_example() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hertz.toml");
    let loaded = contactdd::io::load_file(&file).unwrap();
    let model = augmented(loaded.model);
    let sol = run(&model, &loaded.settings);
    assert!(sol.converged, "{:?}", sol.message);
    let pair = &sol.contact[0];
    assert!(sol.gap_tol.is_some_and(|tol| pair.max_penetration() <= tol));
    assert!(pair.complementarity() <= sol.gap_tol.unwrap_or(0.0));
    let (a, b) = (pair.force_on(0), pair.force_on(1));
    assert!((a[0] + b[0]).hypot(a[1] + b[1]) <= 1e-10 * a[0].hypot(a[1]));
    assert!((b[1].abs() - 900.0).abs() <= 1e-8 * 900.0, "{b:?}");
}

/// The monolithic reference in augmented mode (plain Uzawa updates around its own Newton solver)
/// reaches the same exact contact as the DD's accelerated loop: the notch and a stiff block under
/// a softer one, with a gap tolerance near round-off.
#[test]
fn exact_mode_agrees_with_the_monolithic_reference() {
    use contactdd::ddm::monolithic::{solve_monolithic_with, MonolithicSettings};
    for model in [
        augmented(notch(0.05)),
        augmented(cases::stiff_under_soft(0.05)),
    ] {
        let gap_tol = Some(1e-13);
        let dd = run(
            &model,
            &Settings {
                gap_tol,
                ..Settings::default()
            },
        );
        assert!(dd.converged, "{}: {:?}", model.name, dd.message);
        let settings = MonolithicSettings {
            gap_tol,
            ..MonolithicSettings::default()
        };
        let mono = solve_monolithic_with(&model, &settings, None).unwrap();
        assert!(mono.converged, "{}: {:?}", model.name, mono.message);
        assert!(mono.updates > 1);
        let (a, b) = (&dd.contact[0], &mono.contact[0]);
        let scale = peak(b);
        for (p, q) in a.pressure.iter().zip(&b.pressure) {
            assert!(
                (p - q).abs() <= 1e-8 * scale,
                "{}: {p} against {q}",
                model.name
            );
        }
    }
}

/// The paper's notch in exact mode with penalty θ given.
fn exact_notch_with_theta(theta: f64) -> Model {
    let mut model = augmented(notch(0.05));
    model.pairs[0].penalty = contactdd::ddm::Penalty::Theta(theta);
    model
}

/// A penalty far softer than the contact (θ = 100 and 1e6 on the notch, whose rod model gives
/// 4.3e−7): the monolithic reference's exact mode meets the Signorini conditions to its gap
/// tolerance, a millionth of the notch's depth at most (with the pair's own θ its first solve
/// moved the bodies into each other by θ·p, and the tolerance taken from it let a violation of 85 %
/// of the depth through), and its peak pressure is the decomposition's to 1e−6.
#[test]
fn a_soft_penalty_reaches_exact_contact_in_the_monolithic_reference() {
    use contactdd::ddm::monolithic::{solve_monolithic_with, MonolithicSettings};
    // The notch's depth r0 (`contactdd::ddm::benchmark`).
    let depth = 0.05;
    for theta in [100.0, 1e6] {
        let model = exact_notch_with_theta(theta);
        let dd = run(&model, &Settings::default());
        assert!(dd.converged, "θ = {theta}: {:?}", dd.message);
        let mono = solve_monolithic_with(&model, &MonolithicSettings::default(), None).unwrap();
        assert!(mono.converged, "θ = {theta}: {:?}", mono.message);
        let gap_tol = mono.gap_tol.expect("an augmented pair has a gap tolerance");
        assert!(gap_tol <= 1e-6 * depth, "θ = {theta}: gap-tol {gap_tol:e}");
        let pair = &mono.contact[0];
        assert!(pair.complementarity() <= gap_tol, "θ = {theta}");
        assert!(pair.max_penetration() <= gap_tol, "θ = {theta}");
        let (a, b) = (peak(&dd.contact[0]), peak(pair));
        assert!(
            (a - b).abs() <= 1e-6 * a,
            "θ = {theta}: peak {b} against {a}"
        );
        assert_eq!(dd.contact[0].closed, pair.closed, "θ = {theta}");
    }
}

/// The default gap tolerance does not depend on θ where the inner penalty is the stiffer one
/// (θ softer than the rod model's with c = AUGMENTED_C and h the points' shares): the paper's θ,
/// 100 times it, 100 and 1e6 give the monolithic reference the same tolerance, and the same as
/// the decomposition's.
#[test]
fn the_default_gap_tolerance_does_not_depend_on_the_penalty() {
    use contactdd::ddm::monolithic::{solve_monolithic_with, MonolithicSettings};
    let paper = notch(0.05).theta(0);
    let tols: Vec<(f64, f64)> = [paper, 100.0 * paper, 100.0, 1e6]
        .into_iter()
        .map(|theta| {
            let model = exact_notch_with_theta(theta);
            let settings = MonolithicSettings::default();
            let mono = solve_monolithic_with(&model, &settings, None).unwrap();
            let dd = run(&model, &Settings::default());
            (mono.gap_tol.unwrap(), dd.gap_tol.unwrap())
        })
        .collect();
    let (first, _) = tols[0];
    for &(mono, dd) in &tols {
        assert!((mono - first).abs() <= 1e-12 * first, "{tols:?}");
        assert!((mono - dd).abs() <= 1e-9 * dd, "{tols:?}");
    }
}

/// A wall of 8 blocks drawn by `scripts/random_walls.py` (seed 99: non-matching balanced pairs,
/// c = 5e−4, exact contact on every pair). An Anderson extrapolation across a change of the
/// closed set takes its loop further from done, and later updates would build on it: restarted
/// after such an update, the loop converges, in
/// equilibrium, to the monolithic reference's exact contact within the gap tolerance's reach
/// (1e−3 of the peak pressure; 3.5e−5 measured). The monolithic loop is plain Uzawa with the
/// pairs' own θ: an independent path to the same conditions.
#[test]
fn a_wall_of_blocks_reaches_exact_contact() {
    use contactdd::ddm::monolithic::{solve_monolithic_with, MonolithicSettings};
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/walls/wall99.toml");
    let model = contactdd::io::setup::load_file(&file).unwrap().model;
    let dd = run(&model, &Settings::default());
    assert!(dd.converged, "{:?}", dd.message);
    let worst = dd.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
    assert!(worst <= 1e-8, "equilibrium residual {worst:e}");
    let mono = solve_monolithic_with(&model, &MonolithicSettings::default(), None).unwrap();
    assert!(mono.converged, "{:?}", mono.message);
    let scale = dd.contact.iter().map(peak).fold(0.0, f64::max);
    for (a, b) in dd.contact.iter().zip(&mono.contact) {
        for (p, q) in a.pressure.iter().zip(&b.pressure) {
            assert!((p - q).abs() <= 1e-3 * scale, "{}: {p} against {q}", a.name);
        }
    }
}
