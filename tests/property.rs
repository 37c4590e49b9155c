//! A property test of the whole solve on random multi-body problems (tests/support/
//! random_problem.rs draws them as problem files: 2–5 bodies in a column or a row, moduli 1e-12 …
//! 1e12 apart, length scales 1e-6 … 1e6, P1 and P2, random penalties, loads, gaps, friction and
//! supports). Every case is loaded, prepared and solved with the default settings (the interface
//! Newton method) on its own thread, and
//!
//! - nothing may panic, and no case may run longer than `CASE_SECONDS` (a hang fails);
//! - a converged result must balance: its applied loads, support reactions and contact forces,
//!   read from what a user sees (the model's load vectors at the load factor,
//!   `contactdd_io::reactions`, `PairResult::force_on`) and summed here, must cancel to 1e-6 —
//!   per body relative to the largest force total of a body, and over the whole problem (whose
//!   balanced pairs cancel) relative to Σ|applied| + Σ|reactions|; every reported number must be
//!   finite;
//! - a refusal (a load error, a setup error or a stop other than `converged`) must say why: a
//!   non-empty message without a NaN in it.
//!
//! The solver's own balance check (crates/ddm/src/force_balance.rs) is not used.
//!
//! `CONTACTDD_PROPERTY_CASES=N` runs N cases instead of the CI budget (`scripts/property_long.sh`
//! runs a long budget); `CONTACTDD_PROPERTY_CASE=k` runs case k alone and prints its problem file.

#[path = "support/random_problem.rs"]
mod random_problem;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use contactdd::ddm::{prepare, solve, Forces, Hooks, Model, Solution};
use contactdd::io::load_str;
use contactdd::io::reactions::reactions;
use contactdd::io::summary::stop_name;

/// Cases run in CI (cases 0 to 199, a few seconds); `scripts/property_long.sh` runs more
/// (docs/input-checks.md, "Random problems").
const CI_CASES: u64 = 200;
/// The wall-time cap of one case.
const CASE_SECONDS: u64 = 60;
/// The balance a converged result must meet.
const TOL: f64 = 1e-6;

