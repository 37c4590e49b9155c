//! Balanced contact pairs (docs/method.md §4): on curved and non-matching zones the two sides of a
//! pair receive equal and opposite forces, the gap rows do not change under a joint translation,
//! the decomposition agrees with the monolithic reference, and pairs that match node for node
//! keep the paper's arithmetic.

use contactdd_core::{
    Component, Constraints, Diagonal, ElasticBody, Load, Material, Mesh, Order, Plane, Rectangle,
};
use contactdd_ddm::contact::{Interface, Role};
use contactdd_ddm::*;

fn rect(origin: [f64; 2], corner: [f64; 2], nx: usize, ny: usize, order: Order) -> Mesh {
    Rectangle {
        origin,
        corner,
        nx,
        ny,
        diagonal: Diagonal::Right,
        mirror: false,
        order,
    }
    .mesh()
    .unwrap()
}

fn body(name: &str, mesh: Mesh, young: f64, fixed: &[(&str, Component)], loads: &[Load]) -> Body {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for &(b, c) in fixed {
        constraints.fix(&mesh, b, c, 0.0).unwrap();
    }
    let load = contactdd_core::loads::load_vector(&mesh, loads).unwrap();
    ElasticBody {
        name: name.into(),
        mesh,
        material: Material::new(young, 0.3).unwrap(),
        plane: Plane::Strain,
        constraints,
        load,
    }
}

type Body = ElasticBody;

fn pair(name: &str, bodies: [usize; 2], boundaries: [&str; 2], forces: Forces) -> ContactPair {
    ContactPair {
        name: name.into(),
        bodies,
        boundaries: boundaries.map(String::from),
        penalty: Penalty::Theta(1e-4),
        profile: None,
        enforcement: Enforcement::Penalty,
        forces,
        friction: Default::default(),
    }
}

/// A half ring of radii 1 and 0.1 centred at (0, 1) (touching y = 0 at x = 0), clamped on its
/// right flat end, and the block [−1.5, 1.5] × [−1, 0] pushed up against it by a pressure on
/// its bottom, held by u_x = 0 on its bottom and left side (vertically the contact holds it); E_disc/E_block =
/// `ratio`; P2, non-matching and not mirror-symmetric (one end clamped, the block graded).
fn disc_on_block(ratio: f64, forces: Forces) -> Model {
    let block = rect([0.0, 0.0], [1.0, 1.0], 45, 8, Order::P1)
        .map_nodes(|[s, q]| [-1.5 + 3.0 * s.powf(1.1), q - 1.0])
        .unwrap()
        .to_p2();
    let disc = rect([0.0, 0.0], [1.0, 1.0], 36, 8, Order::P1)
        .map_nodes(|[s, q]| {
            let r = 1.0 - 0.9 * q;
            let t = std::f64::consts::PI * (s - 1.0);
            [r * t.cos(), 1.0 + r * t.sin()]
        })
        .unwrap()
        .to_p2();
    let block = body(
        "block",
        block,
        1000.0,
        &[("bottom", Component::X), ("left", Component::X)],
        &[Load::Pressure {
            boundary: "bottom".into(),
            value: 20.0,
        }],
    );
    let disc = body(
        "disc",
        disc,
        1000.0 * ratio,
        &[("right", Component::Both)],
        &[],
    );
    Model {
        name: format!("disc on block, ratio {ratio}"),
        plane: Plane::Strain,
        bodies: vec![block, disc],
        pairs: vec![pair("disc", [0, 1], ["top", "bottom"], forces)],
        remote: Vec::new(),
    }
}

/// Three blocks stacked with different cell counts (every interface non-matching), the middle
/// one held vertically only by its contacts.
fn column(forces: Forces) -> Model {
    let block =
        |i: usize, nx: usize| rect([0.0, i as f64], [1.0, i as f64 + 1.0], nx, 6, Order::P1);
    let bodies = vec![
        body(
            "b0",
            block(0, 7),
            1000.0,
            &[("bottom", Component::Both)],
            &[],
        ),
        body("b1", block(1, 11), 300.0, &[("left", Component::X)], &[]),
        body(
            "b2",
            block(2, 5),
            1000.0,
            &[("left", Component::X)],
            &[Load::Pressure {
                boundary: "top".into(),
                value: 10.0,
            }],
        ),
    ];
    Model {
        name: "column".into(),
        plane: Plane::Strain,
        bodies,
        pairs: vec![
            pair("01", [0, 1], ["top", "bottom"], forces),
            pair("12", [1, 2], ["top", "bottom"], forces),
        ],
        remote: Vec::new(),
    }
}

