//! A body condensed onto the normal displacements of its contact points.
//!
//! Each body's Robin problem (docs/method.md §3) is
//!   (K + N D Nᵀ) ũ = f + N r,   D = diag(φ_j w_j / θ),   r_j = (w_j/θ)(φ_j u^k_n,j + (d_j − s^k_j)⁻),
//! where column j of N is the normal n_j at the node of contact point j. A floating body has a
//! singular K, so we factor the *reference* operator K₀ = K + N D₀ Nᵀ with D₀ = diag(w_j/θ) (φ ≡ 1,
//! regular as soon as the contact zone holds the body) once, with the contact DOFs ordered last.
//! With C₀ = Nᵀ K₀⁻¹ N (from the trailing Schur factor L₂₂: C₀ = YᵀY, Y = L₂₂⁻¹ N) and
//! f₀ = Nᵀ K₀⁻¹ f, the normal displacements of the Robin solution satisfy
//!   ũ_n = f₀ + C₀ (r − E ũ_n),   E = D − D₀ = −diag((1 − φ_j) w_j/θ).
//! Only points with φ_j < 1 (set J) enter the matrix: with F = −E_J and v = F^{½} ũ_J,
//!   (I − F^{½} C₀,JJ F^{½}) v = F^{½} z_J,   z = f₀ + C₀ r,
//! a small dense SPD system that is SPD exactly when the Robin problem is regular, so a failed
//! Cholesky there *is* the diagnosis "this body is floating". An iteration therefore costs a few
//! small dense operations per body, never a sparse solve. The full field is K₀⁻¹(f + N T) for the
//! accumulated interface load T, recovered by one sparse solve at the end.
//!
//! That is the *dense* path: C₀ holds m² values and its setup costs about m³ flops. When the
//! contact zone is long against the body, the *sparse* path ([`crate::sparse_body`]) keeps only
//! the sparse factor of K₀ and solves with it instead; [`Condensation`] chooses per body
//! (`docs/sparse-path.md`).

use std::time::Instant;

use faer::prelude::Solve;
use faer::{Mat, Side};

use contactdd_core::geometry::dot;
use contactdd_core::{dof, node_vector, BodyError, ElasticBody, FactoredBody, Vector, DIM};

use contactdd_core::memory;
use rayon::prelude::*;

use crate::contact::{ContactPoint, Interface};
use crate::error::SetupError;
pub use crate::error::Singular;
use crate::model::Model;
use crate::sparse_body::{spring_additions, RobinFactor, SparseContact};

/// How the bodies are condensed on their contact points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Condensation {
    /// Per body, the cheaper of the two by the cost model of `docs/sparse-path.md`.
    #[default]
    Auto,
    /// The dense blocks C₀ on the contact points (every body).
    Dense,
    /// The sparse factor alone (every body).
    Sparse,
}

impl std::fmt::Display for Condensation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Condensation::Auto => "auto",
            Condensation::Dense => "dense",
            Condensation::Sparse => "sparse",
        })
    }
}

/// The cost model: the dense path while its blocks on the contact points (`m` points, `dofs`
/// interface DOFs: Y, C₀ and the Robin matrix) hold at most [`DENSE_PER_FACTOR`] times the values
/// of the body's sparse factor `factor_len` (fill-reducing order, no dense trailing block).
/// Dense blocks of at most [`DENSE_ALWAYS`] values are always kept: their operations take
/// milliseconds whatever the body, and the dense path is the one a distributed run uses, so small
/// problems give the same bits on one process and on several.
pub fn prefers_dense(m: usize, dofs: usize, factor_len: usize) -> bool {
    let dense = (m as f64) * (dofs as f64 + 2.0 * m as f64);
    dense <= DENSE_ALWAYS || dense <= DENSE_PER_FACTOR * factor_len as f64
}

/// Dense blocks this small (8 MiB of values) are cheap in absolute terms.
pub const DENSE_ALWAYS: f64 = (1u64 << 20) as f64;

