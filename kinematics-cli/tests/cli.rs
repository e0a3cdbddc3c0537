//! The `kinematics` command as a user runs it: on the examples' definition
//! files, on a definition with an error, and with wrong arguments; its
//! numbers against the code `mechanism!` generates.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use kinematics_examples::FourBar;

fn mechanisms() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/mechanisms")
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kinematics"))
        .args(args)
        .output()
        .expect("the command runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A definition's text as its file holds it: without the indentation it
/// has inside `mechanism! { … }`.
fn dedent(text: &str) -> String {
    let lines: Vec<&str> = text.trim_matches('\n').lines().collect();
    let mut out: Vec<&str> = lines
        .iter()
        .map(|l| l.strip_prefix("    ").unwrap_or_else(|| l.trim_start()))
        .collect();
    while out.last().is_some_and(|l| l.trim().is_empty()) {
        out.pop();
    }
    out.join("\n") + "\n"
}

/// Every definition of the examples has its file in `examples/mechanisms`,
/// with the same text, and `check` accepts every file.
#[test]
fn the_examples_definition_files_are_the_examples_and_check_clean() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(mechanisms())
        .expect("the folder")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "mech"))
        .collect();
    files.sort();
    let contents: Vec<String> = files
        .iter()
        .map(|f| std::fs::read_to_string(f).expect("readable"))
        .collect();
    let defs = kinematics_examples::definitions();
    assert_eq!(defs.len(), files.len());
    for (name, def) in defs {
        let want = dedent(def);
        assert!(
            contents.contains(&want),
            "no file of examples/mechanisms holds {name} as the examples define it"
        );
    }
    for f in &files {
        let out = run(&["check", f.to_str().expect("a UTF-8 path")]);
        assert!(
            out.status.success(),
            "{}: {}",
            f.display(),
            text(&out.stderr)
        );
    }
}

#[test]
fn check_prints_the_blocks_and_the_assemblies() {
    let four_bar = mechanisms().join("four_bar.mech");
    let out = run(&["check", four_bar.to_str().expect("a UTF-8 path")]);
    let stdout = text(&out.stdout);
    assert!(out.status.success());
    assert!(
        stdout.starts_with("FourBar: 1 driver, 2 unknowns, 2 scalar equations"),
        "{stdout}"
    );
    assert!(
        stdout.contains("th3, th4 from equations 1, 2: closed form, RRR dyad, two modes"),
        "{stdout}"
    );
    assert!(stdout.contains("assemblies: 2\n"), "{stdout}");
    // The RSSR's joints section: 4 links, 2 revolute and 2 spherical
    // joints, the coupler's spin passive.
    let rssr = mechanisms().join("rssr.mech");
    let stdout = text(&run(&["check", rssr.to_str().expect("a UTF-8 path")]).stdout);
    assert!(
        stdout.contains("mobility: F = 6(4 − 4 − 1) + 8 − 1 = 1 (Kutzbach–Gruebler)\n"),
        "{stdout}"
    );
    // The Watt six-bar: two RRR dyads, four assemblies.
    let watt = mechanisms().join("watt.mech");
    let stdout = text(&run(&["check", watt.to_str().expect("a UTF-8 path")]).stdout);
    assert!(stdout.contains("assemblies: 4\n"), "{stdout}");
}

