//! Coulomb and Tresca friction at a contact point (docs/friction.md): a pair's tangential law,
//! the state a frictional point carries from step to step, and the regularised return mapping
//! with the derivative that the semismooth Newton method uses.
//!
//! A carrier j of a frictional pair reads the tangential relative displacement
//!   g_j = u_α(x_j)·t_j − u_β(x′_j)·t_j,  t_j = ν_j turned by +90°,
//! through its tangential row (the same dual mortar coefficients as its gap row). Its tangential
//! traction is the projection of the trial value onto the friction disc:
//!   σ_t = proj_[−b, b] (λ_t − (g − g₀)/θ_t),
//! with b = μ p (Coulomb, p = −σ_n ≥ 0 the contact pressure) or b = the Tresca bound where the
//! point is closed, θ_t the tangential penalty, g₀ the tangential displacement at the end of the
//! last step and λ_t the traction there (or the augmented Lagrangian's estimate). The point
//! sticks where the trial value lies inside the disc and slips, opposing the slip, on its edge.

/// The tangential law of a contact pair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Friction {
    /// No friction (the default).
    #[default]
    None,
    /// Coulomb's law: |σ_t| ≤ μ |σ_n|.
    Coulomb {
        /// The friction coefficient μ ≥ 0.
        mu: f64,
    },
    /// Tresca's law: |σ_t| ≤ the bound wherever the point is in contact.
    Tresca {
        /// The largest tangential traction (a stress, ≥ 0).
        bound: f64,
    },
}

impl Friction {
    /// The law as the contact layer uses it: μ = 0 and a zero Tresca bound are frictionless, so
    /// that they give the frictionless answer to the bit.
    pub fn resolved(self) -> Friction {
        match self {
            Friction::Coulomb { mu: 0.0 } | Friction::Tresca { bound: 0.0 } => Friction::None,
            f => f,
        }
    }

    /// True for a law with friction.
    pub fn is_active(&self) -> bool {
        self.resolved() != Friction::None
    }

    /// What is wrong with the law's parameter, if anything.
    pub fn problem(&self) -> Option<String> {
        match *self {
            Friction::None => None,
            Friction::Coulomb { mu } if !(mu.is_finite() && mu >= 0.0) => Some(format!(
                "the friction coefficient mu must be finite and at least 0, got {mu}"
            )),
            Friction::Tresca { bound } if !(bound.is_finite() && bound >= 0.0) => Some(format!(
                "the Tresca bound must be finite and at least 0, got {bound}"
            )),
            _ => None,
        }
    }

    /// The slip bound b ≥ 0 for the contact pressure p = −σ_n (p > 0 where closed).
    pub fn bound(&self, p: f64) -> f64 {
        match *self {
            _ if p <= 0.0 => 0.0,
            Friction::None => 0.0,
            Friction::Coulomb { mu } => mu * p,
            Friction::Tresca { bound } => bound,
        }
    }
}

impl std::fmt::Display for Friction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Friction::None => f.write_str("frictionless"),
            Friction::Coulomb { mu } => write!(f, "Coulomb, mu = {mu}"),
            Friction::Tresca { bound } => write!(f, "Tresca, bound = {bound}"),
        }
    }
}

/// Where a frictional point is on the friction disc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Not in contact: no tangential traction.
    Open,
    /// Inside the disc: no slip (up to the penalty's elastic slip θ_t σ_t).
    Stick,
    /// On the edge of the disc: the traction is the bound, opposing the slip.
    Slip,
}

impl Status {
    /// The name in the outputs.
    pub fn name(self) -> &'static str {
        match self {
            Status::Open => "open",
            Status::Stick => "stick",
            Status::Slip => "slip",
        }
    }
}

/// The friction of one carrier point.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionPoint {
    /// The pair's law.
    pub law: Friction,
    /// The tangential row: g = Σ c u_k over the interface unknowns k (the point's own tangential
    /// unknown and its partner's unknowns).
    pub row: Vec<(usize, f64)>,
    /// The tangential penalty θ_t (the point's normal θ).
    pub theta: f64,
    /// λ_t: the tangential traction at the end of the last step, or the augmented Lagrangian's
    /// estimate.
    pub multiplier: f64,
    /// g₀: the tangential displacement at the end of the last step (0 from the unloaded state).
    pub reference: f64,
}

impl FrictionPoint {
    /// The trial traction λ_t − (g − g₀)/θ_t at the tangential displacement `g`.
    pub fn trial(&self, g: f64) -> f64 {
        self.multiplier - (g - self.reference) / self.theta
    }

    /// The tangential traction σ_t and the status at the tangential displacement `g` and the
    /// contact pressure p = −σ_n.
    pub fn traction(&self, g: f64, p: f64) -> (f64, Status) {
        if p <= 0.0 {
            return (0.0, Status::Open);
        }
        let (trial, b) = (self.trial(g), self.law.bound(p));
        if trial.abs() <= b {
            (trial, Status::Stick)
        } else {
            (b.copysign(trial), Status::Slip)
        }
    }

    /// dσ_t/dp on the slip edge (Coulomb: μ times the slip's sign; Tresca: 0).
    pub fn slip_slope(&self, g: f64) -> f64 {
        match self.law {
            Friction::Coulomb { mu } => mu.copysign(self.trial(g)),
            _ => 0.0,
        }
    }

    /// The tangential displacement g = Σ c u_k of the interface displacements `u`.
    pub fn slip_sum(&self, u: &[f64]) -> f64 {
        self.row.iter().map(|&(k, c)| c * u[k]).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(law: Friction) -> FrictionPoint {
        FrictionPoint {
            law,
            row: vec![(0, 1.0), (1, -1.0)],
            theta: 0.5,
            multiplier: 0.0,
            reference: 0.0,
        }
    }

    #[test]
    fn the_traction_lies_on_the_disc_and_opposes_the_slip() {
        let p = point(Friction::Coulomb { mu: 0.3 });
        // Inside: the elastic spring −g/θ_t.
        assert_eq!(p.traction(0.01, 1.0), (-0.02, Status::Stick));
        // Outside: the bound μ p with the sign opposite the slip.
        let (t, s) = p.traction(1.0, 2.0);
        assert_eq!(s, Status::Slip);
        assert!((t + 0.6).abs() < 1e-15);
        assert_eq!(p.traction(-1.0, 2.0).0, 0.6);
        // Open: nothing.
        assert_eq!(p.traction(1.0, 0.0), (0.0, Status::Open));
        let tresca = point(Friction::Tresca { bound: 0.25 });
        assert_eq!(tresca.traction(1.0, 7.0), (-0.25, Status::Slip));
        assert_eq!(tresca.slip_slope(1.0), 0.0);
        assert_eq!(p.slip_slope(1.0), -0.3);
    }

    #[test]
    fn zero_friction_is_frictionless_and_bad_parameters_are_named() {
        assert!(!Friction::Coulomb { mu: 0.0 }.is_active());
        assert!(Friction::Coulomb { mu: 0.1 }.is_active());
        assert!(Friction::Coulomb { mu: -0.1 }.problem().is_some());
        assert!(Friction::Coulomb { mu: f64::NAN }.problem().is_some());
        assert!(Friction::Tresca { bound: -1.0 }.problem().is_some());
        assert!(Friction::Tresca { bound: 2.0 }.problem().is_none());
    }
}
