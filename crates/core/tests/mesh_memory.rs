//! The estimate of `contactdd_core::mesh_memory` against the memory a rectangle mesh's
//! construction really takes, measured by a counting global allocator: the estimate is at least
//! the measured peak (so a refusal never lets a mesh through that would not fit) and at most
//! twice it (so a mesh that fits is not refused).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};

use contactdd_core::mesh_memory::{self, MeshMemory};
use contactdd_core::{Diagonal, Order, Rectangle};

/// The system allocator, counting the bytes alive and their peak.
struct Counting;

static ALIVE: AtomicU64 = AtomicU64::new(0);
static PEAK: AtomicU64 = AtomicU64::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            let now =
                ALIVE.fetch_add(layout.size() as u64, Ordering::SeqCst) + layout.size() as u64;
            PEAK.fetch_max(now, Ordering::SeqCst);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        System.dealloc(p, layout);
        ALIVE.fetch_sub(layout.size() as u64, Ordering::SeqCst);
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The measured peak and kept bytes of building the mesh of `nx × ny` cells of `order`.
fn measured(nx: usize, ny: usize, order: Order) -> MeshMemory {
    let rectangle = Rectangle {
        origin: [0.0, 0.0],
        corner: [2.0, 1.0],
        nx,
        ny,
        diagonal: Diagonal::Alternate,
        mirror: false,
        order,
    };
    let before = ALIVE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let mesh = rectangle.mesh().unwrap();
    let peak = PEAK.load(Ordering::SeqCst) - before;
    let kept = ALIVE.load(Ordering::SeqCst) - before;
    drop(mesh);
    MeshMemory { peak, kept }
}

// One test only: the counts are global, and tests of one file run on parallel threads.
#[test]
fn the_estimate_bounds_the_measured_peak_within_twice() {
    let mut two_bodies = Vec::new();
    for (nx, ny) in [(40, 20), (300, 100), (1000, 500), (200, 1500)] {
        for order in [Order::P1, Order::P2] {
            let m = measured(nx, ny, order);
            let e = mesh_memory::rectangle(nx, ny, order);
            let ratio = e.peak as f64 / m.peak as f64;
            println!(
                "{nx} × {ny} {order:?}: measured peak {} B ({:.0} B per cell), kept {} B; \
                 estimate {} B, {} B (peak ratio {ratio:.2})",
                m.peak,
                m.peak as f64 / (nx * ny) as f64,
                m.kept,
                e.peak,
                e.kept
            );
            assert!(
                e.peak >= m.peak && ratio <= 2.0,
                "{nx} × {ny} {order:?}: {e:?} vs {m:?}"
            );
            assert!(
                e.kept >= m.kept && e.kept as f64 <= 2.0 * m.kept as f64,
                "{nx} × {ny} {order:?}: {e:?} vs {m:?}"
            );
            two_bodies.push((m, e));
        }
    }
    // Two bodies built one after the other, the first kept: measured as the sequence of both.
    let first = measured(300, 100, Order::P2);
    let before = ALIVE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let a = Rectangle {
        origin: [0.0, 0.0],
        corner: [1.0, 1.0],
        nx: 300,
        ny: 100,
        diagonal: Diagonal::Right,
        mirror: false,
        order: Order::P2,
    };
    let b = Rectangle {
        mirror: true,
        nx: 1000,
        ny: 500,
        ..a.clone()
    };
    let meshes = (a.mesh().unwrap(), b.mesh().unwrap());
    let peak = PEAK.load(Ordering::SeqCst) - before;
    drop(meshes);
    let estimate = mesh_memory::sequence([
        mesh_memory::rectangle(300, 100, Order::P2),
        mesh_memory::rectangle(1000, 500, Order::P2),
    ]);
    assert!(first.peak > 0);
    assert!(
        estimate >= peak && estimate as f64 <= 2.0 * peak as f64,
        "{estimate} vs {peak}"
    );
}
