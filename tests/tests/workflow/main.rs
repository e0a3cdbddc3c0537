//! The engineer's workflow, in one test binary: the figures of merit
//! against their closed forms (`merit.rs`) and the textbooks' names for
//! coordinates and parameters (`names.rs`).

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod merit;
mod names;
