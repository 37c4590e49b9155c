//! The MPI exchange (`--features mpi`): the bodies' values travel between ranks whole, by
//! `MPI_Allgatherv` to every rank or by point-to-point messages to the ranks of neighbouring
//! bodies, so every rank holds the same bits as a single process would
//! (`contactdd_ddm::exchange`, `docs/mpi.md`).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator, CommunicatorCollectives, Destination, Equivalence, Root, Source};
use mpi::Count;

use contactdd_ddm::exchange::{partition, Exchange};

use crate::rank_use::RankUse;

/// Starts MPI for the life of the returned value (`None` if it cannot be started, or already
/// was: then the run is a single process).
pub fn init() -> Option<mpi::environment::Universe> {
    mpi::initialize_with_threading(mpi::Threading::Serialized).map(|(universe, _)| universe)
}

/// This process's rank in `MPI_COMM_WORLD`, while MPI runs.
pub fn world_rank() -> Option<usize> {
    let running = mpi::environment::is_initialized() && !mpi::environment::is_finalized();
    running.then(|| SimpleCommunicator::world().rank() as usize)
}

/// When MPI runs with more than one rank: a broadcast of rank 0's exit code (a collective).
pub fn root_exit() -> Option<impl FnOnce(u8) -> u8> {
    world_rank()?;
    let world = SimpleCommunicator::world();
    (world.size() > 1).then_some(move |mut code: u8| {
        world.process_at_rank(0).broadcast_into(&mut code);
        code
    })
}

/// The bodies partitioned over the ranks of `MPI_COMM_WORLD`.
pub struct MpiExchange {
    owner: Vec<usize>,
    rank: usize,
    size: usize,
    /// Nanoseconds spent in collectives and point-to-point exchanges.
    nanos: AtomicU64,
    /// Values received from other ranks: by all-gathers, and point to point.
    gathered: AtomicU64,
    swapped: AtomicU64,
}

impl MpiExchange {
    /// The exchange of bodies of estimated factorisation costs `cost` when MPI runs with more
    /// than one rank; `None` otherwise.
    pub fn for_costs(cost: &[f64]) -> Option<MpiExchange> {
        world_rank()?;
        let world = SimpleCommunicator::world();
        let size = world.size() as usize;
        if size < 2 {
            return None;
        }
        Some(MpiExchange {
            owner: partition(cost, size),
            rank: world.rank() as usize,
            size,
            nanos: AtomicU64::new(0),
            gathered: AtomicU64::new(0),
            swapped: AtomicU64::new(0),
        })
    }

    /// Number of ranks.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Every rank's communication time, values received and peak memory, given this rank's
    /// peak (a collective).
    pub fn usage(&self, peak_mib: f64) -> Vec<RankUse> {
        let load = |a: &AtomicU64| a.load(Ordering::Relaxed) as f64;
        let own = [
            load(&self.nanos) * 1e-9,
            load(&self.gathered),
            load(&self.swapped),
            peak_mib,
        ];
        let mut all = vec![0.0; own.len() * self.size];
        SimpleCommunicator::world().all_gather_into(&own[..], &mut all[..]);
        all.chunks(own.len())
            .map(|c| RankUse {
                communication: c[0],
                gathered: c[1],
                point_to_point: c[2],
                peak_mib: c[3],
            })
            .collect()
    }

    /// Runs an exchange, adding its wall time to the communication time.
    fn timed<R>(&self, f: impl FnOnce(&SimpleCommunicator) -> R) -> R {
        let start = Instant::now();
        let out = f(&SimpleCommunicator::world());
        let nanos = start.elapsed().as_nanos().min(u64::MAX as u128) as u64;
        self.nanos.fetch_add(nanos, Ordering::Relaxed);
        out
    }

    /// The bodies of every rank, rank by rank, each in increasing order.
    fn bodies_by_rank(&self) -> Vec<Vec<usize>> {
        let mut by_rank = vec![Vec::new(); self.size];
        for (b, &r) in self.owner.iter().enumerate() {
            by_rank[r].push(b);
        }
        by_rank
    }
}

impl Exchange for MpiExchange {
    fn owner(&self) -> &[usize] {
        &self.owner
    }

    fn rank(&self) -> usize {
        self.rank
    }

