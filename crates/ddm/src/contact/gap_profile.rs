//! Prescribed gap profiles, added to the geometric normal gap of a contact pair.

use contactdd_core::{Point, Vector};

/// The straight line a profile lies along: the contact coordinate of a point `p` is ξ = p · d, with
/// `d` the line's unit direction (the coordinate of `p`'s projection on the line through the
/// origin with direction `d`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Along {
    /// The x coordinate, d = (1, 0) (horizontal contact lines).
    #[default]
    X,
    /// The y coordinate, d = (0, 1) (vertical contact lines).
    Y,
    /// Along a direction vector `[dx, dy]` (any non-zero length; it is normalised).
    Direction(Vector),
    /// Along the direction at this angle in degrees, counter-clockwise from the x axis:
    /// d = (cos θ, sin θ).
    Angle(f64),
}

impl Along {
    /// The unit direction d, or `None` for a zero or non-finite direction or angle.
    pub fn unit(&self) -> Option<Vector> {
        let d = match *self {
            Along::X => [1.0, 0.0],
            Along::Y => [0.0, 1.0],
            Along::Direction(d) => d,
            Along::Angle(degrees) => {
                let (sin, cos) = degrees.to_radians().sin_cos();
                [cos, sin]
            }
        };
        let len = d[0].hypot(d[1]);
        (len.is_finite() && len > 0.0).then(|| [d[0] / len, d[1] / len])
    }

    /// The contact coordinate ξ = p · d of point `p` (NaN for an invalid direction, which
    /// [`Along::unit`] reports beforehand).
    pub fn coordinate(&self, p: Point) -> f64 {
        match (*self, self.unit()) {
            // Exactly the coordinate, with no rounding from a product with 1 and 0.
            (Along::X, _) => p[0],
            (Along::Y, _) => p[1],
            (_, Some(d)) => p[0] * d[0] + p[1] * d[1],
            (_, None) => f64::NAN,
        }
    }
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
                let xi = along.coordinate(p);
                let base = (1.0 - ((xi - centre) / b).powi(2)).max(0.0);
                r0 * base.powf(power)
            }
            GapProfile::Uniform { value } => value,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn notch(along: Along) -> GapProfile {
        GapProfile::Notch {
            r0: 0.05,
            b: 1.2,
            centre: 0.7,
            power: 1.5,
            along,
        }
    }

    /// Points spread over [-2, 2]², deterministic.
    fn points() -> Vec<Point> {
        (0..200)
            .map(|k| {
                let t = k as f64;
                [2.0 * (0.37 * t).sin(), 2.0 * (0.91 * t + 0.3).cos()]
            })
            .collect()
    }

    #[test]
    fn the_x_profile_rotated_by_90_degrees_is_the_y_profile() {
        for p in points() {
            let y = notch(Along::Y).at(p);
            for along in [Along::Angle(90.0), Along::Direction([0.0, 3.0])] {
                let rotated = notch(along).at(p);
                assert!((rotated - y).abs() < 1e-15, "{along:?} at {p:?}");
            }
        }
    }

    #[test]
    fn a_profile_along_a_line_is_the_x_profile_of_the_rotated_points() {
        // Rotating the points by θ carries the x profile onto the profile along angle θ.
        for degrees in [30.0, 135.0, -60.0] {
            let (s, c) = f64::to_radians(degrees).sin_cos();
            for p in points() {
                let q = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
                let want = notch(Along::X).at(p);
                for along in [Along::Angle(degrees), Along::Direction([2.0 * c, 2.0 * s])] {
                    let got = notch(along).at(q);
                    assert!((got - want).abs() < 1e-13, "{along:?}: {got} vs {want}");
                }
            }
        }
    }

    #[test]
    fn zero_and_non_finite_directions_have_no_unit() {
        for along in [
            Along::Direction([0.0, 0.0]),
            Along::Direction([f64::NAN, 1.0]),
            Along::Angle(f64::INFINITY),
        ] {
            assert_eq!(along.unit(), None, "{along:?}");
        }
    }
}
