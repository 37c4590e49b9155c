//! Load histories (`contactdd_ddm::history`): a block pressed on a foundation, then pushed
//! sideways, with Coulomb friction — the force balance of the block at every increment, the
//! onset of sliding at the closed form μN — and on frictionless cases against the load steps
//! (one group, to the bit) and superposition (two groups on a linear case).

use contactdd::ddm::history::{solve_history, HistoryStep, Increment, LoadGroup, LoadHistory};
use contactdd::ddm::steps::solve_steps;
use contactdd::ddm::*;
use contactdd::fem::{loads::load_vector, Component, Constraints, Load, Order};
use contactdd::frictional::block_on_foundation;

/// The block of [`block_on_foundation`] (8 × 4 P1 cells) with the loads `loads` and the
/// supports `supports` (none: friction alone holds it sideways).
fn block(loads: &[Load], supports: &[(&str, Component)], friction: Friction) -> Model {
    let mut model = block_on_foundation(0.0, 0.0, friction, (8, Order::P1), 0.05);
    let upper = &mut model.bodies[1];
    upper.load = load_vector(&upper.mesh, loads).expect("valid loads");
    let mut constraints = Constraints::new(upper.mesh.num_nodes());
    for &(b, c) in supports {
        constraints
            .fix(&upper.mesh, b, c, 0.0)
            .expect("a valid support");
    }
    upper.constraints = constraints;
    model
}

fn pressure(p: f64) -> Load {
    Load::Pressure {
        boundary: "top".into(),
        value: p,
    }
}

fn push(q: f64) -> Load {
    Load::Traction {
        boundary: "left".into(),
        value: [q, 0.0],
    }
}

/// A group of the block's load `load` (nothing on the foundation).
fn group(model: &Model, name: &str, load: Load) -> LoadGroup {
    let mesh = &model.bodies[1].mesh;
    LoadGroup {
        name: name.into(),
        loads: vec![Vec::new(), load_vector(mesh, &[load]).expect("valid loads")],
    }
}

fn step(name: &str, factors: &[(usize, f64)], increments: usize) -> HistoryStep {
    HistoryStep {
        name: name.into(),
        factors: factors.to_vec(),
        increments,
    }
}

fn run(model: &Model, history: &LoadHistory) -> Vec<(Increment, Solution)> {
    run_on(model, history, Condensation::Auto)
}

