//! The monolithic reference against independent checks: the domain decomposition's answer (a
//! second method), the applied loads that the contact forces must carry (conservation), the
//! rejection that `solve` gives a body that is not held, its Newton count on the Hertz
//! example, and walls of blocks drawn at random on which the decomposition once failed.

use std::path::Path;

use contactdd::cases;
use contactdd::ddm::benchmark::Notch;
use contactdd::ddm::monolithic::{solve_monolithic_with, MonolithicSettings};
use contactdd::ddm::{
    prepare, prepare_with, solve, solve_monolithic, Condensation, Forces, Gamma, Hooks, Method,
    Model, MonolithicSolution, Settings, Solution,
};
use contactdd::fem::{Component, Constraints, Material};

/// The paper's notch with the lower body `ratio` times stiffer.
fn notch_with_contrast(ratio: f64) -> Model {
    let mut model = Notch::default().model().unwrap();
    model.name = format!("notch, lower {ratio:e} times stiffer");
    let e = model.bodies[0].material.young();
    model.bodies[0].material = Material::new(e * ratio, 0.3).unwrap();
    model
}

/// The paper's notch with penalty factor `c`.
fn notch_with_penalty(c: f64) -> Model {
    let mut model = Notch {
        c,
        ..Notch::default()
    }
    .model()
    .unwrap();
    model.name = format!("notch, c = {c:e}");
    model
}

/// The notch with non-matching meshes and the lower body supported at its bottom. (Held only by
/// their contact, the two bodies could move up together, and their non-matching sides' forces do
/// not balance exactly: no equilibrium exists, and each method treats the residue its own way.)
fn non_matching_held() -> Model {
    let mut model = cases::non_matching_notch(0.05);
    let lower = &mut model.bodies[0];
    lower
        .constraints
        .fix(&lower.mesh, "bottom", Component::Y, 0.0)
        .unwrap();
    model
}

/// Largest |a − b| relative to the largest |b|.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