/// How many times the sparse factor's values the dense blocks may hold (docs/sparse-path.md).
pub const DENSE_PER_FACTOR: f64 = 1.0;

/// What a body keeps of its condensation.
enum Reduction {
    /// C₀ = Nᵀ K₀⁻¹ N.
    Dense(Mat<f64>),
    /// The contact points in the sparse factor's numbering.
    Sparse(SparseContact),
}

/// One body's factorised reference operator and its condensation on the contact points.
pub struct CondensedBody {
    op: FactoredBody,
    /// Nodes and normals of the contact points (body-local order).
    nodes: Vec<usize>,
    normals: Vec<Vector>,
    /// Reference spring stiffness w_j/θ_j (φ = 1).
    d0: Vec<f64>,
    /// C₀, or what the sparse path keeps instead.
    reduction: Reduction,
    /// f₀ = Nᵀ K₀⁻¹ f (with the prescribed displacements), at the load factor.
    f0: Vec<f64>,
    /// f₀ at load factor 1.
    f0_full: Vec<f64>,
    load: Vec<f64>,
    /// The factor on the loads and prescribed displacements (1: the problem as given).
    factor: f64,
    /// The other load groups of a load history ([`crate::history`]), and their factors.
    groups: Vec<GroupLoad>,
    /// The reduced right-hand side of the other groups at their factors (sparse path; empty
    /// while every group's factor is 0).
    group_rhs: Vec<f64>,
}

/// One load group of a body other than its own load ([`crate::history::LoadGroup`]).
struct GroupLoad {
    /// The group's load vector.
    load: Vec<f64>,
    /// Nᵀ(K₀⁻¹L − K₀⁻¹0): the normal displacements under the group's load alone.
    f0: Vec<f64>,
    /// The reduced right-hand side of the load alone (sparse path; empty on the dense one).
    rhs: Vec<f64>,
    /// The group's factor.
    factor: f64,
}

/// The cached factorisation of the reduced Robin matrix for one φ.
#[derive(Default)]
pub struct RobinCache {
    phi: Vec<f64>,
    set: Vec<usize>,
    sqrt_f: Vec<f64>,
    llt: Option<faer::linalg::solvers::Llt<f64>>,
    /// The Robin factor of the sparse path.
    sparse: RobinFactor,
}

/// Analyses the bodies of `model` that `owns` selects (in parallel; the others `None`) once the
/// dense blocks on their contact points are known to fit in memory, then checks the whole
/// estimate: the bodies are factorised together.
pub fn analyse_all<'a>(
    model: &'a Model,
    interface: &Interface,
    condensation: Condensation,
    owns: &(dyn Fn(usize) -> bool + Sync),
) -> Result<Vec<Option<Analysed<'a>>>, SetupError> {
    // Forced dense blocks are known before the symbolic analysis, whose cost grows with them.
    if condensation == Condensation::Dense {
        let dense = (0..model.bodies.len())
            .filter(|&b| owns(b))
            .map(|b| dense_bytes(interface.of_body(b).len(), interface.of_body(b).len()))
            .fold(0u64, u64::saturating_add);
        memory::check("condensing the bodies on their contact points", dense)?;
    }
    let analysed = model
        .bodies
        .par_iter()
        .enumerate()
        .map(|(b, body)| {
            owns(b)
                .then(|| Analysed::new(body, interface.of_body(b), condensation))
                .transpose()
        })
        .collect::<Result<Vec<_>, _>>()?;
    let bytes = analysed
        .iter()
        .flatten()
        .map(Analysed::memory_estimate)
        .fold(0u64, u64::saturating_add);
    memory::check("factorising and condensing the bodies", bytes)?;
    Ok(analysed)
}

/// Bytes of the dense blocks of a body with `m` contact points and `dofs` interface DOFs (at
/// least m): Y (dofs × m), C₀ (m × m) and the Robin matrix (at most m × m).
fn dense_bytes(m: usize, dofs: usize) -> u64 {
    let m = m as u64;
    m.saturating_mul(dofs as u64 + 2 * m)
        .saturating_mul(size_of::<f64>() as u64)
}

