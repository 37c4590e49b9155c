//! Hertz contact between dissimilar materials: the shipped Hertz example (a half disc pressed on
//! a block, curved non-matching P2 meshes) with E_disc / E_block = 1, 10 and 0.1, at the penalties
//! θE*/a = 1e-2 and 1e-3 and at two loads, scaled with E* so that Hertz's half-width
//! a = sqrt(4PR/(πE*)) is R/10 or R/20 whatever the materials. Prints each side's half-width,
//! measured where the gap d − s changes sign, against a.
//!
//! With the balanced pairs (the default), every side stays within 2.5 % of Hertz whatever the
//! contrast, and within 1.4 % at θE*/a = 1e-3 (`tests/hertz_contrast.rs` pins the contrasts
//! there to 2 %); with
//! `forces = "own-side"` the soft curved body's tangential displacement leaks into the gap (docs/method.md
//! §4, "Which normal the gap uses, and balanced forces").
//!
//! Run: `cargo run --release --example hertz_contrast`

use contactdd::hertz::case;

fn main() -> Result<(), String> {
    let text = std::fs::read_to_string("examples/hertz.toml").map_err(|e| e.to_string())?;
    println!("E_disc/E_block  a/R   θE*/a  Newton          disc side  block side");
    for (a_over_r, stiffness) in [(0.1, 1e-2), (0.05, 1e-2), (0.1, 1e-3)] {
        for ratio in [1.0, 10.0, 0.1] {
            let (state, e) = case(&text, ratio, stiffness, a_over_r)?;
            println!(
                "{ratio:<15} {a_over_r:<5} {stiffness:<6e} {state:<15} {:>+9.2}%  {:>+9.2}%",
                100.0 * e[0],
                100.0 * e[1]
            );
        }
    }
    println!("(half-width / Hertz − 1; a = sqrt(4PR/(πE*)))");
    Ok(())
}