fn run(model: &Model, settings: &Settings) -> Solution {
    let prepared = prepare_with(model, settings.condensation).unwrap();
    let sol = solve(model, &prepared, settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{}: {:?}", model.name, sol.message);
    sol
}

/// |F₀ + F₁| / |F₀| of every pair.
fn imbalances(sol: &Solution) -> Vec<f64> {
    sol.contact
        .iter()
        .map(|p| {
            let (a, b) = (p.force_on(0), p.force_on(1));
            (a[0] + b[0]).hypot(a[1] + b[1]) / a[0].hypot(a[1])
        })
        .collect()
}

fn settings(accelerator: Accelerator, condensation: Condensation) -> Settings {
    Settings {
        tol: 1e-12,
        max_iter: 3000,
        accelerator,
        condensation,
        ..Settings::anderson()
    }
}

#[test]
fn balanced_pairs_carry_equal_and_opposite_forces() {
    let anderson = Settings::anderson().accelerator;
    let cases = [
        disc_on_block(1.0, Forces::Balanced),
        disc_on_block(10.0, Forces::Balanced),
        column(Forces::Balanced),
    ];
    for model in &cases {
        for (accelerator, condensation) in [
            (Accelerator::Newton, Condensation::Dense),
            (Accelerator::Newton, Condensation::Sparse),
            (anderson, Condensation::Dense),
        ] {
            let sol = run(model, &settings(accelerator, condensation));
            let worst = imbalances(&sol).into_iter().fold(0.0, f64::max);
            println!(
                "{} {accelerator} {condensation:?}: {} iterations, imbalance {worst:.1e}",
                model.name, sol.iterations
            );
            assert!(worst <= 1e-10, "{}: imbalance {worst:e}", model.name);
            // Every pair carries the whole load: it acts on one end of the stack, the vertical
            // supports are at the other.
            let applied: f64 = model
                .bodies
                .iter()
                .map(|b| b.load.iter().skip(1).step_by(2).sum::<f64>())
                .sum();
            for p in &sol.contact {
                let carried = p.force_on(1);
                assert!(
                    (carried[1].abs() - applied.abs()).abs() <= 1e-8 * applied.abs(),
                    "{}: {carried:?} against {applied}",
                    model.name
                );
            }
        }
    }
}

/// The test above can fail: the paper's own-side formulation on the same curved, non-matching
/// zone leaves an imbalance far above its bound, and the solver's force balance refuses it.
#[test]
fn the_own_side_formulation_does_not_balance_there() {
    let model = disc_on_block(1.0, Forces::OwnSide);
    let settings = settings(Accelerator::Newton, Condensation::Dense);
    let prepared = prepare_with(&model, settings.condensation).unwrap();
    let sol = solve(&model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(
        matches!(sol.stop, Stop::Unbalanced { .. }),
        "{:?}",
        sol.stop
    );
    let worst = imbalances(&sol)[0];
    assert!(worst > 1e-4, "imbalance {worst:e}");
}

/// The gap rows of a balanced pair read a rigid translation of both bodies as no change of any
/// gap; the own-side rows do not on a curved zone.
#[test]
fn balanced_gaps_do_not_change_under_a_joint_translation() {
    for (forces, invariant) in [(Forces::Balanced, true), (Forces::OwnSide, false)] {
        let interface = Interface::new(&disc_on_block(1.0, forces)).unwrap();
        let tangents = interface
            .points
            .iter()
            .filter(|p| p.role == Role::Tangent)
            .count();
        assert_eq!(tangents > 0, invariant, "{forces}");
        let v = [0.37, -1.3];
        let un: Vec<f64> = interface
            .points
            .iter()
            .map(|p| v[0] * p.normal[0] + v[1] * p.normal[1])
            .collect();
        let mut s = vec![0.0; un.len()];
        interface.sum_normal(&un, &mut s);
        let worst = interface
            .points
            .iter()
            .zip(&s)
            .filter(|(p, _)| p.has_partner())
            .fold(0.0f64, |m, (_, s)| m.max(s.abs()));
        if invariant {
            assert!(worst <= 1e-13, "{forces}: s = {worst:e}");
        } else {
            assert!(worst > 1e-3, "{forces}: s = {worst:e}");
        }
    }
}

/// The decomposition and the monolithic reference solve the same balanced problem.
#[test]
fn the_decomposition_agrees_with_the_monolithic_reference_on_balanced_pairs() {
    for model in [
        disc_on_block(10.0, Forces::Balanced),
        column(Forces::Balanced),
    ] {
        let reference = solve_monolithic(&model).unwrap();
        assert!(reference.converged, "{:?}", reference.message);
        let dd = run(&model, &settings(Accelerator::Newton, Condensation::Dense));
        for (a, b) in dd.contact.iter().zip(&reference.contact) {
            let peak = a.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
            let diff = a
                .pressure
                .iter()
                .zip(&b.pressure)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                diff <= 1e-8 * peak,
                "{}: pressures differ by {diff:e}",
                model.name
            );
            let (fa, fb) = (a.force_on(0), b.force_on(0));
            assert!((fa[0] - fb[0]).hypot(fa[1] - fb[1]) <= 1e-8 * fa[0].hypot(fa[1]));
        }
    }
}

/// Two blocks whose contact edges match node for node: asking for balanced forces changes
/// nothing, to the bit (the paper's benchmark is such a pair).
#[test]
fn pairs_that_match_node_for_node_keep_their_arithmetic() {
    let model = |forces| {
        let lower = body(
            "lower",
            rect([0.0, 0.0], [1.0, 1.0], 8, 4, Order::P2),
            1000.0,
            &[("bottom", Component::Both)],
            &[],
        );
        let upper = body(
            "upper",
            rect([0.0, 1.0], [1.0, 2.0], 8, 4, Order::P2),
            300.0,
            &[("left", Component::X)],
            &[Load::Pressure {
                boundary: "top".into(),
                value: 10.0,
            }],
        );
        Model {
            name: "matching".into(),
            plane: Plane::Strain,
            bodies: vec![lower, upper],
            pairs: vec![pair("p", [0, 1], ["top", "bottom"], forces)],
            remote: Vec::new(),
        }
    };
    let (a, b) = (model(Forces::Balanced), model(Forces::OwnSide));
    let interface = Interface::new(&a).unwrap();
    assert!(interface.points.iter().all(|p| p.role == Role::OwnSide));
    assert_eq!(interface.formulations[0].forces, Forces::OwnSide);
    let s = settings(Accelerator::Newton, Condensation::Dense);
    let (sa, sb) = (run(&a, &s), run(&b, &s));
    assert_eq!(sa.iterations, sb.iterations);
    assert_eq!(sa.contact[0].pressure, sb.contact[0].pressure);
    assert_eq!(sa.bodies[1].displacement, sb.bodies[1].displacement);
}

/// A pair's formulation: the stiffened inner penalty only for an augmented balanced pair under
/// [`InnerPenalty::Stiffened`], never stiffer than the rod model allows; a θ that is not positive
/// is refused.
#[test]
fn only_augmented_balanced_pairs_get_the_stiffened_inner_penalty() {
    let model = disc_on_block(1.0, Forces::Balanced);
    let (a, b) = (&model.bodies[0], &model.bodies[1]);
    let stiffened = |enforcement, forces, inner| {
        let pair = ContactPair {
            enforcement,
            forces,
            ..model.pairs[0].clone()
        };
        let f = pair.formulation(&model.bodies, inner).unwrap();
        assert_eq!(
            (f.enforcement, f.forces, f.theta),
            (enforcement, forces, 1e-4)
        );
        f.inner == InnerPenalty::Stiffened
    };
    use Enforcement::{Augmented, Penalty as Plain};
    use InnerPenalty::{AsGiven, Stiffened};
    assert!(stiffened(Augmented, Forces::Balanced, Stiffened));
    assert!(!stiffened(Augmented, Forces::Balanced, AsGiven));
    assert!(!stiffened(Augmented, Forces::OwnSide, Stiffened));
    assert!(!stiffened(Plain, Forces::Balanced, Stiffened));
    let f = Formulation::new(1e-4, Augmented, Forces::Balanced, Stiffened);
    let rod = Penalty::RodModel { c: 0.05, h: 1e-3 }.theta(a, b);
    assert_eq!(f.point_theta(1e-3, a, b), rod.min(1e-4));
    assert_eq!(f.point_theta(0.0, a, b), 1e-4);
    let bad = ContactPair {
        penalty: Penalty::Theta(0.0),
        ..model.pairs[0].clone()
    };
    assert!(bad.formulation(&model.bodies, AsGiven).is_err());
}