/// A body assembled and analysed (the symbolic factorisation), not yet factorised: its
/// [`memory_estimate`](Analysed::memory_estimate) can be checked before anything big is allocated.
pub struct Analysed<'a> {
    body: &'a ElasticBody,
    op: FactoredBody,
    interface: Vec<usize>,
    nodes: Vec<usize>,
    normals: Vec<Vector>,
    d0: Vec<f64>,
    /// The dense path (else the sparse one).
    dense: bool,
    /// Seconds spent assembling and in the symbolic analysis.
    assembly: f64,
    symbolic: f64,
}

/// Wall times of one body's setup phases, seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SetupTimes {
    /// Assembly of the stiffness matrix.
    pub assembly: f64,
    /// Elimination of the supports, fill-reducing ordering and symbolic Cholesky analysis.
    pub symbolic: f64,
    /// Numeric Cholesky factorisation.
    pub numeric: f64,
    /// Condensation on the contact points: Y = L₂₂⁻¹N, C₀ = YᵀY and f₀.
    pub condensation: f64,
}

impl<'a> Analysed<'a> {
    /// Assembles one body and analyses its factorisation: with the contact DOFs last on the dense
    /// path, in a fill-reducing order on the sparse one; `condensation` chooses the path.
    pub fn new(
        body: &'a ElasticBody,
        points: &[ContactPoint],
        condensation: Condensation,
    ) -> Result<Analysed<'a>, BodyError> {
        let nodes: Vec<usize> = points.iter().map(|p| p.node).collect();
        let normals: Vec<Vector> = points.iter().map(|p| p.normal).collect();
        let d0: Vec<f64> = points.iter().map(|p| p.spring).collect();
        let springs: Vec<(usize, Vector)> =
            nodes.iter().copied().zip(normals.iter().copied()).collect();
        body.check_held(&springs)?;
        if body.load.iter().any(|v| !v.is_finite()) {
            return Err(BodyError::NonFinite {
                body: body.name.clone(),
                what: "the load vector".into(),
            });
        }
        // Only DOFs that carry a normal component couple to the contact (a straight horizontal
        // contact line needs u_y only), which keeps the dense Schur block as small as possible.
        let mut interface: Vec<usize> = nodes
            .iter()
            .zip(&normals)
            .flat_map(|(&v, n)| (0..DIM).filter(|&c| n[c] != 0.0).map(move |c| dof(v, c)))
            .collect();
        interface.sort_unstable();
        interface.dedup();
        let t = Instant::now();
        let k = body.stiffness();
        let assembly = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let (op, dense) = analyse(body, k, &interface, nodes.len(), condensation)?;
        Ok(Analysed {
            body,
            op,
            interface,
            nodes,
            normals,
            d0,
            dense,
            assembly,
            symbolic: t.elapsed().as_secs_f64(),
        })
    }

    /// Bytes that [`condense`](Analysed::condense) allocates: the sparse factor and the dense
    /// blocks on the contact points.
    pub fn memory_estimate(&self) -> u64 {
        if !self.dense {
            // The reference factor and the Robin factor of the iteration.
            return self.op.memory_estimate().saturating_mul(2);
        }
        let dense = dense_bytes(self.nodes.len(), self.interface.len());
        self.op.memory_estimate().saturating_add(dense)
    }

    /// True if the body takes the dense path.
    pub fn is_dense(&self) -> bool {
        self.dense
    }

    /// Factorises (with the reference springs) and condenses the body; also returns the times
    /// of its setup phases.
    pub fn condense(self, par: faer::Par) -> Result<(CondensedBody, SetupTimes), BodyError> {
        let Analysed {
            body,
            mut op,
            interface,
            nodes,
            normals,
            d0,
            dense,
            assembly,
            symbolic,
        } = self;
        let t = Instant::now();
        op.set_parallelism(par);
        op.factorize(&spring_additions(&nodes, &normals, &d0))?;
        let numeric = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let reduction = if dense {
            Reduction::Dense(condense_dense(&op, &interface, &nodes, &normals, par)?)
        } else {
            Reduction::Sparse(SparseContact::new(&op, body, &nodes, &normals))
        };
        let x = op.solve(&body.load)?;
        let f0: Vec<f64> = nodes
            .iter()
            .zip(&normals)
            .map(|(&v, n)| dot(*n, node_vector(&x, v)))
            .collect();
        let times = SetupTimes {
            assembly,
            symbolic,
            numeric,
            condensation: t.elapsed().as_secs_f64(),
        };
        let condensed = CondensedBody {
            op,
            nodes,
            normals,
            d0,
            reduction,
            f0_full: f0.clone(),
            f0,
            load: body.load.clone(),
            factor: 1.0,
            groups: Vec::new(),
            group_rhs: Vec::new(),
        };
        Ok((condensed, times))
    }
}

