//! Prescribed displacements (supports) and the check that a body has no rigid-body modes left.

use nalgebra::{Matrix3, SymmetricEigen};

use crate::error::SupportError;
use crate::mesh::Mesh;

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
    /// The normal component of a straight axis-aligned boundary (a symmetry line: u·n fixed,
    /// zero shear).
    Normal,
}

/// Prescribed values per DOF of one body (`None` = free).
#[derive(Clone, Debug, PartialEq)]
pub struct Constraints {
    values: Vec<Option<f64>>,
}

impl Constraints {
    /// No DOF constrained, for a mesh with `num_nodes` nodes.
    pub fn new(num_nodes: usize) -> Constraints {
        Constraints {
            values: vec![None; 2 * num_nodes],
        }
    }

    /// Prescribes `value` for `component` on every node of boundary (or node set) `name`.
    /// A DOF fixed twice keeps the last value.
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
                    return Err(SupportError::NotAxisAligned {
                        boundary: name.to_string(),
                    })
                }
            },
        };
        for v in nodes {
            for &c in comps {
                self.values[2 * v + c] = Some(value);
            }
        }
        Ok(())
    }

    /// Prescribes (or frees, with `None`) one DOF directly.
    pub fn set(&mut self, dof: usize, value: Option<f64>) {
        self.values[dof] = value;
    }

    /// Prescribed value of DOF `dof`, if any.
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

    /// Constrained DOFs and their values.
    pub fn fixed(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| (i, v)))
    }
}

/// 0 if boundary `name` is a straight line x = const, 1 if y = const, None otherwise.
fn axis_normal(mesh: &Mesh, name: &str) -> Option<usize> {
    let edges = mesh.boundary(name).ok()?;
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

/// Rigid-body modes of a body that neither its supports nor the given normal springs remove.
/// `springs` are (node, unit direction) pairs of springs of any positive stiffness. Returns a
/// human readable description of each free mode (empty if the body is held).
pub fn free_rigid_modes(
    mesh: &Mesh,
    constraints: &Constraints,
    springs: &[(usize, [f64; 2])],
) -> Vec<String> {
    let p = mesh.nodes();
    let n = p.len().max(1) as f64;
    let c = p
        .iter()
        .fold([0.0, 0.0], |s, x| [s[0] + x[0] / n, s[1] + x[1] / n]);
    let h = mesh.bounding_box_diameter().max(f64::MIN_POSITIVE);
    // Mode values at a node: tx, ty and a rotation scaled to unit size over the body.
    let mode = |v: usize| -> [[f64; 3]; 2] {
        let (dx, dy) = ((p[v][0] - c[0]) / h, (p[v][1] - c[1]) / h);
        [[1.0, 0.0, -dy], [0.0, 1.0, dx]]
    };
    let mut gram = Matrix3::<f64>::zeros();
    let mut add = |row: [f64; 3]| {
        for i in 0..3 {
            for j in 0..3 {
                gram[(i, j)] += row[i] * row[j];
            }
        }
    };
    for (dof, _) in constraints.fixed() {
        add(mode(dof / 2)[dof % 2]);
    }
    for &(v, dir) in springs {
        let m = mode(v);
        add([0, 1, 2].map(|k| dir[0] * m[0][k] + dir[1] * m[1][k]));
    }
    let scale = gram.trace().max(1.0);
    let eig = SymmetricEigen::new(gram);
    let names = ["translation in x", "translation in y", "rotation"];
    (0..3)
        .filter(|&k| eig.eigenvalues[k] <= 1e-10 * scale)
        .map(|k| {
            let v = eig.eigenvectors.column(k);
            let parts: Vec<&str> = (0..3)
                .filter(|&i| v[i].abs() > 0.3)
                .map(|i| names[i])
                .collect();
            parts.join(" + ")
        })
        .collect()
}
