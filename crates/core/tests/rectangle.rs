//! Graded and x-mirrored rectangle meshes: node positions follow the documented geometric
//! progression, mirroring is a reflection, and a graded mesh solves a uniform stress state exactly.

use contactdd_core::loads::load_vector;
use contactdd_core::{
    Component, Constraints, Diagonal, ElasticBody, Layout, Load, Material, Mesh, Order, Plane,
    Rectangle,
};

fn block(nx: usize, ny: usize, order: Order) -> Rectangle {
    Rectangle {
        origin: [1.0, -1.0],
        corner: [3.0, 0.5],
        nx,
        ny,
        diagonal: Diagonal::Alternate,
        mirror: false,
        order,
    }
}

fn layout(gx: f64, gy: f64, mirror_x: bool) -> Layout {
    Layout {
        grading: [gx, gy],
        mirror_x,
    }
}

/// The documented positions along one axis: sizes h, h q, h q², ... with q = g^(1/(n−1)).
fn documented(lo: f64, hi: f64, n: usize, g: f64) -> Vec<f64> {
    let q = g.powf(1.0 / (n - 1) as f64);
    let sizes: Vec<f64> = (0..n).map(|k| q.powi(k as i32)).collect();
    let total: f64 = sizes.iter().sum();
    let mut out = vec![lo];
    let mut x = lo;
    for h in sizes {
        x += (hi - lo) * h / total;
        out.push(x);
    }
    out
}

/// Sorted distinct values of coordinate `c` of the nodes.
fn distinct(mesh: &Mesh, c: usize) -> Vec<f64> {
    let mut v: Vec<f64> = mesh.nodes().iter().map(|p| p[c]).collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    v
}

#[test]
fn graded_nodes_follow_the_documented_progression() {
    let (nx, ny, gx, gy) = (6, 4, 3.0, 0.4);
    let mesh = block(nx, ny, Order::P1)
        .mesh_with(&layout(gx, gy, false))
        .expect("graded mesh");
    for (c, lo, hi, n, g) in [(0, 1.0, 3.0, nx, gx), (1, -1.0, 0.5, ny, gy)] {
        let got = distinct(&mesh, c);
        let want = documented(lo, hi, n, g);
        assert_eq!(got.len(), want.len());
        for (a, b) in got.iter().zip(&want) {
            assert!((a - b).abs() < 1e-12, "axis {c}: {got:?} vs {want:?}");
        }
        // The last cell is g times the first.
        let ratio = (got[n] - got[n - 1]) / (got[1] - got[0]);
        assert!((ratio - g).abs() < 1e-10 * g, "axis {c}: ratio {ratio}");
    }
    // Grading 1 is the uniform mesh, to the last bit.
    let uniform = block(nx, ny, Order::P1).mesh().expect("uniform");
    let same = block(nx, ny, Order::P1)
        .mesh_with(&layout(1.0, 1.0, false))
        .expect("grading 1");
    assert_eq!(uniform.nodes(), same.nodes());
}

#[test]
fn mirroring_in_x_is_the_reflection_with_left_and_right_swapped() {
    let plain = block(5, 3, Order::P2)
        .mesh_with(&layout(2.5, 1.0, false))
        .expect("plain");
    let mirrored = block(5, 3, Order::P2)
        .mesh_with(&layout(2.5, 1.0, true))
        .expect("mirrored");
    // The vertices come first, in grid order (the mid-side nodes follow in triangle order).
    let vertices = 6 * 4;
    for (p, q) in plain.nodes().iter().zip(mirrored.nodes()).take(vertices) {
        assert!((p[0] - (4.0 - q[0])).abs() < 1e-12 && p[1] == q[1]);
    }
    // The fine cells are now at x = 3, and every side keeps its outward normal.
    let xs = distinct(&mirrored, 0);
    assert!(xs[xs.len() - 1] - xs[xs.len() - 3] < xs[2] - xs[0]);
    for (name, x, normal) in [("left", 1.0, [-1.0, 0.0]), ("right", 3.0, [1.0, 0.0])] {
        for edge in mirrored.boundary(name).expect("side") {
            for v in edge.nodes() {
                assert!((mirrored.nodes()[v][0] - x).abs() < 1e-12, "{name}");
            }
            let (n, _) = mirrored.edge_normal(edge);
            assert!(
                (n[0] - normal[0]).abs() < 1e-14 && n[1].abs() < 1e-14,
                "{name}"
            );
        }
    }
}

#[test]
fn bad_grading_is_an_error() {
    for g in [0.0, -2.0, f64::NAN, f64::INFINITY] {
        let result = block(3, 3, Order::P1).mesh_with(&layout(g, 1.0, false));
        assert!(result.is_err(), "grading {g} accepted");
    }
}

/// A block held by rollers on `left` (u_x = 0) and `bottom` (u_y = 0) under a traction tx on
/// `right` and a pressure p on `top` has the uniform stress σxx = tx, σyy = −p, σxy = 0 and the
/// linear displacement of Hooke's law: the finite element solution is exact on any mesh.
#[test]
fn graded_and_mirrored_meshes_solve_uniform_stress_exactly() {
    let material = Material::new(1000.0, 0.3).expect("material");
    let (tx, p) = (4.0, 7.0);
    let (e, nu) = (1000.0, 0.3);
    // Plane strain compliance.
    let exx = ((1.0 - nu * nu) * tx + nu * (1.0 + nu) * p) / e;
    let eyy = (-(1.0 - nu * nu) * p - nu * (1.0 + nu) * tx) / e;
    for order in [Order::P1, Order::P2] {
        for mirror_x in [false, true] {
            let mesh = block(5, 4, order)
                .mesh_with(&layout(4.0, 0.3, mirror_x))
                .expect("mesh");
            let mut constraints = Constraints::new(mesh.num_nodes());
            constraints
                .fix(&mesh, "left", Component::X, 0.0)
                .expect("left");
            constraints
                .fix(&mesh, "bottom", Component::Y, 0.0)
                .expect("bottom");
            let loads = [
                Load::Pressure {
                    boundary: "top".into(),
                    value: p,
                },
                Load::Traction {
                    boundary: "right".into(),
                    value: [tx, 0.0],
                },
            ];
            let load = load_vector(&mesh, &loads).expect("loads");
            let body = ElasticBody {
                name: "block".into(),
                mesh,
                material,
                plane: Plane::Strain,
                constraints,
                load,
            };
            let u = body.solve().expect("solved").displacement;
            let mut worst: f64 = 0.0;
            for (v, q) in body.mesh.nodes().iter().enumerate() {
                let exact = [exx * (q[0] - 1.0), eyy * (q[1] + 1.0)];
                worst = worst
                    .max((u[2 * v] - exact[0]).abs())
                    .max((u[2 * v + 1] - exact[1]).abs());
            }
            let scale = exx.abs().max(eyy.abs());
            assert!(
                worst < 1e-10 * scale,
                "{order:?}, mirror_x {mirror_x}: error {worst:e}"
            );
        }
    }
}
