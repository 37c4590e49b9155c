//! The dual mortar coefficients of triangulated surfaces in space (`contactdd::ddm::contact3d`),
//! against what they must reproduce: linear fields and flat gaps exactly, the identity on
//! matching meshes, consistent loads of a uniform pressure, rigid-motion invariance, and the
//! second-order convergence of a curved gap.

use contactdd_ddm::contact3d::{dual_mortar, MortarRow, Point3, PointRows, Surface, TriangleIndex};

/// A triangulated square [x0, x0 + size]² (n × n cells, each split along a diagonal) at height
/// `z(x, y)`, facing up (`up`) or down, with the interior nodes moved in the plane by up to
/// `jitter` of a cell (a deterministic pattern).
fn square(
    n: usize,
    x0: f64,
    size: f64,
    up: bool,
    jitter: f64,
    z: &dyn Fn(f64, f64) -> f64,
) -> Surface {
    let h = size / n as f64;
    let mut points = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let interior = i > 0 && j > 0 && i < n && j < n;
            let (dx, dy) = match interior {
                true => (
                    jitter * h * ((7 * i + 3 * j) as f64).sin(),
                    jitter * h * ((5 * i + 11 * j) as f64).cos(),
                ),
                false => (0.0, 0.0),
            };
            let (x, y) = (x0 + i as f64 * h + dx, x0 + j as f64 * h + dy);
            points.push([x, y, z(x, y)]);
        }
    }
    let v = |i: usize, j: usize| j * (n + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            let pair = match (i + j) % 2 {
                0 => [[a, b, c], [a, c, d]],
                _ => [[a, b, d], [b, c, d]],
            };
            for t in pair {
                triangles.push(if up { t } else { [t[0], t[2], t[1]] });
            }
        }
    }
    Surface::new(points, triangles).unwrap()
}

fn rows(reference: &Surface, partner: &Surface, search: f64) -> Vec<Option<MortarRow>> {
    dual_mortar(reference, partner, &TriangleIndex::new(partner), search)
}

/// The covered rows: (node, row) where the partner covers the node all around.
fn covered(rows: &[Option<MortarRow>]) -> Vec<(usize, &MortarRow)> {
    let out: Vec<(usize, &MortarRow)> = (rows.iter().enumerate())
        .filter_map(|(j, r)| r.as_ref().map(|r| (j, r)))
        .filter(|(_, r)| (r.coverage - 1.0).abs() < 1e-12)
        .collect();
    assert!(!out.is_empty());
    out
}

/// Σ_k c_jk f(x_k) over a row.
fn interpolate(row: &MortarRow, partner: &Surface, f: impl Fn(Point3) -> f64) -> f64 {
    row.coefficients
        .iter()
        .map(|&(k, c)| c * f(partner.points()[k]))
        .sum()
}

/// Non-matching flat surfaces at a distance: every covered node reads the partner's x and y
/// exactly (a linear field), its coefficients sum to 1, and its gap is the distance.
#[test]
fn flat_non_matching_surfaces_reproduce_linear_fields_and_the_gap() {
    let gap = 0.013;
    let reference = square(7, 0.0, 1.0, true, 0.2, &|_, _| 0.0);
    let partner = square(11, -0.1, 1.2, false, 0.25, &|_, _| gap);
    let rows = rows(&reference, &partner, 0.1);
    let inside = covered(&rows);
    assert!(inside.len() >= 25, "{} covered", inside.len());
    for (j, row) in inside {
        let x = reference.points()[j];
        let sum: f64 = row.coefficients.iter().map(|e| e.1).sum();
        assert!((sum - 1.0).abs() < 1e-13);
        for c in 0..2 {
            let read = interpolate(row, &partner, |p| p[c]);
            assert!(
                (read - x[c]).abs() < 1e-13,
                "node {j}: {read} against {}",
                x[c]
            );
        }
        assert!((row.gap - gap).abs() < 1e-14, "node {j}: gap {}", row.gap);
    }
}

/// A tilted flat partner: the gap along the reference normal is linear, and every covered node
/// reads it at its own position.
#[test]
fn a_tilted_partner_gives_the_linear_gap_at_every_node() {
    let plane = |x: f64, y: f64| 0.02 + 0.05 * x - 0.03 * y;
    let reference = square(6, 0.0, 1.0, true, 0.2, &|_, _| 0.0);
    let partner = square(9, -0.2, 1.4, false, 0.2, &plane);
    let rows = rows(&reference, &partner, 0.2);
    for (j, row) in covered(&rows) {
        let [x, y, _] = reference.points()[j];
        assert!((row.gap - plane(x, y)).abs() < 1e-14, "node {j}");
    }
}

/// Meshes that match node for node: each node reads its own partner node alone.
#[test]
fn matching_meshes_give_the_identity() {
    let reference = square(5, 0.0, 1.0, true, 0.15, &|_, _| 0.0);
    let partner = square(5, 0.0, 1.0, false, 0.15, &|_, _| 0.0);
    let rows = rows(&reference, &partner, 0.1);
    for (j, row) in rows.iter().enumerate() {
        let row = row.as_ref().unwrap();
        for &(k, c) in &row.coefficients {
            let expected = if k == j { 1.0 } else { 0.0 };
            assert!((c - expected).abs() < 1e-13, "node {j}, partner {k}: {c}");
        }
    }
}

