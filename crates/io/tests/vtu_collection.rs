//! The `collection` layout of the `.vtu` files (one file per result, one `Piece` per body)
//! against the `per-body` layout (one file per body) and against the solution written: in every
//! encoding, each piece reads back (by `contactdd_io::vtu_read`) to the arrays of the body's own
//! file bit for bit, and its displacement and points are the solution's; the other files are those
//! of the per-body folder; the manifest and `results.pvd` name the one file; a distributed solve
//! refuses the layout before writing anything.

use std::path::{Path, PathBuf};

use contactdd_ddm::benchmark::Notch;
use contactdd_ddm::{prepare, solve, Hooks, Model, Settings, Solution};
use contactdd_io::distributed_results::{write_results_shared, Part};
use contactdd_io::output::{write_results_noted, write_step_results};
use contactdd_io::vtu::{VtuFormat, VtuLayout, VtuOptions};
use contactdd_io::vtu_read::{parse_vtu, parse_vtu_pieces, Section, VtuFile};
use serde_json::Value;

fn notch() -> (Model, Solution) {
    let model = Notch::default().model().expect("notch");
    let prepared = prepare(&model).expect("prepared");
    let sol = solve(&model, &prepared, &Settings::default(), Hooks::default()).expect("solved");
    (model, sol)
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contactdd-coll-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn summary(dir: &Path) -> Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary");
    serde_json::from_str(&text).expect("JSON")
}

fn manifest(dir: &Path) -> Vec<String> {
    (summary(dir)["files"].as_array().expect("a manifest").iter())
        .map(|f| f.as_str().expect("a name").to_string())
        .collect()
}

