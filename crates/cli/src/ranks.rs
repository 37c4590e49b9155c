//! The processes of one `contactdd solve`: one, or (built with `--features mpi` and started by
//! `mpirun`) several MPI ranks, each computing the bodies the partition gives it
//! (`docs/mpi.md`). Rank 0 prints and writes the results; every rank ends with the same exit code.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use contactdd_ddm::exchange::{Exchange, Local};
use contactdd_ddm::{Model, Solution};
use contactdd_io::distributed_results::{
    shared_monitor, shared_reactions, write_results_shared, write_step_results_shared, Part,
};
use contactdd_io::reactions::BodyReactions;
use contactdd_io::setup::Monitor;
use contactdd_io::steps::HistoryLabels;
use contactdd_io::vtu::{CollectionOverRanks, VtuFormat, VtuLayout, VtuOptions};
use contactdd_io::Loaded;

use crate::rank_use::peak_mib;
use crate::rank_use::RankUse;
use crate::Exit;
#[cfg(feature = "mpi")]
use contactdd_io::{distributed_setup::estimated_costs, read_problem};

/// The processes of a solve and how they share the bodies.
pub struct Ranks {
    exchange: Arc<dyn Exchange>,
    size: usize,
    /// The encoding and layout of the `.vtu` files every rank writes.
    vtu: VtuOptions,
    #[cfg(feature = "mpi")]
    mpi: Option<Arc<crate::mpi_exchange::MpiExchange>>,
}

impl Ranks {
    /// Reads the problem file `path` for this run: in one process every body is meshed; under
    /// `mpirun` with more than one rank the bodies are partitioned by their estimated
    /// factorisation cost, and each rank meshes only its own and holds the others as their
    /// contact skins (a collective). The `.vtu` files are written in the encoding and layout
    /// of `vtu`, or else in the file's `[output] vtu` and `vtu-layout`. The one-file layout over
    /// several ranks is refused before the solve ([`CollectionOverRanks`]), on every rank.
    pub fn load(
        path: &Path,
        (format, layout): (Option<VtuFormat>, Option<VtuLayout>),
    ) -> anyhow::Result<(Loaded, Ranks)> {
        let (loaded, mut ranks) = Ranks::load_file(path)?;
        let output = loaded.problem.output;
        ranks.vtu = VtuOptions {
            format: format.or(output.vtu).unwrap_or_default(),
            layout: layout.or(output.vtu_layout).unwrap_or_default(),
        };
        if ranks.size > 1 && ranks.vtu.layout == VtuLayout::Collection {
            return Err(CollectionOverRanks.into());
        }
        Ok((loaded, ranks))
    }

    /// [`Ranks::load`] with the `.vtu` files in the default format.
    fn load_file(path: &Path) -> anyhow::Result<(Loaded, Ranks)> {
        #[cfg(feature = "mpi")]
        {
            let file = read_problem(path).map_err(|e| anyhow::anyhow!("{e}"))?;
            let costs = estimated_costs(&file.problem, &file.base_dir);
            if let Some(mpi) = crate::mpi_exchange::MpiExchange::for_costs(&costs) {
                let mpi = Arc::new(mpi);
                let loaded = file.resolve_on(&*mpi).map_err(|e| anyhow::anyhow!("{e}"))?;
                let ranks = Ranks {
                    exchange: mpi.clone(),
                    size: mpi.size(),
                    vtu: VtuOptions::default(),
                    mpi: Some(mpi),
                };
                if ranks.is_root() {
                    crate::warn_loaded(path, &loaded);
                }
                return Ok((loaded, ranks));
            }
            let loaded = file.resolve().map_err(|e| anyhow::anyhow!("{e}"))?;
            crate::warn_loaded(path, &loaded);
            let ranks = Ranks::alone(&loaded.model);
            Ok((loaded, ranks))
        }
        #[cfg(not(feature = "mpi"))]
        {
            let loaded = crate::load(path)?;
            let ranks = Ranks::alone(&loaded.model);
            Ok((loaded, ranks))
        }
    }

