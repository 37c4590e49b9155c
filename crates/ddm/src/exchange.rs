//! The communication seam: how the per-body results of one process reach the others.
//!
//! Only the bodies' own computations — the Robin solves, the responses of the interface Newton
//! method, the initial loads, the recovered fields — are split: each process computes the bodies
//! it *owns*, and an [`Exchange`] brings their values to the processes that need them:
//! - to every process ([`Exchange::gather`], a collective), where the iteration reads the whole
//!   interface: the interface Newton system, Anderson's least squares, the coarse problem, the
//!   per-body checks every process must agree on;
//! - to the processes of neighbouring bodies only ([`Exchange::swap`], point to point, planned by
//!   [`Neighbours`]), after each Robin sweep of the relaxed iteration: a body's sweep reads only
//!   its own points and their partners.
//!
//! No floating-point sum ever mixes the processes' partial results in an order of their own: a
//! reduction runs either on full vectors in the single process's order, or on per-body partial
//! sums added in body order, as one process adds them. So a distributed run reproduces the
//! single-process one bit for bit.
//!
//! [`Local`] is the in-process exchange (one process owns every body; rayon parallelises over
//! them); the command line's MPI exchange (`--features mpi`, `docs/mpi.md`) is the other.

use std::ops::Range;

use faer::Mat;

use crate::outcome::Breakdown;

/// How the bodies' values are shared between the processes of one solve.
pub trait Exchange: Send + Sync {
    /// The process that computes each body.
    fn owner(&self) -> &[usize];
    /// This process.
    fn rank(&self) -> usize;
    /// Every body's values, in body order and the same on every process, given this process's
    /// own bodies' values in increasing body order. A collective: every process calls it.
    fn gather(&self, own: Vec<Vec<f64>>) -> Vec<Vec<f64>>;
    /// The first error of any process (by rank), the same on every process. A collective.
    fn agree(&self, error: Option<String>) -> Option<String>;
    /// Point to point: sends every `(rank, values)` of `sends` to that rank and returns what the
    /// ranks `from` send to this one, in the order of `from`. Only the ranks named take part, and
    /// two ranks receive each other's messages in the order they were sent.
    fn swap(&self, sends: Vec<(usize, Vec<f64>)>, from: &[usize]) -> Vec<Vec<f64>>;

    /// Whether this process computes body `b`.
    fn owns(&self, b: usize) -> bool {
        self.owner()[b] == self.rank()
    }
    /// Whether this process owns every body (nothing to exchange).
    fn is_local(&self) -> bool {
        self.owner().iter().all(|&r| r == self.rank())
    }
}

/// One process owns every body: every exchange is a no-op.
#[derive(Clone, Debug)]
pub struct Local {
    owner: Vec<usize>,
}

impl Local {
    /// The exchange of a model with `bodies` bodies in one process.
    pub fn new(bodies: usize) -> Local {
        Local {
            owner: vec![0; bodies],
        }
    }
}

impl Exchange for Local {
    fn owner(&self) -> &[usize] {
        &self.owner
    }
    fn rank(&self) -> usize {
        0
    }
    fn gather(&self, own: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        own
    }
    fn agree(&self, error: Option<String>) -> Option<String> {
        error
    }
    fn swap(&self, _sends: Vec<(usize, Vec<f64>)>, from: &[usize]) -> Vec<Vec<f64>> {
        // One process has no neighbours: nothing is ever sent here.
        vec![Vec::new(); from.len()]
    }
}

/// Who sends which bodies' values to whom when only neighbours exchange: a process receives the
/// values of the other processes' bodies that its own bodies read, and sends its own bodies'
/// values to the processes whose bodies read them. Every process holds then its own bodies'
/// values and those of their neighbours, and nothing else is current.
#[derive(Clone, Debug, Default)]
pub struct Neighbours {
    /// Per process this one sends to: the own bodies it sends, in increasing order.
    send: Vec<(usize, Vec<usize>)>,
    /// Per process this one receives from: the bodies it receives, in increasing order.
    recv: Vec<(usize, Vec<usize>)>,
}

