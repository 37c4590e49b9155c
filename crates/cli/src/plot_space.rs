//! The figures of a result folder in space (`"dimension": 3` in `summary.json`), one contact
//! pair at a time from `contact.csv` (`pair,body,node,x,y,z,weight,gap,pressure`): the contact
//! pressure as a map over the contact surface seen along its normal, and the pressure against
//! the distance from the centre of the pressure (the radial profile).
//!
//! `contact.csv` carries no normals, so the direction of view is found from the points
//! themselves: the direction in which they spread least (the smallest principal direction of
//! their covariance, each point weighted by its force w·p, or by its area w when nothing is
//! pressed). A view within 10° of a coordinate axis looks along that axis and keeps the other two
//! coordinates as they are; any other view projects onto the plane through the points' centroid.

use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use contactdd_io::output::safe_file_name;

use crate::args::{Format, PlotArgs};
use crate::plot_data::{space_force_unit, Summary, Table, Units};
use crate::plot_draw::{linear, ok, render, series, span, Figure, Frame, Line, Look, Marker};
use crate::plot_draw::{tick, COLORS};
use crate::plot_mesh::{colour_bar, equal_aspect, significant, viridis, BAR_WIDTH};
use crate::plot_steps;

/// A view looks along a coordinate axis when the normal is within 10° of it: cos 10°.
const SNAP_COS: f64 = 0.984_807_753_012_208;

type Vec3 = [f64; 3];

/// One contact point of `contact.csv`.
struct SpacePoint {
    at: Vec3,
    weight: f64,
    pressure: f64,
}

/// A pair: its points (every side's, in the order of the file) and its totals.
struct SpacePair {
    name: String,
    points: Vec<SpacePoint>,
    /// The resultant normal force: `summary.json`'s `normal_force`, else Σ w p.
    force: f64,
    /// The peak pressure: `summary.json`'s `peak_pressure`, else the largest p.
    peak: f64,
}

impl SpacePair {
    /// The largest pressure of `contact.csv`'s points (0 when none is pressed).
    fn largest(&self) -> f64 {
        self.points.iter().map(|p| p.pressure).fold(0.0, f64::max)
    }
}

/// Says on stderr which options have no meaning for a result in space and are ignored.
pub fn notes(args: &PlotArgs) {
    if args.tol.is_some() {
        eprintln!(
            "note: --tol is ignored: it draws the tolerance line of a convergence history, \
             which a result in space does not have"
        );
    }
    if args.problem.is_some() {
        eprintln!(
            "note: --problem is ignored for a result in space (dimension = 3); give the axes' \
             units with --units"
        );
    }
}

/// The pressure map and the radial profile of every pair of the folder `dir` in space.
pub fn figures(
    dir: &Path,
    summary: &Summary,
    units: &Units,
    out: &Path,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for pair in read_pairs(dir, summary)? {
        let view = View::of(&pair.points);
        let flat: Vec<(f64, f64)> = pair.points.iter().map(|p| view.project(p.at)).collect();
        let name = safe_file_name(&pair.name);
        let map = Map {
            pair: &pair,
            view: &view,
            flat: &flat,
            window: window(&flat, &pair.points),
            units,
        };
        written.extend(render(&map, out, &format!("pressure-map-{name}"), formats)?);
        let centre = centre(&flat, &pair.points);
        let mut radial: Vec<(f64, f64)> = (flat.iter().zip(&pair.points))
            .map(|(f, p)| (distance(*f, centre), p.pressure))
            .collect();
        radial.sort_by(|a, b| a.0.total_cmp(&b.0));
        // The pressed zone and as much again.
        let pressed = radial.iter().filter(|r| r.1 > 0.0).map(|r| r.0);
        if let Some(limit) = pressed.reduce(f64::max).filter(|l| *l > 0.0) {
            radial.retain(|r| r.0 <= 2.0 * limit);
        }
        let profile = Profile {
            pair: &pair,
            radial,
            centre: view.lift(centre, &pair.points),
            size: extent(&pair.points),
            units,
        };
        let stem = format!("pressure-profile-{name}");
        written.extend(render(&profile, out, &stem, formats)?);
    }
    // A load history: the load–displacement curve and the forces against the load factor.
    let steps = dir.join("steps.csv");
    if steps.is_file() {
        let table = Table::read(&steps)?;
        let units = Units {
            space: true,
            ..units.clone()
        };
        written.extend(plot_steps::figures(&table, &units, None, out, formats)?);
    }
    Ok(written)
}

