//! The one float format of every text file contactdd writes (CSV, VTU): the shortest text that
//! reads back to the same value, with an exponent only for very small or large magnitudes, and
//! `inf`, `-inf`, `NaN` for non-finite values (which Python's `float()`, numpy and pandas read).

use std::fmt::Write as _;

/// Appends `x` in the shortest text that reads back to the same value.
pub fn push_f64(out: &mut String, x: f64) {
    let magnitude = x.abs();
    // `Display` never uses an exponent, which is long for very small or large values.
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&magnitude) {
        let _ = write!(out, "{x}");
    } else {
        let _ = write!(out, "{x:e}");
    }
}

/// `x` as [`push_f64`] writes it.
pub fn format_f64(x: f64) -> String {
    let mut out = String::new();
    push_f64(&mut out, x);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip() {
        for x in [0.0, -0.0, 1.0, 0.1, -2.5e-7, 1e300, 123456.789, 5e-324] {
            let text = format_f64(x);
            assert_eq!(text.parse::<f64>(), Ok(x), "{text}");
        }
    }

    #[test]
    fn exponents_and_non_finite_values() {
        assert_eq!(format_f64(0.25), "0.25");
        assert_eq!(format_f64(-2.5e-7), "-2.5e-7");
        assert_eq!(format_f64(1e15), "1e15");
        assert_eq!(format_f64(f64::INFINITY), "inf");
        assert_eq!(format_f64(f64::NEG_INFINITY), "-inf");
        assert_eq!(format_f64(f64::NAN), "NaN");
    }
}