impl Neighbours {
    /// The plan for bodies where body b reads the values of the bodies `reads[b]`.
    pub fn new(exchange: &dyn Exchange, reads: &[Vec<usize>]) -> Neighbours {
        let (owner, me) = (exchange.owner(), exchange.rank());
        let ranks = owner.iter().max().map_or(1, |r| r + 1).max(me + 1);
        let mut send = vec![Vec::new(); ranks];
        let mut recv = vec![Vec::new(); ranks];
        for (b, read) in reads.iter().enumerate() {
            for &c in read {
                let (reader, holder) = (owner[b], owner[c]);
                if reader == me && holder != me {
                    recv[holder].push(c);
                }
                if holder == me && reader != me {
                    send[reader].push(c);
                }
            }
        }
        let tidy = |lists: Vec<Vec<usize>>| -> Vec<(usize, Vec<usize>)> {
            lists
                .into_iter()
                .enumerate()
                .filter(|(_, l)| !l.is_empty())
                .map(|(r, mut l)| {
                    l.sort_unstable();
                    l.dedup();
                    (r, l)
                })
                .collect()
        };
        Neighbours {
            send: tidy(send),
            recv: tidy(recv),
        }
    }

    /// The bodies whose values this process receives.
    pub fn received(&self) -> impl Iterator<Item = usize> + '_ {
        self.recv
            .iter()
            .flat_map(|(_, bodies)| bodies.iter().copied())
    }

    /// Fills the slices `ranges[b]` of every buffer in `values` of the bodies this process
    /// receives with their owners' values (point to point).
    pub fn share(
        &self,
        exchange: &dyn Exchange,
        ranges: &[Range<usize>],
        values: &mut [&mut [f64]],
    ) {
        if self.send.is_empty() && self.recv.is_empty() {
            return;
        }
        // Per message: its length first (never an empty buffer), then per body its slice of
        // each buffer.
        let sends = self
            .send
            .iter()
            .map(|(rank, bodies)| {
                let mut v = vec![0.0];
                for &b in bodies {
                    for buf in values.iter() {
                        v.extend_from_slice(&buf[ranges[b].clone()]);
                    }
                }
                v[0] = (v.len() - 1) as f64;
                (*rank, v)
            })
            .collect();
        let from: Vec<usize> = self.recv.iter().map(|(r, _)| *r).collect();
        for ((_, bodies), message) in self.recv.iter().zip(exchange.swap(sends, &from)) {
            let mut at = 1;
            for &b in bodies {
                for buf in values.iter_mut() {
                    let range = ranges[b].clone();
                    if let Some(v) = message.get(at..at + range.len()) {
                        buf[range.clone()].copy_from_slice(v);
                    }
                    at += range.len();
                }
            }
        }
    }
}

/// Fills the slices `ranges[b]` of `values` of the bodies this process does not own with their
/// owners' values.
pub fn share_slices(exchange: &dyn Exchange, ranges: &[Range<usize>], values: &mut [f64]) {
    if exchange.is_local() {
        return;
    }
    let own = owned(exchange, ranges.len())
        .map(|b| values[ranges[b].clone()].to_vec())
        .collect();
    for (range, v) in ranges.iter().zip(exchange.gather(own)) {
        values[range.clone()].copy_from_slice(&v);
    }
}

