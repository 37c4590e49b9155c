//! Finite element core tests: element invariants, patch tests, convergence rates against an exact
//! solution, and a cantilever against Timoshenko beam theory.

use std::collections::BTreeMap;

use contactdd_core::assembly::{add_body_force, add_edge_traction, affine, Pattern};
use contactdd_core::element::{self, Affine, TRIANGLE_DEGREE_5};
use contactdd_core::factor::FactoredBody;
use contactdd_core::{
    Component, Constraints, Diagonal, ElasticBody, Material, Mesh, Order, Plane, Rectangle,
};

fn unit_square(n: usize, order: Order, diagonal: Diagonal) -> Mesh {
    Rectangle {
        origin: [0.0, 0.0],
        corner: [1.0, 1.0],
        nx: n,
        ny: n,
        diagonal,
        mirror: false,
        order,
    }
    .mesh()
    .unwrap()
}

/// A P1 mesh with interior nodes moved off the grid (an irregular mesh for patch tests).
fn irregular(n: usize, order: Order) -> Mesh {
    let base = unit_square(n, Order::P1, Diagonal::Alternate);
    let h = 1.0 / n as f64;
    let moved = base
        .map_nodes(|[x, y]| {
            let interior = x > 1e-12 && x < 1.0 - 1e-12 && y > 1e-12 && y < 1.0 - 1e-12;
            if interior {
                // A smooth but irregular perturbation, small enough to keep triangles valid.
                let dx = 0.25 * h * (7.0 * x + 3.0 * y * y).sin();
                let dy = 0.25 * h * (5.0 * y * x + 2.0 * x).cos();
                [x + dx, y + dy]
            } else {
                [x, y]
            }
        })
        .unwrap();
    match order {
        Order::P1 => moved,
        Order::P2 => moved.to_p2(),
    }
}

fn steel() -> Material {
    Material::new(200.0, 0.3).unwrap()
}

#[test]
fn shape_functions_partition_unity_and_gradients_sum_to_zero() {
    let geo = Affine::new([[0.1, 0.2], [1.3, 0.4], [0.5, 1.1]]);
    for order in [Order::P1, Order::P2] {
        for l in TRIANGLE_DEGREE_5.points {
            let n = element::shape(order, *l);
            let sum: f64 = n.iter().sum();
            assert!((sum - 1.0).abs() < 1e-14, "{order:?}: Σ N = {sum}");
            let g = geo.grad(order, *l);
            let gs = g.iter().fold([0.0, 0.0], |s, v| [s[0] + v[0], s[1] + v[1]]);
            assert!(
                gs[0].abs() < 1e-12 && gs[1].abs() < 1e-12,
                "{order:?}: Σ ∇N = {gs:?}"
            );
        }
        // Kronecker property at the nodes.
        for (i, l) in element::node_barycentric(order).iter().enumerate() {
            let n = element::shape(order, *l);
            for (j, v) in n.iter().take(order.nodes_per_cell()).enumerate() {
                let expect = if i == j { 1.0 } else { 0.0 };
                assert!((v - expect).abs() < 1e-14);
            }
        }
    }
}

#[test]
fn element_stiffness_is_symmetric_with_rigid_modes_in_kernel() {
    let geo = Affine::new([[0.1, 0.2], [1.3, 0.4], [0.5, 1.1]]);
    let d = steel().elasticity(Plane::Strain);
    for order in [Order::P1, Order::P2] {
        let k = element::stiffness(order, &geo, &d);
        let n = 2 * order.nodes_per_cell();
        let scale = (0..n).map(|i| k[i][i]).fold(0.0, f64::max);
        let pts: Vec<[f64; 2]> = element::node_barycentric(order)
            .iter()
            .map(|l| geo.point(*l))
            .collect();
        for i in 0..n {
            for j in 0..n {
                assert!((k[i][j] - k[j][i]).abs() < 1e-12 * scale);
            }
        }
        let modes: [Box<dyn Fn([f64; 2]) -> [f64; 2]>; 3] = [
            Box::new(|_| [1.0, 0.0]),
            Box::new(|_| [0.0, 1.0]),
            Box::new(|p| [-p[1], p[0]]),
        ];
        for mode in &modes {
            let r: Vec<f64> = pts.iter().flat_map(|&p| mode(p)).collect();
            for row in k.iter().take(n) {
                let kr: f64 = (0..n).map(|j| row[j] * r[j]).sum();
                assert!(kr.abs() < 1e-12 * scale, "{order:?}: K r = {kr}");
            }
        }
        // A non-rigid mode (uniform stretch) has positive energy.
        let s: Vec<f64> = pts.iter().flat_map(|&p| [p[0], 0.0]).collect();
        let energy: f64 = (0..n)
            .map(|i| (0..n).map(|j| s[i] * k[i][j] * s[j]).sum::<f64>())
            .sum();
        assert!(energy > 1e-6 * scale);
    }
}

