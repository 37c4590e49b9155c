//! Friction in space: a block on a foundation (non-matching P1 meshes), the foundation's top the
//! reference side.
//!
//! - Held only by friction (no support), pressed by P and sheared by Q < μP along an oblique
//!   direction: every body balances, the contact's resultant is (Q, −P) times the area, the
//!   tractions meet Coulomb's law, and the independent check reads the law back.
//! - Sheared by Q > μP: the block slides, and the solver says so.
//! - Dragged by its top far enough that every point slips, obliquely: under Coulomb's law the
//!   tangential resultant is μ times the normal one, under Tresca's the bound times the area, each
//!   along the drag; every traction opposes its point's slip.
//! - μ = 0 gives the frictionless answer to the bit; exact (augmented) friction keeps the sticking
//!   points at zero slip; a load history carries the friction state; sequential = parallel.

use contactdd_core::solid::assembly::add_face_traction;
use contactdd_core::solid::element::elasticity_matrix;
use contactdd_core::solid::{dof, BoxMesh, SolidMesh, TetOrder};
use contactdd_ddm::contact3d::DiscStatus;
use contactdd_ddm::solid_balance::solid_balance;
use contactdd_ddm::solid_contact::{SolidContactError, SolidProgress};
use contactdd_ddm::solid_dd::{solve_solid_dd, solve_solid_dd_steps};
use contactdd_ddm::solid_monolithic::{
    solve_solid_monolithic, solve_solid_monolithic_from, SolidBodySpec, SolidContactSolution,
    SolidPairSpec,
};
use contactdd_ddm::{Enforcement, Friction};

const P: f64 = 40.0;
const MU: f64 = 0.3;
/// The direction of the shear and of the drag, oblique to the mesh and to the tangents.
const ANGLE: f64 = 0.6;

fn boxed(origin: [f64; 3], size: [f64; 3], cells: [usize; 3]) -> SolidMesh {
    BoxMesh {
        origin,
        size,
        cells,
        order: TetOrder::P1,
    }
    .mesh()
    .unwrap()
}

/// The foundation [0, 1]² × [−0.5, 0] (held at its bottom) and the block [0, 1]² × [0, 0.6].
fn meshes() -> [SolidMesh; 2] {
    [
        boxed([0.0, 0.0, -0.5], [1.0, 1.0, 0.5], [5, 4, 2]),
        boxed([0.0; 3], [1.0, 1.0, 0.6], [3, 4, 2]),
    ]
}

fn nodes(mesh: &SolidMesh, face: &str) -> Vec<usize> {
    let mut v = mesh.face(face).unwrap().to_vec();
    v.sort_unstable();
    v.dedup();
    v
}

/// How the block is loaded: a pressure and shear on its top, or its top dragged by `drag`
/// horizontally and pushed down by `down`.
enum Load {
    Shear(f64),
    Drag { drag: f64, down: f64 },
}

fn problem(
    m: &[SolidMesh; 2],
    load: Load,
    friction: Friction,
) -> (Vec<SolidBodySpec<'_>>, Vec<SolidPairSpec>) {
    let d = elasticity_matrix(2.1e5, 0.3).unwrap();
    let held: Vec<(usize, f64)> = (nodes(&m[0], "z-").iter())
        .flat_map(|&v| (0..3).map(move |c| (dof(v, c), 0.0)))
        .collect();
    let (dir, mut block_load, mut prescribed) = (
        [ANGLE.cos(), ANGLE.sin()],
        vec![0.0; 3 * m[1].num_nodes()],
        Vec::new(),
    );
    match load {
        Load::Shear(q) => {
            let t = [q * dir[0], q * dir[1], -P];
            add_face_traction(&m[1], "z+", |_, _| t, &mut block_load).unwrap();
        }
        Load::Drag { drag, down } => {
            for v in nodes(&m[1], "z+") {
                prescribed.push((dof(v, 0), drag * dir[0]));
                prescribed.push((dof(v, 1), drag * dir[1]));
                prescribed.push((dof(v, 2), -down));
            }
        }
    }
    let bodies = vec![
        SolidBodySpec {
            mesh: &m[0],
            elasticity: d,
            prescribed: held,
            load: vec![0.0; 3 * m[0].num_nodes()],
        },
        SolidBodySpec {
            mesh: &m[1],
            elasticity: elasticity_matrix(7e4, 0.33).unwrap(),
            prescribed,
            load: block_load,
        },
    ];
    let pairs = vec![SolidPairSpec {
        reference: (0, "z+".into()),
        partner: (1, "z-".into()),
        theta: 1e-6,
        search: 0.1,
        enforcement: Enforcement::Penalty,
        friction,
    }];
    (bodies, pairs)
}

