//! A bounded property test of `contactdd plot`'s reader of result folders: every mutant of a real
//! folder is refused with exit 1 or plotted with exit 0, never a panic (exit 101), a signal or a
//! hang (a run is killed after [`TIMEOUT`]).
//!
//! **Seed corpus** (generated, not stored): the binary solves two shipped examples into four
//! temporary folders,
//!
//! - `examples/notch.toml`, three times, with zlib, binary and ASCII `.vtu` files:
//!   `summary.json`, `contact.csv`, `history.csv`, `lower.vtu`, `upper.vtu` (frictionless, one
//!   load);
//! - `examples/friction_block.toml` with `[solver] load-steps = 2` and a monitor added:
//!   `summary.json` with a Coulomb law, `contact.csv` with the friction columns, `history.csv`,
//!   `steps.csv` and the VTU files of both steps (the second step's are the ones drawn),
//!
//! so that every figure's reader is reached. Each case mutates one file of one folder by one to
//! three of: a bit flip, a truncation, a number replaced by an edge value (`nan`, `1e300`, `-1`,
//! `inf`, `0`, a huge integer, …), a word replaced by a token (`null`, `[]`, `{}`, `"x"`, a status
//! name, …), a line deleted or repeated. The generator is seeded (xorshift64*, as in the
//! workspace's `tests/fuzz.rs`), so the run is deterministic; a failure names the case, the file,
//! the mutations and the message. The file is restored after each case. Half the cases draw SVG,
//! half PNG (the two back ends place text and shapes differently). With `PLOT_FUZZ_SHOW` set in
//! the environment, every case and its outcome is printed (run with `--nocapture`).

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Mutants per seed folder.
const CASES: usize = 120;
/// Longest a run may take before it counts as a hang.
const TIMEOUT: Duration = Duration::from_secs(20);

/// Numbers swapped in.
const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "-0.0",
    "1e300",
    "-1e300",
    "1e-300",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "3",
    "1e9",
    "99999999999999999999",
    "18446744073709551615",
];

