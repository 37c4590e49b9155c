//! The five choices of the Robin coefficient φ^k (docs/method.md §3).

use std::fmt;
use std::str::FromStr;

use crate::contact::Status;

/// A domain decomposition method, named as in docs/method.md.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// φ = 0: parallel Neumann scheme (a floating body is singular).
    Neumann,
    /// φ = 1 on the whole contact zone.
    Robin,
    /// φ = χ(s^k): 1 where the bodies penetrate, else 0 (semismooth Newton).
    ActiveSet,
    /// Two-point: chord divided difference between s^{k−1} and s^k.
    NewtonChord,
    /// Two-point: Kurchatov divided difference between s^{k−1} and 2 s^k − s^{k−1}.
    NewtonKurchatov,
}

impl Method {
    /// All methods, in the order of docs/method.md.
    pub const ALL: [Method; 5] = [
        Method::Neumann,
        Method::Robin,
        Method::ActiveSet,
        Method::NewtonChord,
        Method::NewtonKurchatov,
    ];

    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Neumann => "neumann",
            Method::Robin => "robin",
            Method::ActiveSet => "active-set",
            Method::NewtonChord => "newton-chord",
            Method::NewtonKurchatov => "newton-kurchatov",
        }
    }

    /// φ^k at one contact point with initial gap `d`, sums `s` = s^k and `s_prev` = s^{k−1}.
    pub fn phi(self, d: f64, s: f64, s_prev: f64) -> f64 {
        let chi = if d - s < 0.0 { 1.0 } else { 0.0 };
        // g(s) = (d − s)⁻ = min(0, d − s); the two-point coefficients are divided differences of −g.
        let g = |s: f64| (d - s).min(0.0);
        let tiny = |ds: f64| ds.abs() <= 1e-12 * s.abs().max(d.abs()).max(f64::MIN_POSITIVE);
        match self {
            Method::Neumann => 0.0,
            Method::Robin => 1.0,
            Method::ActiveSet => chi,
            Method::NewtonChord => {
                let ds = s_prev - s;
                if tiny(ds) {
                    chi
                } else {
                    (-(g(s_prev) - g(s)) / ds).clamp(0.0, 1.0)
                }
            }
            Method::NewtonKurchatov => {
                let ds = s - s_prev;
                if tiny(ds) {
                    chi
                } else {
                    (-(g(2.0 * s - s_prev) - g(s_prev)) / (2.0 * ds)).clamp(0.0, 1.0)
                }
            }
        }
    }
}

impl Method {
    /// The tangential Robin coefficient φ_t of a frictional point with status `status` (the
    /// tangential law's slope in units of the tangential penalty, as φ is the normal law's):
    /// `neumann` 0, `robin` 1, and the other methods the slope of the law's branch, 1 where the
    /// point sticks and 0 where it slips (the bound does not move with the slip) or is open.
    pub fn phi_tangential(self, status: Status) -> f64 {
        match self {
            Method::Neumann => 0.0,
            Method::Robin => 1.0,
            _ if status == Status::Stick => 1.0,
            _ => 0.0,
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown method name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown method '{0}' (expected one of: neumann, robin, active-set, newton-chord, newton-kurchatov)")]
pub struct UnknownMethod(pub String);

impl FromStr for Method {
    type Err = UnknownMethod;

    fn from_str(s: &str) -> Result<Method, UnknownMethod> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownMethod(s.to_string()))
    }
}
