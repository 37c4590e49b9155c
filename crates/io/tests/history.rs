//! `[[steps]]` load histories in problem files: the groups of the loads, the steps' factors and
//! increments, the history a run solves (against the load steps to the bit and superposition),
//! and bad histories refused with the step and the key named.

use std::path::Path;

use contactdd_ddm::history::{solve_history, LoadHistory};
use contactdd_ddm::steps::solve_steps;
use contactdd_ddm::*;
use contactdd_io::problem::Problem;
use contactdd_io::*;

/// A block pressed on a foundation and pushed against a support on its left side (frictionless:
/// the support holds it sideways); `loads` are its load tables, `rest` the rest of the file.
fn text(loads: &str, rest: &str) -> String {
    format!(
        r#"
plane = "strain"
[materials.m]
young = 1000.0
poisson = 0.3
[[bodies]]
name = "foundation"
material = "m"
mesh = {{ kind = "rectangle", x = [0.0, 4.0], y = [0.0, 1.0], nx = 16, ny = 4 }}
supports = [{{ boundary = "bottom", component = "both" }}]
[[bodies]]
name = "block"
material = "m"
mesh = {{ kind = "rectangle", x = [1.0, 3.0], y = [1.0, 2.0], nx = 8, ny = 4 }}
supports = [{{ boundary = "left", component = "x" }}]
{loads}
[[contact]]
bodies = ["foundation", "block"]
boundaries = ["top", "bottom"]
penalty = {{ c = 0.05, h = 1.0 }}
{rest}
"#
    )
}

const GROUPED: &str = r#"
[[bodies.loads]]
kind = "pressure"
boundary = "top"
value = 10.0
group = "press"
[[bodies.loads]]
kind = "body-force"
value = [1.0, -2.0]
group = "weight"
"#;

const PRESS_THEN_WEIGHT: &str = r#"
[[steps]]
name = "press"
factors = { press = 1.0 }
increments = 2
[[steps]]
name = "weight"
factors = { weight = 1.0 }
increments = 3
"#;

fn loaded(text: &str) -> Result<Loaded, LoadError> {
    load_str(text, "history.toml", Path::new("."))
}

