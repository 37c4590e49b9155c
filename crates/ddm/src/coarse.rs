//! The coarse correction: every body that its supports leave free to move rigidly is moved rigidly
//! so that its applied load and its contact forces balance.
//!
//! This is the natural coarse space of FETI-type methods (Farhat & Roux 1991; for contact, Dostál's
//! TFETI): the rigid motions R_b of the floating bodies, 3 per body in 2D at most. A local Robin
//! solve cannot move a body held only by its contacts towards equilibrium faster than its springs
//! allow, and along a chain of N bodies information travels one body per sweep; the coarse problem
//! couples all floating bodies at once.
//!
//! With c_b the coefficients of body b's free modes, a contact point j moves by ρ_j · c_{b(j)}
//! along its normal (ρ_jq = n_j · R_q(x_j)), so the sum across its pair changes by
//!   Δs_j(c) = ρ_j · c_{b(j)} + Σ_k c_jk ρ_k · c_{b(k)}
//! (k: the partner points interpolated at j's projection). The balance of body b's free mode q is
//!   F_bq(c) = R_qᵀ f_b + Σ_{j ∈ b} (w_j/θ_j) (d_j − s_j − Δs_j(c))⁻ ρ_jq = 0,
//! a small piecewise-linear system, solved by a semismooth Newton method with a backtracking line
//! search on ‖F‖. Its generalised Jacobian uses the closed points; a body with no closed point
//! uses all its partnered points instead, which moves it towards its partners. The Newton steps
//! are minimum-norm least-squares steps (column-scaled, with a tiny Levenberg–Marquardt shift), so
//! a motion that no contact resists (two bodies translating together along their contact) is left
//! alone.
//!
//! A rigid motion R c of a body adds K₀ R c = N D₀ Nᵀ R c to its load, because K R c = 0: the
//! interface load T therefore changes by D₀ ρ c and the relation U = f₀ + C₀ T stays exact.

use std::ops::Range;

use faer::{Mat, Side};

use crate::contact::Interface;
use crate::exchange::{share_vectors, Exchange};
use crate::facts::BodyFacts;
use crate::model::Model;

/// Newton steps at most per correction (the system is piecewise linear and small).
const MAX_NEWTON: usize = 50;
/// Relative accuracy of the balance.
const BALANCE_TOL: f64 = 1e-12;

/// Which bodies the coarse correction moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoarseMode {
    /// No coarse correction (the paper's one-level iteration).
    Off,
    /// The floating bodies that touch another floating body, in a cluster that a held body
    /// carries: chains and stacks resting on a support. A floating body whose partners are all
    /// held by supports is balanced by its own Robin solve already, and so is every body of a
    /// cluster that no support carries; they are left to the sweep.
    Chains,
    /// Every floating body.
    All,
}

impl std::fmt::Display for CoarseMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CoarseMode::Off => "off",
            CoarseMode::Chains => "chains",
            CoarseMode::All => "all",
        })
    }
}

/// The coarse spaces of a model, for [`CoarseMode::Chains`] and [`CoarseMode::All`].
#[derive(Clone, Debug, Default)]
pub struct Coarse {
    chains: FloatingModes,
    all: FloatingModes,
}

impl Coarse {
    /// Finds the free rigid modes of every body and their values on the contact points.
    pub fn new(model: &Model, interface: &Interface) -> Coarse {
        let facts: Vec<BodyFacts> = (0..model.bodies.len()).map(|b| model.facts(b)).collect();
        let in_chain = chains(model, &facts);
        Coarse {
            chains: FloatingModes::new(model, interface, &facts, |b| in_chain[b]),
            all: FloatingModes::new(model, interface, &facts, |_| true),
        }
    }

    /// Scales the bodies' loads by `factor` (a load step); the other load groups' factors
    /// become 0.
    pub fn set_load_factor(&mut self, factor: f64) {
        self.chains.set_load_factor(factor);
        self.all.set_load_factor(factor);
    }

