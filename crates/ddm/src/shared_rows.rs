//! The sparse path's bodies in the interface Newton system of a distributed solve (`docs/mpi.md`,
//! `docs/sparse-path.md`). On the sparse path the Newton step couples the rows
//! K₀ δu − N D₀ δτ = 0 of every sparse body in one sparse LU. Each process factorises that same
//! system: the process that owns a sparse body packs its rows and its points' reduced DOFs once
//! per solve, and the others replay them, entry for entry and in the same order, so that every
//! process assembles what one process assembles and the steps agree to the bit.

use faer::sparse::Triplet;

use crate::condensed::CondensedBody;
use crate::exchange::{share_vectors, Exchange};

/// How a body enters the Newton system.
pub enum BodyPart {
    /// A dense body: its block B_b.
    Dense,
    /// A sparse body this process owns: its rows come from its factorised operator.
    Own {
        /// Number of its reduced unknowns.
        free: usize,
    },
    /// A sparse body of another process: its rows as that process packed them.
    Remote(SparseRows),
}

impl BodyPart {
    /// The number of reduced unknowns of a sparse body (`None` for a dense one).
    pub fn sparse_free(&self) -> Option<usize> {
        match self {
            BodyPart::Dense => None,
            BodyPart::Own { free } => Some(*free),
            BodyPart::Remote(rows) => Some(rows.free),
        }
    }
}

/// A sparse body's rows of the Newton system in its own numbering: reduced unknowns `0..free`,
/// then its point j as column `free + j`.
pub struct SparseRows {
    free: usize,
    dofs: Vec<Vec<(usize, f64)>>,
    rows: Vec<(usize, usize, f64)>,
}

impl SparseRows {
    /// Point j's reduced DOFs with the normal's components (`SparseContact::point_dofs`).
    pub fn point_dofs(&self, j: usize) -> &[(usize, f64)] {
        self.dofs.get(j).map_or(&[], Vec::as_slice)
    }

    /// Pushes the rows with the reduced unknowns at columns `offset..` and the points at
    /// `start..`, as `SparseContact::push_body_rows` does on the owning process.
    pub fn replay(
        &self,
        (offset, start): (usize, usize),
        trip: &mut Vec<Triplet<usize, usize, f64>>,
    ) {
        for &(r, c, v) in &self.rows {
            let col = if c < self.free {
                offset + c
            } else {
                start + (c - self.free)
            };
            trip.push(Triplet::new(offset + r, col, v));
        }
    }
}

/// How every body enters the Newton system, the same on every process: in one process from the
/// bodies themselves; on several, the sparse bodies of the other processes from their packed
/// rows (a collective).
pub fn body_parts(bodies: &[Option<CondensedBody>], exchange: &dyn Exchange) -> Vec<BodyPart> {
    let own = |body: &CondensedBody| match body.sparse() {
        Some(_) => BodyPart::Own {
            free: body.operator().num_free(),
        },
        None => BodyPart::Dense,
    };
    if exchange.is_local() {
        return bodies
            .iter()
            .map(|b| b.as_ref().map_or(BodyPart::Dense, own))
            .collect();
    }
    let packed = bodies
        .iter()
        .map(|b| b.as_ref().map(pack).unwrap_or_default())
        .collect();
    share_vectors(exchange, packed)
        .iter()
        .zip(bodies)
        .map(|(values, body)| match body {
            Some(body) => own(body),
            None => unpack(values).map_or(BodyPart::Dense, BodyPart::Remote),
        })
        .collect()
}

/// A sparse body's rows and point DOFs: `[free, points, per point its DOF count and (dof, n)
/// pairs, then (row, column, value) triples]`; empty for a dense body.
fn pack(body: &CondensedBody) -> Vec<f64> {
    let Some(s) = body.sparse() else {
        return Vec::new();
    };
    let op = body.operator();
    let free = op.num_free();
    let mut trip = Vec::new();
    s.push_body_rows(op, body.reference_springs(), (0, free), &mut trip);
    let points = body.len();
    let mut out = vec![free as f64, points as f64];
    for j in 0..points {
        let dofs = s.point_dofs(j);
        out.push(dofs.len() as f64);
        out.extend(dofs.iter().flat_map(|&(r, n)| [r as f64, n]));
    }
    out.extend(
        trip.iter()
            .flat_map(|t| [t.row as f64, t.col as f64, t.val]),
    );
    out
}

/// The rows [`pack`] packed (`None` for a dense body's empty vector).
fn unpack(values: &[f64]) -> Option<SparseRows> {
    let (free, points) = (*values.first()? as usize, *values.get(1)? as usize);
    let mut at = 2;
    let mut dofs = Vec::with_capacity(points);
    for _ in 0..points {
        let k = *values.get(at)? as usize;
        let pairs = values.get(at + 1..at + 1 + 2 * k)?;
        dofs.push(pairs.chunks(2).map(|p| (p[0] as usize, p[1])).collect());
        at += 1 + 2 * k;
    }
    let rows = values
        .get(at..)?
        .chunks_exact(3)
        .map(|t| (t[0] as usize, t[1] as usize, t[2]))
        .collect();
    Some(SparseRows { free, dofs, rows })
}
