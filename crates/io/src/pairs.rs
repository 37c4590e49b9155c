//! One `[[contact]]` entry → a contact pair: its two bodies and boundaries, its penalty (the rod
//! model θ = c·h·(1/E*₁ + 1/E*₂) for `{ c, h }`, θ itself for `{ theta }`) and its gap profile.

use contactdd_core::ElasticBody;
use contactdd_ddm::{ContactPair, GapProfile, Penalty, SetupError};

use crate::error::pair_error;
use crate::number::format_f64 as num;
use crate::problem::{ContactSpec, GapSpec, PenaltySpec};

/// One `[[contact]]` entry → a contact pair between two of `bodies`, whose name must differ from
/// those of the `earlier` pairs (this one is `contact[earlier.len()]`).
pub fn pair(
    spec: &ContactSpec,
    bodies: &[ElasticBody],
    earlier: &[ContactPair],
) -> Result<ContactPair, SetupError> {
    let mut name = spec.pair_name();
    if name.is_empty() {
        // No name and no bodies: the entry's position is all that identifies it.
        name = format!("contact[{}]", earlier.len());
    }
    let ids = pair_bodies(spec, &name, bodies)?;
    let penalty = penalty(&name, &spec.penalty)?;
    let (a, b) = (&bodies[ids[0]], &bodies[ids[1]]);
    let theta = penalty.theta(a, b);
    if !(theta.is_finite() && theta > 0.0) {
        return Err(pair_error(
            &name,
            "penalty",
            format!("θ = {} is not a positive finite number", num(theta)),
        ));
    }
    let profile = spec
        .gap
        .as_ref()
        .map(|g| gap_profile(&name, g))
        .transpose()?;
    if let Some(j) = earlier.iter().position(|p| p.name == name) {
        return Err(pair_error(
            &name,
            "name",
            format!(
                "the name is used by both contact[{j}] and contact[{}]; give each pair its own \
                 name",
                earlier.len()
            ),
        ));
    }
    Ok(ContactPair {
        name,
        bodies: ids,
        boundaries: [spec.boundaries[0].clone(), spec.boundaries[1].clone()],
        penalty,
        profile,
        enforcement: spec.enforcement.map(Into::into).unwrap_or_default(),
        forces: spec.forces.map(Into::into).unwrap_or_default(),
        friction: Default::default(),
    })
}

/// The indices of the two bodies of pair `name`, which must be two different ones of `bodies`,
/// each with the boundary the entry names.
fn pair_bodies(
    spec: &ContactSpec,
    name: &str,
    bodies: &[ElasticBody],
) -> Result<[usize; 2], SetupError> {
    for (key, list) in [("bodies", &spec.bodies), ("boundaries", &spec.boundaries)] {
        if list.len() != 2 {
            return Err(pair_error(
                name,
                key,
                format!("needs exactly 2 entries, got {}", list.len()),
            ));
        }
    }
    let mut ids = [0usize; 2];
    for (s, body) in spec.bodies.iter().enumerate() {
        ids[s] = bodies.iter().position(|b| b.name == *body).ok_or_else(|| {
            let mut names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
            names.sort_unstable();
            pair_error(
                name,
                &format!("bodies[{s}]"),
                format!("unknown body '{body}' (known: {})", names.join(", ")),
            )
        })?;
    }
    if ids[0] == ids[1] {
        return Err(pair_error(
            name,
            "bodies",
            format!(
                "names body '{}' twice; a contact pair needs two different bodies",
                spec.bodies[0]
            ),
        ));
    }
    for s in 0..2 {
        let body = &bodies[ids[s]];
        body.mesh
            .boundary(&spec.boundaries[s])
            .map_err(|source| SetupError::PairBoundary {
                pair: name.to_string(),
                key: format!("boundaries[{s}]"),
                body: body.name.clone(),
                source,
            })?;
    }
    Ok(ids)
}

fn penalty(pair: &str, spec: &PenaltySpec) -> Result<Penalty, SetupError> {
    let positive = |key: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(pair_error(
                pair,
                &format!("penalty.{key}"),
                format!("must be a positive finite number, got {}", num(v)),
            ))
        }
    };
    match (spec.theta, spec.c, spec.h) {
        (Some(theta), None, None) => Ok(Penalty::Theta(positive("theta", theta)?)),
        (None, Some(c), Some(h)) => Ok(Penalty::RodModel {
            c: positive("c", c)?,
            h: positive("h", h)?,
        }),
        (Some(_), _, _) => Err(pair_error(
            pair,
            "penalty",
            "give either theta, or c and h (rod model), not both",
        )),
        (None, None, None) => Err(pair_error(
            pair,
            "penalty",
            "give either theta = θ or c and h (rod model θ = c·h·(1/E*₁ + 1/E*₂))",
        )),
        (None, _, _) => Err(pair_error(
            pair,
            "penalty",
            "the rod model needs both c and h",
        )),
    }
}

fn gap_profile(pair: &str, spec: &GapSpec) -> Result<GapProfile, SetupError> {
    let check = |key: &str, v: f64, positive: bool| {
        if v.is_finite() && (!positive || v > 0.0) {
            Ok(v)
        } else {
            let what = if positive {
                "a positive finite number"
            } else {
                "finite"
            };
            Err(pair_error(
                pair,
                &format!("gap.{key}"),
                format!("must be {what}, got {}", num(v)),
            ))
        }
    };
    Ok(match *spec {
        GapSpec::Notch {
            r0,
            b,
            centre,
            power,
            along,
        } => GapProfile::Notch {
            r0: check("r0", r0, false)?,
            b: check("b", b, true)?,
            centre: check("centre", centre, false)?,
            power: check("power", power, true)?,
            along: match along.unit() {
                Some(_) => along,
                None => {
                    return Err(pair_error(
                        pair,
                        "gap.along",
                        format!("needs a finite, non-zero direction, got {along:?}"),
                    ))
                }
            },
        },
        GapSpec::Uniform { value } => GapProfile::Uniform {
            value: check("value", value, false)?,
        },
    })
}
