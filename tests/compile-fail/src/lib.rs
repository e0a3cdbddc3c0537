//! The compile-fail cases of mechanism definitions (`ui/`, checked by
//! `tests/compile_fail.rs` with trybuild): a crate of their own, whose
//! only dependency is the library with its default features, so that the
//! project trybuild makes for them builds that and nothing else.
#![no_std]
