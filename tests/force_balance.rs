//! The independent force balance decides the verdict (crates/ddm/src/force_balance.rs): a result
//! the solver calls converged balances its loads by its reactions, whatever the stiffness contrast
//! or the size of a prescribed displacement; where double precision cannot resolve the bodies'
//! strains, the solve says so instead.
//!
//! The references are independent of the solver: the stack's exact solution (a uniform pressure
//! p = 100 through every interface, so every pair carries p · 2 = 200) and, for the other
//! examples, the applied loads against the support reactions that `contactdd_io::reactions`
//! computes from the fields.

use contactdd::ddm::{prepare, solve, Hooks, Solution, Stop};
use contactdd::io::reactions::reactions;
use contactdd::io::{load_str, Loaded};

fn example(name: &str) -> String {
    let path = format!("{}/examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap()
}

fn load(text: &str) -> Loaded {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    load_str(text, "test.toml", &dir).unwrap()
}

fn run(loaded: &Loaded) -> Solution {
    let prepared = prepare(&loaded.model).unwrap();
    solve(&loaded.model, &prepared, &loaded.settings, Hooks::default()).unwrap()
}

/// |Σ applied + Σ reactions| over |Σ applied| (balanced pairs' forces cancel between bodies).
fn global_imbalance(loaded: &Loaded, sol: &Solution) -> f64 {
    let mut net = [0.0; 2];
    let mut applied = 0.0f64;
    for body in &loaded.model.bodies {
        for c in 0..2 {
            let f: f64 = body.load.iter().skip(c).step_by(2).sum();
            net[c] += f;
            applied = applied.max(f.abs());
        }
    }
    for r in reactions(&loaded.model, &sol.bodies, &sol.contact) {
        net[0] += r.total[0];
        net[1] += r.total[1];
    }
    net[0].hypot(net[1]) / applied
}

/// The message of a refusal for rounding (a stiffness contrast or a displacement far beyond the
/// strains).
fn says_rounding(sol: &Solution) -> bool {
    matches!(sol.stop, Stop::Unbalanced { .. })
        && sol
            .message
            .as_deref()
            .is_some_and(|m| m.contains("double precision"))
}

/// The stack of eight blocks with its steel `young` times stiffer: every pair carries 200 where
/// it converges; at 9.2e18 (1.3e14 times the aluminium) the factorisation of a floating steel
/// block loses its rigid motion, and the solve must not call that a solution.
#[test]
fn a_stiff_stack_is_right_or_refused() {
    for young in [2.1e5, 2.1e9, 2.1e13, 9.2e18] {
        let text = example("stack.toml").replace("young = 2.1e5", &format!("young = {young:e}"));
        let loaded = load(&text);
        let sol = run(&loaded);
        if !sol.converged {
            assert!(says_rounding(&sol), "E = {young:e}: {:?}", sol.message);
            assert!(young > 1e12, "E = {young:e}: refused at a modest contrast");
            continue;
        }
        for pair in &sol.contact {
            let f = pair.force_on(1)[1];
            assert!(
                (f - 200.0).abs() <= 1e-6 * 200.0,
                "E = {young:e}, {}: {f}",
                pair.name
            );
        }
        assert!(global_imbalance(&loaded, &sol) <= 1e-6);
    }
}

/// The three cases of a "rigid" body by a huge modulus: three bodies with the upper one
/// 1e12 times stiffer, the P2 notch with the upper block 1e12 times stiffer, and the stack's steel
/// at 9.2e18. Each is a solution that balances, or a refusal that names the rounding.
#[test]
fn rigid_by_modulus_is_never_a_wrong_solution() {
    let three = example("three_bodies.toml");
    let notch = example("notch.toml");
    // The notch with its paper settings removed (the default interface Newton method), P2, and
    // its upper block of a material 1e12 times stiffer.
    let notch = notch[..notch.find("[solver]").unwrap()]
        .replace("order = \"p1\"", "order = \"p2\"")
        .replace(
            "[[bodies]]\nname = \"upper\"\nmaterial = \"steel\"",
            "[materials.rigid]\nyoung = 2.1e17\npoisson = 0.3\n\n[[bodies]]\nname = \"upper\"\nmaterial = \"rigid\"",
        );
    assert!(notch.contains("material = \"rigid\""));
    let cases = [three.replacen("young = 7.0e4", "young = 7.0e16", 1), notch];
    for text in &cases {
        let loaded = load(text);
        let sol = run(&loaded);
        let imbalance = global_imbalance(&loaded, &sol);
        assert!(
            !sol.converged || imbalance <= 1e-6,
            "converged with an imbalance {imbalance:e}"
        );
        assert!(sol.converged || says_rounding(&sol), "{:?}", sol.message);
    }
}

/// A prescribed displacement of 4.3e7 (a rigid motion far above the strains; the 4.3e9
/// behaves alike but takes 105 Newton steps) on the cylinder between plates: a solution that
/// balances, or a refusal that names the rounding.
#[test]
fn a_huge_prescribed_displacement_is_never_a_wrong_solution() {
    let text = example("cylinder_plates.toml").replace(
        "boundary = \"upper-mid\", component = \"x\", value = 0.0",
        "boundary = \"upper-mid\", component = \"x\", value = 4.3e7",
    );
    assert!(text.contains("4.3e7"));
    let text = text.replace("load-steps = 5", "");
    let loaded = load(&text);
    let sol = run(&loaded);
    assert!(sol.converged || says_rounding(&sol), "{:?}", sol.message);
    assert!(!sol.converged || global_imbalance(&loaded, &sol) <= 1e-6);
}

/// The shipped examples balance to the default tolerance, and the balance the solver reports
/// agrees with the reactions computed apart.
#[test]
fn the_examples_balance() {
    for name in [
        "stack.toml",
        "three_bodies.toml",
        "hertz.toml",
        "cylinder_plates.toml",
    ] {
        let loaded = load(&example(name));
        let sol = run(&loaded);
        assert!(sol.converged, "{name}: {:?}", sol.message);
        let worst = sol
            .balance
            .bodies
            .iter()
            .map(|b| b.imbalance)
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-6 && sol.balance.loads <= 1e-6,
            "{name}: {worst:e}"
        );
        let global = global_imbalance(&loaded, &sol);
        assert!(global <= 1e-6, "{name}: {global:e}");
    }
}
