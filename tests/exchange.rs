//! The communication seam without MPI: R "ranks" are R threads of this test, each preparing and
//! solving only the bodies the partition gives it, joined by an in-memory exchange that behaves
//! like `MPI_Allgatherv` (every rank deposits its bodies' values, waits for the others, reads all).
//! Every rank meshes only its own bodies and holds the others as their contact skins, as on MPI
//! ranks. Every rank must reproduce the single-process solve bit for bit: the iterations, the
//! history, the interface loads and its own bodies' displacements (it holds no other field), on
//! the notch and on a column of blocks, for the
//! interface Newton method, the paper's sweeps, the two-level sweeps and Anderson acceleration.
//! `scripts/test_mpi.sh` checks the same through `mpirun` and the real MPI exchange.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Barrier, Condvar, Mutex};

use contactdd::cases;
use contactdd::ddm::exchange::{factor_cost, partition, Exchange};
use contactdd::ddm::{
    prepare, prepare_on, prepare_with, solve, Accelerator, CoarseMode, Condensation, Gamma, Hooks,
    Method, Model, Settings, Solution,
};

/// What the ranks deposit for one collective: per rank, its bodies' values or its error.
struct Shared {
    barrier: Barrier,
    values: Mutex<Vec<Vec<Vec<f64>>>>,
    errors: Mutex<Vec<Option<String>>>,
    /// Point-to-point messages in flight per (from, to), oldest first.
    mail: Mutex<HashMap<(usize, usize), VecDeque<Vec<f64>>>>,
    arrived: Condvar,
    /// Values received point to point, per rank.
    received: Mutex<Vec<usize>>,
}

impl Shared {
    fn new(ranks: usize) -> Arc<Shared> {
        Arc::new(Shared {
            barrier: Barrier::new(ranks),
            values: Mutex::new(vec![Vec::new(); ranks]),
            errors: Mutex::new(vec![None; ranks]),
            mail: Mutex::new(HashMap::new()),
            arrived: Condvar::new(),
            received: Mutex::new(vec![0; ranks]),
        })
    }
}

/// One rank's end of the in-memory exchange.
struct ThreadExchange {
    owner: Vec<usize>,
    rank: usize,
    shared: Arc<Shared>,
}

impl Exchange for ThreadExchange {
    fn owner(&self) -> &[usize] {
        &self.owner
    }
    fn rank(&self) -> usize {
        self.rank
    }
    fn gather(&self, own: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        self.shared.values.lock().unwrap()[self.rank] = own;
        self.shared.barrier.wait();
        let by_rank = self.shared.values.lock().unwrap().clone();
        // Nobody deposits the next collective's values before everyone has read these.
        self.shared.barrier.wait();
        let mut next: Vec<_> = by_rank.into_iter().map(Vec::into_iter).collect();
        self.owner
            .iter()
            .map(|&r| next[r].next().expect("a value per owned body"))
            .collect()
    }
    fn agree(&self, error: Option<String>) -> Option<String> {
        self.shared.errors.lock().unwrap()[self.rank] = error;
        self.shared.barrier.wait();
        let first = self
            .shared
            .errors
            .lock()
            .unwrap()
            .iter()
            .flatten()
            .next()
            .cloned();
        self.shared.barrier.wait();
        first
    }
    fn swap(&self, sends: Vec<(usize, Vec<f64>)>, from: &[usize]) -> Vec<Vec<f64>> {
        let mut mail = self.shared.mail.lock().unwrap();
        for (to, v) in sends {
            mail.entry((self.rank, to)).or_default().push_back(v);
        }
        self.shared.arrived.notify_all();
        let mut out = Vec::with_capacity(from.len());
        for &r in from {
            loop {
                if let Some(v) = mail.get_mut(&(r, self.rank)).and_then(VecDeque::pop_front) {
                    self.shared.received.lock().unwrap()[self.rank] += v.len();
                    out.push(v);
                    break;
                }
                mail = self.shared.arrived.wait(mail).unwrap();
            }
        }
        out
    }
}

