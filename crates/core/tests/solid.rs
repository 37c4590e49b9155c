//! The 3D tetrahedral layer (`contactdd_core::solid`) against closed forms: rigid modes in the
//! kernel, patch tests on distorted meshes, a bar under uniform traction, convergence rates of a
//! manufactured solution, exact quadrature, Gmsh's P2 node positions, a conforming box mesh,
//! thread-count independence and typed errors.

use contactdd_core::solid::assembly::{add_body_force, add_face_traction, stiffness};
use contactdd_core::solid::element::{
    elasticity_matrix, element_stiffness, tet_reference_grad, tet_shape, TetGeometry, TetRule,
    TET_DEGREE_1, TET_DEGREE_2, TET_DEGREE_5,
};
use contactdd_core::solid::post::von_mises;
use contactdd_core::solid::rigid::RigidModes;
use contactdd_core::solid::supports::{constraints, fix, fix_field};
use contactdd_core::solid::{
    dof, num_dofs, Axis, BoxMesh, Point3, SolidBody, SolidError, SolidMesh, TetOrder, Vector3,
};
use contactdd_core::{Material, MaterialError};
use faer::sparse::SparseColMat;

const E: f64 = 210.0;
const NU: f64 = 0.3;

fn unit_box(order: TetOrder, n: usize) -> SolidMesh {
    BoxMesh {
        origin: [0.0; 3],
        size: [1.0; 3],
        cells: [n; 3],
        order,
    }
    .mesh()
    .unwrap()
}

/// Moves the interior vertices of a box mesh by up to 0.2 cell widths (a fixed pseudo-random
/// pattern); P2 mid-edge nodes follow to their edges' midpoints, so the elements stay straight.
fn distorted(order: TetOrder, n: usize) -> SolidMesh {
    let mesh = BoxMesh {
        origin: [-0.5, 0.2, 1.0],
        size: [2.0, 1.0, 1.5],
        cells: [n, n + 1, n],
        order,
    }
    .mesh()
    .unwrap();
    let (lo, hi) = ([-0.5, 0.2, 1.0], [1.5, 1.2, 2.5]);
    let h = [2.0 / n as f64, 1.0 / (n + 1) as f64, 1.5 / n as f64];
    let mut seed = 12345u64;
    let mut rand = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut nodes = mesh.nodes().to_vec();
    for p in nodes.iter_mut() {
        let inside = (0..3).all(|c| p[c] > lo[c] + 1e-9 && p[c] < hi[c] - 1e-9);
        for c in 0..3 {
            let r = rand();
            if inside {
                p[c] += 0.4 * h[c] * r;
            }
        }
    }
    if order == TetOrder::P2 {
        for e in 0..mesh.num_tets() {
            let t = mesh.tet(e);
            for (k, [a, b]) in contactdd_core::solid::element::TET_EDGES.iter().enumerate() {
                let (pa, pb) = (nodes[t[*a]], nodes[t[*b]]);
                nodes[t[4 + k]] = std::array::from_fn(|c| 0.5 * (pa[c] + pb[c]));
            }
        }
    }
    mesh.with_nodes(nodes).unwrap()
}

fn d() -> [[f64; 6]; 6] {
    elasticity_matrix(E, NU).unwrap()
}

fn lame() -> (f64, f64) {
    let mu = E / (2.0 * (1.0 + NU));
    (E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU)), mu)
}

fn matvec(k: &SparseColMat<usize, f64>, x: &[f64]) -> Vec<f64> {
    let (cp, ri, v) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    let mut y = vec![0.0; k.nrows()];
    for j in 0..k.ncols() {
        for p in cp[j]..cp[j + 1] {
            y[ri[p]] += v[p] * x[j];
        }
    }
    y
}

