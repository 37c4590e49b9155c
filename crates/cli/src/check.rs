//! `contactdd check`: load and validate a problem file (including the contact geometry) and
//! describe it, without factorising or solving anything.

use anyhow::Result;

use contactdd_core::{num_dofs, Component, ElasticBody, Load, Order};
use contactdd_ddm::contact::check as contact_check;
use contactdd_ddm::contact::{Interface, Role};
use contactdd_ddm::solver::check_friction;
use contactdd_ddm::{Enforcement, Model, Penalty};
use contactdd_io::fields::has_friction;
use contactdd_io::problem::{BodySpec, MeshSpec};
use contactdd_io::Loaded;

use crate::args::CheckArgs;
use crate::report::{sig, vec2};
use crate::solve::count;
use crate::{load, Exit};

/// `contactdd check`.
pub fn check(args: CheckArgs) -> Result<Exit> {
    let mut loaded = load(&args.file)?;
    if let Some(f) = args.friction {
        loaded.model.pairs.iter_mut().for_each(|p| p.friction = f);
    }
    let interface = Interface::new(&loaded.model).map_err(|e| anyhow::anyhow!("{e}"))?;
    let findings = contact_check::check(&loaded.model, &interface);
    let file = args.file.display();
    contact_check::refuse(&findings).map_err(|e| anyhow::anyhow!("{file}: {e}"))?;
    check_friction(&interface, &loaded.settings).map_err(|e| anyhow::anyhow!("{file}: {e}"))?;
    say!("{}", describe(&loaded, &interface).trim_end());
    for f in &findings {
        eprintln!("warning: {file}: {f}");
    }
    say!("ok: '{file}' is a valid problem");
    Ok(Exit::Success)
}

/// The description `contactdd check` prints: the problem, each body, each contact pair, the
/// solver settings.
fn describe(loaded: &Loaded, interface: &Interface) -> String {
    let (model, problem) = (&loaded.model, &loaded.problem);
    let mut out = format!(
        "problem {} (plane {}): {}, {}\n",
        model.name,
        match model.plane {
            contactdd_core::Plane::Strain => "strain",
            contactdd_core::Plane::Stress => "stress",
        },
        count(model.bodies.len(), "body", "bodies"),
        count(model.pairs.len(), "contact pair", "contact pairs"),
    );
    if let Some(units) = &problem.units {
        out += &format!("units: {units}\n");
    }
    for (body, spec) in model.bodies.iter().zip(&problem.bodies) {
        out += &body_text(body, spec);
    }
    for p in 0..model.pairs.len() {
        out += &pair_text(model, p, interface);
    }
    out += &solver_text(loaded);
    out
}

/// A body: sizes and material, mesh, boundaries, supports and loads.
fn body_text(body: &ElasticBody, spec: &BodySpec) -> String {
    let nodes = body.mesh.num_nodes();
    let prescribed = body.constraints.num_prescribed();
    let mut out = format!(
        "body {}: {} nodes, {} elements ({}), {} DOFs ({} prescribed), E = {}, ν = {}\n",
        body.name,
        nodes,
        body.mesh.num_cells(),
        match body.mesh.order() {
            Order::P1 => "P1",
            Order::P2 => "P2",
        },
        num_dofs(nodes) - prescribed.min(num_dofs(nodes)),
        prescribed,
        sig(body.material.young()),
        body.material.poisson()
    );
    out += &format!("  mesh: {}\n", mesh_text(&spec.mesh));
    let names: Vec<&str> = body.mesh.boundaries().keys().map(String::as_str).collect();
    out += &format!("  boundaries: {}\n", names.join(", "));
    if spec.supports.is_empty() {
        out += "  supports: none (held by contact only)\n";
    }
    for s in &spec.supports {
        let comp = match s.component {
            Component::X => "u_x",
            Component::Y => "u_y",
            Component::Both => "u_x, u_y",
            Component::Normal => "u_n (symmetry)",
        };
        out += &format!("  support: {comp} = {} on {}\n", sig(s.value), s.boundary);
    }
    for l in &spec.loads {
        out += &match &l.load {
            Load::Pressure { boundary, value } => {
                format!("  load: pressure {} on {boundary}\n", sig(*value))
            }
            Load::Traction { boundary, value } => {
                format!("  load: traction {} on {boundary}\n", vec2(*value))
            }
            Load::BodyForce { value } => format!("  load: body force {}\n", vec2(*value)),
        };
        if let Some(group) = &l.group {
            out.insert_str(out.len() - 1, &format!(" (group {group})"));
        }
    }
    out
}

/// `  load history: press (2 increments: press 1), shear (…)`.
fn history_text(history: &contactdd_ddm::history::LoadHistory) -> String {
    let names = history.group_names();
    let steps: Vec<String> = (history.steps.iter())
        .map(|s| {
            let factors: Vec<String> = (s.factors.iter())
                .map(|&(g, f)| format!("{} {}", names[g], sig(f)))
                .collect();
            format!(
                "{} ({} increments: {})",
                s.name,
                s.increments,
                factors.join(", ")
            )
        })
        .collect();
    format!("  load history: {}\n", steps.join(", "))
}

