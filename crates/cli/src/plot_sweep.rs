//! The γ study figure of `contactdd plot`, from the CSV of `contactdd sweep`
//! (`method,gamma,iterations,converged,reason`): iterations against γ per method. A failed run
//! is drawn at the iteration it stopped, its marker telling how it failed (diverged, ran out of
//! iterations, stalled); an `auto` run is a horizontal line at its iteration count.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::args::Format;
use crate::plot_data::Table;
use crate::plot_draw::{linear, series, span, Figure, Frame, Legend, Line, Look, Marker, COLORS};

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum End {
    Converged,
    Diverged,
    MaxIterations,
    /// Stalled, interrupted or out of multiplier updates.
    Other,
}

impl End {
    /// From the `converged` and `reason` fields (reasons as in crates/ddm `short_reason`).
    fn of(converged: &str, reason: &str) -> End {
        if converged == "true" {
            End::Converged
        } else if reason.starts_with("max iterations") {
            End::MaxIterations
        } else if reason.contains(" at iteration ") {
            End::Diverged
        } else {
            End::Other
        }
    }

    /// The failure marker (hollow and larger than the methods' markers).
    fn look(self, color: RGBColor) -> Look {
        let marker = match self {
            End::Diverged => Marker::Cross,
            End::MaxIterations => Marker::Triangle,
            End::Other | End::Converged => Marker::Plus,
        };
        Look::new(color, Line::None, marker).hollow(6)
    }

    fn name(self) -> &'static str {
        match self {
            End::Converged => "converged",
            End::Diverged => "diverged (at its iteration)",
            End::MaxIterations => "max iterations",
            End::Other => "stalled / other",
        }
    }
}

/// One run of the sweep.
struct Run {
    /// `None` for `auto`.
    gamma: Option<f64>,
    iterations: f64,
    end: End,
}

/// The runs of one method, in file order.
struct MethodRuns {
    method: String,
    runs: Vec<Run>,
}

/// The `<stem>` figure of a sweep CSV.
pub fn figures(table: &Table, out: &Path, stem: &str, formats: &[Format]) -> Result<Vec<PathBuf>> {
    let methods = read(table)?;
    crate::plot_draw::render(&Sweep { methods }, out, stem, formats)
}

fn read(table: &Table) -> Result<Vec<MethodRuns>> {
    let [mc, gc, ic, cc, rc] =
        ["method", "gamma", "iterations", "converged", "reason"].map(|n| table.column(n));
    if mc.is_err() || gc.is_err() {
        bail!(
            "'{}' is not the CSV of a sweep (no columns method and gamma): `contactdd plot` \
             takes a result folder, its summary.json, or the CSV of `contactdd sweep`",
            table.path.display()
        );
    }
    let (mc, gc, ic, cc, rc) = (mc?, gc?, ic?, cc?, rc?);
    let mut methods: Vec<MethodRuns> = Vec::new();
    for (r, row) in table.rows.iter().enumerate() {
        let run = Run {
            gamma: if row[gc] == "auto" {
                None
            } else {
                Some(table.number(r, gc)?)
            },
            iterations: table.number(r, ic)?,
            end: End::of(&row[cc], &row[rc]),
        };
        match methods.iter_mut().find(|m| m.method == row[mc]) {
            Some(m) => m.runs.push(run),
            None => methods.push(MethodRuns {
                method: row[mc].clone(),
                runs: vec![run],
            }),
        }
    }
    if methods.is_empty() {
        bail!("'{}' has no runs", table.path.display());
    }
    Ok(methods)
}

/// Iterations against γ.
struct Sweep {
    methods: Vec<MethodRuns>,
}

/// The look of method `m`: colour, line style and marker all differ, and the markers are
/// outlines of growing size, so that methods with equal counts show as nested shapes.
fn method_look(m: usize) -> Look {
    let lines = [Line::Solid, Line::Dashed, Line::Dotted];
    let markers = [Marker::Circle, Marker::Square, Marker::Diamond];
    let size = 3 + (m % 5) as i32;
    Look::new(COLORS[m % COLORS.len()], lines[m % 3], markers[m % 3]).hollow(size)
}

impl Figure for Sweep {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let runs = || self.methods.iter().flat_map(|m| m.runs.iter());
        let x = span(runs().filter_map(|r| r.gamma), 0.04, 0.0..1.0);
        let y = 0.0..span(runs().map(|r| r.iterations).chain([1.0]), 0.0, 0.0..1.0).end * 1.08;
        let frame = Frame {
            caption: "iterations to converge against γ".into(),
            x_label: "relaxation parameter γ".into(),
            y_label: "iterations m".into(),
        };
        let legend = self.legend();
        let (left, right) = legend.split(root);
        let mut chart = linear(&left, &frame, x.clone(), y)?;
        for (m, method) in self.methods.iter().enumerate() {
            let look = method_look(m);
            let done: Vec<(f64, f64)> = method
                .runs
                .iter()
                .filter(|r| r.end == End::Converged)
                .filter_map(|r| Some((r.gamma?, r.iterations)))
                .collect();
            series(&mut chart, &done, look)?;
            for run in method.runs.iter().filter(|r| r.gamma.is_none()) {
                let at = [(x.start, run.iterations), (x.end, run.iterations)];
                series(&mut chart, &at, auto_look(look))?;
            }
        }
        for end in FAILURES {
            self.failures(&mut chart, end)?;
        }
        legend.draw(&right)
    }
}

/// The legend entry of an `auto` run.
fn auto_label(method: &str, run: &Run) -> String {
    match run.end {
        End::Converged => format!("{method} auto: {}", run.iterations),
        end => format!("{method} auto: {}", end.name()),
    }
}

/// The ways a run fails, in legend order.
const FAILURES: [End; 3] = [End::Diverged, End::MaxIterations, End::Other];

/// An `auto` run: a dotted line in its method's colour.
fn auto_look(method: Look) -> Look {
    Look {
        marker: Marker::None,
        line: Line::Dotted,
        ..method
    }
}

impl Sweep {
    /// Per method its look and its `auto` runs, then the kinds of failure that occur (in grey).
    fn legend(&self) -> Legend {
        let mut legend = Legend::default();
        for (m, method) in self.methods.iter().enumerate() {
            legend.add(method.method.clone(), method_look(m));
            for run in method.runs.iter().filter(|r| r.gamma.is_none()) {
                legend.add(auto_label(&method.method, run), auto_look(method_look(m)));
            }
        }
        for end in FAILURES {
            let failed = |r: &Run| r.end == end && r.gamma.is_some();
            if self.methods.iter().any(|m| m.runs.iter().any(failed)) {
                legend.add(end.name(), end.look(RGBColor(90, 90, 90)));
            }
        }
        legend
    }

    /// Draws the failed runs ending with `end`, each in its method's colour.
    fn failures<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        end: End,
    ) -> Result<()> {
        for (m, method) in self.methods.iter().enumerate() {
            let pts: Vec<(f64, f64)> = method
                .runs
                .iter()
                .filter(|r| r.end == end)
                .filter_map(|r| Some((r.gamma?, r.iterations)))
                .collect();
            series(chart, &pts, end.look(method_look(m).color))?;
        }
        Ok(())
    }
}
