//! Support reactions in `summary.json`, checked against the conservation law: on every body,
//! applied load + support reactions + contact force = 0. The reactions come from the fields
//! (K u − f on the supported DOFs), the contact force from the reported nodal contact forces, the
//! load from the load vector: three independent computations.

use std::path::Path;

use contactdd_ddm::{prepare, solve, Hooks};
use contactdd_io::output::{applied_load, summary_json};
use serde_json::Value;

/// Solves `text` to a tight tolerance and returns the model and `summary.json`.
fn solved(text: &str) -> (contactdd_ddm::Model, Value) {
    let mut loaded = contactdd_io::load_str(text, "case.toml", Path::new(".")).expect("valid");
    loaded.settings.tol = 1e-10;
    loaded.settings.max_iter = 2000;
    let model = loaded.model;
    let prepared = prepare(&model).expect("prepared");
    let sol = solve(&model, &prepared, &loaded.settings, Hooks::default()).expect("solved");
    assert!(sol.converged, "{:?}", sol.message);
    let summary = summary_json(&model, &sol);
    (model, summary)
}

fn vector(v: &Value) -> [f64; 2] {
    [0, 1].map(|k| v[k].as_f64().expect("a number"))
}

/// Per body: applied load + total reaction + contact force of every pair on it, relative to the
/// largest applied load of the model; returns the reactions per body for further checks.
fn check_balance(model: &contactdd_ddm::Model, summary: &Value, tol: f64) -> Vec<[f64; 2]> {
    let scale = model
        .bodies
        .iter()
        .map(|b| applied_load(&b.load))
        .fold(0.0f64, |m, f| m.max(f[0].hypot(f[1])));
    let mut totals = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        let entry = &summary["reactions"][b];
        assert_eq!(entry["body"], body.name.as_str());
        let reaction = vector(&entry["total"]);
        // Each supported DOF counts in one boundary: the boundaries add up to the total.
        let mut supports = [0.0; 2];
        for s in entry["supports"].as_array().expect("supports") {
            let f = vector(&s["force"]);
            supports[0] += f[0];
            supports[1] += f[1];
        }
        let gap = (supports[0] - reaction[0]).hypot(supports[1] - reaction[1]);
        assert!(
            gap <= 1e-12 * scale,
            "body {}: {supports:?} vs {reaction:?}",
            body.name
        );
        let mut sum = [0.0; 2];
        for k in 0..2 {
            sum[k] = applied_load(&body.load)[k] + reaction[k];
        }
        for pair in summary["contact"].as_array().expect("pairs") {
            for side in 0..2 {
                if pair["bodies"][side] == body.name.as_str() {
                    let f = vector(&pair["force"][side]);
                    sum[0] += f[0];
                    sum[1] += f[1];
                }
            }
        }
        let residual = sum[0].hypot(sum[1]) / scale;
        assert!(
            residual <= tol,
            "body {}: imbalance {residual:.2e}",
            body.name
        );
        totals.push(reaction);
    }
    totals
}

#[test]
fn notch_held_at_the_bottom_balances_load_reactions_and_contact() {
    // The notch benchmark with the lower body held on its bottom instead of pressed there: the
    // support carries the load 2100 · 4 = 8400 that the upper body puts on it.
    let notch = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/notch.toml"),
    )
    .expect("examples/notch.toml");
    let held = notch.replacen(
        "supports = [{ boundary = \"right\", component = \"x\", value = 0.0 }]\n\
         loads = [{ kind = \"pressure\", boundary = \"bottom\", value = 2100.0 }]",
        "supports = [{ boundary = \"right\", component = \"x\" }, \
         { boundary = \"bottom\", component = \"y\" }]",
        1,
    );
    assert_ne!(held, notch, "the lower body's supports were replaced");
    let (model, summary) = solved(&held);
    let totals = check_balance(&model, &summary, 1e-8);
    assert!((totals[0][1] - 8400.0).abs() <= 1e-6 * 8400.0, "{totals:?}");
    // Both supported boundaries of the lower body are listed.
    let supports: Vec<&str> = summary["reactions"][0]["supports"]
        .as_array()
        .expect("supports")
        .iter()
        .map(|s| s["boundary"].as_str().expect("a name"))
        .collect();
    assert_eq!(supports, ["bottom", "right"]);
    // The corner (4, 0) lies on both: its x reaction is the right side's (u_x held there), its y
    // reaction the bottom's, so the bottom takes no x force and the right side no y force.
    let force = |k: usize| vector(&summary["reactions"][0]["supports"][k]["force"]);
    let (bottom, right) = (force(0), force(1));
    assert_eq!(bottom[0], 0.0, "bottom {bottom:?}");
    assert_eq!(right[1], 0.0, "right {right:?}");
    assert!(
        (bottom[1] - 8400.0).abs() <= 1e-6 * 8400.0,
        "bottom {bottom:?}"
    );
}

#[test]
fn offset_blocks_with_an_oblique_load_balance() {
    // Different materials, non-matching meshes, the upper block off-centre and loaded obliquely:
    // its x support takes the tangential load, the lower block's clamped bottom the rest.
    let text = r#"
        plane = "strain"
        [materials.steel]
        young = 2.1e5
        poisson = 0.3
        [materials.aluminium]
        young = 7.0e4
        poisson = 0.33
        [[bodies]]
        name = "base"
        material = "steel"
        mesh = { kind = "rectangle", x = [0.0, 2.0], y = [0.0, 0.5], nx = 16, ny = 4 }
        supports = [{ boundary = "bottom", component = "both" }]
        [[bodies]]
        name = "block"
        material = "aluminium"
        mesh = { kind = "rectangle", x = [0.7, 1.6], y = [0.5, 1.0], nx = 7, ny = 4 }
        supports = [{ boundary = "left", component = "x" }]
        loads = [{ kind = "traction", boundary = "top", value = [30.0, -100.0] }]
        [[contact]]
        bodies = ["base", "block"]
        boundaries = ["top", "bottom"]
        penalty = { c = 0.05, h = 0.5 }
    "#;
    let (model, summary) = solved(text);
    let totals = check_balance(&model, &summary, 1e-8);
    // The tangential load 30 · 0.9 = 27 goes to the block's x support alone.
    assert!((totals[1][0] + 27.0).abs() <= 1e-8 * 100.0, "{totals:?}");
}

