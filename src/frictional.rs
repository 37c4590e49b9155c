//! Frictional test problems built in code, shared by the tests and
//! `examples/friction_iterations.rs` (docs/friction.md):
//!
//! - [`block_on_foundation`]: a block with no support pressed on a clamped foundation and pushed
//!   sideways, so that friction alone holds it (closed forms: the block's balance, and the
//!   threshold Q = μN of sliding);
//! - [`sheared_wall`]: the wall of [`crate::cases::wall`] with Coulomb friction on every pair and
//!   its top row pushed sideways.
//!
//! Plane strain; the rod-model penalty θ = c·h·(1/E*₁ + 1/E*₂).

use contactdd_core::{loads::load_vector, Component, Diagonal, Load, Mesh, Order, Rectangle};
use contactdd_ddm::{ContactPair, Enforcement, Forces, Friction, Model, Penalty};

use crate::cases::{body, wall, WALL_Q};

/// The block's Young's modulus (ν = 0.3).
pub const BLOCK_E: f64 = 1000.0;

fn mesh(x: [f64; 2], y: [f64; 2], nx: usize, ny: usize, order: Order) -> Mesh {
    Rectangle {
        origin: [x[0], y[0]],
        corner: [x[1], y[1]],
        nx,
        ny,
        diagonal: Diagonal::Right,
        mirror: false,
        order,
    }
    .mesh()
    .expect("a valid rectangle")
}

/// A 2 × 1 block (`upper` × 4 cells of `order`) on a 4 × 1 foundation (16 × 4 cells) clamped
/// at its bottom, pressed by `p` on its top (N = 2p) and pushed by the traction `q` on its left
/// side (Q = q); the block has no support. One pair, `joint`, with `friction` and the rod-model
/// penalty factor `c`.
pub fn block_on_foundation(
    p: f64,
    q: f64,
    friction: Friction,
    (upper, order): (usize, Order),
    c: f64,
) -> Model {
    let foundation = body(
        "foundation",
        mesh([0.0, 4.0], [0.0, 1.0], 16, 4, order),
        BLOCK_E,
        &[("bottom", Component::X), ("bottom", Component::Y)],
        None,
    );
    let mut block = body(
        "block",
        mesh([1.0, 3.0], [1.0, 2.0], upper, 4, order),
        BLOCK_E,
        &[],
        Some(("top", p)),
    );
    push(&mut block.load, &block.mesh, "left", q);
    Model {
        name: "block".into(),
        plane: foundation.plane,
        bodies: vec![foundation, block],
        pairs: vec![ContactPair {
            name: "joint".into(),
            bodies: [0, 1],
            boundaries: ["top".into(), "bottom".into()],
            penalty: Penalty::RodModel { c, h: 1.0 },
            profile: None,
            enforcement: Enforcement::Penalty,
            forces: Forces::Balanced,
            friction,
        }],
        remote: Vec::new(),
    }
}

/// Adds the traction [q, 0] on `boundary` to the load vector `load`.
fn push(load: &mut [f64], mesh: &Mesh, boundary: &str, q: f64) {
    let traction = [Load::Traction {
        boundary: boundary.into(),
        value: [q, 0.0],
    }];
    let extra = load_vector(mesh, &traction).expect("a known boundary");
    load.iter_mut().zip(extra).for_each(|(f, e)| *f += e);
}

/// The wall of `n` × `n` blocks of [`wall`] (penalty factor `c`) with Coulomb friction μ on
/// every pair, its top row also pushed along x by `shear` times the pressure on its top.
pub fn sheared_wall(n: usize, mu: f64, shear: f64, c: f64) -> Model {
    let mut model = wall(n, n, c);
    for pair in &mut model.pairs {
        pair.friction = Friction::Coulomb { mu };
    }
    for body in model.bodies.iter_mut().skip(n * (n - 1)) {
        push(&mut body.load, &body.mesh, "top", shear * WALL_Q);
    }
    model
}
