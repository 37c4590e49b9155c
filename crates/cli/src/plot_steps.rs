//! The load-step figures of `contactdd plot`, from `steps.csv`: the load–displacement curve (the
//! monitored displacement against each pair's resultant contact force) and the force against the
//! load factor; with friction (`<pair>_tangential_force` columns), each frictional pair's
//! resultant tangential force against the load factor. Every curve starts at the unloaded state
//! (0, 0); steps that did not converge are marked apart.

use std::path::{Path, PathBuf};

use anyhow::Result;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::args::Format;
use crate::plot_data::{Table, Units};
use crate::plot_draw::{
    linear, ok, render, series, span, Figure, Frame, Legend, Line, Look, Marker, COLORS,
};

/// The columns of `steps.csv` that the figures use.
struct Steps {
    factor: Vec<f64>,
    converged: Vec<bool>,
    /// The monitored displacement component that moves most, with its name, if monitored.
    monitor: Option<(&'static str, Vec<f64>)>,
    /// Per pair, its name and |F| per step (the resultant on its first body).
    forces: Vec<(String, Vec<f64>)>,
    /// Per frictional pair, its name and the resultant tangential force Σ w σ_t per step.
    tangential: Vec<(String, Vec<f64>)>,
}

/// `load-displacement` (with a monitor), `steps-force`, and `steps-tangential-force` (with
/// friction); `monitor` names the monitored boundary ("top of upper") when known.
pub fn figures(
    table: &Table,
    units: &Units,
    monitor: Option<&str>,
    out: &Path,
    formats: &[Format],
) -> Result<Vec<PathBuf>> {
    let steps = read(table)?;
    let mut written = Vec::new();
    if steps.monitor.is_some() {
        let fig = StepFigure {
            steps: &steps,
            units,
            monitor,
            against_factor: false,
        };
        written.extend(render(&fig, out, "load-displacement", formats)?);
    }
    let fig = StepFigure {
        steps: &steps,
        units,
        monitor,
        against_factor: true,
    };
    written.extend(render(&fig, out, "steps-force", formats)?);
    if !steps.tangential.is_empty() {
        let fig = Tangential {
            steps: &steps,
            units,
        };
        written.extend(render(&fig, out, "steps-tangential-force", formats)?);
    }
    Ok(written)
}

fn read(table: &Table) -> Result<Steps> {
    let converged_col = table.column("converged")?;
    let converged = table
        .rows
        .iter()
        .map(|r| r[converged_col] == "true")
        .collect();
    let monitor = monitored(table)?;
    let mut forces = Vec::new();
    for name in &table.header {
        if let Some(pair) = name.strip_suffix("_force_x") {
            let fx = table.numbers(name)?;
            let fy = table.numbers(&format!("{pair}_force_y"))?;
            let norm = fx.iter().zip(&fy).map(|(x, y)| x.hypot(*y)).collect();
            forces.push((pair.to_string(), norm));
        } else if let Some(pair) = name.strip_suffix("_normal_force") {
            // In space: the pair's normal force Σ w p, a magnitude.
            let f = table.numbers(name)?;
            forces.push((pair.to_string(), f.iter().map(|v| v.abs()).collect()));
        }
    }
    let mut tangential = Vec::new();
    for name in &table.header {
        if let Some(pair) = name.strip_suffix("_tangential_force") {
            tangential.push((pair.to_string(), table.numbers(name)?));
        }
    }
    Ok(Steps {
        factor: table.numbers("factor")?,
        converged,
        monitor,
        forces,
        tangential,
    })
}

/// The monitored displacement component that moves most (of `monitor_ux`, `monitor_uy` and,
/// in space, `monitor_uz`), with its name; a body pushed down (or left) plots as a positive
/// displacement −u, as usual for a load–displacement curve.
fn monitored(table: &Table) -> Result<Option<(&'static str, Vec<f64>)>> {
    let reach = |u: &[f64]| {
        u.iter()
            .filter(|v| v.is_finite())
            .fold(0.0, |m: f64, v| m.max(v.abs()))
    };
    let mut best: Option<([&'static str; 2], Vec<f64>)> = None;
    for (column, names) in [
        ("monitor_ux", ["u_x", "−u_x"]),
        ("monitor_uy", ["u_y", "−u_y"]),
        ("monitor_uz", ["u_z", "−u_z"]),
    ] {
        if table.column(column).is_err() {
            continue;
        }
        let u = table.numbers(column)?;
        if !best.as_ref().is_some_and(|(_, b)| reach(&u) <= reach(b)) {
            best = Some((names, u));
        }
    }
    Ok(best.map(|(name, u)| {
        if u.iter().filter(|v| v.is_finite()).sum::<f64>() < 0.0 {
            (name[1], u.iter().map(|v| -v).collect())
        } else {
            (name[0], u)
        }
    }))
}

/// Force against the monitored displacement, or against the load factor.
const MARKERS: [Marker; 4] = [
    Marker::Circle,
    Marker::Square,
    Marker::Triangle,
    Marker::Diamond,
];

/// The look of pair `p`'s curve.
fn pair_look(p: usize) -> Look {
    Look::new(COLORS[p % COLORS.len()], Line::Solid, MARKERS[p % 4])
}

/// The mark of a step that did not converge.
fn failed_look() -> Look {
    Look::new(RGBColor(200, 0, 0), Line::None, Marker::Cross).hollow(7)
}

struct StepFigure<'a> {
    steps: &'a Steps,
    units: &'a Units,
    monitor: Option<&'a str>,
    against_factor: bool,
}

impl StepFigure<'_> {
    fn abscissa(&self) -> (&[f64], String) {
        match (&self.steps.monitor, self.against_factor) {
            (Some((name, u)), false) => {
                let what = match self.monitor {
                    Some(boundary) => format!("mean {name} on {boundary}"),
                    None => format!("monitored displacement {name}"),
                };
                (u, Units::label(&what, self.units.length.as_deref()))
            }
            _ => (&self.steps.factor, "load factor".to_string()),
        }
    }
}

impl Figure for StepFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (xs, x_label) = self.abscissa();
        let all_f = || {
            self.steps
                .forces
                .iter()
                .flat_map(|(_, f)| f.iter().copied())
        };
        let x = span(xs.iter().copied().chain([0.0]), 0.05, 0.0..1.0);
        let y = 0.0..span(all_f().chain([0.0]), 0.08, 0.0..1.0).end;
        let frame = Frame {
            caption: match (self.against_factor, self.monitor) {
                (true, _) => "contact force per load step".into(),
                (false, Some(boundary)) => {
                    format!("load–displacement curve, monitored: {boundary}")
                }
                (false, None) => "load–displacement curve".into(),
            },
            x_label,
            y_label: Units::label("resultant contact force |F|", self.units.force().as_deref()),
        };
        let mut legend = Legend::default();
        for (p, (pair, _)) in self.steps.forces.iter().enumerate() {
            legend.add(format!("pair {pair}"), pair_look(p));
        }
        if self.steps.converged.contains(&false) {
            legend.add("step not converged", failed_look());
        }
        let (left, right) = legend.split(root);
        let mut chart = linear(&left, &frame, x, y)?;
        for (p, (_, f)) in self.steps.forces.iter().enumerate() {
            // From the unloaded state: no load, no displacement, no contact force.
            let steps = xs.iter().copied().zip(f.iter().copied());
            let pts: Vec<(f64, f64)> = std::iter::once((0.0, 0.0)).chain(steps).collect();
            series(&mut chart, &pts, pair_look(p))?;
        }
        let failed: Vec<(f64, f64)> = self
            .steps
            .forces
            .iter()
            .flat_map(|(_, f)| xs.iter().zip(f).zip(&self.steps.converged))
            .filter(|(_, &ok)| !ok)
            .map(|((&x, &f), _)| (x, f))
            .collect();
        series(&mut chart, &failed, failed_look())?;
        legend.draw(&right)
    }
}

