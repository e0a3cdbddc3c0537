//! Definitions built by structure to stress the compiler, for robustness
//! tests: deep nesting of every kind, long names, many items, long sums and
//! products, long chains of signs, extreme literals, many errors on one
//! line, long comments. Each case is the four-bar with one part replaced
//! by a structure of a size drawn (log-uniformly) up to the size of a large
//! file, so that the limits of [`crate::limits`] are reached from below and
//! passed.

use std::fmt::Write as _;

/// The kinds of structure, by name (for reports).
pub const KINDS: [&str; 17] = [
    "nested parentheses",
    "nested calls",
    "nested brackets and braces",
    "long sum",
    "long product",
    "chain of signs",
    "long name",
    "long misspelt name",
    "many parameters",
    "many duplicate names",
    "many points",
    "many unknown names",
    "extreme literals",
    "extreme powi",
    "long doc comment",
    "nested attribute",
    "long chain of loops",
];

/// The four-bar, its first loop's right-hand side replaced by `rhs`, with
/// `extra` added to the parameters and `points` to the points.
fn four_bar(params: &str, points: &str, rhs: &str, doc: &str) -> String {
    format!(
        "/// Four-bar.{doc}\npub struct FourBar {{\n    params   {{ a, b, c, d{params} }}\n    \
         drivers  {{ phi }}\n    unknowns {{ th3, th4 }}\n    points   {{\n        \
         B = polar(a, phi);\n{points}    }}\n    loops    {{ B + polar(b, th3) == {rhs}; }}\n}}\n"
    )
}

/// The right-hand side of the valid four-bar's loop.
const RHS: &str = "vec2(d, 0.0) + polar(c, th4)";

/// A size from 1 to `max`, log-uniform.
fn size(rng: &mut fastrand::Rng, max: usize) -> usize {
    let bits = usize::BITS - max.leading_zeros();
    let b = rng.u32(0..=bits);
    let top = (1usize << b).min(max);
    rng.usize(top / 2..=top).max(1)
}

/// Case `seed`: its kind and its text.
#[must_use]
pub fn case(seed: u64) -> (&'static str, String) {
    case_of_size(seed, usize::MAX)
}