    /// Sets the other load groups of a load history ([`crate::history`]): `work[b][g]` is the
    /// work of group g's load on body b along each of the body's free rigid modes (its facts'
    /// `free`, in order; empty: none). Each group starts at factor 0.
    pub fn set_load_groups(&mut self, work: &[Vec<Vec<f64>>]) {
        self.chains.set_load_groups(work);
        self.all.set_load_groups(work);
    }

    /// Sets the load combination of a load history: `factor` on the bodies' own loads,
    /// `group_factors[g]` on group g of [`Coarse::set_load_groups`]. Without other groups this is
    /// [`Coarse::set_load_factor`], to the bit.
    pub fn set_load_combination(&mut self, factor: f64, group_factors: &[f64]) {
        self.chains.set_load_combination(factor, group_factors);
        self.all.set_load_combination(factor, group_factors);
    }

    /// Number of coarse unknowns in `mode`.
    pub fn len(&self, mode: CoarseMode) -> usize {
        match mode {
            CoarseMode::Off => 0,
            CoarseMode::Chains => self.chains.len(),
            CoarseMode::All => self.all.len(),
        }
    }

    /// The free rigid modes of every floating body on the contact points: per body the range of
    /// its mode numbers, and per point the normal value ρ_jq of each mode q of its body.
    pub fn floating_modes(&self) -> (&[Range<usize>], &[Vec<f64>]) {
        (&self.all.range, &self.all.rho)
    }

    /// The work R_qᵀ f of the bodies' loads (at the load factor) along every mode of
    /// [`Coarse::floating_modes`].
    pub fn floating_loads(&self) -> &[f64] {
        &self.all.load
    }

    /// Moves the bodies that `mode` selects rigidly into balance in the state (`un`, `t`).
    /// Returns the number of Newton steps taken.
    ///
    /// A process reads only its own bodies' points and their partners' values (all it holds
    /// current in the relaxed sweeps); the balance and its Jacobian are sums of per-body parts
    /// that `exchange` shares and every process adds in body order, so every process takes the
    /// same steps as one process would (a collective).
    pub fn correct(
        &self,
        mode: CoarseMode,
        interface: &Interface,
        exchange: &dyn Exchange,
        un: &mut [f64],
        t: &mut [f64],
    ) -> usize {
        let shared = Shared {
            interface,
            exchange,
            owned: (0..interface.body_range.len())
                .map(|b| exchange.owns(b))
                .collect(),
        };
        match mode {
            CoarseMode::Off => 0,
            CoarseMode::Chains => self.chains.correct(&shared, un, t),
            CoarseMode::All => self.all.correct(&shared, un, t),
        }
    }
}

/// Which bodies [`CoarseMode::Chains`] moves: the floating bodies that touch another floating
/// body, in a cluster of floating bodies (connected by contact pairs) that touches a body held
/// by its supports. A cluster that no held body carries is left to the sweeps: its load does not
/// travel to a support, every body of it balances against its partners in its own Robin solve,
/// and its coarse problem fixes only the bodies' relative motions (singular along the joint one).
fn chains(model: &Model, facts: &[BodyFacts]) -> Vec<bool> {
    let floating = |b: usize| !facts[b].free.is_empty();
    // Union–find of the floating bodies over their pairs.
    let mut root: Vec<usize> = (0..facts.len()).collect();
    fn find(root: &mut [usize], mut b: usize) -> usize {
        while root[b] != b {
            root[b] = root[root[b]];
            b = root[b];
        }
        b
    }
    let mut touches_floating = vec![false; facts.len()];
    for pair in &model.pairs {
        let [a, b] = pair.bodies;
        if a != b && floating(a) && floating(b) {
            (touches_floating[a], touches_floating[b]) = (true, true);
            let (ra, rb) = (find(&mut root, a), find(&mut root, b));
            root[ra] = rb;
        }
    }
    let mut carried = vec![false; facts.len()];
    for pair in &model.pairs {
        let [a, b] = pair.bodies;
        for (f, h) in [(a, b), (b, a)] {
            if floating(f) && !floating(h) {
                let r = find(&mut root, f);
                carried[r] = true;
            }
        }
    }
    (0..facts.len())
        .map(|b| touches_floating[b] && carried[find(&mut root, b)])
        .collect()
}

