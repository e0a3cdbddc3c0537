//! Benchmarks of the code `mechanism!` generates; see `benches/steps/`.
//!
//! `cargo bench -p kinematics-bench --bench steps` prints the table of the
//! README's performance section.

/// CPU time of the calling thread, in nanoseconds: what the benchmarks
/// time, so that other jobs on the machine count only through the caches
/// and the clock they share.
///
/// # Panics
/// If the clock cannot be read (it always can on Linux).
#[allow(unsafe_code)]
#[must_use]
pub fn thread_cpu_ns() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to write into.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &raw mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    #[allow(clippy::cast_precision_loss)]
    let ns = t.tv_sec as f64 * 1e9 + t.tv_nsec as f64;
    ns
}
