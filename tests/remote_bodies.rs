//! A process of a distributed solve meshes only its own bodies and holds each of the others as
//! its contact skin and facts (`docs/mpi.md`). Everything every process builds from the whole
//! model — the contact geometry, the coarse space of rigid modes, the overlap check, the contact
//! points' positions — must come out the same as from the whole bodies, to the bit, on every
//! shipped example: curved and non-matching balanced pairs (Hertz, the cylinder between plates,
//! P2), floating chains (the column), three bodies and the paper's notch.

use std::path::Path;

use contactdd::ddm::coarse::Coarse;
use contactdd::ddm::contact::check::check;
use contactdd::ddm::contact::Interface;
use contactdd::ddm::Model;
use contactdd::io::load_file;

fn same_as_whole(model: &Model, remote: &[usize]) {
    let seen = model.as_seen_by(|b| !remote.contains(&b));
    let whole = Interface::new(model).unwrap();
    let interface = Interface::new(&seen).unwrap();
    assert_eq!(interface, whole, "{}: contact geometry", model.name);
    let (a, b) = (Coarse::new(model, &whole), Coarse::new(&seen, &interface));
    assert_eq!(
        a.floating_modes(),
        b.floating_modes(),
        "{}: coarse",
        model.name
    );
    assert_eq!(check(&seen, &interface), check(model, &whole));
    for p in &whole.points {
        let (x, y) = (
            model.position(p.body, p.node),
            seen.position(p.body, p.node),
        );
        assert_eq!(x, y, "{}: position of node {}", model.name, p.node);
    }
    for &b in remote {
        assert_eq!(seen.facts(b), model.facts(b));
        let skin = &seen.bodies[b].mesh;
        assert_eq!(skin.num_cells(), 0);
        let contact_nodes = whole.points[whole.body_range[b].clone()]
            .iter()
            .map(|p| p.node)
            .collect::<std::collections::BTreeSet<_>>();
        assert_eq!(
            skin.num_nodes(),
            contact_nodes.len(),
            "{}: skin",
            model.name
        );
    }
}

#[test]
fn every_example_builds_the_same_geometry_from_skins() {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for file in [
        "notch.toml",
        "hertz.toml",
        "stack.toml",
        "three_bodies.toml",
        "cylinder_plates.toml",
    ] {
        let model = load_file(&examples.join(file)).unwrap().model;
        let n = model.bodies.len();
        // Each body alone remote, and every body but the first.
        for b in 0..n {
            same_as_whole(&model, &[b]);
        }
        same_as_whole(&model, &(1..n).collect::<Vec<_>>());
    }
}

#[test]
fn non_matching_and_floating_cases_build_the_same_geometry_from_skins() {
    for model in [
        contactdd::cases::non_matching_notch(0.05),
        contactdd::cases::column(5, 0.05),
        contactdd::cases::recess(0.5, 0.05, 24),
    ] {
        for b in 0..model.bodies.len() {
            same_as_whole(&model, &[b]);
        }
    }
}
