//! The contact patch test in space: two boxes of different materials on non-matching
//! tetrahedral meshes, the upper one pressed by a uniform pressure P onto the lower one, held
//! only by the contact vertically, with roller supports on their x− and y− faces. The exact
//! solution is a uniaxial stress state, linear in both bodies, so the finite element solution is
//! exact and every contact point carries P.
//!
//! The contact is the penalty law through the dual mortar rows of `contact3d` (the lower box's top
//! is the reference surface): closed points add the springs (w_j/θ) a_j a_jᵀ, a_j point j's
//! normal row, to the bodies' stiffness, and the coupled system is solved once.

use contactdd_core::factor::FactoredBody;
use contactdd_core::solid::assembly::{add_face_traction, stiffness};
use contactdd_core::solid::element::elasticity_matrix;
use contactdd_core::solid::{dof, BoxMesh, SolidMesh, TetOrder};
use contactdd_core::supports::Constraints;
use contactdd_ddm::contact3d::{dual_mortar, PointRows, Side, Surface, TriangleIndex};
use faer::sparse::{SparseColMat, Triplet};

/// The triangles of face `name` of `mesh` as a surface over its own nodes, and each surface
/// node's mesh node.
fn surface(mesh: &SolidMesh, name: &str) -> (Surface, Vec<usize>) {
    let flat = mesh.face(name).unwrap();
    let mut nodes: Vec<usize> = flat.to_vec();
    nodes.sort_unstable();
    nodes.dedup();
    let local = |v: usize| nodes.binary_search(&v).unwrap();
    let points = nodes.iter().map(|&v| mesh.nodes()[v]).collect();
    let triangles: Vec<[usize; 3]> = flat
        .chunks(3)
        .map(|t| [local(t[0]), local(t[1]), local(t[2])])
        .collect();
    (Surface::new(points, triangles).unwrap(), nodes)
}

/// The unique nodes of face `name`.
fn face_nodes(mesh: &SolidMesh, name: &str) -> Vec<usize> {
    let mut nodes = mesh.face(name).unwrap().to_vec();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Rollers on the x− and y− faces of the body whose DOFs start at `offset`, and on its z− face
/// where `floor`.
fn rollers(c: &mut Constraints, mesh: &SolidMesh, offset: usize, floor: bool) {
    let faces: &[(&str, usize)] = match floor {
        true => &[("x-", 0), ("y-", 1), ("z-", 2)],
        false => &[("x-", 0), ("y-", 1)],
    };
    for &(name, component) in faces {
        for v in face_nodes(mesh, name) {
            c.prescribe(offset + dof(v, component), 0.0);
        }
    }
}

/// The pressures of the contact points of the patch test with `cells` per box, the penalty θ
/// and the pressure P, and the total contact force.
fn patch(cells: [[usize; 3]; 2], theta: f64, pressure: f64) -> (Vec<f64>, f64) {
    let lower = BoxMesh {
        origin: [0.0, 0.0, -1.0],
        size: [1.0, 1.0, 1.0],
        cells: cells[0],
        order: TetOrder::P1,
    }
    .mesh()
    .unwrap();
    let upper = BoxMesh {
        origin: [0.0, 0.0, 0.0],
        size: [1.0, 1.0, 0.7],
        cells: cells[1],
        order: TetOrder::P1,
    }
    .mesh()
    .unwrap();
    let offset = 3 * lower.num_nodes();
    let n = offset + 3 * upper.num_nodes();
    let mut trip = Vec::new();
    let materials = [(2.1e5, 0.3), (7.0e4, 0.33)];
    for ((mesh, at), (e, nu)) in [(&lower, 0), (&upper, offset)].into_iter().zip(materials) {
        let k = stiffness(mesh, &elasticity_matrix(e, nu).unwrap());
        for (col, rows) in (0..k.ncols()).map(|c| (c, k.as_ref().col_range(c))) {
            for idx in rows {
                let row = k.symbolic().row_idx()[idx];
                trip.push(Triplet::new(at + row, at + col, k.val()[idx]));
            }
        }
    }
    let (reference, ref_nodes) = surface(&lower, "z+");
    let (partner, par_nodes) = surface(&upper, "z-");
    let rows = dual_mortar(&reference, &partner, &TriangleIndex::new(&partner), 0.1);
    let mut points = Vec::new();
    for (j, row) in rows.iter().enumerate() {
        let row = row.as_ref().unwrap();
        let point = PointRows::new(j, reference.normals()[j], row);
        // Point j's normal row over the Cartesian DOFs of both bodies.
        let a: Vec<(usize, f64)> = (point.terms.iter())
            .flat_map(|&(side, k, c)| {
                let at = match side {
                    Side::Reference => dof(ref_nodes[k], 0),
                    Side::Partner => offset + dof(par_nodes[k], 0),
                };
                (0..3).map(move |d| (at + d, c * point.frame[0][d]))
            })
            .collect();
        let spring = reference.weights()[j] / theta;
        for &(p, x) in &a {
            for &(q, y) in &a {
                trip.push(Triplet::new(p, q, spring * x * y));
            }
        }
        points.push(a);
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).unwrap();
    let mut c = Constraints::for_dofs(n);
    rollers(&mut c, &lower, 0, true);
    rollers(&mut c, &upper, offset, false);
    let mut f = vec![0.0; n];
    let mut top = vec![0.0; 3 * upper.num_nodes()];
    add_face_traction(&upper, "z+", |_, _| [0.0, 0.0, -pressure], &mut top).unwrap();
    f[offset..].copy_from_slice(&top);
    let mut body = FactoredBody::new("pair", k, &c, &[]).unwrap();
    body.factorize(&[]).unwrap();
    let u = body.solve(&f).unwrap();
    let pressures: Vec<f64> = (points.iter())
        .map(|a| a.iter().map(|&(p, x)| x * u[p]).sum::<f64>() / theta)
        .collect();
    let total = (pressures.iter().zip(reference.weights()))
        .map(|(p, w)| p * w)
        .sum();
    (pressures, total)
}

/// Every contact point carries the pressure to 1e-8, on non-matching meshes, at two penalties.
#[test]
fn a_uniform_pressure_crosses_non_matching_meshes_exactly() {
    let pressure = 3.0;
    for theta in [1e-4, 1e-7] {
        for cells in [[[3, 3, 2], [4, 5, 2]], [[5, 4, 2], [3, 3, 3]]] {
            let (pressures, total) = patch(cells, theta, pressure);
            for (j, p) in pressures.iter().enumerate() {
                assert!(
                    (p / pressure - 1.0).abs() < 1e-8,
                    "point {j}: {p} (θ {theta})"
                );
            }
            assert!((total / pressure - 1.0).abs() < 1e-10, "total {total}");
        }
    }
}
