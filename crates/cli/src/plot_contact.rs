//! The contact figures of `contactdd plot`, one pair at a time from `contact.csv`: the contact
//! pressure along the contact line (both sides), and the gap with each point's status. The
//! grouping of the points by pair and side, the coordinate along the line and the window shown
//! also serve the friction figure (`plot_friction`).

use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use contactdd_io::output::safe_file_name;

use crate::args::Format;
use crate::plot_data::{Table, Units};
use crate::plot_draw::{
    linear, ok, render, series, span, Figure, Frame, Legend, Line, Look, Marker, COLORS,
};

/// One contact point of `contact.csv`.
#[derive(Clone, Debug)]
pub struct Point {
    /// Undeformed x.
    pub x: f64,
    /// Undeformed y.
    pub y: f64,
    gap: f64,
    /// The contact pressure p ≥ 0.
    pub pressure: f64,
    status: String,
    /// Its row of the table (0 for the first row after the header).
    pub row: usize,
}

/// One side of a pair: the body and its points.
pub struct Side {
    /// The side's body.
    pub body: String,
    /// Its points, in the order of the file.
    pub points: Vec<Point>,
}

/// A pair: its name and sides, in the order of `contact.csv`.
pub struct Pair {
    /// The pair's name.
    pub name: String,
    /// Its sides, in the order of the file.
    pub sides: Vec<Side>,
}

impl Pair {
    /// The coordinate along the contact line: x when the points spread more along x, else y.
    /// Returns the axis name and the coordinate of a point.
    pub fn along(&self) -> (&'static str, fn(&Point) -> f64) {
        let all = || self.sides.iter().flat_map(|s| s.points.iter());
        let extent = |f: fn(&Point) -> f64| {
            let r = span(all().map(f), 0.0, 0.0..0.0);
            r.end - r.start
        };
        if extent(|p| p.x) >= extent(|p| p.y) {
            ("x", |p| p.x)
        } else {
            ("y", |p| p.y)
        }
    }
}

/// The pressure and gap figures of every pair of `contact.csv`.
pub fn figures(
    table: &Table,
    units: &Units,
    out: &Path,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for pair in pairs(table)? {
        let name = safe_file_name(&pair.name);
        let pressure = Pressure { pair: &pair, units };
        written.extend(render(
            &pressure,
            out,
            &format!("pressure-{name}"),
            formats,
        )?);
        let gap = Gap { pair: &pair, units };
        written.extend(render(&gap, out, &format!("gap-{name}"), formats)?);
    }
    Ok(written)
}

/// Groups the rows by pair and side, keeping the order of the file.
pub fn pairs(table: &Table) -> Result<Vec<Pair>> {
    let [pc, bc, xc, yc, gc, prc, sc] =
        ["pair", "body", "x", "y", "gap", "pressure", "status"].map(|n| table.column(n));
    let (pc, bc, sc) = (pc?, bc?, sc?);
    let (xc, yc, gc, prc) = (xc?, yc?, gc?, prc?);
    let mut pairs: Vec<Pair> = Vec::new();
    for (r, row) in table.rows.iter().enumerate() {
        let point = Point {
            x: table.number(r, xc)?,
            y: table.number(r, yc)?,
            gap: table.number(r, gc)?,
            pressure: table.number(r, prc)?,
            status: row[sc].clone(),
            row: r,
        };
        let pair = match pairs.iter_mut().position(|p| p.name == row[pc]) {
            Some(i) => &mut pairs[i],
            None => {
                pairs.push(Pair {
                    name: row[pc].clone(),
                    sides: Vec::new(),
                });
                let last = pairs.len() - 1;
                &mut pairs[last]
            }
        };
        match pair.sides.iter_mut().find(|s| s.body == row[bc]) {
            Some(side) => side.points.push(point),
            None => pair.sides.push(Side {
                body: row[bc].clone(),
                points: vec![point],
            }),
        }
    }
    if pairs.is_empty() {
        bail!("'{}' has no contact points", table.path.display());
    }
    Ok(pairs)
}

/// The look of side `s`: solid line and filled circles for the first, dashed line and crosses
/// for the second, so that coinciding curves both stay visible.
pub fn side_look(s: usize) -> Look {
    let color = COLORS[s % COLORS.len()];
    match s {
        0 => Look::new(color, Line::Solid, Marker::Circle),
        1 => Look::new(color, Line::Dashed, Marker::Cross),
        _ => Look::new(color, Line::Dotted, Marker::Square).hollow(4),
    }
}