    /// One process owning every body of `model`.
    fn alone(model: &Model) -> Ranks {
        Ranks {
            exchange: Arc::new(Local::new(model.bodies.len())),
            size: 1,
            vtu: VtuOptions::default(),
            #[cfg(feature = "mpi")]
            mpi: None,
        }
    }

    /// The exchange to prepare the model on.
    pub fn exchange(&self) -> Arc<dyn Exchange> {
        self.exchange.clone()
    }

    /// Number of processes.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Whether this process prints and writes the results.
    pub fn is_root(&self) -> bool {
        self.exchange.rank() == 0
    }

    /// The support reactions of every body, each computed by the rank that holds its field (a
    /// collective).
    pub fn reactions(&self, model: &Model, sol: &Solution) -> Vec<BodyReactions> {
        shared_reactions(model, sol, &self.part())
    }

    /// The monitored displacement of `sol`, from the rank that holds the body's field (a
    /// collective).
    pub fn monitored(&self, sol: &Solution, monitor: &Monitor) -> [f64; 2] {
        shared_monitor(sol, monitor, &self.part())
    }

    /// Writes the result folder: in one process all of it; on several ranks each rank its own
    /// bodies' VTU files and rank 0 the rest (a collective). Returns the paths this rank wrote.
    pub fn write_results(
        &self,
        dir: &Path,
        model: &Model,
        sol: &Solution,
        reactions: &[BodyReactions],
        units: Option<&str>,
    ) -> std::io::Result<Vec<PathBuf>> {
        write_results_shared(dir, model, sol, reactions, units, &self.part())
    }

    /// [`write_results`](Ranks::write_results) for the steps of a load-step run, or the
    /// increments of a load history (`labels`).
    pub fn write_step_results(
        &self,
        dir: &Path,
        model: &Model,
        steps: &[(f64, Solution)],
        (monitor, units): (Option<&Monitor>, Option<&str>),
        labels: Option<&HistoryLabels>,
    ) -> std::io::Result<Vec<PathBuf>> {
        write_step_results_shared(dir, model, steps, monitor, units, labels, &self.part())
    }

    /// This process's part in writing a shared result folder.
    fn part(&self) -> Part<'_> {
        let exchange = &*self.exchange;
        Part {
            root: self.is_root(),
            owns: Box::new(move |b| exchange.owns(b)),
            agree: Box::new(move |error| exchange.agree(error)),
            gather: Box::new(move |own| exchange.gather(own)),
            vtu: self.vtu,
        }
    }

    /// Per rank, the time it spent communicating and its peak memory (a collective; one entry
    /// for a single process).
    pub fn usage(&self) -> Vec<RankUse> {
        let own = RankUse {
            communication: 0.0,
            gathered: 0.0,
            point_to_point: 0.0,
            peak_mib: peak_mib(),
        };
        #[cfg(feature = "mpi")]
        if let Some(mpi) = &self.mpi {
            return mpi.usage(own.peak_mib);
        }
        vec![own]
    }
}

/// Runs `command` on rank 0 alone when MPI runs with several ranks (the others wait for it), and
/// returns its exit code on every rank; in one process, runs it.
pub fn on_root(command: impl FnOnce() -> Exit) -> Exit {
    #[cfg(feature = "mpi")]
    if let Some(share) = crate::mpi_exchange::root_exit() {
        let code = if is_root() { command() as u8 } else { 0 };
        return match share(code) {
            0 => Exit::Success,
            2 => Exit::NotConverged,
            _ => Exit::Error,
        };
    }
    command()
}

/// Whether this process is the one that reports (rank 0, or the only process).
pub fn is_root() -> bool {
    #[cfg(feature = "mpi")]
    if let Some(rank) = crate::mpi_exchange::world_rank() {
        return rank == 0;
    }
    true
}
