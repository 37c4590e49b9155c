//! `normal` supports on inclined straight boundaries, checked against independent solutions: the
//! same body built axis-aligned (the plain elimination) and rotated, and a dense Lagrange
//! multiplier solve of the constraints u·n = g.

use contactdd_core::post::reaction_on;
use contactdd_core::rigid::{free_modes, free_rigid_modes};
use contactdd_core::{
    dof, Component, Constraints, Diagonal, ElasticBody, Load, Material, Mesh, Order, Plane,
    Rectangle, SupportError, Vector,
};

fn rect(order: Order) -> Mesh {
    Rectangle {
        origin: [0.0, 0.0],
        corner: [2.0, 1.0],
        nx: 8,
        ny: 5,
        diagonal: Diagonal::Right,
        mirror: false,
        order,
    }
    .mesh()
    .unwrap()
}

fn rotation(angle_deg: f64) -> impl Fn(Vector) -> Vector {
    let (s, c) = angle_deg.to_radians().sin_cos();
    move |[x, y]| [c * x - s * y, s * x + c * y]
}

fn body(mesh: Mesh, supports: &[(&str, Component, f64)], loads: &[Load]) -> ElasticBody {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for &(b, c, v) in supports {
        constraints.fix(&mesh, b, c, v).unwrap();
    }
    let load = contactdd_core::loads::load_vector(&mesh, loads).unwrap();
    ElasticBody {
        name: "block".into(),
        mesh,
        material: Material::new(210.0, 0.3).unwrap(),
        plane: Plane::Strain,
        constraints,
        load,
    }
}

fn node(u: &[f64], v: usize) -> Vector {
    [u[dof(v, 0)], u[dof(v, 1)]]
}

fn max_abs(u: &[f64]) -> f64 {
    u.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The block of [0, 2] × [0, 1] on a sliding floor (bottom) against a symmetry line (left), with
/// prescribed normal displacements, a traction and a body force; rotated by `angle` degrees.
/// The prescribed values are given in the outward-normal convention of inclined supports; on the
/// axis-parallel lines the value is u_x (left) and u_y (bottom), whose outward normals are −x and
/// −y, hence the sign flips.
fn sliding_block(order: Order, angle: f64) -> ElasticBody {
    let rot = rotation(angle);
    let (g_left, g_bottom) = (2e-3, -1e-3);
    let mesh = rect(order).map_nodes(&rot).unwrap();
    let sign = if angle == 0.0 { -1.0 } else { 1.0 };
    body(
        mesh,
        &[
            ("left", Component::Normal, sign * g_left),
            ("bottom", Component::Normal, sign * g_bottom),
        ],
        &[
            Load::Traction {
                boundary: "right".into(),
                value: rot([-3.0, 1.5]),
            },
            Load::Pressure {
                boundary: "top".into(),
                value: 2.0,
            },
            Load::BodyForce {
                value: rot([0.5, -1.0]),
            },
        ],
    )
}

#[test]
fn a_rotated_body_gives_the_rotated_displacements_and_reactions() {
    for order in [Order::P1, Order::P2] {
        let plain = sliding_block(order, 0.0);
        assert_eq!(plain.constraints.inclined().count(), 0);
        let reference = plain.solve().unwrap();
        let scale = max_abs(&reference.displacement);
        for angle in [30.0, 117.0] {
            let turned = sliding_block(order, angle);
            assert!(turned.constraints.inclined().count() > 0);
            let solution = turned.solve().unwrap();
            let rot = rotation(angle);
            let mut worst = 0.0f64;
            for v in 0..plain.mesh.num_nodes() {
                let expect = rot(node(&reference.displacement, v));
                let got = node(&solution.displacement, v);
                worst = worst.max(
                    (0..2)
                        .map(|c| (got[c] - expect[c]).abs())
                        .fold(0.0, f64::max),
                );
            }
            println!(
                "{order:?} {angle}°: displacement difference {:.2e}",
                worst / scale
            );
            assert!(worst < 1e-10 * scale, "{order:?} {angle}°: {worst}");
            for name in ["left", "bottom"] {
                let r0 = reaction_on(&plain.mesh, name, &reference.residual).unwrap();
                let r = reaction_on(&turned.mesh, name, &solution.residual).unwrap();
                let expect = rot(r0);
                let size = r0[0].hypot(r0[1]);
                let diff = (r[0] - expect[0]).hypot(r[1] - expect[1]);
                println!(
                    "{order:?} {angle}°: reaction on {name} {r:?}, difference {:.2e}",
                    diff / size
                );
                assert!(
                    diff < 1e-9 * size,
                    "{order:?} {angle}° {name}: {r:?} vs {expect:?}"
                );
            }
        }
    }
}

#[test]
fn an_inclined_sliding_support_has_no_tangential_reaction_and_balances_the_load() {
    let body = sliding_block(Order::P2, 30.0);
    let solution = body.solve().unwrap();
    let rot = rotation(30.0);
    let applied: Vec<f64> = (0..2)
        .map(|c| {
            (0..body.mesh.num_nodes())
                .map(|v| body.load[dof(v, c)])
                .sum()
        })
        .collect();
    let size = applied[0].hypot(applied[1]);
    // Every node of a support but the corner (on both, so fixed): the tangential part of its
    // reaction vanishes.
    for (name, tangent) in [("left", rot([0.0, 1.0])), ("bottom", rot([1.0, 0.0]))] {
        for v in body.mesh.boundary_nodes(name).unwrap() {
            if body.constraints.inclined_normal(v).is_none() {
                assert_eq!(v, 0, "only the corner is fixed");
                continue;
            }
            let r = node(&solution.residual, v);
            let t = r[0] * tangent[0] + r[1] * tangent[1];
            assert!(
                t.abs() < 1e-10 * size,
                "{name} node {v}: tangential reaction {t}"
            );
        }
    }
    // The corner node is on both supports: count it once.
    let total: Vec<f64> = (0..2)
        .map(|c| {
            (0..body.mesh.num_nodes())
                .filter(|&v| body.constraints.holds(dof(v, c)))
                .map(|v| solution.residual[dof(v, c)])
                .sum()
        })
        .collect();
    let balance = (total[0] + applied[0]).hypot(total[1] + applied[1]);
    println!(
        "reactions {total:?}, load {applied:?}, imbalance {:.2e}",
        balance / size
    );
    assert!(balance < 1e-10 * size);
    // Off the supports the residual is round-off.
    let free_residual = (0..body.load.len())
        .filter(|&d| !body.constraints.holds(d))
        .map(|d| solution.residual[d].abs())
        .fold(0.0, f64::max);
    assert!(free_residual < 1e-10 * size);
}

/// Solves K u = f subject to u·n_v = g_v on the inclined nodes and the x/y prescriptions with
/// dense Lagrange multipliers (nalgebra's LU): an elimination-free reference.
fn lagrange_reference(body: &ElasticBody) -> Vec<f64> {
    let k = body.stiffness();
    let n = k.ncols();
    let rows: Vec<(Vec<(usize, f64)>, f64)> = body
        .constraints
        .fixed()
        .map(|(d, g)| (vec![(d, 1.0)], g))
        .chain(
            body.constraints
                .inclined()
                .map(|(v, nrm, g)| (vec![(dof(v, 0), nrm[0]), (dof(v, 1), nrm[1])], g)),
        )
        .collect();
    let m = rows.len();
    let mut a = nalgebra::DMatrix::<f64>::zeros(n + m, n + m);
    let mut b = nalgebra::DVector::<f64>::zeros(n + m);
    let (cp, ri, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            a[(ri[p], j)] += val[p];
        }
        b[j] = body.load[j];
    }
    for (i, (terms, g)) in rows.iter().enumerate() {
        for &(d, c) in terms {
            a[(n + i, d)] = c;
            a[(d, n + i)] = c;
        }
        b[n + i] = *g;
    }
    let x = a.lu().solve(&b).unwrap();
    x.iter().take(n).copied().collect()
}