/// The symbolic analysis of the path `condensation` asks for. `Auto` keeps the dense path without
/// a second analysis when [`prefers_dense`] holds already against half the stiffness entries (a
/// lower bound of the factor's values); otherwise it analyses the sparse order first and analyses
/// again with the contact DOFs last only if the factor's size then keeps the dense path. Returns
/// the analysis and whether it is the dense path's.
fn analyse(
    body: &ElasticBody,
    k: faer::sparse::SparseColMat<usize, f64>,
    interface: &[usize],
    m: usize,
    condensation: Condensation,
) -> Result<(FactoredBody, bool), BodyError> {
    let new =
        |k, interface: &[usize]| FactoredBody::new(&body.name, k, &body.constraints, interface);
    let n = interface.len();
    match condensation {
        Condensation::Dense => Ok((new(k, interface)?, true)),
        Condensation::Sparse => Ok((new(k, &[])?, false)),
        Condensation::Auto if prefers_dense(m, n, k.val().len() / 2) => {
            Ok((new(k, interface)?, true))
        }
        Condensation::Auto => {
            let sparse = new(k.clone(), &[])?;
            if prefers_dense(m, n, sparse.factor_len()) {
                drop(sparse);
                Ok((new(k, interface)?, true))
            } else {
                Ok((sparse, false))
            }
        }
    }
}

/// C₀ = YᵀY with Y = L₂₂⁻¹ N on the free interface DOFs: the dense path's condensation.
fn condense_dense(
    op: &FactoredBody,
    interface: &[usize],
    nodes: &[usize],
    normals: &[Vector],
    par: faer::Par,
) -> Result<Mat<f64>, BodyError> {
    let l22 = op.schur_factor()?;
    let index = op.interface_index(interface);
    let pos: std::collections::HashMap<usize, Option<(usize, f64)>> =
        interface.iter().copied().zip(index).collect();
    let m = nodes.len();
    let mut y = Mat::<f64>::zeros(l22.nrows(), m);
    for (j, (&v, n)) in nodes.iter().zip(normals).enumerate() {
        for c in 0..DIM {
            if let Some(Some((i, k))) = pos.get(&dof(v, c)) {
                y[(*i, j)] += n[c] * k;
            }
        }
    }
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l22.as_ref(), y.as_mut(), par);
    Ok(y.transpose() * &y)
}

impl CondensedBody {
    /// Number of contact points.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True if the body has no contact points.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// B = C₀ D₀: the change of the normal displacements per unit change of τ = D₀⁻¹ T (the
    /// interface load in displacement units). B maps a rigid motion's normal values to themselves.
    /// `None` on the sparse path, which never forms it.
    pub fn load_response(&self) -> Option<Mat<f64>> {
        match &self.reduction {
            Reduction::Dense(c0) => Some(Mat::from_fn(self.len(), self.len(), |i, j| {
                c0[(i, j)] * self.d0[j]
            })),
            Reduction::Sparse(_) => None,
        }
    }

