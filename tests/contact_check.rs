//! The contact geometry checks find nothing to say about the shipped examples and the test cases
//! of `src/cases.rs`: every one of them is a well-posed contact problem.

use std::path::Path;

use contactdd::cases;
use contactdd::ddm::contact::check::check;
use contactdd::ddm::contact::Interface;
use contactdd::ddm::Model;

fn findings(model: &Model) -> Vec<String> {
    let interface = Interface::new(model).unwrap();
    check(model, &interface)
        .iter()
        .map(|f| f.to_string())
        .collect()
}

#[test]
fn the_shipped_examples_get_no_finding() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut seen = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let loaded = contactdd::io::load_file(&path).unwrap();
            assert_eq!(findings(&loaded.model), Vec::<String>::new(), "{path:?}");
            seen += 1;
        }
    }
    assert!(seen >= 4, "only {seen} examples");
}

#[test]
fn the_test_cases_get_no_finding() {
    let models = [
        cases::stiff_under_soft(0.5),
        cases::column(4, 0.5),
        cases::recess(0.5, 0.5, 8),
        cases::non_matching_notch(0.5),
        contactdd::ddm::benchmark::Notch::default().model().unwrap(),
    ];
    for model in &models {
        assert_eq!(findings(model), Vec::<String>::new(), "{}", model.name);
    }
}
