//! Benchmarks of the code `mechanism!` generates; see `benches/steps/`.
//!
//! `cargo bench -p kinematics-bench --bench steps` prints the table of the
//! README's performance section.