/// The outputs of a sweep in one exchange: fills the other processes' bodies' slices
/// `ranges[b]` of every buffer in `values` and returns every body's status.
pub fn share_outputs(
    exchange: &dyn Exchange,
    ranges: &[Range<usize>],
    values: &mut [&mut [f64]],
    status: Vec<Result<(), Breakdown>>,
) -> Vec<Result<(), Breakdown>> {
    if exchange.is_local() {
        return status;
    }
    // Per body: its slice of each buffer, then its status.
    let packed = ranges
        .iter()
        .zip(&status)
        .map(|(range, s)| {
            let mut v: Vec<f64> = values
                .iter()
                .flat_map(|buf| buf[range.clone()].iter().copied())
                .collect();
            v.push(encode(s));
            v
        })
        .collect();
    let all = share_vectors(exchange, packed);
    for (range, v) in ranges.iter().zip(&all) {
        for (k, buf) in values.iter_mut().enumerate() {
            let at = k * range.len();
            buf[range.clone()].copy_from_slice(&v[at..at + range.len()]);
        }
    }
    all.iter()
        .map(|v| decode(v.last().copied().unwrap_or(f64::NAN)))
        .collect()
}

/// Every body's entry of `per_body`, where this process filled its own bodies'.
pub fn share_vectors(exchange: &dyn Exchange, per_body: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    if exchange.is_local() {
        return per_body;
    }
    let own = per_body
        .into_iter()
        .enumerate()
        .filter(|(b, _)| exchange.owns(*b))
        .map(|(_, v)| v)
        .collect();
    exchange.gather(own)
}

/// Every body's matrix, where this process filled its own bodies' (the others may be empty).
pub fn share_matrices(exchange: &dyn Exchange, mats: Vec<Mat<f64>>) -> Vec<Mat<f64>> {
    if exchange.is_local() {
        return mats;
    }
    let flat = mats
        .iter()
        .map(|m| {
            let mut v = vec![m.nrows() as f64, m.ncols() as f64];
            for j in 0..m.ncols() {
                v.extend((0..m.nrows()).map(|i| m[(i, j)]));
            }
            v
        })
        .collect();
    share_vectors(exchange, flat)
        .iter()
        .map(|v| {
            let (r, c) = (v[0] as usize, v[1] as usize);
            Mat::from_fn(r, c, |i, j| v[2 + j * r + i])
        })
        .collect()
}

/// The bodies this process owns, in increasing order.
fn owned(exchange: &dyn Exchange, bodies: usize) -> impl Iterator<Item = usize> + '_ {
    (0..bodies).filter(move |&b| exchange.owns(b))
}

/// A status as a number (exact in f64).
pub(crate) fn encode(status: &Result<(), Breakdown>) -> f64 {
    match status {
        Ok(()) => 0.0,
        Err(Breakdown::LostContact) => 1.0,
        Err(Breakdown::Singular) => 2.0,
        Err(Breakdown::NonFinite) => 3.0,
        Err(Breakdown::Growth) => 4.0,
        Err(Breakdown::NoDescent) => 5.0,
        Err(Breakdown::Slides) => 6.0,
    }
}

pub(crate) fn decode(code: f64) -> Result<(), Breakdown> {
    match code as i64 {
        0 => Ok(()),
        1 => Err(Breakdown::LostContact),
        2 => Err(Breakdown::Singular),
        4 => Err(Breakdown::Growth),
        5 => Err(Breakdown::NoDescent),
        6 => Err(Breakdown::Slides),
        _ => Err(Breakdown::NonFinite),
    }
}

/// Splits `cost` (one estimate per body, in body order) over `ranks` processes: contiguous runs
/// of bodies (so that neighbours in a chain, numbered in order, stay together) whose costs are as
/// close to equal as cutting at body boundaries allows. Returns the owner of every body; every
/// rank gets at least one body when there are enough.
pub fn partition(cost: &[f64], ranks: usize) -> Vec<usize> {
    let ranks = ranks.max(1);
    let total: f64 = cost.iter().sum();
    let mut owner = Vec::with_capacity(cost.len());
    let (mut rank, mut done) = (0usize, 0.0);
    for (b, &c) in cost.iter().enumerate() {
        let left = cost.len() - b;
        let ranks_left = ranks - rank;
        // Move on when this rank has its share (cut at the nearer side of the target) or when
        // the remaining bodies are just enough for the remaining ranks.
        let target = total * (rank + 1) as f64 / ranks as f64;
        let past = done + c / 2.0 > target || left < ranks_left;
        if rank + 1 < ranks && past && owner.last() == Some(&rank) {
            rank += 1;
        }
        owner.push(rank);
        done += c;
    }
    owner
}

