//! Hard test problems beyond the paper's mirror-symmetric notch, built in code. Tests, benches and
//! `examples/iteration_counts.rs` share them.
//!
//! - [`stiff_under_soft`]: a clamped block under a ten times softer loaded block, notch gap;
//! - [`column()`]: a column of blocks on a frictionless floor, held only by their contacts;
//! - [`recess`]: two large blocks pressed together over a shallow recess (the closed form of two
//!   pressed half-planes applies);
//! - [`non_matching_notch`]: the paper's notch with different meshes on the two sides;
//! - [`wall`]: a wall of blocks in rows and columns, confined between two walls and pressed on
//!   top (contacts across horizontal and vertical lines; closed forms for the penalty and the
//!   exact contact).
//!
//! All are plane strain, in cm and N/cm², with the rod-model penalty θ = c·h·(1/E*₁ + 1/E*₂).

use contactdd_core::{
    Component, Constraints, Diagonal, ElasticBody, Load, Material, Mesh, Order, Plane, Rectangle,
};
use contactdd_ddm::contact::gap_profile::{Along, GapProfile};
use contactdd_ddm::{ContactPair, Enforcement, Model, Penalty};

/// A structured rectangle mesh of `[x0, x1] × [y0, y1]`.
pub fn rectangle(x: [f64; 2], y: [f64; 2], nx: usize, ny: usize, mirror: bool) -> Mesh {
    Rectangle {
        origin: [x[0], y[0]],
        corner: [x[1], y[1]],
        nx,
        ny,
        diagonal: Diagonal::Right,
        mirror,
        order: Order::P1,
    }
    .mesh()
    .expect("a valid rectangle")
}

/// A body with supports (boundary, component) and a pressure on one boundary.
pub fn body(
    name: &str,
    mesh: Mesh,
    young: f64,
    supports: &[(&str, Component)],
    pressure: Option<(&str, f64)>,
) -> ElasticBody {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for &(b, c) in supports {
        constraints.fix(&mesh, b, c, 0.0).expect("a known boundary");
    }
    let loads: Vec<Load> = pressure
        .map(|(boundary, value)| Load::Pressure {
            boundary: boundary.into(),
            value,
        })
        .into_iter()
        .collect();
    let load = contactdd_core::loads::load_vector(&mesh, &loads).expect("a known boundary");
    ElasticBody {
        name: name.into(),
        mesh,
        material: Material::new(young, 0.3).expect("a valid material"),
        plane: Plane::Strain,
        constraints,
        load,
    }
}

/// A contact pair between body `a`'s top and body `b`'s bottom.
pub fn top_bottom(name: &str, a: usize, b: usize, c: f64, h: f64) -> ContactPair {
    ContactPair {
        name: name.into(),
        bodies: [a, b],
        boundaries: ["top".into(), "bottom".into()],
        penalty: Penalty::RodModel { c, h },
        profile: None,
        enforcement: Enforcement::Penalty,
        forces: Default::default(),
        friction: Default::default(),
    }
}

/// The notch profile d = r0 {[1 − (ξ − centre)²/b²]⁺}^{3/2} along x.
pub fn notch_profile(r0: f64, b: f64, centre: f64) -> GapProfile {
    GapProfile::Notch {
        r0,
        b,
        centre,
        power: 1.5,
        along: Along::X,
    }
}

/// The paper's notch geometry ([0, 4] × [0, 1] under [0, 4] × [1, 2], symmetry on x = 4) with a
/// lower block clamped at its bottom and an upper block ten times softer, pressed down by
/// q = 0.01 E_upper, held only by the contact vertically; penalty factor `c`.
pub fn stiff_under_soft(c: f64) -> Model {
    let e = 2.1e5;
    let lower = body(
        "stiff",
        rectangle([0.0, 4.0], [0.0, 1.0], 32, 16, false),
        e,
        &[("bottom", Component::Both), ("right", Component::X)],
        None,
    );
    let upper = body(
        "soft",
        rectangle([0.0, 4.0], [1.0, 2.0], 32, 16, true),
        e / 10.0,
        &[("right", Component::X)],
        Some(("top", 0.01 * e / 10.0)),
    );
    notch_pair("stiff-under-soft", lower, upper, c)
}