/// The pairs of `dir/contact.csv`, which the summary must list and the folder hold.
fn read_pairs(dir: &Path, summary: &Summary) -> Result<Vec<SpacePair>> {
    let path = dir.join("contact.csv");
    if !summary.has("contact.csv") {
        bail!(
            "'{}': a result in space (\"dimension\": 3) whose file list names no contact.csv; \
             its figures are drawn from contact.csv (see docs/plots.md)",
            dir.join("summary.json").display()
        );
    }
    if std::fs::symlink_metadata(&path).is_err() {
        bail!(
            "'{}' is missing: summary.json lists it, and the figures of a result in space are \
             drawn from it",
            path.display()
        );
    }
    let table = Table::read(&path)?;
    let columns = ["pair", "x", "y", "z", "weight", "pressure"].map(|n| table.column(n));
    let [pc, xc, yc, zc, wc, prc] = columns;
    let (pc, xc, yc, zc, wc, prc) = (pc?, xc?, yc?, zc?, wc?, prc?);
    let mut pairs: Vec<SpacePair> = Vec::new();
    for (r, row) in table.rows.iter().enumerate() {
        let finite = |c: usize| -> Result<f64> {
            let v = table.number(r, c)?;
            if !v.is_finite() {
                bail!(
                    "'{}' line {}, column '{}': {v} is not a finite number",
                    path.display(),
                    r + 2,
                    table.header[c]
                );
            }
            Ok(v)
        };
        let point = SpacePoint {
            at: [finite(xc)?, finite(yc)?, finite(zc)?],
            weight: finite(wc)?.max(0.0),
            pressure: finite(prc)?,
        };
        match pairs.iter_mut().find(|p| p.name == row[pc]) {
            Some(pair) => pair.points.push(point),
            None => pairs.push(SpacePair {
                name: row[pc].clone(),
                points: vec![point],
                force: 0.0,
                peak: 0.0,
            }),
        }
    }
    if pairs.is_empty() {
        bail!("'{}' has no contact points", path.display());
    }
    for pair in &mut pairs {
        let recorded = summary.totals.iter().find(|t| t.name == pair.name);
        let sum = pair.points.iter().map(|p| p.weight * p.pressure).sum();
        pair.force = recorded.and_then(|t| t.normal_force).unwrap_or(sum);
        pair.peak = recorded
            .and_then(|t| t.peak_pressure)
            .unwrap_or_else(|| pair.largest());
    }
    Ok(pairs)
}

/// The plane a pair's pressure is drawn on.
struct View {
    /// The origin of the in-plane coordinates.
    origin: Vec3,
    /// The in-plane unit directions (horizontal, vertical on the figure).
    axes: [Vec3; 2],
    /// The unit normal of the plane.
    normal: Vec3,
    /// The axes' names: coordinates (`x`, `y`) or directions.
    names: [String; 2],
}

impl View {
    /// The view of `points` along their normal (see the module's documentation).
    fn of(points: &[SpacePoint]) -> View {
        let (centroid, normal) = plane(points);
        let k = (0..3)
            .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
            .unwrap_or(2);
        if normal[k].abs() >= SNAP_COS {
            // Along a coordinate axis: the other two coordinates as they are.
            let (a, b) = [(1, 2), (0, 2), (0, 1)][k];
            return View {
                origin: [0.0; 3],
                axes: [unit(a), unit(b)],
                normal: unit(k),
                names: [AXES[a].into(), AXES[b].into()],
            };
        }
        // The coordinate axis farthest from the normal, projected onto the plane, is horizontal.
        let a = (0..3)
            .min_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
            .unwrap_or(0);
        let e1 = normalized(sub(unit(a), scale(normal, normal[a])));
        let e2 = cross(normal, e1);
        let name = |e: Vec3| {
            let c = e.map(|v| tick(v, &(-1.0..1.0)));
            format!("along ({}, {}, {}) from the centroid", c[0], c[1], c[2])
        };
        View {
            origin: centroid,
            axes: [e1, e2],
            normal,
            names: [name(e1), name(e2)],
        }
    }