/// Each frictional pair's resultant tangential force Σ w σ_t (signed, along the tangents of its
/// reference side) against the load factor.
struct Tangential<'a> {
    steps: &'a Steps,
    units: &'a Units,
}

impl Figure for Tangential<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let (xs, curves) = (&self.steps.factor, &self.steps.tangential);
        let all_f = || curves.iter().flat_map(|(_, f)| f.iter().copied());
        let x = span(xs.iter().copied().chain([0.0]), 0.05, 0.0..1.0);
        let y = span(all_f().chain([0.0]), 0.08, -1.0..1.0);
        let frame = Frame {
            caption: "tangential contact force per load step".into(),
            x_label: "load factor".into(),
            y_label: Units::label(
                "resultant tangential force F_t",
                self.units.force().as_deref(),
            ),
        };
        let mut legend = Legend::default();
        for (p, (pair, _)) in curves.iter().enumerate() {
            legend.add(format!("pair {pair}"), pair_look(p));
        }
        if self.steps.converged.contains(&false) {
            legend.add("step not converged", failed_look());
        }
        let (left, right) = legend.split(root);
        let mut chart = linear(&left, &frame, x.clone(), y)?;
        let zero = LineSeries::new([(x.start, 0.0), (x.end, 0.0)], BLACK.mix(0.5));
        ok(chart.draw_series(zero))?;
        for (p, (_, f)) in curves.iter().enumerate() {
            let steps = xs.iter().copied().zip(f.iter().copied());
            let pts: Vec<(f64, f64)> = std::iter::once((0.0, 0.0)).chain(steps).collect();
            series(&mut chart, &pts, pair_look(p))?;
        }
        let failed: Vec<(f64, f64)> = curves
            .iter()
            .flat_map(|(_, f)| xs.iter().zip(f).zip(&self.steps.converged))
            .filter(|(_, &ok)| !ok)
            .map(|((&x, &f), _)| (x, f))
            .collect();
        series(&mut chart, &failed, failed_look())?;
        legend.draw(&right)
    }
}
