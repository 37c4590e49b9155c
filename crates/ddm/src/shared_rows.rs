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
    /// The lower triangle of the reduced stiffness K, for the symmetric step.
    stiffness: Vec<(usize, usize, f64)>,
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

/// Calls `f(row, col, value)` for the lower triangle of a sparse body's reduced stiffness K (no
/// springs) with its unknowns at `offset..`, column by column with rows ascending, in the same
/// order on every process: the symmetric Newton step's block of the body
/// (`crate::newton::primal`). Nothing for a dense body.
pub fn stiffness_columns(
    part: &BodyPart,
    body: Option<&CondensedBody>,
    offset: usize,
    f: &mut dyn FnMut(usize, usize, f64),
) {
    match (part, body) {
        (BodyPart::Remote(rows), _) => rows
            .stiffness
            .iter()
            .for_each(|&(r, c, v)| f(offset + r, offset + c, v)),
        (BodyPart::Own { .. }, Some(body)) => {
            stiffness_entries(body, |r, c, v| f(offset + r, offset + c, v))
        }
        _ => {}
    }
}

/// Calls `f(row, col, value)` for the lower triangle of the body's reduced stiffness, column by
/// column.
fn stiffness_entries(body: &CondensedBody, mut f: impl FnMut(usize, usize, f64)) {
    let op = body.operator();
    let lower = op.reduced_lower();
    let values = op.reduced_stiffness_values();
    let (col_ptr, row_idx) = (lower.symbolic().col_ptr(), lower.symbolic().row_idx());
    for col in 0..lower.ncols() {
        for p in col_ptr[col]..col_ptr[col + 1] {
            f(row_idx[p], col, values[p]);
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
/// pairs, the number of rows' triples, the rows' (row, column, value) triples, then the
/// stiffness's]`; empty for a dense body.
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
    out.push(trip.len() as f64);
    out.extend(
        trip.iter()
            .flat_map(|t| [t.row as f64, t.col as f64, t.val]),
    );
    drop(trip);
    stiffness_entries(body, |r, c, v| out.extend([r as f64, c as f64, v]));
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
    let count = *values.get(at)? as usize;
    let triples = |v: &[f64]| {
        v.chunks_exact(3)
            .map(|t| (t[0] as usize, t[1] as usize, t[2]))
            .collect()
    };
    let end = count.checked_mul(3)?.checked_add(at + 1)?;
    let rows = triples(values.get(at + 1..end)?);
    let stiffness = triples(values.get(end..)?);
    Some(SparseRows {
        free,
        dofs,
        rows,
        stiffness,
    })
}
