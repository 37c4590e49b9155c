//! What the processes of a distributed solve tell each other during the Robin sweeps.
//!
//! A body's Robin sweep reads the normal displacements of its own points and of their partners
//! (`Interface::reads`). So after a sweep each process sends its bodies' new values only to the
//! processes whose bodies read them, point to point ([`Neighbours`]); what every process must
//! agree on travels in collectives: per body its status, relative change, closed points and
//! contact force ([`BodyChecks`]), Aitken's dot products as per-body partial sums added in body
//! order ([`BodySums`]), and the coarse correction's balance and Jacobian, likewise summed from
//! per-body parts (`crate::coarse`). Anderson's least squares read the whole interface vector, so
//! with Anderson every process receives every body's values (an all-gather), as before.
//!
//! Every value a process computes is computed as in one process, and every sum adds the same
//! numbers in the same order, so the iteration is the single process's to the bit.

use std::ops::Range;

use crate::contact::Interface;
use crate::exchange::{
    decode, encode, share_outputs, share_slices, share_vectors, Exchange, Neighbours,
};
use crate::measures::{body_breakdown, body_change, body_contact};
use crate::outcome::Breakdown;
use crate::settings::{Accelerator, Settings};

/// How the sweeps' outputs reach the other processes.
pub(crate) enum Sharing {
    /// To every process: Anderson's least squares read the whole interface.
    Everyone,
    /// To the processes whose bodies read them.
    Neighbours(Neighbours),
}

impl Sharing {
    /// The sharing the iteration of `settings` needs.
    pub(crate) fn new(
        settings: &Settings,
        exchange: &dyn Exchange,
        interface: &Interface,
    ) -> Sharing {
        match settings.accelerator {
            Accelerator::Anderson { .. } => Sharing::Everyone,
            // One process has no neighbours to plan for.
            _ if exchange.is_local() => Sharing::Neighbours(Neighbours::default()),
            _ => Sharing::Neighbours(Neighbours::new(exchange, &interface.reads())),
        }
    }

    /// Shares a sweep's outputs Ũ (`un`) and T̃ (`t`) of this process's bodies; returns every
    /// body's status where all statuses travel with them, this process's otherwise (the
    /// [`BodyChecks`] share them).
    pub(crate) fn outputs(
        &self,
        exchange: &dyn Exchange,
        ranges: &[Range<usize>],
        un: &mut [f64],
        t: &mut [f64],
        swept: Vec<Result<(), Breakdown>>,
    ) -> Vec<Result<(), Breakdown>> {
        match self {
            Sharing::Everyone => share_outputs(exchange, ranges, &mut [un, t], swept),
            // The sweeps read only U; the loads T of other bodies are shared once at the end.
            Sharing::Neighbours(plan) => {
                plan.share(exchange, ranges, &mut [un]);
                swept
            }
        }
    }

    /// Gives every process every body's `values` (a collective; nothing to do where every
    /// process holds them already).
    pub(crate) fn everywhere(
        &self,
        exchange: &dyn Exchange,
        ranges: &[Range<usize>],
        values: &mut [f64],
    ) {
        if let Sharing::Neighbours(_) = self {
            share_slices(exchange, ranges, values);
        }
    }
}

/// What every process learns of every body after a sweep.
pub(crate) struct BodyChecks {
    /// The first body that broke down, and why.
    pub breakdown: Option<(usize, Breakdown)>,
    /// Per body, its relative change.
    pub rel_change: Vec<f64>,
    /// Per body, its closed points.
    pub active: Vec<usize>,
    /// Per body, its total normal contact force.
    pub contact_force: Vec<f64>,
}

impl BodyChecks {
    /// The checks of a sweep with statuses `swept` that led to the state `next` (pair sums
    /// `s_next`) from `before`, against the bodies' value `scale`: each process checks its own
    /// bodies, and a collective gives every process every body's checks.
    pub(crate) fn new(
        interface: &Interface,
        exchange: &dyn Exchange,
        swept: Vec<Result<(), Breakdown>>,
        scale: &[f64],
        next: &[f64],
        before: &[f64],
        s_next: &[f64],
    ) -> BodyChecks {
        let per_body = swept
            .into_iter()
            .enumerate()
            .map(|(b, swept)| {
                if !exchange.owns(b) {
                    return Vec::new();
                }
                let range = interface.body_range[b].clone();
                let status =
                    body_breakdown(swept, &next[range.clone()], scale[b]).map_or(Ok(()), Err);
                let (active, force) = body_contact(interface, s_next, b);
                let change = body_change(range, next, before);
                vec![encode(&status), change, active as f64, force]
            })
            .collect();
        let all = share_vectors(exchange, per_body);
        let field = |i: usize| {
            all.iter()
                .map(move |v| v.get(i).copied().unwrap_or(f64::NAN))
        };
        BodyChecks {
            breakdown: field(0)
                .enumerate()
                .find_map(|(b, code)| decode(code).err().map(|reason| (b, reason))),
            rel_change: field(1).collect(),
            active: field(2).map(|a| a as usize).collect(),
            contact_force: field(3).collect(),
        }
    }
}

/// Sums over the bodies in body order, the same on every process.
pub(crate) struct BodySums<'a> {
    exchange: &'a dyn Exchange,
    /// The points of this process's bodies, body by body in increasing order.
    pub own: Vec<Range<usize>>,
}

impl<'a> BodySums<'a> {
    /// The sums of a solve on `exchange` with the bodies' points `ranges`.
    pub(crate) fn new(exchange: &'a dyn Exchange, ranges: &[Range<usize>]) -> BodySums<'a> {
        let own = (0..ranges.len())
            .filter(|&b| exchange.owns(b))
            .map(|b| ranges[b].clone())
            .collect();
        BodySums { exchange, own }
    }

    /// Every body's partial sums added in body order, given this process's bodies' (a
    /// collective).
    pub(crate) fn total(&self, own: Vec<[f64; 4]>) -> [f64; 4] {
        let mut own = own.into_iter();
        let per_body = (0..self.exchange.owner().len())
            .map(|b| match self.exchange.owns(b) {
                true => own.next().map_or_else(Vec::new, |v| v.to_vec()),
                false => Vec::new(),
            })
            .collect();
        let mut total = [0.0; 4];
        for v in share_vectors(self.exchange, per_body) {
            for (t, x) in total.iter_mut().zip(v) {
                *t += x;
            }
        }
        total
    }
}