#[test]
fn inclined_supports_match_a_lagrange_multiplier_solve() {
    // A parallelogram turned by 30°: its left and bottom sides are inclined and not
    // perpendicular; the top right corner is pulled.
    let rot = rotation(30.0);
    let mesh = rect(Order::P2)
        .map_nodes(|[x, y]| rot([x + 0.6 * y, y]))
        .unwrap();
    let body = body(
        mesh,
        &[
            ("left", Component::Normal, 1e-3),
            ("bottom", Component::Normal, -2e-3),
            ("right", Component::X, 4e-3),
        ],
        &[Load::Traction {
            boundary: "top".into(),
            value: [1.0, 2.0],
        }],
    );
    let u = body.solve().unwrap().displacement;
    let reference = lagrange_reference(&body);
    let diff = u
        .iter()
        .zip(&reference)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!(
        "Lagrange reference: difference {:.2e}",
        diff / max_abs(&reference)
    );
    assert!(diff < 1e-10 * max_abs(&reference));
    // The prescriptions hold: u·n = g on every inclined node (outward normal convention).
    for (v, n, g) in body.constraints.inclined() {
        let un = n[0] * u[dof(v, 0)] + n[1] * u[dof(v, 1)];
        assert!((un - g).abs() < 1e-14, "node {v}: u·n = {un}, g = {g}");
    }
}

#[test]
fn the_normal_of_an_inclined_support_is_outward() {
    let rot = rotation(30.0);
    let mesh = rect(Order::P1).map_nodes(&rot).unwrap();
    let mut c = Constraints::new(mesh.num_nodes());
    c.fix(&mesh, "left", Component::Normal, 0.5).unwrap();
    let outward = rot([-1.0, 0.0]);
    // The corners shared with top and bottom are there too.
    assert_eq!(c.inclined().count(), 6);
    for (_, n, g) in c.inclined() {
        assert!((n[0] - outward[0]).abs() < 1e-15 && (n[1] - outward[1]).abs() < 1e-15);
        assert_eq!(g, 0.5);
    }
}