/// Max row sum of |K|.
fn norm_inf(k: &SparseColMat<usize, f64>) -> f64 {
    let ones = vec![1.0; k.ncols()];
    let (cp, ri, v) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    let mut y = vec![0.0; k.nrows()];
    for j in 0..k.ncols() {
        for p in cp[j]..cp[j + 1] {
            y[ri[p]] += v[p].abs() * ones[j];
        }
    }
    y.into_iter().fold(0.0, f64::max)
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn rigid_modes_are_in_the_kernel_and_k_is_symmetric() {
    for order in [TetOrder::P1, TetOrder::P2] {
        let mesh = distorted(order, 3);
        let k = stiffness(&mesh, &d());
        let scale = norm_inf(&k);
        for (m, r) in RigidModes::new(&mesh).vectors(&mesh).iter().enumerate() {
            let kr = matvec(&k, r);
            let rel = max_abs(&kr) / (scale * max_abs(r));
            assert!(
                rel < 1e-12,
                "{order:?} mode {m}: |K r| / (|K| |r|) = {rel:e}"
            );
        }
        let (cp, ri, v) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        let entry = |i: usize, j: usize| {
            let rows = &ri[cp[j]..cp[j + 1]];
            rows.binary_search(&i).map(|p| v[cp[j] + p]).unwrap()
        };
        let vmax = max_abs(v);
        for j in 0..k.ncols() {
            for p in cp[j]..cp[j + 1] {
                let i = ri[p];
                assert!((v[p] - entry(j, i)).abs() <= 1e-14 * vmax, "K({i},{j})");
            }
        }
        // Positive definite once supported: the Cholesky factorisation succeeds, and the energy of
        // a non-rigid displacement is positive.
        let mut cons = constraints(&mesh);
        fix(&mut cons, &mesh, "x-", &Axis::ALL, 0.0).unwrap();
        let body = SolidBody::new("b", mesh.clone(), Material::new(E, NU).unwrap(), &cons);
        assert!(body.is_ok(), "{order:?}: {:?}", body.err());
        let x: Vec<f64> = (0..k.ncols())
            .map(|i| ((i * 7919) % 13) as f64 - 6.0)
            .collect();
        let energy: f64 = matvec(&k, &x).iter().zip(&x).map(|(a, b)| a * b).sum();
        assert!(energy > 0.0);
    }
}

#[test]
fn element_stiffness_kills_rigid_modes_of_a_curved_p2_tetrahedron() {
    let mut x: Vec<Point3> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.1, 0.0],
        [0.2, 1.0, 0.1],
        [0.1, 0.2, 1.3],
    ];
    for [a, b] in contactdd_core::solid::element::TET_EDGES {
        x.push(std::array::from_fn(|c| {
            0.5 * (x[a][c] + x[b][c]) + 0.03 * (c as f64 + 1.0)
        }));
    }
    let geo = TetGeometry::new(&x);
    assert!(geo.is_curved());
    let k = element_stiffness(&geo, &d());
    let kmax = k.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for m in 0..6 {
        let r: Vec<f64> = (0..30)
            .map(|i| {
                let (v, c) = (i / 3, i % 3);
                let p = x[v];
                let rot = [[0.0, p[2], -p[1]], [-p[2], 0.0, p[0]], [p[1], -p[0], 0.0]];
                if m < 3 {
                    f64::from(u8::from(c == m))
                } else {
                    rot[c][m - 3]
                }
            })
            .collect();
        let kr = (0..30).map(|i| (0..30).map(|j| k[i][j] * r[j]).sum::<f64>());
        let worst = kr.fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(worst < 1e-12 * kmax * 30.0, "mode {m}: {worst:e}");
    }
}

/// Solves with `g` prescribed on all six faces and body force `f`; returns the worst nodal error
/// against `g`, relative to the largest |g|.
fn patch(mesh: &SolidMesh, g: &dyn Fn(Point3) -> Vector3, f: &dyn Fn(Point3) -> Vector3) -> f64 {
    let mut cons = constraints(mesh);
    for face in ["x-", "x+", "y-", "y+", "z-", "z+"] {
        fix_field(&mut cons, mesh, face, g).unwrap();
    }
    let body = SolidBody::new("patch", mesh.clone(), Material::new(E, NU).unwrap(), &cons).unwrap();
    let mut rhs = vec![0.0; num_dofs(mesh.num_nodes())];
    add_body_force(mesh, f, &mut rhs).unwrap();
    let u = body.solve(&rhs).unwrap();
    let mut worst: f64 = 0.0;
    let mut size: f64 = 0.0;
    for (v, p) in mesh.nodes().iter().enumerate() {
        let e = g(*p);
        for c in 0..3 {
            worst = worst.max((u[dof(v, c)] - e[c]).abs());
            size = size.max(e[c].abs());
        }
    }
    worst / size
}

#[test]
fn patch_test_linear_field_p1_and_p2() {
    let a = [[0.3, -0.2, 0.15], [0.05, 0.4, -0.25], [-0.1, 0.2, 0.35]];
    let g = move |x: Point3| -> Vector3 {
        std::array::from_fn(|i| {
            0.1 * (i as f64 + 1.0) + (0..3).map(|j| a[i][j] * x[j]).sum::<f64>()
        })
    };
    for order in [TetOrder::P1, TetOrder::P2] {
        let err = patch(&distorted(order, 3), &g, &|_| [0.0; 3]);
        assert!(err < 1e-10, "{order:?}: {err:e}");
    }
}