/// The estimated cost of factorising a body with `dofs` degrees of freedom: a nested-dissection
/// Cholesky factorisation of a 2D mesh takes about dofs^1.5 flops. (The condensation on the
/// contact points, dofs × points, is left out: the points are not known before the contact
/// geometry is built.)
pub fn factor_cost(dofs: usize) -> f64 {
    (dofs as f64).powf(1.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_bodies_split_evenly_and_contiguously() {
        let owner = partition(&[1.0; 6], 3);
        assert_eq!(owner, vec![0, 0, 1, 1, 2, 2]);
        let owner = partition(&[1.0; 2], 3);
        assert_eq!(owner, vec![0, 1]);
    }

    #[test]
    fn a_heavy_body_gets_a_rank_of_its_own() {
        let owner = partition(&[10.0, 1.0, 1.0, 1.0], 2);
        assert_eq!(owner, vec![0, 1, 1, 1]);
    }

    #[test]
    fn every_rank_gets_a_body_when_there_are_enough() {
        let owner = partition(&[100.0, 1.0, 1.0], 3);
        assert_eq!(owner, vec![0, 1, 2]);
    }

    /// A process of a partition, for planning only (it exchanges nothing).
    struct Planner {
        owner: Vec<usize>,
        rank: usize,
    }

    impl Exchange for Planner {
        fn owner(&self) -> &[usize] {
            &self.owner
        }
        fn rank(&self) -> usize {
            self.rank
        }
        fn gather(&self, own: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
            own
        }
        fn agree(&self, error: Option<String>) -> Option<String> {
            error
        }
        fn swap(&self, _sends: Vec<(usize, Vec<f64>)>, from: &[usize]) -> Vec<Vec<f64>> {
            vec![Vec::new(); from.len()]
        }
    }

    #[test]
    fn neighbours_exchange_only_what_other_ranks_read() {
        // Bodies 0..5 on ranks [0, 0, 1, 1, 2]; body 2 reads 1 and 4, body 4 reads 0 and 2,
        // body 0 reads 2 twice (its points' partners repeat), body 1 reads 0 (same rank).
        let owner = vec![0, 0, 1, 1, 2];
        let reads = vec![vec![2, 2], vec![0], vec![1, 4], vec![], vec![0, 2]];
        let plan = |rank| {
            let n = Neighbours::new(
                &Planner {
                    owner: owner.clone(),
                    rank,
                },
                &reads,
            );
            (n.send, n.recv)
        };
        // Rank 0 sends body 1 to rank 1 and body 0 to rank 2; it receives body 2 from rank 1.
        assert_eq!(
            plan(0),
            (vec![(1, vec![1]), (2, vec![0])], vec![(1, vec![2])])
        );
        // Rank 1 sends body 2 to ranks 0 and 2, and receives body 1 and body 4.
        assert_eq!(
            plan(1),
            (
                vec![(0, vec![2]), (2, vec![2])],
                vec![(0, vec![1]), (2, vec![4])]
            )
        );
        assert_eq!(
            plan(2),
            (vec![(1, vec![4])], vec![(0, vec![0]), (1, vec![2])])
        );
        // A rank with no body plans nothing.
        let idle = Neighbours::new(
            &Planner {
                owner: owner.clone(),
                rank: 3,
            },
            &reads,
        );
        assert!(idle.send.is_empty() && idle.recv.is_empty());
    }

    #[test]
    fn statuses_survive_the_encoding() {
        for s in [
            Ok(()),
            Err(Breakdown::LostContact),
            Err(Breakdown::Singular),
            Err(Breakdown::NonFinite),
            Err(Breakdown::Growth),
            Err(Breakdown::NoDescent),
            Err(Breakdown::Slides),
        ] {
            assert_eq!(decode(encode(&s)), s);
        }
    }
}
