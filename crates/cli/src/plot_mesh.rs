//! The deformed bodies of `contactdd plot`, each element coloured by its von Mises stress, over
//! the undeformed outlines, read back from the bodies' `.vtu` files (the last load step's with
//! load steps), one body per `Piece` (a file per body, or one file for all of them). The reader (`contactdd_io::vtu_read`) knows only what `crates/io/src/vtu.rs`
//! writes, ASCII or binary; the figure draws triangles (the corners of a quadratic triangle), a
//! curved edge of a quadratic triangle (its mid-side node off the chord's midpoint) as two
//! segments through its mid-side node.

use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::args::Format;
use contactdd_io::result_set::read_result_file;
use contactdd_io::vtu_read::{parse_vtu_pieces, Section, VtuFile};

use crate::plot_data::{Units, VTU_LIMIT};
use crate::plot_draw::{linear, ok, render, span, tick, Figure, Frame};

/// Pixels right of the chart for the colour bar.
pub const BAR_WIDTH: u32 = 140;

/// One body: deformed corner coordinates of its triangles and their von Mises stress.
struct Body {
    /// Per triangle, its deformed corners, with the mid-side node of a curved edge between them.
    triangles: Vec<Vec<(f64, f64)>>,
    stress: Vec<f64>,
    /// The undeformed node coordinates and the displacements, for the scale.
    points: Vec<(f64, f64)>,
    displacement: Vec<(f64, f64)>,
    cells: Vec<[usize; 3]>,
    /// Per triangle, the mid-side node of each edge (0,1), (1,2), (2,0) if that edge is curved.
    mids: Vec<[Option<usize>; 3]>,
}

/// The `bodies` figure from the `.vtu` files `files` (plain names in `dir`).
pub fn figures(
    dir: &Path,
    files: &[String],
    units: &Units,
    out: &Path,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    let names = last_step(files);
    if names.is_empty() {
        return Ok(Vec::new());
    }
    let mut bodies = Vec::new();
    for name in &names {
        // A file of one body, or of every body (one piece each).
        let path = dir.join(name);
        let bytes = read_result_file(&path, VTU_LIMIT)?;
        let pieces = parse_vtu_pieces(&bytes).map_err(|e| anyhow!("'{}': {e}", path.display()))?;
        for piece in &pieces {
            match read_body(&path, piece)? {
                Some(body) => bodies.push(body),
                None => {
                    // Not an error of the folder: a field holding NaN (the iterate of a failed
                    // solve) cannot be drawn; the other figures are still worth having.
                    eprintln!("note: {name} has non-finite values; the bodies figure is left out");
                    return Ok(Vec::new());
                }
            }
        }
    }
    let mut fig = Bodies {
        bodies,
        units,
        scale: 1.0,
    };
    fig.scale = fig.scale();
    fig.deform();
    render(&fig, out, "bodies", formats)
}

/// The `.vtu` files of the last load step (`<body>-step<k>.vtu`, or `bodies-step<k>.vtu`, with
/// the largest k), or all.
fn last_step(files: &[String]) -> Vec<String> {
    let vtu: Vec<&String> = files.iter().filter(|f| f.ends_with(".vtu")).collect();
    let step =
        |f: &str| -> Option<u64> { f.strip_suffix(".vtu")?.rsplit_once("-step")?.1.parse().ok() };
    match vtu.iter().filter_map(|f| step(f)).max() {
        Some(k) => vtu
            .into_iter()
            .filter(|f| step(f) == Some(k))
            .cloned()
            .collect(),
        None => vtu.into_iter().cloned().collect(),
    }
}

