//! Rigid motions that no closed contact resists.
//!
//! Every body's supports leave it a few free rigid modes (the core's [`free_modes`], at most 3
//! per body, each listed once: an orthonormal basis). A combination of them over all bodies is
//! in the kernel of J_χ when it changes no closed pair sum s_j and no tangential displacement g_j
//! of a frictional point that sticks: then S, which maps a body's rigid motion to zero, and the
//! closed contact and stick terms all vanish on it (a slipping point's term acts through s_j
//! alone, so it does not resist a motion that keeps s_j). The kernel is found from the
//! Gram matrix of those changes, which holds only geometry (normals and mode values), so neither a
//! stiffness contrast nor the penalty's size moves the threshold.

use nalgebra::{DMatrix, SymmetricEigen};

use contactdd_core::rigid::{describe, free_modes, motion_on, NUM_MODES};

use crate::model::Model;

use super::system::{Affine, ReducedSystem, Sparse};

/// One free rigid mode of one body.
pub(super) struct Mode {
    pub body: usize,
    /// Coefficients in the body's rigid basis.
    pub coefficients: [f64; NUM_MODES],
    /// Its values on the body's part of x (from the body's offset).
    pub on_x: Vec<f64>,
    /// The first x index of its body.
    pub offset: usize,
    /// The work of the body's applied loads along it.
    pub work: f64,
}

/// The free rigid modes of all bodies, with their changes of the contact points' pair sums and
/// tangential displacements stored per point (a mode changes only the points of its body and of
/// the points partnered with them, so the cost grows with the points, not with points × modes).
pub(super) struct Modes {
    list: Vec<Mode>,
    /// Per contact point, the modes that change its pair sum s_j and by how much.
    pub on_s: Vec<Vec<(usize, f64)>>,
    /// Per contact point, the modes that change its tangential displacement g_j (empty for a
    /// point without friction).
    pub on_g: Vec<Vec<(usize, f64)>>,
}

impl std::ops::Deref for Modes {
    type Target = [Mode];
    fn deref(&self) -> &[Mode] {
        &self.list
    }
}

impl Modes {
    /// Σ_m w_m Δs_j(m): the change of point j's pair sum along the motion with mode weights `w`.
    pub fn s_along(&self, j: usize, w: &[f64]) -> f64 {
        self.on_s[j].iter().map(|&(m, v)| w[m] * v).sum()
    }

    /// Σ_m w_m Δg_j(m): the change of point j's tangential displacement along the motion.
    pub fn g_along(&self, j: usize, w: &[f64]) -> f64 {
        self.on_g[j].iter().map(|&(m, v)| w[m] * v).sum()
    }
}

/// A kernel motion: a combination of modes, orthonormal on x.
pub(super) struct Kernel {
    /// Per kernel motion, its values on x.
    pub on_x: Vec<Sparse>,
    /// Per kernel motion, the coefficients of every mode.
    pub weights: Vec<Vec<f64>>,
}

/// The free rigid modes of every body.
pub(super) fn free_rigid_modes(model: &Model, system: &ReducedSystem) -> Modes {
    let mut list = Vec::new();
    let mut of_body: Vec<Vec<usize>> = vec![Vec::new(); model.bodies.len()];
    for (b, body) in model.bodies.iter().enumerate() {
        for v in free_modes(&body.mesh, &body.constraints, &[]) {
            let on_x = motion_on(&body.mesh, &v, &system.bodies[b].dofs);
            let dofs: Vec<usize> = (0..body.load.len())
                .filter(|&d| body.constraints.get(d).is_none())
                .collect();
            let motion = motion_on(&body.mesh, &v, &dofs);
            let work = dofs
                .iter()
                .zip(&motion)
                .map(|(&d, m)| m * body.load[d])
                .sum();
            of_body[b].push(list.len());
            list.push(Mode {
                body: b,
                coefficients: v,
                on_x,
                offset: system.offset[b],
                work,
            });
        }
    }
    let changes = |a: &Affine| changes(system, &list, &of_body, a);
    let on_s = system.s.iter().map(changes).collect();
    let on_g = (system.g.iter())
        .map(|row| row.as_ref().map_or_else(Vec::new, changes))
        .collect();
    Modes { list, on_s, on_g }
}

/// The modes that change the affine function `a` of x, with the change (`of_body`: the modes of
/// every body); the terms are summed in their order, as a dense product would.
fn changes(
    system: &ReducedSystem,
    list: &[Mode],
    of_body: &[Vec<usize>],
    a: &Affine,
) -> Vec<(usize, f64)> {
    let mut out: Vec<(usize, f64)> = Vec::new();
    for &(i, c) in &a.terms {
        let b = system.offset.partition_point(|&o| o <= i) - 1;
        for &m in &of_body[b] {
            let v = c * list[m].on_x[i - list[m].offset];
            match out.iter_mut().find(|(n, _)| *n == m) {
                Some((_, sum)) => *sum += v,
                None => out.push((m, v)),
            }
        }
    }
    out.sort_by_key(|&(m, _)| m);
    out.retain(|&(_, v)| v != 0.0);
    out
}