/// How a case ended.
enum Verdict {
    /// Converged and balanced.
    Converged,
    /// Refused, under this name (`load`, `prepare`, `setup` or a stop name).
    Refused(&'static str),
    /// A property failed.
    Failed(String),
}

fn norm(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

/// `x ≤ limit`, false for a NaN.
fn within(x: f64, limit: f64) -> bool {
    x <= limit
}

fn add(a: &mut [f64; 2], b: [f64; 2]) {
    a[0] += b[0];
    a[1] += b[1];
}

/// The balance of a converged result, from the loads, the reactions and the contact forces.
fn balance(model: &Model, sol: &Solution) -> Result<(), String> {
    let n = model.bodies.len();
    let mut applied = vec![[0.0; 2]; n];
    for (b, body) in model.bodies.iter().enumerate() {
        for node in body.load.chunks(2) {
            add(
                &mut applied[b],
                [node[0] * sol.load_factor, node[1] * sol.load_factor],
            );
        }
    }
    let mut contact = vec![[0.0; 2]; n];
    let mut contact_size = vec![0.0; n];
    let mut balanced = true;
    for (pair, result) in model.pairs.iter().zip(&sol.contact) {
        balanced &= pair.forces == Forces::Balanced;
        for side in 0..2 {
            let f = result.force_on(side);
            add(&mut contact[pair.bodies[side]], f);
            contact_size[pair.bodies[side]] += norm(f);
        }
    }
    let reactions = reactions(model, &sol.bodies, &sol.contact);
    if reactions.len() != n {
        return Err(format!("reactions of {} bodies of {n}", reactions.len()));
    }
    let mut reaction = vec![[0.0; 2]; n];
    let mut reaction_size = vec![0.0; n];
    for (b, r) in reactions.iter().enumerate() {
        for s in &r.supports {
            add(&mut reaction[b], s.force);
            reaction_size[b] += norm(s.force);
        }
        if norm([reaction[b][0] - r.total[0], reaction[b][1] - r.total[1]])
            > 1e-9 * reaction_size[b]
        {
            return Err(format!(
                "body {b}: the supports' reactions do not add up to the total"
            ));
        }
    }
    let finite = |v: [f64; 2]| v[0].is_finite() && v[1].is_finite();
    if !(applied.iter().chain(&contact).chain(&reaction)).all(|&v| finite(v)) {
        return Err("a non-finite load, reaction or contact force".into());
    }
    let totals: Vec<f64> = (0..n)
        .map(|b| norm(applied[b]) + reaction_size[b] + contact_size[b])
        .collect();
    let scale = totals.iter().fold(0.0f64, |a, &t| a.max(t));
    let mut out = Vec::new();
    for b in 0..n {
        let mut net = applied[b];
        add(&mut net, reaction[b]);
        add(&mut net, contact[b]);
        if !within(norm(net), TOL * scale) {
            out.push(format!(
                "body b{b}: |applied + reactions + contact| = {:.3e} of {scale:.3e} (applied {:?}, reactions {:?}, contact {:?})",
                norm(net) / scale, applied[b], reaction[b], contact[b]
            ));
        }
    }
    if balanced {
        let (mut net, mut size) = ([0.0; 2], 0.0);
        for b in 0..n {
            add(&mut net, applied[b]);
            add(&mut net, reaction[b]);
            size += norm(applied[b]) + reaction_size[b];
        }
        if !within(norm(net), TOL * size) {
            out.push(format!(
                "whole problem: |Σ applied + Σ reactions| = {:.3e} of Σ|applied| + Σ|reactions| = {size:.3e}",
                norm(net) / size
            ));
        }
    }
    if out.is_empty() {
        Ok(())
    } else {
        Err(format!("converged but out of balance: {}", out.join("; ")))
    }
}

/// A refusal's message must say something, and no NaN.
fn refusal(name: &'static str, message: &str) -> Verdict {
    if message.trim().is_empty() {
        Verdict::Failed(format!("{name} without a message"))
    } else if message.contains("NaN") {
        Verdict::Failed(format!("{name} with a NaN in its message: {message}"))
    } else {
        Verdict::Refused(name)
    }
}

/// Loads, prepares and solves one problem text, and judges the result.
fn judge(text: &str, cancel: &AtomicBool) -> Verdict {
    let loaded = match load_str(text, "random.toml", Path::new(".")) {
        Ok(l) => l,
        Err(e) => return refusal("load", &e.to_string()),
    };
    let prepared = match prepare(&loaded.model) {
        Ok(p) => p,
        Err(e) => return refusal("prepare", &e.to_string()),
    };
    let hooks = Hooks {
        cancel: Some(cancel),
        ..Hooks::default()
    };
    let sol = match solve(&loaded.model, &prepared, &loaded.settings, hooks) {
        Ok(s) => s,
        Err(e) => return refusal("setup", &e.to_string()),
    };
    if !sol.converged {
        return refusal(stop_name(&sol.stop), sol.message.as_deref().unwrap_or(""));
    }
    match balance(&loaded.model, &sol) {
        Ok(()) => Verdict::Converged,
        // The solver's own figures, for the report only.
        Err(e) => Verdict::Failed(format!(
            "{e} [the solver's balance: imbalance {:.2e}, floor {:.2e}]",
            sol.balance
                .bodies
                .iter()
                .fold(0.0f64, |a, b| a.max(b.imbalance)),
            sol.balance
                .bodies
                .iter()
                .fold(0.0f64, |a, b| a.max(b.floor)),
        )),
    }
}

/// Runs one case on its own thread, under `catch_unwind` and the time cap.
fn run_case(text: String) -> Verdict {
    let cancel = Arc::new(AtomicBool::new(false));
    let (send, receive) = mpsc::channel();
    let flag = Arc::clone(&cancel);
    std::thread::spawn(move || {
        let verdict = catch_unwind(AssertUnwindSafe(|| judge(&text, &flag)))
            .unwrap_or_else(|_| Verdict::Failed("panicked".into()));
        let _ = send.send(verdict);
    });
    match receive.recv_timeout(Duration::from_secs(CASE_SECONDS)) {
        Ok(verdict) => verdict,
        Err(_) => {
            // Ask the solve to stop so that the next cases get the cores back.
            cancel.store(true, Ordering::Relaxed);
            let _ = receive.recv_timeout(Duration::from_secs(CASE_SECONDS));
            Verdict::Failed(format!("no answer within {CASE_SECONDS} s (a hang)"))
        }
    }
}

fn env(name: &str) -> Option<u64> {
    std::env::var(name).ok().and_then(|v| v.trim().parse().ok())
}

#[test]
fn random_problems_balance_when_converged_and_never_panic_nor_hang() {
    let start = Instant::now();
    let cases: Vec<u64> = match env("CONTACTDD_PROPERTY_CASE") {
        Some(k) => vec![k],
        None => (0..env("CONTACTDD_PROPERTY_CASES").unwrap_or(CI_CASES)).collect(),
    };
    let (mut converged, mut refused) = (0usize, BTreeMap::<&str, usize>::new());
    let (mut failures, mut slowest) = (Vec::new(), 0.0f64);
    for &k in &cases {
        let drawn = random_problem::draw(k);
        if cases.len() == 1 {
            eprintln!("case {k}: {}\n{}", drawn.what, drawn.text);
        }
        let t = Instant::now();
        let verdict = run_case(drawn.text);
        slowest = slowest.max(t.elapsed().as_secs_f64());
        match verdict {
            Verdict::Converged => converged += 1,
            Verdict::Refused(name) => *refused.entry(name).or_default() += 1,
            Verdict::Failed(e) => {
                eprintln!("FAILED case {k} ({}): {e}", drawn.what);
                failures.push(k);
            }
        }
    }
    let refusals: Vec<String> = refused.iter().map(|(k, v)| format!("{k} {v}")).collect();
    eprintln!(
        "property: {} cases, {converged} converged, refused: {}; {} failures {failures:?}; slowest case {slowest:.2} s, {:.1} s in all",
        cases.len(),
        if refusals.is_empty() {
            "none".into()
        } else {
            refusals.join(", ")
        },
        failures.len(),
        start.elapsed().as_secs_f64()
    );
    eprintln!("| outcome | cases |\n|---|---:|\n| converged, balanced | {converged} |");
    for (name, count) in &refused {
        eprintln!("| refused: {name} | {count} |");
    }
    eprintln!("| failed | {} |", failures.len());
    assert!(
        failures.is_empty(),
        "failed cases {failures:?} (rerun one with CONTACTDD_PROPERTY_CASE=k)"
    );
    assert!(
        cases.len() < 10 || 2 * converged >= cases.len(),
        "only {converged} of {} cases converged: the test checks too little",
        cases.len()
    );
}
