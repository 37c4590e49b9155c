//! Friction in space: the tangential traction is a vector of the tangent plane, bounded by the
//! disc of radius b (Coulomb: b = μ p; Tresca: the given bound). The return mapping projects the
//! trial traction onto the disc; its derivative is what a semismooth Newton step linearises.

/// Whether a point sticks (the trial traction is inside the disc) or slips (on its edge).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiscStatus {
    /// |trial| ≤ b: the traction is the trial one.
    Stick,
    /// |trial| > b: the traction is b times the trial's direction.
    Slip,
}

/// The traction of the `trial` traction on the disc of radius `bound` (≥ 0), with its status.
pub fn project(trial: [f64; 2], bound: f64) -> ([f64; 2], DiscStatus) {
    let size = trial[0].hypot(trial[1]);
    if size <= bound {
        (trial, DiscStatus::Stick)
    } else {
        let scale = bound / size;
        (trial.map(|t| scale * t), DiscStatus::Slip)
    }
}

/// The derivatives of [`project`]: with respect to the trial traction (a 2 × 2 matrix: the
/// identity where it sticks, (b/|t|)(I − t̂ t̂ᵀ) where it slips) and with respect to the bound
/// (zero where it sticks, t̂ where it slips).
pub fn derivative(trial: [f64; 2], bound: f64) -> ([[f64; 2]; 2], [f64; 2]) {
    let size = trial[0].hypot(trial[1]);
    if size <= bound {
        return ([[1.0, 0.0], [0.0, 1.0]], [0.0; 2]);
    }
    let d = trial.map(|t| t / size);
    let scale = bound / size;
    let m = [
        [scale * (1.0 - d[0] * d[0]), -scale * d[0] * d[1]],
        [-scale * d[1] * d[0], scale * (1.0 - d[1] * d[1])],
    ];
    (m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_projection_stays_in_the_disc_and_keeps_the_direction() {
        let (t, s) = project([0.3, -0.4], 1.0);
        assert_eq!((t, s), ([0.3, -0.4], DiscStatus::Stick));
        let (t, s) = project([3.0, -4.0], 2.0);
        assert_eq!(s, DiscStatus::Slip);
        assert!((t[0] - 1.2).abs() < 1e-15 && (t[1] + 1.6).abs() < 1e-15);
        let (t, _) = project([1.0, 1.0], 0.0);
        assert_eq!(t, [0.0, 0.0]);
    }

    /// The derivative against central differences, inside and outside the disc.
    #[test]
    fn the_derivative_is_that_of_the_projection() {
        let h = 1e-6;
        for (trial, bound) in [([0.2, 0.1], 1.0), ([2.0, -1.5], 0.7), ([-0.3, 4.0], 2.5)] {
            let (m, db) = derivative(trial, bound);
            for c in 0..2 {
                let (mut plus, mut minus) = (trial, trial);
                plus[c] += h;
                minus[c] -= h;
                let (p, _) = project(plus, bound);
                let (q, _) = project(minus, bound);
                for r in 0..2 {
                    let fd = (p[r] - q[r]) / (2.0 * h);
                    assert!((fd - m[r][c]).abs() < 1e-8, "{trial:?}: d{r}/d{c}");
                }
            }
            let (p, _) = project(trial, bound + h);
            let (q, _) = project(trial, bound - h);
            for r in 0..2 {
                assert!(((p[r] - q[r]) / (2.0 * h) - db[r]).abs() < 1e-8);
            }
        }
    }
}