/// Case `seed` with every count and length drawn up to `cap` at most:
/// the suite's cases, which pass every nesting and expression limit but
/// keep the accepted definitions small enough to compile quickly in a
/// debug build.
#[must_use]
pub fn case_of_size(seed: u64, cap: usize) -> (&'static str, String) {
    let mut rng = fastrand::Rng::with_seed(seed);
    let size = |rng: &mut fastrand::Rng, max: usize| size(rng, max.min(cap));
    // Points and loops cost the most to compile: a twentieth of the cap.
    let heavy = |rng: &mut fastrand::Rng, max: usize| size(rng, max.min(cap / 20));
    let k = rng.usize(..KINDS.len());
    let kind = KINDS[k];
    let text = match k {
        0 => {
            let n = size(&mut rng, 20_000);
            let rhs = format!(
                "vec2(d, 0.0) + polar({}c{}, th4)",
                "(".repeat(n),
                ")".repeat(n)
            );
            four_bar("", "", &rhs, "")
        }
        1 => {
            let n = size(&mut rng, 20_000);
            let f = ["sin", "cos", "sqrt", "exp"][rng.usize(..4)];
            let rhs = format!(
                "vec2(d, 0.0) + polar(c + 0.0 * {}phi{}, th4)",
                format!("{f}(").repeat(n),
                ")".repeat(n)
            );
            four_bar("", "", &rhs, "")
        }
        2 => {
            let n = size(&mut rng, 20_000);
            let (open, close) = [("[", "]"), ("{", "}"), ("(", ")")][rng.usize(..3)];
            let rhs = format!(
                "vec2(d, 0.0) + polar(c * {}1.0{}, th4)",
                open.repeat(n),
                close.repeat(n)
            );
            four_bar("", "", &rhs, "")
        }
        3 | 4 => {
            let n = size(&mut rng, 50_000);
            let op = if k == 3 { " + 0.0 * c" } else { " * 1.0" };
            let rhs = format!("vec2(d, 0.0) + polar(c{}, th4)", op.repeat(n));
            four_bar("", "", &rhs, "")
        }
        5 => {
            let n = size(&mut rng, 50_000);
            let signs = if n.is_multiple_of(2) { "- " } else { "-" };
            let rhs = format!("vec2(d, 0.0) + polar({}c, th4)", signs.repeat(2 * n));
            four_bar("", "", &rhs, "")
        }
        6 | 7 => {
            let n = size(&mut rng, 1 << 20);
            let mut name = String::with_capacity(n + 1);
            for _ in 0..n {
                name.push(char::from(b'a' + rng.u8(..26)));
            }
            let mut used = name.clone();
            if k == 7 {
                // The last letter changed: "did you mean" is asked for.
                used.pop();
                used.push(if name.ends_with('z') { 'y' } else { 'z' });
            }
            let rhs = format!("vec2(d, 0.0) + polar(c + 0.0 * {used}, th4)");
            four_bar(&format!(", {name}"), "", &rhs, "")
        }
        8 | 9 => {
            let n = size(&mut rng, 200_000);
            let mut params = String::new();
            for i in 0..n {
                if k == 8 {
                    let _ = write!(params, ", p{i}");
                } else {
                    params.push_str(", p");
                }
            }
            four_bar(&params, "", RHS, "")
        }
        10 => {
            let n = heavy(&mut rng, 50_000);
            let mut points = String::new();
            for i in 0..n {
                let _ = writeln!(points, "        P{i} = B + polar(a, th3 + {i}.0);");
            }
            four_bar("", &points, RHS, "")
        }
        11 => {
            let n = size(&mut rng, 20_000);
            let mut rhs = String::from(RHS);
            for i in 0..n {
                let _ = write!(rhs, " + 0.0 * vec2(u{i}, u{i})");
            }
            // On one line: every error's excerpt is the same long line.
            four_bar("", "", &rhs, "")
        }
        12 => {
            let literals = [
                "1e308 * 1e308",
                "1e-400",
                "0.0 / 0.0",
                "18446744073709551616",
                "340282366920938463463374607431768211456.0",
                "1e999999999",
                "0x7fffffffffffffff",
                "1_000_000_000_000_000_000_000_000_000_000",
                "-1e308 - 1e308",
                "4294967296",
            ];
            let lit = literals[rng.usize(..literals.len())];
            let rhs = format!("vec2(d, 0.0) + polar(c + 0.0 * ({lit}), th4)");
            four_bar("", "", &rhs, "")
        }
        13 => {
            let exps = [
                "2147483647",
                "-2147483647",
                "-2147483648",
                "2147483648",
                "65536",
                "65537",
                "-65536",
                "99999999999999999999",
            ];
            let a = exps[rng.usize(..exps.len())];
            let b = exps[rng.usize(..exps.len())];
            let rhs = format!(
                "vec2(d, 0.0) + polar(c * powi(powi(1.0 + 0.0000000001 * phi, {a}), {b}), th4)"
            );
            four_bar("", "", &rhs, "")
        }
        14 => {
            let n = size(&mut rng, 1 << 20);
            let mut doc = String::with_capacity(n + n / 60 * 5);
            let mut line = 0;
            for _ in 0..n {
                if line == 60 {
                    doc.push_str("\n///");
                    line = 0;
                }
                doc.push(char::from(b'a' + rng.u8(..26)));
                line += 1;
            }
            four_bar("", "", RHS, &format!("\n/// {doc}"))
        }
        16 => {
            // Four-bars in series, each driven by the rocker of the one
            // before: 2n unknowns in n blocks of two.
            let n = heavy(&mut rng, 3000);
            let mut unknowns = String::new();
            let mut loops = String::new();
            let mut prev = String::from("phi");
            for i in 0..n {
                let _ = write!(unknowns, "{}u{i}, w{i}", if i == 0 { "" } else { ", " });
                let _ = writeln!(
                    loops,
                    "        polar(a, {prev}) + polar(b, u{i}) == vec2(d, 0.0) + polar(c, w{i});"
                );
                prev = format!("w{i}");
            }
            format!(
                "/// A chain of four-bars.\npub struct Chain {{\n    params {{ a, b, c, d }}\n    \
                 drivers {{ phi }}\n    unknowns {{ {unknowns} }}\n    loops {{\n{loops}    }}\n}}\n"
            )
        }
        _ => {
            let n = size(&mut rng, 20_000);
            let attr = format!(
                "\n#[cfg_attr({}feature = \"x\"{}, derive(serde::Serialize))]",
                "any(".repeat(n),
                ")".repeat(n)
            );
            four_bar("", "", RHS, "").replacen("\npub struct", &format!("{attr}\npub struct"), 1)
        }
    };
    (kind, text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind is drawn, and the base case compiles.
    #[test]
    fn every_kind_is_drawn_and_the_base_compiles() {
        let mut seen = [false; KINDS.len()];
        for seed in 0..400 {
            let (kind, _) = case(seed);
            if let Some(k) = KINDS.iter().position(|&x| x == kind) {
                seen[k] = true;
            }
        }
        assert!(seen.iter().all(|&s| s), "{seen:?}");
        assert!(crate::compile_str(&four_bar("", "", RHS, "")).is_ok());
    }
}

/// Compiles cases `seeds` on a thread of 2 MiB of stack (the default of a
/// spawned thread): each must be answered, with the compiled model or with
/// errors located inside the text. Returns, per case, its kind, the text's
/// length, whether it compiled and the seconds it took.
///
/// # Panics
/// If a case is answered with an error outside its text, or the thread
/// cannot be spawned.
#[must_use]
pub fn run_on_small_stack(
    seeds: std::ops::Range<u64>,
    cap: usize,
) -> Vec<(&'static str, usize, bool, f64)> {
    let worker = std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || {
            seeds
                .map(|seed| {
                    let (kind, text) = case_of_size(seed, cap);
                    let started = std::time::Instant::now();
                    let result = crate::compile_str(&text);
                    let seconds = started.elapsed().as_secs_f64();
                    if let Err(e) = &result {
                        let lines = text.lines().count().max(1);
                        assert!(
                            !e.0.is_empty()
                                && e.0
                                    .iter()
                                    .all(|d| d.line >= 1 && d.line <= lines && d.column >= 1),
                            "case {seed} ({kind}): an error outside the text: {:?}",
                            e.0.first().map(|d| (&d.message, d.line, d.column))
                        );
                    }
                    (kind, text.len(), result.is_ok(), seconds)
                })
                .collect()
        });
    #[allow(clippy::expect_used)]
    worker
        .expect("a thread of 2 MiB")
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e))
}

