//! A problem at the documented size limit (two bodies of 4 000 000 rectangle cells) is refused by
//! the estimate of its mesh construction, exit 1 with both numbers, when the memory is short:
//! with the available memory set by `CONTACTDD_MEM_AVAILABLE`, and under an address space limit
//! (`ulimit -v`), where the construction used to die by SIGABRT. Nothing large is allocated: the
//! refusal comes before any mesh is built.

use std::path::PathBuf;
use std::process::{Command, Output};

use contactdd_core::mesh_memory;
use contactdd_core::Order;

/// A problem file of two bodies of `n × n` cells each.
fn problem(n: usize, tag: &str) -> PathBuf {
    let text = format!(
        r#"
plane = "strain"

[materials.steel]
young = 2.1e5
poisson = 0.3

[[bodies]]
name = "lower"
material = "steel"
mesh = {{ kind = "rectangle", x = [0.0, 4.0], y = [0.0, 1.0], nx = {n}, ny = {n}, order = "p2" }}
supports = [{{ boundary = "bottom", component = "both", value = 0.0 }}]

[[bodies]]
name = "upper"
material = "steel"
mesh = {{ kind = "rectangle", x = [0.0, 4.0], y = [1.0, 2.0], nx = {n}, ny = {n}, mirror = true, order = "p2" }}
supports = [{{ boundary = "top", component = "y", value = -0.01 }}, {{ boundary = "left", component = "x", value = 0.0 }}]

[[contact]]
name = "interface"
bodies = ["lower", "upper"]
boundaries = ["top", "bottom"]
penalty = {{ c = 0.05, h = 1.0 }}
"#
    );
    let path = std::env::temp_dir().join(format!(
        "contactdd-memory-{tag}-{}.toml",
        std::process::id()
    ));
    std::fs::write(&path, text).unwrap();
    path
}

fn check(file: &PathBuf, available: Option<u64>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_contactdd"));
    command.arg("check").arg(file);
    if let Some(bytes) = available {
        command.env("CONTACTDD_MEM_AVAILABLE", bytes.to_string());
    }
    command.output().expect("contactdd runs")
}

#[test]
fn two_bodies_at_the_limit_are_refused_when_memory_is_short() {
    let file = problem(2000, "limit");
    // Room for one body's construction, not for the second beside the first.
    let one = mesh_memory::rectangle(2000, 2000, Order::P2);
    let run = check(&file, Some(one.peak + 1));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{run:?}");
    assert!(
        stderr.contains("building the rectangle meshes of 2 bodies needs about")
            && stderr.contains("GiB of memory, but only")
            && stderr.contains("is available (CONTACTDD_MEM_AVAILABLE in the environment)"),
        "{stderr}"
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_small_problem_passes_the_same_check() {
    let file = problem(8, "small");
    let run = check(&file, Some(1 << 30));
    assert!(run.status.success(), "{run:?}");
    let _ = std::fs::remove_file(&file);
}

#[cfg(target_os = "linux")]
#[test]
fn an_address_space_limit_refuses_before_building() {
    let file = problem(2000, "ulimit");
    // 1.5 GB of address space: less than the two P2 bodies' construction. Were the estimate not checked,
    // the construction would abort (exit 134) at this limit, having used at most 1.5 GB.
    let run = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 1500000 && exec \"$0\" check \"$1\"")
        .arg(env!("CARGO_BIN_EXE_contactdd"))
        .arg(&file)
        .env_remove("CONTACTDD_MEM_AVAILABLE")
        .output()
        .expect("sh runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{run:?}");
    assert!(
        stderr.contains("needs about")
            && stderr.contains("(the address space limit (ulimit -v) less VmSize)"),
        "{stderr}"
    );
    let _ = std::fs::remove_file(&file);
}
