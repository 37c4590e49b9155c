//! Prescribed gap profiles, added to the geometric normal gap of a contact pair.

use contactdd_core::Point;

/// Which coordinate of a contact node a profile is a function of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Along {
    /// The x coordinate (horizontal contact lines).
    #[default]
    X,
    /// The y coordinate (vertical contact lines).
    Y,
}

/// A prescribed initial gap profile d_p(ξ) of the contact coordinate ξ.
#[derive(Clone, Debug, PartialEq)]
pub enum GapProfile {
    /// The paper's notch: d_p(ξ) = r0 · {[1 − ((ξ − centre)/b)²]⁺}^power.
    Notch {
        /// Depth r0.
        r0: f64,
        /// Half-width b.
        b: f64,
        /// Centre ξ_c.
        centre: f64,
        /// Exponent (3/2 in the benchmark).
        power: f64,
        /// Contact coordinate.
        along: Along,
    },
    /// A constant gap added everywhere.
    Uniform {
        /// Added gap.
        value: f64,
    },
}

impl GapProfile {
    /// The profile's value at point `p`.
    pub fn at(&self, p: Point) -> f64 {
        match *self {
            GapProfile::Notch {
                r0,
                b,
                centre,
                power,
                along,
            } => {
                let xi = match along {
                    Along::X => p[0],
                    Along::Y => p[1],
                };
                let base = (1.0 - ((xi - centre) / b).powi(2)).max(0.0);
                r0 * base.powf(power)
            }
            GapProfile::Uniform { value } => value,
        }
    }
}
