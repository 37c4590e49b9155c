//! What the processes of a distributed solve hand each other beyond interface values
//! (`docs/mpi.md`), packed into one vector of `f64` for the exchange's gather: a body's contact
//! skin and facts ([`pack_remote`]), and a body's support reactions ([`pack_reactions`]).
//!
//! Counts and node numbers travel as `f64` (exact below 2⁵³), names as their UTF-8 bytes, and
//! numbers whole, so that every process unpacks the bits the owner packed.

use std::collections::BTreeMap;

use contactdd_core::rigid::RigidBasis;
use contactdd_core::{Edge, ElasticBody, Material, Mesh, Order, Plane};
use contactdd_ddm::{BodyFacts, Remote};

use crate::reactions::{BodyReactions, SupportReaction};

/// A packed vector that ends early or holds a value of the wrong kind (a bug, not an input).
#[derive(Debug, thiserror::Error)]
#[error("a packed body from another process is malformed at value {at}")]
pub struct Malformed {
    /// Position of the first value that could not be read.
    pub at: usize,
}

/// Appends values to a packed vector.
#[derive(Default)]
struct Packer(Vec<f64>);

impl Packer {
    fn num(&mut self, x: f64) {
        self.0.push(x);
    }

    fn count(&mut self, n: usize) {
        self.0.push(n as f64);
    }

    fn text(&mut self, s: &str) {
        self.count(s.len());
        self.0.extend(s.bytes().map(f64::from));
    }
}

/// Reads a packed vector in the order it was written.
struct Unpacker<'a> {
    values: &'a [f64],
    at: usize,
}

impl Unpacker<'_> {
    fn num(&mut self) -> Result<f64, Malformed> {
        let x = self.values.get(self.at).copied();
        let x = x.ok_or(Malformed { at: self.at })?;
        self.at += 1;
        Ok(x)
    }

    fn count(&mut self) -> Result<usize, Malformed> {
        let at = self.at;
        let x = self.num()?;
        let exact = x >= 0.0 && x.fract() == 0.0 && x < 2f64.powi(53);
        exact.then_some(x as usize).ok_or(Malformed { at })
    }

    fn point(&mut self) -> Result<[f64; 2], Malformed> {
        Ok([self.num()?, self.num()?])
    }

    fn text(&mut self) -> Result<String, Malformed> {
        let at = self.at;
        let n = self.count()?;
        let bytes = (0..n)
            .map(|_| u8::try_from(self.count()?).map_err(|_| Malformed { at }))
            .collect::<Result<Vec<u8>, _>>()?;
        String::from_utf8(bytes).map_err(|_| Malformed { at })
    }
}

/// The skin of a remote body's stand-in and its facts (see [`Remote::of`]).
pub fn pack_remote(stand_in: &ElasticBody, remote: &Remote) -> Vec<f64> {
    let mut p = Packer::default();
    let mesh = &stand_in.mesh;
    p.count(match mesh.order() {
        Order::P1 => 1,
        Order::P2 => 2,
    });
    p.count(mesh.num_nodes());
    for (x, &id) in mesh.nodes().iter().zip(&remote.ids) {
        p.num(x[0]);
        p.num(x[1]);
        p.count(id);
    }
    p.count(mesh.boundaries().len());
    for (name, edges) in mesh.boundaries() {
        p.text(name);
        p.count(edges.len());
        for e in edges {
            p.count(e.a);
            p.count(e.b);
            p.count(e.mid.map_or(0, |m| m + 1));
        }
    }
    p.count(mesh.node_sets().len());
    mesh.node_sets().keys().for_each(|name| p.text(name));
    pack_facts(&mut p, &remote.facts);
    p.0
}

fn pack_facts(p: &mut Packer, f: &BodyFacts) {
    p.count(f.nodes);
    p.count(f.cells);
    p.count(f.prescribed);
    let (center, size) = f.basis.parts();
    for x in [f.lo, f.hi, center].iter().flatten() {
        p.num(*x);
    }
    p.num(size);
    p.count(f.free.len());
    for (v, work) in f.free.iter().zip(&f.free_load) {
        v.iter().for_each(|&x| p.num(x));
        p.num(*work);
    }
    f.applied_load.iter().for_each(|&x| p.num(x));
}

