//! Definitions with errors, compiled at run time from text: the same
//! messages at the same places as `mechanism!` reports them at compile
//! time (each compile-fail case of `tests/compile-fail/ui`, whose expected rustc output
//! is checked in beside it), and no panic on mutated text.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use kinematics_core::runtime::{CompileError, Model};
use kinematics_examples::mechanism_bodies;

/// The `.rs` files of `tests/compile-fail/ui` with an expected `.stderr` beside them.
fn ui_cases() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("compile-fail/ui");
    let mut out = Vec::new();
    let Ok(dirs) = std::fs::read_dir(&root) else {
        return out;
    };
    for dir in dirs.flatten() {
        let Ok(files) = std::fs::read_dir(dir.path()) else {
            continue;
        };
        for f in files.flatten() {
            let p = f.path();
            if p.extension().is_some_and(|e| e == "rs") && p.with_extension("stderr").exists() {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The errors of an expected rustc output: message, line and column.
fn expected_errors(stderr: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = stderr.lines().collect();
    let mut out = Vec::new();
    for (k, l) in lines.iter().enumerate() {
        let Some(message) = l.strip_prefix("error: ") else {
            continue;
        };
        let Some(at) = lines
            .get(k + 1)
            .and_then(|n| n.trim_start().strip_prefix("--> "))
        else {
            continue;
        };
        let mut parts = at.rsplit(':');
        let column = parts.next().and_then(|c| c.parse().ok());
        let line = parts.next().and_then(|c| c.parse().ok());
        if let (Some(line), Some(column)) = (line, column) {
            out.push((message.to_string(), line, column));
        }
    }
    out
}

/// Every compile-fail case whose errors come from the definition itself:
/// compiled from the text of its `mechanism!` body, the errors are the
/// expected ones, message for message, at the same line and column.
#[test]
fn every_diagnostic_of_the_macro_is_reported_at_the_same_place() {
    let mut checked = 0;
    for case in ui_cases() {
        let source = std::fs::read_to_string(&case).unwrap_or_default();
        let stderr = std::fs::read_to_string(case.with_extension("stderr")).unwrap_or_default();
        let expected = expected_errors(&stderr);
        for (text, first_line) in mechanism_bodies(&source) {
            let last_line = first_line + text.lines().count();
            // The errors rustc reports inside this body.
            let inside: Vec<&(String, usize, usize)> = expected
                .iter()
                .filter(|(_, line, _)| (first_line..=last_line).contains(line))
                .collect();
            let found: Vec<(String, usize, usize)> = match Model::compile(text) {
                Ok(_) => Vec::new(),
                Err(CompileError::Definition(d)) => {
                    d.0.iter()
                        .map(|d| (d.message.clone(), first_line + d.line - 1, d.column))
                        .collect()
                }
                Err(e) => panic!("{}: {e}", case.display()),
            };
            let want: Vec<(String, usize, usize)> = inside.into_iter().cloned().collect();
            assert_eq!(found, want, "{}", case.display());
            checked += want.len();
        }
    }
    println!("{checked} diagnostics at the same place with the same message");
    // Every family of diagnostics is covered (names, syntax, dimensions,
    // arity, counting, structure, mobility, bodies, loads and joints).
    assert_eq!(
        checked, 89,
        "diagnostics compared (the README gives this number)"
    );
}

/// A small deterministic generator, so that a failure names its case.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

/// Seeded mutations of the examples' definitions as text: characters
/// deleted, duplicated or replaced by one of `{}()[];,=+-*/.` or a letter,
/// and the text cut short. Each is compiled at run time; none may panic,
/// and every error must be located inside the text. Set
/// `KINEMATICS_FUZZ_CASES` for a longer run.
#[test]
fn mutated_text_is_an_error_inside_the_text_never_a_panic() {
    let cases: usize = std::env::var("KINEMATICS_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1500);
    let bases: Vec<&str> = kinematics_examples::definitions()
        .into_iter()
        .map(|(_, t)| t)
        .collect();
    assert!(bases.len() >= 10);
    let alphabet: Vec<char> = "{}()[];,=+-*/.:#!\"'0123456789abxyzphi_ \n"
        .chars()
        .collect();
    let mut rng = Lcg(0x5eed);
    let (mut rejected, mut accepted) = (0usize, 0usize);
    for case in 0..cases {
        let mut text: Vec<char> = bases[case % bases.len()].chars().collect();
        for _ in 0..=rng.below(3) {
            let at = rng.below(text.len());
            match rng.below(4) {
                0 => {
                    text.remove(at);
                }
                1 => text.insert(at, text[at]),
                2 => text[at] = alphabet[rng.below(alphabet.len())],
                _ => text.truncate(at.max(1)),
            }
            if text.is_empty() {
                break;
            }
        }
        let text: String = text.into_iter().collect();
        let outcome = std::panic::catch_unwind(|| Model::compile(&text).map(|m| m.name().len()));
        match outcome {
            Err(_) => panic!("case {case} panicked on:\n{text}"),
            Ok(Ok(_)) => accepted += 1,
            Ok(Err(CompileError::Definition(d))) => {
                rejected += 1;
                let lines: Vec<&str> = text.lines().collect();
                for e in &d.0 {
                    let line = lines.get(e.line - 1).copied().unwrap_or("");
                    let inside = e.line >= 1
                        && e.line <= lines.len().max(1)
                        && e.column >= 1
                        && e.column <= line.chars().count() + 1;
                    assert!(inside, "case {case}: {e:?} outside of:\n{text}");
                    assert!(!e.message.is_empty(), "case {case}");
                }
            }
            Ok(Err(e)) => panic!("case {case}: {e}"),
        }
    }
    println!("{rejected} rejected with located errors, {accepted} accepted");
    assert!(
        rejected > cases / 2 && accepted > 0,
        "{rejected} / {accepted}"
    );
}
