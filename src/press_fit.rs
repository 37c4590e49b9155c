//! An interference (press) fit built in code: a quarter of a solid shaft of radius
//! [`SHAFT_RADIUS`] pressed into a quarter of a ring of inner radius [`RING_INNER`] and outer
//! radius [`RING_OUTER`], steel, plane strain, symmetry supports on both bodies (u_x = 0 on x = 0,
//! u_y = 0 on y = 0), so that both bodies are fully held and only the interference loads them.
//!
//! The concentric fit has a closed form (Lamé, [`lame_pressure`]): a uniform interface pressure.
//! The meshes are structured polar meshes; their boundaries are `outer` (the shaft's arc),
//! `inner` and `outer` (the ring's arcs), `left` (x = 0) and `bottom` (y = 0).

use std::collections::BTreeMap;
use std::f64::consts::FRAC_PI_2;

use contactdd_core::{
    Component, Constraints, Edge, ElasticBody, Material, Mesh, MeshError, Order, Plane,
};
use contactdd_ddm::{ContactPair, Enforcement, Model, Penalty};

/// The shaft's radius before the fit.
pub const SHAFT_RADIUS: f64 = 1.005;
/// The ring's inner radius before the fit.
pub const RING_INNER: f64 = 1.0;
/// The ring's outer radius.
pub const RING_OUTER: f64 = 2.0;
/// Young's modulus of both bodies (steel, N/mm²).
pub const YOUNG: f64 = 2.0e5;
/// Poisson's ratio of both bodies.
pub const POISSON: f64 = 0.3;

/// The options of [`press_fit`].
#[derive(Clone, Copy, Debug)]
pub struct PressFit {
    /// Cells along the ring's quarter arc.
    pub arcs: usize,
    /// Cells along the shaft's quarter arc (`arcs`: the nodes of the two arcs lie on the same
    /// rays, so the chords of the two polygons are parallel and the gap is the same everywhere;
    /// other counts give non-matching meshes whose chord sags make the gap vary along the arc).
    pub shaft_arcs: usize,
    /// Cells across the ring's thickness and along the shaft's radius.
    pub radial: usize,
    /// Promote both meshes to P2.
    pub p2: bool,
    /// With `p2`: put the mid-side nodes of the arcs on the circles (curved, isoparametric P2
    /// triangles; otherwise they sit on the chords and the arcs are polygons).
    pub curved: bool,
    /// The pair's penalty.
    pub penalty: Penalty,
    /// The pair's enforcement.
    pub enforcement: Enforcement,
    /// Every node of both meshes is shifted by this vector (a near-coincident mesh).
    pub shift: [f64; 2],
    /// The shaft's radius (1.005 the fit; 1.0 with no interference).
    pub shaft_radius: f64,
}

impl Default for PressFit {
    fn default() -> Self {
        PressFit {
            arcs: 32,
            shaft_arcs: 32,
            radial: 8,
            p2: false,
            curved: false,
            penalty: Penalty::RodModel { c: 0.05, h: 1.0 },
            enforcement: Enforcement::Penalty,
            shift: [0.0, 0.0],
            shaft_radius: SHAFT_RADIUS,
        }
    }
}

/// Lamé's interface pressure of a solid shaft in a ring of the same material, plane strain,
/// for a radial interference `delta` at the common radius `b` (ring outer radius `c`):
/// p = E δ / ((1 + ν) b [(1 − 2ν) + ((1 − 2ν) b² + c²)/(c² − b²)]).
pub fn lame_pressure(delta: f64, b: f64, c: f64) -> f64 {
    let (e, nu) = (YOUNG, POISSON);
    let shaft = 1.0 - 2.0 * nu;
    let ring = ((1.0 - 2.0 * nu) * b * b + c * c) / (c * c - b * b);
    e * delta / ((1.0 + nu) * b * (shaft + ring))
}