/// The stand-in body `name` (of `material` and `plane`, known to every process) and its remote
/// part, from what [`pack_remote`] packed.
pub fn unpack_remote(
    values: &[f64],
    name: &str,
    material: Material,
    plane: Plane,
) -> Result<(ElasticBody, Remote), Malformed> {
    let mut u = Unpacker { values, at: 0 };
    let order = match u.count()? {
        1 => Order::P1,
        2 => Order::P2,
        _ => return Err(Malformed { at: 0 }),
    };
    let n = u.count()?;
    let (mut nodes, mut ids) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for _ in 0..n {
        nodes.push(u.point()?);
        ids.push(u.count()?);
    }
    let mut boundaries = BTreeMap::new();
    for _ in 0..u.count()? {
        let name = u.text()?;
        let edges = (0..u.count()?)
            .map(|_| {
                let (a, b, mid) = (u.count()?, u.count()?, u.count()?);
                Ok(Edge {
                    a,
                    b,
                    mid: mid.checked_sub(1),
                })
            })
            .collect::<Result<Vec<Edge>, Malformed>>()?;
        boundaries.insert(name, edges);
    }
    let sets = (0..u.count()?)
        .map(|_| u.text())
        .collect::<Result<Vec<_>, _>>()?;
    let at = u.at;
    let mesh =
        Mesh::skin_from_parts(nodes, order, boundaries, sets).map_err(|_| Malformed { at })?;
    let facts = unpack_facts(&mut u, order)?;
    let stand_in = Remote::stand_in(name, mesh, material, plane);
    Ok((stand_in, Remote { ids, facts }))
}

fn unpack_facts(u: &mut Unpacker<'_>, order: Order) -> Result<BodyFacts, Malformed> {
    let (nodes, cells, prescribed) = (u.count()?, u.count()?, u.count()?);
    let (lo, hi, center) = (u.point()?, u.point()?, u.point()?);
    let size = u.num()?;
    let (mut free, mut free_load) = (Vec::new(), Vec::new());
    for _ in 0..u.count()? {
        free.push([u.num()?, u.num()?, u.num()?]);
        free_load.push(u.num()?);
    }
    Ok(BodyFacts {
        nodes,
        cells,
        prescribed,
        order,
        lo,
        hi,
        basis: RigidBasis::from_parts(center, size),
        free,
        free_load,
        applied_load: u.point()?,
    })
}

/// A body's support reactions.
pub fn pack_reactions(r: &BodyReactions) -> Vec<f64> {
    let mut p = Packer::default();
    p.text(&r.body);
    p.count(r.supports.len());
    for s in &r.supports {
        p.text(&s.boundary);
        s.force.iter().for_each(|&x| p.num(x));
    }
    r.total.iter().for_each(|&x| p.num(x));
    p.0
}

/// The reactions [`pack_reactions`] packed.
pub fn unpack_reactions(values: &[f64]) -> Result<BodyReactions, Malformed> {
    let mut u = Unpacker { values, at: 0 };
    let body = u.text()?;
    let supports = (0..u.count()?)
        .map(|_| {
            Ok(SupportReaction {
                boundary: u.text()?,
                force: u.point()?,
            })
        })
        .collect::<Result<Vec<_>, Malformed>>()?;
    Ok(BodyReactions {
        body,
        supports,
        total: u.point()?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use contactdd_core::{Constraints, Diagonal, Rectangle};

    #[test]
    fn a_remote_body_and_its_reactions_travel_whole() {
        let mesh = Rectangle {
            origin: [0.0, 0.1],
            corner: [1.3, 0.7],
            nx: 5,
            ny: 3,
            diagonal: Diagonal::Right,
            mirror: false,
            order: Order::P2,
        }
        .mesh()
        .unwrap();
        let n = mesh.num_nodes();
        let material = Material::new(2.1e5, 0.3).unwrap();
        let body = ElasticBody {
            name: "blöck".into(),
            load: (0..2 * n).map(|i| (i as f64 * 0.37).sin()).collect(),
            constraints: Constraints::new(n),
            mesh,
            material,
            plane: Plane::Strain,
        };
        let (stand_in, remote) = Remote::of(&body, &["top", "left"]);
        let packed = pack_remote(&stand_in, &remote);
        let (back, back_remote) = unpack_remote(&packed, "blöck", material, Plane::Strain).unwrap();
        assert_eq!(back_remote, remote);
        assert_eq!(back.mesh.nodes(), stand_in.mesh.nodes());
        assert_eq!(back.mesh.boundaries(), stand_in.mesh.boundaries());
        assert_eq!(remote.facts.free.len(), 3);
        assert!(unpack_remote(&packed[..packed.len() - 1], "b", material, Plane::Strain).is_err());

        let r = BodyReactions {
            body: "blöck".into(),
            supports: vec![SupportReaction {
                boundary: "bottom".into(),
                force: [1.5, -2.0 / 3.0],
            }],
            total: [1e-300, f64::MAX],
        };
        assert_eq!(unpack_reactions(&pack_reactions(&r)).unwrap(), r);
    }
}
