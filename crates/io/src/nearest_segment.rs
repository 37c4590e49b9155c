//! The nearest of many straight segments to a point, through a uniform grid of the segments'
//! bounding boxes: a query looks at the segments near the point, so reading every point of a
//! contact zone costs about the zone's size, not its square. The answer is the one a scan of
//! all segments in order gives (the first of the nearest).

use std::collections::HashMap;

use contactdd_core::mesh::dist;
use contactdd_core::Point;

/// A straight piece with a value at each end: its two end points and their values.
pub type Segment = ([Point; 2], [f64; 2]);

/// Segments indexed by the grid cells their bounding boxes touch.
pub struct Segments<'a> {
    segments: &'a [Segment],
    /// The grid's origin and cell size.
    origin: Point,
    cell: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
    /// The grid's extent in cells: no segment lies outside `lo..=hi`.
    lo: (i64, i64),
    hi: (i64, i64),
}

impl<'a> Segments<'a> {
    /// The index of `segments`, with cells of their mean length.
    pub fn new(segments: &'a [Segment]) -> Segments<'a> {
        let total: f64 = segments.iter().map(|([a, b], _)| dist(*a, *b)).sum();
        let mean = total / segments.len().max(1) as f64;
        let mut origin = [f64::INFINITY; 2];
        for ([a, b], _) in segments {
            for d in 0..2 {
                origin[d] = origin[d].min(a[d]).min(b[d]);
            }
        }
        let cell = if mean > 0.0 && mean.is_finite() {
            mean
        } else {
            1.0
        };
        let mut index = Segments {
            segments,
            origin,
            cell,
            cells: HashMap::new(),
            lo: (i64::MAX, i64::MAX),
            hi: (i64::MIN, i64::MIN),
        };
        for (s, ([a, b], _)) in segments.iter().enumerate() {
            let (p, q) = (index.cell_of(*a), index.cell_of(*b));
            for ix in p.0.min(q.0)..=p.0.max(q.0) {
                for iy in p.1.min(q.1)..=p.1.max(q.1) {
                    index.cells.entry((ix, iy)).or_default().push(s);
                }
            }
            index.lo = (index.lo.0.min(p.0.min(q.0)), index.lo.1.min(p.1.min(q.1)));
            index.hi = (index.hi.0.max(p.0.max(q.0)), index.hi.1.max(p.1.max(q.1)));
        }
        index
    }

    fn cell_of(&self, x: Point) -> (i64, i64) {
        let c = |d: usize| ((x[d] - self.origin[d]) / self.cell).floor() as i64;
        (c(0), c(1))
    }

    /// The value of the segment nearest to `x`, interpolated at its point nearest to `x` (0 if
    /// there is no segment); of several at the same distance, the first.
    pub fn read(&self, x: Point) -> f64 {
        if self.segments.is_empty() || !(x[0].is_finite() && x[1].is_finite()) {
            return read_all(self.segments, x);
        }
        let c = self.cell_of(x);
        // Rings of cells around x's cell: every segment outside ring r is at least r cells away.
        let reach = [
            c.0 - self.lo.0,
            self.hi.0 - c.0,
            c.1 - self.lo.1,
            self.hi.1 - c.1,
        ];
        let last = reach.iter().copied().max().unwrap_or(0).max(0);
        let mut best: Option<(f64, usize, f64)> = None;
        let mut visited = 0;
        for r in 0..=last {
            // Far from every segment the rings are mostly empty: a scan is then cheaper.
            visited += 8 * r as usize + 1;
            if visited > 4 * self.segments.len() + 64 {
                return read_all(self.segments, x);
            }
            for cell in ring(c, r) {
                for &s in self.cells.get(&cell).map_or(&[][..], |v| v.as_slice()) {
                    let (d, value) = nearest(&self.segments[s], x);
                    if best.map_or(true, |(bd, bs, _)| d < bd || (d == bd && s < bs)) {
                        best = Some((d, s, value));
                    }
                }
            }
            if best.is_some_and(|(d, _, _)| d < r as f64 * self.cell) {
                break;
            }
        }
        best.map_or(0.0, |(_, _, value)| value)
    }
}

/// The cells at Chebyshev distance `r` from `c`.
fn ring(c: (i64, i64), r: i64) -> Vec<(i64, i64)> {
    if r == 0 {
        return vec![c];
    }
    let mut cells = Vec::with_capacity(8 * r as usize);
    for i in -r..=r {
        cells.extend([(c.0 + i, c.1 - r), (c.0 + i, c.1 + r)]);
    }
    for j in -r + 1..r {
        cells.extend([(c.0 - r, c.1 + j), (c.0 + r, c.1 + j)]);
    }
    cells
}

/// The distance from `x` to `segment` and the segment's value at its point nearest to `x`.
fn nearest(([a, b], [pa, pb]): &Segment, x: Point) -> (f64, f64) {
    let (ab, ax) = ([b[0] - a[0], b[1] - a[1]], [x[0] - a[0], x[1] - a[1]]);
    let length2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if length2 > 0.0 {
        ((ab[0] * ax[0] + ab[1] * ax[1]) / length2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let point = [a[0] + t * ab[0], a[1] + t * ab[1]];
    (dist(x, point), (1.0 - t) * pa + t * pb)
}

/// [`Segments::read`] by a scan of all segments.
pub fn read_all(segments: &[Segment], x: Point) -> f64 {
    let mut best = (f64::INFINITY, 0.0);
    for segment in segments {
        let (d, value) = nearest(segment, x);
        if d < best.0 {
            best = (d, value);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wavy line of many segments with values along it, read at points on, near and far from
    /// it: the grid gives the scan's answer to the bit.
    #[test]
    fn the_grid_reads_what_a_scan_reads() {
        let n = 400;
        let point = |k: usize| {
            let s = k as f64 / n as f64;
            [4.0 * s, 0.3 * (9.0 * s).sin()]
        };
        let segments: Vec<Segment> = (0..n)
            .map(|k| ([point(k), point(k + 1)], [k as f64, (k + 1) as f64]))
            .collect();
        let index = Segments::new(&segments);
        for q in 0..997 {
            let s = q as f64 / 997.0;
            for offset in [0.0, 1e-3, 0.05, 0.7, 5.0] {
                let x = [-1.0 + 6.0 * s, 0.3 * (9.0 * s).cos() + offset];
                assert_eq!(
                    index.read(x).to_bits(),
                    read_all(&segments, x).to_bits(),
                    "{x:?}"
                );
            }
        }
        assert_eq!(Segments::new(&[]).read([0.0, 0.0]), 0.0);
    }
}
