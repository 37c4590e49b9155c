//! What one rank of a solve spent: communication and peak memory, for the report of a
//! distributed run.

/// What one rank spent, for the report of a distributed run.
#[derive(Clone, Copy, Debug)]
pub struct RankUse {
    /// Seconds in the exchanges (including waiting for the other ranks).
    pub communication: f64,
    /// Values received from the other ranks by all-gathers.
    pub gathered: f64,
    /// Values received from the other ranks point to point.
    pub point_to_point: f64,
    /// Peak resident memory, MiB (0 where the system does not say).
    pub peak_mib: f64,
}

/// The peak resident memory of this process, MiB, from `/proc/self/status` (0 elsewhere).
pub fn peak_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kib| kib / 1024.0)
}
