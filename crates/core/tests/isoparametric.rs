//! Curved (isoparametric) P2 triangles: the patch test, areas and a thick ring under pressure
//! (Lamé) against closed forms, converging faster than straight P2 on the same nodes, consistent
//! pressure loads on a curved edge, and `normal` supports refused on curved edges.

use std::collections::{BTreeMap, HashMap};
use std::f64::consts::FRAC_PI_2;

use contactdd_core::assembly::{add_edge_traction, add_pressure, affine, Pattern};
use contactdd_core::element::{self, Geometry};
use contactdd_core::{
    Component, Constraints, Diagonal, Edge, ElasticBody, Material, Mesh, Order, Plane, Rectangle,
    SupportError,
};

fn steel() -> Material {
    Material::new(200.0, 0.3).unwrap()
}

/// A quarter annulus `r0 ≤ r ≤ r1`, `0 ≤ φ ≤ π/2` (a quarter disc if `r0 = 0`) of P2 triangles on
/// an `nr × nphi` polar grid. With `curved`, every node sits at its polar position, so a mid-side
/// node lies at the polar mean `(r̄, φ̄)` of its edge (on the circle along the arcs); without, at the
/// midpoint of its edge's chord. Boundaries: `inner` (r = r0 > 0), `outer`, `x-axis`, `y-axis`.
fn quarter_ring(r0: f64, r1: f64, nr: usize, nphi: usize, curved: bool) -> Mesh {
    let disc = r0 == 0.0;
    let (dr, dphi) = ((r1 - r0) / nr as f64, FRAC_PI_2 / nphi as f64);
    let polar = |(a, b): (usize, usize)| {
        let (r, phi) = (r0 + 0.5 * dr * a as f64, 0.5 * dphi * b as f64);
        [r * phi.cos(), r * phi.sin()]
    };
    let mut index: HashMap<(usize, usize), usize> = HashMap::new();
    let mut nodes = Vec::new();
    // Node of fine-grid position (a, b) (vertices at even a and b); `ends` are the vertices of
    // the edge a mid-side node belongs to.
    let mut node = |g: (usize, usize), ends: Option<[(usize, usize); 2]>| {
        let g = if disc && g.0 == 0 { (0, 0) } else { g };
        *index.entry(g).or_insert_with(|| {
            let x = match ends {
                Some([p, q]) if !curved => {
                    let (p, q) = (polar(p), polar(q));
                    [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]
                }
                _ => polar(g),
            };
            nodes.push(x);
            nodes.len() - 1
        })
    };
    let mut cells = Vec::new();
    let mut tri = |v: [(usize, usize); 3], cells: &mut Vec<usize>| {
        // On an edge from the centre of a disc, the mid-side node is on the other end's ray.
        let mid = |p: (usize, usize), q: (usize, usize)| match (p.0, q.0) {
            (0, _) if disc => (q.0 / 2, q.1),
            (_, 0) if disc => (p.0 / 2, p.1),
            _ => ((p.0 + q.0) / 2, (p.1 + q.1) / 2),
        };
        let ids = [
            node(v[0], None),
            node(v[1], None),
            node(v[2], None),
            node(mid(v[0], v[1]), Some([v[0], v[1]])),
            node(mid(v[1], v[2]), Some([v[1], v[2]])),
            node(mid(v[2], v[0]), Some([v[2], v[0]])),
        ];
        cells.extend(ids);
        ids
    };
    let mut boundaries: BTreeMap<String, Vec<Edge>> = BTreeMap::new();
    let mut add = |name: &str, ids: [usize; 6], (i, j, m): (usize, usize, usize)| {
        let edge = Edge {
            a: ids[i],
            b: ids[j],
            mid: Some(ids[m]),
        };
        boundaries.entry(name.to_string()).or_default().push(edge);
    };
    for i in 0..nr {
        for j in 0..nphi {
            let (a, b) = (2 * i, 2 * j);
            let t1 = tri([(a, b), (a + 2, b), (a + 2, b + 2)], &mut cells);
            if j == 0 {
                add("x-axis", t1, (0, 1, 3));
            }
            if i + 1 == nr {
                add("outer", t1, (1, 2, 4));
            }
            if disc && i == 0 {
                if j + 1 == nphi {
                    add("y-axis", t1, (2, 0, 5));
                }
                continue;
            }
            let t2 = tri([(a, b), (a + 2, b + 2), (a, b + 2)], &mut cells);
            if j + 1 == nphi {
                add("y-axis", t2, (1, 2, 4));
            }
            if i == 0 {
                add("inner", t2, (2, 0, 5));
            }
        }
    }
    Mesh::new(nodes, Order::P2, cells, boundaries, BTreeMap::new()).unwrap()
}