#[test]
fn patch_test_quadratic_field_p2_with_its_body_force() {
    // u_i = ½ xᵀ H_i x + linear, H_i symmetric.
    let h = [
        [[0.4, 0.1, -0.2], [0.1, -0.3, 0.05], [-0.2, 0.05, 0.25]],
        [[-0.1, 0.3, 0.0], [0.3, 0.2, -0.15], [0.0, -0.15, 0.1]],
        [[0.2, -0.05, 0.1], [-0.05, 0.15, 0.3], [0.1, 0.3, -0.35]],
    ];
    let g = move |x: Point3| -> Vector3 {
        std::array::from_fn(|i| {
            let q: f64 = (0..3)
                .flat_map(|j| (0..3).map(move |k| (j, k)))
                .map(|(j, k)| 0.5 * h[i][j][k] * x[j] * x[k])
                .sum();
            q + 0.1 * x[(i + 1) % 3] + 0.05
        })
    };
    // f = −(λ + μ) ∇(∇·u) − μ Δu: ∂_m(∇·u) = Σ_i H_i[i][m], (Δu)_m = Σ_j H_m[j][j].
    let (lambda, mu) = lame();
    let f = move |_: Point3| -> Vector3 {
        std::array::from_fn(|m| {
            let grad_div: f64 = (0..3).map(|i| h[i][i][m]).sum();
            let lap: f64 = (0..3).map(|j| h[m][j][j]).sum();
            -(lambda + mu) * grad_div - mu * lap
        })
    };
    let err = patch(&distorted(TetOrder::P2, 3), &g, &f);
    assert!(err < 1e-10, "P2 quadratic: {err:e}");
    // P1 cannot represent it: the same test fails for P1 (the test can fail).
    let err1 = patch(&distorted(TetOrder::P1, 3), &g, &f);
    assert!(err1 > 1e-6, "P1 quadratic unexpectedly exact: {err1:e}");
}

#[test]
fn bar_under_uniform_traction_matches_the_uniaxial_solution() {
    let sigma = 7.5;
    for order in [TetOrder::P1, TetOrder::P2] {
        let mesh = BoxMesh {
            origin: [0.0; 3],
            size: [3.0, 1.0, 0.5],
            cells: [6, 2, 2],
            order,
        }
        .mesh()
        .unwrap();
        let mut cons = constraints(&mesh);
        fix(&mut cons, &mesh, "x-", &[Axis::X], 0.0).unwrap();
        fix(&mut cons, &mesh, "y-", &[Axis::Y], 0.0).unwrap();
        fix(&mut cons, &mesh, "z-", &[Axis::Z], 0.0).unwrap();
        let mut f = vec![0.0; num_dofs(mesh.num_nodes())];
        add_face_traction(&mesh, "x+", |_, _| [sigma, 0.0, 0.0], &mut f).unwrap();
        // The load: total σ × area; on P2 the face's vertices carry nothing.
        let total: f64 = (0..mesh.num_nodes()).map(|v| f[dof(v, 0)]).sum();
        assert!((total - sigma * 0.5).abs() < 1e-13);
        if order == TetOrder::P2 {
            for tri in mesh.face("x+").unwrap().chunks(6) {
                for &v in &tri[..3] {
                    assert!(f[dof(v, 0)].abs() < 1e-14, "vertex load {}", f[dof(v, 0)]);
                }
            }
        }
        let body =
            SolidBody::new("bar", mesh.clone(), Material::new(E, NU).unwrap(), &cons).unwrap();
        let u = body.solve(&f).unwrap();
        let exact = |p: Point3| {
            [
                sigma * p[0] / E,
                -NU * sigma * p[1] / E,
                -NU * sigma * p[2] / E,
            ]
        };
        let scale = sigma * 3.0 / E;
        for (v, p) in mesh.nodes().iter().enumerate() {
            let e = exact(*p);
            for c in 0..3 {
                assert!(
                    (u[dof(v, c)] - e[c]).abs() < 1e-10 * scale,
                    "{order:?} node {v} comp {c}"
                );
            }
        }
        for s in body
            .centroid_stresses(&u)
            .unwrap()
            .iter()
            .chain(&body.nodal_stresses(&u).unwrap())
        {
            let expected = [sigma, 0.0, 0.0, 0.0, 0.0, 0.0];
            for i in 0..6 {
                assert!(
                    (s[i] - expected[i]).abs() < 1e-9 * sigma,
                    "{order:?} stress {s:?}"
                );
            }
            assert!((von_mises(*s) - sigma).abs() < 1e-9 * sigma);
        }
    }
}

