//! Polygons in a plane: the overlap of two convex polygons (Sutherland–Hodgman clipping) and
//! their signed areas. The mortar integration clips every projected partner triangle against the
//! reference triangle it faces.

/// A point in the plane of a reference triangle.
pub type Point2 = [f64; 2];

/// Twice the signed area of the triangle (a, b, c): positive when counterclockwise.
pub fn orient(a: Point2, b: Point2, c: Point2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The signed area of a polygon: positive when its vertices run counterclockwise.
pub fn area(polygon: &[Point2]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let (p, q) = (polygon[i], polygon[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

/// The part of the convex polygon `subject` inside the convex, counterclockwise polygon `clip`:
/// `subject` cut by the half-plane left of each edge of `clip` in turn. Empty (or fewer than
/// three vertices) where they do not overlap.
pub fn clip_convex(subject: &[Point2], clip: &[Point2]) -> Vec<Point2> {
    let mut out = subject.to_vec();
    for i in 0..clip.len() {
        if out.len() < 3 {
            return Vec::new();
        }
        let (a, b) = (clip[i], clip[(i + 1) % clip.len()]);
        out = cut(&out, a, b);
    }
    if out.len() < 3 {
        return Vec::new();
    }
    out
}

/// The part of `polygon` on the left of the line from `a` to `b` (the line itself included).
fn cut(polygon: &[Point2], a: Point2, b: Point2) -> Vec<Point2> {
    let side = |p: Point2| orient(a, b, p);
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for i in 0..polygon.len() {
        let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        // The edge crosses the line strictly: its crossing point is a vertex of the cut.
        if (sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0) {
            let t = sp / (sp - sq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_overlapping_triangles_clip_to_their_common_part() {
        let t: [Point2; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        // The same triangle shifted by half to the right: the overlap is the triangle
        // (0.5, 0), (1, 0), (0.5, 0.5) of area 1/8.
        let s: Vec<Point2> = t.iter().map(|p| [p[0] + 0.5, p[1]]).collect();
        let c = clip_convex(&s, &t);
        assert!((area(&c) - 0.125).abs() < 1e-15, "{c:?}");
        // A triangle inside is its own overlap; one outside has none.
        let inner = [[0.1, 0.1], [0.3, 0.1], [0.1, 0.3]];
        assert!((area(&clip_convex(&inner, &t)) - area(&inner)).abs() < 1e-16);
        let outer = [[2.0, 2.0], [3.0, 2.0], [2.0, 3.0]];
        assert!(clip_convex(&outer, &t).is_empty());
    }

    /// The overlap of a square with a rotated copy of itself (a regular octagon for 45°) has the
    /// area of the regular octagon of inradius 1, 8 tan(π/8).
    #[test]
    fn a_square_and_its_rotation_overlap_in_an_octagon() {
        let square = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let rotated: Vec<Point2> = square
            .iter()
            .map(|p| [r * (p[0] - p[1]), r * (p[0] + p[1])])
            .collect();
        let c = clip_convex(&rotated, &square);
        assert_eq!(c.len(), 8);
        let octagon = 8.0 * (std::f64::consts::PI / 8.0).tan();
        assert!((area(&c) - octagon).abs() < 1e-14, "{}", area(&c));
    }
}
