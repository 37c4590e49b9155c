//! One `[[contact]]` entry → a contact pair: its two bodies and boundaries, its penalty (the rod
//! model θ = c·h·(1/E*₁ + 1/E*₂) for `{ c, h }`, θ itself for `{ theta }`) and its gap profile.

use contactdd_core::names::{listed, shown};
use contactdd_core::ElasticBody;
use contactdd_ddm::{ContactPair, Forces, Friction, GapProfile, Penalty, SetupError};

use crate::body_vtus::safe_file_name;
use crate::error::pair_error;
use crate::number::format_f64 as num;
use crate::problem::{ContactSpec, FrictionLaw, FrictionSpec, GapSpec, PenaltySpec};

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
    let forces: Forces = spec.forces.map(Into::into).unwrap_or_default();
    let friction = spec
        .friction
        .map(|f| friction(&name, &f, forces))
        .transpose()?
        .unwrap_or_default();
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
    check_file_name(&name, earlier)?;
    Ok(ContactPair {
        name,
        bodies: ids,
        boundaries: [spec.boundaries[0].clone(), spec.boundaries[1].clone()],
        penalty,
        profile,
        enforcement: spec.enforcement.map(Into::into).unwrap_or_default(),
        forces,
        friction,
    })
}

/// Refuses a pair name that gives the same file name as an earlier pair's: the pair names
/// become `steps.csv` columns (`<pair>_force_x`…) and plot files (`pressure-<pair>.svg`…) through
/// [`safe_file_name`], compared regardless of case so that the files differ on every file
/// system.
fn check_file_name(name: &str, earlier: &[ContactPair]) -> Result<(), SetupError> {
    let file_name = |n: &str| safe_file_name(n).to_lowercase();
    let own = file_name(name);
    match earlier.iter().position(|p| file_name(&p.name) == own) {
        Some(j) => Err(pair_error(
            name,
            "name",
            format!(
                "gives the same column and file names ('{}') as contact[{j}]'s name '{}'; give \
                 the pairs names that differ in more than case and characters other than \
                 letters, digits, '-', '_' and '.'",
                shown(&safe_file_name(name)),
                shown(&earlier[j].name)
            ),
        )),
        None => Ok(()),
    }
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
                format!(
                    "unknown body '{}' (known: {})",
                    shown(body),
                    listed(names).join(", ")
                ),
            )
        })?;
    }
    if ids[0] == ids[1] {
        return Err(pair_error(
            name,
            "bodies",
            format!(
                "names body '{}' twice; a contact pair needs two different bodies",
                shown(&spec.bodies[0])
            ),
        ));
    }
    for s in 0..2 {
        let body = &bodies[ids[s]];
        body.mesh
            .boundary(&spec.boundaries[s])
            .map_err(|source| SetupError::PairBoundary {
                pair: shown(name),
                key: format!("boundaries[{s}]"),
                body: shown(&body.name),
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

/// The tangential law of pair `pair` (whose forces are `forces`): [`friction_law`], and friction
/// needs balanced forces.
fn friction(pair: &str, spec: &FrictionSpec, forces: Forces) -> Result<Friction, SetupError> {
    let law = friction_law(spec).map_err(|(key, message)| pair_error(pair, &key, message))?;
    if law.is_active() && forces == Forces::OwnSide {
        return Err(pair_error(
            pair,
            "friction",
            "friction needs forces = \"balanced\" (own-side pairs carry no tangential forces)",
        ));
    }
    Ok(law)
}

/// The tangential law of a `friction` table: the law's own parameter and no other, finite and at
/// least 0. An error is the key (`friction.mu`, `friction.bound`) and the message.
pub fn friction_law(spec: &FrictionSpec) -> Result<Friction, (String, String)> {
    let err = |key: &str, message: String| (format!("friction.{key}"), message);
    let value = |key: &str, v: Option<f64>, what: &str| match v {
        None => Err(err(key, format!("{what} friction needs {key}"))),
        Some(v) if v.is_finite() && v >= 0.0 => Ok(v),
        Some(v) => Err(err(
            key,
            format!("must be a finite number at least 0, got {}", num(v)),
        )),
    };
    let unused = |key: &str, v: Option<f64>, what: &str| match v {
        Some(_) => Err(err(key, what.replace("KEY", key))),
        None => Ok(()),
    };
    Ok(match spec.law {
        FrictionLaw::None => {
            unused("mu", spec.mu, "law = \"none\" takes no KEY")?;
            unused("bound", spec.bound, "law = \"none\" takes no KEY")?;
            Friction::None
        }
        FrictionLaw::Coulomb => {
            unused("bound", spec.bound, "Coulomb friction takes mu, not KEY")?;
            Friction::Coulomb {
                mu: value("mu", spec.mu, "Coulomb")?,
            }
        }
        FrictionLaw::Tresca => {
            unused("mu", spec.mu, "Tresca friction takes bound, not KEY")?;
            Friction::Tresca {
                bound: value("bound", spec.bound, "Tresca")?,
            }
        }
    })
}

/// The friction of the command line's `--friction` (and Python's `friction=` string):
/// `coulomb:MU`, `tresca:BOUND` or `none`, the parameter finite and at least 0.
pub fn parse_friction(s: &str) -> Result<Friction, String> {
    let given = s.trim();
    let (law, value) = match given.split_once(':') {
        Some((law, value)) => (law.trim(), Some(value.trim())),
        None => (given, None),
    };
    // What the messages echo: the value shown safely (escaped, cut).
    let (s, law_shown) = (shown(given), shown(law));
    let number = |what: &str| match value.map(str::parse::<f64>) {
        Some(Ok(v)) => Ok(v),
        Some(Err(_)) => Err(format!(
            "'{s}': the {what} after '{law}:' must be a number",
            law = law_shown
        )),
        None => Err(format!("'{s}': give the {what} as {law_shown}:VALUE")),
    };
    let friction = match law {
        "none" if value.is_none() => Friction::None,
        "none" => return Err(format!("'{s}': none takes no value")),
        "coulomb" => Friction::Coulomb {
            mu: number("friction coefficient")?,
        },
        "tresca" => Friction::Tresca {
            bound: number("bound")?,
        },
        _ => {
            return Err(format!(
                "unknown friction '{s}' (expected coulomb:MU, tresca:BOUND or none)"
            ))
        }
    };
    match friction.problem() {
        Some(problem) => Err(format!("'{s}': {problem}")),
        None => Ok(friction),
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