/// Prescribes `exact` on the whole boundary, solves with body force `f`, returns (mesh, u).
fn solve_dirichlet(
    mesh: Mesh,
    material: Material,
    exact: impl Fn([f64; 2]) -> [f64; 2],
    f: impl Fn([f64; 2]) -> [f64; 2],
) -> (Mesh, Vec<f64>) {
    let plane = Plane::Strain;
    let mut constraints = Constraints::new(mesh.num_nodes());
    let mut load = vec![0.0; 2 * mesh.num_nodes()];
    add_body_force(&mesh, f, &mut load);
    let k = Pattern::new(&mesh).stiffness(&mesh, &material.elasticity(plane));
    for name in ["left", "right", "bottom", "top"] {
        for v in mesh.boundary_nodes(name).unwrap() {
            constraints_set(&mut constraints, v, exact(mesh.nodes()[v]));
        }
    }
    let mut op = FactoredBody::new("patch", k, &constraints, &[]).unwrap();
    op.factorize(&[]).unwrap();
    let u = op.solve(&load).unwrap();
    (mesh, u)
}

fn constraints_set(c: &mut Constraints, node: usize, value: [f64; 2]) {
    c.set(2 * node, Some(value[0]));
    c.set(2 * node + 1, Some(value[1]));
}

#[test]
fn patch_test_reproduces_linear_fields_on_irregular_meshes() {
    let lin = |p: [f64; 2]| {
        [
            0.1 + 0.02 * p[0] - 0.03 * p[1],
            -0.2 + 0.01 * p[0] + 0.04 * p[1],
        ]
    };
    for order in [Order::P1, Order::P2] {
        let (mesh, u) = solve_dirichlet(irregular(6, order), steel(), lin, |_| [0.0, 0.0]);
        let mut worst: f64 = 0.0;
        for (v, p) in mesh.nodes().iter().enumerate() {
            let e = lin(*p);
            worst = worst
                .max((u[2 * v] - e[0]).abs())
                .max((u[2 * v + 1] - e[1]).abs());
        }
        assert!(worst < 1e-10, "{order:?}: patch test error {worst:e}");
    }
}

/// Exact solution u = (s, s), s = sin πx sin πy, with the body force that makes it exact.
fn manufactured(
    material: Material,
) -> (impl Fn([f64; 2]) -> [f64; 2], impl Fn([f64; 2]) -> [f64; 2]) {
    let (l, m) = material.lame(Plane::Strain);
    let pi = std::f64::consts::PI;
    let exact = move |p: [f64; 2]| {
        let s = (pi * p[0]).sin() * (pi * p[1]).sin();
        [s, s]
    };
    let force = move |p: [f64; 2]| {
        let s = (pi * p[0]).sin() * (pi * p[1]).sin();
        let cc = (pi * p[0]).cos() * (pi * p[1]).cos();
        let f = (l + m) * pi * pi * (s - cc) + 2.0 * m * pi * pi * s;
        [f, f]
    };
    (exact, force)
}

fn exact_strain(p: [f64; 2]) -> [f64; 3] {
    let pi = std::f64::consts::PI;
    let (sx, cx, sy, cy) = (
        (pi * p[0]).sin(),
        (pi * p[0]).cos(),
        (pi * p[1]).sin(),
        (pi * p[1]).cos(),
    );
    [pi * cx * sy, pi * sx * cy, pi * sx * cy + pi * cx * sy]
}

