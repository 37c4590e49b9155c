//! Hertz in space: an elastic sphere pressed on an elastic half-space, solved by the monolithic
//! reference of `solid_monolithic` on a quarter model, against the closed forms a = (3FR/4E*)^⅓
//! and p₀ = 3F/(2πa²) at the force F it finds.
//!
//! The half-space is the block [0, L]² × [−L, 0] and the sphere of radius R the block
//! [0, L]² × [0, L] whose bottom is bent onto the sphere z = R − √(R² − x² − y²); both meshes are
//! graded towards the contact (ten times finer there) and do not match. Symmetry rollers hold the
//! faces x = 0 and y = 0, the block rests on its bottom, and the sphere's top is moved down by δ.
//!
//!     cargo test --release -p contactdd-ddm --test solid_hertz -- --ignored --nocapture

use contactdd_core::solid::element::elasticity_matrix;
use contactdd_core::solid::{dof, BoxMesh, SolidMesh, TetOrder};
use contactdd_ddm::solid_dd::solve_solid_dd;
use contactdd_ddm::solid_monolithic::{
    solve_solid_monolithic, SolidBodySpec, SolidContactError, SolidContactPoint,
    SolidContactSolution, SolidPairSpec,
};

/// A solver of the reference's problems: the monolithic reference or the decomposition.
type Solver =
    fn(&[SolidBodySpec<'_>], &[SolidPairSpec]) -> Result<SolidContactSolution, SolidContactError>;

const R: f64 = 5.0;
const L: f64 = 1.0;
const E: f64 = 2.1e5;
const NU: f64 = 0.3;

/// A unit box of `n` cubes per side mapped by `place`.
fn mapped(n: usize, order: TetOrder, place: impl Fn([f64; 3]) -> [f64; 3]) -> SolidMesh {
    let mesh = BoxMesh {
        origin: [0.0; 3],
        size: [1.0; 3],
        cells: [n; 3],
        order,
    }
    .mesh()
    .unwrap();
    let nodes = (mesh.nodes().iter()).map(|&p| place(p)).collect();
    mesh.with_nodes(nodes).unwrap()
}

fn face_dofs(mesh: &SolidMesh, name: &str, c: usize, value: f64) -> Vec<(usize, f64)> {
    let mut nodes = mesh.face(name).unwrap().to_vec();
    nodes.sort_unstable();
    nodes.dedup();
    nodes.into_iter().map(|v| (dof(v, c), value)).collect()
}

/// The contact points of the quarter model with `n` cubes per side (the sphere `m`), the sphere's
/// top moved down by `delta`, solved by `solve`.
fn hertz(
    (n, m, order, delta): (usize, usize, TetOrder, f64),
    solve: Solver,
) -> (Vec<SolidContactPoint>, usize, Vec<(&'static str, f64)>) {
    // Spacing graded towards the contact by t ↦ t (c + (1 − c) t), ten times finer there than
    // at the far side; the block's z = −L grade(1 − t_z).
    let grade = |t: f64| t * (0.1 + 0.9 * t);
    let block = mapped(n, order, |[x, y, z]| {
        [L * grade(x), L * grade(y), -L * grade(1.0 - z)]
    });
    let cap = |x: f64, y: f64| R - (R * R - x * x - y * y).sqrt();
    let sphere = mapped(m, order, |[x, y, z]| {
        let (x, y, z) = (L * grade(x), L * grade(y), grade(z));
        [x, y, L * z + cap(x, y) * (1.0 - z)]
    });
    let elasticity = elasticity_matrix(E, NU).unwrap();
    let mut specs = Vec::new();
    for (b, mesh) in [&block, &sphere].into_iter().enumerate() {
        let mut prescribed = face_dofs(mesh, "x-", 0, 0.0);
        prescribed.extend(face_dofs(mesh, "y-", 1, 0.0));
        match b {
            0 => prescribed.extend(face_dofs(mesh, "z-", 2, 0.0)),
            _ => prescribed.extend(face_dofs(mesh, "z+", 2, -delta)),
        }
        specs.push(SolidBodySpec {
            mesh,
            elasticity,
            prescribed,
            load: vec![0.0; 3 * mesh.num_nodes()],
        });
    }
    let pairs = [SolidPairSpec {
        reference: (0, "z+".into()),
        partner: (1, "z-".into()),
        theta: 1e-9,
        search: 0.3,
        enforcement: Default::default(),
        friction: Default::default(),
    }];
    let sol = solve(&specs, &pairs).unwrap();
    (sol.points, sol.newton_steps, sol.timings)
}

/// The force F of the whole sphere, the contact radius a fitted to p² = p₀²(1 − r²/a²) over the
/// points above a fifth of the peak, and the peak pressure.
fn measure(points: &[SolidContactPoint]) -> (f64, f64, f64) {
    let force = 4.0 * points.iter().map(|p| p.weight * p.pressure).sum::<f64>();
    let peak = points.iter().map(|p| p.pressure).fold(0.0, f64::max);
    let fit: Vec<(f64, f64)> = (points.iter())
        .filter(|p| p.pressure > 0.2 * peak)
        .map(|p| {
            (
                p.position[0].powi(2) + p.position[1].powi(2),
                p.pressure.powi(2),
            )
        })
        .collect();
    let k = fit.len() as f64;
    let (mx, my) = fit
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / k, b + y / k));
    let (sxy, sxx) = fit.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    (force, (-intercept / slope).sqrt(), peak)
}

/// The decomposition and the monolithic reference solve the same discrete problem in the same
/// Newton steps: on a coarse Hertz model their pressures agree to 1e-9 of the peak.
#[test]
fn the_decomposition_matches_the_monolithic_reference() {
    let case = (4, 3, TetOrder::P2, 0.004);
    let (dd, dd_steps, _) = hertz(case, solve_solid_dd);
    let (mono, mono_steps, _) = hertz(case, solve_solid_monolithic);
    assert_eq!(dd_steps, mono_steps);
    let peak = mono.iter().map(|p| p.pressure).fold(0.0, f64::max);
    assert!(peak > 0.0);
    for (a, b) in dd.iter().zip(&mono) {
        assert_eq!(a.node, b.node);
        assert!(
            (a.pressure - b.pressure).abs() < 1e-9 * peak,
            "{a:?} against {b:?}"
        );
    }
}

#[test]
#[ignore = "heavy: about three minutes in release"]
fn a_sphere_on_a_half_space_follows_hertz() {
    let e_star = E / (2.0 * (1.0 - NU * NU));
    let (order, n, m, delta) = (TetOrder::P2, 14, 13, 0.004);
    let started = std::time::Instant::now();
    let (points, steps, phases) = hertz((n, m, order, delta), solve_solid_dd);
    let dd_time = started.elapsed().as_secs_f64();
    let started = std::time::Instant::now();
    let (mono, mono_steps, _) = hertz((n, m, order, delta), solve_solid_monolithic);
    let mono_time = started.elapsed().as_secs_f64();
    println!(
        "decomposition {dd_time:.1} s ({phases:?}), {steps} steps; monolithic {mono_time:.1} s, \
         {mono_steps} steps"
    );
    let peak = mono.iter().map(|p| p.pressure).fold(0.0, f64::max);
    for (a, b) in points.iter().zip(&mono) {
        assert!(
            (a.pressure - b.pressure).abs() < 1e-9 * peak,
            "{a:?} against {b:?}"
        );
    }
    let (force, a, peak) = measure(&points);
    let a_hertz = (3.0 * force * R / (4.0 * e_star)).cbrt();
    let p_hertz = 3.0 * force / (2.0 * std::f64::consts::PI * a_hertz * a_hertz);
    println!(
        "{order:?} {n}/{m}: F = {force:.4}, a = {a:.5} against {a_hertz:.5} ({:+.2} %), \
         p0 = {peak:.2} against {p_hertz:.2} ({:+.2} %), {steps} Newton steps",
        100.0 * (a / a_hertz - 1.0),
        100.0 * (peak / p_hertz - 1.0)
    );
    assert!((a / a_hertz - 1.0).abs() < 0.02);
    assert!((peak / p_hertz - 1.0).abs() < 0.03);
}

/// The decomposition gives the same bits on one thread and on two (bodies in parallel).
#[test]
fn the_decomposition_is_the_same_on_any_number_of_threads() {
    let case = (4, 3, TetOrder::P2, 0.004);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| hertz(case, solve_solid_dd)).0
    };
    let (one, two) = (run(1), run(2));
    assert!(one.iter().any(|p| p.pressure > 0.0));
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(
            a.pressure.to_bits(),
            b.pressure.to_bits(),
            "{a:?} against {b:?}"
        );
    }
}
