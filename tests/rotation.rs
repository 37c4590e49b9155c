//! Frame invariance: the paper's notch on non-matching meshes, rotated as a whole (meshes, the
//! normal supports, the pressure loads and the gap profile's line), has the contact pressures of
//! the unrotated problem at every point. It exercises inclined normals, inclined supports and
//! profiles along an inclined line, against a reference that shares nothing with the rotation.

use contactdd::cases;
use contactdd::ddm::contact::gap_profile::{Along, GapProfile};
use contactdd::ddm::{prepare, solve, Forces, Hooks, Model, Settings};
use contactdd::fem::{Component, Mesh, Plane};

/// `mesh` rotated by `deg` degrees about the origin.
fn rotated(mesh: Mesh, deg: f64) -> Mesh {
    let (s, c) = deg.to_radians().sin_cos();
    mesh.map_nodes(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
        .unwrap()
}

/// The notch with 32 × 16 cells below and 24 × 16 above, rotated by `deg`.
fn notch(deg: f64, forces: Forces) -> Model {
    let body = |name: &str, y: [f64; 2], nx: usize, mirror: bool, loaded: &str| {
        let mesh = rotated(cases::rectangle([0.0, 4.0], y, nx, 16, mirror), deg);
        let supports = [("right", Component::Normal)];
        cases::body(name, mesh, 2.1e5, &supports, Some((loaded, 2100.0)))
    };
    let mut pair = cases::top_bottom("notch", 0, 1, 0.05, 1.0);
    pair.forces = forces;
    pair.profile = Some(GapProfile::Notch {
        r0: 0.05,
        b: 1.0,
        centre: 4.0,
        power: 1.5,
        along: Along::Angle(deg),
    });
    Model {
        name: format!("notch rotated by {deg}°"),
        plane: Plane::Strain,
        bodies: vec![
            body("lower", [0.0, 1.0], 32, false, "bottom"),
            body("upper", [1.0, 2.0], 24, true, "top"),
        ],
        pairs: vec![pair],
        remote: Vec::new(),
    }
}

fn pressures(model: &Model) -> Vec<f64> {
    let prepared = prepare(model).unwrap();
    // Own-side forces on non-matching meshes leave the bodies out of balance by about 1e-3 of
    // the load (each side integrates its own pressures): accept that, to compare the pressures.
    let own_side = model.pairs.iter().any(|p| p.forces == Forces::OwnSide);
    let settings = Settings {
        tol: 1e-10,
        balance_tol: own_side.then_some(1e-2),
        ..Settings::default()
    };
    let sol = solve(model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{}: {:?}", model.name, sol.message);
    sol.contact[0].pressure.clone()
}

#[test]
fn a_rotated_problem_has_the_same_pressures() {
    for forces in [Forces::Balanced, Forces::OwnSide] {
        let reference = pressures(&notch(0.0, forces));
        let peak = reference.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        assert!(peak > 0.0);
        for deg in [30.0, -73.0] {
            let turned = pressures(&notch(deg, forces));
            assert_eq!(turned.len(), reference.len());
            let worst = turned
                .iter()
                .zip(&reference)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                worst <= 1e-9 * peak,
                "{forces:?}, {deg}°: {worst:e} of {peak}"
            );
        }
    }
}