/// An error in the file: exit status 1, the macro's message located in
/// the file with the line and a caret.
#[test]
fn an_error_is_located_in_the_file() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let file = dir.join("bad.mech");
    let good = std::fs::read_to_string(mechanisms().join("slider_crank.mech")).expect("readable");
    let bad = good.replacen("C = vec2(x, e);", "C = vec2(x, f);", 1);
    assert_ne!(good, bad, "the slider-crank's definition changed");
    std::fs::write(&file, &bad).expect("written");
    let (line, column) = bad
        .lines()
        .enumerate()
        .find_map(|(i, l)| l.find("vec2(x, f)").map(|c| (i + 1, c + 9)))
        .expect("the line");
    let out = run(&["check", file.to_str().expect("a UTF-8 path")]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.starts_with("error: unknown name `f`"), "{stderr}");
    assert!(
        stderr.contains(&format!("--> {}:{line}:{column}", file.display())),
        "{stderr}"
    );
    let caret = format!("| {}^", " ".repeat(column - 1));
    assert!(
        stderr
            .lines()
            .any(|l| l.trim_start().ends_with(caret.trim_start())),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `analyze` against the generated four-bar: the same pose, rates,
/// accelerations and coupler point to 1e-13.
#[test]
fn analyze_agrees_with_the_generated_code() {
    let four_bar = mechanisms().join("four_bar.mech");
    let params = mechanisms().join("four_bar.toml");
    let out = run(&[
        "analyze",
        four_bar.to_str().expect("a UTF-8 path"),
        "--params",
        params.to_str().expect("a UTF-8 path"),
        "--at",
        "phi=0.5",
        "--at",
        "th3=0.9",
        "--at",
        "th4=1.7",
        "--rate",
        "phi=10",
        "--acceleration",
        "phi=-2",
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let numbers = |label: &str| -> Vec<f64> {
        let line = stdout
            .lines()
            .find(|l| {
                l.split_whitespace()
                    .collect::<Vec<_>>()
                    .starts_with(&label.split(' ').collect::<Vec<_>>())
            })
            .unwrap_or_else(|| panic!("no line {label} in:\n{stdout}"));
        line.split_whitespace()
            .filter_map(|w| w.parse().ok())
            .collect()
    };
    let g = FourBar::CRANK_ROCKER;
    let pose = g
        .assemble(&[0.5, 0.9, 1.7].into())
        .expect("the crank-rocker assembles");
    let s = g.analyze(&pose, 10.0, -2.0).expect("analyses");
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs().max(1.0);
    for (label, q, qd, qdd) in [
        ("th3", s.q.th3, s.qd.th3, s.qdd.th3),
        ("th4", s.q.th4, s.qd.th4, s.qdd.th4),
    ] {
        let v = numbers(label);
        assert!(
            close(v[0], q) && close(v[1], qd) && close(v[2], qdd),
            "{label}: {v:?}"
        );
    }
    // P is the examples' fifth point.
    let p = &s.points[4];
    for (label, want) in [
        ("P position", p.position),
        ("P velocity", p.velocity),
        ("P accel.", p.acceleration),
    ] {
        let v = numbers(label);
        assert!(
            close(v[0], want.x) && close(v[1], want.y),
            "{label}: {v:?} against {want:?}"
        );
    }
}

/// Wrong arguments: exit status 2 and a message that says what to give.
#[test]
fn wrong_arguments_say_what_to_give() {
    let four_bar = mechanisms().join("four_bar.mech");
    let path = four_bar.to_str().expect("a UTF-8 path");
    let params = mechanisms().join("four_bar.toml");
    let params = params.to_str().expect("a UTF-8 path");
    let cases: [(&[&str], &str); 4] = [
        (
            &[
                "analyze", path, "--params", params, "--at", "phi=0.5", "--at", "th3=1",
            ],
            "give a guess for `th4` with --at th4=<value>",
        ),
        (
            &["analyze", path, "--at", "phi=0.5"],
            "parameter `a` has no value",
        ),
        (
            &["analyze", path, "--params", params, "--at", "psi=1"],
            "`psi` is not a coordinate of FourBar",
        ),
        (
            &["analyze", path, "--params", params, "--at", "phi=half"],
            "`half` is not a number",
        ),
    ];
    for (args, message) in cases {
        let out = run(args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
}

/// The README shows `check`'s output for the four-bar as it is.
#[test]
fn the_readme_shows_checks_output() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md"))
            .expect("the README");
    let block = readme
        .split("```text\nFourBar: 1 driver")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .map(|rest| format!("FourBar: 1 driver{rest}"))
        .expect("the README shows check's output");
    let four_bar = mechanisms().join("four_bar.mech");
    let out = run(&["check", four_bar.to_str().expect("a UTF-8 path")]);
    assert_eq!(text(&out.stdout), block);
}