    /// The sparse path's contact points, or `None` on the dense path.
    pub fn sparse(&self) -> Option<&SparseContact> {
        match &self.reduction {
            Reduction::Dense(_) => None,
            Reduction::Sparse(s) => Some(s),
        }
    }

    /// U = f₀ + C₀ D₀ τ: the normal displacements under the interface load D₀τ (on the sparse
    /// path one sparse solve).
    pub fn respond(&self, tau: &[f64]) -> Result<Vec<f64>, BodyError> {
        let c0t = self.apply_response(tau)?;
        Ok(self.f0.iter().zip(&c0t).map(|(f, c)| f + c).collect())
    }

    /// B τ = C₀ D₀ τ (on the sparse path one sparse solve).
    pub fn apply_response(&self, tau: &[f64]) -> Result<Vec<f64>, BodyError> {
        let t: Vec<f64> = tau.iter().zip(&self.d0).map(|(t, d)| t * d).collect();
        self.apply_c0(&t)
    }

    /// The starting state of the sweeps for the normal displacements `un0`: (U⁰, T⁰) with
    /// T⁰ = [`initial_load`](CondensedBody::initial_load) and U⁰ = f₀ + C₀T⁰, the displacements
    /// T⁰ reproduces. On the dense path U⁰ is `un0` itself; on the sparse path T⁰ is approximate
    /// and U⁰ close to `un0`, so that U⁰ and T⁰ still describe one field.
    pub fn initial_state(&self, un0: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let t = self.initial_load(un0);
        if let Reduction::Sparse(_) = self.reduction {
            if let Ok(c0t) = self.apply_c0(&t) {
                let u = self.f0.iter().zip(&c0t).map(|(f, c)| f + c).collect();
                return (u, t);
            }
        }
        (un0.to_vec(), t)
    }

    /// C₀ v.
    fn apply_c0(&self, v: &[f64]) -> Result<Vec<f64>, BodyError> {
        match &self.reduction {
            Reduction::Dense(c0) => Ok((0..self.len())
                .map(|i| (0..self.len()).map(|j| c0[(i, j)] * v[j]).sum())
                .collect()),
            Reduction::Sparse(s) => s.apply_c0(&self.op, v),
        }
    }

    /// The reference spring stiffnesses D₀ = w/θ.
    pub fn reference_springs(&self) -> &[f64] {
        &self.d0
    }

    /// f₀ = Nᵀ K₀⁻¹ f: the normal displacements under the body's load alone.
    pub fn free_response(&self) -> &[f64] {
        &self.f0
    }

    /// The load vector the body carries now: its own load at the load factor plus every load
    /// group at its factor.
    pub fn applied_load(&self) -> Vec<f64> {
        let mut f: Vec<f64> = self.load.iter().map(|v| self.factor * v).collect();
        for g in self.groups.iter().filter(|g| g.factor != 0.0) {
            f.iter_mut()
                .zip(&g.load)
                .for_each(|(a, b)| *a += g.factor * b);
        }
        f
    }

    /// Scales the loads and prescribed displacements by `factor` (a load step): f₀ is linear
    /// in both.
    /// The other load groups' factors become 0.
    pub fn set_load_factor(&mut self, factor: f64) {
        self.factor = factor;
        self.f0 = self.f0_full.iter().map(|v| factor * v).collect();
        self.groups.iter_mut().for_each(|g| g.factor = 0.0);
        self.group_rhs.clear();
    }