/// Two bodies of the notch geometry in contact across y = 1 with the paper's notch profile.
fn notch_pair(name: &str, lower: ElasticBody, upper: ElasticBody, c: f64) -> Model {
    let mut pair = top_bottom("notch", 0, 1, c, 1.0);
    pair.profile = Some(notch_profile(0.05, 1.0, 4.0));
    Model {
        name: name.into(),
        plane: Plane::Strain,
        bodies: vec![lower, upper],
        pairs: vec![pair],
        remote: Vec::new(),
    }
}

/// A column of `n` blocks [0, 2] × [0.25 k, 0.25 (k + 1)] (half model, symmetry on x = 0) on a
/// frictionless floor, pressed by p = 100 on top. Steel and aluminium alternate, and so do the
/// meshes (40 × 5 and 30 × 5 cells), so every interface is non-matching. The exact solution is
/// the uniform stress σ_yy = −p: every contact pressure is p.
pub fn column(n: usize, c: f64) -> Model {
    let bodies = (0..n)
        .map(|k| {
            let y = 0.25 * k as f64;
            let (young, nx) = if k % 2 == 0 { (2.1e5, 40) } else { (7.0e4, 30) };
            let mut supports = vec![("left", Component::X)];
            if k == 0 {
                supports.push(("bottom", Component::Y));
            }
            let load = (k + 1 == n).then_some(("top", 100.0));
            body(
                &format!("b{k}"),
                rectangle([0.0, 2.0], [y, y + 0.25], nx, 5, false),
                young,
                &supports,
                load,
            )
        })
        .collect();
    let pairs = (1..n)
        .map(|k| top_bottom(&format!("b{}-b{k}", k - 1), k - 1, k, c, 0.25))
        .collect();
    Model {
        name: format!("column-{n}"),
        plane: Plane::Strain,
        bodies,
        pairs,
        remote: Vec::new(),
    }
}

/// Half-width of the recess of [`recess`].
pub const RECESS_B: f64 = 1.0;
/// Depth of the recess of [`recess`].
pub const RECESS_R0: f64 = 0.002;
/// Pressure on the blocks of [`recess`].
pub const RECESS_Q: f64 = 100.0;

/// Two blocks [0, 20] × [−10, 0] and [0, 20] × [0, 10] (half model, symmetry on x = 0), pressed
/// together by q = 100 over a shallow recess d = r0 (1 − x²/b²)^{3/2}, b = 1, r0 = 0.002. The
/// lower block (E₁ = ratio · E₂) rests on a frictionless floor; the upper one (E₂ = 2.1e5) is held
/// vertically only by the contact. `n` sets the mesh (4n × n cells per block), graded
/// quadratically towards the recess and the contact line.
pub fn recess(ratio: f64, c: f64, n: usize) -> Model {
    let e2 = 2.1e5;
    let mesh = |y: [f64; 2], mirror: bool| {
        let m = rectangle([0.0, 20.0], y, 4 * n, n, mirror);
        // Grade towards x = 0 and towards the contact line y = 0: ξ ↦ L ξ^2 keeps the cells near
        // the recess small.
        m.map_nodes(|p| {
            let gx = 20.0 * (p[0] / 20.0).powi(2);
            let gy = 10.0 * (p[1] / 10.0).abs().powi(2) * p[1].signum();
            [gx, gy]
        })
        .expect("a valid graded mesh")
    };
    let lower = body(
        "lower",
        mesh([-10.0, 0.0], false),
        ratio * e2,
        &[("left", Component::X), ("bottom", Component::Y)],
        None,
    );
    let upper = body(
        "upper",
        mesh([0.0, 10.0], true),
        e2,
        &[("left", Component::X)],
        Some(("top", RECESS_Q)),
    );
    let mut pair = top_bottom("recess", 0, 1, c, 1.0);
    pair.profile = Some(notch_profile(RECESS_R0, RECESS_B, 0.0));
    Model {
        name: "recess".into(),
        plane: Plane::Strain,
        bodies: vec![lower, upper],
        pairs: vec![pair],
        remote: Vec::new(),
    }
}