/// Groups of modes coupled by the rows `rows` (per row, its modes): the connected components
/// of the Gram matrix's graph, each ascending, in the order of their first mode; and per mode, its
/// component.
fn components<'a>(
    q: usize,
    rows: impl Iterator<Item = &'a Vec<(usize, f64)>>,
) -> (Vec<Vec<usize>>, Vec<usize>) {
    let mut parent: Vec<usize> = (0..q).collect();
    fn root(parent: &mut [usize], mut a: usize) -> usize {
        while parent[a] != a {
            parent[a] = parent[parent[a]];
            a = parent[a];
        }
        a
    }
    for row in rows {
        if let Some(&(first, _)) = row.first() {
            for &(m, _) in &row[1..] {
                let (x, y) = (root(&mut parent, first), root(&mut parent, m));
                parent[x.max(y)] = x.min(y);
            }
        }
    }
    let mut index = vec![usize::MAX; q];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut of = vec![0; q];
    for m in 0..q {
        let r = root(&mut parent, m);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        of[m] = index[r];
        groups[index[r]].push(m);
    }
    (groups, of)
}

/// The combinations of `modes` that change no pair sum of the points in `chi` and no tangential
/// displacement of the points in `stick` (empty without friction). The Gram matrix of those
/// changes is block diagonal over the groups of modes that closed points couple; each block's
/// null space is found on its own.
pub(super) fn kernel(modes: &Modes, chi: &[bool], stick: &[bool]) -> Kernel {
    let q = modes.len();
    let mut out = Kernel {
        on_x: Vec::new(),
        weights: Vec::new(),
    };
    if q == 0 {
        return out;
    }
    let closed = (0..chi.len()).filter(|&j| chi[j]);
    let sticking = (0..stick.len()).filter(|&j| stick[j]);
    let rows = closed.clone().map(|j| &modes.on_s[j]);
    let (groups, of) = components(q, rows.chain(sticking.clone().map(|j| &modes.on_g[j])));
    let mut position = vec![0; q];
    for group in &groups {
        for (i, &m) in group.iter().enumerate() {
            position[m] = i;
        }
    }
    let mut grams: Vec<DMatrix<f64>> = (groups.iter())
        .map(|g| DMatrix::zeros(g.len(), g.len()))
        .collect();
    let add = |grams: &mut Vec<DMatrix<f64>>, row: &[(usize, f64)]| {
        for &(a, va) in row {
            for &(b, vb) in row {
                grams[of[a]][(position[a], position[b])] += va * vb;
            }
        }
    };
    closed.for_each(|j| add(&mut grams, &modes.on_s[j]));
    // Only where some point sticks: a frictionless model's Gram matrix stays the same to the bit.
    if stick.iter().any(|&s| s) {
        let mut tangential: Vec<DMatrix<f64>> = (groups.iter())
            .map(|g| DMatrix::zeros(g.len(), g.len()))
            .collect();
        sticking.for_each(|j| add(&mut tangential, &modes.on_g[j]));
        grams.iter_mut().zip(tangential).for_each(|(g, t)| *g += t);
    }
    let scale = (grams.iter())
        .flat_map(|g| g.diagonal().iter().copied().collect::<Vec<_>>())
        .fold(0.0, f64::max);
    for (group, gram) in groups.iter().zip(grams) {
        null_space(modes, group, gram, scale, &mut out);
    }
    out
}

/// Adds the null space of the Gram matrix `gram` of the modes `group` (eigenvalues at most
/// 1e-10 `scale`) to `out`, orthonormal on x.
fn null_space(modes: &Modes, group: &[usize], gram: DMatrix<f64>, scale: f64, out: &mut Kernel) {
    if held(&gram, 1e-9 * scale) {
        return;
    }
    let first = out.on_x.len();
    let eig = SymmetricEigen::new(gram);
    for (k, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda > 1e-10 * scale {
            continue;
        }
        let mut w = vec![0.0; modes.len()];
        for (i, &m) in group.iter().enumerate() {
            w[m] = eig.eigenvectors[(i, k)];
        }
        let mut z = combination(modes, group, &w);
        for e in &out.on_x[first..] {
            let d = sparse_dot(e, &z);
            z.iter_mut().zip(e).for_each(|(x, y)| x.1 -= d * y.1);
        }
        let norm = sparse_dot(&z, &z).sqrt();
        if norm > 1e-12 {
            z.iter_mut().for_each(|x| x.1 /= norm);
            out.on_x.push(z);
            out.weights.push(w);
        }
    }
}

/// Groups of at most this many modes go straight to the eigendecomposition.
const SMALL_GROUP: usize = 24;

