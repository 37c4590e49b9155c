//! Isotropic linear elastic material in plane strain or plane stress.
//!
//! Strains and stresses are engineering 3-vectors `(ε_xx, ε_yy, γ_xy)` and `(σ_xx, σ_yy, σ_xy)`;
//! Hooke's law is `σ = D ε`. Plane stress replaces λ by `2λμ/(λ + 2μ)`.

use crate::error::MaterialError;

/// The 2D idealisation of a thick or thin body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Plane {
    /// ε_zz = 0 (thick bodies).
    Strain,
    /// σ_zz = 0 (thin plates).
    Stress,
}

/// Young's modulus and Poisson's ratio, checked on construction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    young: f64,
    poisson: f64,
}

impl Material {
    /// Validates `E > 0` (finite) and `ν ∈ (−1, 0.5)`.
    pub fn new(young: f64, poisson: f64) -> Result<Material, MaterialError> {
        if !(young.is_finite() && young > 0.0) {
            return Err(MaterialError::YoungModulus(young));
        }
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(MaterialError::PoissonRatio(poisson));
        }
        Ok(Material { young, poisson })
    }

    /// Young's modulus E.
    pub fn young(&self) -> f64 {
        self.young
    }

    /// Poisson's ratio ν.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// Lamé parameters (λ, μ) of the 2D model (plane stress uses the reduced λ).
    pub fn lame(&self, plane: Plane) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        match plane {
            Plane::Strain => (lambda, mu),
            Plane::Stress => (2.0 * lambda * mu / (lambda + 2.0 * mu), mu),
        }
    }

    /// The elasticity matrix D with `σ = D ε` in engineering notation.
    pub fn elasticity(&self, plane: Plane) -> [[f64; 3]; 3] {
        let (l, m) = self.lame(plane);
        [[l + 2.0 * m, l, 0.0], [l, l + 2.0 * m, 0.0], [0.0, 0.0, m]]
    }

    /// The out-of-plane stress σ_zz (non-zero in plane strain only).
    pub fn sigma_zz(&self, plane: Plane, sxx: f64, syy: f64) -> f64 {
        match plane {
            Plane::Strain => self.poisson * (sxx + syy),
            Plane::Stress => 0.0,
        }
    }

    /// `E* = E / (1 − ν²)` in plane strain, `E` in plane stress: the modulus of the rod model
    /// and of Hertz's formulas.
    pub fn plane_modulus(&self, plane: Plane) -> f64 {
        match plane {
            Plane::Strain => self.young / (1.0 - self.poisson * self.poisson),
            Plane::Stress => self.young,
        }
    }
}

/// von Mises equivalent stress from the in-plane components and σ_zz.
pub fn von_mises(sxx: f64, syy: f64, sxy: f64, szz: f64) -> f64 {
    (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2)) + 3.0 * sxy * sxy)
        .sqrt()
}