    /// The in-plane coordinates of `p`.
    fn project(&self, p: Vec3) -> (f64, f64) {
        let d = sub(p, self.origin);
        (dot(d, self.axes[0]), dot(d, self.axes[1]))
    }

    /// The point of the plane at `flat`, at the points' mean depth along the normal (weighted as
    /// the plane is fitted).
    fn lift(&self, flat: (f64, f64), points: &[SpacePoint]) -> Vec3 {
        let w = weights(points);
        let total: f64 = w.iter().sum();
        let depth = (points.iter().zip(&w))
            .map(|(p, w)| w * dot(sub(p.at, self.origin), self.normal))
            .sum::<f64>()
            / total;
        let [e1, e2] = self.axes;
        let at = add(scale(e1, flat.0), scale(e2, flat.1));
        add(self.origin, add(at, scale(self.normal, depth)))
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// Each point's weight in the fitted plane: its force w·p, or its area w when no point is
/// pressed, or 1 when no point has an area.
fn weights(points: &[SpacePoint]) -> Vec<f64> {
    let force: Vec<f64> = points
        .iter()
        .map(|p| p.weight * p.pressure.max(0.0))
        .collect();
    if force.iter().sum::<f64>() > 0.0 {
        return force;
    }
    let area: Vec<f64> = points.iter().map(|p| p.weight).collect();
    if area.iter().sum::<f64>() > 0.0 {
        return area;
    }
    vec![1.0; points.len()]
}

/// The weighted centroid of `points` and the direction in which they spread least.
fn plane(points: &[SpacePoint]) -> (Vec3, Vec3) {
    let w = weights(points);
    let total: f64 = w.iter().sum();
    let mut c = [0.0; 3];
    for (p, w) in points.iter().zip(&w) {
        c = add(c, scale(p.at, w / total));
    }
    let mut cov = [[0.0; 3]; 3];
    for (p, w) in points.iter().zip(&w) {
        let d = sub(p.at, c);
        for (i, row) in cov.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v += w * d[i] * d[j] / total;
            }
        }
    }
    (c, least_direction(cov))
}

/// The unit eigenvector of the smallest eigenvalue of the symmetric 3 × 3 matrix `a` (cyclic
/// Jacobi rotations).
fn least_direction(mut a: [[f64; 3]; 3]) -> Vec3 {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diagonal = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-30 * diagonal || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut().chain(v.iter_mut()) {
                let (kp, kq) = (row[p], row[q]);
                row[p] = c * kp - s * kq;
                row[q] = s * kp + c * kq;
            }
            for k in 0..3 {
                let (pk, qk) = (a[p][k], a[q][k]);
                a[p][k] = c * pk - s * qk;
                a[q][k] = s * pk + c * qk;
            }
        }
    }
    let i = (0..3)
        .min_by(|&i, &j| a[i][i].total_cmp(&a[j][j]))
        .unwrap_or(2);
    normalized([v[0][i], v[1][i], v[2][i]])
}

/// The centre of the pressure in the plane: the apex of the paraboloid p² = α + β u + γ v −
/// δ (u² + v²) fitted by least squares (weights w) to the pressed points, which is the centre of
/// a Hertz contact (p² = p₀² (1 − r²/a²)) even in a model cut along its symmetry planes; else
/// (no apex: δ under 0.1 % of the largest p², or an apex outside the pressed points' extent) the
/// pressure-weighted centroid Σ w p (u, v) / Σ w p.
fn centre(flat: &[(f64, f64)], points: &[SpacePoint]) -> (f64, f64) {
    let pressed: Vec<((f64, f64), f64, f64)> = (flat.iter().zip(points))
        .filter(|(_, p)| p.pressure > 0.0)
        .map(|(f, p)| (*f, p.weight, p.pressure))
        .collect();
    let force: f64 = pressed.iter().map(|(_, w, p)| w * p).sum();
    if pressed.is_empty() || force <= 0.0 {
        let n = flat.len().max(1) as f64;
        return flat
            .iter()
            .fold((0.0, 0.0), |c, f| (c.0 + f.0 / n, c.1 + f.1 / n));
    }
    let centroid = pressed.iter().fold((0.0, 0.0), |c, ((u, v), w, p)| {
        (c.0 + u * w * p / force, c.1 + v * w * p / force)
    });
    let u = span(pressed.iter().map(|x| x.0 .0), 0.1, 0.0..0.0);
    let v = span(pressed.iter().map(|x| x.0 .1), 0.1, 0.0..0.0);
    let size = (u.end - u.start).max(v.end - v.start);
    apex(&pressed, centroid, size)
        .filter(|a| u.contains(&a.0) && v.contains(&a.1))
        .unwrap_or(centroid)
}