#[cfg(test)]
mod small_stack {
    /// The structure-aware cases (`KINEMATICS_FUZZ_CASES` of them, 3000 by
    /// default), their counts capped at 2000 (past every nesting and
    /// expression limit, the accepted ones small), on a 2 MiB thread: each
    /// answered, none aborts (an abort ends the test binary). The cases at
    /// full size, in child processes, are the benchmark's `fuzz_structure`.
    #[test]
    fn structured_cases_are_answered_on_a_small_stack() {
        let cases: u64 = std::env::var("KINEMATICS_FUZZ_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(3000);
        let results = super::run_on_small_stack(0..cases, 2000);
        let accepted = results.iter().filter(|r| r.2).count();
        println!(
            "{cases} cases: {accepted} accepted, {} rejected",
            results.len() - accepted
        );
        for kind in super::KINDS {
            let of: Vec<_> = results.iter().filter(|r| r.0 == kind).collect();
            let seconds: f64 = of.iter().map(|r| r.3).sum();
            let worst = of.iter().map(|r| r.3).fold(0.0, f64::max);
            println!(
                "{kind}: {} cases, {seconds:.2} s in all, {worst:.3} s at most",
                of.len()
            );
        }
        assert_eq!(results.len() as u64, cases);
        assert!(accepted > 0 && accepted < results.len());
    }
}