/// A body's mesh and stress from its piece `file` of the file `path`, or `None` when an array
/// it draws holds a non-finite value (the iterate of a failed solve).
fn read_body(path: &Path, file: &VtuFile) -> Result<Option<Body>> {
    let arrays = [
        (Section::Points, ""),
        (Section::PointData, "displacement"),
        (Section::Cells, "connectivity"),
        (Section::Cells, "offsets"),
        (Section::CellData, "element_von_mises"),
    ]
    .map(|(section, name)| {
        let missing = || anyhow!("'{}' has no array {name:?}", path.display());
        file.array(section, name)
            .map(|a| &a.values)
            .ok_or_else(missing)
    });
    let [xyz, u, conn, offsets, stress] = arrays;
    let (xyz, u, conn, offsets, stress) = (xyz?, u?, conn?, offsets?, stress?.clone());
    if [xyz, u, &stress]
        .iter()
        .any(|a| a.iter().any(|v| !v.is_finite()))
    {
        return Ok(None);
    }
    let points: Vec<(f64, f64)> = xyz.chunks_exact(3).map(|p| (p[0], p[1])).collect();
    let displacement: Vec<(f64, f64)> = u.chunks_exact(3).map(|p| (p[0], p[1])).collect();
    let bad = || anyhow!("'{}': cells do not fit the points", path.display());
    if displacement.len() != points.len() || stress.len() != offsets.len() {
        return Err(bad());
    }
    let mut cells = Vec::with_capacity(offsets.len());
    let mut mids = Vec::with_capacity(offsets.len());
    let mut begin = 0usize;
    for &end in offsets {
        // The first three nodes of a (linear or quadratic) triangle are its corners.
        let corner = |k: usize| -> Result<usize> {
            let v = *conn.get(begin + k).ok_or_else(bad)?;
            let i = v as usize;
            if v < 0.0 || v.fract() != 0.0 || i >= points.len() {
                return Err(bad());
            }
            Ok(i)
        };
        let c = [corner(0)?, corner(1)?, corner(2)?];
        let quadratic = end as usize >= begin + 6;
        let mut mid = [None; 3];
        for (k, m) in mid.iter_mut().enumerate().filter(|_| quadratic) {
            let v = corner(3 + k)?;
            *m = curved(points[c[k]], points[c[(k + 1) % 3]], points[v]).then_some(v);
        }
        cells.push(c);
        mids.push(mid);
        begin = end as usize;
    }
    Ok(Some(Body {
        triangles: Vec::new(),
        stress,
        points,
        displacement,
        cells,
        mids,
    }))
}

/// Whether the mid-side node `m` of the edge from `a` to `b` is off its midpoint by more than
/// 1e-8 of the edge (the mesh's own test of a curved edge).
fn curved(a: (f64, f64), b: (f64, f64), m: (f64, f64)) -> bool {
    let off = (m.0 - 0.5 * (a.0 + b.0)).hypot(m.1 - 0.5 * (a.1 + b.1));
    off > 1e-8 * (b.0 - a.0).hypot(b.1 - a.1)
}

/// The outline paths with the mid-side node of every curved edge inserted between its ends.
fn through_mids(
    paths: Vec<Vec<usize>>,
    cells: &[[usize; 3]],
    mids: &[[Option<usize>; 3]],
) -> Vec<Vec<usize>> {
    let mut on: std::collections::HashMap<(usize, usize), usize> = Default::default();
    for (c, m) in cells.iter().zip(mids) {
        for k in 0..3 {
            if let Some(v) = m[k] {
                let (a, b) = (c[k], c[(k + 1) % 3]);
                on.insert((a.min(b), a.max(b)), v);
            }
        }
    }
    if on.is_empty() {
        return paths;
    }
    paths
        .into_iter()
        .map(|path| {
            let mut out = Vec::with_capacity(2 * path.len());
            for (i, &v) in path.iter().enumerate() {
                if let Some(&p) = i.checked_sub(1).and_then(|i| path.get(i)) {
                    out.extend(on.get(&(p.min(v), p.max(v))));
                }
                out.push(v);
            }
            out
        })
        .collect()
}

/// The bodies, deformed, coloured by stress.
struct Bodies<'a> {
    bodies: Vec<Body>,
    units: &'a Units,
    scale: f64,
}

impl Bodies<'_> {
    /// The displacement scale that makes the largest displacement 5% of the bodies' extent,
    /// rounded to 1, 2 or 5 times a power of ten.
    fn scale(&self) -> f64 {
        let pts = || self.bodies.iter().flat_map(|b| b.points.iter());
        let (x, y) = (
            span(pts().map(|p| p.0), 0.0, 0.0..1.0),
            span(pts().map(|p| p.1), 0.0, 0.0..1.0),
        );
        let extent = (x.end - x.start).max(y.end - y.start);
        let umax = self
            .bodies
            .iter()
            .flat_map(|b| b.displacement.iter())
            .map(|u| u.0.hypot(u.1))
            .filter(|u| u.is_finite())
            .fold(0.0, f64::max);
        if umax == 0.0 || extent == 0.0 {
            return 1.0;
        }
        let raw = 0.05 * extent / umax;
        let p = 10f64.powf(raw.log10().floor());
        [5.0, 2.0, 1.0]
            .into_iter()
            .map(|m| m * p)
            .find(|&s| s <= raw)
            .unwrap_or(p)
    }

    fn deform(&mut self) {
        let s = self.scale;
        for b in &mut self.bodies {
            let at = |i: usize| {
                (
                    b.points[i].0 + s * b.displacement[i].0,
                    b.points[i].1 + s * b.displacement[i].1,
                )
            };
            b.triangles = b
                .cells
                .iter()
                .zip(&b.mids)
                .map(|(c, m)| {
                    (0..3)
                        .flat_map(|k| std::iter::once(c[k]).chain(m[k]))
                        .map(at)
                        .collect()
                })
                .collect();
        }
    }
}