/// The unit square of P2 triangles (4 × 4) with its interior mid-side nodes moved off their
/// midpoints, and the mid-side nodes of the bottom side slid along it (a curved parametrisation
/// of a straight side).
fn curved_square() -> Mesh {
    let n = 4;
    let base = Rectangle {
        origin: [0.0, 0.0],
        corner: [1.0, 1.0],
        nx: n,
        ny: n,
        diagonal: Diagonal::Alternate,
        mirror: false,
        order: Order::P2,
    }
    .mesh()
    .unwrap();
    let h = 1.0 / n as f64;
    let mut is_mid = vec![false; base.num_nodes()];
    for e in 0..base.num_cells() {
        for &v in &base.cell(e)[3..] {
            is_mid[v] = true;
        }
    }
    let nodes: Vec<[f64; 2]> = base
        .nodes()
        .iter()
        .zip(&is_mid)
        .map(|(&[x, y], &mid)| {
            let inside = x > 1e-12 && x < 1.0 - 1e-12 && y > 1e-12 && y < 1.0 - 1e-12;
            match (mid, inside) {
                (true, true) => [
                    x + 0.12 * h * (7.0 * x + 3.0 * y).sin(),
                    y + 0.12 * h * (5.0 * x * y + 2.0 * x).cos(),
                ],
                (true, false) if y < 1e-12 => [x + 0.1 * h, y],
                _ => [x, y],
            }
        })
        .collect();
    let mesh = base.with_nodes(nodes).unwrap();
    assert!(mesh.is_curved());
    mesh
}

/// `K r` over `|K| |r|` for the displacement field `f` at the nodes.
fn relative_kr(mesh: &Mesh, f: impl Fn([f64; 2]) -> [f64; 2]) -> f64 {
    let k = Pattern::new(mesh).stiffness(mesh, &steel().elasticity(Plane::Strain));
    let r: Vec<f64> = mesh.nodes().iter().flat_map(|&p| f(p)).collect();
    let (col_ptr, row_idx, val) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    let mut kr = vec![0.0; r.len()];
    let mut size = 0.0f64;
    for (j, &rj) in r.iter().enumerate() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            kr[row_idx[p]] += val[p] * rj;
            size = size.max((val[p] * rj).abs());
        }
    }
    kr.iter().fold(0.0f64, |m, v| m.max(v.abs())) / size
}

#[test]
fn curved_patch_reproduces_a_linear_field_and_rigid_motions_cost_nothing() {
    let mesh = curved_square();
    let linear = |[x, y]: [f64; 2]| [0.01 + 0.02 * x - 0.03 * y, -0.02 + 0.015 * x + 0.04 * y];
    let mut constraints = Constraints::new(mesh.num_nodes());
    for name in ["left", "right", "bottom", "top"] {
        for v in mesh.boundary_nodes(name).unwrap() {
            let u = linear(mesh.nodes()[v]);
            for (c, uc) in u.into_iter().enumerate() {
                constraints.set(2 * v + c, Some(uc));
            }
        }
    }
    let body = ElasticBody {
        name: "patch".into(),
        load: vec![0.0; 2 * mesh.num_nodes()],
        mesh,
        material: steel(),
        plane: Plane::Strain,
        constraints,
    };
    let solution = body.solve().unwrap();
    for (v, &p) in body.mesh.nodes().iter().enumerate() {
        let u = linear(p);
        for c in 0..2 {
            let err = (solution.displacement[2 * v + c] - u[c]).abs();
            assert!(err < 1e-13, "node {v} component {c}: error {err}");
        }
    }
    // The strain is the field's everywhere, inside every curved triangle too.
    let (mesh, u) = (&body.mesh, &solution.displacement);
    let mut seen_off = 0;
    for e in (0..mesh.num_cells()).filter(|&e| mesh.is_curved_cell(e)) {
        let geo = Geometry::of_cell(mesh, e);
        let ue: Vec<[f64; 2]> = mesh
            .cell(e)
            .iter()
            .map(|&v| [u[2 * v], u[2 * v + 1]])
            .collect();
        for l in element::TRIANGLE_DEGREE_5.points {
            let eps = geo.strain(Order::P2, *l, &ue);
            for (got, want) in eps.iter().zip([0.02, 0.04, -0.03 + 0.015]) {
                assert!((got - want).abs() < 1e-13, "cell {e}: ε = {eps:?}");
            }
        }
        // Mapped straight (affinely) the same nodal values give another strain: the test sees
        // which geometry is used.
        let straight = element::strain(Order::P2, &affine(mesh, mesh.cell(e)), [1.0 / 3.0; 3], &ue);
        let off = (straight[0] - 0.02).abs() + (straight[1] - 0.04).abs();
        seen_off += usize::from(off > 1e-4);
    }
    assert!(
        seen_off > 10,
        "{seen_off} curved cells differ when mapped affinely"
    );
    for mode in [
        |_: [f64; 2]| [1.0, 0.0],
        |_: [f64; 2]| [0.0, 1.0],
        |[x, y]: [f64; 2]| [-y, x],
    ] {
        let kr = relative_kr(mesh, mode);
        assert!(kr < 1e-14, "K r / |K||r| = {kr}");
    }
    // A non-rigid field (a shear) costs something: the check can fail.
    assert!(relative_kr(mesh, |[_, y]| [y, 0.0]) > 1e-3);
}