/// The monolithic reference (converged) and the DD (default settings, tight tolerance) of
/// `model`.
fn both(model: &Model) -> (MonolithicSolution, Solution) {
    let reference = solve_monolithic(model).unwrap();
    assert!(
        reference.converged,
        "{}: {:?}",
        model.name, reference.message
    );
    let settings = Settings {
        tol: 1e-12,
        max_iter: 200,
        ..Settings::default()
    };
    let prepared = prepare(model).unwrap();
    let dd = solve(model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(dd.converged, "{}: DD {:?}", model.name, dd.message);
    (reference, dd)
}

/// Every pair's pressures and gaps agree to `tol`.
fn contact_agrees(name: &str, dd: &Solution, reference: &MonolithicSolution, tol: f64) {
    for (pair, refp) in dd.contact.iter().zip(&reference.contact) {
        let err = relative_difference(&pair.pressure, &refp.pressure);
        assert!(err <= tol, "{name}: pressure off by {err:e}");
        let err = relative_difference(&pair.gap, &refp.gap);
        assert!(err <= tol, "{name}: gap d − s off by {err:e}");
    }
}

/// The DD and the monolithic solution agree to `tol` on every pair's pressures and gaps and,
/// where no rigid motion is left free, on the displacement fields.
fn agree(model: &Model, tol: impl Fn(&Solution) -> f64) {
    let (reference, dd) = both(model);
    let tol = tol(&dd);
    contact_agrees(&model.name, &dd, &reference, tol);
    if reference.rigid_modes.is_empty() {
        for (body, refb) in dd.bodies.iter().zip(&reference.bodies) {
            let err = relative_difference(&body.displacement, &refb.displacement);
            assert!(
                err <= tol,
                "{} '{}': u off by {err:e}",
                model.name,
                body.name
            );
        }
    }
}

#[test]
fn the_decomposition_and_the_monolithic_solution_agree() {
    for model in [
        Notch::default().model().unwrap(),
        cases::column(8, 0.5),
        non_matching_held(),
        cases::stiff_under_soft(0.005),
    ] {
        agree(&model, |_| 1e-8);
    }
}

/// With the lower body 1e8 times stiffer, the DD's own round-off shows in the load it carries
/// (about 5e-8 of it, where the monolithic result carries it to 1e-14): the two agree to 1e-8
/// plus that error.
#[test]
fn a_stiff_pair_agrees_within_the_decompositions_own_load_error() {
    let model = notch_with_contrast(1e8);
    let applied: f64 = model.bodies[0].load.iter().skip(1).step_by(2).sum();
    agree(&model, |dd| {
        let carried = dd.contact[0].force_on(0)[1];
        1e-8 + 2.0 * (carried + applied).abs() / applied.abs()
    });
}

/// The contact force on each side of the notch equals the load applied to that body: both bodies
/// are held vertically only by the contact.
fn carries_the_load(model: &Model) {
    let sol = solve_monolithic(model).unwrap();
    assert!(sol.converged, "{}: {:?}", model.name, sol.message);
    let pair = &sol.contact[0];
    for side in 0..2 {
        let applied: f64 = model.bodies[side].load.iter().skip(1).step_by(2).sum();
        let carried = pair.force_on(side)[1];
        assert!(
            (carried + applied).abs() <= 1e-8 * applied.abs(),
            "{} side {side}: contact force {carried} against the applied {applied}",
            model.name
        );
    }
}

#[test]
fn contact_forces_carry_the_applied_load() {
    carries_the_load(&notch_with_contrast(1e8));
    carries_the_load(&notch_with_contrast(1e-8));
    carries_the_load(&notch_with_penalty(1e6));
    carries_the_load(&notch_with_penalty(1e-4));
}

/// The notch's two bodies can move up together, and nothing else: one rigid mode, listed once.
#[test]
fn the_one_free_motion_is_found_once() {
    for model in [notch_with_contrast(1.0), notch_with_contrast(1e8)] {
        let sol = solve_monolithic(&model).unwrap();
        assert_eq!(
            sol.rigid_modes,
            ["translation in y of 'lower' together with translation in y of 'upper'"]
        );
    }
}

/// A soft block with no horizontal support on a clamped one: the contact holds it only
/// vertically. Both solvers reject it with the same message.
#[test]
fn a_body_that_is_not_held_is_rejected_as_solve_rejects_it() {
    let mut model = cases::stiff_under_soft(0.05);
    let soft = &mut model.bodies[1];
    soft.constraints = Constraints::new(soft.mesh.num_nodes());
    let dd = prepare(&model).err().expect("solve rejects it").to_string();
    let mono = solve_monolithic(&model)
        .expect_err("monolithic rejects it")
        .to_string();
    assert_eq!(mono, dd);
    assert!(mono.contains("soft"), "{mono}");
    // And a supported one is accepted.
    let soft = &mut model.bodies[1];
    soft.constraints
        .fix(&soft.mesh, "right", Component::X, 0.0)
        .unwrap();
    assert!(solve_monolithic(&model).unwrap().converged);
}

/// A step cap too small to settle: the result says so instead of claiming convergence.
#[test]
fn a_run_cut_short_is_not_converged() {
    let model = cases::stiff_under_soft(0.005);
    let settings = MonolithicSettings {
        max_steps: 1,
        ..MonolithicSettings::default()
    };
    let sol = solve_monolithic_with(&model, &settings, None).unwrap();
    assert!(!sol.converged);
    assert!(sol
        .message
        .as_deref()
        .unwrap_or("")
        .contains("did not settle"));
    assert_eq!(sol.history.len(), 1);
}

/// The Hertz example (non-matching curved contact, stiff penalty) settles within 25 Newton
/// steps, in equilibrium.
#[test]
fn hertz_settles_within_25_steps() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hertz.toml");
    let loaded = contactdd::io::setup::load_file(&path).unwrap();
    let sol = solve_monolithic(&loaded.model).unwrap();
    assert!(sol.converged, "{:?}", sol.message);
    assert!(sol.newton_steps <= 25, "{} steps", sol.newton_steps);
    // The block is held vertically only by the contact: it carries the applied load.
    let block = &loaded.model.bodies[1];
    let applied: f64 = block.load.iter().skip(1).step_by(2).sum();
    let carried = sol.contact[0].force_on(1)[1];
    assert!(
        (carried + applied).abs() <= 1e-8 * applied.abs(),
        "{carried} against {applied}"
    );
}

