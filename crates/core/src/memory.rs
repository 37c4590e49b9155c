//! Memory estimates checked against what the system has available, so that a problem too big for
//! the machine is refused with a message stating both numbers instead of aborting the process on a
//! failed allocation.

use thiserror::Error;

/// An estimate that exceeds the available memory.
#[derive(Debug, Error, Clone, PartialEq)]
#[error(
    "{what} needs about {} of memory, but only {} is available (MemAvailable in /proc/meminfo); \
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
}

/// The memory available to a new allocation: `MemAvailable` of `/proc/meminfo`, or `None` where
/// that cannot be read (then nothing is checked).
pub fn available() -> Option<u64> {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| mem_available(&text))
}

/// Fails if `needed` bytes exceed the available memory.
pub fn check(what: &str, needed: u64) -> Result<(), OutOfMemory> {
    match available() {
        Some(available) if needed > available => Err(OutOfMemory {
            what: what.to_string(),
            needed,
            available,
        }),
        _ => Ok(()),
    }
}

/// The `MemAvailable` line of a `/proc/meminfo` text, in bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
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