/// [`run`] with the bodies condensed on the path `condensation`.
fn run_on(
    model: &Model,
    history: &LoadHistory,
    condensation: Condensation,
) -> Vec<(Increment, Solution)> {
    let mut prepared = prepare_with(model, condensation).unwrap_or_else(|e| panic!("{e}"));
    solve_history(
        model,
        &mut prepared,
        &Settings::default(),
        history,
        Hooks::default(),
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

const P: f64 = 10.0;
const MU: f64 = 0.3;
/// μN with N = 2P, the block's width times the pressure.
const MU_N: f64 = MU * 2.0 * P;

/// The frictional block with groups `press` (P on the top, unit factor) and `shear` (a unit
/// push: the factor is the push Q).
fn frictional(shear_steps: &[(f64, usize)]) -> (Model, LoadHistory) {
    let model = block(&[], &[], Friction::Coulomb { mu: MU });
    let groups = vec![
        group(&model, "press", pressure(P)),
        group(&model, "shear", push(1.0)),
    ];
    let mut steps = vec![step("press", &[(1, 1.0)], 2)];
    for (k, &(q, n)) in shear_steps.iter().enumerate() {
        steps.push(step(&format!("shear{k}"), &[(2, q)], n));
    }
    (model, LoadHistory { groups, steps })
}

/// The contact forces on the block balance its loads: 2p down, q along x.
fn balanced(sol: &Solution, p: f64, q: f64) {
    let on_block = sol.contact[0].force_on(1);
    assert!((on_block[0] + q).abs() < 1e-8 * P, "{on_block:?} {q}");
    assert!((on_block[1] - 2.0 * p).abs() < 1e-8 * P, "{on_block:?} {p}");
    let t = sol.contact[0].tangential_force();
    assert!((t.abs() - q.abs()).abs() < 1e-8 * P, "{t} {q}");
}

#[test]
fn press_then_shear_up_to_nine_tenths_of_mu_n_balances_at_every_increment() {
    let (model, history) = frictional(&[(0.9 * MU_N, 6)]);
    let done = run(&model, &history);
    assert_eq!(done.len(), 8);
    for (inc, sol) in &done {
        assert!(sol.converged, "{inc:?}: {:?}", sol.message);
        balanced(sol, P * inc.factors[1], inc.factors[2]);
    }
    let (last, _) = &done[7];
    assert_eq!(last.factors, vec![0.0, 1.0, 0.9 * MU_N]);
    // The press step ramps the pressure alone: half, then all of it.
    assert_eq!(done[0].0.factors, vec![0.0, 0.5, 0.0]);
    assert_eq!((done[2].0.step, done[2].0.increment), (1, 1));
}

fn slides(sol: &Solution) -> bool {
    matches!(
        sol.stop,
        Stop::Diverged {
            body: 1,
            reason: outcome::Breakdown::Slides,
            ..
        }
    )
}

#[test]
fn a_push_past_mu_n_stops_at_the_first_increment_beyond_it() {
    // Q = 1.4, 2.8, 4.2, 5.6, 7.0 > μN = 6.
    let (model, history) = frictional(&[(8.4, 6)]);
    let done = run(&model, &history);
    assert_eq!(done.len(), 2 + 5);
    let (inc, sol) = done.last().expect("increments");
    assert!((inc.factors[2] - 7.0).abs() < 1e-12, "{inc:?}");
    assert!(!sol.converged);
    assert!(slides(sol), "{:?}", sol.stop);
    for (inc, sol) in &done[..done.len() - 1] {
        assert!(sol.converged, "{inc:?}: {:?}", sol.message);
        balanced(sol, P * inc.factors[1], inc.factors[2]);
    }
}

#[test]
fn a_fine_history_finds_the_onset_of_sliding_at_mu_n() {
    // Up to 98 % of μN in 7 increments, then increments of 0.1 % of μN to 102 %.
    let (model, history) = frictional(&[(0.98 * MU_N, 7), (1.02 * MU_N, 40)]);
    let done = run(&model, &history);
    let (inc, sol) = done.last().expect("increments");
    // Past μN every closed point slips: the block slides.
    assert!(slides(sol), "{inc:?}: {:?}", sol.stop);
    let onset = inc.factors[2];
    assert!(
        (onset - MU_N).abs() <= 0.005 * MU_N,
        "onset {onset} against μN = {MU_N}"
    );
    for (inc, sol) in &done[..done.len() - 1] {
        assert!(sol.converged, "{inc:?}: {:?}", sol.message);
        balanced(sol, P * inc.factors[1], inc.factors[2]);
    }
}

fn displacements(sol: &Solution) -> Vec<f64> {
    sol.bodies
        .iter()
        .flat_map(|b| b.displacement.iter().copied())
        .collect()
}

#[test]
fn a_one_group_history_is_the_load_steps_to_the_bit() {
    let loads = [pressure(P), push(4.0)];
    let model = block(&loads, &[], Friction::Coulomb { mu: MU });
    let mut prepared = prepare(&model).unwrap_or_else(|e| panic!("{e}"));
    let settings = Settings::default();
    let steps = solve_steps(
        &model,
        &mut prepared,
        &settings,
        &[0.5, 1.0],
        Hooks::default(),
        &mut |_, _, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let history = LoadHistory {
        groups: Vec::new(),
        steps: vec![step("half", &[(0, 0.5)], 1), step("all", &[(0, 1.0)], 1)],
    };
    let done = solve_history(
        &model,
        &mut prepared,
        &settings,
        &history,
        Hooks::default(),
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(done.len(), 2);
    for ((f, a), (inc, b)) in steps.iter().zip(&done) {
        assert!(a.converged && b.converged);
        assert_eq!(inc.factors, vec![*f]);
        assert_eq!(a.iterations, b.iterations);
        let (da, db) = (displacements(a), displacements(b));
        assert!(da.iter().zip(&db).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert_eq!(a.contact[0].tangential, b.contact[0].tangential);
        assert_eq!(a.contact[0].pressure, b.contact[0].pressure);
    }
    // The same loads as a named group (nothing left in the default group): the same bits.
    let bare = block(&[], &[], Friction::Coulomb { mu: MU });
    let mesh = &bare.bodies[1].mesh;
    let all = LoadGroup {
        name: "all".into(),
        loads: vec![Vec::new(), load_vector(mesh, &loads).expect("valid loads")],
    };
    let history = LoadHistory {
        groups: vec![all],
        steps: vec![step("half", &[(1, 0.5)], 1), step("all", &[(1, 1.0)], 1)],
    };
    let grouped = run(&bare, &history);
    for ((_, a), (_, b)) in steps.iter().zip(&grouped) {
        let (da, db) = (displacements(a), displacements(b));
        assert!(da.iter().zip(&db).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}

#[test]
fn two_groups_on_a_linear_case_superpose() {
    // The block held in x on its left side, frictionless, pressed by P and by a body force
    // along (1, −2): the contact zone stays closed everywhere, so the answer is linear.
    let held = [("left", Component::X)];
    let model = block(&[], &held, Friction::None);
    let weight = Load::BodyForce { value: [1.0, -2.0] };
    let groups = vec![
        group(&model, "press", pressure(P)),
        group(&model, "weight", weight),
    ];
    let history = |steps| LoadHistory {
        groups: groups.clone(),
        steps,
    };
    for condensation in [Condensation::Dense, Condensation::Sparse] {
        let run = |steps| run_on(&model, &history(steps), condensation);
        let both = run(vec![
            step("press", &[(1, 1.0)], 1),
            step("weight", &[(2, 1.0)], 2),
        ]);
        let press = run(vec![step("press", &[(1, 1.0)], 1)]);
        let weight = run(vec![step("weight", &[(2, 1.0)], 1)]);
        let closed = &both.last().expect("increments").1.contact[0].closed;
        let last = |d: &[(Increment, Solution)]| {
            let (_, sol) = d.last().expect("increments");
            assert!(sol.converged, "{:?}", sol.message);
            // The same contact zone under each load: the answer is linear in the loads.
            assert_eq!(&sol.contact[0].closed, closed);
            displacements(sol)
        };
        let (u, u1, u2) = (last(&both), last(&press), last(&weight));
        let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let error = (u.iter().zip(u1.iter().zip(&u2)))
            .map(|(u, (a, b))| (u - a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(
            error <= 1e-10 * scale,
            "{condensation}: {error} against {scale}"
        );
    }
}

#[test]
fn bad_histories_are_refused() {
    let model = block(&[], &[("left", Component::X)], Friction::None);
    let cases = [
        (LoadHistory::default(), "at least one step"),
        (
            LoadHistory {
                groups: Vec::new(),
                steps: vec![step("s", &[(3, 1.0)], 1)],
            },
            "no load group",
        ),
        (
            LoadHistory {
                groups: Vec::new(),
                steps: vec![step("s", &[(0, 1.0)], 0)],
            },
            "at least 1 increment",
        ),
        (
            LoadHistory {
                groups: Vec::new(),
                steps: vec![step("s", &[(0, f64::NAN)], 1)],
            },
            "finite",
        ),
    ];
    for (history, message) in cases {
        let mut prepared = prepare(&model).unwrap_or_else(|e| panic!("{e}"));
        let Err(e) = solve_history(
            &model,
            &mut prepared,
            &Settings::default(),
            &history,
            Hooks::default(),
            &mut |_, _| {},
        ) else {
            panic!("{history:?} accepted");
        };
        assert!(e.to_string().contains(message), "{e}");
    }
}

#[test]
fn press_then_shear_with_exact_friction_balances_at_every_increment() {
    let (mut model, history) = frictional(&[(0.9 * MU_N, 3)]);
    model.pairs[0].enforcement = Enforcement::Augmented;
    let done = run(&model, &history);
    assert_eq!(done.len(), 5);
    for (inc, sol) in &done {
        assert!(sol.converged, "{inc:?}: {:?}", sol.message);
        balanced(sol, P * inc.factors[1], inc.factors[2]);
        let pair = &sol.contact[0];
        assert!(pair.traction_excess() <= 1e-12, "{inc:?}");
        // Exact stick: the sticking points keep their tangential displacement.
        assert!(
            pair.slip_violation() <= 1e-8,
            "{inc:?}: {}",
            pair.slip_violation()
        );
    }
}