    /// Sets the body's other load groups (a load history, [`crate::history`]): per group its
    /// load vector (empty: the group does not load this body), each at factor 0. The body's own
    /// load and prescribed displacements stay the default group. One solve per group with the
    /// kept factor: the group's response is Nᵀ(K₀⁻¹L − K₀⁻¹0), without the prescribed values.
    /// `body` names the body in errors (a load of the wrong length or not finite).
    pub fn set_load_groups(&mut self, body: &str, loads: &[Vec<f64>]) -> Result<(), BodyError> {
        if loads.is_empty() {
            self.groups.clear();
            self.set_load_factor(self.factor);
            return Ok(());
        }
        let zero = vec![0.0; self.load.len()];
        let free = self.op.solve(&zero)?;
        let sparse = matches!(self.reduction, Reduction::Sparse(_));
        let free_rhs = match sparse {
            true => self.op.reduced_load(&zero),
            false => Vec::new(),
        };
        let mut groups = Vec::with_capacity(loads.len());
        for load in loads {
            let load = match load.is_empty() {
                true => zero.clone(),
                false => load.clone(),
            };
            if load.len() != zero.len() || load.iter().any(|v| !v.is_finite()) {
                return Err(BodyError::NonFinite {
                    body: body.to_string(),
                    what: format!(
                        "a load group's load vector ({} entries for {} DOFs)",
                        load.len(),
                        zero.len()
                    ),
                });
            }
            let x = self.op.solve(&load)?;
            let f0 = (self.nodes.iter().zip(&self.normals))
                .map(|(&v, n)| dot(*n, node_vector(&x, v)) - dot(*n, node_vector(&free, v)))
                .collect();
            let rhs = match sparse {
                true => (self.op.reduced_load(&load).iter().zip(&free_rhs))
                    .map(|(a, b)| a - b)
                    .collect(),
                false => Vec::new(),
            };
            groups.push(GroupLoad {
                load,
                f0,
                rhs,
                factor: 0.0,
            });
        }
        self.groups = groups;
        self.set_load_factor(self.factor);
        Ok(())
    }

    /// Sets the load combination of a load history: `factor` on the body's own load and
    /// prescribed displacements (the default group), `group_factors[g]` on the load of group g
    /// of [`set_load_groups`](CondensedBody::set_load_groups). Without other groups this is
    /// [`set_load_factor`](CondensedBody::set_load_factor), to the bit.
    pub fn set_load_combination(&mut self, factor: f64, group_factors: &[f64]) {
        self.set_load_factor(factor);
        for (g, &c) in self.groups.iter_mut().zip(group_factors) {
            g.factor = c;
            if c == 0.0 {
                continue;
            }
            self.f0.iter_mut().zip(&g.f0).for_each(|(f, v)| *f += c * v);
            if !g.rhs.is_empty() {
                self.group_rhs.resize(g.rhs.len(), 0.0);
                (self.group_rhs.iter_mut().zip(&g.rhs)).for_each(|(f, v)| *f += c * v);
            }
        }
    }

    /// The factorised operator.
    pub fn operator(&self) -> &FactoredBody {
        &self.op
    }

    /// The interface load T⁰ whose field K₀⁻¹(f + N T⁰) has normal displacements `un0`
    /// (least-squares-free: falls back to T⁰ = 0 if C₀ is singular).
    pub fn initial_load(&self, un0: &[f64]) -> Vec<f64> {
        let m = self.len();
        let c0 = match &self.reduction {
            Reduction::Dense(c0) => c0,
            Reduction::Sparse(s) => {
                let rhs: Vec<f64> = (0..m).map(|i| un0[i] - self.f0[i]).collect();
                return s.initial_load(&self.op, &rhs);
            }
        };
        let rhs = Mat::<f64>::from_fn(m, 1, |i, _| un0[i] - self.f0[i]);
        match c0.llt(Side::Lower) {
            Ok(llt) => {
                let t = llt.solve(&rhs);
                let t: Vec<f64> = (0..m).map(|i| t[(i, 0)]).collect();
                if t.iter().all(|v| v.is_finite()) {
                    t
                } else {
                    vec![0.0; m]
                }
            }
            Err(_) => vec![0.0; m],
        }
    }

