//! The formulation of a contact pair in one value: its normal law (the penalty θ), how it
//! enforces non-penetration, how its pressure loads the two bodies, and the inner penalty of its
//! points. The interface builder derives one [`Formulation`] per pair
//! ([`crate::model::ContactPair::formulation`]), resolves it against the built points, and the
//! contact layer reads it there.

use contactdd_core::ElasticBody;

use super::friction::Friction;

/// The rod model's factor c of the inner penalty of an augmented balanced pair's point, with the
/// point's share of its boundary as h: the spring w/θ is then E*/c (E* = 1/(1/E*_α + 1/E*_β)),
/// about 1/c times the stiffness that the bodies oppose to one node, so each multiplier update
/// leaves about c/(1 + c) of the error (`docs/augmented-lagrangian.md`). 0.05 is the paper's
/// factor. The pair's own θ is used where it is stiffer.
pub const AUGMENTED_C: f64 = 0.05;

/// How the penalty parameter θ of a contact pair is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Penalty {
    /// θ given directly (length / stress units).
    Theta(f64),
    /// The rod model of docs/method.md §2: θ = c · h · (1/E*_α + 1/E*_β), which for equal materials is
    /// θ = 2 c h (1 − ν²)/E in plane strain (2 c h / E in plane stress). `c` is dimensionless, `h` a
    /// characteristic body height.
    RodModel {
        /// Dimensionless factor c (the benchmark uses 0.05).
        c: f64,
        /// Characteristic height h.
        h: f64,
    },
}

impl Penalty {
    /// θ for a pair of materials.
    pub fn theta(&self, a: &ElasticBody, b: &ElasticBody) -> f64 {
        let modulus = |body: &ElasticBody| body.material.plane_modulus(body.plane);
        match *self {
            Penalty::Theta(t) => t,
            Penalty::RodModel { c, h } => c * h * (1.0 / modulus(a) + 1.0 / modulus(b)),
        }
    }
}

/// The inner penalty of the augmented balanced pairs (`docs/augmented-lagrangian.md`, "Speed").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InnerPenalty {
    /// Every point's θ at most the rod model's with c = [`AUGMENTED_C`] and h the point's share
    /// of its boundary: each multiplier update then contracts by about the same factor whatever
    /// the pair's θ and the mesh. For the interface Newton method, whose count does not depend
    /// on θ.
    #[default]
    Stiffened,
    /// The pair's θ as given: for the Robin sweeps, whose count grows as θ stiffens.
    AsGiven,
}

/// How a contact pair enforces non-penetration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Enforcement {
    /// The paper's penalty formulation: the contact pressure is (s − d)⁺/θ, and the answer
    /// depends on θ (the bodies interpenetrate by θ·p).
    #[default]
    Penalty,
    /// The augmented Lagrangian (Uzawa) loop of [`crate::augmented`] around the penalty solves:
    /// converges to the exact unilateral (Signorini) contact for any fixed θ.
    Augmented,
}

impl std::fmt::Display for Enforcement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Enforcement::Penalty => "penalty",
            Enforcement::Augmented => "augmented",
        })
    }
}

/// How a contact pair's pressure loads its two bodies (docs/method.md §4, "Which normal the gap
/// uses").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Forces {
    /// Both sides read the gap along the normals of the flatter side, whose pressure loads both
    /// bodies with equal and opposite forces (dual mortar coefficients): the pair's forces
    /// balance on non-matching and curved zones. A pair whose sides match node for node on a
    /// flat zone is the same discrete problem as `OwnSide` and keeps its arithmetic.
    #[default]
    Balanced,
    /// The paper's formulation: each side is loaded only by its own points' pressure along its own
    /// normal, with the partner's displacement read along the partner's normal.
    OwnSide,
}

impl std::fmt::Display for Forces {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Forces::Balanced => "balanced",
            Forces::OwnSide => "own-side",
        })
    }
}

/// The formulation of one contact pair: what the contact points are built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Formulation {
    /// The normal law's penalty θ of the pair (positive and finite): the contact pressure is
    /// (d − θλ − s)⁻/θ.
    pub theta: f64,
    /// Penalty or augmented Lagrangian.
    pub enforcement: Enforcement,
    /// How the pressure loads the two bodies. The interface holds the resolved value: a balanced
    /// pair whose sides match node for node is the own-side formulation.
    pub forces: Forces,
    /// The inner penalty of the pair's points: [`InnerPenalty::Stiffened`] only for an
    /// augmented balanced pair whose solve asks for it, [`InnerPenalty::AsGiven`] otherwise.
    pub inner: InnerPenalty,
    /// The tangential law (resolved: μ = 0 is [`Friction::None`]). A frictional pair keeps its
    /// balanced forces even where its sides match node for node.
    pub friction: Friction,
}

impl Formulation {
    /// The formulation of a pair with penalty θ `theta`, enforcement and forces as given, under
    /// the solve's inner penalty `inner` of the augmented balanced pairs.
    pub fn new(theta: f64, enforcement: Enforcement, forces: Forces, inner: InnerPenalty) -> Self {
        let stiffened = inner == InnerPenalty::Stiffened
            && enforcement == Enforcement::Augmented
            && forces == Forces::Balanced;
        Formulation {
            theta,
            enforcement,
            forces,
            inner: if stiffened {
                InnerPenalty::Stiffened
            } else {
                InnerPenalty::AsGiven
            },
            friction: Friction::None,
        }
    }

    /// The same formulation with the tangential law `friction` (resolved).
    pub fn with_friction(self, friction: Friction) -> Self {
        Formulation {
            friction: friction.resolved(),
            ..self
        }
    }

    /// The θ of a contact point of weight `weight` of body `a`, facing body `b`.
    pub fn point_theta(&self, weight: f64, a: &ElasticBody, b: &ElasticBody) -> f64 {
        // Own-side pairs keep θ: on non-matching meshes their two sides' multipliers are tied
        // only through the penalty, and a stiffer one lets them drift apart (the non-matching
        // notch then stalls at 5e−5). A weightless point (a P2 vertex on a coarse side, say)
        // keeps θ too: it carries nothing, its spring stays 0.
        if self.inner == InnerPenalty::Stiffened && weight > 0.0 {
            self.theta.min(
                Penalty::RodModel {
                    c: AUGMENTED_C,
                    h: weight,
                }
                .theta(a, b),
            )
        } else {
            self.theta
        }
    }
}
