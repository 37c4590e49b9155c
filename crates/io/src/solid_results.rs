//! The result folder of a solve in space: `summary.json`, `contact.csv` and one `.vtu` file of
//! tetrahedra per body (`docs/three-d.md`, "Problem files and results").

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use contactdd_core::solid::element::elasticity;
use contactdd_core::solid::post::{nodal_stresses, von_mises};
use contactdd_core::solid::TetOrder;
use contactdd_ddm::contact3d::DiscStatus;
use contactdd_ddm::solid_contact::SolidFrictionPoint;

use crate::atomic::write_atomic;
use crate::body_vtus::safe_file_name;
use crate::number::push_f64;
use crate::problem::FrictionSpec;
use crate::solid_run::{tangential_force, SolidOutcome};
use crate::solid_setup::SolidModel;
use crate::solid_vtu::{stress_tensors, write_solid_vtu, write_solid_vtu_pieces};
use crate::vtu::{Field, VtuData, VtuLayout, COLLECTION_STEM};

/// Writes the result files of `outcome` into `dir` (created if needed) and returns their paths.
pub fn write_solid_results(
    dir: &Path,
    model: &SolidModel,
    outcome: &SolidOutcome,
) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut written = write_bodies(dir, model, outcome)?;
    let contact = dir.join("contact.csv");
    write_atomic(&contact, solid_contact_csv(model, outcome).as_bytes())?;
    written.push(contact);
    if outcome.steps.len() > 1 {
        let steps = dir.join("steps.csv");
        write_atomic(&steps, solid_steps_csv(model, outcome).as_bytes())?;
        written.push(steps);
    }
    let summary = dir.join("summary.json");
    let mut value = solid_summary(model, outcome);
    let names: Vec<String> = (written.iter().chain([&summary]))
        .filter_map(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .collect();
    value["files"] = json!(names);
    let text = serde_json::to_string_pretty(&value)?;
    write_atomic(&summary, format!("{text}\n").as_bytes())?;
    written.push(summary);
    Ok(written)
}

/// `steps.csv`: one row per load step, with its factor, Newton steps, verdict, worst imbalance,
/// every pair's normal force Σ w p and the monitored face's mean displacement (empty without
/// one).
fn solid_steps_csv(model: &SolidModel, outcome: &SolidOutcome) -> String {
    let mut out = String::from("step,factor,newton_steps,converged,imbalance");
    for p in &model.pairs {
        out.push_str(&format!(",{}_normal_force", p.name));
    }
    let frictional: Vec<usize> = (0..model.pairs.len())
        .filter(|&k| model.pairs[k].friction.is_active())
        .collect();
    for &k in &frictional {
        let name = &model.pairs[k].name;
        out.push_str(&format!(
            ",{name}_tangential_x,{name}_tangential_y,{name}_tangential_z"
        ));
    }
    out.push_str(",monitor_ux,monitor_uy,monitor_uz\n");
    for (k, s) in outcome.steps.iter().enumerate() {
        out.push_str(&format!(
            "{},{},{},{},{:e}",
            k + 1,
            s.factor,
            s.newton_steps,
            s.converged,
            s.imbalance
        ));
        for f in &s.pair_forces {
            out.push_str(&format!(",{f:e}"));
        }
        for &k in &frictional {
            let [x, y, z] = s.tangential_forces[k];
            out.push_str(&format!(",{x:e},{y:e},{z:e}"));
        }
        match s.monitor {
            Some([x, y, z]) => out.push_str(&format!(",{x:e},{y:e},{z:e}\n")),
            None => out.push_str(",,,\n"),
        }
    }
    out
}

/// Every body's displacement, nodal stress tensor and von Mises stress, one `.vtu` file per body
/// or one collection, as `[output]` says.
fn write_bodies(
    dir: &Path,
    model: &SolidModel,
    outcome: &SolidOutcome,
) -> std::io::Result<Vec<PathBuf>> {
    let options = model.output.vtu_options();
    let invalid = |e: contactdd_core::solid::SolidError| {
        std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string())
    };
    let mut arrays = Vec::with_capacity(model.bodies.len());
    for (b, body) in model.bodies.iter().enumerate() {
        let u = &outcome.solution.displacements[b];
        let stress = nodal_stresses(&body.mesh, &elasticity(&body.material), u).map_err(invalid)?;
        let mises: Vec<f64> = stress.iter().map(|s| von_mises(*s)).collect();
        arrays.push((stress_tensors(&stress), mises));
    }
    let fields: Vec<[Field<'_>; 2]> = (arrays.iter())
        .map(|(tensor, mises)| {
            [
                Field {
                    name: "stress",
                    components: 9,
                    values: tensor,
                },
                Field {
                    name: "von_mises",
                    components: 1,
                    values: mises,
                },
            ]
        })
        .collect();
    let pieces: Vec<_> = (model.bodies.iter().zip(&fields).enumerate())
        .map(|(b, (body, f))| {
            let data = VtuData {
                displacement: Some(&outcome.solution.displacements[b]),
                points: f,
                cells: &[],
            };
            (&body.mesh, data)
        })
        .collect();
    if options.layout == VtuLayout::Collection {
        let path = dir.join(format!("{COLLECTION_STEM}.vtu"));
        write_solid_vtu_pieces(&path, &pieces, options.format)?;
        return Ok(vec![path]);
    }
    let mut written = Vec::with_capacity(pieces.len());
    for ((mesh, data), body) in pieces.into_iter().zip(&model.bodies) {
        let path = dir.join(format!("{}.vtu", safe_file_name(&body.name)));
        write_solid_vtu(&path, mesh, data, options.format)?;
        written.push(path);
    }
    Ok(written)
}

