//! Hertz contact between dissimilar materials at a stiff penalty (the hard case): the
//! shipped Hertz example with E_disc/E_block = 10 and 0.1, θE*/a = 1e-3, P2. Both sides' contact
//! half-widths are within 2 % of Hertz's closed form a = sqrt(4PR/(πE*)), as for identical
//! materials (`examples/hertz_contrast.rs` prints the whole table); and the same example on P1
//! meshes.

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

/// The same with P1 elements on both bodies (identical materials, θE*/a = 1e-2): the balanced
/// pair reads the faceted disc through the dual mortar coefficients, and both half-widths stay
/// within 2 % of Hertz.
#[test]
fn p1_meshes_match_hertz() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hertz.toml");
    let text = std::fs::read_to_string(file)
        .unwrap()
        .replace("order = \"p2\"", "order = \"p1\"");
    assert!(!text.contains("\"p2\""));
    let (state, errors) = case(&text, 1.0, 1e-2, 0.1).unwrap();
    println!("P1: {state}, half-widths {errors:?}");
    assert!(!state.contains("NOT"), "{state}");
    for (side, e) in errors.iter().enumerate() {
        assert!(e.abs() <= 0.02, "side {side}: {:+.2} %", 100.0 * e);
    }
}
