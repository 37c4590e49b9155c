//! A bounded property test of the two text front ends: the problem-file loader (TOML → load and
//! resolve → for the small problems, solve) and the Gmsh reader. The shipped examples and the test
//! meshes are mutated by a seeded generator (byte flips, truncations, line deletions and
//! duplications, numbers swapped for 0, -1, 1e300, nan, …), and every mutant must
//!
//! - never panic (each case runs under `catch_unwind`);
//! - never report `converged` with an equilibrium residual above the tolerance.
//!
//! Sizes stay capped so that no case asks for much work: the swapped-in numbers are either small
//! or far beyond the loader's limits (refused at once), only models of at most `SOLVE_NODES` nodes
//! are solved, with at most `MAX_ITER` iterations. The runs are deterministic; a failure names the
//! seed, the mutation and the message.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use contactdd::ddm::{prepare, solve, Hooks};
use contactdd::fem::gmsh::parse_msh;
use contactdd::io::load_str;

/// Problem-file mutants per seed file.
const PROBLEM_CASES: usize = 120;
/// Gmsh mutants per seed mesh.
const GMSH_CASES: usize = 400;
/// Largest model (total nodes) that is solved.
const SOLVE_NODES: usize = 3000;
/// Iteration cap of the solves.
const MAX_ITER: usize = 100;

/// Numbers swapped in: edge values, and sizes either small or refused by the loader's limits.
const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "-0.0",
    "1e300",
    "-1e300",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "0.5",
    "3",
    "1e9",
    "99999999999999999999",
    "18446744073709551615",
];

/// Tokens swapped in for a word.
const WORDS: &[&str] = &[
    "\"\"",
    "[]",
    "{}",
    "true",
    "\"top\"",
    "\"bottom\"",
    "=",
    "[[",
    "]]",
    "#",
    "\"p2\"",
    "$EndNodes",
    "$Nodes",
    "\n",
    "\"auto\"",
];

/// xorshift64*: a few lines, deterministic, good enough to pick mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Byte ranges of the numbers and of the words of `text`.
fn tokens(text: &str, numbers: bool) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let is_number = |b: u8| b.is_ascii_digit() || b == b'.' || b == b'-' || b == b'e';
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let inside = |b: u8| {
            if numbers {
                is_number(b)
            } else {
                b.is_ascii_alphanumeric() || b == b'_'
            }
        };
        if inside(bytes[i]) && (!numbers || bytes[i] != b'e') {
            let start = i;
            while i < bytes.len() && inside(bytes[i]) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// One to three random mutations of `text`, and their description.
fn mutate(text: &str, rng: &mut Rng) -> (String, String) {
    let mut bytes = text.as_bytes().to_vec();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(3) {
        let current = String::from_utf8_lossy(&bytes).into_owned();
        let kind = rng.below(6);
        let (new, desc) = match kind {
            0 if !bytes.is_empty() => {
                let i = rng.below(bytes.len());
                let mut b = bytes.clone();
                b[i] ^= 1 << rng.below(8);
                (b, format!("flip byte {i}"))
            }
            1 => {
                let n = rng.below(bytes.len() + 1);
                (bytes[..n].to_vec(), format!("truncate at {n}"))
            }
            2 | 3 => {
                let numbers = kind == 2;
                let spans = tokens(&current, numbers);
                if spans.is_empty() {
                    continue;
                }
                let (a, b) = spans[rng.below(spans.len())];
                let with = if numbers {
                    NUMBERS[rng.below(NUMBERS.len())]
                } else {
                    WORDS[rng.below(WORDS.len())]
                };
                let s = format!("{}{with}{}", &current[..a], &current[b..]);
                (s.into_bytes(), format!("{:?} → {with}", &current[a..b]))
            }
            _ => {
                let lines: Vec<&str> = current.split_inclusive('\n').collect();
                if lines.is_empty() {
                    continue;
                }
                let k = rng.below(lines.len());
                let mut out: Vec<&str> = lines.clone();
                let desc = if kind == 4 {
                    out.remove(k);
                    format!("delete line {}", k + 1)
                } else {
                    out.insert(k, lines[k]);
                    format!("repeat line {}", k + 1)
                };
                (out.concat().into_bytes(), desc)
            }
        };
        bytes = new;
        what.push(desc);
    }
    (
        String::from_utf8_lossy(&bytes).into_owned(),
        what.join(", "),
    )
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Files of `dir` with extension `ext`.
fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    out.sort();
    out
}

/// Loads one problem text and, if it is small, solves it; returns whether it was solved.
fn load_and_solve(text: &str, base: &Path) -> Result<bool, String> {
    let Ok(loaded) = load_str(text, "fuzz.toml", base) else {
        return Ok(false);
    };
    let nodes: usize = loaded.model.bodies.iter().map(|b| b.mesh.num_nodes()).sum();
    if nodes > SOLVE_NODES {
        return Ok(false);
    }
    let Ok(prepared) = prepare(&loaded.model) else {
        return Ok(false);
    };
    let mut settings = loaded.settings.clone();
    settings.max_iter = settings.max_iter.min(MAX_ITER);
    let Ok(sol) = solve(&loaded.model, &prepared, &settings, Hooks::default()) else {
        return Ok(false);
    };
    let tol = settings.equilibrium_tol;
    let out = sol.equilibrium.iter().find(|e| e.is_nan() || **e > tol);
    if let (true, Some(worst)) = (sol.converged, out) {
        return Err(format!(
            "converged with the equilibrium residual {worst} above {tol}"
        ));
    }
    Ok(true)
}

/// Runs `case` on `cases` mutants of every seed; panics on the first failure, naming it.
fn run(
    seeds: &[PathBuf],
    cases: usize,
    case: impl Fn(&str, &Path) -> Result<bool, String>,
) -> (usize, usize) {
    let (mut run, mut deep) = (0, 0);
    for (s, path) in seeds.iter().enumerate() {
        let text = std::fs::read_to_string(path).unwrap();
        let base = path.parent().unwrap();
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ (s as u64 + 1));
        for k in 0..cases {
            let (mutant, what) = mutate(&text, &mut rng);
            let outcome = catch_unwind(AssertUnwindSafe(|| case(&mutant, base)));
            match outcome {
                Ok(Ok(solved)) => deep += usize::from(solved),
                Ok(Err(e)) => panic!("{path:?}, case {k} ({what}): {e}"),
                Err(_) => panic!("{path:?}, case {k} ({what}): panicked"),
            }
            run += 1;
        }
    }
    (run, deep)
}

#[test]
fn mutated_problem_files_never_panic_nor_claim_a_false_convergence() {
    let start = Instant::now();
    let seeds = files(&root().join("examples"), "toml");
    assert!(seeds.len() >= 4);
    let (cases, solved) = run(&seeds, PROBLEM_CASES, load_and_solve);
    eprintln!(
        "problem files: {cases} mutants, {solved} solved, {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert!(
        solved > 0,
        "no mutant was solved: the harness tests nothing deep"
    );
}

#[test]
fn mutated_gmsh_files_never_panic() {
    let start = Instant::now();
    let mut seeds = files(&root().join("crates/core/tests/data"), "msh");
    seeds.extend(files(&root().join("examples/meshes"), "msh"));
    let (cases, parsed) = run(&seeds, GMSH_CASES, |text, _| Ok(parse_msh(text).is_ok()));
    eprintln!(
        "gmsh files: {cases} mutants, {parsed} parsed, {:.1} s",
        start.elapsed().as_secs_f64()
    );
}