/// The owner of every body of `model` on `ranks` ranks, as the command line partitions them.
fn owners(model: &Model, ranks: usize) -> Vec<usize> {
    let cost: Vec<f64> = model
        .bodies
        .iter()
        .map(|b| factor_cost(2 * b.mesh.num_nodes()))
        .collect();
    partition(&cost, ranks)
}

/// Solves `model` on `ranks` threads joined by the in-memory exchange; every rank's solution.
fn distributed(model: &Model, settings: &Settings, ranks: usize) -> Vec<Solution> {
    distributed_on(model, settings, ranks, Condensation::Auto)
}

/// [`distributed`] on the condensation path `condensation`.
fn distributed_on(
    model: &Model,
    settings: &Settings,
    ranks: usize,
    condensation: Condensation,
) -> Vec<Solution> {
    distributed_traffic(model, settings, ranks, condensation).0
}

/// [`distributed_on`], with the number of values every rank received point to point.
fn distributed_traffic(
    model: &Model,
    settings: &Settings,
    ranks: usize,
    condensation: Condensation,
) -> (Vec<Solution>, Vec<usize>) {
    let owner = owners(model, ranks);
    let shared = Shared::new(ranks);
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..ranks)
            .map(|rank| {
                let exchange = Arc::new(ThreadExchange {
                    owner: owner.clone(),
                    rank,
                    shared: shared.clone(),
                });
                let owner = owner.clone();
                scope.spawn(move || {
                    let model = &model.as_seen_by(|b| owner[b] == rank);
                    let prepared = prepare_on(model, condensation, exchange).unwrap();
                    let owned = prepared.bodies.iter().flatten().count();
                    assert!(owned < model.bodies.len(), "rank {rank} owns every body");
                    let sol = solve(model, &prepared, settings, Hooks::default()).unwrap();
                    for (b, body) in sol.bodies.iter().enumerate() {
                        assert_eq!(body.has_fields(), owner[b] == rank, "rank {rank}: {b}");
                    }
                    sol
                })
            })
            .collect();
        let solutions = handles.into_iter().map(|h| h.join().unwrap()).collect();
        (solutions, shared.received.lock().unwrap().clone())
    })
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Everything the iteration computed, as bits.
fn assert_same(one: &Solution, other: &Solution, what: &str) {
    assert_eq!(one.iterations, other.iterations, "{what}: iterations");
    assert_eq!(one.stop, other.stop, "{what}: stop");
    assert_eq!(one.history.len(), other.history.len(), "{what}: history");
    for (a, b) in one.history.iter().zip(&other.history) {
        assert_eq!(
            bits(&a.rel_change),
            bits(&b.rel_change),
            "{what}: k = {}",
            a.k
        );
        assert_eq!(a.gamma.to_bits(), b.gamma.to_bits(), "{what}: k = {}", a.k);
        assert_eq!(a.active, b.active, "{what}: k = {}", a.k);
    }
    assert_eq!(
        bits(&one.interface_loads),
        bits(&other.interface_loads),
        "{what}: interface loads"
    );
    // A rank holds the fields of its own bodies only.
    for (a, b) in one.bodies.iter().zip(&other.bodies) {
        if b.has_fields() {
            assert_eq!(
                bits(&a.displacement),
                bits(&b.displacement),
                "{what}: {}",
                a.name
            );
        }
    }
}

fn schemes() -> Vec<(&'static str, Settings)> {
    let paper = Settings::paper(Method::NewtonKurchatov, Gamma::Constant(0.5));
    let two_level = Settings::two_level();
    let anderson = Settings {
        coarse: CoarseMode::Chains,
        ..Settings::anderson()
    };
    vec![
        ("interface newton", Settings::default()),
        ("paper", paper),
        ("two-level", two_level),
        ("anderson", anderson),
    ]
}

