//! Invariance under rigid motions: a problem shifted by a tiny amount (1e−14, 1e−10, 1e−6 of its
//! size) or rotated (0.5°, 30°) as a whole (meshes, normal supports, clamped edges, pressure
//! loads, the gap profile's line) has the peak contact pressure and the resultant contact force
//! (turned back) of the unmoved problem to 1e−6. The paper's notch on matching meshes exercises
//! the decision that turns a balanced pair whose sides match node for node into the own-side
//! formulation (a different discrete problem: its peak pressure differs by 2 %), which must not
//! depend on rounding; two blocks of different widths exercise the balanced pairs themselves.

use contactdd::cases;
use contactdd::ddm::contact::gap_profile::{Along, GapProfile};
use contactdd::ddm::{prepare, solve, Forces, Hooks, Model, Settings};
use contactdd::fem::{Component, Mesh, Plane};

/// A rigid motion: a rotation by `deg` degrees about the origin, then a shift.
#[derive(Clone, Copy, Debug)]
struct Motion {
    deg: f64,
    shift: [f64; 2],
}

impl Motion {
    fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.deg.to_radians().sin_cos();
        [
            c * p[0] - s * p[1] + self.shift[0],
            s * p[0] + c * p[1] + self.shift[1],
        ]
    }

    /// A vector turned back by the rotation.
    fn unturn(&self, v: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.deg.to_radians().sin_cos();
        [c * v[0] + s * v[1], -s * v[0] + c * v[1]]
    }

    fn mesh(&self, mesh: Mesh) -> Mesh {
        mesh.map_nodes(|p| self.apply(p)).unwrap()
    }
}

/// The paper's notch on matching 32 × 16 meshes (the upper one mirrored), held by normal
/// supports on the right edges, moved by `m`.
fn notch(m: Motion, forces: Forces) -> Model {
    let body = |name: &str, y: [f64; 2], mirror: bool, loaded: &str| {
        let mesh = m.mesh(cases::rectangle([0.0, 4.0], y, 32, 16, mirror));
        let supports = [("right", Component::Normal)];
        cases::body(name, mesh, 2.1e5, &supports, Some((loaded, 2100.0)))
    };
    let mut pair = cases::top_bottom("notch", 0, 1, 0.05, 1.0);
    pair.forces = forces;
    // The profile's coordinate ξ = x·d along the turned x axis d: the centre moves by shift·d.
    let (s, c) = m.deg.to_radians().sin_cos();
    pair.profile = Some(GapProfile::Notch {
        r0: 0.05,
        b: 1.0,
        centre: 4.0 + c * m.shift[0] + s * m.shift[1],
        power: 1.5,
        along: Along::Angle(m.deg),
    });
    Model {
        name: format!("notch moved by {m:?}"),
        plane: Plane::Strain,
        bodies: vec![
            body("lower", [0.0, 1.0], false, "bottom"),
            body("upper", [1.0, 2.0], true, "top"),
        ],
        pairs: vec![pair],
        remote: Vec::new(),
    }
}

/// A 2 × 0.5 block clamped at its bottom under a 3 × 0.5 block held by a normal support on its
/// left and pressed on its top (the same mesh size, but the sides do not match node for node),
/// moved by `m`.
fn blocks(m: Motion, forces: Forces) -> Model {
    let rectangle = |x, y, nx, mirror| m.mesh(cases::rectangle(x, y, nx, 2, mirror));
    let lower = cases::body(
        "lower",
        rectangle([0.0, 2.0], [0.0, 0.5], 8, false),
        2.1e5,
        &[("bottom", Component::Both)],
        None,
    );
    let upper = cases::body(
        "upper",
        rectangle([-0.5, 2.5], [0.5, 1.0], 12, true),
        2.1e5,
        &[("left", Component::Normal)],
        Some(("top", 100.0)),
    );
    let mut pair = cases::top_bottom("pair", 0, 1, 0.05, 0.5);
    pair.forces = forces;
    Model {
        name: format!("blocks moved by {m:?}"),
        plane: Plane::Strain,
        bodies: vec![lower, upper],
        pairs: vec![pair],
        remote: Vec::new(),
    }
}

/// The peak contact pressure and the resultant contact force on side 0, turned back by `m`.
fn peak_and_resultant(model: &Model, m: Motion) -> (f64, [f64; 2]) {
    let prepared = prepare(model).unwrap();
    let settings = Settings {
        tol: 1e-10,
        ..Settings::default()
    };
    let sol = solve(model, &prepared, &settings, Hooks::default()).unwrap();
    assert!(sol.converged, "{}: {:?}", model.name, sol.message);
    let pair = &sol.contact[0];
    let peak = pair.pressure.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let mut force = [0.0; 2];
    for i in (0..pair.side.len()).filter(|&i| pair.side[i] == 0) {
        force[0] += pair.fx[i];
        force[1] += pair.fy[i];
    }
    (peak, m.unturn(force))
}

/// The motions: shifts by 1e−14, 1e−10 and 1e−6 of the size (in both directions, and along a
/// skew direction), rotations by 0.5° and 30°, and a rotation with a shift.
fn motions(size: f64) -> Vec<Motion> {
    let shift = |d: f64| Motion {
        deg: 0.0,
        shift: [d, -0.7 * d],
    };
    let turn = |deg: f64| Motion {
        deg,
        shift: [0.0, 0.0],
    };
    vec![
        shift(1e-14),
        shift(-1e-14),
        shift(1e-10),
        shift(1e-6 * size),
        shift(-1e-6 * size),
        turn(0.5),
        turn(30.0),
        Motion {
            deg: -0.5,
            shift: [3e-7 * size, 1e-14],
        },
    ]
}

fn assert_invariant(name: &str, build: fn(Motion, Forces) -> Model, size: f64) {
    for forces in [Forces::Balanced, Forces::OwnSide] {
        let still = Motion {
            deg: 0.0,
            shift: [0.0, 0.0],
        };
        let (peak, resultant) = peak_and_resultant(&build(still, forces), still);
        let scale = resultant[0].hypot(resultant[1]);
        assert!(peak > 0.0 && scale > 0.0);
        for m in motions(size) {
            let (moved_peak, moved_resultant) = peak_and_resultant(&build(m, forces), m);
            let change = (moved_peak - peak).abs() / peak;
            assert!(
                change < 1e-6,
                "{name}, {forces:?}, {m:?}: peak {moved_peak} against {peak} ({change:.1e})"
            );
            let off = (moved_resultant[0] - resultant[0]).hypot(moved_resultant[1] - resultant[1]);
            assert!(
                off < 1e-6 * scale,
                "{name}, {forces:?}, {m:?}: resultant {moved_resultant:?} against {resultant:?}"
            );
        }
    }
}

#[test]
fn the_matching_notch_moved_has_the_same_peak_and_resultant() {
    assert_invariant("notch", notch, 4.0);
}

#[test]
fn two_blocks_moved_have_the_same_peak_and_resultant() {
    assert_invariant("blocks", blocks, 3.0);
}