    /// Solves the Robin problem for coefficients `phi` and right-hand side `r` (see the module
    /// docs). Writes the normal displacements ũ_n to `un` and the interface load
    /// t = r − E ũ_n (so that ũ = K₀⁻¹(f + N t)) to `t`.
    pub fn robin_solve(
        &self,
        phi: &[f64],
        r: &[f64],
        cache: &mut RobinCache,
        un: &mut [f64],
        t: &mut [f64],
    ) -> Result<(), Singular> {
        let m = self.len();
        let c0 = match &self.reduction {
            Reduction::Dense(c0) => c0,
            Reduction::Sparse(s) => {
                let point = (
                    self.nodes.as_slice(),
                    self.normals.as_slice(),
                    self.d0.as_slice(),
                );
                return s.robin_solve(
                    &self.op,
                    point,
                    (self.factor, &self.group_rhs),
                    phi,
                    r,
                    &mut cache.sparse,
                    (un, t),
                );
            }
        };
        if cache.phi.as_slice() != phi || (cache.llt.is_none() && !cache.set.is_empty()) {
            cache.phi = phi.to_vec();
            cache.set = (0..m).filter(|&j| phi[j] < 1.0).collect();
            cache.sqrt_f = cache
                .set
                .iter()
                .map(|&j| ((1.0 - phi[j]) * self.d0[j]).sqrt())
                .collect();
            let (set, sf) = (&cache.set, &cache.sqrt_f);
            let g = Mat::<f64>::from_fn(set.len(), set.len(), |a, b| {
                let id = if a == b { 1.0 } else { 0.0 };
                id - sf[a] * c0[(set[a], set[b])] * sf[b]
            });
            cache.llt = None;
            if !set.is_empty() {
                let llt = g.llt(Side::Lower).map_err(|_| Singular)?;
                // A pivot this small means the Robin operator is numerically singular.
                let l = llt.L();
                if (0..set.len()).any(|i| l[(i, i)] * l[(i, i)] < 1e-11) {
                    return Err(Singular);
                }
                cache.llt = Some(llt);
            }
        }
        // z = f₀ + C₀ r
        for i in 0..m {
            un[i] = self.f0[i] + (0..m).map(|j| c0[(i, j)] * r[j]).sum::<f64>();
        }
        let (set, sf) = (&cache.set, &cache.sqrt_f);
        if let Some(llt) = &cache.llt {
            let rhs = Mat::<f64>::from_fn(set.len(), 1, |a, _| sf[a] * un[set[a]]);
            let v = llt.solve(&rhs);
            // ũ_J = F^{-½} v; then ũ = z + C₀,·J F ũ_J.
            let fu: Vec<f64> = (0..set.len()).map(|a| sf[a] * v[(a, 0)]).collect();
            for i in 0..m {
                un[i] += set
                    .iter()
                    .zip(&fu)
                    .map(|(&j, &x)| c0[(i, j)] * x)
                    .sum::<f64>();
            }
        }
        for j in 0..m {
            t[j] = r[j] + (1.0 - phi[j]) * self.d0[j] * un[j];
        }
        Ok(())
    }

    /// The full displacement K₀⁻¹(λf + Σ c_g L_g + N T) for interface load `t_load`, with the
    /// prescribed displacements times λ (the load factor; c_g, L_g: the other load groups').
    pub fn recover(&self, t_load: &[f64]) -> Result<Vec<f64>, BodyError> {
        let mut f: Vec<f64> = self.load.iter().map(|v| self.factor * v).collect();
        for g in self.groups.iter().filter(|g| g.factor != 0.0) {
            f.iter_mut()
                .zip(&g.load)
                .for_each(|(f, v)| *f += g.factor * v);
        }
        for ((&v, n), &t) in self.nodes.iter().zip(&self.normals).zip(t_load) {
            for c in 0..DIM {
                f[dof(v, c)] += n[c] * t;
            }
        }
        let mut u = self.op.solve(&f)?;
        if self.factor != 1.0 {
            // The solve imposes the prescribed values themselves; the field they cause alone
            // (zero load) scales the rest of the way.
            let g = self.op.solve(&vec![0.0; f.len()])?;
            u.iter_mut()
                .zip(&g)
                .for_each(|(u, g)| *u += (self.factor - 1.0) * g);
        }
        Ok(u)
    }
}
