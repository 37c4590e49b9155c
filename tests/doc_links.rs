//! The repository's documentation stands alone: every relative Markdown link and every file path
//! quoted in backticks in a Markdown file names a file or folder that exists in the repository.

use std::path::{Path, PathBuf};

/// Top-level folders whose paths the docs quote.
const ROOTS: [&str; 8] = [
    "docs/",
    "examples/",
    "crates/",
    "tests/",
    "benches/",
    "scripts/",
    "python/",
    "src/",
];

fn markdown_files(root: &Path) -> Vec<PathBuf> {
    let mut out = vec![root.join("README.md"), root.join("python/README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
    out
}

/// Relative link targets `](target)` of a Markdown text (no URLs, no anchors).
fn links(text: &str) -> Vec<String> {
    text.split("](")
        .skip(1)
        .filter_map(|rest| rest.split(')').next())
        .map(|t| t.split('#').next().unwrap_or("").to_string())
        .filter(|t| !t.is_empty() && !t.contains("://") && !t.starts_with("mailto:"))
        .collect()
}

/// Paths quoted in backticks that start with one of [`ROOTS`], trimmed at the first character
/// that cannot belong to a path.
fn quoted_paths(text: &str) -> Vec<String> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .filter(|q| ROOTS.iter().any(|r| q.starts_with(r)))
        .map(|q| {
            q.split(|c: char| c.is_whitespace() || c == ':' || c == ',')
                .next()
                .unwrap_or("")
                .trim_end_matches(['.', ')'])
                .to_string()
        })
        .filter(|q| !q.contains('*') && !q.contains('<'))
        .collect()
}

#[test]
fn every_documented_path_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut missing = Vec::new();
    for file in markdown_files(root) {
        let text = std::fs::read_to_string(&file).unwrap();
        let dir = file.parent().unwrap();
        for link in links(&text) {
            if !dir.join(&link).exists() {
                missing.push(format!("{}: link {link}", file.display()));
            }
        }
        for path in quoted_paths(&text) {
            if !root.join(&path).exists() {
                missing.push(format!("{}: path {path}", file.display()));
            }
        }
    }
    assert!(missing.is_empty(), "missing:\n{}", missing.join("\n"));
}

#[test]
fn the_checks_see_links_and_paths() {
    assert_eq!(
        links("see [a](docs/x.md#s) and [b](https://e.org)"),
        ["docs/x.md"]
    );
    assert_eq!(
        quoted_paths("run `examples/notch.toml`, `docs/a.md:` and `cargo test`"),
        ["examples/notch.toml", "docs/a.md"]
    );
}