fn check(name: &str, model: &Model) {
    let prepared = prepare_with(model, Condensation::Dense).unwrap();
    for (scheme, settings) in schemes() {
        // A run that stops without converging (the paper's sweeps on a column, cut at 60
        // iterations; Anderson without safeguard on the notch) must stop alike everywhere too.
        let settings = Settings {
            max_iter: 60,
            ..settings
        };
        let one = solve(model, &prepared, &settings, Hooks::default()).unwrap();
        if settings.accelerator == Accelerator::Newton {
            assert!(one.converged, "{name} {scheme}: {:?}", one.message);
        }
        for ranks in [2, 3] {
            for (rank, sol) in distributed(model, &settings, ranks).iter().enumerate() {
                assert_same(
                    &one,
                    sol,
                    &format!("{name} {scheme}, rank {rank} of {ranks}"),
                );
            }
        }
    }
}

#[test]
fn the_notch_on_two_and_three_ranks_is_the_single_process_solve_bit_for_bit() {
    let model = contactdd::ddm::benchmark::Notch::default().model().unwrap();
    // Three ranks for two bodies: one rank owns none and still takes part.
    check("notch", &model);
}

#[test]
fn a_column_on_two_and_three_ranks_is_the_single_process_solve_bit_for_bit() {
    check("column", &cases::column(6, 0.5));
}

#[test]
fn accelerators_are_named_as_the_settings_say() {
    // Guards the scheme list above: the cases cover every accelerator.
    let kinds: Vec<Accelerator> = schemes().iter().map(|(_, s)| s.accelerator).collect();
    assert!(kinds.contains(&Accelerator::Newton));
    assert!(kinds.contains(&Accelerator::None));
    assert!(kinds
        .iter()
        .any(|a| matches!(a, Accelerator::Anderson { .. })));
}

/// A block that slides freely (no support) cannot be factorised on the rank that owns it; every
/// rank gets that rank's error, naming the block, and none waits for the others.
#[test]
fn a_body_one_rank_cannot_factorise_fails_every_rank_with_its_message() {
    let mut model = cases::column(4, 0.5);
    let last = model.bodies.len() - 1;
    model.bodies[last].constraints =
        contactdd::fem::Constraints::new(model.bodies[last].mesh.num_nodes());
    let single = prepare(&model)
        .err()
        .expect("the sliding block is refused")
        .to_string();
    assert!(
        single.contains(&format!("'{}'", model.bodies[last].name)),
        "{single}"
    );
    let owner = partition(&vec![1.0; model.bodies.len()], 2);
    assert_ne!(owner[last], 0, "the failing body is not on the first rank");
    let shared = Shared::new(2);
    let errors: Vec<String> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..2)
            .map(|rank| {
                let exchange = Arc::new(ThreadExchange {
                    owner: owner.clone(),
                    rank,
                    shared: shared.clone(),
                });
                let model = &model;
                scope.spawn(move || {
                    prepare_on(model, Condensation::Auto, exchange)
                        .err()
                        .map(|e| e.to_string())
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap().unwrap())
            .collect()
    });
    assert_eq!(errors, vec![single.clone(), single]);
}

/// The sparse path couples every body in one sparse LU: forced on several ranks, it is refused
/// with a message that says what to use instead, on every rank (the check needs no exchange).
/// The sparse path on several ranks: every rank assembles the same coupled Newton system (the
/// other ranks' sparse bodies replayed from their packed rows) and reproduces the single-process
/// sparse solve bit for bit, with the interface Newton method and with Anderson's sweeps.
#[test]
fn the_sparse_path_on_two_and_three_ranks_is_the_single_process_solve_bit_for_bit() {
    let notch = contactdd::ddm::benchmark::Notch::default().model().unwrap();
    for (name, model) in [("notch", notch), ("column", cases::column(5, 0.5))] {
        let prepared = prepare_with(&model, Condensation::Sparse).unwrap();
        for (scheme, settings) in schemes().into_iter().filter(|(s, _)| *s != "paper") {
            let settings = Settings {
                max_iter: 60,
                ..settings
            };
            let one = solve(&model, &prepared, &settings, Hooks::default()).unwrap();
            for ranks in [2, 3] {
                let all = distributed_on(&model, &settings, ranks, Condensation::Sparse);
                for (rank, sol) in all.iter().enumerate() {
                    let what = format!("{name} sparse {scheme}, rank {rank} of {ranks}");
                    assert_same(&one, sol, &what);
                }
            }
        }
    }
}

