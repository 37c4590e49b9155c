//! Frictional test problems built in code, shared by the tests and
//! `examples/friction_iterations.rs` (docs/friction.md):
//!
//! - [`block_on_foundation`]: a block with no support pressed on a clamped foundation and pushed
//!   sideways, so that friction alone holds it (closed forms: the block's balance, and the
//!   threshold Q = μN of sliding);
//! - [`sheared_wall`]: the wall of [`crate::cases::wall`] with Coulomb friction on every pair and
//!   its top row pushed sideways;
//! - [`sheared_block`]: the same block held by its top, pressed and sheared by prescribed
//!   displacements;
//! - [`cattaneo_mindlin`]: two mirror-image cylindrical blocks pressed together, then sheared
//!   (the Cattaneo–Mindlin partial slip), as a load history.
//!
//! Plane strain; the rod-model penalty θ = c·h·(1/E*₁ + 1/E*₂) (θ given directly for
//! [`cattaneo_mindlin`]).

use contactdd_core::{
    dof, loads::load_vector, Component, Constraints, Diagonal, ElasticBody, Load, Material, Mesh,
    Order, Plane, Rectangle,
};
use contactdd_ddm::history::{HistoryStep, LoadGroup, LoadHistory};
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

/// The block of [`block_on_foundation`] held by its top instead of loaded: the top moved by
/// `down` towards the foundation and by `along` sideways (prescribed displacements), so that
/// both bodies are held and friction decides how the base sticks and slips.
pub fn sheared_block(friction: Friction, (down, along): (f64, f64)) -> Model {
    let mut model = block_on_foundation(0.0, 0.0, friction, (8, Order::P1), 0.05);
    let block = &mut model.bodies[1];
    for (component, value) in [(Component::X, along), (Component::Y, -down)] {
        (block.constraints)
            .fix(&block.mesh, "top", component, value)
            .expect("the block has a top");
    }
    model.name = "sheared-block".into();
    model
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

/// The Cattaneo–Mindlin problem of [`cattaneo_mindlin`]: what it needs besides the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CattaneoMindlin {
    /// Element order (P2 meshes are the P1 ones with mid-side nodes added).
    pub order: Order,
    /// The P1 cell size in the zone |x| ≤ [`CM_ZONE`] and near the contact line.
    pub h: f64,
    /// Coulomb's coefficient μ.
    pub mu: f64,
    /// The shear Q as a fraction of μP.
    pub shear: f64,
    /// The press step's increments.
    pub press: usize,
    /// The shear step's increments.
    pub increments: usize,
    /// The penalty θ.
    pub theta: f64,
    /// How the pair enforces contact.
    pub enforcement: Enforcement,
}

/// Young's modulus of both blocks of [`cattaneo_mindlin`] (ν = 0.3).
pub const CM_E: f64 = 2.1e5;
/// The radius of curvature of the upper block's bottom at the contact point.
pub const CM_R: f64 = 10.0;
/// The normal load P per unit thickness.
pub const CM_P: f64 = 90.0;
/// The half-width of the zone meshed at the finest size (beyond it the cells grow by 10 % per
/// cell), and of the circular part of the profile (beyond it the profile continues straight).
pub const CM_ZONE: f64 = 0.15;

/// Node coordinates from 0 to `len`: steps of `h` up to `zone`, then growing by the factor 1.1
/// per cell, the last steps scaled to end at `len` exactly.
fn graded(h: f64, zone: f64, len: f64) -> Vec<f64> {
    let n = (zone / h).round().max(1.0) as usize;
    let mut out: Vec<f64> = (0..=n).map(|i| i as f64 * (zone / n as f64)).collect();
    let (mut x, mut step) = (zone, zone / n as f64);
    let mut tail = Vec::new();
    while x < len {
        step *= 1.1;
        x += step;
        tail.push(x);
    }
    let scale = (len - zone) / (x - zone);
    out.extend(tail.iter().map(|t| zone + (t - zone) * scale));
    out
}

/// The rise of the upper block's bottom above the contact point at abscissa x: a circle's
/// x²/(2R) for |x| ≤ z = [`CM_ZONE`], its slope then falling linearly to 0 at 2z, flat beyond
/// (the rise z²/R at the ends), so that the blocks differ little but for the contact zone.
fn profile(x: f64) -> f64 {
    let (a, z) = (x.abs().min(2.0 * CM_ZONE), CM_ZONE);
    match a <= z {
        true => a * a / (2.0 * CM_R),
        false => z * z / (2.0 * CM_R) + z / CM_R * (a - z) - (a - z).powi(2) / (2.0 * CM_R),
    }
}