/// A structured polar mesh of the annular sector r ∈ [r0, r1], φ ∈ [0, π/2] (`r0 = 0`: the quarter
/// disc, whose first ring of cells is a fan around the centre), with `arcs` cells along each arc
/// and `radial` across.
pub fn quarter(r0: f64, r1: f64, arcs: usize, radial: usize) -> Result<Mesh, MeshError> {
    let solid = r0 == 0.0;
    let mut nodes = Vec::new();
    // Node (i, k): radius index i (0 at r0), angle index k; a solid disc has one node at i = 0.
    let index = |i: usize, k: usize| {
        if solid {
            if i == 0 {
                0
            } else {
                1 + (i - 1) * (arcs + 1) + k
            }
        } else {
            i * (arcs + 1) + k
        }
    };
    for i in 0..=radial {
        let r = r0 + (r1 - r0) * i as f64 / radial as f64;
        if solid && i == 0 {
            nodes.push([0.0, 0.0]);
            continue;
        }
        for k in 0..=arcs {
            let phi = FRAC_PI_2 * k as f64 / arcs as f64;
            nodes.push([r * phi.cos(), r * phi.sin()]);
        }
    }
    let mut cells = Vec::new();
    for i in 0..radial {
        for k in 0..arcs {
            if solid && i == 0 {
                cells.extend([0, index(1, k), index(1, k + 1)]);
                continue;
            }
            let (a, b) = (index(i, k), index(i + 1, k));
            let (c, d) = (index(i + 1, k + 1), index(i, k + 1));
            cells.extend([a, b, c, a, c, d]);
        }
    }
    let arc = |i: usize| {
        (0..arcs)
            .map(|k| Edge::new(index(i, k), index(i, k + 1)))
            .collect()
    };
    let line = |k: usize| {
        (0..radial)
            .map(|i| Edge::new(index(i, k), index(i + 1, k)))
            .collect()
    };
    let mut boundaries = BTreeMap::new();
    boundaries.insert("outer".to_string(), arc(radial));
    if !solid {
        boundaries.insert("inner".to_string(), arc(0));
    }
    boundaries.insert("bottom".to_string(), line(0));
    boundaries.insert("left".to_string(), line(arcs));
    Mesh::new(nodes, Order::P1, cells, boundaries, BTreeMap::new())
}

/// One body of the fit: symmetry supports, no load.
fn held(name: &str, mesh: Mesh) -> Result<ElasticBody, String> {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for (boundary, component) in [("left", Component::X), ("bottom", Component::Y)] {
        constraints
            .fix(&mesh, boundary, component, 0.0)
            .map_err(|e| e.to_string())?;
    }
    let load = vec![0.0; 2 * mesh.num_nodes()];
    Ok(ElasticBody {
        name: name.into(),
        mesh,
        material: Material::new(YOUNG, POISSON).map_err(|e| e.to_string())?,
        plane: Plane::Strain,
        constraints,
        load,
    })
}

/// The P2 mesh `mesh` of a polar mesh with the mid-side node of every arc edge (both vertices
/// at the same radius r > 0) moved onto the circle of radius r, at the mean angle of the
/// vertices: curved triangles whose arcs follow the circles to O(h³).
pub fn on_arcs(mesh: &Mesh) -> Result<Mesh, MeshError> {
    let mut nodes = mesh.nodes().to_vec();
    let radius = |p: [f64; 2]| p[0].hypot(p[1]);
    for e in 0..mesh.num_cells() {
        let c = mesh.cell(e);
        for (i, j, m) in contactdd_core::mesh::TRIANGLE_EDGES {
            let (a, b) = (mesh.nodes()[c[i]], mesh.nodes()[c[j]]);
            let r = radius(a);
            if r > 0.0 && (radius(b) - r).abs() <= 1e-12 * r {
                let phi = 0.5 * (a[1].atan2(a[0]) + b[1].atan2(b[0]));
                nodes[c[m]] = [r * phi.cos(), r * phi.sin()];
            }
        }
    }
    mesh.with_nodes(nodes)
}

/// The press fit: body 0 the ring, body 1 the shaft, one pair between the ring's `inner` and the
/// shaft's `outer` arcs.
pub fn press_fit(options: &PressFit) -> Result<Model, String> {
    let finish = |mesh: Mesh| -> Result<Mesh, String> {
        let mesh = match (options.p2, options.curved) {
            (false, _) => mesh,
            (true, false) => mesh.to_p2(),
            (true, true) => on_arcs(&mesh.to_p2()).map_err(|e| e.to_string())?,
        };
        let [dx, dy] = options.shift;
        mesh.map_nodes(|p| [p[0] + dx, p[1] + dy])
            .map_err(|e| e.to_string())
    };
    let (arcs, radial) = (options.arcs, options.radial);
    let ring = quarter(RING_INNER, RING_OUTER, arcs, radial).map_err(|e| e.to_string())?;
    let shaft = quarter(0.0, options.shaft_radius, options.shaft_arcs, radial)
        .map_err(|e| e.to_string())?;
    let bodies = vec![held("ring", finish(ring)?)?, held("shaft", finish(shaft)?)?];
    let pair = ContactPair {
        name: "fit".into(),
        bodies: [0, 1],
        boundaries: ["inner".into(), "outer".into()],
        penalty: options.penalty,
        profile: None,
        enforcement: options.enforcement,
        forces: Default::default(),
        friction: Default::default(),
    };
    Ok(Model {
        name: "press-fit".into(),
        plane: Plane::Strain,
        bodies,
        pairs: vec![pair],
        remote: Vec::new(),
    })
}