/// The points of a side inside `window` along the contact line, sorted, as (coordinate, value).
fn curve(
    side: &Side,
    along: fn(&Point) -> f64,
    window: &Range<f64>,
    value: fn(&Point) -> f64,
) -> Vec<(f64, f64)> {
    let mut pts: Vec<(f64, f64)> = side
        .points
        .iter()
        .map(|p| (along(p), value(p)))
        .filter(|p| window.contains(&p.0))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// The stretch of the contact line to show: the pressed zone and as much again around it (a
/// Hertz contact is a small part of its boundary), within the points' own extent.
pub fn window(pair: &Pair, along: fn(&Point) -> f64) -> Range<f64> {
    let all = || pair.sides.iter().flat_map(|s| s.points.iter());
    let whole = span(all().map(along), 0.02, 0.0..1.0);
    let pressed = span(
        all().filter(|p| p.pressure > 0.0).map(along),
        0.5,
        whole.clone(),
    );
    pressed.start.max(whole.start)..pressed.end.min(whole.end)
}

/// The chart frame of a contact figure: the caption names the pair, the axes carry units.
pub fn frame(
    what: &str,
    pair: &Pair,
    axis: &str,
    y_label: &str,
    y_unit: Option<&str>,
    units: &Units,
) -> Frame {
    Frame {
        caption: format!("{what}, pair {}", pair.name),
        x_label: Units::label(axis, units.length.as_deref()),
        y_label: Units::label(y_label, y_unit),
    }
}

/// Contact pressure p ≥ 0 (`contact.csv`'s `pressure`) against the coordinate along the contact
/// line.
struct Pressure<'a> {
    pair: &'a Pair,
    units: &'a Units,
}

impl Figure for Pressure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (axis, along) = self.pair.along();
        let x = window(self.pair, along);
        let all = || self.pair.sides.iter().flat_map(|s| s.points.iter());
        let top = span(all().map(|p| p.pressure), 0.0, 0.0..1.0).end.max(0.0);
        let y = 0.0..if top > 0.0 { top * 1.1 } else { 1.0 };
        let mut legend = Legend::default();
        for (s, side) in self.pair.sides.iter().enumerate() {
            legend.add(side.body.clone(), side_look(s));
        }
        let (left, right) = legend.split(root);
        let stress = self.units.stress.as_deref();
        let frame = frame(
            "contact pressure",
            self.pair,
            axis,
            "contact pressure p",
            stress,
            self.units,
        );
        let mut chart = linear(&left, &frame, x.clone(), y)?;
        for (s, side) in self.pair.sides.iter().enumerate() {
            series(
                &mut chart,
                &curve(side, along, &x, |p| p.pressure),
                side_look(s),
            )?;
        }
        legend.draw(&right)
    }
}

/// The gap d − s along the contact line, each point marked by its status.
struct Gap<'a> {
    pair: &'a Pair,
    units: &'a Units,
}

/// The status markers: closed filled, open hollow, no partner a triangle on the top edge.
fn status_look(status: &str) -> Look {
    let grey = RGBColor(60, 60, 60);
    match status {
        "closed" => Look::new(grey, Line::None, Marker::Circle),
        "open" => Look::new(grey, Line::None, Marker::Circle).hollow(5),
        _ => Look::new(grey, Line::None, Marker::Triangle).hollow(5),
    }
}

const STATUSES: [(&str, &str); 3] = [
    ("closed", "closed"),
    ("open", "open"),
    ("no-partner", "no partner (gap ∞)"),
];

impl Figure for Gap<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (axis, along) = self.pair.along();
        let x = window(self.pair, along);
        let shown = || {
            self.pair
                .sides
                .iter()
                .flat_map(|s| s.points.iter())
                .filter(|p| x.contains(&along(p)))
        };
        let y = span(shown().map(|p| p.gap).chain([0.0]), 0.08, -1.0..1.0);
        let line = |s: usize| Look {
            marker: Marker::None,
            ..side_look(s)
        };
        let mut legend = Legend::default();
        for (s, side) in self.pair.sides.iter().enumerate() {
            legend.add(format!("{} gap", side.body), line(s));
        }
        for (status, label) in STATUSES {
            if shown().any(|p| p.status == status) {
                legend.add(label, status_look(status));
            }
        }
        let (left, right) = legend.split(root);
        let length = self.units.length.as_deref();
        let frame = frame(
            "gap and status",
            self.pair,
            axis,
            "gap d − s",
            length,
            self.units,
        );
        let top = y.end;
        let mut chart = linear(&left, &frame, x.clone(), y)?;
        let zero = LineSeries::new([(x.start, 0.0), (x.end, 0.0)], BLACK.mix(0.5));
        ok(chart.draw_series(zero))?;
        for (s, side) in self.pair.sides.iter().enumerate() {
            let mut finite = curve(side, along, &x, |p| p.gap);
            finite.retain(|p| p.1.is_finite());
            series(&mut chart, &finite, line(s))?;
        }
        for (status, _) in STATUSES {
            let pts: Vec<(f64, f64)> = shown()
                .filter(|p| p.status == status)
                .map(|p| (along(p), if p.gap.is_finite() { p.gap } else { top }))
                .collect();
            series(&mut chart, &pts, status_look(status))?;
        }
        legend.draw(&right)
    }
}
