//! A global allocator that forwards to the system's and counts, per
//! thread, the bytes live and their peak: for the tests and benchmarks
//! that measure memory in proportion to their input. A binary installs it
//! with `#[global_allocator] static GLOBAL: Counting = Counting;`.
// Implementing `GlobalAlloc` requires `unsafe`; it only forwards to the
// system allocator and counts.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The counting allocator.
pub struct Counting;

thread_local! {
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn add(bytes: isize) {
    // `try_with`: nothing is counted while the thread's locals are torn
    // down.
    let _ = LIVE.try_with(|live| {
        let now = live.get() + bytes;
        live.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call is forwarded unchanged to the system allocator, which
// upholds the `GlobalAlloc` contract; the counting touches no memory the
// allocator hands out.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size() as isize);
        // SAFETY: same layout as requested.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        add(-(layout.size() as isize));
        // SAFETY: `ptr` was allocated by `System` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        add(new_size as isize - layout.size() as isize);
        // SAFETY: as for `System::realloc`, with the caller's guarantees.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// The bytes live on this thread (allocated less freed since it started,
/// or since the last [`reset`]), and their peak since the last call, which
/// starts the next peak from the bytes live now.
#[must_use]
pub fn live_and_peak() -> (isize, isize) {
    let live = LIVE.with(Cell::get);
    let peak = PEAK.with(|p| p.replace(live));
    (live, peak)
}

/// Counts this thread's live bytes and their peak from zero.
pub fn reset() {
    LIVE.with(|l| l.set(0));
    PEAK.with(|p| p.set(0));
}