/// Every shipped example, at its full load (load steps aside): the monolithic reference settles
/// within 25 Newton steps, in equilibrium, and agrees with the DD to 1e-8 in every pair's
/// pressures and gaps. That includes the cylinder between two plates (two curved non-matching
/// pairs), on which full active-set steps without globalisation wander from closed set to
/// closed set.
#[test]
fn every_example_settles_and_agrees_with_the_decomposition() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 6, "{files:?}");
    for file in files {
        let model = contactdd::io::setup::load_file(&file).unwrap().model;
        if model.is_augmented() {
            // The augmented Lagrangian's agreement is tests/augmented.rs's.
            continue;
        }
        let (reference, dd) = both(&model);
        let name = &model.name;
        assert!(
            reference.newton_steps <= 25,
            "{name}: {} steps",
            reference.newton_steps
        );
        contact_agrees(name, &dd, &reference, 1e-8);
        let residual = reference.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
        assert!(
            residual <= 1e-10,
            "{name}: equilibrium residual {residual:e}"
        );
    }
}

/// Walls of elastic blocks drawn by `scripts/random_walls.py` (seeds 19, 286 and 375, written to
/// `tests/data/walls/` with penalty contact), each a case the default solver failed on:
///
/// - `wall19` (7 bodies, balanced pairs, some matching node for node): the first Newton step's J
///   was singular, because a closed point of an own-side pair was counted as holding its partner
///   body, which only its own points load;
/// - `wall286` (5 bodies, own-side pairs): "nothing holds" a block that its closed neighbours'
///   points did not in fact hold, for the same reason;
/// - `wall375` (4 bodies): a block 0.045 wide standing on a base whose nodes are 0.4 apart was
///   rejected as "not positive definite": the base, chosen to carry the balanced pair's
///   pressure on a tie of flatness, had no node under the block.
///
/// Each must now converge with the default settings in at most 30 steps, agree with the
/// monolithic reference on every pair's pressures to 1e−8 of the peak, and be in equilibrium:
/// every body's field carries the forces of its contact pressures to 1e−8 (the solver's check).
fn wall_agrees(seed: usize) {
    wall_agrees_on(seed, Condensation::Auto, 30);
}

/// Own-side pairs on non-matching meshes carry different forces on their two sides, so their
/// walls do not balance (docs/outputs.md, "The force balance"): these tests compare the
/// decomposition with the monolithic reference on the same discrete problem, so they accept
/// that imbalance.
fn own_side_tol(model: &Model) -> Option<f64> {
    let own_side = model.pairs.iter().any(|p| p.forces == Forces::OwnSide);
    own_side.then_some(1.0)
}

/// [`wall_agrees`] with every body on the path `condensation`, in at most `steps` steps.
fn wall_agrees_on(seed: usize, condensation: Condensation, steps: usize) {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/walls/wall{seed}.toml"));
    let model = contactdd::io::setup::load_file(&file).unwrap().model;
    let prepared = prepare_with(&model, condensation).unwrap();
    let settings = Settings {
        tol: 1e-10,
        balance_tol: own_side_tol(&model),
        ..Settings::default()
    };
    let dd = solve(&model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(dd.converged, "wall{seed}: {:?}", dd.message);
    assert!(
        dd.iterations <= steps,
        "wall{seed}: {} iterations",
        dd.iterations
    );
    let limits = MonolithicSettings {
        balance_tol: own_side_tol(&model).unwrap_or(MonolithicSettings::default().balance_tol),
        ..MonolithicSettings::default()
    };
    let reference = solve_monolithic_with(&model, &limits, None).unwrap();
    assert!(reference.converged, "wall{seed}: {:?}", reference.message);
    for (pair, refp) in dd.contact.iter().zip(&reference.contact) {
        let err = relative_difference(&pair.pressure, &refp.pressure);
        assert!(
            err <= 1e-8,
            "wall{seed}, {}: pressure off by {err:e}",
            pair.name
        );
    }
    let worst = dd.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
    assert!(worst <= 1e-8, "wall{seed}: equilibrium residual {worst:e}");
}

#[test]
fn an_own_side_pair_closed_on_one_side_does_not_hold_the_other() {
    wall_agrees(19);
    wall_agrees(286);
}

#[test]
fn a_narrow_block_on_a_coarse_base_stands() {
    wall_agrees(375);
}

/// `wall11` (6 bodies, own-side pairs on non-matching P2 meshes, a stiff penalty) with every
/// block on the sparse path. Own-side pairs on non-matching meshes derive from no energy, and this
/// wall's penalty problem has several exact solutions: a start from zero load reaches one 0.6 %
/// off in pressure, with the bottom corners of a narrow block open, and the monolithic reference's
/// damped path from u = 0 reaches one state or another depending on round-off (a change of the
/// elimination order moved it to a third, in equilibrium to 1e−13 with pressures up to 30 % off).
/// Sparse bodies start unloaded only where the problem minimises an energy (`newton.rs`,
/// `variational`); here they start from u⁰ as dense ones do, and reach the dense path's state.
#[test]
fn sparse_blocks_start_unloaded_only_where_the_solution_is_unique() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/walls/wall11.toml");
    let model = contactdd::io::setup::load_file(&file).unwrap().model;
    let settings = Settings {
        tol: 1e-10,
        balance_tol: own_side_tol(&model),
        ..Settings::default()
    };
    let on = |condensation| {
        let prepared = prepare_with(&model, condensation).unwrap();
        let dd = solve(&model, &prepared, &settings, Hooks::default()).unwrap();
        assert!(dd.converged, "{condensation:?}: {:?}", dd.message);
        assert!(
            dd.iterations <= 30,
            "{condensation:?}: {} iterations",
            dd.iterations
        );
        let worst = dd.equilibrium.iter().fold(0.0f64, |m, &e| m.max(e));
        assert!(
            worst <= 1e-8,
            "{condensation:?}: equilibrium residual {worst:e}"
        );
        dd
    };
    let (sparse, dense) = (on(Condensation::Sparse), on(Condensation::Dense));
    for (s, d) in sparse.contact.iter().zip(&dense.contact) {
        let err = relative_difference(&s.pressure, &d.pressure);
        assert!(err <= 1e-8, "{}: pressure off by {err:e}", s.name);
    }
}

