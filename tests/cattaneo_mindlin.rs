//! Cattaneo–Mindlin partial slip against its closed form (plane strain, two bodies of one
//! material): a cylinder of radius R pressed by P on a flat ([`cattaneo_mindlin`]: two blocks,
//! mirror images but for the upper one's curved bottom, so that pressing loads no tangential
//! traction and shearing does not change the pressure, as between two half-planes), then
//! sheared by Q = μP/2 with P held, in a load history with Coulomb friction μ = 0.3.
//!
//! Closed forms: Hertz's half-width b = sqrt(4PR/(πE*)), 1/E* = 2(1 − ν²)/E, pressure
//! p(x) = p₀ sqrt(1 − x²/b²), p₀ = 2P/(πb); the stick zone |x| < c = b sqrt(1 − Q/(μP)) and the
//! tangential traction q(x) = μp₀ [sqrt(1 − x²/b²) − (c/b) sqrt(1 − x²/c²)] in it,
//! μp₀ sqrt(1 − x²/b²) in the slip zones c ≤ |x| < b.
//!
//! Measured on the last increment's reference side (the flat lower block's top): the stick
//! half-width c (half the distance between the midpoints that separate the outermost sticking
//! points from their slipping neighbours) against b·sqrt(1 − Q/μP) with Hertz's b and with the
//! computed half-width b_h (the same midpoints for the pressed points); the relative L2 errors
//! of q(x) and p(x) over the contact zone; the resultant tangential force against Q.
//!
//! The pair uses the penalty (θ given, θE*/b ≤ 1e-3), not the augmented Lagrangian: an
//! augmented frictional history does not converge past its first increment. Run with
//! `--nocapture` for the numbers; the `#[ignore]`d test is a finer mesh.

use std::time::Instant;

use contactdd::ddm::history::{solve_history, Increment};
use contactdd::ddm::solution::PairResult;
use contactdd::ddm::{prepare, Enforcement, FrictionStatus, Hooks, Settings, Solution};
use contactdd::fem::Order;
use contactdd::frictional::{cattaneo_mindlin, CattaneoMindlin, CM_E, CM_P, CM_R};

const NU: f64 = 0.3;
const MU: f64 = 0.3;

/// The problem with elements of `order`, P1 cells of `h` at the contact, penalty θ.
fn case(order: Order, h: f64, theta: f64) -> CattaneoMindlin {
    CattaneoMindlin {
        order,
        h,
        mu: MU,
        shear: 0.5,
        press: 2,
        increments: 4,
        theta,
        enforcement: Enforcement::Penalty,
    }
}

