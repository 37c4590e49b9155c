//! The text of the CSV files: `contact.csv` ([`contact_csv`], [`pairs_csv`]), `history.csv`
//! ([`history_csv`]) and the table of a γ sweep ([`sweep_csv`]). Non-finite values are written as
//! `inf`, `-inf` or `NaN`, which Python's `float()`, numpy and pandas read back.

use contactdd_ddm::gamma_study::SweepRun;
use contactdd_ddm::solution::{BodyResult, PairResult, Solution};
use contactdd_ddm::Model;

use crate::fields::{contact_pressures, friction_point, has_friction};
use crate::number::format_f64 as num;
use crate::summary::point_status;

/// `contact.csv` of a solve of `model`: one row per contact point, with the friction columns when
/// some pair of the model has friction ([`pairs_csv`]).
pub fn contact_csv(model: &Model, sol: &Solution) -> String {
    pairs_csv(&sol.contact, &sol.bodies, has_friction(model))
}

/// The contact CSV of any list of pair results (`bodies`: the bodies they name, for their
/// meshes), with header `pair,body,x,y,gap,pressure,nodal_traction,status`: `pressure` is the
/// contact pressure p ≥ 0 of [`contact_pressures`], `nodal_traction` the normal traction of the
/// point's nodal contact force, [`PairResult::pressure`] (σ_n = −p where the point's own pressure
/// acts; on the following side of a balanced pair the reference side's forces on the node over its
/// weight). With `friction`, four columns follow: `tangential_traction` (σ_t along t = n turned
/// by +90°, [`PairResult::tangential`]), `slip` (g − g₀ of this solve), `total_slip` (g) and
/// `friction` (`open`, `stick` or `slip`).
pub fn pairs_csv(pairs: &[PairResult], bodies: &[BodyResult], friction: bool) -> String {
    let mut header = vec![
        "pair",
        "body",
        "x",
        "y",
        "gap",
        "pressure",
        "nodal_traction",
        "status",
    ];
    if friction {
        header.extend(["tangential_traction", "slip", "total_slip", "friction"]);
    }
    let pressures = contact_pressures(pairs, bodies);
    let rows = pairs.iter().zip(pressures).flat_map(|(p, pressure)| {
        (0..p.gap.len()).map(move |i| {
            let mut row = vec![
                p.name.clone(),
                p.bodies[p.side[i]].clone(),
                num(p.x[i]),
                num(p.y[i]),
                num(p.gap[i]),
                num(pressure[i]),
                num(p.pressure[i]),
                point_status(p, i).to_string(),
            ];
            if friction {
                let f = friction_point(p, i);
                row.extend([num(f.tangential), num(f.slip), num(f.total_slip)]);
                row.push(f.status.name().to_string());
            }
            row
        })
    });
    csv_text(header.into_iter().map(String::from), rows)
}

/// `history.csv`: one row per iteration, header
/// `k,gamma,measure,rel_change_<body>…,active_<body>…,normal_force_<body>…` (`measure`: what the
/// stopping test compares with the tolerance; `normal_force` is
/// Σ w |σ_n| over the body's contact points, see docs/outputs.md).
pub fn history_csv(sol: &Solution) -> String {
    let mut header = vec!["k".to_string(), "gamma".into(), "measure".into()];
    for prefix in ["rel_change", "active", "normal_force"] {
        header.extend(sol.bodies.iter().map(|b| format!("{prefix}_{}", b.name)));
    }
    let rows = sol.history.iter().map(|r| {
        let mut row = vec![r.k.to_string(), num(r.gamma), num(r.measure)];
        row.extend(r.rel_change.iter().map(|&x| num(x)));
        row.extend(r.active.iter().map(|a| a.to_string()));
        row.extend(r.contact_force.iter().map(|&f| num(f)));
        row
    });
    csv_text(header, rows)
}

/// The table of a γ sweep, header `method,gamma,iterations,converged,reason` (γ `auto` for the
/// Aitken rule, reason empty when converged).
pub fn sweep_csv(runs: &[SweepRun]) -> String {
    let header = ["method", "gamma", "iterations", "converged", "reason"];
    let rows = runs.iter().map(|r| {
        vec![
            r.method.name().to_string(),
            r.gamma.map_or_else(|| "auto".to_string(), num),
            r.iterations.to_string(),
            r.converged.to_string(),
            r.reason.clone(),
        ]
    });
    csv_text(header.map(String::from), rows)
}

/// The text of a CSV table (the `csv` crate's writer: fields quoted where they hold a comma, a
/// quote or a line break; every record ends in `\n`).
pub(crate) fn csv_text(
    header: impl IntoIterator<Item = String>,
    rows: impl IntoIterator<Item = Vec<String>>,
) -> String {
    let mut writer = csv::WriterBuilder::new()
        .flexible(true)
        .from_writer(Vec::new());
    // Writing into memory cannot fail.
    let _ = writer.write_record(header.into_iter().collect::<Vec<_>>());
    for row in rows {
        let _ = writer.write_record(&row);
    }
    let bytes = writer.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_where_needed() {
        let rows = [vec!["a,b".to_string(), "say \"x\"".into(), "plain".into()]];
        assert_eq!(
            csv_text(["h1", "h2", "h3"].map(String::from), rows),
            "h1,h2,h3\n\"a,b\",\"say \"\"x\"\"\",plain\n"
        );
    }
}