/// The apex of the paraboloid of [`centre`], fitted in coordinates about `at` scaled by `size`.
fn apex(pressed: &[((f64, f64), f64, f64)], at: (f64, f64), size: f64) -> Option<(f64, f64)> {
    if size <= 0.0 {
        return None;
    }
    let mut m = [[0.0; 5]; 4];
    let mut top: f64 = 0.0;
    for &((u, v), w, p) in pressed {
        let (u, v) = ((u - at.0) / size, (v - at.1) / size);
        let phi = [1.0, u, v, -(u * u + v * v)];
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] += w * phi[i] * phi[j];
            }
            m[i][4] += w * phi[i] * p * p;
        }
        top = top.max(p * p);
    }
    let [_, beta, gamma, delta] = solve4(m)?;
    if delta.is_nan() || delta <= 1e-3 * top {
        return None;
    }
    let (u, v) = (beta / (2.0 * delta), gamma / (2.0 * delta));
    Some((at.0 + u * size, at.1 + v * size))
}

/// The solution of the 4 × 4 system whose augmented matrix is `m` (Gaussian elimination with
/// partial pivoting); `None` when it is singular.
fn solve4(mut m: [[f64; 5]; 4]) -> Option<[f64; 4]> {
    let scale = m
        .iter()
        .flat_map(|r| r[..4].iter())
        .fold(0.0, |a: f64, v| a.max(v.abs()));
    for col in 0..4 {
        let pivot = (col..4).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].is_nan() || m[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        m.swap(col, pivot);
        for row in col + 1..4 {
            let f = m[row][col] / m[col][col];
            for k in col..5 {
                m[row][k] -= f * m[col][k];
            }
        }
    }
    let mut x = [0.0; 4];
    for row in (0..4).rev() {
        let known: f64 = (row + 1..4).map(|k| m[row][k] * x[k]).sum();
        x[row] = (m[row][4] - known) / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The largest extent of `points` along a coordinate axis.
fn extent(points: &[SpacePoint]) -> f64 {
    (0..3)
        .map(|k| {
            let r = span(points.iter().map(|p| p.at[k]), 0.0, 0.0..0.0);
            r.end - r.start
        })
        .fold(0.0, f64::max)
}

fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

fn unit(k: usize) -> Vec3 {
    let mut e = [0.0; 3];
    e[k] = 1.0;
    e
}

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: Vec3, s: f64) -> Vec3 {
    a.map(|v| v * s)
}

fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a` scaled to length 1 (the z axis for a zero vector).
fn normalized(a: Vec3) -> Vec3 {
    let n = dot(a, a).sqrt();
    if n > 0.0 && n.is_finite() {
        scale(a, 1.0 / n)
    } else {
        unit(2)
    }
}

/// The unit of a force in space ([`crate::plot_data::space_force_unit`]).
fn force_unit(units: &Units) -> Option<String> {
    let (stress, length) = (units.stress.as_deref()?, units.length.as_deref()?);
    Some(space_force_unit(stress, length))
}

/// `value` with its unit, if any.
fn with_unit(value: f64, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{} {u}", significant(value)),
        None => significant(value),
    }
}

/// The pressure of a pair over its contact surface, seen along the normal: a disc per point,
/// of the point's area w, coloured by its pressure on the scale [0, the largest pressure].
struct Map<'a> {
    pair: &'a SpacePair,
    view: &'a View,
    flat: &'a [(f64, f64)],
    /// The stretch of each in-plane axis shown ([`window`]).
    window: [Range<f64>; 2],
    units: &'a Units,
}

/// The part of the plane to show: the pressed zone and as much again around it on each axis
/// (a Hertz contact is a small part of its contact surface), within the points' own extent.
fn window(flat: &[(f64, f64)], points: &[SpacePoint]) -> [Range<f64>; 2] {
    let axis = |f: fn(&(f64, f64)) -> f64| {
        let whole = span(flat.iter().map(f), 0.0, 0.0..0.0);
        let pressed = (flat.iter().zip(points)).filter(|(_, p)| p.pressure > 0.0);
        let zone = span(pressed.map(|(x, _)| f(x)), 0.5, whole.clone());
        zone.start.max(whole.start)..zone.end.min(whole.end)
    };
    [axis(|f| f.0), axis(|f| f.1)]
}

impl Figure for Map<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (w, h) = root.dim_in_pixel();
        let (left, right) = root.split_horizontally(w.saturating_sub(BAR_WIDTH));
        let points = &self.pair.points;
        let shown = |i: &usize| {
            let inside = |r: &Range<f64>, v: f64| r.start <= v && v <= r.end;
            inside(&self.window[0], self.flat[*i].0) && inside(&self.window[1], self.flat[*i].1)
        };
        let reach = (0..points.len())
            .filter(shown)
            .map(|i| (points[i].weight / std::f64::consts::PI).sqrt())
            .fold(0.0, f64::max);
        let widen = |r: &Range<f64>| {
            let pad = reach.max(0.03 * (r.end - r.start));
            (r.start - pad)..(r.end + pad)
        };
        let (x, y) = equal_aspect(
            widen(&self.window[0]),
            widen(&self.window[1]),
            (w.saturating_sub(BAR_WIDTH + 72 + 42)) as f64 / (h - 48 - 60) as f64,
        );
        let length = self.units.length.as_deref();
        let frame = Frame {
            caption: title(self.pair, self.units),
            x_label: Units::label(&self.view.names[0], length),
            y_label: Units::label(&self.view.names[1], length),
        };
        let mut chart = linear(&left, &frame, x.clone(), y)?;
        let (pixels, _) = chart.plotting_area().dim_in_pixel();
        let per_unit = pixels as f64 / (x.end - x.start);
        let largest = self.pair.largest();
        let bar = 0.0..if largest > 0.0 { largest } else { 1.0 };
        // The highest pressures last, on top.
        let mut order: Vec<usize> = (0..self.flat.len()).filter(shown).collect();
        let count = order.len();
        order.sort_by(|&a, &b| points[a].pressure.total_cmp(&points[b].pressure));
        let discs = order.into_iter().map(|i| {
            let radius = (points[i].weight / std::f64::consts::PI).sqrt() * per_unit;
            let colour = viridis(points[i].pressure / bar.end);
            Circle::new(
                self.flat[i],
                radius.round().max(1.0) as u32,
                colour.filled(),
            )
        });
        ok(chart.draw_series(discs))?;
        let data = span(points.iter().map(|p| p.pressure), 0.0, 0.0..0.0);
        let label = Units::label("pressure", self.units.stress.as_deref());
        colour_bar(&right, &bar, &data, label)?;
        let note = format!("{count} of {} points", points.len());
        ok(right.draw(&Text::new(note, (0, 440), ("sans-serif", 13))))
    }
}

/// The caption of a pair's figures: its name, normal force and peak pressure.
fn title(pair: &SpacePair, units: &Units) -> String {
    format!(
        "pair {}: normal force {}, peak {}",
        pair.name,
        with_unit(pair.force, force_unit(units).as_deref()),
        with_unit(pair.peak, units.stress.as_deref())
    )
}

/// The pressure of every point of a pair against its distance from the centre of the pressure,
/// in the plane of the map.
struct Profile<'a> {
    pair: &'a SpacePair,
    /// (distance, pressure), by increasing distance.
    radial: Vec<(f64, f64)>,
    /// The centre, in the problem's coordinates.
    centre: Vec3,
    /// The extent of the pair's points, for the centre's digits.
    size: f64,
    units: &'a Units,
}

impl Figure for Profile<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let reach = self.radial.last().map_or(0.0, |r| r.0);
        let x = 0.0..if reach > 0.0 { reach * 1.03 } else { 1.0 };
        let largest = self.pair.largest();
        let y = 0.0..if largest > 0.0 { largest * 1.1 } else { 1.0 };
        let c = self.centre.map(|v| tick(v, &(0.0..self.size)));
        let frame = Frame {
            caption: title(self.pair, self.units),
            x_label: Units::label(
                &format!("distance from the centre ({}, {}, {})", c[0], c[1], c[2]),
                self.units.length.as_deref(),
            ),
            y_label: Units::label("contact pressure p", self.units.stress.as_deref()),
        };
        let mut chart = linear(root, &frame, x, y)?;
        let look = Look {
            size: 3,
            ..Look::new(COLORS[0], Line::None, Marker::Circle)
        };
        series(&mut chart, &self.radial, look)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(at: Vec3, pressure: f64) -> SpacePoint {
        SpacePoint {
            at,
            weight: 1.0,
            pressure,
        }
    }

    #[test]
    fn the_least_direction_is_the_smallest_eigenvector() {
        // A rotated diagonal matrix: eigenvalues 3, 2, 1 on the directions of r1, r2, r3.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let r = [[s, s, 0.0], [-s, s, 0.0], [0.0, 0.0, 1.0]];
        let lambda = [1.0, 3.0, 2.0];
        let mut a = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] = (0..3).map(|k| r[k][i] * lambda[k] * r[k][j]).sum();
            }
        }
        let n = least_direction(a);
        assert!((dot(n, r[0]).abs() - 1.0).abs() < 1e-12, "{n:?}");
    }

    #[test]
    fn a_tilted_plane_is_seen_along_its_normal() {
        // Points on the plane x + z = 1 (normal (1, 0, 1)/√2): not near an axis.
        let pts: Vec<SpacePoint> = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.3)]
            .iter()
            .map(|&(x, y)| point([x, y, 1.0 - x], 1.0))
            .collect();
        let view = View::of(&pts);
        let n = std::f64::consts::FRAC_1_SQRT_2;
        assert!((dot(view.normal, [n, 0.0, n]).abs() - 1.0).abs() < 1e-12);
        // Distances in the plane are distances in space.
        let (a, b) = (view.project(pts[0].at), view.project(pts[3].at));
        assert!((distance(a, b) - 3f64.sqrt()).abs() < 1e-12);
        // A plane z = 0.5: the view keeps x and y.
        let flat: Vec<SpacePoint> = [(0.0, 0.0), (2.0, 0.0), (0.0, 1.0)]
            .iter()
            .map(|&(x, y)| point([x, y, 0.5], 1.0))
            .collect();
        let view = View::of(&flat);
        assert_eq!(view.names, ["x", "y"]);
        assert_eq!(view.project([2.0, 1.0, 0.5]), (2.0, 1.0));
    }

    #[test]
    fn the_centre_of_a_hertz_quarter_is_its_corner() {
        // p = √(1 − r²) on a quarter disc of the grid: the apex is the origin, where the
        // pressure-weighted centroid is not.
        let mut flat = Vec::new();
        let mut pts = Vec::new();
        for i in 0..12 {
            for j in 0..12 {
                let (u, v) = (0.1 * i as f64, 0.1 * j as f64);
                flat.push((u, v));
                pts.push(point([u, v, 0.0], (1.0 - u * u - v * v).max(0.0).sqrt()));
            }
        }
        let c = centre(&flat, &pts);
        assert!(c.0.abs() < 1e-9 && c.1.abs() < 1e-9, "{c:?}");
        // A uniform pressure has no apex: the centroid.
        pts.iter_mut().for_each(|p| p.pressure = 2.0);
        let c = centre(&flat, &pts);
        assert!(
            (c.0 - 0.55).abs() < 1e-12 && (c.1 - 0.55).abs() < 1e-12,
            "{c:?}"
        );
    }

    #[test]
    fn force_units_in_space() {
        let units = |s: &str| Units::parse(Some(s));
        assert_eq!(force_unit(&units("mm, MPa")).as_deref(), Some("N"));
        assert_eq!(force_unit(&units("m, MPa")).as_deref(), Some("MN"));
        assert_eq!(force_unit(&units("cm, N/cm^2")).as_deref(), Some("N"));
        assert_eq!(
            force_unit(&units("mm, N/cm^2")).as_deref(),
            Some("N/cm^2·mm²")
        );
        assert_eq!(force_unit(&Units::default()), None);
    }
}