/// `wall302` (4 bodies, own-side pairs, a stiff penalty): a block pressed from above is left with
/// no closed point by a step, and again by the next one, which glued its points, while the
/// blocks around it still have the wrong closed sets. It was reported as pulled away ("nothing
/// holds") at step 2; the monolithic reference solves it in 3 steps. The watchdog now goes back
/// to its checkpoint, where every block was held, and the wall converges (in 42 steps at the
/// file's tolerance: an own-side wall with a penalty this stiff is the slowest family of
/// `scripts/random_walls.py`).
#[test]
fn a_block_stranded_twice_is_not_given_up_while_a_held_state_came_before() {
    wall_agrees_on(302, Condensation::Auto, 60);
}

/// The notch under loads `factor` times the paper's.
fn notch_scaled(factor: f64) -> Model {
    let mut model = Notch::default().model().unwrap();
    model.name = format!("notch under {factor:e} times its loads");
    for body in &mut model.bodies {
        body.load.iter_mut().for_each(|f| *f *= factor);
    }
    model
}

/// Loads of 1e-30 and 1e-60 (on a geometry whose contact points match exactly) solve like any
/// other, and no load gives zero at once: the starting value u⁰ = 1e-4 of the paper would bury them in rounding, so the
/// iterations start at the data's scale. The interface Newton method and the paper's
/// Newton–Kurchatov sweeps both agree with the monolithic reference, which has no starting value.
#[test]
fn tiny_loads_converge_to_the_references_answer() {
    let kurchatov = Settings {
        tol: 1e-10,
        max_iter: 500,
        ..Settings::paper(Method::NewtonKurchatov, Gamma::Constant(0.5))
    };
    for factor in [1e-30, 1e-60] {
        let model = notch_scaled(factor);
        agree(&model, |_| 1e-8);
        let reference = solve_monolithic(&model).unwrap();
        let prepared = prepare(&model).unwrap();
        let sweeps = solve(&model, &prepared, &kurchatov, Hooks::default()).unwrap();
        assert!(sweeps.converged, "{}: {:?}", model.name, sweeps.message);
        contact_agrees(&model.name, &sweeps, &reference, 1e-6);
    }
    // No load at all: zero is the answer, at once, for the sweeps too (which start from u⁰ = 0
    // there and would find nothing closed to hold the floating bodies).
    let model = notch_scaled(0.0);
    let prepared = prepare(&model).unwrap();
    for method in [Method::NewtonKurchatov, Method::ActiveSet, Method::Robin] {
        let settings = Settings::paper(method, Gamma::Constant(0.5));
        let sol = solve(&model, &prepared, &settings, Hooks::default()).unwrap();
        assert!(sol.converged, "{method}: {:?}", sol.message);
        assert_eq!(sol.iterations, 1, "{method}");
        assert!(sol.contact[0].pressure.iter().all(|&p| p == 0.0));
        assert!(sol
            .bodies
            .iter()
            .all(|b| b.displacement.iter().all(|&u| u == 0.0)));
    }
}
