//! Assembling near a known pose and analysing velocities and accelerations
//! allocate nothing on the heap.
//!
//! A counting global allocator records every allocation of this test
//! binary; the hot path must leave the count unchanged.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]
// Implementing `GlobalAlloc` requires `unsafe`; it only forwards to the
// system allocator and counts.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use kinematics_examples::{FourBar, RRtrRrt};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every method forwards to `System` with the caller's arguments,
// which upholds the `GlobalAlloc` contract unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        // SAFETY: same layout as requested.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by `System` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        // SAFETY: forwarded unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn assemble_and_analyze_allocate_nothing() {
    let m = FourBar::CRANK_ROCKER;
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let six = RRtrRrt::EXAMPLE_4_2;
    let mut pose6 = six
        .assemble(&RRtrRrt::example_4_2_guess())
        .expect("assembles");
    let mut checksum = 0.0;
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for k in 0..3600 {
        let phi = f64::from(k) * std::f64::consts::TAU / 3600.0;
        pose.phi = phi;
        pose = m.assemble(&pose).expect("assembles");
        let s = m.analyze(&pose, 10.0, 2.0).expect("analysis");
        checksum += s.qdd.th4 + s.point_p().acceleration.x;
        pose6.phi = std::f64::consts::FRAC_PI_4 + 0.1 * phi.sin();
        pose6 = six.assemble(&pose6).expect("assembles");
        let s6 = six.analyze(&pose6, 4.712, 0.0).expect("analysis");
        checksum += s6.qdd.phi4 + s6.point_e().acceleration.x;
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert!(checksum.is_finite());
    assert_eq!(
        after - before,
        0,
        "the hot path allocated {} times",
        after - before
    );
}
