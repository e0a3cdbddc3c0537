//! Every mutated definition with `bodies` and `loads` sections (loads of
//! the rates and of the time among them) that the macro accepts expands
//! to code that compiles, its dynamics sections included. This file
//! failing to build is the test failing.

kinematics_macros::__fuzz_accepted!(7331, 1500, 1);

#[test]
fn many_accepted_mutants_with_loads_were_compiled() {
    const { assert!(ACCEPTED_MUTANTS > 30, "too few accepted mutants") };
}