/// A uniform pressure p on a reference surface inside its partner (forces w_j p, every node
/// covered) passed through the coefficients loads the partner with the consistent loads of that
/// pressure: p ∫ φ_k on every partner node whose triangles lie inside the reference square, and
/// p times the reference area in all.
#[test]
fn a_uniform_pressure_yields_the_partners_consistent_loads() {
    let reference = square(8, 0.1, 0.8, true, 0.2, &|_, _| 0.0);
    let partner = square(11, 0.0, 1.0, false, 0.2, &|_, _| 0.0);
    let rows = rows(&reference, &partner, 0.1);
    let mut load = vec![0.0; partner.points().len()];
    for (j, row) in rows.iter().enumerate() {
        let row = row.as_ref().unwrap();
        assert!((row.coverage - 1.0).abs() < 1e-12, "node {j}");
        for &(k, c) in &row.coefficients {
            load[k] += reference.weights()[j] * c;
        }
    }
    let total: f64 = load.iter().sum();
    assert!((total - 0.64).abs() < 1e-14, "{total}");
    let inside = |p: Point3| (0..2).all(|c| p[c] > 0.1 && p[c] < 0.9);
    let mut checked = 0;
    for (k, (&f, &w)) in load.iter().zip(partner.weights()).enumerate() {
        let around = partner.triangles().iter().filter(|t| t.contains(&k));
        if around.flatten().all(|&v| inside(partner.points()[v])) {
            assert!((f - w).abs() < 1e-14, "partner node {k}: {f} against {w}");
            checked += 1;
        }
    }
    assert!(checked >= 25, "{checked} partner nodes checked");
}

/// A rigid motion of both surfaces changes no coefficient and no gap.
#[test]
fn a_rigid_motion_changes_nothing() {
    let bump = |x: f64, y: f64| 0.01 + 0.02 * (x * x + y * y);
    let (reference, partner) = (
        square(6, 0.0, 1.0, true, 0.2, &|_, _| 0.0),
        square(8, -0.1, 1.2, false, 0.2, &bump),
    );
    let (a, b) = (0.7f64, -0.4f64);
    let rotate = |p: Point3| {
        let (x, y, z) = (
            p[0],
            p[1] * a.cos() - p[2] * a.sin(),
            p[1] * a.sin() + p[2] * a.cos(),
        );
        [
            x * b.cos() - y * b.sin() + 3.0,
            x * b.sin() + y * b.cos() - 1.0,
            z + 0.5,
        ]
    };
    let moved = |s: &Surface| {
        Surface::new(
            s.points().iter().map(|&p| rotate(p)).collect(),
            s.triangles().to_vec(),
        )
        .unwrap()
    };
    let before = rows(&reference, &partner, 0.2);
    let after = rows(&moved(&reference), &moved(&partner), 0.2);
    for (j, (x, y)) in before.iter().zip(&after).enumerate() {
        let (Some(x), Some(y)) = (x, y) else {
            assert_eq!(x.is_some(), y.is_some(), "node {j}");
            continue;
        };
        assert!((x.gap - y.gap).abs() < 1e-13, "node {j}");
        for (p, q) in x.coefficients.iter().zip(&y.coefficients) {
            assert_eq!(p.0, q.0);
            assert!((p.1 - q.1).abs() < 1e-12, "node {j}");
        }
    }
}

/// The gap of a flat reference under a sphere of radius R at distance g: the largest error at
/// the covered nodes within R/2 of the axis against the exact g + R − √(R² − r²) falls as h²
/// (the partner's interpolation and the dual weighting are both second order).
#[test]
fn the_gap_to_a_sphere_converges_at_second_order() {
    let (radius, g) = (2.0, 0.01);
    let sphere = |x: f64, y: f64| {
        let r2 = (x - 0.5).powi(2) + (y - 0.5).powi(2);
        g + radius - (radius * radius - r2).sqrt()
    };
    let mut errors = Vec::new();
    for n in [8, 16, 32] {
        let reference = square(n, 0.0, 1.0, true, 0.1, &|_, _| 0.0);
        let partner = square(n * 3 / 2 + 1, -0.05, 1.1, false, 0.1, &sphere);
        let rows = rows(&reference, &partner, 0.5);
        let worst = covered(&rows)
            .into_iter()
            .filter(|(j, _)| {
                let [x, y, _] = reference.points()[*j];
                (x - 0.5).hypot(y - 0.5) < 0.25 * radius
            })
            .map(|(j, row)| {
                let [x, y, _] = reference.points()[j];
                (row.gap - sphere(x, y)).abs()
            })
            .fold(0.0, f64::max);
        errors.push(worst);
    }
    for w in errors.windows(2) {
        let rate = (w[0] / w[1]).log2();
        assert!((1.7..2.4).contains(&rate), "errors {errors:?}");
    }
}

