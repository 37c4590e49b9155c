//! Prescribed displacements (supports). Which rigid-body modes they leave a body is
//! [`crate::rigid::free_rigid_modes`].
//!
//! A support prescribes displacement components in global x/y, or the normal component u·n of a
//! straight boundary. On a boundary parallel to an axis that is an ordinary x or y prescription;
//! on an inclined boundary each of its nodes keeps the direction n and the value, and the
//! factorised operator ([`crate::factor::FactoredBody`]) solves for the tangential component
//! u·t of those nodes only.

use std::collections::BTreeMap;

use crate::error::SupportError;
use crate::geometry::{dof, dot, node_of, num_dofs, Vector, DIM};
use crate::mesh::Mesh;

/// Below this |sin| of the angle between two prescribed directions of one node they count as the
/// same direction: the later replaces the earlier instead of both being solved for (which would
/// divide by the tiny sine).
const PARALLEL: f64 = 1e-6;

/// Which displacement component a support prescribes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Component {
    /// u_x only.
    X,
    /// u_y only.
    Y,
    /// Both components.
    Both,
    /// The normal component of a straight boundary (a symmetry line or sliding support: u·n
    /// fixed, zero shear). On a boundary parallel to an axis the value is u_x (x = const) or u_y
    /// (y = const), as for `X` and `Y`; on an inclined boundary it is u·n with n the body's
    /// outward unit normal.
    Normal,
}

/// One prescription on a node: `u · direction = value`.
type Row = (Vector, f64);

/// Prescribed values per DOF of one body (`None` = free), and the nodes held along one inclined
/// direction only.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraints {
    values: Vec<Option<f64>>,
    /// Node → (outward unit normal, u·n) for the nodes of inclined `normal` supports whose
    /// x and y components are both free.
    inclined: BTreeMap<usize, Row>,
}

impl Constraints {
    /// No DOF constrained, for a mesh with `num_nodes` nodes.
    pub fn new(num_nodes: usize) -> Constraints {
        Constraints {
            values: vec![None; num_dofs(num_nodes)],
            inclined: BTreeMap::new(),
        }
    }

    /// No DOF constrained among `num_dofs` DOFs, whatever their number per node (the 3D layer,
    /// [`crate::solid`], has three); set them with [`Constraints::prescribe`].
    pub fn for_dofs(num_dofs: usize) -> Constraints {
        Constraints {
            values: vec![None; num_dofs],
            inclined: BTreeMap::new(),
        }
    }

    /// Prescribes `value` for DOF `dof` directly, whatever the number of DOFs per node (no
    /// inclined support involved).
    ///
    /// # Panics
    /// If `dof` is not below [`Constraints::len`].
    pub fn prescribe(&mut self, dof: usize, value: f64) {
        self.values[dof] = Some(value);
    }

    /// Prescribes `value` for `component` on every node of boundary (or node set) `name`.
    ///
    /// Each support prescribes one or two directions per node (x, y, or an inclined normal). A
    /// direction prescribed twice keeps the last value. Two different directions on one node (an
    /// inclined normal support meeting another support at a corner) fix the node entirely, at the
    /// point meeting both; a third replaces the earlier one closer to its own direction.
    pub fn fix(
        &mut self,
        mesh: &Mesh,
        name: &str,
        component: Component,
        value: f64,
    ) -> Result<(), SupportError> {
        if !value.is_finite() {
            return Err(SupportError::NonFinite {
                boundary: name.to_string(),
                value,
            });
        }
        let nodes = mesh.boundary_nodes(name)?;
        let comps: &[usize] = match component {
            Component::X => &[0],
            Component::Y => &[1],
            Component::Both => &[0, 1],
            Component::Normal => match axis_normal(mesh, name) {
                Some(0) => &[0],
                Some(_) => &[1],
                None => {
                    let n = line_normal(mesh, name)?;
                    for v in nodes {
                        self.add_row(v, (n, value));
                    }
                    return Ok(());
                }
            },
        };
        for v in nodes {
            for &c in comps {
                self.set(dof(v, c), Some(value));
            }
        }
        Ok(())
    }

