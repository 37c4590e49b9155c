//! Hostile names in a problem file: names of a megabyte or with terminal escapes are refused with
//! the name shown escaped and cut, names that would give the same `steps.csv` column or plot file
//! are refused naming both, and ordinary names load as before.

use std::path::Path;

use contactdd_io::load_str;

/// Two blocks pressed together; `BODY`, `MATERIAL`, `BOUNDARY` and `TAIL` are replaced.
const TEMPLATE: &str = r#"
plane = "strain"

[materials."MATERIAL"]
young = 1000.0
poisson = 0.3

[[bodies]]
name = "BODY"
material = "MATERIAL"
mesh = { kind = "rectangle", x = [0.0, 2.0], y = [0.0, 1.0], nx = 4, ny = 2 }
supports = [{ boundary = "BOUNDARY", component = "both" }]

[[bodies]]
name = "upper"
material = "MATERIAL"
mesh = { kind = "rectangle", x = [0.0, 2.0], y = [1.0, 2.0], nx = 4, ny = 2 }
supports = [{ boundary = "left", component = "x" }]
loads = [{ kind = "pressure", boundary = "top", value = 10.0 }]

[[contact]]
bodies = ["BODY", "upper"]
boundaries = ["top", "bottom"]
penalty = { c = 0.05, h = 1.0 }
TAIL
"#;

fn problem(body: &str, material: &str, boundary: &str, tail: &str) -> String {
    TEMPLATE
        .replace("BODY", body)
        .replace("MATERIAL", material)
        .replace("BOUNDARY", boundary)
        .replace("TAIL", tail)
}

fn error_of(text: &str) -> String {
    match load_str(text, "bad.toml", Path::new(".")) {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// A message that shows a hostile name safely: short, no raw control character.
fn assert_safe(message: &str) {
    assert!(
        message.len() < 600,
        "{} bytes: {}…",
        message.len(),
        &message[..300]
    );
    assert!(
        !message.chars().any(|c| c.is_control() && c != '\n'),
        "{message:?}"
    );
}

#[test]
fn ordinary_names_load() {
    let loaded = load_str(
        &problem("lower", "steel", "bottom", ""),
        "ok.toml",
        Path::new("."),
    )
    .expect("valid");
    assert_eq!(loaded.model.bodies[0].name, "lower");
}

#[test]
fn megabyte_names_are_refused_with_a_short_message() {
    let huge = "n".repeat(1 << 20);
    for (text, key) in [
        (problem(&huge, "steel", "bottom", ""), "bodies[0].name"),
        (problem("lower", &huge, "bottom", ""), "materials"),
        (
            problem("lower", "steel", &huge, ""),
            "bodies[0].supports[0].boundary",
        ),
    ] {
        let message = error_of(&text);
        assert_safe(&message);
        for part in [key, "1048576 bytes long", "at most 256", "…(1048576 bytes)"] {
            assert!(message.contains(part), "{part} missing: {message}");
        }
    }
    // 256 bytes are accepted.
    let most = "m".repeat(256);
    load_str(
        &problem("lower", &most, "bottom", ""),
        "ok.toml",
        Path::new("."),
    )
    .expect("256");
}

#[test]
fn control_characters_in_names_are_refused_and_escaped() {
    // TOML's \u001b and \u0007: an escape sequence and a bell.
    for (text, key) in [
        (
            problem("low\\u001b[2Jer", "steel", "bottom", ""),
            "bodies[0].name",
        ),
        (problem("lower", "st\\u0007eel", "bottom", ""), "materials"),
        (
            problem("lower", "steel", "bot\\u202etom", ""),
            "bodies[0].supports[0].boundary",
        ),
    ] {
        let message = error_of(&text);
        assert_safe(&message);
        assert!(message.contains(key), "{message}");
        assert!(
            message.contains("\\u{1b}")
                || message.contains("\\u{7}")
                || message.contains("\\u{202e}"),
            "{message}"
        );
        assert!(message.contains("printable text"), "{message}");
    }
}

#[test]
fn an_unknown_boundary_is_named_as_given() {
    // A valid name that is merely unknown is echoed as given.
    let message = error_of(&problem("lower", "steel", "rigth", ""));
    assert!(message.contains("no boundary named 'rigth'"), "{message}");
}

#[test]
fn pair_names_with_the_same_file_name_are_refused() {
    for (a, b) in [("x/y", "x_y"), ("a b", "a_b"), ("Top", "top")] {
        let tail = format!(
            "name = \"{a}\"\n\n[[contact]]\nname = \"{b}\"\nbodies = [\"lower\", \"upper\"]\n\
             boundaries = [\"right\", \"left\"]\npenalty = {{ c = 0.05, h = 1.0 }}\n"
        );
        let message = error_of(&problem("lower", "steel", "bottom", &tail));
        for part in [
            format!("contact pair '{b}'"),
            format!("contact[0]'s name '{a}'"),
        ] {
            assert!(message.contains(&part), "{part} missing: {message}");
        }
    }
    // Names that differ in a kept character are fine.
    let tail = "name = \"x-y\"\n\n[[contact]]\nname = \"x_y\"\nbodies = [\"lower\", \"upper\"]\n\
                boundaries = [\"right\", \"left\"]\npenalty = { c = 0.05, h = 1.0 }\n";
    load_str(
        &problem("lower", "steel", "bottom", tail),
        "ok.toml",
        Path::new("."),
    )
    .expect("ok");
}

#[test]
fn load_groups_with_the_same_column_are_refused() {
    let text = problem("lower", "steel", "bottom", "").replace(
        "value = 10.0 }]",
        "value = 10.0, group = \"a b\" }, { kind = \"pressure\", boundary = \"top\", \
             value = 1.0, group = \"a_b\" }]",
    ) + "\n[[steps]]\nfactors = { \"a b\" = 1.0, a_b = 1.0 }\n";
    let message = error_of(&text);
    for part in ["load groups 'a b' and 'a_b'", "factor_a_b"] {
        assert!(message.contains(part), "{part} missing: {message}");
    }
}

#[test]
fn a_raw_escape_in_the_file_is_escaped_in_the_parse_error() {
    // A raw ESC inside a TOML string is a syntax error whose message echoes the line.
    let text = problem("low\u{1b}[2Jer", "steel", "bottom", "");
    let message = error_of(&text);
    assert!(message.contains("TOML parse error"), "{message}");
    assert!(
        message.contains("\\u{1b}[2J") && !message.contains('\u{1b}'),
        "{message}"
    );
}
