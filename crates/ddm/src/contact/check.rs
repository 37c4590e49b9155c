//! Plausibility checks of the contact geometry, run once the contact points are built: a pair
//! whose bodies start deeply inside each other, or that can never touch, is almost always a
//! mistake in the problem file that the solver would otherwise turn into a confident answer.
//!
//! Every criterion is relative to the size of the bodies, so scaling all lengths changes nothing.
//! A body's *thickness* is the shorter side of its bounding box.
//!
//! - **Deep overlap (error).** The largest initial overlap of a pair (−d at a point with a partner)
//!   exceeds half the thickness of the thinner body. Two boundaries that face away from each
//!   other (`bottom` of the upper body paired with `top` of the lower one) project through both
//!   bodies and show an overlap of about the sum of their thicknesses; two bodies placed at the
//!   same position overlap by a whole thickness. The penalty would push the bodies apart with
//!   strains of order one, far outside linear elasticity, so no answer is meaningful: refused.
//! - **Overlap (warning).** An overlap above 1 % of the thinner body's thickness: the penalty
//!   strains the bodies by about that fraction. That may be an intended interference fit, so the
//!   solve goes on, but the user is told.
//! - **No partner (warning).** Not a single point of either side of the pair faces the other side
//!   (boundaries that coincide with normals pointing the same way, or that lie side by side): the
//!   pair can never carry a force.

use std::fmt;

use contactdd_core::Point;

use super::points::{ContactPoint, Interface};
use crate::error::SetupError;
use crate::model::Model;

/// Overlap, as a fraction of the thinner body's thickness, beyond which a pair is refused.
pub const ERROR_FRACTION: f64 = 0.5;

/// Overlap, as a fraction of the thinner body's thickness, beyond which a pair gets a warning.
pub const WARNING_FRACTION: f64 = 0.01;

/// One finding about the contact geometry of a pair.
#[derive(Clone, Debug, PartialEq)]
pub enum Finding {
    /// The largest initial overlap of a pair, when it exceeds [`WARNING_FRACTION`] of the
    /// thinner body's thickness (an error beyond [`ERROR_FRACTION`]).
    Overlap {
        /// Pair name.
        pair: String,
        /// The body whose contact point overlaps most.
        body: String,
        /// That contact point.
        at: Point,
        /// The overlap there (−gap, positive).
        overlap: f64,
        /// The thickness of the thinner body of the pair.
        thickness: f64,
    },
    /// No contact point of the pair faces the other side.
    NoPartner {
        /// Pair name.
        pair: String,
    },
}

impl Finding {
    /// True if the problem must be refused, false for a warning.
    pub fn is_error(&self) -> bool {
        match self {
            Finding::Overlap {
                overlap, thickness, ..
            } => *overlap > ERROR_FRACTION * thickness,
            Finding::NoPartner { .. } => false,
        }
    }

    /// The pair the finding is about.
    pub fn pair(&self) -> &str {
        match self {
            Finding::Overlap { pair, .. } | Finding::NoPartner { pair } => pair,
        }
    }

    /// The finding without the pair's name.
    fn message(&self) -> String {
        match self {
            Finding::Overlap {
                body,
                at,
                overlap,
                thickness,
                ..
            } => {
                let share = 100.0 * overlap / thickness;
                let cause = if self.is_error() {
                    "do the paired boundaries face away from each other, or do the bodies sit on \
                     top of each other?"
                } else {
                    "the penalty strains the bodies by about that much"
                };
                format!(
                    "the bodies start overlapping by {overlap:.4e} at ({:.4e}, {:.4e}) on \
                     body '{body}', {share:.3}% of the thinner body's thickness {thickness:.4e}: \
                     {cause}",
                    at[0], at[1]
                )
            }
            Finding::NoPartner { .. } => "no contact point faces the other body (do the \
                                          boundaries' outward normals point the same way?): the \
                                          pair can never carry a force"
                .to_string(),
        }
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "contact pair '{}': {}", self.pair(), self.message())
    }
}

/// The findings about every pair of `model`, whose contact points are `interface`.
pub fn check(model: &Model, interface: &Interface) -> Vec<Finding> {
    let mut findings = Vec::new();
    // Each pair's points, in one pass over all of them.
    let mut of_pair: Vec<Vec<&ContactPoint>> = vec![Vec::new(); model.pairs.len()];
    for q in &interface.points {
        if let Some(list) = of_pair.get_mut(q.pair) {
            list.push(q);
        }
    }
    for (p, pair) in model.pairs.iter().enumerate() {
        let Some(worst) = of_pair[p]
            .iter()
            .filter(|q| q.has_partner())
            .max_by(|a, b| (-a.gap).total_cmp(&-b.gap))
        else {
            findings.push(Finding::NoPartner {
                pair: pair.name.clone(),
            });
            continue;
        };
        let thickness = pair
            .bodies
            .iter()
            .map(|&b| {
                let (lo, hi) = model.bounds(b);
                (hi[0] - lo[0]).min(hi[1] - lo[1])
            })
            .fold(f64::INFINITY, f64::min);
        let overlap = -worst.gap;
        if overlap > WARNING_FRACTION * thickness {
            let body = &model.bodies[worst.body];
            findings.push(Finding::Overlap {
                pair: pair.name.clone(),
                body: body.name.clone(),
                at: model.position(worst.body, worst.node),
                overlap,
                thickness,
            });
        }
    }
    findings
}

/// The first error among `findings`, as a setup error.
pub fn refuse(findings: &[Finding]) -> Result<(), SetupError> {
    match findings.iter().find(|f| f.is_error()) {
        Some(f) => Err(SetupError::Pair {
            pair: f.pair().to_string(),
            message: f.message(),
        }),
        None => Ok(()),
    }
}