    /// Prescribes (or frees, with `None`) one DOF directly. On a node of an inclined normal
    /// support a prescribed component combines with the normal one as in [`Constraints::fix`].
    pub fn set(&mut self, dof: usize, value: Option<f64>) {
        let v = node_of(dof);
        match value {
            Some(x) if self.inclined.contains_key(&v) => {
                let mut e = [0.0; DIM];
                e[dof % DIM] = 1.0;
                self.add_row(v, (e, x));
            }
            _ => self.values[dof] = value,
        }
    }

    /// Prescribed value of DOF `dof`, if any. A node held only along an inclined normal has no
    /// prescribed x or y value ([`Constraints::inclined`]).
    pub fn get(&self, dof: usize) -> Option<f64> {
        self.values[dof]
    }

    /// Number of DOFs (2 per node).
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True if there are no DOFs at all.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Constrained DOFs and their values (the x and y prescriptions; see also
    /// [`Constraints::inclined`]).
    pub fn fixed(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| (i, v)))
    }

    /// The nodes held along an inclined direction only: (node, outward unit normal n, u·n).
    pub fn inclined(&self) -> impl Iterator<Item = (usize, Vector, f64)> + '_ {
        self.inclined.iter().map(|(&v, &(n, g))| (v, n, g))
    }

    /// The outward unit normal and value u·n if node `v` is held along an inclined normal only.
    pub fn inclined_normal(&self, v: usize) -> Option<(Vector, f64)> {
        self.inclined.get(&v).copied()
    }

    /// Number of prescribed directions (one per prescribed DOF, one per inclined node): the
    /// number of unknowns the supports remove.
    pub fn num_prescribed(&self) -> usize {
        self.fixed().count() + self.inclined.len()
    }

    /// True if some support prescribes something.
    pub fn any(&self) -> bool {
        self.values.iter().any(Option::is_some) || !self.inclined.is_empty()
    }

    /// True if a support acts on DOF `dof`: its value is prescribed, or its node is held along an
    /// inclined direction (then the support's reaction has x and y components on the node).
    pub fn holds(&self, dof: usize) -> bool {
        self.values[dof].is_some() || self.inclined.contains_key(&node_of(dof))
    }

    /// Removes from the per-DOF vector `r` its components along the prescribed directions (what
    /// the supports take of a residual `K u − f`: their reactions).
    pub fn remove_prescribed(&self, r: &mut [f64]) {
        for (d, _) in self.fixed() {
            r[d] = 0.0;
        }
        for (&v, &(n, _)) in &self.inclined {
            let along = n[0] * r[dof(v, 0)] + n[1] * r[dof(v, 1)];
            for c in 0..DIM {
                r[dof(v, c)] -= along * n[c];
            }
        }
    }

    /// The node's current prescriptions as rows.
    fn rows(&self, v: usize) -> Vec<Row> {
        let mut rows: Vec<Row> = (0..DIM)
            .filter_map(|c| {
                let mut e = [0.0; DIM];
                e[c] = 1.0;
                self.values[dof(v, c)].map(|x| (e, x))
            })
            .collect();
        rows.extend(self.inclined.get(&v).copied());
        rows
    }

    /// Adds the prescription `row` to node `v`: a row of (nearly) the same direction is replaced;
    /// of two other rows, the one closer to `row`'s direction goes.
    fn add_row(&mut self, v: usize, row: Row) {
        let mut rows = self.rows(v);
        rows.retain(|r| cross(r.0, row.0).abs() > PARALLEL);
        if rows.len() == 2 {
            let closer = usize::from(cross(rows[1].0, row.0).abs() < cross(rows[0].0, row.0).abs());
            rows.remove(closer);
        }
        rows.push(row);
        self.store(v, &rows);
    }

    /// Stores at most two independent rows of node `v`: one axis row as a DOF value, one inclined
    /// row as such, two rows as the x and y values meeting both.
    fn store(&mut self, v: usize, rows: &[Row]) {
        self.inclined.remove(&v);
        self.values[dof(v, 0)] = None;
        self.values[dof(v, 1)] = None;
        match rows {
            [] => {}
            [(d, x)] => match axis_of(*d) {
                Some(c) => self.values[dof(v, c)] = Some(*x),
                None => {
                    self.inclined.insert(v, (*d, *x));
                }
            },
            [a, b, ..] => {
                let u = meet(*a, *b);
                for c in 0..DIM {
                    self.values[dof(v, c)] = Some(u[c]);
                }
            }
        }
    }
}