/// Tokens swapped in for a word.
const WORDS: &[&str] = &[
    "null",
    "[]",
    "{}",
    "\"x\"",
    "\"\"",
    "true",
    "closed",
    "open",
    "stick",
    "slip",
    "none",
    "ascii",
    "binary",
    "zlib",
    "vtkZLibDataCompressor",
    ",",
    "\"",
    "\n",
    "</DataArray>",
    "<DataArray",
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

/// Byte ranges of the numbers (`numbers`) or of the words of `text`.
fn tokens(text: &[u8], numbers: bool) -> Vec<(usize, usize)> {
    let inside = |b: u8| {
        if numbers {
            b.is_ascii_digit() || b == b'.' || b == b'-' || b == b'e' || b == b'+'
        } else {
            b.is_ascii_alphanumeric() || b == b'_'
        }
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        if inside(text[i]) && (!numbers || text[i].is_ascii_digit() || text[i] == b'-') {
            let start = i;
            while i < text.len() && inside(text[i]) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// One mutation of `bytes`, and its description; `None` when it does not apply.
fn mutate_once(bytes: &[u8], rng: &mut Rng) -> Option<(Vec<u8>, String)> {
    let kind = rng.below(7);
    match kind {
        0 if !bytes.is_empty() => {
            let i = rng.below(bytes.len());
            let mut b = bytes.to_vec();
            b[i] ^= 1 << rng.below(8);
            Some((b, format!("flip a bit of byte {i}")))
        }
        1 => {
            let n = rng.below(bytes.len() + 1);
            Some((bytes[..n].to_vec(), format!("truncate at {n}")))
        }
        2..=4 => {
            let numbers = kind != 4;
            let spans = tokens(bytes, numbers);
            if spans.is_empty() {
                return None;
            }
            let (a, b) = spans[rng.below(spans.len())];
            let with = if numbers {
                NUMBERS[rng.below(NUMBERS.len())]
            } else {
                WORDS[rng.below(WORDS.len())]
            };
            let was = String::from_utf8_lossy(&bytes[a..b]).into_owned();
            let out = [&bytes[..a], with.as_bytes(), &bytes[b..]].concat();
            Some((out, format!("{was:?} at {a} → {with:?}")))
        }
        _ => {
            let lines: Vec<&[u8]> = bytes.split_inclusive(|&b| b == b'\n').collect();
            if lines.is_empty() {
                return None;
            }
            let k = rng.below(lines.len());
            let mut out = lines.clone();
            let desc = if kind == 5 {
                out.remove(k);
                format!("delete line {}", k + 1)
            } else {
                out.insert(k, lines[k]);
                format!("repeat line {}", k + 1)
            };
            Some((out.concat(), desc))
        }
    }
}

/// One to three mutations of `bytes`, and their description.
fn mutate(bytes: &[u8], rng: &mut Rng) -> (Vec<u8>, String) {
    let mut bytes = bytes.to_vec();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(3) {
        if let Some((new, desc)) = mutate_once(&bytes, rng) {
            bytes = new;
            what.push(desc);
        }
    }
    (bytes, what.join(", "))
}

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// Exit code (`None` for a signal) and stderr of `contactdd args`, killed after [`TIMEOUT`]
/// (`Err` then).
fn run(args: &[&str]) -> Result<(Option<i32>, String), String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_contactdd"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run contactdd");
    let mut stderr = child.stderr.take().expect("stderr");
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {TIMEOUT:?}"));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Ok((status.code(), reader.join().expect("stderr reader")))
}

/// Solves `file` into `out` with the `.vtu` files in `encoding`; panics unless it converges.
fn solve(file: &Path, out: &Path, encoding: &str) {
    let args = ["solve", path(file), "--out", path(out), "--quiet"];
    let (code, err) = run(&[&args[..], &["--vtu-format", encoding]].concat()).expect("solve");
    assert_eq!(code, Some(0), "{}: {err}", file.display());
}

/// The four seed folders (see the module comment) under `dir`.
fn seeds(dir: &Path) -> Vec<PathBuf> {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let notch = dir.join("notch");
    solve(&examples.join("notch.toml"), &notch, "zlib");
    let binary = dir.join("notch-binary");
    solve(&examples.join("notch.toml"), &binary, "binary");
    let ascii = dir.join("notch-ascii");
    solve(&examples.join("notch.toml"), &ascii, "ascii");
    let block = std::fs::read_to_string(examples.join("friction_block.toml")).expect("example");
    assert!(
        !block.contains("[solver]"),
        "the example changed: update this test"
    );
    let steps = dir.join("friction_steps.toml");
    let solver = "\n[solver]\nload-steps = 2\nmonitor = { body = \"block\", boundary = \"top\" }\n";
    std::fs::write(&steps, format!("{block}{solver}")).expect("write");
    let friction = dir.join("friction");
    solve(&steps, &friction, "zlib");
    vec![notch, binary, ascii, friction]
}

/// The files of `folder` that `plot` reads, sorted: every `.csv`, `.vtu` and `.json`.
fn targets(folder: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(folder)
        .expect("read folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| e == "csv" || e == "vtu" || e == "json")
        })
        .collect();
    out.sort();
    out
}

#[test]
fn mutated_result_folders_never_crash_or_hang_plot() {
    let dir = std::env::temp_dir().join(format!("contactdd-plotfuzz-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let start = Instant::now();
    let mut rng = Rng(0x5eed_0fc0_ffee);
    let mut failures = Vec::new();
    let (mut plotted, mut refused) = (0, 0);
    for folder in seeds(&dir) {
        // The pristine folder plots, with the figures of every reader.
        let (code, err) = run(&["plot", path(&folder), "--format", "svg"]).expect("pristine");
        assert_eq!(code, Some(0), "{}: {err}", folder.display());
        assert!(folder.join("plots/history.svg").is_file());
        assert!(folder.join("plots/bodies.svg").is_file());
        let files = targets(&folder);
        assert!(files.len() >= 5, "{files:?}");
        for case in 0..CASES {
            let file = &files[rng.below(files.len())];
            let pristine = std::fs::read(file).expect("read");
            let (bytes, what) = mutate(&pristine, &mut rng);
            std::fs::write(file, &bytes).expect("write mutant");
            let format = if case % 2 == 0 { "svg" } else { "png" };
            let name = file.file_name().expect("name").to_string_lossy();
            let result = run(&["plot", path(&folder), "--format", format]);
            std::fs::write(file, &pristine).expect("restore");
            let fail = match result {
                Ok((Some(0), _)) => {
                    if std::env::var_os("PLOT_FUZZ_SHOW").is_some() {
                        eprintln!("{case} {name}: {what}: plotted");
                    }
                    plotted += 1;
                    continue;
                }
                Ok((Some(1), err)) if !err.contains("internal error") && !err.is_empty() => {
                    refused += 1;
                    if std::env::var_os("PLOT_FUZZ_SHOW").is_some() {
                        eprintln!("{case} {name}: {what}: {}", err.trim());
                    }
                    continue;
                }
                Ok((code, err)) => format!("exit {code:?}: {}", err.trim()),
                Err(hang) => hang,
            };
            let seed = folder.file_name().expect("seed").to_string_lossy();
            failures.push(format!(
                "{seed} case {case} ({format}), {name}: {what}: {fail}"
            ));
        }
    }
    eprintln!(
        "{plotted} mutants plotted, {refused} refused, {} failed, in {:.1} s",
        failures.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // Both outcomes occur: the mutations reach past the first check of the reader.
    assert!(
        plotted > 0 && refused > 0,
        "{plotted} plotted, {refused} refused"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
