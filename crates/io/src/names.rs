//! The names a problem gives (the problem, materials, bodies, boundaries and node sets, contact
//! pairs, load groups, steps) and the names it refers to, checked before anything is built: each
//! must meet [`name_problem`]'s rule (at most [`MAX_NAME_BYTES`] bytes, no control or invisible
//! formatting character), so that no later message, file name or table carries a hostile one.
//! Messages show names through [`shown`].

use std::fmt::Display;

pub use contactdd_core::names::{name_problem, shown, MAX_NAME_BYTES};
use contactdd_core::Load;
use contactdd_ddm::SetupError;

use crate::problem::{BodySpec, ContactSpec, LoadSpec, MeshSpec, Problem, SupportSpec};

/// Checks the name `name` found at `key` (e.g. `bodies[0].name`) against [`name_problem`]'s
/// rule; the error names the key and shows the name.
pub fn check_name(key: impl Display, name: &str) -> Result<(), SetupError> {
    match name_problem(name) {
        Some(message) => Err(SetupError::Invalid {
            key: key.to_string(),
            message,
        }),
        None => Ok(()),
    }
}

/// Checks every name a problem gives or refers to, in file order.
pub fn check_problem_names(problem: &Problem) -> Result<(), SetupError> {
    if let Some(name) = &problem.name {
        check_name("name", name)?;
    }
    for name in problem.materials.keys() {
        check_name("materials", name)?;
    }
    for (i, body) in problem.bodies.iter().enumerate() {
        check_body_names(i, body)?;
    }
    for (i, pair) in problem.contact.iter().enumerate() {
        check_pair_names(i, pair)?;
    }
    if let Some(m) = &problem.solver.monitor {
        check_name("solver.monitor.body", &m.body)?;
        check_name("solver.monitor.boundary", &m.boundary)?;
    }
    for (k, step) in problem.steps.iter().enumerate() {
        if let Some(name) = &step.name {
            check_name(format!("steps[{k}].name"), name)?;
        }
        for group in step.factors.keys() {
            check_name(format!("steps[{k}].factors"), group)?;
        }
    }
    Ok(())
}

/// Checks the names of `bodies[i]`: its own, its material's, its mesh's (a Gmsh surface, an
/// inline mesh's boundaries and node sets), and those of its supports and loads.
pub fn check_body_names(i: usize, body: &BodySpec) -> Result<(), SetupError> {
    let key = format!("bodies[{i}]");
    check_name(format!("{key}.name"), &body.name)?;
    check_name(format!("{key}.material"), &body.material)?;
    match &body.mesh {
        MeshSpec::Gmsh {
            surface: Some(s), ..
        } => check_name(format!("{key}.mesh.surface"), s)?,
        MeshSpec::Inline {
            boundaries,
            node_sets,
            ..
        } => {
            for name in boundaries.keys() {
                check_name(format!("{key}.mesh.boundaries"), name)?;
            }
            for name in node_sets.keys() {
                check_name(format!("{key}.mesh.node-sets"), name)?;
            }
        }
        _ => {}
    }
    check_entry_names(&key, &body.supports, &body.loads)
}

/// Checks the boundary names of `supports` and the boundary and group names of `loads` of the
/// body at `key`.
pub fn check_entry_names(
    key: &str,
    supports: &[SupportSpec],
    loads: &[LoadSpec],
) -> Result<(), SetupError> {
    for (j, s) in supports.iter().enumerate() {
        check_name(format!("{key}.supports[{j}].boundary"), &s.boundary)?;
    }
    for (j, l) in loads.iter().enumerate() {
        if let Load::Pressure { boundary, .. } | Load::Traction { boundary, .. } = &l.load {
            check_name(format!("{key}.loads[{j}].boundary"), boundary)?;
        }
        if let Some(group) = &l.group {
            check_name(format!("{key}.loads[{j}].group"), group)?;
        }
    }
    Ok(())
}

/// Checks the names of `contact[i]`: its own, its bodies' and its boundaries'.
pub fn check_pair_names(i: usize, pair: &ContactSpec) -> Result<(), SetupError> {
    if let Some(name) = &pair.name {
        check_name(format!("contact[{i}].name"), name)?;
    }
    for (s, body) in pair.bodies.iter().enumerate() {
        check_name(format!("contact[{i}].bodies[{s}]"), body)?;
    }
    for (s, boundary) in pair.boundaries.iter().enumerate() {
        check_name(format!("contact[{i}].boundaries[{s}]"), boundary)?;
    }
    Ok(())
}