    fn gather(&self, own: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        let by_rank = self.bodies_by_rank();
        let lens: Vec<Count> = own.iter().map(|v| count(v.len())).collect();
        let flat = own.concat();
        self.timed(|world| {
            let body_counts: Vec<Count> = by_rank.iter().map(|b| count(b.len())).collect();
            let all_lens = all_gather_varcount(world, &lens, &body_counts);
            let mut data_counts = Vec::with_capacity(self.size);
            let mut next = all_lens.iter();
            for bodies in &by_rank {
                data_counts.push(next.by_ref().take(bodies.len()).sum::<Count>());
            }
            let data = all_gather_varcount(world, &flat, &data_counts);
            let others = data.len().saturating_sub(flat.len()) as u64;
            self.gathered.fetch_add(others, Ordering::Relaxed);
            let mut out = vec![Vec::new(); self.owner.len()];
            let (mut lens, mut at) = (all_lens.iter(), 0usize);
            for &b in by_rank.iter().flatten() {
                let n = lens.next().map_or(0, |&n| n as usize);
                out[b] = data[at..at + n].to_vec();
                at += n;
            }
            out
        })
    }

    fn agree(&self, error: Option<String>) -> Option<String> {
        // A leading 1 marks an error, a lone 0 its absence: never an empty byte buffer, whose
        // dangling address (1) OpenMPI would take for MPI_IN_PLACE.
        let bytes: Vec<u8> = match error {
            Some(e) => std::iter::once(1u8).chain(e.into_bytes()).collect(),
            None => vec![0],
        };
        self.timed(|world| {
            let mut counts = vec![0 as Count; self.size];
            world.all_gather_into(&count(bytes.len()), &mut counts[..]);
            let all = all_gather_varcount(world, &bytes, &counts);
            let mut at = 0usize;
            for &n in &counts {
                let n = n as usize;
                if all.get(at) == Some(&1) {
                    return Some(String::from_utf8_lossy(&all[at + 1..at + n]).into_owned());
                }
                at += n;
            }
            None
        })
    }

    fn swap(&self, sends: Vec<(usize, Vec<f64>)>, from: &[usize]) -> Vec<Vec<f64>> {
        self.timed(|world| {
            // Non-blocking sends, so that two ranks that send to each other do not wait for each
            // other's receive; the messages keep their order between two ranks (MPI's
            // non-overtaking rule), which matches successive swaps.
            mpi::request::scope(|scope| {
                let sent: Vec<_> = sends
                    .iter()
                    .map(|(to, v)| {
                        world
                            .process_at_rank(rank(*to))
                            .immediate_send(scope, &v[..])
                    })
                    .collect();
                let received: Vec<Vec<f64>> = from
                    .iter()
                    .map(|&r| world.process_at_rank(rank(r)).receive_vec::<f64>().0)
                    .collect();
                let values = received.iter().map(Vec::len).sum::<usize>() as u64;
                self.swapped.fetch_add(values, Ordering::Relaxed);
                for request in sent {
                    request.wait();
                }
                received
            })
        })
    }
}

/// A rank as MPI numbers it (ranks fit in its `int`: they come from it).
fn rank(r: usize) -> mpi::Rank {
    mpi::Rank::try_from(r).unwrap_or(mpi::Rank::MAX)
}

/// `MPI_Allgatherv`: the concatenation of every rank's `send`, whose lengths are `counts`.
fn all_gather_varcount<T: Equivalence + Default + Clone>(
    world: &SimpleCommunicator,
    send: &[T],
    counts: &[Count],
) -> Vec<T> {
    let displs: Vec<Count> = counts
        .iter()
        .scan(0, |at, &c| {
            let d = *at;
            *at += c;
            Some(d)
        })
        .collect();
    let total = counts.iter().map(|&c| c as usize).sum();
    let mut recv = vec![T::default(); total];
    let mut partition = PartitionMut::new(&mut recv[..], counts, &displs[..]);
    world.all_gather_varcount_into(send, &mut partition);
    recv
}

/// A length as an MPI count. The interface values of one rank are far below 2³¹; the recovered
/// fields of one rank reach it only beyond 10⁹ degrees of freedom.
fn count(n: usize) -> Count {
    Count::try_from(n).unwrap_or(Count::MAX)
}
