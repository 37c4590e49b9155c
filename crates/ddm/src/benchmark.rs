//! An example problem built in code: the paper's two-body notch benchmark (docs/method.md §5), the
//! problem of `examples/notch.toml` without reading a file (a test in `contactdd-io` checks that
//! both give the same model and solution). Tests, benches, `examples/large_two_bodies.rs` and the
//! Python module's `notch_benchmark()` use it; it also shows how to build a [`Model`] by hand.
//!
//! Two blocks `L` × `H` = 4 × 1 (P1 or P2 rectangles, `nx` × `ny` cells each; the upper mesh is
//! the mirror image of the lower one so that the contact nodes match) are pressed together by
//! q = 0.01 E on their outer faces; their right edges are symmetry lines (u_x = 0), nothing else
//! holds them. Their common face has a notch of depth 0.05 at x = 4, the gap profile
//! d(x) = 0.05 · {[1 − (x − 4)²]⁺}^{3/2}; the penalty is the rod model with c = 0.05, h = `H`.
//!
//! ```text
//!          q ↓ ↓ ↓ ↓ ↓ ↓ ↓ ↓
//!   y = 2  +----- top -----+
//!          |     upper     | right: u_x = 0
//!   y = 1  +--- bottom ---.+  contact "notch": lower.top / upper.bottom
//!          +---- top -----'+
//!          |     lower     | right: u_x = 0
//!   y = 0  +--- bottom ----+
//!          q ↑ ↑ ↑ ↑ ↑ ↑ ↑ ↑
//!        x = 0           x = 4
//! ```
//!
//! ```
//! use contactdd_ddm::benchmark::Notch;
//!
//! let model = Notch { nx: 8, ny: 4, ..Notch::default() }.model()?;
//! assert_eq!(model.bodies.len(), 2);
//! # Ok::<(), contactdd_ddm::SetupError>(())
//! ```

use contactdd_core::{
    BodyError, Component, Constraints, Diagonal, ElasticBody, Load, Material, MeshError, Order,
    Plane, Rectangle,
};

use crate::contact::formulation::{Enforcement, Penalty};
use crate::contact::gap_profile::{Along, GapProfile};
use crate::error::SetupError;
use crate::model::{ContactPair, Model};

/// Parameters of the notch benchmark (defaults: the paper's values).
#[derive(Clone, Debug, PartialEq)]
pub struct Notch {
    /// Cells in x per body (32).
    pub nx: usize,
    /// Cells in y per body (16).
    pub ny: usize,
    /// Element order (P1).
    pub order: Order,
    /// Young's modulus E (any value: displacements do not depend on it since q = 0.01 E).
    pub young: f64,
    /// Poisson's ratio (0.3).
    pub poisson: f64,
    /// Rod-model penalty factor c (0.05).
    pub c: f64,
}

impl Default for Notch {
    fn default() -> Notch {
        Notch {
            nx: 32,
            ny: 16,
            order: Order::P1,
            young: 2.1e5,
            poisson: 0.3,
            c: 0.05,
        }
    }
}

/// Body height h and length l (cm).
pub const H: f64 = 1.0;
/// Body length l (cm).
pub const L: f64 = 4.0;

impl Notch {
    /// The applied pressure q = 0.01 E.
    pub fn pressure(&self) -> f64 {
        0.01 * self.young
    }

    /// Builds the model.
    pub fn model(&self) -> Result<Model, SetupError> {
        let material = Material::new(self.young, self.poisson)
            .map_err(|e| SetupError::Factor(BodyError::Material(e)))?;
        let q = self.pressure();
        let mut bodies = Vec::new();
        for (name, y0, mirror, loaded) in
            [("lower", 0.0, false, "bottom"), ("upper", H, true, "top")]
        {
            let mesh = Rectangle {
                origin: [0.0, y0],
                corner: [L, y0 + H],
                nx: self.nx,
                ny: self.ny,
                diagonal: Diagonal::Right,
                mirror,
                order: self.order,
            }
            .mesh()
            .map_err(|source| mesh_error(name, source))?;
            let mut constraints = Constraints::new(mesh.num_nodes());
            constraints
                .fix(&mesh, "right", Component::X, 0.0)
                .map_err(|source| SetupError::Support {
                    body: name.into(),
                    key: String::new(),
                    source,
                })?;
            let load = contactdd_core::loads::load_vector(
                &mesh,
                &[Load::Pressure {
                    boundary: loaded.into(),
                    value: q,
                }],
            )
            .map_err(|source| mesh_error(name, source))?;
            bodies.push(ElasticBody {
                name: name.into(),
                mesh,
                material,
                plane: Plane::Strain,
                constraints,
                load,
            });
        }
        Ok(Model {
            name: "notch".into(),
            plane: Plane::Strain,
            bodies,
            pairs: vec![ContactPair {
                name: "notch".into(),
                bodies: [0, 1],
                boundaries: ["top".into(), "bottom".into()],
                penalty: Penalty::RodModel { c: self.c, h: H },
                profile: Some(GapProfile::Notch {
                    r0: 0.05,
                    b: 1.0,
                    centre: L,
                    power: 1.5,
                    along: Along::X,
                }),
                enforcement: Enforcement::Penalty,
                forces: Default::default(),
                friction: Default::default(),
            }],
            remote: Vec::new(),
        })
    }
}

fn mesh_error(body: &str, source: MeshError) -> SetupError {
    SetupError::Mesh {
        body: body.into(),
        key: String::new(),
        source,
    }
}
