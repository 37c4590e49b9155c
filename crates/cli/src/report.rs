//! Console text: the per-iteration table, the per-pair contact report and number formatting.

use std::fmt::Write as _;
use std::io::IsTerminal;

use contactdd_core::Vector;
use contactdd_ddm::solution::PairResult;
use contactdd_ddm::{Accelerator, Friction, Model, Record, Settings};
use contactdd_io::reactions::BodyReactions;

/// A number with 4 significant digits: fixed notation for moderate magnitudes, else exponent.
pub fn sig(x: f64) -> String {
    let m = x.abs();
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e6).contains(&m) {
        let decimals = (3 - m.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.3e}")
    }
}

/// A 2D vector as `(x, y)`.
pub fn vec2(v: Vector) -> String {
    format!("({}, {})", sig(v[0]), sig(v[1]))
}

/// Writes a progress note to stderr, only when stderr is a terminal (never into logs or pipes).
pub fn progress(note: &str) {
    if std::io::stderr().is_terminal() {
        eprintln!("{note}");
    }
}

/// The live status of an iteration: its number, the largest relative change, the closed points.
pub fn status_text(r: &Record) -> String {
    let change = r.rel_change.iter().copied().fold(0.0, f64::max);
    let closed: usize = r.active.iter().sum();
    format!(
        "iteration {}  change {change:.2e}  closed points {closed}",
        r.k
    )
}

/// The per-iteration table: k, γ, then per body the relative change, the number of closed contact
/// points and the normal force Σ w |σ_n| (the sum of magnitudes, not the resultant).
pub struct IterationTable {
    bodies: Vec<String>,
    /// The second column: γ for the sweeps, the step length for the Newton method.
    step: &'static str,
    /// The stopping test's measure, and the tolerance it is compared with.
    measure: &'static str,
    tol: f64,
}

const CHANGE_WIDTH: usize = 9;
const ACTIVE_WIDTH: usize = 6;
const FORCE_WIDTH: usize = 10;
const MEASURE_WIDTH: usize = 10;

impl IterationTable {
    /// A table for the bodies of `model` solved with `settings`.
    pub fn new(model: &Model, settings: &Settings) -> IterationTable {
        let newton = settings.accelerator == Accelerator::Newton;
        IterationTable {
            bodies: model.bodies.iter().map(|b| b.name.clone()).collect(),
            step: if newton { "step" } else { "gamma" },
            measure: if newton { "residual" } else { "change" },
            tol: settings.tol,
        }
    }

    /// The header: what the stopping test measures over its tolerance, the column groups, then
    /// the body names.
    pub fn header(&self) -> String {
        let n = self.bodies.len();
        let group = |title: &str, width: usize| format!("  {title:<w$}", w = n * width);
        let mut top = format!(
            "{:>5}  {:>6}  {:>w$}",
            "",
            "",
            self.measure,
            w = MEASURE_WIDTH
        );
        top += &group("relative change", CHANGE_WIDTH);
        top += &group("closed points", ACTIVE_WIDTH);
        top += &group("normal force Σw|σn|", FORCE_WIDTH);
        let tol = format!("≤ {:e}", self.tol);
        let mut names = format!("{:>5}  {:>6}  {tol:>w$}", "k", self.step, w = MEASURE_WIDTH);
        for (width, gap) in [(CHANGE_WIDTH, 2), (ACTIVE_WIDTH, 2), (FORCE_WIDTH, 2)] {
            names += &" ".repeat(gap);
            for b in &self.bodies {
                let short: String = b.chars().take(width - 1).collect();
                let _ = write!(names, "{short:>width$}");
            }
        }
        format!("{}\n{}", top.trim_end(), names)
    }

    /// One iteration's line.
    pub fn line(&self, r: &Record) -> String {
        let measure = format!("{:.2e}", r.measure);
        let mut s = format!(
            "{:>5}  {:>6.4}  {measure:>w$}  ",
            r.k,
            r.gamma,
            w = MEASURE_WIDTH
        );
        for x in &r.rel_change {
            let _ = write!(s, "{:>w$}", format!("{x:.2e}"), w = CHANGE_WIDTH);
        }
        s += "  ";
        for a in &r.active {
            let _ = write!(s, "{a:>w$}", w = ACTIVE_WIDTH);
        }
        s += "  ";
        for f in &r.contact_force {
            let _ = write!(s, "{:>w$}", sig(*f), w = FORCE_WIDTH);
        }
        s
    }
}