/// Every array of `file` as (section, name, components, bits of the values): NaN compares by its
/// bits.
fn bits(file: &VtuFile) -> Vec<(Section, String, usize, Vec<u64>)> {
    (file.arrays.iter())
        .map(|a| {
            let values = a.values.iter().map(|v| v.to_bits()).collect();
            (a.section, a.name.clone(), a.components, values)
        })
        .collect()
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn each_piece_is_the_body_file_bit_for_bit_in_every_encoding() {
    let (model, sol) = notch();
    assert!(sol.bodies.len() >= 2, "the notch has several bodies");
    for format in [VtuFormat::Ascii, VtuFormat::Binary, VtuFormat::Zlib] {
        let per_body = temp(&format!("per-body-{format}"));
        let collection = temp(&format!("collection-{format}"));
        write_results_noted(&per_body, &model, &sol, Some("mm"), format).expect("per body");
        let options = VtuOptions {
            format,
            layout: VtuLayout::Collection,
        };
        write_results_noted(&collection, &model, &sol, Some("mm"), options).expect("collection");

        // The manifest: the body files give way to the one file, in their place.
        let names: Vec<String> = (sol.bodies.iter())
            .map(|b| format!("{}.vtu", b.name))
            .collect();
        let mut expected = vec!["contact.csv".to_string(), "history.csv".to_string()];
        expected.extend(names.iter().cloned());
        expected.push("results.pvd".into());
        assert_eq!(manifest(&per_body), expected);
        assert_eq!(
            manifest(&collection),
            ["contact.csv", "history.csv", "bodies.vtu", "results.pvd"]
        );
        for name in &names {
            assert!(
                !collection.join(name).exists(),
                "{name} in the collection folder"
            );
        }
        // The other files are the same, byte for byte; the summary but for its manifest and
        // its timings.
        for name in ["contact.csv", "history.csv"] {
            assert_eq!(
                read(&per_body.join(name)),
                read(&collection.join(name)),
                "{name}"
            );
        }
        let strip = |mut s: Value| {
            let object = s.as_object_mut().expect("an object");
            object.remove("files");
            object.remove("timing_s");
            s
        };
        assert_eq!(strip(summary(&per_body)), strip(summary(&collection)));
        let pvd = String::from_utf8(read(&collection.join("results.pvd"))).expect("text");
        assert!(
            pvd.contains("<DataSet timestep=\"1\" part=\"0\" file=\"bodies.vtu\"/>"),
            "{pvd}"
        );
        assert_eq!(pvd.matches("<DataSet").count(), 1, "{pvd}");

        let pieces = parse_vtu_pieces(&read(&collection.join("bodies.vtu"))).expect("pieces");
        assert_eq!(pieces.len(), sol.bodies.len(), "{format}");
        for ((piece, name), body) in pieces.iter().zip(&names).zip(&sol.bodies) {
            let own = parse_vtu(&read(&per_body.join(name))).expect("body file");
            assert_eq!(bits(piece), bits(&own), "{format}: {name}");
            // And against the solution itself, not only the other writer.
            let u = piece
                .array(Section::PointData, "displacement")
                .expect("displacement");
            let padded: Vec<f64> = (body.displacement.chunks(2))
                .flat_map(|d| [d[0], d[1], 0.0])
                .collect();
            assert_eq!(u.values, padded, "{format}: {name}");
            let points = piece.array(Section::Points, "").expect("points");
            let nodes: Vec<f64> = (body.mesh.nodes().iter())
                .flat_map(|p| [p[0], p[1], 0.0])
                .collect();
            assert_eq!(points.values, nodes, "{format}: {name}");
        }
        // One file of all pieces reads, flattened, as the body files one after the other.
        let flat = parse_vtu(&read(&collection.join("bodies.vtu"))).expect("flat");
        let joined: Vec<_> = pieces.iter().flat_map(bits).collect();
        assert_eq!(bits(&flat), joined);
        std::fs::remove_dir_all(&per_body).expect("clean");
        std::fs::remove_dir_all(&collection).expect("clean");
    }
}

/// A single body: the collection file is the body's own file, byte for byte (the multi-piece
/// writer adds nothing around one piece).
#[test]
fn a_collection_of_one_body_is_its_file() {
    let (model, sol) = notch();
    let mut one = model.clone();
    one.bodies.truncate(1);
    one.pairs.clear();
    let mut alone = sol.clone();
    alone.bodies.truncate(1);
    alone.contact.clear();
    for format in [VtuFormat::Ascii, VtuFormat::Binary, VtuFormat::Zlib] {
        let a = temp(&format!("one-a-{format}"));
        let b = temp(&format!("one-b-{format}"));
        write_results_noted(&a, &one, &alone, None, format).expect("per body");
        let collection = VtuOptions {
            format,
            layout: VtuLayout::Collection,
        };
        write_results_noted(&b, &one, &alone, None, collection).expect("collection");
        let name = format!("{}.vtu", alone.bodies[0].name);
        assert_eq!(read(&a.join(name)), read(&b.join("bodies.vtu")), "{format}");
        std::fs::remove_dir_all(&a).expect("clean");
        std::fs::remove_dir_all(&b).expect("clean");
    }
}

#[test]
fn load_steps_get_one_file_per_step() {
    let (model, sol) = notch();
    let dir = temp("steps");
    let steps = vec![(0.5, sol.clone()), (1.0, sol)];
    let options = VtuOptions {
        format: VtuFormat::Zlib,
        layout: VtuLayout::Collection,
    };
    write_step_results(&dir, &model, &steps, (None, None), options).expect("written");
    assert_eq!(
        manifest(&dir),
        [
            "contact.csv",
            "history.csv",
            "steps.csv",
            "bodies-step1.vtu",
            "bodies-step2.vtu",
            "results.pvd"
        ]
    );
    let pvd = String::from_utf8(read(&dir.join("results.pvd"))).expect("text");
    assert!(pvd.contains("timestep=\"0.5\" part=\"0\" file=\"bodies-step1.vtu\""));
    assert!(pvd.contains("timestep=\"1\" part=\"0\" file=\"bodies-step2.vtu\""));
    std::fs::remove_dir_all(&dir).expect("clean");
}

/// A process that does not hold every body refuses the layout, naming the fix, and nothing is
/// written (the previous set stays).
#[test]
fn a_process_without_every_body_refuses_the_collection() {
    let (model, sol) = notch();
    let dir = temp("ranks");
    let part = Part {
        owns: Box::new(|b| b == 0),
        ..Part::alone_as(VtuOptions {
            format: VtuFormat::Zlib,
            layout: VtuLayout::Collection,
        })
    };
    let error = write_results_shared(&dir, &model, &sol, &[], None, &part).expect_err("refused");
    let message = error.to_string();
    assert!(message.contains("MPI rank"), "{message}");
    assert!(message.contains("--vtu-layout per-body"), "{message}");
    assert_eq!(std::fs::read_dir(&dir).expect("list").count(), 0);
    std::fs::remove_dir_all(&dir).expect("clean");
}

#[test]
fn the_output_table_names_the_layout() {
    let file = |layout: &str| {
        format!(
            r#"
            plane = "strain"
            [materials.steel]
            young = 1.0
            poisson = 0.3
            [[bodies]]
            name = "block"
            material = "steel"
            mesh = {{ kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0], nx = 1, ny = 1 }}
            supports = [{{ boundary = "bottom", component = "both" }}]
            [output]
            {layout}
            "#
        )
    };
    let load = |text: &str| contactdd_io::load_str(text, "t.toml", Path::new("."));
    let output = |layout: &str| load(&file(layout)).expect("valid").problem.output;
    assert_eq!(output("").vtu_layout, None);
    assert_eq!(output("").vtu_options(), VtuOptions::default());
    let collection = output("vtu-layout = \"collection\"");
    assert_eq!(collection.vtu_layout, Some(VtuLayout::Collection));
    assert_eq!(collection.vtu_options().layout, VtuLayout::Collection);
    assert_eq!(
        output("vtu-layout = \"per-body\"").vtu_layout,
        Some(VtuLayout::PerBody)
    );
    let error = load(&file("vtu-layout = \"single\"")).expect_err("unknown layout");
    let message = error.to_string();
    assert!(
        message.contains("per-body") && message.contains("collection"),
        "{message}"
    );
    assert_eq!("collection".parse(), Ok(VtuLayout::Collection));
    let unknown = "pieces".parse::<VtuLayout>().expect_err("unknown");
    assert!(unknown.to_string().contains("'per-body' or 'collection'"));
}