fn error(text: &str) -> String {
    match loaded(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn solve_all(loaded: &Loaded, history: &LoadHistory) -> Vec<Solution> {
    let mut prepared = prepare(&loaded.model).unwrap_or_else(|e| panic!("{e}"));
    let done = solve_history(
        &loaded.model,
        &mut prepared,
        &loaded.settings,
        history,
        Hooks::default(),
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    done.into_iter().map(|(_, s)| s).collect()
}

fn displacements(sol: &Solution) -> Vec<f64> {
    sol.bodies
        .iter()
        .flat_map(|b| b.displacement.iter().copied())
        .collect()
}

#[test]
fn a_history_reads_its_groups_steps_and_increments() {
    let l = loaded(&text(GROUPED, PRESS_THEN_WEIGHT)).unwrap_or_else(|e| panic!("{e}"));
    let history = l.history.as_ref().expect("a history");
    assert_eq!(history.group_names(), ["default", "press", "weight"]);
    assert_eq!(history.len(), 5);
    let factors: Vec<Vec<f64>> = history
        .increments()
        .into_iter()
        .map(|i| i.factors)
        .collect();
    assert_eq!(factors[0], [0.0, 0.5, 0.0]);
    assert_eq!(factors[1], [0.0, 1.0, 0.0]);
    assert_eq!(factors[4], [0.0, 1.0, 1.0]);
    // The grouped loads are not the bodies' own: the default group holds nothing.
    assert!(l.model.bodies[1].load.iter().all(|&f| f == 0.0));
    // Written out and read back: the same problem.
    let written = toml::to_string(&l.problem).expect("serialisable");
    let again: Problem = toml::from_str(&written).unwrap_or_else(|e| panic!("{e}\n{written}"));
    assert_eq!(again, l.problem);
}

#[test]
fn a_history_of_two_groups_ends_at_their_superposition() {
    let l = loaded(&text(GROUPED, PRESS_THEN_WEIGHT)).unwrap_or_else(|e| panic!("{e}"));
    let both = solve_all(&l, l.history.as_ref().expect("a history"));
    assert_eq!(both.len(), 5);
    assert!(both.iter().all(|s| s.converged));
    let alone = |group: &str| {
        let rest = format!("[[steps]]\nfactors = {{ {group} = 1.0 }}\n");
        // The other group is named (at 0) so that no load is left without a step.
        let other = if group == "press" { "weight" } else { "press" };
        let rest = format!("{rest}[[steps]]\nfactors = {{ {other} = 0.0 }}\n");
        let l = loaded(&text(GROUPED, &rest)).unwrap_or_else(|e| panic!("{e}"));
        let sols = solve_all(&l, l.history.as_ref().expect("a history"));
        displacements(sols.last().expect("a solve"))
    };
    let (u1, u2) = (alone("press"), alone("weight"));
    let u = displacements(both.last().expect("a solve"));
    let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let error = (u.iter().zip(u1.iter().zip(&u2)))
        .map(|(u, (a, b))| (u - a - b).abs())
        .fold(0.0f64, f64::max);
    assert!(error <= 1e-10 * scale, "{error} against {scale}");
}

#[test]
fn a_one_group_history_is_the_load_steps_to_the_bit() {
    let plain = r#"loads = [{ kind = "pressure", boundary = "top", value = 10.0 }]"#;
    let steps = loaded(&text(plain, "[solver]\nload-steps = [0.5, 1.0]\n"))
        .unwrap_or_else(|e| panic!("{e}"));
    let factors = steps.steps.clone().expect("load steps");
    let mut prepared = prepare(&steps.model).unwrap_or_else(|e| panic!("{e}"));
    let by_steps = solve_steps(
        &steps.model,
        &mut prepared,
        &steps.settings,
        &factors,
        Hooks::default(),
        &mut |_, _, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let rest = "[[steps]]\nfactors = { default = 0.5 }\n[[steps]]\nfactors = { default = 1.0 }\n";
    let grouped =
        r#"loads = [{ kind = "pressure", boundary = "top", value = 10.0, group = "all" }]"#;
    let rest_grouped = rest.replace("default", "all");
    for (loads, rest) in [(plain, rest), (grouped, rest_grouped.as_str())] {
        let l = loaded(&text(loads, rest)).unwrap_or_else(|e| panic!("{e}"));
        let by_history = solve_all(&l, l.history.as_ref().expect("a history"));
        assert_eq!(by_history.len(), 2);
        for ((_, a), b) in by_steps.iter().zip(&by_history) {
            assert!(a.converged && b.converged);
            assert_eq!(a.iterations, b.iterations);
            let (da, db) = (displacements(a), displacements(b));
            assert!(
                da.iter().zip(&db).all(|(x, y)| x.to_bits() == y.to_bits()),
                "{loads}"
            );
        }
    }
}

#[test]
fn bad_histories_are_refused_with_the_step_named() {
    let cases = [
        (
            "[[steps]]\nname = \"p\"\nfactors = { pres = 1.0 }\n[[steps]]\nfactors = { press = 1.0, weight = 1.0 }\n",
            "steps: [0] 'p': factors: no load group named 'pres' (known: default, press, weight)",
        ),
        (
            "[[steps]]\nfactors = { press = 1.0, weight = 1.0 }\nincrements = -2\n",
            "steps: [0] 'step1': increments must be at least 1, got -2",
        ),
        (
            "[[steps]]\nfactors = { press = 1.0, weight = 1.0 }\nincrements = 0\n",
            "increments must be at least 1, got 0",
        ),
        (
            "[[steps]]\nfactors = { press = 1.0, weight = 1.0 }\n[solver]\nload-steps = 2\n",
            "[solver] load-steps and [[steps]] exclude each other",
        ),
        (
            "[[steps]]\nfactors = { press = 1.0 }\nincrements = 6000\n[[steps]]\nfactors = { weight = 1.0 }\nincrements = 5000\n",
            "at most 10000 increments in all, got 11000",
        ),
        (
            "[[steps]]\nfactors = { press = 1.0, weight = 1.0 }\nincrements = 10001\n",
            "at most 10000 increments, got 10001",
        ),
        (
            "[[steps]]\nfactors = { press = 1.0 }\n",
            "no step sets the factor of load group 'weight'",
        ),
        ("", "loads of group 'press' need a [[steps]] history"),
        (
            "[[steps]]\nfactors = { press = nan, weight = 1.0 }\n",
            "factors.press: must be finite, got NaN",
        ),
        (
            "[[steps]]\nfactors = {}\n",
            "give the factor of at least one load group",
        ),
    ];
    for (rest, message) in cases {
        let e = error(&text(GROUPED, rest));
        assert!(e.contains(message), "{e}\nexpected: {message}");
        assert!(e.contains("history.toml"), "{e}");
    }
    // An unknown key of a load is still refused, and a step's unknown key too.
    let typo = GROUPED.replace("group = \"press\"", "grop = \"press\"");
    let e = error(&text(&typo, PRESS_THEN_WEIGHT));
    assert!(e.contains("grop"), "{e}");
    let e = error(&text(
        GROUPED,
        &format!("{PRESS_THEN_WEIGHT}incremnts = 2\n"),
    ));
    assert!(e.contains("incremnts"), "{e}");
}