/// The manufactured solution u = A sin(k·x) + B cos(q·x) and its body force
/// f = −(λ + μ) ∇(∇·u) − μ Δu.
struct Manufactured {
    a: Vector3,
    k: Vector3,
    b: Vector3,
    q: Vector3,
}

impl Manufactured {
    fn u(&self, x: Point3) -> Vector3 {
        let (s, c) = (dot(self.k, x).sin(), dot(self.q, x).cos());
        std::array::from_fn(|i| self.a[i] * s + self.b[i] * c)
    }

    fn f(&self, x: Point3) -> Vector3 {
        let (lambda, mu) = lame();
        let (s, c) = (dot(self.k, x).sin(), dot(self.q, x).cos());
        let (ak, bq) = (dot(self.a, self.k), dot(self.b, self.q));
        let (kk, qq) = (dot(self.k, self.k), dot(self.q, self.q));
        std::array::from_fn(|i| {
            ((lambda + mu) * ak * self.k[i] + mu * kk * self.a[i]) * s
                + ((lambda + mu) * bq * self.q[i] + mu * qq * self.b[i]) * c
        })
    }
}

fn dot(a: Vector3, b: Vector3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The L2 error of the finite element solution on the unit cube with n cells per side.
fn l2_error(order: TetOrder, n: usize, m: &Manufactured) -> f64 {
    let mesh = unit_box(order, n);
    let u = |x: Point3| m.u(x);
    let uh = patch_solution(&mesh, &u, &|x| m.f(x));
    let p2 = order == TetOrder::P2;
    let mut sum = 0.0;
    for e in 0..mesh.num_tets() {
        let geo = mesh.geometry(e);
        let t = mesh.tet(e);
        for (l, w) in TET_DEGREE_5.points.iter().zip(TET_DEGREE_5.weights) {
            let nl = tet_shape(p2, *l);
            let exact = m.u(geo.point(*l));
            let dv = w * geo.grad(*l).1 / 6.0;
            for c in 0..3 {
                let value: f64 = t
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| nl[k] * uh[dof(v, c)])
                    .sum();
                sum += dv * (value - exact[c]).powi(2);
            }
        }
    }
    sum.sqrt()
}

fn patch_solution(
    mesh: &SolidMesh,
    g: &dyn Fn(Point3) -> Vector3,
    f: &dyn Fn(Point3) -> Vector3,
) -> Vec<f64> {
    let mut cons = constraints(mesh);
    for face in ["x-", "x+", "y-", "y+", "z-", "z+"] {
        fix_field(&mut cons, mesh, face, g).unwrap();
    }
    let body = SolidBody::new("m", mesh.clone(), Material::new(E, NU).unwrap(), &cons).unwrap();
    let mut rhs = vec![0.0; num_dofs(mesh.num_nodes())];
    add_body_force(mesh, f, &mut rhs).unwrap();
    body.solve(&rhs).unwrap()
}

#[test]
fn manufactured_solution_converges_at_rates_two_and_three() {
    let m = Manufactured {
        a: [0.3, -0.2, 0.5],
        k: [1.1, 0.6, -0.9],
        b: [-0.1, 0.4, 0.2],
        q: [0.4, 1.3, 0.8],
    };
    for (order, sizes, rate) in [
        (TetOrder::P1, [4, 8, 16], 2.0),
        (TetOrder::P2, [2, 4, 8], 3.0),
    ] {
        let errs: Vec<f64> = sizes.iter().map(|&n| l2_error(order, n, &m)).collect();
        let rates: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        eprintln!("{order:?}: errors {errs:?}, rates {rates:?}");
        for r in &rates {
            assert!(
                (r - rate).abs() < 0.3,
                "{order:?}: rates {rates:?}, expected {rate}"
            );
        }
    }
}

fn factorial(n: u32) -> f64 {
    (1..=n).map(f64::from).product()
}

/// ∫ ξ^a η^b ζ^c over the reference tetrahedron, divided by its volume 1/6.
fn monomial(rule: &TetRule, [a, b, c]: [u32; 3]) -> (f64, f64) {
    let q: f64 = rule
        .points
        .iter()
        .zip(rule.weights)
        .map(|(l, w)| w * l[1].powi(a as i32) * l[2].powi(b as i32) * l[3].powi(c as i32))
        .sum();
    let exact = 6.0 * factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
    (q, exact)
}

