//! The guard of the coarse correction in the relaxed sweeps.
//!
//! The coarse correction moves the floating bodies rigidly into balance against their partners'
//! current shapes. With a stiff penalty the balance needs only a tiny overlap, so where those
//! shapes do not yet fit each other (a recess, early in the iteration) the balanced position
//! touches at a few points only. The next sweep then solves every body against that contact,
//! and `active-set` in particular linearises at it: the bodies answer with a large deformation
//! and the iteration can stall (docs/two-level.md, "The guard").
//!
//! The guard watches the size of the sweeps' unrelaxed update ‖Ũ − U‖. When a sweep from a
//! corrected state makes it grow by more than [`GROWTH`] against the last iteration's, the
//! guard sweeps once more from the state before the correction; if that update is smaller, the
//! correction hurts, and it is switched off for the rest of the solve. Otherwise the corrected
//! sweep stands. Where the update never grows that much, the iteration is the unguarded one to
//! the bit.

use super::update::Update;
use super::Run;
use crate::coarse::CoarseMode;
use crate::outcome::Breakdown;
use crate::relaxation::GROWTH;

impl Run<'_> {
    /// Whether the guard watches this solve: a coarse correction is in use and the sweeps are
    /// relaxed (Anderson combines its own history of states).
    pub(super) fn guarded(&self) -> bool {
        self.coarse != CoarseMode::Off && matches!(self.update, Update::Relax(_))
    }

    /// One parallel Robin sweep from the current state into `buf.tilde`, `buf.t_tilde`, shared
    /// as the iteration needs.
    pub(super) fn sweep(&mut self) -> Vec<Result<(), Breakdown>> {
        let (exchange, ranges) = (&*self.prepared.exchange, &self.interface.body_range);
        let (state, buf) = (&self.state, &mut self.buf);
        let swept = (self.sweep).apply(
            &state.u,
            &state.s,
            &state.s_prev,
            &mut buf.tilde,
            &mut buf.t_tilde,
        );
        (self.sharing).outputs(exchange, ranges, &mut buf.tilde, &mut buf.t_tilde, swept)
    }

    /// Checks the sweep `swept` that ran from a state the coarse correction moved (`corrected`)
    /// or left alone, and returns the statuses of the sweep the iteration continues with.
    pub(super) fn guard(
        &mut self,
        swept: Vec<Result<(), Breakdown>>,
        corrected: bool,
    ) -> Vec<Result<(), Breakdown>> {
        let size = self.update_size();
        let last = self.last_update.replace(size);
        let grown = last.is_some_and(|last| size > GROWTH * last);
        if !(corrected && grown) {
            return swept;
        }
        let (state, buf) = (&mut self.state, &mut self.buf);
        let kept = [
            state.u.clone(),
            state.t.clone(),
            buf.tilde.clone(),
            buf.t_tilde.clone(),
        ];
        state.u.copy_from_slice(&buf.input);
        state.t.copy_from_slice(&buf.input_t);
        self.interface.sum_normal(&state.u, &mut state.s);
        let plain = self.sweep();
        let plain_size = self.update_size();
        if size > plain_size {
            self.coarse = CoarseMode::Off;
            self.last_update = None;
            return plain;
        }
        let (state, buf) = (&mut self.state, &mut self.buf);
        let [u, t, tilde, t_tilde] = kept;
        (state.u, state.t, buf.tilde, buf.t_tilde) = (u, t, tilde, t_tilde);
        self.interface.sum_normal(&state.u, &mut state.s);
        swept
    }

    /// ‖Ũ − U‖ over every body's points, summed body by body in body order (a collective); a
    /// non-finite size is infinite, so that it counts as grown and as larger than any other.
    fn update_size(&self) -> f64 {
        let (u, tilde) = (&self.state.u, &self.buf.tilde);
        let own = (self.sums.own.iter())
            .map(|range| {
                let sum = range
                    .clone()
                    .map(|j| (tilde[j] - u[j]).powi(2))
                    .sum::<f64>();
                [sum, 0.0, 0.0, 0.0]
            })
            .collect();
        let size = self.sums.total(own)[0].sqrt();
        match size.is_finite() {
            true => size,
            false => f64::INFINITY,
        }
    }
}
