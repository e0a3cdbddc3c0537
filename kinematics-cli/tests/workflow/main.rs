//! The command as an engineer uses it, in one test binary: values with
//! units, degrees out and assemblies without guesses
//! (`units_and_assemblies.rs`), and the figures of merit it prints
//! (`figures.rs`), and the report opened in a browser (`report.rs`).

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

#[path = "../common/mod.rs"]
mod common;
mod figures;
mod report;
mod simulate;
mod synthesize;
mod units_and_assemblies;