#[test]
fn quadrature_rules_are_exact_to_their_degree_and_not_beyond() {
    for (rule, degree) in [(&TET_DEGREE_1, 1), (&TET_DEGREE_2, 2), (&TET_DEGREE_5, 5)] {
        let mut beyond = 0.0f64;
        for a in 0..=degree + 1 {
            for b in 0..=degree + 1 - a {
                for c in 0..=degree + 1 - a - b {
                    let (q, exact) = monomial(rule, [a, b, c]);
                    if a + b + c <= degree {
                        assert!((q - exact).abs() < 1e-15, "degree {degree}: {a} {b} {c}");
                    } else {
                        beyond = beyond.max((q - exact).abs() / exact);
                    }
                }
            }
        }
        assert!(
            beyond > 1e-6,
            "degree {degree} rule is exact beyond its degree"
        );
    }
}

#[test]
fn p2_nodes_sit_where_gmsh_documents_them() {
    // Gmsh's "Tetrahedron10": vertices (0,0,0), (1,0,0), (0,1,0), (0,0,1), then the midpoints of
    // the edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1.
    let nodes: [Point3; 10] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.0],
        [0.0, 0.0, 0.5],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
    ];
    for (i, p) in nodes.iter().enumerate() {
        let l = [1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]];
        let n = tet_shape(true, l);
        for (k, v) in n.iter().enumerate() {
            assert!(
                (v - f64::from(u8::from(i == k))).abs() < 1e-15,
                "N_{k}(node {i}) = {v}"
            );
        }
    }
    // Gradients against central differences at an interior point.
    let x = [0.21, 0.17, 0.33];
    let bary = |x: [f64; 3]| [1.0 - x[0] - x[1] - x[2], x[0], x[1], x[2]];
    let g = tet_reference_grad(true, bary(x));
    for c in 0..3 {
        let (mut xp, mut xm) = (x, x);
        xp[c] += 1e-6;
        xm[c] -= 1e-6;
        let (np, nm) = (tet_shape(true, bary(xp)), tet_shape(true, bary(xm)));
        for k in 0..10 {
            assert!(
                (g[k][c] - (np[k] - nm[k]) / 2e-6).abs() < 1e-8,
                "dN_{k}/dx_{c}"
            );
        }
    }
}

