//! The friction figure of `contactdd plot`, one per frictional pair: the tangential traction σ_t
//! (`contact.csv`'s `tangential_traction`) along the contact line, between the bounds of its
//! friction law (`summary.json`'s `contact[].friction`): ±μp for Coulomb, ±bound where p > 0 for
//! Tresca. Stick and slip zones (`contact.csv`'s `friction`) are shaded and each point is marked
//! by its status. A `contact.csv` without the friction columns gives no figure.

use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde_json::Value;

use contactdd_io::output::safe_file_name;

use crate::args::Format;
use crate::plot_contact::{frame, pairs, side_look, window, Pair, Point};
use crate::plot_data::{Table, Units};
use crate::plot_draw::{linear, ok, render, series, span, Figure, Legend, Line, Look, Marker};

/// The friction columns of `contact.csv`, after its frictionless ones.
const COLUMNS: [&str; 4] = ["tangential_traction", "slip", "total_slip", "friction"];

/// Where a point is on its friction disc (`contact.csv`'s `friction`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Status {
    Open,
    Stick,
    Slip,
}

impl Status {
    const ALL: [Status; 3] = [Status::Stick, Status::Slip, Status::Open];

    fn parse(text: &str) -> Option<Status> {
        match text {
            "open" => Some(Status::Open),
            "stick" => Some(Status::Stick),
            "slip" => Some(Status::Slip),
            _ => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Status::Open => "open",
            Status::Stick => "stick",
            Status::Slip => "slip",
        }
    }

    /// Stick a filled green dot, slip a filled orange triangle, open a grey ring.
    fn look(self) -> Look {
        match self {
            Status::Stick => Look::new(RGBColor(0, 158, 115), Line::None, Marker::Circle),
            Status::Slip => Look::new(RGBColor(230, 159, 0), Line::None, Marker::Triangle),
            Status::Open => Look::new(RGBColor(60, 60, 60), Line::None, Marker::Circle).hollow(5),
        }
    }
}

/// A pair's friction law (`summary.json`'s `contact[].friction`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Law {
    /// |σ_t| ≤ μ p.
    Coulomb(f64),
    /// |σ_t| ≤ bound where the pair presses (p > 0).
    Tresca(f64),
}

impl Law {
    /// Reads `{"law": "coulomb", "mu": μ}` or `{"law": "tresca", "bound": b}` (μ, b finite and
    /// ≥ 0); `file` and `pair` name it in the error.
    fn read(value: &Value, file: &Path, pair: &str) -> Result<Law> {
        let number = |key: &str| value[key].as_f64().filter(|v| v.is_finite() && *v >= 0.0);
        let law = match value["law"].as_str() {
            Some("coulomb") => number("mu").map(Law::Coulomb),
            Some("tresca") => number("bound").map(Law::Tresca),
            _ => None,
        };
        law.ok_or_else(|| {
            anyhow!(
                "'{}', pair '{pair}': friction {value} is not a friction law ({{\"law\": \"coulomb\", \"mu\": μ}} or {{\"law\": \"tresca\", \"bound\": b}}, μ and b ≥ 0)",
                file.display()
            )
        })
    }

    /// The bound on |σ_t| at a point of pressure `p`.
    fn limit(self, p: f64) -> f64 {
        match self {
            Law::Coulomb(mu) => mu * p.max(0.0),
            Law::Tresca(bound) if p > 0.0 => bound,
            Law::Tresca(_) => 0.0,
        }
    }

    fn label(self) -> String {
        match self {
            Law::Coulomb(mu) => format!("Coulomb ±μp, μ = {mu}"),
            Law::Tresca(bound) => format!("Tresca ±{bound} where p > 0"),
        }
    }
}

/// A point's friction record: its tangential traction and status.
#[derive(Clone, Copy, Debug)]
struct Record {
    traction: f64,
    status: Status,
}

/// Reads row `r`'s friction record (`cols`: the indices of [`COLUMNS`]): `None` where the
/// `friction` field is empty (a point without friction); every number is checked.
fn record(table: &Table, r: usize, cols: &[usize; 4]) -> Result<Option<Record>> {
    let text = table.rows[r][cols[3]].trim();
    if text.is_empty() {
        return Ok(None);
    }
    let Some(status) = Status::parse(text) else {
        bail!(
            "'{}' line {}, column 'friction': '{text}' is not a friction status (open, stick or slip)",
            table.path.display(),
            r + 2
        );
    };
    let traction = table.number(r, cols[0])?;
    for &c in &cols[1..3] {
        table.number(r, c)?;
    }
    Ok(Some(Record { traction, status }))
}