/// The lower block of [`cattaneo_mindlin`], [−1, 1] × [−1, 0] (`upper`: [−1, 1] × [0, 1] with
/// its bottom raised by [`profile`], the rise fading linearly to 0 at the top), graded towards
/// the contact point; the two are mirror images in y = 0 node for node but for the rise.
fn block_mesh(h: f64, order: Order, upper: bool) -> Mesh {
    let half = graded(h, CM_ZONE, 1.0);
    let xs: Vec<f64> = (half.iter().rev().map(|x| -x))
        .chain(half[1..].iter().copied())
        .collect();
    let ys = graded(h, 0.05, 1.0);
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    // Nodes at integer coordinates (i, ±j), mapped onto the graded block.
    let grid = Rectangle {
        origin: [0.0, if upper { 0.0 } else { -(ny as f64) }],
        corner: [nx as f64, if upper { ny as f64 } else { 0.0 }],
        nx,
        ny,
        diagonal: Diagonal::Right,
        mirror: upper,
        order: Order::P1,
    }
    .mesh()
    .expect("a valid rectangle");
    let mesh = grid
        .map_nodes(|[i, j]| {
            let x = xs[i.round() as usize];
            let y = ys[j.abs().round() as usize];
            match upper {
                true => [x, y + profile(x) * (1.0 - y)],
                false => [x, -y],
            }
        })
        .expect("a valid mapped mesh");
    match order {
        Order::P1 => mesh,
        Order::P2 => mesh.to_p2(),
    }
}

/// Cattaneo–Mindlin partial slip: two steel blocks (E = [`CM_E`], ν = 0.3), nearly mirror
/// images in y = 0: the lower one's top is flat, the upper one's bottom a cylinder of radius
/// R = [`CM_R`] near the contact point (0, 0), flattening beyond 2·[`CM_ZONE`]; Coulomb
/// friction μ between them. Load groups: `press`, a pressure P/2 on the lower block's bottom
/// and on the upper block's top (the normal load P = [`CM_P`]); `shear`, on the lower block
/// tractions Q along x on each side and −Q/2 on the bottom (resultant Q, no moment about the
/// contact point), on the upper block their mirror image reversed, with Q = `shear`·μP. The
/// history presses, then shears. The lower block is held only by the contact; the upper
/// block's top centre node is pinned and its top right corner held in y (statically
/// determinate: the loads balance, so the reactions are 0). By the near mirror symmetry the
/// pressing loads little tangential traction (a few % of μp₀, where two half-planes have none)
/// and the shear hardly changes the pressure; the flat side is the pair's reference side, its
/// tangent x, and b/R = 0.01 keeps the curved side's own slope small.
pub fn cattaneo_mindlin(case: &CattaneoMindlin) -> (Model, LoadHistory) {
    let q = case.shear * case.mu * CM_P;
    let p = CM_P / 2.0;
    let material = Material::new(CM_E, 0.3).expect("a valid material");
    let traction = |boundary: &str, value: f64| Load::Traction {
        boundary: boundary.into(),
        value: [value, 0.0],
    };
    let pressure = |boundary: &str| Load::Pressure {
        boundary: boundary.into(),
        value: p,
    };
    let mut bodies = Vec::new();
    let mut press = Vec::new();
    let mut shear = Vec::new();
    for (name, mirror) in [("lower", false), ("upper", true)] {
        let mesh = block_mesh(case.h, case.order, mirror);
        let (outer, sign) = if mirror {
            ("top", -1.0)
        } else {
            ("bottom", 1.0)
        };
        let loads = [
            traction("left", sign * q),
            traction("right", sign * q),
            traction(outer, -sign * q / 2.0),
        ];
        shear.push(load_vector(&mesh, &loads).expect("known boundaries"));
        press.push(load_vector(&mesh, &[pressure(outer)]).expect("a known boundary"));
        let mut constraints = Constraints::new(mesh.num_nodes());
        if mirror {
            // Statically determinate: the top centre node pinned, the top right corner held
            // in y. The loads balance, so the reactions vanish.
            let nearest = |p: [f64; 2]| {
                let d = |n: usize| {
                    let q = mesh.nodes()[n];
                    (q[0] - p[0]).hypot(q[1] - p[1])
                };
                (0..mesh.num_nodes())
                    .min_by(|&a, &b| d(a).total_cmp(&d(b)))
                    .expect("nodes")
            };
            let (pin, corner) = (nearest([0.0, 1.0]), nearest([1.0, 1.0]));
            constraints.set(dof(pin, 0), Some(0.0));
            constraints.set(dof(pin, 1), Some(0.0));
            constraints.set(dof(corner, 1), Some(0.0));
        }
        bodies.push(ElasticBody {
            name: name.into(),
            load: vec![0.0; 2 * mesh.num_nodes()],
            mesh,
            material,
            plane: Plane::Strain,
            constraints,
        });
    }
    let model = Model {
        name: "cattaneo-mindlin".into(),
        plane: Plane::Strain,
        bodies,
        pairs: vec![ContactPair {
            name: "contact".into(),
            bodies: [0, 1],
            boundaries: ["top".into(), "bottom".into()],
            penalty: Penalty::Theta(case.theta),
            profile: None,
            enforcement: case.enforcement,
            forces: Forces::Balanced,
            friction: Friction::Coulomb { mu: case.mu },
        }],
        remote: Vec::new(),
    };
    let step = |name: &str, group: usize, increments: usize| HistoryStep {
        name: name.into(),
        factors: vec![(group, 1.0)],
        increments,
    };
    let history = LoadHistory {
        groups: vec![
            LoadGroup {
                name: "press".into(),
                loads: press,
            },
            LoadGroup {
                name: "shear".into(),
                loads: shear,
            },
        ],
        steps: vec![
            step("press", 1, case.press),
            step("shear", 2, case.increments),
        ],
    };
    (model, history)
}