/// The axis a unit direction is, if it is exactly one.
fn axis_of(d: Vector) -> Option<usize> {
    (0..DIM).find(|&c| d[c] == 1.0 && d[1 - c] == 0.0)
}

/// z-component of `a × b`: the sine of the angle between two unit vectors.
fn cross(a: Vector, b: Vector) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The displacement meeting two rows of different directions; an axis row's component is kept
/// exactly as given.
fn meet((d1, g1): Row, (d2, g2): Row) -> Vector {
    let det = cross(d1, d2);
    let mut u = [
        (g1 * d2[1] - g2 * d1[1]) / det,
        (d1[0] * g2 - d2[0] * g1) / det,
    ];
    for (d, g) in [(d1, g1), (d2, g2)] {
        if let Some(c) = axis_of(d) {
            u[c] = g;
        }
    }
    u
}

/// 0 if boundary `name` is a straight line x = const, 1 if y = const, None otherwise (also when
/// one of its edges is curved).
fn axis_normal(mesh: &Mesh, name: &str) -> Option<usize> {
    let edges = mesh.boundary(name).ok()?;
    if edges.iter().any(|e| mesh.is_curved_edge(e)) {
        return None;
    }
    let p = mesh.nodes();
    let first = edges.first()?;
    let axis = if (p[first.a][0] - p[first.b][0]).abs() < (p[first.a][1] - p[first.b][1]).abs() {
        0
    } else {
        1
    };
    let tol = 1e-9 * mesh.bounding_box_diameter();
    let c = p[first.a][axis];
    edges
        .iter()
        .flat_map(|e| e.nodes())
        .all(|v| (p[v][axis] - c).abs() <= tol)
        .then_some(axis)
}

/// The outward unit normal of boundary `name` if all its nodes lie on one straight line (within
/// 1e-9 × the mesh diameter), none of its edges is curved ([`Mesh::is_curved_edge`]: its normal
/// turns along it) and all its edges face the same side of it.
fn line_normal(mesh: &Mesh, name: &str) -> Result<Vector, SupportError> {
    let not_straight = || SupportError::NotStraight {
        boundary: name.to_string(),
    };
    let edges = mesh
        .boundary(name)
        .map_err(|_| SupportError::NormalOnNodeSet {
            name: name.to_string(),
        })?;
    let p = mesh.nodes();
    let first = edges.first().ok_or_else(not_straight)?;
    if edges.iter().any(|e| mesh.is_curved_edge(e)) {
        return Err(not_straight());
    }
    // The edges run with the body on their left, so Σ (b − a) turned clockwise points outward.
    let s = edges.iter().fold([0.0; DIM], |s, e| {
        std::array::from_fn(|c| s[c] + p[e.b][c] - p[e.a][c])
    });
    let len = s[0].hypot(s[1]);
    if !(len > 0.0 && len.is_finite()) {
        return Err(not_straight());
    }
    let n = [s[1] / len, -s[0] / len];
    let tol = 1e-9 * mesh.bounding_box_diameter();
    let origin = p[first.a];
    let on_line = edges
        .iter()
        .flat_map(|e| e.nodes())
        .all(|v| dot(n, [p[v][0] - origin[0], p[v][1] - origin[1]]).abs() <= tol);
    let same_side = edges.iter().all(|e| dot(mesh.edge_normal(e).0, n) > 0.0);
    if on_line && same_side {
        Ok(n)
    } else {
        Err(not_straight())
    }
}
