//! The bodies of a problem file on the processes of a distributed solve (docs/mpi.md): each
//! process meshes only the bodies the partition gives it, and the others reach it as their
//! contact skins and facts ([`contactdd_ddm::Remote`], packed by [`crate::packed`]). The partition
//! is made before any mesh exists, from each body's estimated size ([`estimated_costs`]).

use std::io::{BufRead, BufReader};
use std::path::Path;

use contactdd_core::Order;
use contactdd_ddm::exchange::{factor_cost, Exchange};
use contactdd_ddm::{Remote, SetupError};

use crate::error::LoadError;
use crate::model_builder::ModelBuilder;
use crate::packed::{pack_remote, unpack_remote};
use crate::problem::{MeshSpec, Problem};

/// Each body's estimated factorisation cost, from its mesh description alone: what the partition
/// balances before any process meshes anything.
pub fn estimated_costs(problem: &Problem, base_dir: &Path) -> Vec<f64> {
    (problem.bodies.iter())
        .map(|b| factor_cost(2 * estimated_nodes(&b.mesh, base_dir)))
        .collect()
}

/// The number of nodes a mesh description will have: exact for rectangles and inline meshes;
/// for a Gmsh file the count in its `$Nodes` header (the whole file's, for a body that is one
/// surface of several), times 4 when P1 triangles are promoted to P2. 1 for a file that cannot be
/// read: meshing it will report why.
pub fn estimated_nodes(spec: &MeshSpec, base_dir: &Path) -> usize {
    match spec {
        MeshSpec::Rectangle { nx, ny, order, .. } => {
            let k = if *order == Order::P2 { 2 } else { 1 };
            (k * nx + 1).saturating_mul(k * ny + 1)
        }
        MeshSpec::Inline { nodes, .. } => nodes.len(),
        MeshSpec::Gmsh { file, order, .. } => {
            let nodes = gmsh_node_count(&base_dir.join(file)).unwrap_or(1);
            match order {
                Some(Order::P2) => 4 * nodes,
                _ => nodes,
            }
        }
    }
}

/// The node count in the line after `$Nodes`: the only number (format 2.2) or the second of four
/// (format 4.1). Reads no further.
fn gmsh_node_count(path: &Path) -> Option<usize> {
    let file = std::fs::File::open(path).ok()?;
    let mut lines = BufReader::new(file).lines().map_while(Result::ok);
    lines.by_ref().find(|l| l.trim() == "$Nodes")?;
    let header = lines.next()?;
    let numbers: Vec<&str> = header.split_whitespace().collect();
    match numbers.as_slice() {
        [n] | [_, n, _, _] => n.parse().ok(),
        _ => None,
    }
}

/// Adds every body of `problem` to `builder`: this process's own, meshed; the others as the
/// stand-ins their processes send. A collective. The first error of any process while meshing
/// (by rank, which with the partition's contiguous runs is the first body's) is every process's.
pub(crate) fn add_bodies(
    builder: &mut ModelBuilder,
    problem: &Problem,
    base_dir: &Path,
    exchange: &dyn Exchange,
) -> Result<(), LoadError> {
    let mut own = Vec::new();
    let mut error = None;
    for (b, spec) in problem.bodies.iter().enumerate() {
        if exchange.owns(b) {
            match builder.body(spec, base_dir) {
                Ok(body) => own.push(body),
                Err(e) => {
                    error = Some(e);
                    break;
                }
            }
        }
    }
    agreed(exchange, error.map_or(Ok(()), Err))?;
    let packed = (own.iter())
        .map(|body| {
            let names = contact_boundaries(problem, &body.name);
            let (stand_in, remote) = Remote::of(body, &names);
            pack_remote(&stand_in, &remote)
        })
        .collect();
    let all = exchange.gather(packed);
    let mut own = own.into_iter();
    for (b, spec) in problem.bodies.iter().enumerate() {
        let body = match exchange.owns(b) {
            true => own.next().map(|body| (body, None)),
            false => stand_in(builder, spec, &all[b]),
        };
        let (body, remote) = body.ok_or_else(|| {
            distributed(format!(
                "body '{}' did not arrive whole from its process",
                contactdd_core::names::shown(&spec.name)
            ))
        })?;
        builder.push_body(body, remote);
    }
    Ok(())
}

/// The stand-in of body `spec` from what its process packed.
fn stand_in(
    builder: &ModelBuilder,
    spec: &crate::problem::BodySpec,
    packed: &[f64],
) -> Option<(contactdd_core::ElasticBody, Option<Remote>)> {
    let material = *builder.materials().get(&spec.material)?;
    let (body, remote) = unpack_remote(packed, &spec.name, material, builder.plane()).ok()?;
    Some((body, Some(remote)))
}

/// The boundaries of body `body` that the problem's contact pairs name.
fn contact_boundaries<'a>(problem: &'a Problem, body: &str) -> Vec<&'a str> {
    let mut names = Vec::new();
    for c in &problem.contact {
        for (b, boundary) in c.bodies.iter().zip(&c.boundaries) {
            if b == body && !names.contains(&boundary.as_str()) {
                names.push(boundary.as_str());
            }
        }
    }
    names
}

/// `result` once every process has said whether it failed: this process's own error, or the
/// first error of another (by rank), or success if none failed. A collective.
pub(crate) fn agreed<T>(
    exchange: &dyn Exchange,
    result: Result<T, LoadError>,
) -> Result<T, LoadError> {
    let first = exchange.agree(result.as_ref().err().map(|e| e.to_string()));
    match (result, first) {
        (Err(e), _) => Err(e),
        (Ok(_), Some(message)) => Err(distributed(message)),
        (Ok(value), None) => Ok(value),
    }
}

fn distributed(message: String) -> LoadError {
    LoadError::Setup(SetupError::Distributed(message))
}