/// (L2 error, energy-norm error) of the manufactured problem on an n × n mesh.
fn errors(n: usize, order: Order) -> (f64, f64) {
    let material = Material::new(1.0, 0.3).unwrap();
    let (exact, force) = manufactured(material);
    let (mesh, u) = solve_dirichlet(
        unit_square(n, order, Diagonal::Right),
        material,
        &exact,
        force,
    );
    let d = material.elasticity(Plane::Strain);
    let (mut l2, mut energy) = (0.0, 0.0);
    for e in 0..mesh.num_cells() {
        let c = mesh.cell(e);
        let geo = affine(&mesh, c);
        let ue: Vec<[f64; 2]> = c.iter().map(|&v| [u[2 * v], u[2 * v + 1]]).collect();
        for (l, w) in TRIANGLE_DEGREE_5
            .points
            .iter()
            .zip(TRIANGLE_DEGREE_5.weights)
        {
            let p = geo.point(*l);
            let nv = element::shape(order, *l);
            let uh = ue.iter().enumerate().fold([0.0, 0.0], |s, (k, v)| {
                [s[0] + nv[k] * v[0], s[1] + nv[k] * v[1]]
            });
            let ex = exact(p);
            l2 += w * geo.area * ((uh[0] - ex[0]).powi(2) + (uh[1] - ex[1]).powi(2));
            let eh = element::strain(order, &geo, *l, &ue);
            let es = exact_strain(p);
            let de = [es[0] - eh[0], es[1] - eh[1], es[2] - eh[2]];
            let sde: f64 = (0..3)
                .map(|i| de[i] * (0..3).map(|j| d[i][j] * de[j]).sum::<f64>())
                .sum();
            energy += w * geo.area * sde;
        }
    }
    (l2.sqrt(), energy.sqrt())
}

#[test]
fn convergence_rates_match_theory() {
    for (order, sizes, l2_rate, energy_rate) in [
        (Order::P1, [8, 16, 32], 2.0, 1.0),
        (Order::P2, [4, 8, 16], 3.0, 2.0),
    ] {
        let errs: Vec<(f64, f64)> = sizes.iter().map(|&n| errors(n, order)).collect();
        for w in errs.windows(2) {
            let rate_l2 = (w[0].0 / w[1].0).log2();
            let rate_e = (w[0].1 / w[1].1).log2();
            assert!(
                (rate_l2 - l2_rate).abs() < 0.2,
                "{order:?}: L2 rate {rate_l2:.3}, expected {l2_rate} (errors {errs:?})"
            );
            assert!(
                (rate_e - energy_rate).abs() < 0.2,
                "{order:?}: energy rate {rate_e:.3}, expected {energy_rate} (errors {errs:?})"
            );
        }
    }
}

#[test]
fn p2_cantilever_tip_deflection_matches_timoshenko_beam() {
    let (len, h, e, nu, p) = (10.0, 1.0, 1000.0, 0.3, 1.0);
    let mesh = Rectangle {
        origin: [0.0, -h / 2.0],
        corner: [len, h / 2.0],
        nx: 40,
        ny: 4,
        diagonal: Diagonal::Alternate,
        mirror: false,
        order: Order::P2,
    }
    .mesh()
    .unwrap();
    let material = Material::new(e, nu).unwrap();
    let mut constraints = Constraints::new(mesh.num_nodes());
    constraints
        .fix(&mesh, "left", Component::Both, 0.0)
        .unwrap();
    // Parabolic shear traction on the free end, total downward force p.
    let mut load = vec![0.0; 2 * mesh.num_nodes()];
    let right = mesh.boundary("right").unwrap().to_vec();
    add_edge_traction(
        &mesh,
        &right,
        |x, _| [0.0, -1.5 * p / h * (1.0 - (2.0 * x[1] / h).powi(2))],
        &mut load,
    );
    let body = ElasticBody {
        name: "beam".into(),
        mesh: mesh.clone(),
        material,
        plane: Plane::Stress,
        constraints,
        load,
    };
    let sol = body.solve().unwrap();
    let tip = mesh
        .nodes()
        .iter()
        .position(|q| (q[0] - len).abs() < 1e-12 && q[1].abs() < 1e-12)
        .unwrap();
    let deflection = -sol.displacement[2 * tip + 1];
    let inertia = h.powi(3) / 12.0;
    let shear_modulus = e / (2.0 * (1.0 + nu));
    let timoshenko =
        p * len.powi(3) / (3.0 * e * inertia) + p * len / (5.0 / 6.0 * shear_modulus * h);
    let rel = (deflection - timoshenko).abs() / timoshenko;
    assert!(
        rel < 0.01,
        "tip {deflection}, Timoshenko {timoshenko}, rel {rel:e}"
    );
    // Reactions balance the applied load.
    let r = contactdd_core::post::reaction_on(&mesh, "left", &sol.residual).unwrap();
    assert!(
        (r[1] - p).abs() < 1e-9 && r[0].abs() < 1e-9,
        "reaction {r:?}"
    );
}