/// True if the Gram matrix `gram` (modes ordered by body, so banded for bodies numbered along
/// the structure) is certainly positive definite with smallest eigenvalue above `floor`: by a
/// banded Cholesky factorisation G = L Lᵀ and λ_min ≥ 1/trace(G⁻¹) = 1/‖L⁻¹‖²_F. The cost
/// grows with the group's size times its band, not with its cube; false (undecided) for small
/// or wide-band groups, which the eigendecomposition decides.
fn held(gram: &DMatrix<f64>, floor: f64) -> bool {
    let q = gram.nrows();
    let band = (0..q)
        .flat_map(|a| {
            (0..a)
                .filter(move |&b| gram[(a, b)] != 0.0)
                .map(move |b| a - b)
        })
        .max()
        .unwrap_or(0);
    if q <= SMALL_GROUP || band * 4 > q || floor <= 0.0 {
        return false;
    }
    // L in band storage: l[a][k] = L[a, a − band + k].
    let mut l = vec![vec![0.0; band + 1]; q];
    for a in 0..q {
        for b in a.saturating_sub(band)..=a {
            let mut v = gram[(a, b)];
            for c in a.saturating_sub(band).max(b.saturating_sub(band))..b {
                v -= l[a][c + band - a] * l[b][c + band - b];
            }
            if a == b {
                if v <= 0.0 || !v.is_finite() {
                    return false;
                }
                l[a][band] = v.sqrt();
            } else {
                l[a][b + band - a] = v / l[b][band];
            }
        }
    }
    // ‖L⁻¹‖²_F column by column: y = L⁻¹ e_i, nonzero from i on.
    let mut trace = 0.0;
    let mut y = vec![0.0; q];
    for i in 0..q {
        y[i..].iter_mut().for_each(|v| *v = 0.0);
        for a in i..q {
            let mut v = if a == i { 1.0 } else { 0.0 };
            for c in a.saturating_sub(band).max(i)..a {
                v -= l[a][c + band - a] * y[c];
            }
            y[a] = v / l[a][band];
            trace += y[a] * y[a];
        }
        if trace * floor >= 1.0 {
            return false;
        }
    }
    true
}

/// Σ_m w_m (mode m on x) over the modes `group` (ascending), on their bodies' parts of x.
fn combination(modes: &Modes, group: &[usize], w: &[f64]) -> Sparse {
    let mut z: Sparse = Vec::new();
    let mut i = 0;
    while i < group.len() {
        let m = &modes[group[i]];
        let mut part = vec![0.0; m.on_x.len()];
        while i < group.len() && modes[group[i]].body == m.body {
            let n = &modes[group[i]];
            part.iter_mut()
                .zip(&n.on_x)
                .for_each(|(a, v)| *a += w[group[i]] * v);
            i += 1;
        }
        z.extend(part.into_iter().enumerate().map(|(k, v)| (m.offset + k, v)));
    }
    z
}

/// The dot product of two motions on the same indices.
fn sparse_dot(a: &Sparse, b: &Sparse) -> f64 {
    a.iter().zip(b).map(|(x, y)| x.1 * y.1).sum()
}

/// The points of `candidates` (ascending) that one of the motions with mode weights `ws` changes:
/// by more than 1e-8 of the motion's largest change `change(j, w)` over the candidates.
pub(super) fn changed_by(
    candidates: &[usize],
    ws: &[Vec<f64>],
    change: impl Fn(usize, &[f64]) -> f64,
) -> Vec<usize> {
    let mut hit = vec![false; candidates.len()];
    for w in ws {
        let c: Vec<f64> = candidates.iter().map(|&j| change(j, w)).collect();
        let largest = c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (h, v) in hit.iter_mut().zip(&c) {
            *h |= largest > 0.0 && v.abs() > 1e-8 * largest;
        }
    }
    (candidates.iter().zip(hit))
        .filter_map(|(&j, h)| h.then_some(j))
        .collect()
}

/// A kernel motion in words: "translation in y of 'lower' together with translation in y of
/// 'upper'".
pub(super) fn describe_motion(model: &Model, modes: &[Mode], weights: &[f64]) -> String {
    let mut parts = Vec::new();
    let mut sums: Vec<(usize, [f64; NUM_MODES])> = Vec::new();
    for (m, &w) in modes.iter().zip(weights) {
        if sums.last().map(|(b, _)| *b) != Some(m.body) {
            sums.push((m.body, [0.0; NUM_MODES]));
        }
        let last = sums.len() - 1;
        for i in 0..NUM_MODES {
            sums[last].1[i] += w * m.coefficients[i];
        }
    }
    for (b, v) in sums {
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.1 {
            let v = v.map(|x| x / norm);
            parts.push(format!("{} of '{}'", describe(&v), model.bodies[b].name));
        }
    }
    parts.join(" together with ")
}

/// Removes the components along the orthonormal motions `basis` from `r` (on x).
pub(super) fn project_out(basis: &[Sparse], r: &mut [f64]) {
    for e in basis {
        let d: f64 = e.iter().map(|&(i, v)| v * r[i]).sum();
        e.iter().for_each(|&(i, v)| r[i] -= d * v);
    }
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