#[test]
fn a_curved_element_matches_the_affine_one_when_its_nodes_are_straight() {
    // Two nodes of the isoparametric map at their midpoints: the same triangle, both paths.
    let v = [[0.1, 0.2], [1.3, 0.4], [0.5, 1.1]];
    let mid = |i: usize, j: usize| [0.5 * (v[i][0] + v[j][0]), 0.5 * (v[i][1] + v[j][1])];
    let iso = element::Isoparametric::new([v[0], v[1], v[2], mid(0, 1), mid(1, 2), mid(2, 0)]);
    let aff = element::Affine::new(v);
    let d = steel().elasticity(Plane::Strain);
    let (ki, ka) = (iso.stiffness(&d), element::stiffness(Order::P2, &aff, &d));
    let scale = (0..12).map(|i| ka[i][i]).fold(0.0, f64::max);
    for i in 0..12 {
        for j in 0..12 {
            assert!((ki[i][j] - ka[i][j]).abs() < 1e-13 * scale, "K[{i}][{j}]");
        }
    }
    assert!((iso.area() - aff.area).abs() < 1e-15);
    for l in element::TRIANGLE_DEGREE_5.points {
        let (gi, ga) = (iso.grad(*l), aff.grad(Order::P2, *l));
        for (a, b) in gi.iter().zip(&ga) {
            assert!((a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-13);
        }
        let (pi, pa) = (iso.point(*l), aff.point(*l));
        assert!((pi[0] - pa[0]).abs() + (pi[1] - pa[1]).abs() < 1e-15);
    }
}

/// Convergence rates of successive errors on meshes of `sizes` cells per side.
fn rates(sizes: &[usize], errors: &[f64]) -> Vec<f64> {
    let n: Vec<f64> = sizes.iter().map(|&n| n as f64).collect();
    (1..errors.len())
        .map(|i| (errors[i - 1] / errors[i]).ln() / (n[i] / n[i - 1]).ln())
        .collect()
}

/// Errors in scientific notation, for the printed summaries.
fn sci(errors: &[f64]) -> String {
    let e: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
    e.join(", ")
}

fn area(mesh: &Mesh) -> f64 {
    (0..mesh.num_cells())
        .map(|e| Geometry::of_cell(mesh, e).area())
        .sum()
}

#[test]
fn the_area_of_a_curved_quarter_disc_converges_at_fourth_order() {
    let exact = std::f64::consts::PI / 4.0;
    let (mut curved, mut straight) = (Vec::new(), Vec::new());
    for n in [2, 4, 8] {
        let c = quarter_ring(0.0, 1.0, n, n, true);
        let s = quarter_ring(0.0, 1.0, n, n, false);
        assert!(c.is_curved() && !s.is_curved());
        curved.push((area(&c) - exact).abs());
        straight.push((area(&s) - exact).abs());
    }
    let (rc, rs) = (rates(&[2, 4, 8], &curved), rates(&[2, 4, 8], &straight));
    println!(
        "area errors: curved {} rates {rc:.2?}; straight {} rates {rs:.2?}",
        sci(&curved),
        sci(&straight)
    );
    assert!(
        rc.iter().all(|&r| r > 3.8),
        "curved {curved:?}, rates {rc:?}"
    );
    assert!(
        rs.iter().all(|&r| (r - 2.0).abs() < 0.1),
        "straight {straight:?}, rates {rs:?}"
    );
    assert!(
        curved[2] < 1e-5 && straight[2] > 1e-3,
        "{curved:?} {straight:?}"
    );
}

/// The largest relative error of the radial displacement on the inner circle of a thick ring
/// (1 ≤ r ≤ 2, plane strain) under internal pressure, against Lamé's solution.
fn lame_error(nr: usize, curved: bool) -> f64 {
    let (r0, r1, p) = (1.0, 2.0, 1.0);
    let material = steel();
    let mesh = quarter_ring(r0, r1, nr, 2 * nr, curved);
    let mut constraints = Constraints::new(mesh.num_nodes());
    constraints
        .fix(&mesh, "x-axis", Component::Normal, 0.0)
        .unwrap();
    constraints
        .fix(&mesh, "y-axis", Component::Normal, 0.0)
        .unwrap();
    let mut load = vec![0.0; 2 * mesh.num_nodes()];
    add_pressure(&mesh, mesh.boundary("inner").unwrap(), p, &mut load);
    let inner = mesh.boundary_nodes("inner").unwrap();
    let body = ElasticBody {
        name: "ring".into(),
        mesh,
        material,
        plane: Plane::Strain,
        constraints,
        load,
    };
    let u = body.solve().unwrap().displacement;
    let (e, nu) = (material.young(), material.poisson());
    let exact = |r: f64| {
        (1.0 + nu) / e * p * r0 * r0 / (r1 * r1 - r0 * r0) * ((1.0 - 2.0 * nu) * r + r1 * r1 / r)
    };
    inner
        .iter()
        .map(|&v| {
            let [x, y] = body.mesh.nodes()[v];
            let r = x.hypot(y);
            let ur = (u[2 * v] * x + u[2 * v + 1] * y) / r;
            (ur / exact(r) - 1.0).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_curved_ring_under_pressure_converges_to_lame_faster_than_a_straight_one() {
    // P2 displacements converge at O(h³) at best; chords in place of the circles cost O(h²).
    let sizes = [6, 12, 24];
    let curved: Vec<f64> = sizes.iter().map(|&n| lame_error(n, true)).collect();
    let straight: Vec<f64> = sizes.iter().map(|&n| lame_error(n, false)).collect();
    let (rc, rs) = (rates(&sizes, &curved), rates(&sizes, &straight));
    println!(
        "Lamé u_r errors: curved {} rates {rc:.2?}; straight {} rates {rs:.2?}",
        sci(&curved),
        sci(&straight)
    );
    assert!(
        rs.iter().all(|&r| (r - 2.0).abs() < 0.2),
        "straight {straight:?}, rates {rs:?}"
    );
    assert!(
        rc.iter().all(|&r| r > 2.5),
        "curved {curved:?}, rates {rc:?}"
    );
    assert!(curved[2] < 1e-5, "curved {curved:?}");
    assert!(straight[2] > 20.0 * curved[2], "{straight:?} {curved:?}");
}

#[test]
fn pressure_on_a_curved_edge_gives_the_arc_resultant_and_the_consistent_nodal_forces() {
    let (p, r0) = (3.0, 1.0);
    let mesh = quarter_ring(r0, 2.0, 2, 3, true);
    let inner = mesh.boundary("inner").unwrap();
    assert!(inner.iter().all(|e| mesh.is_curved_edge(e)));
    let mut f = vec![0.0; 2 * mesh.num_nodes()];
    add_pressure(&mesh, inner, p, &mut f);
    // The whole arc, from (0, 1) to (1, 0) with the body on the left: the resultant of a pressure
    // is p times the chord turned, pushing the ring outwards, towards (1, 1).
    let total = f
        .chunks(2)
        .fold([0.0, 0.0], |s, v| [s[0] + v[0], s[1] + v[1]]);
    for (got, want) in total.iter().zip([p * r0, p * r0]) {
        assert!((got - want).abs() < 1e-14, "resultant {total:?}");
    }
    // Edge by edge: ∫ N_i (−p) n |x'| dt with n |x'| = x' turned clockwise, a cubic in t that
    // Simpson's rule integrates exactly.
    let nodes = mesh.nodes();
    for edge in inner {
        let mut fe = vec![0.0; 2 * mesh.num_nodes()];
        add_pressure(&mesh, std::slice::from_ref(edge), p, &mut fe);
        let m = edge.mid.unwrap();
        let (a, b, c) = (nodes[edge.a], nodes[edge.b], nodes[m]);
        let dx = |t: f64| -> [f64; 2] {
            std::array::from_fn(|k| {
                (4.0 * t - 3.0) * a[k] + (4.0 * t - 1.0) * b[k] + (4.0 - 8.0 * t) * c[k]
            })
        };
        for (i, v) in [edge.a, edge.b, m].into_iter().enumerate() {
            let g = |t: f64| {
                let n = element::edge_shape(Order::P2, t)[i];
                let d = dx(t);
                [-p * n * d[1], p * n * d[0]]
            };
            let (g0, g1, g2) = (g(0.0), g(0.5), g(1.0));
            for k in 0..2 {
                let want = (g0[k] + 4.0 * g1[k] + g2[k]) / 6.0;
                let got = fe[2 * v + k];
                assert!((got - want).abs() < 1e-14, "node {v}: {got} vs {want}");
            }
        }
    }
    // A uniform traction vector carries the parabola's length: against a fine Simpson sum.
    let edge = inner[0];
    let mut ft = vec![0.0; 2 * mesh.num_nodes()];
    add_edge_traction(&mesh, &[edge], |_, _| [1.0, 0.0], &mut ft);
    let total: f64 = ft.chunks(2).map(|v| v[0]).sum();
    let k = 2000;
    let speed = |t: f64| mesh.edge_normal_at(&edge, t).1;
    let length: f64 = (0..k)
        .map(|s| {
            let (t0, t1) = (s as f64 / k as f64, (s + 1) as f64 / k as f64);
            (speed(t0) + 4.0 * speed(0.5 * (t0 + t1)) + speed(t1)) / (6.0 * k as f64)
        })
        .sum();
    assert!(
        (total - length).abs() < 1e-6 * length,
        "{total} vs {length}"
    );
    // The arc of 30° it stands for is within 1e-4 of it, its chord 1% shorter.
    let arc = r0 * std::f64::consts::PI / 6.0;
    assert!((total - arc).abs() < 1e-4 * arc, "{total} vs {arc}");
    let chord = mesh.edge_normal(&edge).1;
    assert!(
        arc - chord > 1e-2 * chord,
        "the arc is longer than its chord"
    );
}

#[test]
fn a_normal_support_is_refused_on_a_curved_edge_even_with_collinear_vertices() {
    // Mid-side nodes of the bottom side moved off it: by 0.1 h (off the line for any tolerance)
    // and by 1e-9 (on the line within the support tolerance, 1e-9 of the diameter √2, but curved
    // for the mesh, 1e-8 of an edge of 1/16).
    for offset in [0.1 / 16.0, 1e-9] {
        let base = Rectangle {
            origin: [0.0, 0.0],
            corner: [1.0, 1.0],
            nx: 16,
            ny: 16,
            diagonal: Diagonal::Alternate,
            mirror: false,
            order: Order::P2,
        }
        .mesh()
        .unwrap();
        let bottom = base.boundary("bottom").unwrap();
        let moved = bottom[3].mid.unwrap();
        let mut nodes = base.nodes().to_vec();
        nodes[moved][1] += offset;
        let mesh = base.with_nodes(nodes).unwrap();
        assert!(mesh.is_curved_edge(&mesh.boundary("bottom").unwrap()[3]));
        let mut c = Constraints::new(mesh.num_nodes());
        let err = c.fix(&mesh, "bottom", Component::Normal, 0.0).unwrap_err();
        assert!(matches!(err, SupportError::NotStraight { .. }), "{err}");
        // The straight sides still take one.
        c.fix(&mesh, "left", Component::Normal, 0.0).unwrap();
    }
}
