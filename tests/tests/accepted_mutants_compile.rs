//! Every mutated definition that the macro accepts (from the same seeded
//! generator as the macro's robustness test) expands to code that compiles:
//! an accepted definition never produces a type error in generated code.
//! This file failing to build is the test failing.

kinematics_macros::__fuzz_accepted!(61453, 3000);

#[test]
fn many_accepted_mutants_were_compiled() {
    // The build of this file type-checked every accepted expansion; make
    // sure that was a substantial number of distinct definitions.
    const { assert!(ACCEPTED_MUTANTS > 30, "too few accepted mutants") };
}