/// The friction figure of every frictional pair of `contact.csv`: a pair that `laws` (the
/// `contact[].friction` of `summary`, a path for messages) names, or one with a stick or slip
/// point. None when the table has no friction column.
pub fn figures(
    table: &Table,
    laws: &[(String, Value)],
    summary: &Path,
    units: &Units,
    out: &Path,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    if !COLUMNS.iter().any(|c| table.header.iter().any(|h| h == c)) {
        return Ok(Vec::new());
    }
    let [a, b, c, d] = COLUMNS.map(|c| table.column(c));
    let cols = [a?, b?, c?, d?];
    let mut written = Vec::new();
    for pair in pairs(table)? {
        let records = pair
            .sides
            .iter()
            .map(|s| {
                s.points
                    .iter()
                    .map(|p| record(table, p.row, &cols))
                    .collect()
            })
            .collect::<Result<Vec<Vec<_>>>>()?;
        let law = laws
            .iter()
            .find(|(name, _)| *name == pair.name)
            .map(|(_, v)| Law::read(v, summary, &pair.name))
            .transpose()?;
        let moving = |r: &Option<Record>| r.is_some_and(|r| r.status != Status::Open);
        if law.is_none() && !records.iter().flatten().any(moving) {
            continue;
        }
        let fig = Friction {
            pair: &pair,
            records: &records,
            law,
            units,
        };
        let name = safe_file_name(&pair.name);
        written.extend(render(&fig, out, &format!("friction-{name}"), formats)?);
    }
    Ok(written)
}

/// One point as drawn: its coordinate along the line, σ_t, p and status.
struct Drawn {
    at: f64,
    traction: f64,
    pressure: f64,
    status: Status,
}

/// σ_t of a frictional pair against the coordinate along the contact line.
struct Friction<'a> {
    pair: &'a Pair,
    /// Per side and point, its friction record.
    records: &'a [Vec<Option<Record>>],
    law: Option<Law>,
    units: &'a Units,
}

impl Friction<'_> {
    /// The sides that carry the tangential traction (the reference side of a balanced pair:
    /// some point not open or σ_t ≠ 0), each with its points inside `window`, sorted; every
    /// side with records when none carries.
    fn carriers(&self, along: fn(&Point) -> f64, window: &Range<f64>) -> Vec<(usize, Vec<Drawn>)> {
        let drawn = |s: usize| -> Vec<Drawn> {
            let side = &self.pair.sides[s];
            let mut pts: Vec<Drawn> = side
                .points
                .iter()
                .zip(&self.records[s])
                .filter_map(|(p, r)| r.map(|r| (p, r)))
                .filter(|(p, _)| window.contains(&along(p)))
                .map(|(p, r)| Drawn {
                    at: along(p),
                    traction: r.traction,
                    pressure: p.pressure,
                    status: r.status,
                })
                .collect();
            pts.sort_by(|a, b| a.at.total_cmp(&b.at));
            pts
        };
        let carries = |s: &usize| {
            self.records[*s]
                .iter()
                .flatten()
                .any(|r| r.status != Status::Open || r.traction != 0.0)
        };
        let sides = 0..self.pair.sides.len();
        let mut chosen: Vec<usize> = sides.clone().filter(carries).collect();
        if chosen.is_empty() {
            chosen = sides
                .filter(|&s| self.records[s].iter().any(Option::is_some))
                .collect();
        }
        chosen.into_iter().map(|s| (s, drawn(s))).collect()
    }
}

/// The stretches of the line where the points stick or slip: each point owns the line up to
/// halfway to its neighbours (its own position at the ends); neighbours of one status merge.
fn zones(points: &[Drawn]) -> Vec<(Range<f64>, Status)> {
    let mut zones: Vec<(Range<f64>, Status)> = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let before = i
            .checked_sub(1)
            .map_or(p.at, |j| 0.5 * (points[j].at + p.at));
        let after = points.get(i + 1).map_or(p.at, |q| 0.5 * (p.at + q.at));
        if p.status == Status::Open {
            continue;
        }
        match zones.last_mut() {
            Some((r, s)) if *s == p.status && r.end == before => r.end = after,
            _ => zones.push((before..after, p.status)),
        }
    }
    zones
}

