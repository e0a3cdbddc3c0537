//! A definition that cannot work is a compile error at the offending tokens,
//! in a mechanical engineer's words. One case per diagnostic, in folders by
//! category; each `.stderr` is the reviewed expected output
//! (regenerate with `TRYBUILD=overwrite` and review the diff).

#[test]
fn definitions_with_errors_do_not_compile() {
    let t = trybuild::TestCases::new();
    t.compile_fail("ui/[!p]*/*.rs");
    // Edge shapes the macro accepts must compile and run.
    t.pass("ui/pass/*.rs");
}