#[test]
fn floating_body_is_a_typed_error() {
    let mesh = unit_square(2, Order::P1, Diagonal::Right);
    let mut constraints = Constraints::new(mesh.num_nodes());
    constraints.fix(&mesh, "left", Component::X, 0.0).unwrap();
    let body = ElasticBody {
        name: "loose".into(),
        mesh: mesh.clone(),
        material: steel(),
        plane: Plane::Strain,
        constraints,
        load: vec![0.0; 2 * mesh.num_nodes()],
    };
    let err = body.solve().unwrap_err().to_string();
    assert!(
        err.contains("loose") && err.contains("translation in y"),
        "{err}"
    );
}

#[test]
fn schur_factor_equals_dense_schur_complement() {
    let mesh = unit_square(3, Order::P2, Diagonal::Alternate);
    let material = steel();
    let mut constraints = Constraints::new(mesh.num_nodes());
    constraints
        .fix(&mesh, "left", Component::Both, 0.0)
        .unwrap();
    let k = Pattern::new(&mesh).stiffness(&mesh, &material.elasticity(Plane::Strain));
    let top: Vec<usize> = mesh
        .boundary_nodes("top")
        .unwrap()
        .iter()
        .flat_map(|&v| [2 * v, 2 * v + 1])
        .collect();
    let mut op = FactoredBody::new("s", k.clone(), &constraints, &top).unwrap();
    // Before a factorisation there is no Schur factor: an error, not a zero matrix.
    assert!(op.schur_factor().is_err());
    op.factorize(&[]).unwrap();
    let l22 = op.schur_factor().expect("factorised with an interface");
    let idx = op.interface_index(&top);
    // (K⁻¹)_cc computed column by column with full solves must equal (L22 L22ᵀ)⁻¹: check
    // S · (K⁻¹)_cc = I.
    let m = l22.nrows();
    let s = &l22 * l22.transpose();
    for (col, &dof_j) in top.iter().enumerate() {
        let Some((j, _)) = idx[col] else { continue };
        let mut f = vec![0.0; op.num_dofs()];
        f[dof_j] = 1.0;
        let x = op.solve(&f).unwrap();
        for i in 0..m {
            let si: f64 = top
                .iter()
                .zip(&idx)
                .filter_map(|(&d, p)| p.map(|(p, _)| s[(i, p)] * x[d]))
                .sum();
            let expect = if i == j { 1.0 } else { 0.0 };
            assert!((si - expect).abs() < 1e-8, "S K⁻¹ [{i},{j}] = {si}");
        }
    }
}

#[test]
fn invalid_meshes_are_typed_errors() {
    let nodes = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [5.0, 5.0]];
    let err = Mesh::new(
        nodes.clone(),
        Order::P1,
        vec![0, 1, 2],
        BTreeMap::new(),
        BTreeMap::new(),
    );
    assert!(matches!(
        err,
        Err(contactdd_core::MeshError::UnreferencedNode { node: 3 })
    ));
    let err = Mesh::new(
        nodes[..3].to_vec(),
        Order::P1,
        vec![0, 2, 1],
        BTreeMap::new(),
        BTreeMap::new(),
    );
    assert!(matches!(
        err,
        Err(contactdd_core::MeshError::InvertedElement { element: 0 })
    ));
    let flat = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let err = Mesh::new(
        flat,
        Order::P1,
        vec![0, 1, 2],
        BTreeMap::new(),
        BTreeMap::new(),
    );
    assert!(matches!(
        err,
        Err(contactdd_core::MeshError::DegenerateElement { element: 0 })
    ));
    let mesh = unit_square(1, Order::P1, Diagonal::Right);
    assert!(mesh
        .boundary("nope")
        .unwrap_err()
        .to_string()
        .contains("left"));
    assert!(Material::new(-1.0, 0.3).is_err() && Material::new(1.0, 0.5).is_err());
}