/// The selected bodies' rigid modes on the contact points.
#[derive(Clone, Debug, Default)]
struct FloatingModes {
    /// Coarse unknowns of each body (empty for a body held by its supports).
    range: Vec<Range<usize>>,
    /// Owning body of every contact point.
    body: Vec<usize>,
    /// ρ_jq for every contact point j and free mode q of its body.
    rho: Vec<Vec<f64>>,
    /// R_qᵀ f for every coarse unknown, at the load factor.
    load: Vec<f64>,
    /// R_qᵀ f at load factor 1.
    load_full: Vec<f64>,
    /// R_qᵀ L_g of every other load group g of a load history.
    groups: Vec<Vec<f64>>,
    /// Per body, the coarse unknowns its points' balance and Jacobian entries involve (its own
    /// and its points' partners' bodies'), in increasing order.
    near: Vec<Vec<usize>>,
}

impl FloatingModes {
    /// The free modes of the bodies `take` selects (their facts' `free`).
    fn new(
        model: &Model,
        interface: &Interface,
        facts: &[BodyFacts],
        take: impl Fn(usize) -> bool,
    ) -> FloatingModes {
        let mut range = Vec::with_capacity(facts.len());
        let mut modes = Vec::with_capacity(facts.len());
        let mut load = Vec::new();
        for (b, f) in facts.iter().enumerate() {
            let (free, work) = if take(b) {
                (f.free.as_slice(), f.free_load.as_slice())
            } else {
                (&[][..], &[][..])
            };
            range.push(load.len()..load.len() + free.len());
            load.extend_from_slice(work);
            modes.push((f.basis, free));
        }
        let rho = interface
            .points
            .iter()
            .map(|p| {
                let (basis, free) = &modes[p.body];
                let x = model.position(p.body, p.node);
                free.iter()
                    .map(|v| {
                        let u = basis.motion(x, v);
                        p.normal[0] * u[0] + p.normal[1] * u[1]
                    })
                    .collect()
            })
            .collect();
        let near = interface
            .body_range
            .iter()
            .enumerate()
            .map(|(b, points)| {
                let mut bodies = vec![b];
                for j in points.clone() {
                    let partners = &interface.points[j].partner;
                    bodies.extend(partners.iter().map(|&(k, _)| interface.points[k].body));
                }
                bodies.sort_unstable();
                bodies.dedup();
                bodies.iter().flat_map(|&c| range[c].clone()).collect()
            })
            .collect();
        FloatingModes {
            range,
            body: interface.points.iter().map(|p| p.body).collect(),
            rho,
            load_full: load.clone(),
            load,
            groups: Vec::new(),
            near,
        }
    }

    fn set_load_factor(&mut self, factor: f64) {
        self.load = self.load_full.iter().map(|v| factor * v).collect();
    }

    fn set_load_groups(&mut self, work: &[Vec<Vec<f64>>]) {
        let count = work.iter().map(Vec::len).max().unwrap_or(0);
        self.groups = (0..count)
            .map(|g| {
                let mut load = vec![0.0; self.load_full.len()];
                for (range, w) in self.range.iter().zip(work) {
                    let w = w.get(g).map_or(&[][..], Vec::as_slice);
                    load[range.clone()]
                        .iter_mut()
                        .zip(w)
                        .for_each(|(l, v)| *l = *v);
                }
                load
            })
            .collect();
    }

