//! The rigid motions in the Newton method: the free rigid modes of floating bodies that the
//! closed points leave free (the kernel of J), and the bodies that nothing holds.

use nalgebra::{DMatrix, DVector};

use super::algebra::{dot, merge};
use super::null_space::null_space;
use super::system::{modes_bound, Evaluation, System};
use crate::contact::Status;

/// Work of the loads along a free rigid motion, relative to their work along all free modes, above
/// which the motion is loaded: far above the rounding of loads that balance (the paper's notch,
/// two bodies pressed from both sides), far below any imbalance a solution could leave.
const WORK_TOL: f64 = 1e-8;

impl System<'_> {
    /// The rigid motions of floating bodies that the closed points `chi` do not resist, as
    /// weights of the free modes: the null space of G = Σ_j l_j s_jᵀ over the closed points, s_j
    /// the change of point j's pair sum per mode and l_j the modes its force acts on. A balanced
    /// carrier loads both sides through its gap row (l_j = s_j); an own-side point loads its own
    /// body only, so a closed point does not hold its partner: with only one side of an own-side
    /// pair closed, the other body moves freely away. A frictional point that sticks (`status`,
    /// empty without friction) resists through its tangential row too.
    pub(super) fn free_motions(&self, chi: &[bool], status: &[Status]) -> Vec<DVector<f64>> {
        let k = modes_bound(self.mode_range);
        if k == 0 {
            return Vec::new();
        }
        // G's terms l_ja s_jb point by point, then summed per entry in the points' order.
        let mut entries = Vec::new();
        // The size of G's diagonal terms, Σ_j |l_ja s_ja| (for balanced pairs, G's diagonal).
        let mut scale = vec![0.0f64; k];
        let mut push = |sum: &[(usize, f64)], load: &[(usize, f64)]| {
            for &(a, l) in load {
                for &(b, s) in sum {
                    entries.push((a, b, l * s));
                    if a == b {
                        scale[a] += (l * s).abs();
                    }
                }
            }
        };
        for j in (0..self.len()).filter(|&j| chi[j]) {
            let (sum, load) = self.mode_entries(j);
            push(&sum, &load);
            if status.get(j) == Some(&Status::Stick) {
                let slip = self.slip_modes(j);
                push(&slip, &slip);
            }
        }
        let scale = scale.into_iter().fold(0.0, f64::max);
        let g = merge(entries);
        // Balanced pairs, and own-side pairs closed on both sides, give a symmetric G = Σ s sᵀ:
        // its null space from an LDLᵀ factorisation in its band, whose cost follows the bodies'
        // neighbourhoods, where a dense eigensolver's cost grows with the cube of all modes.
        let symmetric = g.iter().all(|&(a, b, v)| {
            a == b
                || g.binary_search_by(|e| (e.0, e.1).cmp(&(b, a)))
                    .is_ok_and(|i| g[i].2 == v)
        });
        if symmetric {
            let lower: Vec<(usize, usize, f64)> =
                g.iter().copied().filter(|e| e.1 <= e.0).collect();
            return null_space(k, &lower, 1e-10 * scale);
        }
        // The null space from G's own singular values (those of GᵀG would square the rounding).
        let mut dense = DMatrix::<f64>::zeros(k, k);
        for (a, b, v) in g {
            dense[(a, b)] = v;
        }
        let svd = dense.svd(false, true);
        let Some(v_t) = svd.v_t else {
            return Vec::new();
        };
        svd.singular_values
            .iter()
            .enumerate()
            .filter(|(_, &sigma)| sigma <= 1e-10 * scale)
            .map(|(q, _)| v_t.row(q).transpose())
            .collect()
    }

    /// Point j's change of pair sum per free mode, and the modes its force acts on (a balanced
    /// carrier's gap row loads both sides, an own-side point its own body), as (mode, value)
    /// lists in the modes' order.
    pub(super) fn mode_entries(&self, j: usize) -> (Vec<(usize, f64)>, Vec<(usize, f64)>) {
        let mut sum = Vec::new();
        self.push_modes(j, 1.0, &mut sum);
        for &(q, c) in &self.interface.points[j].partner {
            self.push_modes(q, c, &mut sum);
        }
        sum.sort_by_key(|e| e.0);
        let load = if self.balanced[j] {
            sum.clone()
        } else {
            let mut own = Vec::new();
            self.push_modes(j, 1.0, &mut own);
            own
        };
        (sum, load)
    }

    /// Point j's change of tangential displacement per free mode (its tangential row, through
    /// which its traction also loads the bodies); empty without friction.
    pub(super) fn slip_modes(&self, j: usize) -> Vec<(usize, f64)> {
        let mut sum = Vec::new();
        for &(q, c) in self.interface.points[j]
            .friction
            .iter()
            .flat_map(|f| &f.row)
        {
            self.push_modes(q, c, &mut sum);
        }
        sum.sort_by_key(|e| e.0);
        sum
    }

    /// The frictional points that can close whose tangential displacement the rigid motion `v`
    /// changes (beyond the rounding of its terms): sticking, they would resist it.
    pub(super) fn resisting_tangentially(&self, v: &DVector<f64>) -> Vec<usize> {
        if !self.friction {
            return Vec::new();
        }
        let points = &self.interface.points;
        (0..self.len())
            .filter(|&j| points[j].has_partner() && !self.weightless[j])
            .filter(|&j| {
                let slip = self.slip_modes(j);
                let change: f64 = slip.iter().map(|&(m, x)| x * v[m]).sum();
                // The size of the terms that cancel in a motion along the zone's normal.
                let size: f64 =
                    points[j]
                        .friction
                        .iter()
                        .flat_map(|f| &f.row)
                        .fold(0.0, |a, &(q, c)| {
                            let b = self.body_of[q];
                            let modes = self.mode_range[b].clone().zip(&self.modes[q]);
                            a + c.abs() * modes.map(|(m, r)| (r * v[m]).abs()).sum::<f64>()
                        });
                change.abs() > 1e-8 * size
            })
            .collect()
    }

    /// A floating body that slides at the state `eval`: with every frictional point on the edge
    /// of its disc, the closed points leave a rigid motion v free along which the loads do more
    /// work |W| than friction can oppose, Σ_j w_j b_j |Δg_j(v)| (b_j the slip bound at the
    /// point's pressure, Δg_j the change of its tangential displacement along v). The body is
    /// the one that moves most along v. `None` without friction.
    pub(super) fn sliding(&self, eval: &Evaluation) -> Option<usize> {
        if !self.friction || self.mode_load_norm == 0.0 {
            return None;
        }
        let slipping: Vec<Status> = eval
            .status
            .iter()
            .map(|&s| if s == Status::Stick { Status::Slip } else { s })
            .collect();
        let points = &self.interface.points;
        self.free_motions(&eval.closed, &slipping)
            .iter()
            .find(|v| {
                let capacity: f64 = (0..self.len())
                    .filter(|&j| eval.closed[j])
                    .filter_map(|j| {
                        let (p, f) = (&points[j], points[j].friction.as_ref()?);
                        let change: f64 = self.slip_modes(j).iter().map(|&(m, x)| x * v[m]).sum();
                        Some(p.weight * f.law.bound(-p.pressure(eval.s[j])) * change.abs())
                    })
                    .sum();
                let work = self.work(v).abs();
                work > WORK_TOL * self.mode_load_norm && work > capacity
            })
            .and_then(|v| self.moves_most(v))
    }

    /// Adds c·ρ_j (the modes of point j's body) to the (mode, value) list `list`.
    pub(super) fn push_modes(&self, j: usize, c: f64, list: &mut Vec<(usize, f64)>) {
        let b = self.body_of[j];
        for (m, r) in self.mode_range[b].clone().zip(&self.modes[j]) {
            match list.iter_mut().find(|e| e.0 == m) {
                Some(e) => e.1 += c * r,
                None => list.push((m, 0.0 + c * r)),
            }
        }
    }

    /// An orthonormal basis, on the contact points, of the rigid motions `free` (those some closed
    /// points do not resist): motions of the whole interface that keep every closed pair sum.
    pub(super) fn kernel(&self, free: &[DVector<f64>]) -> Vec<Vec<f64>> {
        let mut basis: Vec<Vec<f64>> = Vec::new();
        for v in free {
            let mut z: Vec<f64> = (0..self.len())
                .map(|j| {
                    let b = self.body_of[j];
                    self.mode_range[b]
                        .clone()
                        .zip(&self.modes[j])
                        .map(|(m, r)| v[m] * r)
                        .sum()
                })
                .collect();
            for e in &basis {
                let d = dot(e, &z);
                z.iter_mut().zip(e).for_each(|(x, y)| *x -= d * y);
            }
            let n = dot(&z, &z).sqrt();
            if n > 1e-8 {
                z.iter_mut().for_each(|x| *x /= n);
                basis.push(z);
            }
        }
        basis
    }

    /// A rigid motion among `free` (the motions some closed points leave free) along which the
    /// loads, and the frictional points' nodal forces `tractions` ((j, w_j σ_t,j), empty
    /// without friction: a slipping point's force does not change along such a motion), do
    /// work: no state with these closed points balances them.
    pub(super) fn loaded_motion(
        &self,
        free: &[DVector<f64>],
        tractions: &[(usize, f64)],
    ) -> Option<DVector<f64>> {
        let total = self.mode_load_norm;
        if total == 0.0 && tractions.is_empty() {
            return None;
        }
        free.iter()
            .find(|v| {
                let (friction, size) = self.friction_work(v, tractions);
                (self.work(v) + friction).abs() > WORK_TOL * (total + size)
            })
            .cloned()
    }

    /// The work of the frictional forces `tractions` along the rigid motion `v`, and the sum of
    /// its terms' sizes.
    fn friction_work(&self, v: &DVector<f64>, tractions: &[(usize, f64)]) -> (f64, f64) {
        tractions
            .iter()
            .fold((0.0, 0.0), |(work, size), &(j, force)| {
                let change: f64 = self.slip_modes(j).iter().map(|&(m, x)| x * v[m]).sum();
                (work + force * change, size + (force * change).abs())
            })
    }

    /// The loads' work along the rigid motion `v` (weights of the free modes).
    pub(super) fn work(&self, v: &DVector<f64>) -> f64 {
        v.iter().zip(self.mode_load).map(|(a, f)| a * f).sum()
    }

    /// The body that moves most along the rigid motion `v`.
    pub(super) fn moves_most(&self, v: &DVector<f64>) -> Option<usize> {
        let share = |b: usize| self.mode_range[b].clone().map(|m| v[m] * v[m]).sum::<f64>();
        (0..self.bodies.len()).max_by(|&a, &b| share(a).total_cmp(&share(b)))
    }

    /// The body that nothing holds in `closed` (whose free motions are `free`, the frictional
    /// forces `tractions`): one none of whose loaders is closed, else the body that moves most
    /// along a loaded free motion.
    pub(super) fn stranded(
        &self,
        closed: &[bool],
        free: &[DVector<f64>],
        tractions: &[(usize, f64)],
    ) -> Option<usize> {
        if let Some(b) = self.unheld(closed) {
            return Some(b);
        }
        let v = self.loaded_motion(free, tractions)?;
        self.moves_most(&v)
    }

    /// The points that can close (partnered, weighted, and carriers on balanced pairs) whose
    /// pair sum the rigid motion `v` changes and whose force acts along it (an own-side point on
    /// a body that moves): closed, they would resist it.
    pub(super) fn resisting(&self, v: &DVector<f64>) -> Vec<usize> {
        self.along_motion(v)
            .into_iter()
            .filter(|&(_, c, a)| c != 0.0 && a != 0.0)
            .map(|(j, _, _)| j)
            .collect()
    }

    /// The body that nothing can ever hold, if the free motions `free` include one along which
    /// the loads do work W and no contact point pushes back: taken the way the loads push, every
    /// point's normal moves away from its partner or along it, so its pressure p ≥ 0 can only do
    /// work ≥ 0 too, and the rigid motion's balance W + Σ (work of p) = 0 has no solution, with
    /// any penalty or with exact contact. The body is the one that moves most along it.
    pub(super) fn unresisted(&self, free: &[DVector<f64>]) -> Option<usize> {
        let v = self.loaded_motion(free, &[])?;
        let push = self.work(&v).signum();
        // Friction can push back along any motion that slides a frictional point.
        let pushed_back = self
            .along_motion(&v)
            .iter()
            .any(|&(_, _, a)| a * push > 0.0)
            || !self.resisting_tangentially(&v).is_empty();
        if pushed_back {
            return None;
        }
        self.moves_most(&v)
    }

    /// Per point that can close: c, the change of its pair sum along the rigid motion `v`, and
    /// a, the same change seen by the bodies its force acts on (its own body's part for an
    /// own-side point; a = c for a balanced carrier, whose force acts through its gap row), so
    /// that its pressure p does work −p·a along v. Each is 0 below 10⁻⁸ of its largest value
    /// (rounding).
    pub(super) fn along_motion(&self, v: &DVector<f64>) -> Vec<(usize, f64, f64)> {
        let points = &self.interface.points;
        let along = |row: &[(usize, f64)]| row.iter().map(|&(m, x)| x * v[m]).sum::<f64>();
        let change: Vec<(usize, f64, f64)> = (0..self.len())
            .filter(|&j| {
                let p = &points[j];
                p.has_partner() && !self.weightless[j] && (!self.balanced[j] || p.carries())
            })
            .map(|j| {
                let (sum, load) = self.mode_entries(j);
                (j, along(&sum), along(&load))
            })
            .collect();
        let largest =
            |f: fn(&(usize, f64, f64)) -> f64| change.iter().fold(0.0f64, |m, c| m.max(f(c).abs()));
        let (sums, works) = (largest(|c| c.1), largest(|c| c.2));
        let cut = |x: f64, top: f64| if x.abs() > 1e-8 * top { x } else { 0.0 };
        change
            .into_iter()
            .map(|(j, c, a)| (j, cut(c, sums), cut(a, works)))
            .collect()
    }
}