/// Viridis at 0 ≤ t ≤ 1, from five stops.
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |x: f64, y: f64| (x + f * (y - x)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl Figure for Bodies<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (w, h) = root.dim_in_pixel();
        let (left, right) = root.split_horizontally(w.saturating_sub(BAR_WIDTH));
        let corners = || {
            let deformed = self
                .bodies
                .iter()
                .flat_map(|b| b.triangles.iter().flatten());
            deformed.chain(self.bodies.iter().flat_map(|b| b.points.iter()))
        };
        let data = span(
            self.bodies.iter().flat_map(|b| b.stress.iter().copied()),
            0.0,
            0.0..0.0,
        );
        let stress = colour_range(&data);
        let (x, y) = equal_aspect(
            span(corners().map(|p| p.0), 0.03, 0.0..1.0),
            span(corners().map(|p| p.1), 0.03, 0.0..1.0),
            (w.saturating_sub(BAR_WIDTH + 72 + 42)) as f64 / (h - 48 - 60) as f64,
        );
        let length = self.units.length.as_deref();
        let frame = Frame {
            caption: format!(
                "von Mises stress, displacements × {} (red: undeformed)",
                tick(self.scale, &(0.0..self.scale))
            ),
            x_label: Units::label("x", length),
            y_label: Units::label("y", length),
        };
        let mut chart = linear(&left, &frame, x, y)?;
        let width = (stress.end - stress.start).max(f64::MIN_POSITIVE);
        for b in &self.bodies {
            let polys = b.triangles.iter().zip(&b.stress).map(|(t, &s)| {
                let c = viridis((s - stress.start) / width);
                Polygon::new(t.clone(), c.filled())
            });
            ok(chart.draw_series(polys))?;
        }
        let red = ShapeStyle::from(&RGBColor(200, 0, 0)).stroke_width(1);
        for b in &self.bodies {
            let paths = through_mids(outline(&b.cells), &b.cells, &b.mids);
            let lines = paths.into_iter().map(|path| {
                let pts = path.into_iter().map(|i| b.points[i]).collect::<Vec<_>>();
                PathElement::new(pts, red)
            });
            ok(chart.draw_series(lines))?;
        }
        let label = Units::label("von Mises", self.units.stress.as_deref());
        colour_bar(&right, &stress, &data, label)
    }
}

/// The colour scale of stresses spanning `data`: the data's own range, unless it is narrow next
/// to the values (a nearly uniform stress, 88.3 to 88.9), whose rounding noise would then paint
/// stark bands; such a range is widened to start at 0. An empty or all-zero range is 0..1.
fn colour_range(data: &Range<f64>) -> Range<f64> {
    let (lo, hi) = (data.start, data.end);
    if hi.is_nan() || hi <= 0.0 {
        return 0.0..1.0;
    }
    if hi - lo < 0.25 * hi.abs().max(lo.abs()) {
        0.0..hi
    } else {
        lo..hi
    }
}