    fn set_load_combination(&mut self, factor: f64, group_factors: &[f64]) {
        self.set_load_factor(factor);
        for (g, &c) in self.groups.iter().zip(group_factors) {
            if c != 0.0 {
                self.load.iter_mut().zip(g).for_each(|(l, v)| *l += c * v);
            }
        }
    }

    fn len(&self) -> usize {
        self.load.len()
    }

    /// Moves the bodies rigidly into balance; returns the number of Newton steps.
    fn correct(&self, shared: &Shared<'_>, un: &mut [f64], t: &mut [f64]) -> usize {
        if self.load.is_empty() {
            return 0;
        }
        let interface = shared.interface;
        let mut s = vec![0.0; un.len()];
        interface.sum_normal(un, &mut s);
        let mut c = vec![0.0; self.len()];
        let mut f = self.residual(shared, &s, &c);
        let scale = self.force_scale(shared, &s);
        let mut steps = 0;
        while steps < MAX_NEWTON && norm(&f) > BALANCE_TOL * scale {
            steps += 1;
            let Some(delta) = self.newton_step(shared, &s, &c, &f) else {
                break;
            };
            let Some((c_new, f_new)) = self.line_search(shared, &s, &c, &f, &delta) else {
                break;
            };
            (c, f) = (c_new, f_new);
        }
        for (j, p) in interface.points.iter().enumerate() {
            let du = self.own_shift(j, &c);
            un[j] += du;
            t[j] += p.spring * du;
        }
        steps
    }

    /// ρ_j · c_{b(j)}: the normal motion of point j.
    #[inline(always)]
    fn own_shift(&self, j: usize, c: &[f64]) -> f64 {
        let cb = &c[self.range[self.body[j]].clone()];
        self.rho[j].iter().zip(cb).map(|(r, x)| r * x).sum()
    }

    /// Δs_j(c).
    #[inline(always)]
    fn shift(&self, interface: &Interface, j: usize, c: &[f64]) -> f64 {
        self.own_shift(j, c)
            + interface.points[j]
                .partner
                .iter()
                .map(|&(k, ck)| ck * self.own_shift(k, c))
                .sum::<f64>()
    }

    /// F(c), one entry per coarse unknown.
    fn residual(&self, shared: &Shared<'_>, s: &[f64], c: &[f64]) -> Vec<f64> {
        let interface = shared.interface;
        let mut f = self.load.clone();
        shared.add_parts(&mut f, |b| {
            let mut part = Part::vector(&self.near[b]);
            for j in interface.body_range[b].clone() {
                let p = &interface.points[j];
                if !p.has_partner() {
                    continue;
                }
                let force = p.weight * p.pressure(s[j] + self.shift(interface, j, c));
                // The point's force on every unknown it loads (its own alone for an own-side
                // point).
                for (u, a) in p.load_row(j) {
                    let r = part.locals(self.range[self.body[u]].clone());
                    for (q, &rho) in r.zip(&self.rho[u]) {
                        part.add_local(q, a * force * rho);
                    }
                }
            }
            part.entries(1)
        });
        f
    }

    /// Size of the forces involved: applied loads and contact forces of the floating bodies.
    fn force_scale(&self, shared: &Shared<'_>, s: &[f64]) -> f64 {
        let interface = shared.interface;
        let mut contact = [0.0];
        shared.add_parts(&mut contact, |b| {
            if self.range[b].is_empty() {
                return Vec::new();
            }
            let sum = interface.body_range[b]
                .clone()
                .map(|j| (interface.points[j].weight * interface.points[j].pressure(s[j])).abs())
                .sum::<f64>();
            vec![0.0, sum]
        });
        norm(&self.load) + contact[0] + f64::MIN_POSITIVE
    }