#[test]
fn box_mesh_is_conforming_and_fills_the_box() {
    for order in [TetOrder::P1, TetOrder::P2] {
        let cells = [3, 2, 4];
        let mesh = BoxMesh {
            origin: [1.0, -1.0, 0.5],
            size: [1.5, 2.0, 1.0],
            cells,
            order,
        }
        .mesh()
        .unwrap();
        let volume: f64 = (0..mesh.num_tets())
            .map(|e| mesh.geometry(e).volume())
            .sum();
        assert!((volume - 3.0).abs() < 1e-12, "{volume}");
        assert_eq!(mesh.num_tets(), 6 * 24);
        let s = if order == TetOrder::P2 { 2 } else { 1 };
        assert_eq!(mesh.num_nodes(), (s * 3 + 1) * (s * 2 + 1) * (s * 4 + 1));
        let mut count = std::collections::HashMap::new();
        for e in 0..mesh.num_tets() {
            let t = mesh.tet(e);
            for skip in 0..4 {
                let mut f: Vec<usize> = (0..4).filter(|&i| i != skip).map(|i| t[i]).collect();
                f.sort_unstable();
                *count.entry(f).or_insert(0) += 1;
            }
        }
        assert!(
            count.values().all(|&c| c <= 2),
            "a face shared by more than two tetrahedra"
        );
        let boundary = count.values().filter(|&&c| c == 1).count();
        assert_eq!(boundary, 4 * (3 * 2 + 2 * 4 + 3 * 4));
        let named: usize = mesh
            .face_names()
            .map(|n| mesh.face(n).unwrap().len() / (3 * s))
            .sum();
        assert_eq!(named, boundary);
        // Outward normals: on x+ the normal is +x.
        let p = mesh.nodes();
        for tri in mesh.face("x+").unwrap().chunks(3 * s) {
            let (a, b, c) = (p[tri[0]], p[tri[1]], p[tri[2]]);
            let n0 = (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
            assert!(n0 > 0.0);
        }
    }
}

#[test]
fn assembly_is_bitwise_independent_of_the_thread_count() {
    let mesh = distorted(TetOrder::P2, 3);
    let k = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| stiffness(&mesh, &d()).val().to_vec())
    };
    let (one, two, three) = (k(1), k(2), k(3));
    assert!(one
        .iter()
        .zip(&two)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(one
        .iter()
        .zip(&three)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
fn invalid_input_gives_typed_errors() {
    assert!(matches!(
        elasticity_matrix(1.0, 0.5),
        Err(MaterialError::PoissonRatio(_))
    ));
    assert!(matches!(
        elasticity_matrix(1.0, -1.0),
        Err(MaterialError::PoissonRatio(_))
    ));
    assert!(matches!(
        elasticity_matrix(1.0, f64::NAN),
        Err(MaterialError::PoissonRatio(_))
    ));
    assert!(matches!(
        elasticity_matrix(0.0, 0.3),
        Err(MaterialError::YoungModulus(_))
    ));
    assert!(matches!(
        elasticity_matrix(-2.0, 0.3),
        Err(MaterialError::YoungModulus(_))
    ));

    let nodes = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let new = |nodes: Vec<Point3>, tets: Vec<usize>, faces: Vec<(String, Vec<usize>)>| {
        SolidMesh::new(nodes, TetOrder::P1, tets, faces)
    };
    assert!(new(nodes.clone(), vec![0, 1, 2, 3], vec![]).is_ok());
    assert!(matches!(
        new(nodes.clone(), vec![0, 2, 1, 3], vec![]),
        Err(SolidError::InvertedElement { element: 0 })
    ));
    let mut flat = nodes.clone();
    flat[3] = [0.3, 0.3, 0.0];
    assert!(matches!(
        new(flat, vec![0, 1, 2, 3], vec![]),
        Err(SolidError::DegenerateElement { element: 0 })
    ));
    assert!(matches!(
        new(nodes.clone(), vec![0, 1, 2, 4], vec![]),
        Err(SolidError::NodeOutOfRange {
            element: 0,
            node: 4,
            count: 4
        })
    ));
    assert!(matches!(
        new(nodes.clone(), vec![0, 1, 2], vec![]),
        Err(SolidError::BadConnectivity { .. })
    ));
    let mut nan = nodes.clone();
    nan[2][1] = f64::NAN;
    assert!(matches!(
        new(nan, vec![0, 1, 2, 3], vec![]),
        Err(SolidError::NonFiniteNode { node: 2 })
    ));
    let mut extra = nodes.clone();
    extra.push([5.0, 5.0, 5.0]);
    assert!(matches!(
        new(extra, vec![0, 1, 2, 3], vec![]),
        Err(SolidError::UnreferencedNode { node: 4 })
    ));
    // A face that is not a face of the tetrahedron.
    let bad_face = vec![("f".to_string(), vec![0, 1, 1])];
    assert!(matches!(
        new(nodes.clone(), vec![0, 1, 2, 3], bad_face),
        Err(SolidError::NotABoundaryFace { .. })
    ));

    // Unknown face names in supports and loads.
    let mesh = unit_box(TetOrder::P1, 1);
    let mut cons = constraints(&mesh);
    match fix(&mut cons, &mesh, "top", &[Axis::Z], 0.0) {
        Err(SolidError::NoSuchFace { name, known }) => {
            assert_eq!(name, "top");
            assert_eq!(known, ["x+", "x-", "y+", "y-", "z+", "z-"]);
        }
        other => panic!("{other:?}"),
    }
    let mut f = vec![0.0; num_dofs(mesh.num_nodes())];
    assert!(matches!(
        add_face_traction(&mesh, "left", |_, _| [1.0; 3], &mut f),
        Err(SolidError::NoSuchFace { .. })
    ));
    assert!(matches!(
        fix(&mut cons, &mesh, "x-", &[Axis::Z], f64::NAN),
        Err(SolidError::NonFinite { .. })
    ));
    assert!(matches!(
        BoxMesh {
            origin: [0.0; 3],
            size: [1.0, -1.0, 1.0],
            cells: [1; 3],
            order: TetOrder::P1
        }
        .mesh(),
        Err(SolidError::BadBox(_))
    ));
    // A body held only on one face's x components keeps rigid modes: not positive definite.
    let mut weak = constraints(&mesh);
    fix(&mut weak, &mesh, "x-", &[Axis::X], 0.0).unwrap();
    assert!(matches!(
        SolidBody::new("w", mesh.clone(), Material::new(E, NU).unwrap(), &weak),
        Err(SolidError::Body(_))
    ));
}