/// The resultant of the contact tractions on the reference side: (t along x, y; the pressure).
fn resultant(sol: &SolidContactSolution) -> [f64; 3] {
    let mut r = [0.0; 3];
    for q in &sol.points {
        let f = q.friction.as_ref().unwrap();
        for c in 0..3 {
            r[c] +=
                q.weight * (f.traction[0] * f.tangents[0][c] + f.traction[1] * f.tangents[1][c]);
        }
        r[2] -= q.weight * q.pressure;
    }
    r
}

/// Coulomb's law at every point: |τ| ≤ μp, with equality exactly where it slips.
fn coulomb_holds(sol: &SolidContactSolution, mu: f64) {
    for q in &sol.points {
        let f = q.friction.as_ref().unwrap();
        let t = f.traction[0].hypot(f.traction[1]);
        assert!(t <= mu * q.pressure * (1.0 + 1e-12) + 1e-12, "{t} > μp");
        if f.status == Some(DiscStatus::Slip) {
            assert!(
                (t - mu * q.pressure).abs() <= 1e-10 * P,
                "slip off the disc"
            );
        }
    }
}

fn checked(bodies: &[SolidBodySpec<'_>], pairs: &[SolidPairSpec], sol: &SolidContactSolution) {
    let check = solid_balance(bodies, pairs, sol).unwrap();
    assert!(check.worst() < 1e-8, "imbalance {:e}", check.worst());
    assert!(
        check.contact_law < 1e-8,
        "contact law {:e}",
        check.contact_law
    );
    assert!(
        check.friction_law < 1e-8,
        "friction law {:e}",
        check.friction_law
    );
}

#[test]
fn friction_alone_holds_a_sheared_block() {
    let m = meshes();
    let q = 0.6 * MU * P;
    let (bodies, pairs) = problem(&m, Load::Shear(q), Friction::Coulomb { mu: MU });
    let sol = solve_solid_dd(&bodies, &pairs).unwrap();
    checked(&bodies, &pairs, &sol);
    coulomb_holds(&sol, MU);
    // The reference side receives what the block's top carries: (Q cos, Q sin, −P) per area.
    let r = resultant(&sol);
    let want = [q * ANGLE.cos(), q * ANGLE.sin(), -P];
    for c in 0..3 {
        assert!(
            (r[c] - want[c]).abs() < 1e-8 * P,
            "resultant {r:?} against {want:?}"
        );
    }
    assert!(sol.newton_steps <= 15, "{} steps", sol.newton_steps);
}

#[test]
fn a_shear_above_friction_slides_the_block() {
    let m = meshes();
    let (bodies, pairs) = problem(&m, Load::Shear(1.2 * MU * P), Friction::Coulomb { mu: MU });
    match solve_solid_dd(&bodies, &pairs) {
        Err(SolidContactError::Slides {
            body,
            work,
            resistance,
        }) => {
            assert_eq!(body, 1);
            assert!(work > resistance);
        }
        other => panic!("expected the block to slide, got {other:?}"),
    }
}

/// Dragged far: every point slips against the drag.
fn dragged(friction: Friction) -> (SolidContactSolution, [f64; 3]) {
    let m = meshes();
    let (bodies, pairs) = problem(
        &m,
        Load::Drag {
            drag: 5e-3,
            down: 2e-4,
        },
        friction,
    );
    let sol = solve_solid_dd(&bodies, &pairs).unwrap();
    checked(&bodies, &pairs, &sol);
    for q in &sol.points {
        let f = q.friction.as_ref().unwrap();
        assert_eq!(f.status, Some(DiscStatus::Slip));
        // The traction on the foundation points along the block's drag, its slip against it.
        let along = f.traction[0] * f.slip[0] + f.traction[1] * f.slip[1];
        assert!(along < 0.0);
    }
    let r = resultant(&sol);
    // Dragged along one direction, the slips spread little about it: the resultant's
    // direction is the drag's to a few parts in a thousand.
    let angle = r[1].atan2(r[0]);
    assert!(
        (angle - ANGLE).abs() < 5e-3,
        "resultant at {angle}, the drag at {ANGLE}"
    );
    (sol, r)
}

/// Σ w |τ| over the points.
fn traction_total(sol: &SolidContactSolution) -> f64 {
    (sol.points.iter())
        .map(|q| {
            let f = q.friction.as_ref().unwrap();
            q.weight * f.traction[0].hypot(f.traction[1])
        })
        .sum()
}

#[test]
fn a_dragged_block_slips_everywhere_at_mu_times_its_weight() {
    let (sol, r) = dragged(Friction::Coulomb { mu: MU });
    coulomb_holds(&sol, MU);
    let normal = -r[2];
    assert!(normal > 0.0);
    let total = traction_total(&sol);
    assert!(
        (total - MU * normal).abs() < 1e-10 * normal,
        "{total} against μN {}",
        MU * normal
    );
}

#[test]
fn tresca_slip_carries_the_bound_over_the_area() {
    let bound = 3.0;
    let (sol, r) = dragged(Friction::Tresca { bound });
    for q in &sol.points {
        let f = q.friction.as_ref().unwrap();
        assert!((f.traction[0].hypot(f.traction[1]) - bound).abs() < 1e-10 * bound);
    }
    // The weights sum to the area 1.
    let total = traction_total(&sol);
    assert!(
        (total - bound).abs() < 1e-10 * bound,
        "{total} against the bound {bound}"
    );
    assert!(r[0].hypot(r[1]) <= bound);
}

#[test]
fn no_friction_coefficient_is_frictionless_to_the_bit() {
    let m = meshes();
    let drag = || Load::Drag {
        drag: 0.0,
        down: 2e-4,
    };
    let (bodies, pairs) = problem(&m, drag(), Friction::Coulomb { mu: 0.0 });
    let zero = solve_solid_dd(&bodies, &pairs).unwrap();
    let (bodies, pairs) = problem(&m, drag(), Friction::None);
    let none = solve_solid_dd(&bodies, &pairs).unwrap();
    assert_eq!(zero.displacements, none.displacements);
    assert_eq!(zero.points, none.points);
}

#[test]
fn exact_friction_keeps_the_sticking_points_in_place() {
    let m = meshes();
    let (bodies, mut pairs) = problem(&m, Load::Shear(0.6 * MU * P), Friction::Coulomb { mu: MU });
    pairs[0].enforcement = Enforcement::Augmented;
    pairs[0].theta = 1e-3;
    let sol = solve_solid_dd(&bodies, &pairs).unwrap();
    checked(&bodies, &pairs, &sol);
    coulomb_holds(&sol, MU);
    let scale = sol.displacements[1]
        .iter()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    let mut sticking = 0;
    for q in &sol.points {
        let f = q.friction.as_ref().unwrap();
        if f.status == Some(DiscStatus::Stick) {
            sticking += 1;
            assert!(
                f.slip[0].hypot(f.slip[1]) < 1e-10 * scale,
                "slip {:?}",
                f.slip
            );
        }
    }
    assert!(sticking > 0);
}

#[test]
fn a_load_history_carries_the_friction_state() {
    let m = meshes();
    let (bodies, pairs) = problem(&m, Load::Shear(0.9 * MU * P), Friction::Coulomb { mu: MU });
    let steps = solve_solid_dd_steps(&bodies, &pairs, &[0.5, 1.0], &|_: SolidProgress| {}).unwrap();
    let last = &steps[1];
    for (q, before) in last.points.iter().zip(&steps[0].points) {
        let (f, b) = (
            q.friction.as_ref().unwrap(),
            before.friction.as_ref().unwrap(),
        );
        assert_eq!(f.carried, [b.traction, b.slip]);
    }
    coulomb_holds(last, MU);
    let r = resultant(last);
    assert!((r[0] - 0.9 * MU * P * ANGLE.cos()).abs() < 1e-8 * P);
}

#[test]
fn parallel_is_sequential_with_friction() {
    let m = meshes();
    let (bodies, pairs) = problem(&m, Load::Shear(0.8 * MU * P), Friction::Coulomb { mu: MU });
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| solve_solid_dd(&bodies, &pairs).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.displacements, two.displacements);
    assert_eq!(one.points, two.points);
}

