//! The memory the construction of a rectangle mesh takes ([`Rectangle::mesh`]), computed from
//! `nx`, `ny` and the order before anything is allocated, so that a problem whose meshes do not
//! fit is refused ([`crate::memory::check`]) instead of aborting on a failed allocation.
//!
//! The estimate follows the allocations of the construction: the nodes (16 B each), the
//! connectivity, the boundary edges, and in [`Mesh::new`] the `used` and boundary-node flags (a
//! byte per node) and the map from each boundary edge to its triangles (a hash table of 40 B
//! entries, sized by powers of two, the old and the new table both alive while it grows); for P2
//! the promotion by [`Mesh::to_p2`]: the P1 mesh, its edge table (a start and a count per node,
//! a 16 B slot per triangle edge), and the P2 nodes, connectivity and boundaries, each allocated
//! at its final size. `crates/core/tests/mesh_memory.rs` measures the peak with a counting
//! allocator and checks that the estimate is above it and within twice of it.
//!
//! [`Rectangle::mesh`]: crate::Rectangle::mesh
//! [`Mesh::new`]: crate::Mesh::new
//! [`Mesh::to_p2`]: crate::Mesh::to_p2

use std::mem::size_of;

use crate::mesh::{Edge, Order};

/// The estimate for one mesh, bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshMemory {
    /// The most memory alive at once while the mesh is built.
    pub peak: u64,
    /// The memory the built mesh keeps.
    pub kept: u64,
}

/// The boundary names and the nodes of their map, whatever the mesh's size.
const NAMES: u64 = 4096;

/// The estimate for a rectangle mesh of `nx × ny` cells of order `order`.
pub fn rectangle(nx: usize, ny: usize, order: Order) -> MeshMemory {
    let (nx, ny) = (nx as u64, ny as u64);
    let cells = nx.saturating_mul(ny);
    let nodes = (nx + 1).saturating_mul(ny + 1);
    let edges = nx
        .saturating_mul(ny + 1)
        .saturating_add(ny.saturating_mul(nx + 1))
        .saturating_add(cells);
    let boundary = (2 * (nx + ny))
        .saturating_mul(size_of::<Edge>() as u64)
        .saturating_add(NAMES);
    let usize_bytes = size_of::<usize>() as u64;
    let point = 2 * size_of::<f64>() as u64;
    let p1_nodes = nodes.saturating_mul(point);
    let p1_cells = cells.saturating_mul(6 * usize_bytes);
    let p1_kept = p1_nodes.saturating_add(p1_cells).saturating_add(boundary);
    // Mesh::new: the new oriented boundaries beside the given ones, the `used` and boundary-node
    // flags and the boundary edge → owners map.
    let owners_entry = (2 + 3) as u64 * usize_bytes;
    let p1_peak = p1_kept
        .saturating_add(boundary)
        .saturating_add(nodes.saturating_mul(2))
        .saturating_add(table_peak(2 * (nx + ny), owners_entry));
    match order {
        Order::P1 => MeshMemory {
            peak: p1_peak,
            kept: p1_kept,
        },
        Order::P2 => {
            let p2_nodes = nodes.saturating_add(edges).saturating_mul(point);
            let p2_cells = cells.saturating_mul(12 * usize_bytes);
            let p2_kept = p2_nodes.saturating_add(p2_cells).saturating_add(boundary);
            // The edge table: a start (usize) and a count (u32) per node, a slot (two usize)
            // per edge of each triangle.
            let table = nodes
                .saturating_mul(usize_bytes + 4)
                .saturating_add(cells.saturating_mul(6 * 2 * usize_bytes));
            let promotion = p1_kept.saturating_add(table).saturating_add(p2_kept);
            MeshMemory {
                peak: p1_peak.max(promotion),
                kept: p2_kept,
            }
        }
    }
}

/// The peak of the memory estimates `meshes`, built one after the other, each kept: the most of
/// the kept memory of the meshes before one plus that one's peak.
pub fn sequence(meshes: impl IntoIterator<Item = MeshMemory>) -> u64 {
    let mut kept = 0u64;
    let mut peak = 0u64;
    for m in meshes {
        peak = peak.max(kept.saturating_add(m.peak));
        kept = kept.saturating_add(m.kept);
    }
    peak
}

/// The most bytes a hash table of `items` entries of `entry` bytes holds while filled one entry
/// at a time: the last table (buckets a power of two, at most 7/8 full) and the one before it,
/// alive together while the entries move, each with a control byte per bucket.
fn table_peak(items: u64, entry: u64) -> u64 {
    let mut buckets: u64 = 4;
    while capacity(buckets) < items {
        if buckets > u64::MAX / 4 {
            return u64::MAX;
        }
        buckets *= 2;
    }
    let bytes = |b: u64| b.saturating_mul(entry + 1).saturating_add(16);
    bytes(buckets).saturating_add(if buckets > 4 { bytes(buckets / 2) } else { 0 })
}

/// The entries a table of `buckets` holds before it grows.
fn capacity(buckets: u64) -> u64 {
    if buckets < 8 {
        buckets - 1
    } else {
        buckets / 8 * 7
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sequence_keeps_the_meshes_before() {
        let m = |peak, kept| MeshMemory { peak, kept };
        assert_eq!(sequence([m(10, 4), m(10, 4)]), 14);
        assert_eq!(sequence([m(10, 8), m(3, 1)]), 11);
        assert_eq!(sequence([]), 0);
    }

    #[test]
    fn tables_grow_by_powers_of_two() {
        assert_eq!(capacity(8), 7);
        // 7 entries fit in 8 buckets; 8 need 16, with the 8 of before alive while they move.
        assert_eq!(table_peak(7, 40), 8 * 41 + 16 + 4 * 41 + 16);
        assert_eq!(table_peak(8, 40), 16 * 41 + 16 + 8 * 41 + 16);
    }

    #[test]
    fn the_documented_limit_costs_gigabytes_in_p2() {
        // 4e6 cells: about 66 B per cell in P1, 330 B in P2.
        let m = rectangle(2000, 2000, Order::P1);
        assert!(m.peak > 200_000_000 && m.kept < m.peak, "{m:?}");
        let m = rectangle(2000, 2000, Order::P2);
        assert!(m.peak > 1 << 30 && m.kept < m.peak, "{m:?}");
        assert_eq!(rectangle(usize::MAX, usize::MAX, Order::P2).peak, u64::MAX);
        assert_eq!(rectangle(usize::MAX, 1, Order::P1).peak, u64::MAX);
        assert_eq!(table_peak(u64::MAX, 40), u64::MAX);
    }
}