/// The boundary of a triangle mesh as paths of node indices: the edges that only one triangle
/// has, chained end to end (a closed outline ends at its first node).
fn outline(cells: &[[usize; 3]]) -> Vec<Vec<usize>> {
    use std::collections::HashMap;
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    for c in cells {
        for (a, b) in [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])] {
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut edges: Vec<(usize, usize)> = count
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect();
    edges.sort_unstable();
    for &(a, b) in &edges {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut paths = Vec::new();
    for &(a, b) in &edges {
        if !unlink(&mut next, a, b) {
            continue;
        }
        let mut path = vec![a, b];
        let mut at = b;
        while let Some(&n) = next.get(&at).and_then(|v| v.first()) {
            unlink(&mut next, at, n);
            path.push(n);
            at = n;
        }
        paths.push(path);
    }
    paths
}

/// Removes the edge a–b from `next`; false if it was already gone.
fn unlink(next: &mut std::collections::HashMap<usize, Vec<usize>>, a: usize, b: usize) -> bool {
    let mut drop = |from: usize, to: usize| {
        next.get_mut(&from)
            .and_then(|v| v.iter().position(|&x| x == to).map(|i| v.swap_remove(i)))
            .is_some()
    };
    let found = drop(a, b);
    drop(b, a);
    found
}

/// Widens `x` or `y` about its centre so that one unit is as long on both axes, for a plotting
/// area `aspect` = width / height.
pub fn equal_aspect(x: Range<f64>, y: Range<f64>, aspect: f64) -> (Range<f64>, Range<f64>) {
    let (dx, dy) = (x.end - x.start, y.end - y.start);
    let widen = |r: Range<f64>, to: f64| {
        let c = 0.5 * (r.start + r.end);
        (c - 0.5 * to)..(c + 0.5 * to)
    };
    if dx / dy > aspect {
        (x, widen(y, dx / aspect))
    } else {
        (widen(x, dy * aspect), y)
    }
}

/// The colour bar of `range` with five labelled ticks, in `area`, titled `label`, and below it
/// the range of the values drawn (`data`).
pub fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    range: &Range<f64>,
    data: &Range<f64>,
    label: String,
) -> Result<()> {
    let (top, bottom, steps) = (60, 400, 85);
    ok(area.draw(&Text::new(label, (0, top - 30), ("sans-serif", 14))))?;
    let step = (bottom - top) / steps;
    for k in 0..steps {
        let t = 1.0 - (k as f64 + 0.5) / steps as f64;
        let y0 = top + k * step;
        ok(area.draw(&Rectangle::new(
            [(10, y0), (30, y0 + step)],
            viridis(t).filled(),
        )))?;
    }
    let bar_end = top + steps * step;
    for k in 0..=4 {
        let t = k as f64 / 4.0;
        let v = range.start + t * (range.end - range.start);
        let y = bar_end - ((bar_end - top) as f64 * t) as i32;
        ok(area.draw(&PathElement::new(vec![(30, y), (35, y)], BLACK)))?;
        ok(area.draw(&Text::new(tick(v, range), (38, y - 7), ("sans-serif", 13))))?;
    }
    let lines = [
        format!("min {}", significant(data.start)),
        format!("max {}", significant(data.end)),
    ];
    for (i, line) in lines.into_iter().enumerate() {
        let at = (0, bar_end + 14 + 17 * i as i32);
        ok(area.draw(&Text::new(line, at, ("sans-serif", 13))))?;
    }
    Ok(())
}

/// `v` to four significant digits, without trailing zeros (powers of ten beyond 1e5).
pub fn significant(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-2..5).contains(&magnitude) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - magnitude).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_last_load_step_is_drawn() {
        let files: Vec<String> = [
            "a-step1.vtu",
            "b-step1.vtu",
            "a-step2.vtu",
            "b-step2.vtu",
            "steps.csv",
        ]
        .map(String::from)
        .into();
        assert_eq!(last_step(&files), ["a-step2.vtu", "b-step2.vtu"]);
        let files: Vec<String> = ["lower.vtu", "upper.vtu", "contact.csv"]
            .map(String::from)
            .into();
        assert_eq!(last_step(&files), ["lower.vtu", "upper.vtu"]);
    }

    #[test]
    fn a_narrow_stress_range_is_widened_to_zero() {
        assert_eq!(colour_range(&(88.3..88.9)), 0.0..88.9);
        assert_eq!(colour_range(&(734.0..3898.0)), 734.0..3898.0);
        assert_eq!(colour_range(&(0.0..0.0)), 0.0..1.0);
        assert_eq!(significant(88.3), "88.3");
        assert_eq!(significant(3898.4), "3898");
        assert_eq!(significant(0.012345), "0.01235");
        assert_eq!(significant(2.5e6), "2.500e6");
    }

    #[test]
    fn the_outline_is_the_boundary_of_the_mesh() {
        // A square of two triangles: four boundary edges, the diagonal inside.
        let paths = outline(&[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(paths.len(), 1);
        let path = &paths[0];
        assert_eq!(path.len(), 5, "{path:?}");
        assert_eq!(path.first(), path.last());
        let mut nodes = path[..4].to_vec();
        nodes.sort_unstable();
        assert_eq!(nodes, [0, 1, 2, 3]);
        // Two separate triangles: two loops.
        assert_eq!(outline(&[[0, 1, 2], [3, 4, 5]]).len(), 2);
    }

    #[test]
    fn a_curved_edge_is_drawn_through_its_mid_side_node() {
        // The square's edge 1–2 bulges out through node 4; its other edges are straight.
        let cells = [[0, 1, 2], [0, 2, 3]];
        let mids = [[None, Some(4), None], [None; 3]];
        let paths = through_mids(outline(&cells), &cells, &mids);
        let path = &paths[0];
        assert_eq!(path.len(), 6, "{path:?}");
        let at = path.iter().position(|&v| v == 4).unwrap();
        let mut ends = [path[at - 1], path[at + 1]];
        ends.sort_unstable();
        assert_eq!(ends, [1, 2]);
        assert!(curved((1.0, 0.0), (1.0, 1.0), (1.1, 0.5)));
        assert!(!curved((1.0, 0.0), (1.0, 1.0), (1.0, 0.5)));
    }

    #[test]
    fn colours_run_from_dark_to_bright() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }
}
