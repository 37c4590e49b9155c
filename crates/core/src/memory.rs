//! Memory estimates checked against what the system has available, so that a problem too big for
//! the machine is refused with a message stating both numbers instead of aborting the process on a
//! failed allocation.
//!
//! The available memory is the least of `MemAvailable` (`/proc/meminfo`) and, under an address
//! space limit (`ulimit -v`, `RLIMIT_AS`), that limit less the process's address space now
//! (`VmSize` of `/proc/self/status`). The environment variable [`AVAILABLE_ENV`], a number of
//! bytes, replaces both: tests use it to check refusals without allocating gigabytes.

use thiserror::Error;

/// An estimate that exceeds the available memory.
#[derive(Debug, Error, Clone, PartialEq)]
#[error(
    "{what} needs about {} of memory, but only {} is available ({origin}); \
     use coarser meshes or a machine with more memory",
    size(*needed),
    size(*available)
)]
pub struct OutOfMemory {
    /// What needs the memory.
    pub what: String,
    /// The estimate, bytes.
    pub needed: u64,
    /// The available memory, bytes.
    pub available: u64,
    /// Where the available memory was read: `MemAvailable in /proc/meminfo`, `the address space
    /// limit (ulimit -v) less VmSize` or the variable [`AVAILABLE_ENV`].
    pub origin: String,
}

/// The environment variable that, set to a number of bytes, is taken as the available memory
/// instead of what the system reports (for tests of the refusals).
pub const AVAILABLE_ENV: &str = "CONTACTDD_MEM_AVAILABLE";

/// The memory available to a new allocation: the least of `MemAvailable` of `/proc/meminfo` and
/// the headroom under an address space limit (see the module documentation), or `None` where
/// neither can be read (then nothing is checked).
pub fn available() -> Option<u64> {
    available_from().map(|(bytes, _)| bytes)
}

/// The available memory and where it was read.
fn available_from() -> Option<(u64, String)> {
    if let Ok(value) = std::env::var(AVAILABLE_ENV) {
        if let Ok(bytes) = value.trim().parse::<u64>() {
            return Some((bytes, format!("{AVAILABLE_ENV} in the environment")));
        }
    }
    let read = |path: &str| std::fs::read_to_string(path).ok();
    let meminfo = read("/proc/meminfo")
        .and_then(|text| mem_available(&text))
        .map(|b| (b, "MemAvailable in /proc/meminfo".to_string()));
    let limit = read("/proc/self/limits")
        .and_then(|text| address_space_limit(&text))
        .and_then(|limit| {
            let used = read("/proc/self/status").and_then(|text| vm_size(&text))?;
            let source = "the address space limit (ulimit -v) less VmSize".to_string();
            Some((limit.saturating_sub(used), source))
        });
    match (meminfo, limit) {
        (Some(a), Some(b)) => Some(if b.0 < a.0 { b } else { a }),
        (a, b) => a.or(b),
    }
}

/// Fails if `needed` bytes exceed the available memory.
pub fn check(what: &str, needed: u64) -> Result<(), OutOfMemory> {
    match available_from() {
        Some((available, source)) if needed > available => Err(OutOfMemory {
            what: what.to_string(),
            needed,
            available,
            origin: source,
        }),
        _ => Ok(()),
    }
}

/// The soft `Max address space` of a `/proc/self/limits` text, in bytes (`None` if unlimited).
fn address_space_limit(limits: &str) -> Option<u64> {
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The `VmSize` line of a `/proc/self/status` text, in bytes.
fn vm_size(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmSize:"))?;
    kilobytes(line)
}

/// The `MemAvailable` line of a `/proc/meminfo` text, in bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    kilobytes(line)
}

/// The number of a `/proc` line `Key:   123 kB`, in bytes.
fn kilobytes(line: &str) -> Option<u64> {
    let mut words = line.split_whitespace().skip(1);
    let value: u64 = words.next()?.parse().ok()?;
    let unit = match words.next() {
        Some("kB") => 1024,
        None => 1,
        Some(_) => return None,
    };
    value.checked_mul(unit)
}

/// Bytes with a binary prefix: `1.5 GiB`.
fn size(bytes: u64) -> String {
    let mut value = bytes as f64;
    for unit in ["B", "KiB", "MiB", "GiB", "TiB"] {
        if value < 1024.0 {
            return format!("{value:.1} {unit}");
        }
        value /= 1024.0;
    }
    format!("{value:.1} PiB")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_available_is_read_in_bytes() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   2000000 kB\n";
        assert_eq!(mem_available(text), Some(2_048_000_000));
        assert_eq!(mem_available("MemFree: 1 kB\n"), None);
        assert_eq!(mem_available("MemAvailable: x kB\n"), None);
    }

    #[test]
    fn the_address_space_limit_is_read_in_bytes() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max address space         4294967296           unlimited            bytes\n";
        assert_eq!(address_space_limit(limits), Some(4 << 30));
        let unlimited =
            "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(address_space_limit(unlimited), None);
        assert_eq!(vm_size("Name: x\nVmSize:\t  123 kB\n"), Some(123 * 1024));
    }

    #[test]
    fn sizes_read_with_binary_prefixes() {
        assert_eq!(size(512), "512.0 B");
        assert_eq!(size(3 << 30), "3.0 GiB");
    }

    #[test]
    fn an_estimate_beyond_any_machine_is_refused() {
        if available().is_none() {
            return;
        }
        let e = check("a test", u64::MAX).unwrap_err();
        assert!(e.available < u64::MAX && e.to_string().contains("a test needs about"));
        assert_eq!(check("a test", 0), Ok(()));
    }
}