#[test]
fn mirrored_rectangle_is_the_reflection() {
    let r = |mirror| Rectangle {
        origin: [0.0, 1.0],
        corner: [4.0, 2.0],
        nx: 4,
        ny: 2,
        diagonal: Diagonal::Right,
        mirror,
        order: Order::P1,
    };
    let plain = r(false).mesh().unwrap();
    let mirrored = r(true).mesh().unwrap();
    for (p, q) in plain.nodes().iter().zip(mirrored.nodes()) {
        assert!((p[0] - q[0]).abs() < 1e-15 && (p[1] - (3.0 - q[1])).abs() < 1e-15);
    }
    // The bottom boundary of the mirrored mesh lies on y = 1 with outward normal −y.
    for e in mirrored.boundary("bottom").unwrap() {
        let (n, _) = mirrored.edge_normal(e);
        assert!((n[1] + 1.0).abs() < 1e-14 && mirrored.nodes()[e.a][1] == 1.0);
    }
}

/// A held body whose factorisation or solve fails says which: the pivot of a matrix that is not
/// positive definite, a non-finite solution as such.
#[test]
fn factor_errors_name_the_pivot_and_non_finite_solutions() {
    let mesh = unit_square(2, Order::P1, Diagonal::Alternate);
    let mut constraints = Constraints::new(mesh.num_nodes());
    constraints
        .fix(&mesh, "left", Component::Both, 0.0)
        .unwrap();
    let k = Pattern::new(&mesh).stiffness(&mesh, &steel().elasticity(Plane::Strain));
    let mut op = FactoredBody::new("b", k, &constraints, &[]).unwrap();
    let free = (0..op.num_dofs())
        .rev()
        .find(|&d| constraints.get(d).is_none())
        .unwrap();
    let err = op.factorize(&[(free, free, -1e12)]).unwrap_err();
    assert!(
        matches!(err, contactdd_core::BodyError::NotPositiveDefinite { ref body, .. } if body == "b"),
        "{err}"
    );
    op.factorize(&[]).unwrap();
    let err = op.solve(&vec![f64::NAN; op.num_dofs()]).unwrap_err();
    assert!(
        matches!(err, contactdd_core::BodyError::NonFinite { .. }),
        "{err}"
    );
}

/// The residual in chosen rows without assembling K is the assembled matrix's residual in those
/// rows to the bit (P1, P2, and P2 with curved cells), and zero elsewhere.
#[test]
fn residual_rows_match_the_assembled_residual_to_the_bit() {
    let curved = irregular(5, Order::P2)
        .map_nodes(|[x, y]| [x + 0.05 * (3.0 * y).sin() * x * (1.0 - x), y])
        .unwrap();
    for mesh in [irregular(5, Order::P1), irregular(5, Order::P2), curved] {
        let d = steel().elasticity(Plane::Strain);
        let k = Pattern::new(&mesh).stiffness(&mesh, &d);
        let n = 2 * mesh.num_nodes();
        let u: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let f: Vec<f64> = (0..n).map(|i| (0.11 * i as f64).cos()).collect();
        let full = contactdd_core::post::residual(&k, &u, &f);
        let rows: Vec<usize> = (0..mesh.num_nodes()).filter(|v| v % 3 == 1).collect();
        let r = contactdd_core::assembly::residual_rows(&mesh, &d, (&u, &f), &rows);
        for v in 0..mesh.num_nodes() {
            for c in 0..2 {
                let want = if v % 3 == 1 { full[2 * v + c] } else { 0.0 };
                assert_eq!(r[2 * v + c].to_bits(), want.to_bits(), "node {v}");
            }
        }
    }
}