/// A rectangle mesh turned by `angle` degrees about the origin, written as an inline mesh.
fn inline_rectangle(x: [f64; 2], y: [f64; 2], n: [usize; 2], angle: f64) -> String {
    use contactdd_core::{Diagonal, Order, Rectangle};
    let (s, c) = angle.to_radians().sin_cos();
    let mesh = Rectangle {
        origin: [x[0], y[0]],
        corner: [x[1], y[1]],
        nx: n[0],
        ny: n[1],
        diagonal: Diagonal::Right,
        mirror: false,
        order: Order::P1,
    }
    .mesh()
    .expect("a mesh")
    .map_nodes(|[x, y]| [c * x - s * y, s * x + c * y])
    .expect("a mesh");
    let list = |items: Vec<String>| format!("[{}]", items.join(", "));
    let nodes = list(
        mesh.nodes()
            .iter()
            .map(|p| format!("[{:?}, {:?}]", p[0], p[1]))
            .collect(),
    );
    let cells = list(
        mesh.cells()
            .chunks(3)
            .map(|t| format!("[{}, {}, {}]", t[0], t[1], t[2]))
            .collect(),
    );
    let boundaries: Vec<String> = mesh
        .boundaries()
        .iter()
        .map(|(name, edges)| {
            let e = list(
                edges
                    .iter()
                    .map(|e| format!("[{}, {}]", e.a, e.b))
                    .collect(),
            );
            format!("{name} = {e}")
        })
        .collect();
    format!(
        "{{ kind = \"inline\", nodes = {nodes}, triangles = {cells}, boundaries = {{ {} }} }}",
        boundaries.join(", ")
    )
}

/// A block pressed onto a base, both cut by the symmetry line x = 0 and the base sliding on its
/// floor: every support a `normal` one, turned by `angle` degrees.
fn sliding_blocks(angle: f64) -> String {
    format!(
        r#"
        plane = "strain"
        [materials.steel]
        young = 2.1e5
        poisson = 0.3
        [[bodies]]
        name = "base"
        material = "steel"
        mesh = {}
        supports = [{{ boundary = "left", component = "normal" }},
                    {{ boundary = "bottom", component = "normal" }}]
        [[bodies]]
        name = "block"
        material = "steel"
        mesh = {}
        supports = [{{ boundary = "left", component = "normal" }}]
        loads = [{{ kind = "pressure", boundary = "top", value = 100.0 }}]
        [[contact]]
        bodies = ["base", "block"]
        boundaries = ["top", "bottom"]
        penalty = {{ c = 0.05, h = 0.25 }}
        "#,
        inline_rectangle([0.0, 2.0], [0.0, 0.5], [16, 4], angle),
        inline_rectangle([0.0, 1.0], [0.5, 1.0], [7, 4], angle),
    )
}

#[test]
fn reactions_on_inclined_normal_supports_rotate_with_the_model() {
    let (plain_model, plain) = solved(&sliding_blocks(0.0));
    check_balance(&plain_model, &plain, 1e-8);
    for angle in [30.0, 117.0] {
        let (model, summary) = solved(&sliding_blocks(angle));
        assert!(model.bodies[0].constraints.inclined().count() > 0);
        check_balance(&model, &summary, 1e-8);
        let (s, c) = f64::to_radians(angle).sin_cos();
        let rot = |[x, y]: [f64; 2]| [c * x - s * y, s * x + c * y];
        for b in 0..2 {
            let supports = summary["reactions"][b]["supports"]
                .as_array()
                .expect("list");
            let expected = plain["reactions"][b]["supports"].as_array().expect("list");
            assert_eq!(supports.len(), expected.len());
            for (got, want) in supports.iter().zip(expected) {
                assert_eq!(got["boundary"], want["boundary"]);
                let (r, r0) = (vector(&got["force"]), rot(vector(&want["force"])));
                let diff = (r[0] - r0[0]).hypot(r[1] - r0[1]);
                println!(
                    "{angle}° body {b} {}: {r:?}, difference {diff:.2e}",
                    got["boundary"]
                );
                assert!(diff <= 1e-7 * 100.0, "{angle}°: {r:?} vs {r0:?}");
            }
        }
        // The base's supports push it up along the floor's normal and take nothing along the
        // floor: no support resists sliding. The corner node, on both supports, splits its
        // reaction along their normals. The normal part is the contact force on the base: the
        // whole load 100 · 1, since the pair's forces are balanced on the non-matching meshes
        // too.
        let r = vector(&summary["reactions"][0]["total"]);
        let (normal, tangential) = (-r[0] * s + r[1] * c, r[0] * c + r[1] * s);
        println!("{angle}° base: normal reaction {normal}, tangential {tangential:.2e}");
        assert!((normal - 100.0).abs() <= 1e-8 * 100.0, "{r:?}");
        assert!(tangential.abs() <= 1e-7 * 100.0, "{r:?}");
    }
}