#[test]
fn a_corner_of_an_inclined_and_an_axis_support_is_fixed_where_both_hold() {
    let rot = rotation(30.0);
    let mesh = rect(Order::P1).map_nodes(&rot).unwrap();
    let corner = 0; // the origin: on "left" and "bottom"
    assert_eq!(mesh.nodes()[corner], [0.0, 0.0]);
    let n = rot([-1.0, 0.0]);
    for order in [[0, 1], [1, 0]] {
        let mut c = Constraints::new(mesh.num_nodes());
        for step in order {
            match step {
                0 => c.fix(&mesh, "left", Component::Normal, 0.2).unwrap(),
                _ => c.fix(&mesh, "bottom", Component::X, 0.1).unwrap(),
            }
        }
        assert!(c.inclined_normal(corner).is_none());
        let (ux, uy) = (
            c.get(dof(corner, 0)).unwrap(),
            c.get(dof(corner, 1)).unwrap(),
        );
        assert_eq!(ux, 0.1);
        assert!((n[0] * ux + n[1] * uy - 0.2).abs() < 1e-15);
        // A later `both` replaces the inclined direction; a later normal replaces x.
        c.fix(&mesh, "bottom", Component::Both, 0.0).unwrap();
        assert_eq!(
            (c.get(dof(corner, 0)), c.get(dof(corner, 1))),
            (Some(0.0), Some(0.0))
        );
    }
}

#[test]
fn kinked_curved_and_node_set_boundaries_are_refused() {
    let mesh = rect(Order::P1).map_nodes(rotation(30.0)).unwrap();
    let mut boundaries = mesh.boundaries().clone();
    let mut kinked = boundaries["left"].clone();
    kinked.extend_from_slice(&boundaries["bottom"]);
    boundaries.insert("corner".into(), kinked);
    let mut sets = mesh.node_sets().clone();
    sets.insert("points".into(), vec![0, 1]);
    let mesh = Mesh::new(
        mesh.nodes().to_vec(),
        mesh.order(),
        mesh.cells().to_vec(),
        boundaries,
        sets,
    )
    .unwrap();
    let mut c = Constraints::new(mesh.num_nodes());
    let err = c.fix(&mesh, "corner", Component::Normal, 0.0).unwrap_err();
    assert_eq!(
        err,
        SupportError::NotStraight {
            boundary: "corner".into()
        }
    );
    assert!(err.to_string().contains("'corner'"), "{err}");
    let err = c.fix(&mesh, "points", Component::Normal, 0.0).unwrap_err();
    assert!(matches!(err, SupportError::NormalOnNodeSet { .. }), "{err}");
    // A curved boundary: the rectangle's top bent into an arc.
    let bent = rect(Order::P1)
        .map_nodes(|[x, y]| [x, y * (1.0 + 0.1 * x * (2.0 - x))])
        .unwrap();
    let mut c = Constraints::new(bent.num_nodes());
    let err = c.fix(&bent, "top", Component::Normal, 0.0).unwrap_err();
    assert_eq!(
        err,
        SupportError::NotStraight {
            boundary: "top".into()
        }
    );
    assert!(c.fix(&bent, "bottom", Component::Normal, 0.0).is_ok());
}

#[test]
fn inclined_normal_supports_remove_the_motion_along_their_normal() {
    let rot = rotation(30.0);
    let sheared = rect(Order::P1)
        .map_nodes(|[x, y]| rot([x + 0.6 * y, y]))
        .unwrap();
    let modes = |supports: &[&str]| {
        let mut c = Constraints::new(sheared.num_nodes());
        for s in supports {
            c.fix(&sheared, s, Component::Normal, 0.0).unwrap();
        }
        free_modes(&sheared, &c, &[])
    };
    // One line: only the translation along it is left; its direction is the line's.
    let one = modes(&["bottom"]);
    assert_eq!(one.len(), 1);
    let basis = contactdd_core::RigidBasis::new(&sheared);
    let t = rot([1.0, 0.0]);
    for &x in sheared.nodes() {
        let u = basis.motion(x, &one[0]);
        assert!(
            (u[0] * t[1] - u[1] * t[0]).abs() < 1e-12,
            "{u:?} not along {t:?}"
        );
    }
    // Two parallel lines still leave it; two lines at different angles hold the body.
    assert_eq!(modes(&["bottom", "top"]).len(), 1);
    assert!(modes(&["bottom", "left"]).is_empty());
    let mut c = Constraints::new(sheared.num_nodes());
    c.fix(&sheared, "left", Component::Normal, 0.0).unwrap();
    c.fix(&sheared, "right", Component::Normal, 0.0).unwrap();
    assert_eq!(free_rigid_modes(&sheared, &c, &[]).len(), 1);
}
