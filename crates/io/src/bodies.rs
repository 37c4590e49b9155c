//! The checks of single bodies: a material, a body's name, its supports and loads on a built
//! mesh, and whether every body of a model is held.

use contactdd_core::names::shown;
use contactdd_core::{BodyError, Constraints, ElasticBody, Load, Material, Mesh, Plane};
use contactdd_ddm::{Model, SetupError};

use crate::error::{body_error, mesh_error};
use crate::number::format_f64 as num;
use contactdd_ddm::history::DEFAULT_GROUP;

use crate::problem::{LoadSpec, SupportSpec};

/// A `[materials.NAME]` table → a validated material (errors name the material and the key).
pub fn material(name: &str, young: f64, poisson: f64) -> Result<Material, SetupError> {
    Material::new(young, poisson).map_err(|source| SetupError::MaterialValue {
        material: shown(name),
        source,
    })
}

/// Checks the name of the next body, `bodies[i]` where i is the number of `earlier` names: not
/// empty, and not one of them.
pub fn check_body_name<'a>(
    name: &str,
    earlier: impl IntoIterator<Item = &'a str>,
) -> Result<(), SetupError> {
    let mut i = 0;
    let mut duplicate = None;
    for other in earlier {
        if duplicate.is_none() && other == name {
            duplicate = Some(i);
        }
        i += 1;
    }
    if name.trim().is_empty() {
        return Err(SetupError::Invalid {
            key: format!("bodies[{i}].name"),
            message: "a body name must not be empty".into(),
        });
    }
    match duplicate {
        Some(j) => Err(body_error(
            name,
            "name",
            format!("the name is used by both bodies[{j}] and bodies[{i}]"),
        )),
        None => Ok(()),
    }
}

/// Checks that every body is held: a body without a contact pair needs supports, and they must
/// remove all its rigid-body modes.
pub fn check_floating(model: &Model) -> Result<(), SetupError> {
    for (b, body) in model.bodies.iter().enumerate() {
        // A remote body's process checks it.
        if model.remote(b).is_some() || model.pairs.iter().any(|p| p.bodies.contains(&b)) {
            continue;
        }
        if !body.constraints.any() {
            return Err(SetupError::Floating {
                body: shown(&body.name),
            });
        }
        // Without contact the supports alone must hold the body.
        if let Err(BodyError::Floating {
            modes, description, ..
        }) = body.check_held(&[])
        {
            return Err(body_error(
                &body.name,
                "supports",
                format!(
                    "the body has no contact pair and its supports leave {modes} rigid-body \
                     mode(s) free ({description}): it would float"
                ),
            ));
        }
    }
    Ok(())
}

/// Body `name` on a built mesh: supports applied in order ([`Constraints::fix`]), loads checked
/// (finite values, known boundaries, group names) and those of the group `default` (the loads
/// without a group) summed into one load vector; the other groups' loads are a `[[steps]]`
/// history's ([`crate::history`]).
pub fn body_on_mesh(
    name: &str,
    mesh: Mesh,
    material: Material,
    plane: Plane,
    supports: &[SupportSpec],
    loads: &[LoadSpec],
) -> Result<ElasticBody, SetupError> {
    let mut constraints = Constraints::new(mesh.num_nodes());
    for (i, s) in supports.iter().enumerate() {
        constraints
            .fix(&mesh, &s.boundary, s.component, s.value)
            .map_err(|source| SetupError::Support {
                body: shown(name),
                key: format!("supports[{i}]"),
                source,
            })?;
    }
    for (i, spec) in loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        if spec.group.as_ref().is_some_and(|g| g.trim().is_empty()) {
            return Err(body_error(
                name,
                &format!("{key}.group"),
                "must not be empty",
            ));
        }
        let l = &spec.load;
        let values: &[f64] = match l {
            Load::Pressure { value, .. } => std::slice::from_ref(value),
            Load::Traction { value, .. } | Load::BodyForce { value } => value,
        };
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(body_error(
                name,
                &format!("{key}.value"),
                format!("must be finite, got {}", num(*v)),
            ));
        }
        if let Load::Pressure { boundary, .. } | Load::Traction { boundary, .. } = l {
            mesh.boundary(boundary)
                .map_err(|e| mesh_error(name, &format!("{key}.boundary"), e))?;
        }
    }
    let load = group_load(name, &mesh, loads, DEFAULT_GROUP)?;
    Ok(ElasticBody {
        name: name.to_string(),
        mesh,
        material,
        plane,
        constraints,
        load,
    })
}

/// The load vector of body `name`'s loads of group `group` (zeros if it has none).
pub fn group_load(
    name: &str,
    mesh: &Mesh,
    loads: &[LoadSpec],
    group: &str,
) -> Result<Vec<f64>, SetupError> {
    let of_group: Vec<Load> = (loads.iter())
        .filter(|l| l.group_name() == group)
        .map(|l| l.load.clone())
        .collect();
    contactdd_core::loads::load_vector(mesh, &of_group).map_err(|e| mesh_error(name, "loads", e))
}