    /// The minimum-norm Newton step J δ = −F for the generalised Jacobian at `c`.
    fn newton_step(
        &self,
        shared: &Shared<'_>,
        s: &[f64],
        c: &[f64],
        f: &[f64],
    ) -> Option<Vec<f64>> {
        let n = self.len();
        let jac = self.jacobian(shared, s, c);
        // Column scaling, then (ĴᵀĴ + μI) y = −ĴᵀF, δ = S y.
        let col: Vec<f64> = (0..n)
            .map(|i| {
                let l = (0..n).map(|r| jac[(r, i)].powi(2)).sum::<f64>().sqrt();
                if l > 0.0 {
                    1.0 / l
                } else {
                    1.0
                }
            })
            .collect();
        let js = Mat::<f64>::from_fn(n, n, |r, i| jac[(r, i)] * col[i]);
        let mut normal = js.transpose() * &js;
        for i in 0..n {
            normal[(i, i)] += 1e-12;
        }
        let rhs = Mat::<f64>::from_fn(n, 1, |i, _| -(0..n).map(|r| js[(r, i)] * f[r]).sum::<f64>());
        let llt = normal.llt(Side::Lower).ok()?;
        let y = faer::prelude::Solve::solve(&llt, &rhs);
        let delta: Vec<f64> = (0..n).map(|i| col[i] * y[(i, 0)]).collect();
        delta.iter().all(|d| d.is_finite()).then_some(delta)
    }

    /// ∂F/∂c on the closed points (all partnered points for a body with none closed).
    fn jacobian(&self, shared: &Shared<'_>, s: &[f64], c: &[f64]) -> Mat<f64> {
        let (interface, n) = (shared.interface, self.len());
        // Of this process's bodies' points (the only ones it reads).
        let closed: Vec<bool> = (0..interface.len())
            .map(|j| {
                let p = &interface.points[j];
                shared.owned[p.body] && p.overlap(s[j] + self.shift(interface, j, c)) < 0.0
            })
            .collect();
        // A body is held once a closed point loads it (its own, or a carrier facing it): count
        // the closed points that load each body.
        let mut held = vec![0.0; self.range.len()];
        shared.add_parts(&mut held, |b| {
            let mut bodies: Vec<usize> = Vec::new();
            for j in interface.body_range[b].clone().filter(|&j| closed[j]) {
                bodies.extend(interface.points[j].load_row(j).map(|(u, _)| self.body[u]));
            }
            bodies.sort_unstable();
            let mut counts: Vec<f64> = Vec::new();
            for run in bodies.chunk_by(|x, y| x == y) {
                counts.extend([run[0] as f64, run.len() as f64]);
            }
            counts
        });
        let mut jac = vec![0.0; n * n];
        shared.add_parts(&mut jac, |b| {
            let mut part = Part::matrix(&self.near[b]);
            for j in interface.body_range[b].clone() {
                let p = &interface.points[j];
                let loose = p.load_row(j).any(|(u, _)| held[self.body[u]] == 0.0);
                if !(closed[j] || (loose && p.has_partner())) {
                    continue;
                }
                let k = p.weight / p.theta;
                // ∂Δs_j/∂c: own modes, then the partner points' modes (as the part's columns).
                let mut grad = Vec::with_capacity(self.rho[j].len() * (1 + p.partner.len()));
                let own = part.locals(self.range[p.body].clone());
                grad.extend(own.zip(self.rho[j].iter().copied()));
                for &(pk, ck) in &p.partner {
                    let cols = part.locals(self.range[self.body[pk]].clone());
                    grad.extend(cols.zip(self.rho[pk].iter().map(|r| ck * r)));
                }
                for (u, a) in p.load_row(j) {
                    let rows = part.locals(self.range[self.body[u]].clone());
                    for (row, &rho) in rows.zip(&self.rho[u]) {
                        for &(col, g) in &grad {
                            part.add_local_at(row, col, -(a * k * rho * g));
                        }
                    }
                }
            }
            part.entries(n)
        });
        Mat::from_fn(n, n, |row, col| jac[row + n * col])
    }