/// Contact pair `p`: its bodies, boundaries and θ, its friction when some pair of the model has
/// friction (a frictionless problem is described as it always was), then the contact points of
/// each side.
fn pair_text(model: &Model, p: usize, interface: &Interface) -> String {
    let pair = &model.pairs[p];
    let friction = if !has_friction(model) {
        String::new()
    } else if pair.friction.is_active() {
        format!("; friction: {}", pair.friction)
    } else {
        "; frictionless".to_string()
    };
    let (a, b) = (&model.bodies[pair.bodies[0]], &model.bodies[pair.bodies[1]]);
    let penalty = match pair.penalty {
        Penalty::Theta(_) => "given".to_string(),
        Penalty::RodModel { c, h } => format!("rod model c = {c}, h = {h}"),
    };
    let mut out = format!(
        "contact pair {}: {}.{} with {}.{}, θ = {} ({penalty}){}{friction}\n",
        pair.name,
        a.name,
        pair.boundaries[0],
        b.name,
        pair.boundaries[1],
        sig(model.theta(p)),
        if pair.profile.is_some() {
            ", with a gap profile"
        } else {
            ""
        }
    );
    for (side, body) in [a, b].into_iter().enumerate() {
        let points: Vec<_> = interface
            .points
            .iter()
            .filter(|q| q.is_contact() && q.pair == p && q.body == pair.bodies[side])
            .collect();
        let partnered: Vec<_> = points.iter().filter(|q| q.has_partner()).collect();
        let min_gap = partnered
            .iter()
            .map(|q| q.gap)
            .fold(f64::INFINITY, f64::min);
        let gap = if partnered.is_empty() {
            String::new()
        } else {
            format!(", smallest initial gap {}", sig(min_gap))
        };
        out += &format!(
            "  {}: {} contact points, {} facing {}{gap}{}\n",
            body.name,
            points.len(),
            partnered.len(),
            [b, a][side].name,
            side_role(interface, p, pair.bodies[side])
        );
    }
    out
}

/// How a side of pair `p` takes part in a balanced pair (empty for an own-side one): whether its
/// pressure loads both bodies (the reference side) or it follows, and its tangential unknowns.
fn side_role(interface: &Interface, p: usize, body: usize) -> String {
    let on_side = || {
        interface
            .points
            .iter()
            .filter(move |q| q.pair == p && q.body == body)
    };
    let tangents = on_side().filter(|q| q.role == Role::Tangent).count();
    let extra = if tangents > 0 {
        format!(", {tangents} tangential unknowns")
    } else {
        String::new()
    };
    match on_side().map(|q| q.role).find(|r| *r != Role::Tangent) {
        Some(Role::Carrier) => format!("; balanced: its pressure loads both sides{extra}"),
        Some(Role::Follower) => format!("; balanced: loaded by the other side{extra}"),
        _ => String::new(),
    }
}

/// The solver lines: the settings as `solve` prints them, the starting values and threads, the
/// load steps with the monitored boundary, and the pairs with exact contact.
fn solver_text(loaded: &Loaded) -> String {
    let settings = &loaded.settings;
    let threads = loaded
        .threads
        .map_or("all cores".to_string(), |n| n.to_string());
    let mut text = format!(
        "solver: {settings}, u0 {:e}, u-prev {:e}, threads {threads}\n",
        settings.u0, settings.u_prev
    );
    if let Some(steps) = &loaded.steps {
        let factors: Vec<String> = steps.iter().map(f64::to_string).collect();
        text += &format!("  load steps: {}", factors.join(", "));
        if let Some(m) = &loaded.monitor {
            text += &format!(
                " (monitor {}.{})",
                loaded.model.bodies[m.body].name, m.boundary
            );
        }
        text += "\n";
    }
    if let Some(history) = &loaded.history {
        text += &history_text(history);
    }
    let augmented: Vec<&str> = loaded
        .model
        .pairs
        .iter()
        .filter(|p| p.enforcement == Enforcement::Augmented)
        .map(|p| p.name.as_str())
        .collect();
    if !augmented.is_empty() {
        text += &format!(
            "  exact contact (augmented Lagrangian) on {}\n",
            augmented.join(", ")
        );
    }
    text
}

fn mesh_text(mesh: &MeshSpec) -> String {
    match mesh {
        MeshSpec::Rectangle {
            x,
            y,
            nx,
            ny,
            mirror,
            ..
        } => format!(
            "rectangle [{}, {}] × [{}, {}], {nx} × {ny} cells{}",
            x[0],
            x[1],
            y[0],
            y[1],
            if *mirror { ", mirrored" } else { "" }
        ),
        MeshSpec::Gmsh { file, .. } => format!("gmsh file {}", file.display()),
        MeshSpec::Inline {
            nodes, triangles, ..
        } => format!(
            "inline mesh, {} nodes, {} triangles",
            nodes.len(),
            triangles.len()
        ),
    }
}
