//! Definitions given as text are untrusted input: the adversarial cases
//! that used to abort the process, take quadratic time or memory, give a
//! wrong number or grow the compiling thread are answered with a located
//! error (or the right number), on a thread of 2 MiB of stack, with memory
//! in proportion to the text.
//!
//! A counting global allocator records, per thread, the bytes live and
//! their peak.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic, clippy::unwrap_used)]

use kinematics_compiler::{compile_str, limits, Diagnostics};
use kinematics_core::runtime::Model;
use kinematics_tests::heap::{live_and_peak, Counting};

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `f` on a fresh thread of 2 MiB of stack (the default of a spawned
/// thread, and what a web server's worker or a notebook's thread has).
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .expect("a thread")
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e))
}

/// The four-bar with `rhs` as its loop's right-hand side.
fn four_bar(rhs: &str) -> String {
    format!(
        "pub struct FourBar {{\n    params {{ a, b, c, d }}\n    drivers {{ phi }}\n    \
         unknowns {{ th3, th4 }}\n    loops {{ polar(a, phi) + polar(b, th3) == {rhs}; }}\n}}"
    )
}

/// The errors of `text`, which must not compile.
fn errors(text: &str) -> Diagnostics {
    match compile_str(text) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// `polar((((…1000 deep…c…))), th4)` aborted a 2 MiB thread (300 deep
/// passed): now an error at the parenthesis past the limit, in words;
/// 40 deep compiles.
#[test]
fn deep_parentheses_are_an_error_at_the_limit() {
    on_small_stack(|| {
        for depth in [100, 1000, 100_000] {
            let rhs = format!(
                "vec2(d, 0.0) + polar({}c{}, th4)",
                "(".repeat(depth),
                ")".repeat(depth)
            );
            let e = errors(&four_bar(&rhs));
            let d = &e.0[0];
            assert!(
                d.message
                    .contains(&format!("nest more than {} deep", limits::MAX_NESTING)),
                "{e}"
            );
            // At a parenthesis on the loop's line.
            assert_eq!(d.line, 5, "{e}");
            assert!(d.excerpt[d.column - 1..].starts_with('('), "{e}");
        }
        let rhs = format!(
            "vec2(d, 0.0) + polar({}c{}, th4)",
            "(".repeat(40),
            ")".repeat(40)
        );
        assert!(compile_str(&four_bar(&rhs)).is_ok());
    });
}

/// `sin(sin(…))` 1000 deep aborted a 2 MiB thread: an error at the limit.
#[test]
fn deep_calls_are_an_error_at_the_limit() {
    on_small_stack(|| {
        let rhs = format!(
            "vec2(d, 0.0) + polar(c + 0.0 * {}phi{}, th4)",
            "sin(".repeat(1000),
            ")".repeat(1000)
        );
        let e = errors(&four_bar(&rhs));
        assert!(e.0[0].message.contains("nest more than"), "{e}");
    });
}

/// `a + 1.0 + …` with 3000 terms aborted a 2 MiB thread (a long sum is a
/// deep tree): an error at the expression's first token that names the
/// limit; a sum of 100 terms compiles.
#[test]
fn long_sums_are_an_error_at_the_limit() {
    on_small_stack(|| {
        let sum = |n: usize| format!("vec2(d, 0.0) + polar(c{}, th4)", " + 0.0 * a".repeat(n));
        let e = errors(&four_bar(&sum(3000)));
        let d = &e.0[0];
        assert!(
            d.message.contains(&format!(
                "more than {} tokens",
                limits::MAX_EXPRESSION_TOKENS
            )),
            "{e}"
        );
        assert_eq!(d.line, 5, "{e}");
        assert!(compile_str(&four_bar(&sum(50))).is_ok());
        // A chain of 3000 signs likewise.
        let signs = format!("vec2(d, 0.0) + polar({}c, th4)", "- -".repeat(1000));
        assert!(errors(&four_bar(&signs)).0[0].message.contains("tokens"));
    });
}

/// A 64 KiB (and a 1 MiB) name used with its last letter changed took 13–16
/// s (and over 60 s) looking for a "did you mean": it is an unknown name,
/// with no hint for a name no person types; a short misspelling, a
/// transposition included, still gets its hint.
#[test]
fn long_misspelt_names_get_no_quadratic_hint() {
    on_small_stack(|| {
        for length in [64 << 10, 1 << 20] {
            let name: String = (0..length)
                .map(|i| char::from(b'a' + (i % 26) as u8))
                .collect();
            let mut used = name.clone();
            used.pop();
            used.push('Z');
            let text = four_bar(&format!("vec2(d, 0.0) + polar(c + 0.0 * {used}, th4)")).replace(
                "params { a, b, c, d }",
                &format!("params {{ a, b, c, d, {name} }}"),
            );
            let e = errors(&text);
            assert!(
                e.0[0].message.starts_with("unknown name"),
                "{}",
                e.0[0].message.len()
            );
            assert!(!e.0[0].message.contains("did you mean"));
        }
        let text = four_bar("vec2(d, 0.0) + polar(c, th4)")
            .replace("params { a, b, c, d }", "params { a, b, c, d, beta }")
            .replace("polar(c, th4)", "polar(c, th4 + btea)");
        let e = errors(&text);
        assert!(e.0[0].message.contains("did you mean `beta`"), "{e}");
    });
}

/// `params { a, b, p, p, … }` with 10 000 duplicates on one line (30 KB)
/// peaked at 584 MiB, each diagnostic holding a copy of the line: now
/// 10 000 names are past the limit of items (one error), and below it the
/// diagnostics share the text, the peak in proportion to its length (the
/// same bytes per byte of text at 1 000 and at 4 500 duplicates, up to
/// the doubling of vectors).
#[test]
fn many_errors_on_one_line_share_the_text() {
    on_small_stack(|| {
        let peak_per_byte = |n: usize| {
            let text = four_bar("vec2(d, 0.0) + polar(c, th4)").replace(
                "params { a, b, c, d }",
                &format!("params {{ a, b, c, d{} }}", ", p".repeat(n)),
            );
            let before = live_and_peak().0;
            let e = errors(&text);
            // Every duplicate, each with a note at the first declaration.
            assert_eq!(e.0.len(), 2 * (n - 1), "every duplicate is reported");
            // One text behind every excerpt.
            let first = e.0[0].excerpt.as_ptr();
            assert!(e.0.iter().all(|d| d.excerpt.as_ptr() == first));
            // The printed errors show a window of the line, not all of it.
            let shown = e.0[n / 2].to_string();
            assert!(shown.len() < 600, "{}", shown.len());
            drop(e);
            let (_, peak) = live_and_peak();
            (peak - before) as f64 / text.len() as f64
        };
        let text = four_bar("vec2(d, 0.0) + polar(c, th4)").replace(
            "params { a, b, c, d }",
            &format!("params {{ a, b, c, d{} }}", ", p".repeat(10_000)),
        );
        let e = errors(&text);
        assert_eq!(e.0.len(), 1, "{e}");
        assert!(e.0[0].message.contains("items"), "{e}");
        let small = peak_per_byte(1000);
        let large = peak_per_byte(4500);
        println!("peak bytes per byte of text: {small:.0} at 1000 duplicates, {large:.0} at 4500");
        // Linear, up to the doubling of the vectors' capacities (measured:
        // 127 to 190 bytes per byte from 250 to 4 900 duplicates, not in
        // order of size).
        assert!(large < 2.0 * small, "{small} {large}");
        assert!(large < 500.0, "{large}");
    });
}

/// `powi(1.0 + 1e-10 φ, -2147483647)` gave an acceleration wrong by a
/// factor 1.1375 (n − 1 wrapped around i32 in the derivative): exponents
/// past ±65536 are an error at the exponent, and one at the limit gives
/// the closed form's x' = n y^(n−1) ε φ' and x'' = n (n−1) y^(n−2) ε² φ'²
/// with y = 1 + ε φ.
#[test]
fn large_powi_exponents_are_checked() {
    let model = |n: i64| {
        format!(
            "pub struct P {{\n    drivers {{ phi }}\n    unknowns {{ x }}\n    \
             constraints {{ x == powi(1.0 + 0.0000000001 * phi, {n}); }}\n}}"
        )
    };
    for n in [-2_147_483_647, 2_147_483_647, 65_537] {
        let e = errors(&model(n));
        assert!(e.0[0].message.contains("exponent of `powi`"), "{e}");
        assert!(
            e.0[0].excerpt[e.0[0].column - 1..].starts_with(&n.to_string()[..1]),
            "{e}"
        );
    }
    let n = -65_536i32;
    let m = Model::compile(&model(i64::from(n))).expect("at the limit");
    let (phi, rate, eps) = (0.7, 3.0, 1e-10);
    let q = m.assemble(&[phi, 1.0]).expect("assembles");
    let s = m.analyze(&q, &[rate], &[0.0]).expect("analyses");
    let y: f64 = 1.0 + eps * phi;
    let nf = f64::from(n);
    let x = y.powi(n);
    let xd = nf * y.powi(n - 1) * eps * rate;
    let xdd = nf * (nf - 1.0) * y.powi(n - 2) * eps * eps * rate * rate;
    assert!((q[1] - x).abs() <= 1e-14 * x.abs(), "{} {x}", q[1]);
    assert!((s.qd[1] - xd).abs() <= 1e-12 * xd.abs(), "{} {xd}", s.qd[1]);
    assert!(
        (s.qdd[1] - xdd).abs() <= 1e-12 * xdd.abs(),
        "{} {xdd}",
        s.qdd[1]
    );
}

/// Each compile kept its text in the thread's table of locations (65 KiB
/// retained per 64 KiB definition): twenty definitions of 64 KiB compiled
/// one after the other on one thread leave its live bytes where the
/// first left them.
#[test]
fn compiling_many_definitions_does_not_grow_the_thread() {
    on_small_stack(|| {
        let doc: String = (0..1100)
            .map(|_| "/// ".to_string() + &"x".repeat(60) + "\n")
            .collect();
        let text = doc + &four_bar("vec2(d, 0.0) + polar(c, th4)");
        assert!(text.len() >= 64 << 10);
        let mut after = Vec::new();
        for _ in 0..20 {
            let compiled = compile_str(&text).expect("compiles");
            drop(compiled);
            after.push(live_and_peak().0);
        }
        let growth = after[19] - after[1];
        assert!(
            growth < 8 << 10,
            "{growth} bytes kept after 18 more compiles: {after:?}"
        );
    });
}

/// The text's size is checked before anything is read.
#[test]
fn oversized_text_is_an_error() {
    let text = " ".repeat(limits::MAX_TEXT_BYTES + 1);
    let e = errors(&text);
    assert!(e.0[0].message.contains("bytes long"), "{e}");
    assert_eq!((e.0[0].line, e.0[0].column), (1, 1));
}

/// Numbers whose operation overflows or is undefined are located errors
/// at compile time, in the macro's pipeline and for a run-time model
/// alike, not a NaN when the model runs: 1e300 · 1e300 = ∞ (beyond
/// f64::MAX ≈ 1.8e308), 0/0 is undefined, 1/0 = ∞. Finite operations on
/// numbers compile (and fold).
#[test]
fn numbers_that_overflow_are_an_error() {
    for (rhs, what) in [
        ("vec2(d + 1e300 * 1e300, 0.0) + polar(c, th4)", "inf"),
        ("vec2(d + 0.0 / 0.0, 0.0) + polar(c, th4)", "NaN"),
        ("vec2(d, 1.0 / 0.0) + polar(c, th4)", "inf"),
        // Inside a built-in: |(1e200, 1e200)|² overflows.
        (
            "vec2(d + norm(vec2(1e200, 1e200)), 0.0) + polar(c, th4)",
            "inf",
        ),
    ] {
        let text = four_bar(rhs);
        let e = errors(&text);
        assert_eq!(e.0.len(), 1, "{rhs}: {e}");
        let message = e.0[0].to_string();
        assert!(
            message.contains(&format!("these numbers give {what}")),
            "{message}"
        );
        let Err(run_time) = Model::compile(&text) else {
            panic!("{rhs}: compiles at run time");
        };
        assert!(
            run_time.to_string().contains("these numbers give"),
            "{run_time}"
        );
    }
    let fine = four_bar("vec2(d + 1e150 * 1e150 - 1e300, 2.0 * 0.5 - 1.0) + polar(c, th4)");
    assert!(compile_str(&fine).is_ok());
}