/// Solves the history; every increment converges in at most 30 Newton steps.
fn run(case: &CattaneoMindlin) -> Vec<(Increment, Solution)> {
    let (model, history) = cattaneo_mindlin(case);
    let settings = Settings {
        tol: 1e-9,
        max_iter: 300,
        ..Settings::default()
    };
    let start = Instant::now();
    let mut prepared = prepare(&model).unwrap_or_else(|e| panic!("{e}"));
    let done = solve_history(
        &model,
        &mut prepared,
        &settings,
        &history,
        Hooks::default(),
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let counts: Vec<usize> = done.iter().map(|(_, s)| s.iterations).collect();
    println!(
        "{:?}, h = {}, θ = {:e}: {} nodes per block, {:.2} s, Newton steps per increment {counts:?}",
        case.order,
        case.h,
        case.theta,
        model.bodies[0].mesh.num_nodes(),
        start.elapsed().as_secs_f64()
    );
    assert_eq!(done.len(), history.len());
    for (inc, sol) in &done {
        assert!(sol.converged, "{inc:?}: {:?}", sol.message);
        assert!(sol.iterations <= 30, "{inc:?}: {} steps", sol.iterations);
    }
    done
}

/// What the last increment shows against the closed forms.
#[derive(Debug)]
struct Measured {
    /// The contact half-width from the pressures, and Hertz's.
    b_h: f64,
    b: f64,
    /// The stick half-width, and the stick zone's centre.
    c: f64,
    centre: f64,
    /// b·sqrt(1 − Q/μP) and b_h·sqrt(1 − Q/μP).
    c_closed: f64,
    c_closed_h: f64,
    /// Relative L2 errors of q(x) and p(x) over the contact zone.
    q_l2: f64,
    p_l2: f64,
    /// Relative errors of the resultant tangential force and of the contact force on the lower
    /// block along x, against Q.
    resultant: f64,
    force: f64,
    /// The largest (|σ_t| − μp)⁺/μp.
    excess: f64,
}

/// Hertz's half-width and peak pressure.
fn hertz() -> (f64, f64) {
    let e_star = CM_E / (2.0 * (1.0 - NU * NU));
    let b = (4.0 * CM_P * CM_R / (std::f64::consts::PI * e_star)).sqrt();
    (b, 2.0 * CM_P / (std::f64::consts::PI * b))
}

/// The reference side's points (those with tangential tractions), sorted along x.
fn reference_points(pair: &PairResult) -> Vec<usize> {
    let side = (0..pair.side.len())
        .find(|&i| pair.status[i] != FrictionStatus::Open)
        .map(|i| pair.side[i])
        .expect("a closed point");
    let mut pts: Vec<usize> = (0..pair.side.len())
        .filter(|&i| pair.side[i] == side)
        .collect();
    pts.sort_by(|&a, &b| pair.x[a].total_cmp(&pair.x[b]));
    pts
}

/// Where the run of points `inside` ends on either side: the midpoints between its outermost
/// points and their outer neighbours; (half-width, centre).
fn extent(x: &[f64], inside: &[bool]) -> (f64, f64) {
    let first = inside.iter().position(|&s| s).expect("a point inside");
    let last = inside.iter().rposition(|&s| s).expect("a point inside");
    assert!(inside[first..=last].iter().all(|&s| s), "not one run");
    let left = 0.5 * (x[first] + x[first - 1]);
    let right = 0.5 * (x[last] + x[last + 1]);
    (0.5 * (right - left), 0.5 * (right + left))
}

fn measure(pair: &PairResult, case: &CattaneoMindlin) -> Measured {
    let pts = reference_points(pair);
    let x: Vec<f64> = pts.iter().map(|&i| pair.x[i]).collect();
    let p: Vec<f64> = pts.iter().map(|&i| -pair.pressure[i]).collect();
    let pressed: Vec<bool> = p.iter().map(|&v| v > 0.0).collect();
    let stick: Vec<bool> = (pts.iter())
        .map(|&i| pair.status[i] == FrictionStatus::Stick)
        .collect();
    let (b_h, _) = extent(&x, &pressed);
    let (c, centre) = extent(&x, &stick);
    let q_total = case.shear * case.mu * CM_P;
    let (b, p0) = hertz();
    let root = |x: f64, a: f64| (1.0 - (x / a).powi(2)).max(0.0).sqrt();
    let ratio = (1.0 - case.shear).sqrt();
    let c_closed = b * ratio;
    let pressure = |x: f64| p0 * root(x, b);
    let traction = |x: f64| case.mu * p0 * (root(x, b) - ratio * root(x, c_closed));
    // σ_t's sign is the resultant's.
    let sign = pair.tangential_force().signum();
    let (mut eq, mut nq, mut ep, mut np) = (0.0, 0.0, 0.0, 0.0);
    for (k, &i) in pts.iter().enumerate() {
        if x[k].abs() >= b && !pressed[k] {
            continue;
        }
        let w = pair.weight[i];
        eq += w * (sign * pair.tangential[i] - traction(x[k])).powi(2);
        nq += w * traction(x[k]).powi(2);
        ep += w * (p[k] - pressure(x[k])).powi(2);
        np += w * pressure(x[k]).powi(2);
    }
    Measured {
        b_h,
        b,
        c,
        centre,
        c_closed,
        c_closed_h: b_h * ratio,
        q_l2: (eq / nq).sqrt(),
        p_l2: (ep / np).sqrt(),
        resultant: (pair.tangential_force().abs() - q_total).abs() / q_total,
        force: (pair.force_on(0)[0] + q_total).abs() / q_total,
        excess: pair.traction_excess(),
    }
}

/// The largest |σ_t| after pressing, relative to μp₀: the setup's coupling of the normal and
/// tangential problems (0 between two half-planes of one material).
fn pressing_traction(pair: &PairResult) -> f64 {
    let (_, p0) = hertz();
    let pts = reference_points(pair);
    pts.iter()
        .fold(0.0f64, |m, &i| m.max(pair.tangential[i].abs()))
        / (MU * p0)
}

/// Solves, measures, prints and checks against the tolerances: c within 3 % of the
/// closed form (with Hertz's b and with b_h), q(x) within 5 % in L2, the resultant equal to Q
/// to 1e-8.
fn check(case: &CattaneoMindlin) -> Measured {
    let done = run(case);
    let press = &done[case.press - 1].1.contact[0];
    let coupling = pressing_traction(press);
    let m = measure(&done.last().expect("increments").1.contact[0], case);
    println!("{m:?}");
    println!(
        "  after pressing max |σ_t| = {:.2} % of μp₀; c/c_closed − 1 = {:+.2} %, \
         c/(b_h sqrt(1 − Q/μP)) − 1 = {:+.2} %, b_h/b − 1 = {:+.2} %, centre {:+.1e}, \
         q L2 {:.2} %, p L2 {:.2} %, resultant {:.1e}",
        100.0 * coupling,
        100.0 * (m.c / m.c_closed - 1.0),
        100.0 * (m.c / m.c_closed_h - 1.0),
        100.0 * (m.b_h / m.b - 1.0),
        m.centre,
        100.0 * m.q_l2,
        100.0 * m.p_l2,
        m.resultant.max(m.force)
    );
    // Measured 2.8 % (P1) to 3.5 % (P2, fine P1): the blocks are not half-planes.
    assert!(coupling <= 0.05, "pressing loads σ_t: {coupling}");
    assert!((m.c / m.c_closed - 1.0).abs() <= 0.03, "{m:?}");
    assert!((m.c / m.c_closed_h - 1.0).abs() <= 0.03, "{m:?}");
    assert!((m.b_h / m.b - 1.0).abs() <= 0.02, "{m:?}");
    // The stick zone is centred (within a cell).
    assert!(m.centre.abs() <= case.h, "{m:?}");
    assert!(m.q_l2 <= 0.05, "{m:?}");
    assert!(m.p_l2 <= 0.05, "{m:?}");
    assert!(m.resultant <= 1e-8 && m.force <= 1e-8, "{m:?}");
    assert!(m.excess <= 1e-12, "{m:?}");
    m
}

#[test]
fn p1_partial_slip_matches_cattaneo_mindlin() {
    check(&case(Order::P1, 0.002, 1e-9));
}

#[test]
fn p2_partial_slip_matches_cattaneo_mindlin() {
    check(&case(Order::P2, 0.004, 1e-9));
}

#[test]
#[ignore = "a finer mesh and a stiffer penalty: about 8 s in release"]
fn fine_p1_partial_slip_matches_cattaneo_mindlin() {
    check(&case(Order::P1, 0.001, 1e-10));
}
