//! A uniform grid of a surface's triangles: which triangles a box may touch, in time that grows
//! with the triangles near the box, not with the surface.

use std::collections::HashMap;

use super::surface::Surface;
use super::Point3;

/// The triangles of a [`Surface`] filed by the grid cells their bounding boxes overlap.
#[derive(Clone, Debug)]
pub struct TriangleIndex {
    origin: Point3,
    cell: f64,
    /// The largest cell index a triangle reaches, per direction.
    limit: [i64; 3],
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl TriangleIndex {
    /// Files every triangle of `surface` in a grid whose cell is the mean side of the triangles'
    /// boxes, so that a triangle overlaps a few cells.
    pub fn new(surface: &Surface) -> TriangleIndex {
        let n = surface.triangles().len();
        let boxes: Vec<(Point3, Point3)> = (0..n).map(|t| surface.bounds(t)).collect();
        let mut origin = [f64::INFINITY; 3];
        let mut side = 0.0;
        for (lo, hi) in &boxes {
            for c in 0..3 {
                origin[c] = origin[c].min(lo[c]);
                side += hi[c] - lo[c];
            }
        }
        // The mean side over the three directions: a flat surface's boxes have one side zero.
        let cell = (1.5 * side / (n as f64 * 3.0)).max(f64::MIN_POSITIVE);
        let mut limit = [0i64; 3];
        for (_, hi) in &boxes {
            for c in 0..3 {
                limit[c] = limit[c].max(((hi[c] - origin[c]) / cell).floor() as i64);
            }
        }
        let mut index = TriangleIndex {
            origin,
            cell,
            limit,
            cells: HashMap::new(),
        };
        for (t, (lo, hi)) in boxes.iter().enumerate() {
            for key in index.keys(*lo, *hi) {
                index.cells.entry(key).or_default().push(t);
            }
        }
        index
    }

    /// The triangles whose boxes may overlap the box from `lo` to `hi`, in increasing order,
    /// each once. A superset: the caller tests the geometry.
    pub fn near(&self, lo: Point3, hi: Point3) -> Vec<usize> {
        let mut out: Vec<usize> = self
            .keys(lo, hi)
            .filter_map(|k| self.cells.get(&k))
            .flatten()
            .copied()
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The grid cells the box from `lo` to `hi` overlaps, clamped to the cells that can hold a
    /// triangle (so that a huge box does not enumerate empty space); none for a box outside them
    /// or with a NaN corner.
    fn keys(&self, lo: Point3, hi: Point3) -> impl Iterator<Item = [i64; 3]> {
        let at = |x: f64, c: usize| ((x - self.origin[c]) / self.cell).floor();
        let (mut a, mut b) = ([0i64; 3], [-1i64; 3]);
        let inside = (0..3).all(|c| at(hi[c], c) >= 0.0 && at(lo[c], c) <= self.limit[c] as f64);
        if inside {
            for c in 0..3 {
                a[c] = at(lo[c], c).max(0.0) as i64;
                b[c] = at(hi[c], c).min(self.limit[c] as f64) as i64;
            }
        }
        (a[0]..=b[0]).flat_map(move |i| {
            (a[1]..=b[1]).flat_map(move |j| (a[2]..=b[2]).map(move |k| [i, j, k]))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wavy surface of 2 n² triangles over the unit square.
    fn wavy(n: usize) -> Surface {
        let mut points = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                points.push([x, y, 0.1 * (5.0 * x).sin() * (3.0 * y).cos()]);
            }
        }
        let v = |i: usize, j: usize| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        Surface::new(points, triangles).unwrap()
    }

    /// Every triangle whose box overlaps a query box is among those the index returns.
    #[test]
    fn the_index_finds_every_triangle_a_box_overlaps() {
        let s = wavy(17);
        let index = TriangleIndex::new(&s);
        let mut seed = 7u64;
        let mut draw = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200 {
            let c = [draw() * 1.2 - 0.1, draw() * 1.2 - 0.1, draw() * 0.3 - 0.15];
            let r = 0.1 * draw();
            let (lo, hi) = (c.map(|x| x - r), c.map(|x| x + r));
            let found = index.near(lo, hi);
            for t in 0..s.triangles().len() {
                let (a, b) = s.bounds(t);
                let overlaps = (0..3).all(|k| a[k] <= hi[k] && b[k] >= lo[k]);
                assert!(!overlaps || found.binary_search(&t).is_ok(), "triangle {t}");
            }
            assert!(
                found.len() < s.triangles().len() / 2,
                "{} found",
                found.len()
            );
        }
    }
}