/// The largest difference of two solutions' displacements relative to the largest
/// displacement, and of their tractions relative to the largest traction.
fn differences(a: &SolidContactSolution, b: &SolidContactSolution) -> (f64, f64) {
    let (mut du, mut su, mut dt, mut st) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (x, y) in a.displacements.iter().zip(&b.displacements) {
        for (x, y) in x.iter().zip(y) {
            du = du.max((x - y).abs());
            su = su.max(x.abs());
        }
    }
    for (p, q) in a.points.iter().zip(&b.points) {
        let (f, g) = (p.friction.as_ref().unwrap(), q.friction.as_ref().unwrap());
        assert_eq!(f.status, g.status, "statuses differ at node {}", p.node);
        for c in 0..2 {
            dt = dt.max((f.traction[c] - g.traction[c]).abs());
            st = st.max(f.traction[c].abs());
        }
        dt = dt.max((p.pressure - q.pressure).abs());
    }
    (du / su, dt / st)
}

/// The decomposition (Coulomb linearised whole on the contact points) against the monolithic
/// reference (successive Tresca problems, each minimised on the coupled system): held by
/// friction, dragged into full slip, under Tresca, and along a load history.
#[test]
fn the_decomposition_meets_the_monolithic_reference() {
    let m = meshes();
    let cases = [
        (Load::Shear(0.6 * MU * P), Friction::Coulomb { mu: MU }),
        (Load::Shear(0.9 * MU * P), Friction::Coulomb { mu: MU }),
        (
            Load::Drag {
                drag: 5e-3,
                down: 2e-4,
            },
            Friction::Coulomb { mu: MU },
        ),
        (
            Load::Drag {
                drag: 1e-4,
                down: 2e-4,
            },
            Friction::Coulomb { mu: 0.5 },
        ),
        (
            Load::Drag {
                drag: 2e-4,
                down: 2e-4,
            },
            Friction::Tresca { bound: 3.0 },
        ),
    ];
    for (load, friction) in cases {
        let (bodies, pairs) = problem(&m, load, friction);
        let dd = solve_solid_dd(&bodies, &pairs).unwrap();
        let mono = solve_solid_monolithic(&bodies, &pairs).unwrap();
        checked(&bodies, &pairs, &mono);
        let (du, dt) = differences(&dd, &mono);
        assert!(
            du < 1e-8 && dt < 1e-8,
            "{friction:?}: displacements {du:e}, tractions {dt:e}"
        );
    }
    // A history: the monolithic increments start where its last ended, as the decomposition's.
    let (bodies, pairs) = problem(&m, Load::Shear(0.9 * MU * P), Friction::Coulomb { mu: MU });
    let dd = solve_solid_dd_steps(&bodies, &pairs, &[0.5, 1.0], &|_: SolidProgress| {}).unwrap();
    let half: Vec<SolidBodySpec<'_>> = (bodies.iter())
        .map(|b| SolidBodySpec {
            mesh: b.mesh,
            elasticity: b.elasticity,
            prescribed: b.prescribed.clone(),
            load: b.load.iter().map(|x| 0.5 * x).collect(),
        })
        .collect();
    let first = solve_solid_monolithic(&half, &pairs).unwrap();
    let second = solve_solid_monolithic_from(&bodies, &pairs, Some(&first)).unwrap();
    let (du, dt) = differences(&dd[1], &second);
    assert!(
        du < 1e-8 && dt < 1e-8,
        "history: displacements {du:e}, tractions {dt:e}"
    );
}