/// `contact.csv`: one row per contact point with a partner: the pair, the reference body, the
/// node, its position, its quadrature weight (area), the initial gap and the pressure; with a
/// frictional pair also the tangential traction on the reference side and the slip as vectors,
/// and the status (`stick`, `slip`, `open`; empty at a frictionless pair's points).
pub fn solid_contact_csv(model: &SolidModel, outcome: &SolidOutcome) -> String {
    let friction = model.pairs.iter().any(|p| p.friction.is_active());
    let mut out = String::from("pair,body,node,x,y,z,weight,gap,pressure");
    if friction {
        out.push_str(",traction_x,traction_y,traction_z,slip_x,slip_y,slip_z,status");
    }
    out.push('\n');
    for p in &outcome.solution.points {
        let pair = &model.pairs[p.pair];
        let body = &model.bodies[pair.sides[0].0];
        let _ = write!(out, "{},{},{}", pair.name, body.name, p.node);
        for v in p.position.iter().chain([&p.weight, &p.gap, &p.pressure]) {
            out.push(',');
            push_f64(&mut out, *v);
        }
        if friction {
            push_friction(&mut out, p.friction.as_ref());
        }
        out.push('\n');
    }
    out
}

/// The friction columns of a point of `contact.csv`.
fn push_friction(out: &mut String, f: Option<&SolidFrictionPoint>) {
    let Some(f) = f else {
        out.push_str(",,,,,,,");
        return;
    };
    for v in f.traction_vector().iter().chain(&f.slip_vector()) {
        out.push(',');
        push_f64(out, *v);
    }
    out.push_str(match f.status {
        Some(DiscStatus::Stick) => ",stick",
        Some(DiscStatus::Slip) => ",slip",
        None => ",open",
    });
}

/// The friction entries of pair `k` of the summary (nothing for a frictionless pair): its law,
/// its tangential force on the reference side and its sticking and slipping points.
fn pair_friction(model: &SolidModel, outcome: &SolidOutcome, k: usize, entry: &mut Value) {
    let law = model.pairs[k].friction;
    if !law.is_active() {
        return;
    }
    let points = outcome.solution.points.iter().filter(|q| q.pair == k);
    let count = |s: DiscStatus| {
        (points.clone())
            .filter(|q| q.friction.as_ref().is_some_and(|f| f.status == Some(s)))
            .count()
    };
    entry["friction"] = json!(FrictionSpec::from(law));
    entry["tangential_force"] = json!(tangential_force(&outcome.solution, k));
    entry["stick"] = json!(count(DiscStatus::Stick));
    entry["slip"] = json!(count(DiscStatus::Slip));
}

/// `summary.json`: the verdict, the solver, the check, the bodies, the pairs and the phases.
pub fn solid_summary(model: &SolidModel, outcome: &SolidOutcome) -> Value {
    let sol = &outcome.solution;
    let bodies: Vec<Value> = (model.bodies.iter().zip(&outcome.balance.bodies))
        .map(|(b, bal)| {
            let applied: [f64; 3] =
                std::array::from_fn(|c| b.load.iter().skip(c).step_by(3).sum::<f64>());
            json!({
                "name": b.name,
                "nodes": b.mesh.num_nodes(),
                "tetrahedra": b.mesh.num_tets(),
                "dofs": 3 * b.mesh.num_nodes(),
                "order": if b.mesh.order() == TetOrder::P2 { "p2" } else { "p1" },
                "applied_load": applied,
                "contact_force": bal.contact,
                "reaction": bal.reaction,
                "imbalance": bal.imbalance,
                "floor": bal.floor,
            })
        })
        .collect();
    let pairs: Vec<Value> = (model.pairs.iter().enumerate())
        .map(|(k, p)| -> Value {
            let points = sol.points.iter().filter(|q| q.pair == k);
            let force: f64 = points.clone().map(|q| q.weight * q.pressure).sum();
            let peak = points.clone().map(|q| q.pressure).fold(0.0, f64::max);
            let mut entry = json!({
                "name": p.name,
                "bodies": [model.bodies[p.sides[0].0].name, model.bodies[p.sides[1].0].name],
                "boundaries": [p.sides[0].1, p.sides[1].1],
                "theta": p.theta,
                "enforcement": p.enforcement.to_string(),
                "points": points.clone().count(),
                "closed": points.filter(|q| q.pressure > 0.0).count(),
                "normal_force": force,
                "peak_pressure": peak,
            });
            pair_friction(model, outcome, k, &mut entry);
            entry
        })
        .collect();
    let timings: serde_json::Map<String, Value> = (sol.timings.iter())
        .map(|(phase, s)| (phase.to_string(), json!(s)))
        .collect();
    let mut summary = json!({
        "problem": model.name,
        "units": model.units,
        "dimension": 3,
        "solver": outcome.solver.label(),
        "converged": outcome.converged,
        "reason": outcome.reason,
        "newton_steps": sol.newton_steps,
        "balance": {
            "worst": outcome.balance.worst(),
            "tol": model.balance_tol,
            "contact_law": outcome.balance.contact_law,
            "gap_violation": outcome.balance.gap_violation,
        },
        "bodies": bodies,
        "contact": pairs,
        "load_steps": outcome.steps.iter().map(|s| json!({
            "factor": s.factor,
            "newton_steps": s.newton_steps,
            "converged": s.converged,
            "imbalance": s.imbalance,
            "normal_forces": s.pair_forces,
            "monitor": s.monitor,
        })).collect::<Vec<_>>(),
        "timings": timings,
    });
    if model.pairs.iter().any(|p| p.friction.is_active()) {
        summary["balance"]["friction_law"] = json!(outcome.balance.friction_law);
    }
    summary
}