impl Figure for Friction<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (axis, along) = self.pair.along();
        let x = window(self.pair, along);
        let sides = self.carriers(along, &x);
        let all = || sides.iter().flat_map(|(_, pts)| pts.iter());
        let limit = |p: &Drawn| self.law.map_or(0.0, |l| l.limit(p.pressure));
        let values = all().flat_map(|p| [p.traction, limit(p), -limit(p)]);
        let y = span(values.chain([0.0]), 0.08, -1.0..1.0);
        let mut legend = Legend::default();
        // The side's colour of the pressure figure; solid for the first side drawn (usually the
        // only one), dashed for a second.
        let line = |k: usize| Look {
            color: side_look(sides[k].0).color,
            marker: Marker::None,
            ..side_look(k)
        };
        for (k, (s, _)) in sides.iter().enumerate() {
            legend.add(format!("σ_t on {}", self.pair.sides[*s].body), line(k));
        }
        let bound = Look::new(RGBColor(90, 90, 90), Line::Solid, Marker::None);
        if let Some(law) = self.law {
            legend.add(law.label(), bound);
        }
        for status in Status::ALL {
            if all().any(|p| p.status == status) {
                legend.add(status.name(), status.look());
            }
        }
        let (left, right) = legend.split(root);
        let stress = self.units.stress.as_deref();
        let what = "tangential traction and friction bound";
        let frame = frame(
            what,
            self.pair,
            axis,
            "tangential traction σ_t",
            stress,
            self.units,
        );
        let mut chart = linear(&left, &frame, x.clone(), y.clone())?;
        for (_, pts) in &sides {
            let shades = zones(pts).into_iter().map(|(r, status)| {
                let style = status.look().color.mix(0.18).filled();
                Rectangle::new([(r.start, y.start), (r.end, y.end)], style)
            });
            ok(chart.draw_series(shades))?;
        }
        let zero = LineSeries::new([(x.start, 0.0), (x.end, 0.0)], BLACK.mix(0.5));
        ok(chart.draw_series(zero))?;
        for (k, (_, pts)) in sides.iter().enumerate() {
            if self.law.is_some() {
                for sign in [1.0, -1.0] {
                    let edge: Vec<(f64, f64)> =
                        pts.iter().map(|p| (p.at, sign * limit(p))).collect();
                    series(&mut chart, &edge, bound)?;
                }
            }
            let curve: Vec<(f64, f64)> = pts.iter().map(|p| (p.at, p.traction)).collect();
            series(&mut chart, &curve, line(k))?;
        }
        for status in Status::ALL {
            let pts: Vec<(f64, f64)> = all()
                .filter(|p| p.status == status)
                .map(|p| (p.at, p.traction))
                .collect();
            series(&mut chart, &pts, status.look())?;
        }
        legend.draw(&right)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(at: f64, status: Status) -> Drawn {
        Drawn {
            at,
            traction: 0.0,
            pressure: 0.0,
            status,
        }
    }

    #[test]
    fn zones_run_halfway_to_the_neighbours() {
        use Status::{Open, Slip, Stick};
        let pts = [
            at(0.0, Slip),
            at(1.0, Stick),
            at(2.0, Stick),
            at(3.0, Open),
            at(5.0, Slip),
        ];
        let z = zones(&pts);
        assert_eq!(z, [(0.0..0.5, Slip), (0.5..2.5, Stick), (4.0..5.0, Slip)]);
    }

    #[test]
    fn laws_and_their_bounds() {
        let file = Path::new("summary.json");
        let read = |v: Value| Law::read(&v, file, "p");
        let coulomb = read(serde_json::json!({"law": "coulomb", "mu": 0.3})).unwrap();
        assert_eq!(coulomb.limit(10.0), 3.0);
        assert_eq!(coulomb.limit(0.0), 0.0);
        let tresca = read(serde_json::json!({"law": "tresca", "bound": 5.0})).unwrap();
        assert_eq!((tresca.limit(0.1), tresca.limit(0.0)), (5.0, 0.0));
        for bad in [
            serde_json::json!({"law": "coulomb", "bound": 5.0}),
            serde_json::json!({"law": "tresca", "bound": -1.0}),
            serde_json::json!({"law": "viscous", "mu": 0.3}),
            serde_json::json!("coulomb"),
        ] {
            let e = read(bad).unwrap_err().to_string();
            assert!(
                e.contains("pair 'p'") && e.contains("not a friction law"),
                "{e}"
            );
        }
    }
}