/// [`recess`] with the lower block also floating vertically: symmetry on its left side and the
/// pressure q on its bottom instead of the floor, so that only the contact holds either block
/// vertically.
pub fn floating_recess(ratio: f64, c: f64, n: usize) -> Model {
    let mut model = recess(ratio, c, n);
    let mesh = model.bodies[0].mesh.clone();
    model.bodies[0] = body(
        "lower",
        mesh,
        ratio * 2.1e5,
        &[("left", Component::X)],
        Some(("bottom", RECESS_Q)),
    );
    model
}

/// The paper's notch benchmark with 32 × 16 cells below and 23 × 12 above (non-matching).
pub fn non_matching_notch(c: f64) -> Model {
    let e = 2.1e5;
    let q = 0.01 * e;
    let lower = body(
        "lower",
        rectangle([0.0, 4.0], [0.0, 1.0], 32, 16, false),
        e,
        &[("right", Component::X)],
        Some(("bottom", q)),
    );
    let upper = body(
        "upper",
        rectangle([0.0, 4.0], [1.0, 2.0], 23, 12, true),
        e,
        &[("right", Component::X)],
        Some(("top", q)),
    );
    notch_pair("non-matching-notch", lower, upper, c)
}

/// Pressure on the top of [`wall`].
pub const WALL_Q: f64 = 100.0;

/// A wall of `columns` × `rows` unit blocks [i, i + 1] × [j, j + 1] (E = 2.1e5, ν = 0.3), the
/// bottom row on a frictionless floor, the outer columns against frictionless side walls
/// (u_x = 0), pressed by q = [`WALL_Q`] on top. The meshes alternate between 10 × 10 and 13 × 13
/// cells like a checkerboard, so every interface is non-matching. Every pair, across horizontal
/// and vertical lines, has the rod-model penalty with factor `c` and h = 1.
///
/// The stress is uniform: σ_yy = −q, and σ_xx follows from the confinement. The blocks overlap by
/// θ p at each of the `columns − 1` vertical interfaces, so the lateral pressure is
/// q ν/(1 − ν) / (1 + 2c (columns − 1)/columns) for the penalty, and q ν/(1 − ν) for the exact
/// contact.
pub fn wall(columns: usize, rows: usize, c: f64) -> Model {
    let name = |i: usize, j: usize| format!("b{i}_{j}");
    let mut bodies = Vec::new();
    for j in 0..rows {
        for i in 0..columns {
            let n = if (i + j) % 2 == 0 { 10 } else { 13 };
            let mut supports = Vec::new();
            if j == 0 {
                supports.push(("bottom", Component::Y));
            }
            if i == 0 {
                supports.push(("left", Component::X));
            }
            if i + 1 == columns {
                supports.push(("right", Component::X));
            }
            let (x, y) = (i as f64, j as f64);
            bodies.push(body(
                &name(i, j),
                rectangle([x, x + 1.0], [y, y + 1.0], n, n, false),
                2.1e5,
                &supports,
                (j + 1 == rows).then_some(("top", WALL_Q)),
            ));
        }
    }
    let index = |i: usize, j: usize| j * columns + i;
    let mut pairs = Vec::new();
    for j in 0..rows {
        for i in 0..columns {
            if j + 1 < rows {
                let (a, b) = (index(i, j), index(i, j + 1));
                pairs.push(top_bottom(
                    &format!("{}-{}", name(i, j), name(i, j + 1)),
                    a,
                    b,
                    c,
                    1.0,
                ));
            }
            if i + 1 < columns {
                let mut pair =
                    top_bottom(&format!("{}-{}", name(i, j), name(i + 1, j)), 0, 0, c, 1.0);
                pair.bodies = [index(i, j), index(i + 1, j)];
                pair.boundaries = ["right".into(), "left".into()];
                pairs.push(pair);
            }
        }
    }
    Model {
        name: format!("wall-{columns}x{rows}"),
        plane: Plane::Strain,
        bodies,
        pairs,
        remote: Vec::new(),
    }
}