/// Lines describing each pair's result: closed points, largest pressure, contact forces on both
/// sides and their balance; for a pair of `model` with friction, its law, the resultant
/// tangential force and the stick and slip lengths.
pub fn pair_report(model: &Model, pairs: &[PairResult], theta: &[f64]) -> Vec<String> {
    let mut lines = Vec::new();
    for (p, pair) in pairs.iter().enumerate() {
        let theta = theta
            .get(p)
            .map_or(String::new(), |t| format!(" (θ = {})", sig(*t)));
        lines.push(format!("contact pair {}{theta}:", pair.name));
        let count = |side: usize| {
            let idx = (0..pair.side.len()).filter(move |&i| pair.side[i] == side);
            (idx.clone().filter(|&i| pair.closed[i]).count(), idx.count())
        };
        let (c0, n0) = count(0);
        let (c1, n1) = count(1);
        lines.push(format!(
            "  closed points: {} {c0} of {n0}, {} {c1} of {n1}",
            pair.bodies[0], pair.bodies[1]
        ));
        // The contact pressure p = −σ_n ≥ 0 of the points whose own pressure acts; a following
        // point's p is read from them (contactdd_io::fields::contact_pressures), so never larger.
        let own = |i: usize| pair.enforced.get(i).copied().unwrap_or(true);
        let peak = (0..pair.pressure.len())
            .filter(|&i| own(i) && pair.pressure[i].is_finite())
            .min_by(|&a, &b| pair.pressure[a].total_cmp(&pair.pressure[b]));
        match peak {
            Some(i) if pair.pressure[i] < 0.0 => lines.push(format!(
                "  max contact pressure p = {} at {} on {}",
                sig(-pair.pressure[i]),
                vec2([pair.x[i], pair.y[i]]),
                pair.bodies[pair.side[i]]
            )),
            _ => lines.push("  no contact pressure: the bodies do not touch".into()),
        }
        let (f0, f1) = (pair.force_on(0), pair.force_on(1));
        let scale = f0[0].hypot(f0[1]).max(f1[0].hypot(f1[1]));
        let balance = if scale > 0.0 {
            format!(
                "; balance |F1 + F2| / |F| = {:.1e}",
                (f0[0] + f1[0]).hypot(f0[1] + f1[1]) / scale
            )
        } else {
            String::new()
        };
        lines.push(format!(
            "  resultant contact force on {} {}, on {} {}{balance}",
            pair.bodies[0],
            vec2(f0),
            pair.bodies[1],
            vec2(f1)
        ));
        lines.push(format!(
            "  largest penetration {}, gap under pressure {} (both 0 for exact contact)",
            sig(pair.max_penetration()),
            sig(pair.complementarity())
        ));
        match model.pairs.get(p).map(|m| m.friction) {
            Some(f) if f.is_active() => lines.push(friction_line(pair, f)),
            _ => {}
        }
    }
    lines
}

/// The friction line of a pair: its law, the resultant tangential force Σ w σ_t and the lengths
/// that stick and slip.
fn friction_line(pair: &PairResult, friction: Friction) -> String {
    let (stick, slip) = pair.stick_slip_lengths();
    format!(
        "  friction ({friction}): tangential force Σ w σ_t = {}, stick length {}, slip length {}",
        sig(pair.tangential_force()),
        sig(stick),
        sig(slip)
    )
}

/// One line per body: `reactions on lower: bottom (0, 8400), total (0, 8400)`, the force each
/// supported boundary exerts on the body.
pub fn reaction_report(reactions: &[BodyReactions]) -> Vec<String> {
    reactions
        .iter()
        .map(|r| {
            if r.supports.is_empty() {
                return format!("reactions on {}: no supports", r.body);
            }
            let items: Vec<String> = r
                .supports
                .iter()
                .map(|s| format!("{} {}", s.boundary, vec2(s.force)))
                .collect();
            format!(
                "reactions on {}: {}, total {}",
                r.body,
                items.join(", "),
                vec2(r.total)
            )
        })
        .collect()
}

/// `applied loads: lower (0, 8400), upper (0, -8400)`.
pub fn applied_loads(model: &Model, factor: f64) -> String {
    let items: Vec<String> = model
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let f = model.facts(i).applied_load.map(|x| x * factor);
            format!("{} {}", b.name, vec2(f))
        })
        .collect();
    format!("applied loads: {}", items.join(", "))
}

/// `time: phase 0.012 s, …` in the given order.
pub fn timing<'a>(phases: impl IntoIterator<Item = (&'a str, f64)>) -> String {
    let items: Vec<String> = phases
        .into_iter()
        .map(|(name, s)| format!("{name} {s:.3} s"))
        .collect();
    format!("time: {}", items.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits() {
        assert_eq!(sig(8400.0), "8400");
        assert_eq!(sig(0.12345), "0.1235");
        assert_eq!(sig(-2.5), "-2.500");
        assert_eq!(sig(4.333e-7), "4.333e-7");
        assert_eq!(sig(0.0), "0");
    }
}
