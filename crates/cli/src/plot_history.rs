//! The convergence figure of `contactdd plot`: what the stopping test measures (the `measure`
//! column of `history.csv`, named by `stop_measure` in summary.json) against the stopping
//! tolerance, and each body's relative change, per iteration on a log scale. With load steps,
//! `history.csv` holds the last step's iterations, and the caption says so.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::args::Format;
use crate::plot_data::Table;
use crate::plot_draw::{ok, render, series, Figure, Legend, Line, Look, Marker, COLORS};

/// What the history figure is drawn from.
pub struct History<'a> {
    /// `history.csv`.
    pub table: Table,
    /// The bodies' names from summary.json: their `rel_change_<body>` columns are drawn (every
    /// `rel_change_*` column when the summary names no body).
    pub bodies: &'a [String],
    /// The stopping tolerance, if known.
    pub tol: Option<f64>,
    /// What the `measure` column is (`relative residual`, …), if known.
    pub measure: Option<&'a str>,
    /// The number of load steps (0 without): history.csv is the last step's.
    pub steps: usize,
}

/// The `history` figure. Columns are found by name, so columns other than `k` and
/// `rel_change_<body>` (whatever they are) are ignored.
pub fn figures(history: &History, out: &Path, formats: &[Format]) -> Result<Vec<PathBuf>> {
    let table = &history.table;
    let k = table.numbers("k")?;
    let names: Vec<String> = if history.bodies.is_empty() {
        let prefixed = table.header.iter();
        let bodies = prefixed.filter_map(|h| h.strip_prefix("rel_change_"));
        bodies.map(String::from).collect()
    } else {
        history.bodies.to_vec()
    };
    let mut bodies = Vec::new();
    for body in names {
        let column = format!("rel_change_{body}");
        if table.column(&column).is_err() {
            continue;
        }
        bodies.push((body, positive(&k, table.numbers(&column)?)));
    }
    if bodies.is_empty() {
        bail!("'{}' has no rel_change_<body> column", table.path.display());
    }
    let measure = match table.column("measure") {
        Ok(_) => {
            let name = history.measure.unwrap_or("stopping measure");
            Some((
                format!("stop test: {name}"),
                positive(&k, table.numbers("measure")?),
            ))
        }
        Err(_) => None,
    };
    let fig = Curves {
        measure,
        bodies,
        tol: history.tol,
        steps: history.steps,
    };
    render(&fig, out, "history", formats)
}

/// The points (k, v) of a column; a log scale has no place for 0, NaN or infinity, so those
/// iterations are left out, as are those whose number k is not finite (a damaged file: the
/// iteration axis would have no end).
fn positive(k: &[f64], values: Vec<f64>) -> Vec<(f64, f64)> {
    k.iter()
        .zip(values)
        .filter(|(k, v)| k.is_finite() && v.is_finite() && *v > 0.0)
        .map(|(&k, v)| (k, v))
        .collect()
}

/// The stopping measure and the relative change per body against the iteration.
struct Curves {
    /// The stopping test's measure, with its legend entry.
    measure: Option<(String, Vec<(f64, f64)>)>,
    bodies: Vec<(String, Vec<(f64, f64)>)>,
    tol: Option<f64>,
    steps: usize,
}

impl Curves {
    /// The caption: which solve the curves are (the last of several load steps) and whether the
    /// tolerance is known.
    fn caption(&self) -> String {
        let mut caption = "convergence history".to_string();
        if self.steps > 1 {
            caption += &format!(", load step {} (the last)", self.steps);
        }
        if self.tol.is_none() {
            caption += " (tolerance unknown: --tol T draws it)";
        }
        caption
    }
}

impl Figure for Curves {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        let measured = self.measure.iter().flat_map(|(_, p)| p.iter());
        let pts = || {
            self.bodies
                .iter()
                .flat_map(|(_, p)| p.iter())
                .chain(measured.clone())
        };
        let k_max = pts().map(|p| p.0).fold(1.0, f64::max);
        let values = || pts().map(|p| p.1).chain(self.tol);
        let lo = values().fold(f64::INFINITY, f64::min);
        let hi = values().fold(0.0, f64::max);
        let (lo, hi) = if lo.is_finite() && hi > 0.0 {
            // At least two decades: plotters then labels the powers of ten only.
            ((lo / 3.0).min(hi / 100.0), hi * 3.0)
        } else {
            (1e-6, 1.0)
        };
        let caption = self.caption();
        let mut legend = Legend::default();
        let measure_look = Look::new(BLACK, Line::Solid, Marker::Square);
        if let Some((name, _)) = &self.measure {
            legend.add(name.clone(), measure_look);
        }
        for (b, (name, _)) in self.bodies.iter().enumerate() {
            legend.add(name.clone(), body_look(b));
        }
        let tol_look = Look::new(BLACK, Line::Dashed, Marker::None);
        if let Some(tol) = self.tol {
            legend.add(format!("tol = {tol:e}"), tol_look);
        }
        let (left, right) = legend.split(root);
        let mut chart = ok(ChartBuilder::on(&left)
            .caption(caption, ("sans-serif", 22))
            .margin(12)
            .margin_right(30)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(0.0..k_max + 0.5, (lo..hi).log_scale()))?;
        ok(chart
            .configure_mesh()
            .x_desc("iteration k")
            .y_desc("stop test and relative change per body")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            // Iterations are whole numbers: no label between them.
            .x_labels((k_max as usize + 1).clamp(2, 11))
            .x_label_formatter(&|v| {
                if v.fract() == 0.0 {
                    format!("{v:.0}")
                } else {
                    String::new()
                }
            })
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .bold_line_style(RGBColor(225, 225, 225))
            .light_line_style(TRANSPARENT)
            .draw())?;
        for (b, (_, pts)) in self.bodies.iter().enumerate() {
            series(&mut chart, pts, body_look(b))?;
        }
        if let Some((_, pts)) = &self.measure {
            series(&mut chart, pts, measure_look)?;
        }
        if let Some(tol) = self.tol {
            series(&mut chart, &[(0.0, tol), (k_max + 0.5, tol)], tol_look)?;
        }
        legend.draw(&right)
    }
}

/// The look of body `b`: colour, line and marker all differ, so that equal changes (two
/// symmetric bodies) show as both curves.
fn body_look(b: usize) -> Look {
    let markers = [
        Marker::Circle,
        Marker::Cross,
        Marker::Square,
        Marker::Triangle,
    ];
    let lines = [Line::Solid, Line::Dashed, Line::Dotted];
    Look::new(COLORS[b % COLORS.len()], lines[b % 3], markers[b % 4])
}
