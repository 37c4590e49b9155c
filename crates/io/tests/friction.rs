//! Friction in problem files and in the outputs: the `friction` key of a `[[contact]]` table reads
//! to the pair's law and writes back to the same text, bad values name the pair and the key, and
//! the outputs of `examples/friction_block.toml` hold friction columns and fields that agree with
//! each other, with Coulomb's law and with the block's force balance — while a frictionless
//! problem's outputs hold none of them.

use std::path::{Path, PathBuf};

use serde_json::Value;

use contactdd_ddm::*;
use contactdd_io::fields::has_friction;
use contactdd_io::problem::{FrictionLaw, Problem};
use contactdd_io::*;

const MU: f64 = 0.3;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn block_text() -> String {
    std::fs::read_to_string(example("friction_block.toml")).expect("the example exists")
}

/// The example with its `friction = …` line replaced by `line` (several lines allowed).
fn with_friction(line: &str) -> String {
    let text = block_text();
    let old = "friction = { law = \"coulomb\", mu = 0.3 }";
    assert!(text.contains(old), "the example's friction line changed");
    text.replace(old, line)
}

fn solved(loaded: &Loaded) -> Solution {
    let prepared = prepare(&loaded.model).unwrap_or_else(|e| panic!("{e}"));
    let sol = solve(&loaded.model, &prepared, &loaded.settings, Hooks::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(sol.converged, "{:?}", sol.message);
    sol
}

#[test]
fn friction_reads_to_the_pairs_law_and_writes_back() {
    for (line, law) in [
        (
            "friction = { law = \"coulomb\", mu = 0.3 }",
            Friction::Coulomb { mu: 0.3 },
        ),
        (
            "friction = { law = \"tresca\", bound = 5.0 }",
            Friction::Tresca { bound: 5.0 },
        ),
        ("friction = { law = \"none\" }", Friction::None),
        ("", Friction::None),
    ] {
        let text = with_friction(line);
        let loaded = load_str(&text, "block.toml", &example("")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded.model.pairs[0].friction, law, "{line}");
        // Written out and read again: the same table and the same law.
        let written = write_problem::to_toml(&loaded.problem).expect("serialises");
        let again =
            load_str(&written, "again.toml", &example("")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again.problem, loaded.problem, "{written}");
        assert_eq!(again.model.pairs[0].friction, law);
        let spec = again.problem.contact[0].friction;
        assert_eq!(spec.is_some(), !line.is_empty(), "{written}");
    }
    // The law's table from the solver's value (what the Python module writes).
    let spec = problem::FrictionSpec::from(Friction::Tresca { bound: 2.5 });
    assert_eq!(
        (spec.law, spec.mu, spec.bound),
        (FrictionLaw::Tresca, None, Some(2.5))
    );
    // A frictionless problem writes no friction key.
    let notch = load_file(&example("notch.toml")).unwrap_or_else(|e| panic!("{e}"));
    let text = write_problem::to_toml(&notch.problem).expect("serialises");
    assert!(!text.contains("friction"), "{text}");
    let _: Problem = toml::from_str(&text).expect("reads back");
}

#[test]
fn bad_friction_values_name_the_pair_and_the_key() {
    for (line, parts) in [
        (
            "friction = { law = \"coulomb\", mu = -0.1 }",
            &["contact pair 'joint'", "friction.mu", "at least 0", "-0.1"][..],
        ),
        (
            "friction = { law = \"coulomb\", mu = nan }",
            &["contact pair 'joint'", "friction.mu", "finite", "NaN"],
        ),
        (
            "friction = { law = \"coulomb\" }",
            &[
                "contact pair 'joint'",
                "friction.mu",
                "Coulomb friction needs mu",
            ],
        ),
        (
            "friction = { law = \"tresca\", bound = -5.0 }",
            &["contact pair 'joint'", "friction.bound", "at least 0"],
        ),
        (
            "friction = { law = \"tresca\", mu = 0.3 }",
            &[
                "contact pair 'joint'",
                "friction.mu",
                "Tresca friction takes bound, not mu",
            ],
        ),
        (
            "friction = { law = \"coulomb\", mu = 0.3, bound = 1.0 }",
            &["friction.bound", "Coulomb friction takes mu, not bound"],
        ),
        (
            "friction = { law = \"none\", mu = 0.3 }",
            &["friction.mu", "law = \"none\" takes no mu"],
        ),
        (
            "friction = { law = \"stick\" }",
            &[
                "friction = { law = \"stick\" }",
                "unknown variant `stick`",
                "`coulomb`",
            ],
        ),
        (
            "friction = { mu = 0.3 }",
            &["friction = { mu = 0.3 }", "missing field `law`"],
        ),
        (
            "friction = { law = \"coulomb\", mu = 0.3, m = 1 }",
            &["unknown field `m`", "`law`, `mu`, `bound`"],
        ),
        (
            "friction = 0.3",
            &["friction = 0.3", "expected a friction table"],
        ),
        (
            "friction = { law = \"coulomb\", mu = 0.3 }\nforces = \"own-side\"",
            &[
                "contact pair 'joint'",
                "friction needs forces = \"balanced\"",
            ],
        ),
    ] {
        let text = with_friction(line);
        let message = match load_str(&text, "bad.toml", &example("")) {
            Ok(_) => panic!("accepted: {line}"),
            Err(e) => e.to_string(),
        };
        assert!(message.contains("bad.toml"), "{message}");
        for part in parts {
            assert!(
                message.contains(part),
                "{line}: '{part}' missing from: {message}"
            );
        }
    }
    // μ = 0 is frictionless, and accepted.
    let text = with_friction("friction = { law = \"coulomb\", mu = 0.0 }");
    let loaded = load_str(&text, "ok.toml", &example("")).unwrap_or_else(|e| panic!("{e}"));
    assert!(!has_friction(&loaded.model));
}

#[test]
fn the_command_lines_friction_grammar() {
    use contactdd_io::pairs::parse_friction;
    assert_eq!(
        parse_friction("coulomb:0.3"),
        Ok(Friction::Coulomb { mu: 0.3 })
    );
    assert_eq!(
        parse_friction(" tresca: 5 "),
        Ok(Friction::Tresca { bound: 5.0 })
    );
    assert_eq!(parse_friction("none"), Ok(Friction::None));
    for (bad, says) in [
        ("coulomb", "coulomb:VALUE"),
        ("coulomb:", "must be a number"),
        ("coulomb:x", "must be a number"),
        ("coulomb:-0.1", "at least 0"),
        ("coulomb:nan", "finite"),
        ("tresca:inf", "finite"),
        ("tresca:-1", "at least 0"),
        ("none:1", "takes no value"),
        ("stick", "unknown friction 'stick'"),
    ] {
        let err = parse_friction(bad).unwrap_err();
        assert!(err.contains(says), "{bad}: {err}");
    }
}

/// The friction columns of `contact.csv`, per row: (pair, body, σ_t, slip, total slip, status).
struct Row {
    body: String,
    pressure: f64,
    tangential: f64,
    slip: f64,
    total_slip: f64,
    status: String,
}

fn rows(csv_text: &str) -> (Vec<String>, Vec<Row>) {
    let mut reader = csv::Reader::from_reader(csv_text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .expect("a header")
        .iter()
        .map(String::from)
        .collect();
    let col = |name: &str| header.iter().position(|h| h == name);
    let mut out = Vec::new();
    if let (Some(t), Some(s), Some(g), Some(f)) = (
        col("tangential_traction"),
        col("slip"),
        col("total_slip"),
        col("friction"),
    ) {
        let p = col("pressure").expect("a pressure column");
        for r in reader.records() {
            let r = r.expect("a row");
            let num = |k: usize| r[k].parse::<f64>().expect("a number");
            out.push(Row {
                body: r[1].to_string(),
                pressure: num(p),
                tangential: num(t),
                slip: num(s),
                total_slip: num(g),
                status: r[f].to_string(),
            });
        }
    }
    (header, out)
}

#[test]
fn the_friction_outputs_agree_with_each_other_and_the_force_balance() {
    let loaded = load_file(&example("friction_block.toml")).unwrap_or_else(|e| panic!("{e}"));
    let sol = solved(&loaded);
    let model = &loaded.model;
    let (header, rows) = rows(&output::contact_csv(model, &sol));
    assert_eq!(
        header[8..],
        ["tangential_traction", "slip", "total_slip", "friction"]
    );
    let summary = output::summary_json(model, &sol);
    let pair = &summary["contact"][0];
    assert_eq!(
        pair["friction"],
        serde_json::json!({ "law": "coulomb", "mu": MU })
    );
    let tangential_force = pair["tangential_force"].as_f64().expect("a number");
    // Σ w σ_t over the reference side (the block, whose pressure loads both sides) is the pair's
    // tangential force; the following side carries none of its own.
    let weights: Vec<f64> = pair["weight"]
        .as_array()
        .expect("weights")
        .iter()
        .map(|w| w.as_f64().expect("a weight"))
        .collect();
    assert_eq!(weights.len(), rows.len());
    let sum: f64 = rows
        .iter()
        .zip(&weights)
        .filter(|(r, _)| r.body == "block")
        .map(|(r, w)| w * r.tangential)
        .sum();
    assert!(
        (sum - tangential_force).abs() <= 1e-12 * tangential_force.abs(),
        "{sum} vs {tangential_force}"
    );
    assert!(rows
        .iter()
        .filter(|r| r.body == "foundation")
        .all(|r| r.tangential == 0.0));
    // Coulomb's law at every point: within the disc; on its edge where the point slips.
    let (mut stick, mut slip) = (0.0, 0.0);
    for (r, w) in rows.iter().zip(&weights) {
        let bound = MU * r.pressure;
        assert!(
            r.tangential.abs() <= bound * (1.0 + 1e-12),
            "{} beyond {bound}",
            r.tangential
        );
        match r.status.as_str() {
            "slip" => {
                assert!((r.tangential.abs() - bound).abs() <= 1e-9 * bound);
                slip += w;
            }
            "stick" => stick += w,
            "open" => assert_eq!(r.tangential, 0.0),
            s => panic!("status {s}"),
        }
        // One solve from the unloaded state: the slip of this solve is the total slip.
        assert_eq!(r.slip, r.total_slip);
    }
    let length = |key: &str| pair[key].as_f64().expect("a length");
    assert!((length("stick_length") - stick).abs() < 1e-12);
    assert!((length("slip_length") - slip).abs() < 1e-12);
    // The block's contact zone is its whole bottom (2 long), and both stick and slip occur.
    assert!(
        (stick + slip - 2.0).abs() < 1e-12 && stick > 0.0 && slip > 0.0,
        "{stick} {slip}"
    );
    // The contact forces on the block balance its loads: the push (4, 0) and the pressure 10 on
    // its top (2 long); the tangential force is the push, against t = +x.
    let on_block: Vec<f64> = (0..2)
        .map(|k| pair["force"][1][k].as_f64().expect("a force"))
        .collect();
    assert!((on_block[0] + 4.0).abs() < 1e-8, "{on_block:?}");
    assert!((on_block[1] - 20.0).abs() < 1e-8, "{on_block:?}");
    assert!((tangential_force + 4.0).abs() < 1e-8, "{tangential_force}");
    // The per-point arrays of summary.json are the columns of contact.csv.
    let statuses: Vec<&str> = pair["friction_status"]
        .as_array()
        .expect("statuses")
        .iter()
        .map(|s| s.as_str().expect("a name"))
        .collect();
    assert_eq!(
        statuses,
        rows.iter().map(|r| r.status.as_str()).collect::<Vec<_>>()
    );
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(pair["tangential_traction"][k].as_f64(), Some(r.tangential));
        assert_eq!(pair["total_slip"][k].as_f64(), Some(r.total_slip));
    }
}

#[test]
fn the_vtu_files_hold_the_friction_fields_only_with_friction() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    for (name, friction) in [("friction_block.toml", true), ("notch.toml", false)] {
        let loaded = load_file(&example(name)).unwrap_or_else(|e| panic!("{e}"));
        let sol = solved(&loaded);
        let out = dir.path().join(name);
        output::write_results(&out, &loaded.model, &sol).expect("written");
        for body in &loaded.model.bodies {
            // The XML names the arrays; binary files append raw bytes after it.
            let bytes = std::fs::read(out.join(format!("{}.vtu", body.name))).expect("a vtu");
            let vtu = String::from_utf8_lossy(&bytes);
            for field in ["contact_tangential", "friction_status"] {
                assert_eq!(
                    vtu.contains(&format!("Name=\"{field}\"")),
                    friction,
                    "{name}: {}: {field}",
                    body.name
                );
            }
        }
        let summary: Value = serde_json::from_str(
            &std::fs::read_to_string(out.join("summary.json")).expect("a summary"),
        )
        .expect("json");
        let contact_csv = std::fs::read_to_string(out.join("contact.csv")).expect("a csv");
        let header = contact_csv.lines().next().expect("a header");
        assert_eq!(header.contains("tangential_traction"), friction, "{header}");
        for pair in summary["contact"].as_array().expect("pairs") {
            for key in [
                "friction",
                "tangential_force",
                "stick_length",
                "slip_length",
                "friction_status",
            ] {
                assert_eq!(pair.get(key).is_some(), friction, "{name}: {key}");
            }
        }
    }
}

#[test]
fn the_vtu_friction_fields_are_the_reference_sides_points() {
    let loaded = load_file(&example("friction_block.toml")).unwrap_or_else(|e| panic!("{e}"));
    let sol = solved(&loaded);
    let pair = &sol.contact[0];
    let block = &sol.bodies[1];
    let (tangential, status) =
        fields::friction_point_data(&block.name, block.mesh.num_nodes(), &sol.contact);
    for i in (0..pair.side.len()).filter(|&i| pair.side[i] == 1) {
        let v = pair.node[i];
        assert_eq!(tangential[v], pair.tangential[i]);
        let code = match pair.status[i] {
            FrictionStatus::Open => 0.0,
            FrictionStatus::Stick => 1.0,
            FrictionStatus::Slip => 2.0,
        };
        assert_eq!(status[v], code);
    }
    assert!(status.contains(&1.0) && status.contains(&2.0));
}
