//! Hertz contact between dissimilar materials at a stiff penalty (the hard case): the
//! shipped Hertz example with E_disc/E_block = 10 and 0.1, θE*/a = 1e-3, P2. Both sides' contact
//! half-widths are within 2 % of Hertz's closed form a = sqrt(4PR/(πE*)), as for identical
//! materials (`examples/hertz_contrast.rs` prints the whole table).

use contactdd::hertz::case;

#[test]
fn dissimilar_materials_match_hertz_at_a_stiff_penalty() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hertz.toml");
    let text = std::fs::read_to_string(file).unwrap();
    for ratio in [10.0, 0.1] {
        let (state, errors) = case(&text, ratio, 1e-3, 0.1).unwrap();
        println!("E_disc/E_block = {ratio}: {state}, half-widths {errors:?}");
        assert!(!state.contains("NOT"), "{ratio}: {state}");
        for (side, e) in errors.iter().enumerate() {
            assert!(
                e.abs() <= 0.02,
                "ratio {ratio}, side {side}: {:+.2} %",
                100.0 * e
            );
        }
    }
}