/// Surfaces far apart, or facing the same way, have no partner.
#[test]
fn distant_or_unfacing_surfaces_have_no_partner() {
    let reference = square(4, 0.0, 1.0, true, 0.0, &|_, _| 0.0);
    let far = square(4, 0.0, 1.0, false, 0.0, &|_, _| 1.0);
    assert!(rows(&reference, &far, 0.5).iter().all(Option::is_none));
    let same_way = square(4, 0.0, 1.0, true, 0.0, &|_, _| 0.01);
    assert!(rows(&reference, &same_way, 0.5).iter().all(Option::is_none));
}

/// Touching non-matching surfaces moved together by a rigid motion (a translation and a small
/// rotation, linearised: u = a + ω × x) neither approach nor slip at any covered point; moving
/// the partner alone by a tangential translation slips every covered point by exactly it.
#[test]
fn rigid_motions_neither_approach_nor_slip() {
    let reference = square(6, 0.0, 1.0, true, 0.2, &|_, _| 0.0);
    let partner = square(9, -0.1, 1.2, false, 0.2, &|_, _| 0.0);
    let rows = rows(&reference, &partner, 0.1);
    let (a, w) = ([0.3, -0.2, 0.1], [0.02, -0.05, 0.03]);
    let rigid = |x: Point3| {
        [
            a[0] + w[1] * x[2] - w[2] * x[1],
            a[1] + w[2] * x[0] - w[0] * x[2],
            a[2] + w[0] * x[1] - w[1] * x[0],
        ]
    };
    let u_ref: Vec<Point3> = reference.points().iter().map(|&x| rigid(x)).collect();
    let u_par: Vec<Point3> = partner.points().iter().map(|&x| rigid(x)).collect();
    let shift = [0.01, 0.004, 0.0];
    let still = vec![[0.0; 3]; reference.points().len()];
    let shifted = vec![shift; partner.points().len()];
    for (j, row) in covered(&rows) {
        let point = PointRows::new(j, reference.normals()[j], row);
        let [s, g1, g2] = point.read(&u_ref, &u_par);
        assert!(
            s.abs() < 1e-15 && g1.abs() < 1e-15 && g2.abs() < 1e-15,
            "node {j}"
        );
        // The partner moves by `shift`: the reference slips by −shift relative to it.
        let [s, g1, g2] = point.read(&still, &shifted);
        let [_, t1, t2] = point.frame;
        let along = |t: Point3| -(t[0] * shift[0] + t[1] * shift[1] + t[2] * shift[2]);
        assert!(s.abs() < 1e-15, "node {j}");
        assert!((g1 - along(t1)).abs() < 1e-15 && (g2 - along(t2)).abs() < 1e-15);
    }
}

/// A quadratic surface of 2 n² six-node triangles over the nodes of `square(2n)`: the side
/// nodes are the midpoints of the coarse triangles' sides.
fn quadratic_square(
    n: usize,
    x0: f64,
    size: f64,
    up: bool,
    z: &dyn Fn(f64, f64) -> f64,
) -> Surface {
    let fine = square(2 * n, x0, size, up, 0.0, z);
    let v = |i: usize, j: usize| j * (2 * n + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (i2, j2) = (2 * i, 2 * j);
            let (a, b, c, d) = (v(i2, j2), v(i2 + 2, j2), v(i2 + 2, j2 + 2), v(i2, j2 + 2));
            let (ab, bc, cd, da, ac) = (
                v(i2 + 1, j2),
                v(i2 + 2, j2 + 1),
                v(i2 + 1, j2 + 2),
                v(i2, j2 + 1),
                v(i2 + 1, j2 + 1),
            );
            for t in [[a, b, c, ab, bc, ac], [a, c, d, ac, cd, da]] {
                triangles.push(match up {
                    true => t,
                    false => [t[0], t[2], t[1], t[5], t[4], t[3]],
                });
            }
        }
    }
    Surface::from_quadratic(fine.points().to_vec(), &triangles).unwrap()
}

/// Quadratic surfaces, split into linear triangles: every node has a positive weight, the
/// weights sum to the area, and non-matching flat sides reproduce linear fields and the gap.
#[test]
fn quadratic_surfaces_read_their_partner_as_the_linear_ones_do() {
    let gap = 0.02;
    let reference = quadratic_square(4, 0.0, 1.0, true, &|_, _| 0.0);
    let partner = quadratic_square(5, -0.1, 1.2, false, &|_, _| gap);
    assert!(reference.weights().iter().all(|&w| w > 0.0));
    let area: f64 = reference.weights().iter().sum();
    assert!((area - 1.0).abs() < 1e-14);
    let rows = rows(&reference, &partner, 0.1);
    for (j, row) in covered(&rows) {
        let x = reference.points()[j];
        for c in 0..2 {
            assert!((interpolate(row, &partner, |p| p[c]) - x[c]).abs() < 1e-13);
        }
        assert!((row.gap - gap).abs() < 1e-14);
    }
}