    /// Backtracking on ‖F‖ along `delta`; None if no step length decreases it.
    fn line_search(
        &self,
        shared: &Shared<'_>,
        s: &[f64],
        c: &[f64],
        f: &[f64],
        delta: &[f64],
    ) -> Option<(Vec<f64>, Vec<f64>)> {
        let f0 = norm(f);
        let mut alpha = 1.0;
        for _ in 0..40 {
            let trial: Vec<f64> = c.iter().zip(delta).map(|(x, d)| x + alpha * d).collect();
            let ft = self.residual(shared, s, &trial);
            if norm(&ft) < (1.0 - 1e-4 * alpha) * f0 {
                return Some((trial, ft));
            }
            alpha *= 0.5;
        }
        None
    }
}

/// The interface and the exchange of one correction.
struct Shared<'a> {
    interface: &'a Interface,
    exchange: &'a dyn Exchange,
    /// Whether this process owns each body.
    owned: Vec<bool>,
}

impl Shared<'_> {
    /// Adds to `total` every body's part, in body order: this process computes its own bodies'
    /// parts with `part(b)` (pairs of an index of `total` and a value), a collective shares them.
    fn add_parts(&self, total: &mut [f64], part: impl Fn(usize) -> Vec<f64>) {
        let per_body = (0..self.interface.body_range.len())
            .map(|b| match self.owned[b] {
                true => part(b),
                false => Vec::new(),
            })
            .collect();
        for entries in share_vectors(self.exchange, per_body) {
            for pair in entries.chunks_exact(2) {
                if let Some(t) = total.get_mut(pair[0] as usize) {
                    *t += pair[1];
                }
            }
        }
    }
}

/// One body's part of the balance (a vector over the coarse unknowns) or of its Jacobian (a
/// matrix), over the unknowns `near` the body involves: a small dense buffer in which every
/// entry sums its terms in the order added.
struct Part<'a> {
    near: &'a [usize],
    /// A matrix (else a vector).
    square: bool,
    values: Vec<f64>,
    used: Vec<bool>,
}

impl<'a> Part<'a> {
    fn vector(near: &'a [usize]) -> Part<'a> {
        Part::sized(near, false)
    }

    fn matrix(near: &'a [usize]) -> Part<'a> {
        Part::sized(near, true)
    }

    fn sized(near: &'a [usize], square: bool) -> Part<'a> {
        let len = if square { near.len() } else { 1 } * near.len();
        Part {
            near,
            square,
            values: vec![0.0; len],
            used: vec![false; len],
        }
    }

    fn local(&self, q: usize) -> Option<usize> {
        self.near.binary_search(&q).ok()
    }

    /// The local numbers of the unknowns `qs` (a body's modes: consecutive, so consecutive
    /// here too); empty where the part does not involve them.
    fn locals(&self, qs: Range<usize>) -> Range<usize> {
        match self.local(qs.start) {
            Some(l) if !qs.is_empty() => l..l + qs.len(),
            _ => 0..0,
        }
    }

    /// Adds `v` to the entry of local number `l` (of the vector; of the matrix, column-major).
    fn add_local(&mut self, l: usize, v: f64) {
        self.used[l] = true;
        self.values[l] += v;
    }

    /// Adds `v` to the matrix's entry at the local numbers (`row`, `col`).
    fn add_local_at(&mut self, row: usize, col: usize, v: f64) {
        self.add_local(row + self.near.len() * col, v);
    }

    /// The entries as pairs (index, value) of a vector, or of a column-major n × n matrix.
    fn entries(&self, n: usize) -> Vec<f64> {
        let len = self.near.len();
        let global = |l: usize| match self.square {
            false => self.near[l],
            true => self.near[l % len] + n * self.near[l / len],
        };
        let mut out = Vec::with_capacity(2 * self.values.len());
        for l in (0..self.values.len()).filter(|&l| self.used[l]) {
            out.extend([global(l) as f64, self.values[l]]);
        }
        out
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}