/// The relaxed sweeps exchange point to point: on a column of blocks, whose body b touches only
/// b − 1 and b + 1, a rank receives per sweep only the normal displacements of the two blocks
/// next to its run of bodies (one message from each neighbouring rank, with its length first),
/// and still reproduces the single-process solve bit for bit: with a constant γ, with Aitken's
/// (whose dot products are summed per body in body order), and in the two-level sweeps (whose
/// coarse problem is summed from per-body parts the same way).
#[test]
fn sweeps_send_a_rank_only_the_blocks_next_to_its_own() {
    let paper = |gamma| Settings::paper(Method::NewtonKurchatov, gamma);
    for (name, settings) in [
        ("gamma 0.5", paper(Gamma::Constant(0.5))),
        ("gamma auto", paper(Gamma::Auto)),
        ("two-level", Settings::two_level()),
    ] {
        neighbour_traffic(
            &format!("column {name}"),
            &cases::column(9, 0.5),
            settings,
            3,
        );
    }
}

/// The same on a wall of 3 × 3 blocks, where a block touches up to four others across
/// horizontal and vertical non-matching interfaces, and the ranks' runs of bodies cut its rows.
#[test]
fn sweeps_on_a_wall_send_a_rank_only_the_blocks_that_touch_its_own() {
    let wall = cases::wall(3, 3, 0.05);
    for ranks in [2, 3] {
        neighbour_traffic("wall", &wall, Settings::two_level(), ranks);
    }
}

/// Solves `model` in one process and on `ranks` ranks (at most 40 sweeps), checks that every
/// rank reproduces the single process bit for bit, and that each sweep brings a rank, point to
/// point, the contact points of exactly the other ranks' bodies that share a contact pair with
/// its own, plus one length per message (one message per neighbouring rank).
fn neighbour_traffic(what: &str, model: &Model, settings: Settings, ranks: usize) {
    let settings = Settings {
        max_iter: 40,
        ..settings
    };
    let prepared = prepare_with(model, Condensation::Dense).unwrap();
    let points: Vec<usize> = prepared
        .interface
        .body_range
        .iter()
        .map(|r| r.len())
        .collect();
    let one = solve(model, &prepared, &settings, Hooks::default()).unwrap();
    let (all, received) = distributed_traffic(model, &settings, ranks, Condensation::Dense);
    let owner = owners(model, ranks);
    for (rank, sol) in all.iter().enumerate() {
        assert_same(&one, sol, &format!("{what} on {ranks} ranks, rank {rank}"));
        let mut ghosts: Vec<usize> = Vec::new();
        for pair in &model.pairs {
            let [a, b] = pair.bodies;
            for (mine, other) in [(a, b), (b, a)] {
                if owner[mine] == rank && owner[other] != rank {
                    ghosts.push(other);
                }
            }
        }
        ghosts.sort_unstable();
        ghosts.dedup();
        let mut senders: Vec<usize> = ghosts.iter().map(|&g| owner[g]).collect();
        senders.sort_unstable();
        senders.dedup();
        let per_sweep = ghosts.iter().map(|&g| points[g]).sum::<usize>() + senders.len();
        assert_eq!(
            received[rank],
            one.iterations * per_sweep,
            "{what} on {ranks} ranks, rank {rank}: ghosts {ghosts:?}, {} sweeps",
            one.iterations
        );
    }
}
