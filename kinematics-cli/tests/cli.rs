//! The `kinematics` command as a user runs it: on the examples' definition
//! files, on a definition with an error, and with wrong arguments; its
//! numbers against the code `mechanism!` generates.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{mechanisms, run, text};

use kinematics_core::sweep::Table;
use kinematics_examples::{FourBar, GasEngine, Rssr};

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
    // The gas engine: its bodies, loads and joints.
    let engine = mechanisms().join("gas_engine.mech");
    let stdout = text(&run(&["check", engine.to_str().expect("a UTF-8 path")]).stdout);
    assert!(stdout.contains("bodies: crank, rod, piston\n"), "{stdout}");
    assert!(
        stdout.contains("loads:  gravity, a force at C\n"),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "joints: bearing (revolute at O, ground–crank, driven by phi), crank_pin \
             (revolute at B, crank–rod), piston_pin (revolute at C, rod–piston), cylinder \
             (prismatic at C, ground–piston)\n"
        ),
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
    // (A missing guess is an error only for an unknown solved by
    // Newton–Raphson: `units_and_assemblies.rs`.)
    let cases: [(&[&str], &str); 8] = [
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
            "`half` is not a finite number",
        ),
        (
            &["sweep", path, "--params", params, "--driver", "th3"],
            "`th3` is not a driver of FourBar; its drivers are phi",
        ),
        (
            &["sweep", path, "--params", params, "--unit", "furlong"],
            "unit `furlong`: give one of m, cm, mm, km, in, ft",
        ),
        (
            &["sweep", path, "--params", params, "--projection", "zx"],
            "projection `zx`: give xy, xz or yz",
        ),
        (
            &["sweep", path, "--params", params, "--link", "AB"],
            "link `AB` is not `P-Q`",
        ),
        (
            &["sweep", path, "--params", params, "--link", "A-Q"],
            "link `A-Q`: FourBar has no point `Q`; its points are A, B, D, C, P",
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

/// Reads a CSV the command wrote: its header and its rows of numbers.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let csv = std::fs::read_to_string(path).expect("the CSV is written");
    let mut lines = csv.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

/// The command's CSV against the library's own sweep of the generated
/// mechanism, read as the same table: the same header, and every column
/// within 1e-11 of its largest magnitude (the CSV holds 13 significant
/// digits).
fn same_as_csv(table: &impl Table, path: &Path) {
    let (header, rows) = read_csv(path);
    assert_eq!(header, table.headers_in("m"));
    assert_eq!(rows.len(), table.rows());
    for (c, name) in header.iter().enumerate() {
        let scale = (0..table.rows())
            .map(|i| table.row(i)[c].abs())
            .fold(1.0f64, f64::max);
        for (i, row) in rows.iter().enumerate() {
            let want = table.row(i)[c];
            assert!(
                (row[c] - want).abs() <= 1e-11 * scale,
                "{name} at sample {i}: {} / {want}",
                row[c]
            );
        }
    }
}

/// The files of a sweep: the CSV, the figures (SVG with the titles they
/// should have) and the animation (a page with a frame per sample).
fn figures_are_written(out: &Path, moving: &[&str], samples: usize) {
    let motion = std::fs::read_to_string(out.join("motion.svg")).expect("motion.svg");
    assert!(motion.contains("angular velocities") && motion.contains("phi (deg)"));
    let points = std::fs::read_to_string(out.join("points.svg")).expect("points.svg");
    for p in moving {
        assert!(points.contains(&format!("velocity of {p}")), "{p}");
        let path = std::fs::read_to_string(out.join(format!("path-{p}.svg"))).expect("a path");
        assert!(path.contains(&format!("path of {p}")));
    }
    let page = std::fs::read_to_string(out.join("animation.html")).expect("the animation");
    let frames = page
        .split("<script id=\"frames\" type=\"application/json\">")
        .nth(1)
        .and_then(|s| s.split("</script>").next())
        .expect("the frames");
    assert_eq!(frames.matches('[').count(), samples + 1);
}

/// `kinematics sweep` of the definition `mech` with the parameters file
/// `params` over a turn of 360 steps at `rpm`, into `out`.
fn sweep_a_turn(mech: &Path, params: &Path, rpm: &str, out: &Path) -> Output {
    run(&[
        "sweep",
        mech.to_str().expect("a UTF-8 path"),
        "--params",
        params.to_str().expect("a UTF-8 path"),
        "--turn",
        "--steps",
        "360",
        "--rpm",
        rpm,
        "--out",
        out.to_str().expect("a UTF-8 path"),
    ])
}

/// `kinematics sweep` of the four-bar and of the RSSR, from their
/// parameters files (with their start poses), against the library's own
/// sweeps of the generated mechanisms.
#[test]
fn sweep_writes_the_library_sweep_as_csv_with_its_figures() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-sweep-{}", std::process::id()));
    let four_bar = mechanisms().join("four_bar.mech");
    let params = mechanisms().join("four_bar.toml");
    let out = dir.join("four_bar");
    let run_out = sweep_a_turn(&four_bar, &params, "600", &out);
    assert!(run_out.status.success(), "{}", text(&run_out.stderr));
    assert!(text(&run_out.stdout).starts_with("FourBar: 360 samples of phi"));
    let g = FourBar::CRANK_ROCKER;
    let start = g
        .assemble(&[0.0, 1.0, 1.6].into())
        .expect("the crank-rocker assembles");
    let library = g
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(360)
        .rpm(600.0)
        .run();
    assert!(library.stop.is_none());
    same_as_csv(&library, &out.join("sweep.csv"));
    figures_are_written(&out, &["B", "C", "P"], 360);

    let rssr = mechanisms().join("rssr.mech");
    let params = mechanisms().join("rssr.toml");
    let out = dir.join("rssr");
    let run_out = run(&[
        "sweep",
        rssr.to_str().expect("a UTF-8 path"),
        "--params",
        params.to_str().expect("a UTF-8 path"),
        "--steps",
        "180",
        "--rpm",
        "300",
        "--acceleration",
        "2",
        "--projection",
        "xz",
        "--out",
        out.to_str().expect("a UTF-8 path"),
    ]);
    assert!(run_out.status.success(), "{}", text(&run_out.stderr));
    let g = Rssr {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let start = g.assemble(&[0.0, 1.0].into()).expect("assembles");
    let library = g
        .sweep(Rssr::PHI, &start)
        .turn()
        .steps(180)
        .rpm(300.0)
        .acceleration(2.0)
        .run();
    same_as_csv(&library, &out.join("sweep.csv"));
    figures_are_written(&out, &["A", "B"], 180);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sweep past a limit position writes the samples before it and says
/// where and why it stopped, with exit status 1.
#[test]
fn a_sweep_that_stops_early_says_so() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-stop-{}", std::process::id()));
    let slider_crank = mechanisms().join("slider_crank.mech");
    let out = run(&[
        "sweep",
        slider_crank.to_str().expect("a UTF-8 path"),
        "--param",
        "a=0.3",
        "--param",
        "b=0.2",
        "--param",
        "e=0",
        "--at",
        "phi=0",
        "--at",
        "th=0",
        "--at",
        "x=0.5",
        "--out",
        dir.to_str().expect("a UTF-8 path"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("the sweep stopped early"), "{stderr}");
    assert!(stderr.contains("the files hold the samples before the stop"));
    let (_, rows) = read_csv(&dir.join("sweep.csv"));
    // 0°, 1°, …, 41°: the limit is at asin(b/a) = 41.8°.
    assert_eq!(rows.len(), 42);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A parallelogram four-bar swept through its fold at φ = 0: by default
/// the sweep stops there (status 1, the change point said); with
/// `--change-points smooth` it passes it on the parallelogram branch
/// (θ3 = 0, θ4 = φ, to the CSV's 13 digits) and says so; with `switch` it
/// folds into the crossed form.
#[test]
fn sweep_passes_a_change_point_as_asked() {
    let four_bar = mechanisms().join("four_bar.mech");
    let path = four_bar.to_str().expect("a UTF-8 path");
    let dir = std::env::temp_dir().join(format!("kinematics-cli-fold-{}", std::process::id()));
    let out = dir.to_str().expect("a UTF-8 path");
    let args = |extra: &[&'static str]| -> Vec<String> {
        let mut a: Vec<String> = [
            "sweep", path, "--param", "a=0.05", "--param", "b=0.12", "--param", "c=0.05",
            "--param", "d=0.12", "--param", "p=0", "--param", "beta=0", "--at", "phi=-0.5", "--at",
            "th3=0", "--at", "th4=-0.5", "--to", "0.5", "--steps", "19", "--out", out,
        ]
        .iter()
        .map(ToString::to_string)
        .collect();
        a.extend(extra.iter().map(ToString::to_string));
        a
    };
    let run_with = |a: &[String]| run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let stopped = run_with(&args(&[]));
    assert_eq!(stopped.status.code(), Some(1));
    // The message says how to continue in the command's terms.
    assert!(
        text(&stopped.stderr).contains("change point near phi")
            && text(&stopped.stderr)
                .contains("continue with `--change-points smooth` (or `switch`)"),
        "{}",
        text(&stopped.stderr)
    );
    for (how, parallelogram) in [("smooth", true), ("switch", false)] {
        let passed = run_with(&args(&["--change-points", how]));
        assert!(passed.status.success(), "{how}: {}", text(&passed.stderr));
        assert!(text(&passed.stdout).contains("passed a change point near phi"));
        let (header, rows) = read_csv(&dir.join("sweep.csv"));
        assert_eq!(rows.len(), 20);
        let col = |name: &str| header.iter().position(|h| h == name).expect("a column");
        let last = &rows[19];
        let on_it =
            last[col("th3_rad")].abs() < 1e-12 && (last[col("th4_rad")] - 0.5).abs() < 1e-12;
        assert_eq!(on_it, parallelogram, "{how}: {last:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `kinematics sweep` of a definition with `bodies` and `loads` (the
/// examples' gas engine) writes the forces beside the motion: its
/// `forces.csv` against the forces of the library's sweep of the
/// generated engine, value for value, and the plot of the torque.
#[test]
fn sweep_writes_the_forces_of_a_definition_with_bodies_and_loads() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-forces-{}", std::process::id()));
    let engine = mechanisms().join("gas_engine.mech");
    let params = mechanisms().join("gas_engine.toml");
    let run_out = sweep_a_turn(&engine, &params, "3000", &dir);
    assert!(run_out.status.success(), "{}", text(&run_out.stderr));
    assert!(text(&run_out.stdout).contains("mean effort of phi:"));
    let g = GasEngine::SMALL;
    let start = g
        .assemble(&[0.0, 0.0, 0.125].into())
        .expect("the engine assembles");
    let sweep = g
        .sweep(GasEngine::PHI, &start)
        .turn()
        .steps(360)
        .rpm(3000.0)
        .run();
    let forces = g
        .dynamics()
        .and_then(|d| d.along(&g, &sweep))
        .expect("the forces");
    let (header, rows) = read_csv(&dir.join("forces.csv"));
    let library = forces.to_csv();
    let want: Vec<Vec<f64>> = library
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    assert_eq!(
        header,
        library
            .lines()
            .next()
            .expect("a header")
            .split(',')
            .collect::<Vec<_>>()
    );
    assert_eq!(rows.len(), 360);
    for (c, name) in header.iter().enumerate() {
        let scale = want.iter().map(|r| r[c].abs()).fold(1.0f64, f64::max);
        for (i, (row, w)) in rows.iter().zip(&want).enumerate() {
            assert!(
                (row[c] - w[c]).abs() <= 1e-11 * scale,
                "{name} at sample {i}: {} / {}",
                row[c],
                w[c]
            );
        }
    }
    // The torque is not trivially zero: the gas and the inertia load it.
    let peak = rows.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
    assert!(peak > 10.0, "peak torque {peak} N·m");
    let svg = std::fs::read_to_string(dir.join("forces.svg")).expect("forces.svg");
    assert!(svg.contains("driver efforts") && svg.contains("shaking force"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `kinematics sweep` of a definition with `bodies`, `loads` and a
/// `sensitivities` section (the gas engine with three of its parameters
/// listed) writes the efforts' sensitivities at every sample: its
/// `effort_sensitivities.csv` against the library's, the same definition
/// compiled at run time and assembled at each row's crank angle, to 1e-11
/// of each column's largest magnitude.
#[test]
fn sweep_writes_the_effort_sensitivities_of_a_definition_with_them() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-sens-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let engine = std::fs::read_to_string(mechanisms().join("gas_engine.mech")).expect("readable");
    let end = engine.trim_end().rfind('}').expect("the definition's end");
    let sensed = format!("{}    sensitivities {{ a, r3, m3 }}\n}}\n", &engine[..end]);
    let file = dir.join("sensed_engine.mech");
    std::fs::write(&file, &sensed).expect("writable");
    let params = mechanisms().join("gas_engine.toml");
    let out = dir.join("out");
    let run_out = sweep_a_turn(&file, &params, "3000", &out);
    assert!(run_out.status.success(), "{}", text(&run_out.stderr));
    assert!(text(&run_out.stdout).contains("effort_sensitivities.csv"));
    let (header, rows) = read_csv(&out.join("effort_sensitivities.csv"));
    assert_eq!(
        header,
        [
            "phi (deg)",
            "dQ_phi/da (N·m per unit of a)",
            "dQ_phi/dr3 (N·m per unit of r3)",
            "dQ_phi/dm3 (N·m per unit of m3)"
        ]
    );
    assert_eq!(rows.len(), 360);
    let g = GasEngine::SMALL;
    let model = kinematics_core::runtime::Model::compile(&sensed)
        .expect("the definition compiles")
        .with_values(&g.parameter_values())
        .expect("the engine's values");
    let dynamics = model.dynamics().expect("its dynamics");
    let w = 3000.0 * std::f64::consts::TAU / 60.0;
    let mut want = Vec::new();
    for row in &rows {
        let phi = row[0].to_radians();
        let th = (-(g.a / g.b) * phi.sin()).asin();
        let x = g.a * phi.cos() + g.b * th.cos();
        let pose = model.assemble(&[phi, th, x]).expect("the engine assembles");
        let motion = model.analyze(&pose, &[w], &[0.0]).expect("a motion");
        let s = dynamics
            .effort_sensitivities_of(&model, &motion)
            .expect("the sensitivities");
        want.push(s.iter().map(|p| p.effort[0]).collect::<Vec<f64>>());
    }
    for c in 0..3 {
        let scale = want.iter().map(|r| r[c].abs()).fold(0.0f64, f64::max);
        assert!(scale > 1e-3, "{} is {scale} at most", header[c + 1]);
        for (i, (row, w)) in rows.iter().zip(&want).enumerate() {
            assert!(
                (row[c + 1] - w[c]).abs() <= 1e-11 * scale,
                "{} at sample {i}: {} / {}",
                header[c + 1],
                row[c + 1],
                w[c]
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// 10 000 nested parentheses aborted the command (a stack overflow of its
/// 8 MiB main thread): `check` now exits with the located error that
/// names the limit.
#[test]
fn deeply_nested_text_is_a_located_error_not_an_abort() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-deep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let file = dir.join("deep.mech");
    let depth = 10_000;
    let definition = format!(
        "pub struct FourBar {{\n    params {{ a, b, c, d }}\n    drivers {{ phi }}\n    \
         unknowns {{ th3, th4 }}\n    loops {{ polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + \
         polar({}c{}, th4); }}\n}}\n",
        "(".repeat(depth),
        ")".repeat(depth)
    );
    std::fs::write(&file, definition).expect("written");
    let path = file.to_string_lossy().into_owned();
    let out = run(&["check", &path]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("nest more than 64 deep"), "{stderr}");
    assert!(stderr.contains("deep.mech:5:"), "{stderr}");
    // The excerpt is a window of the long line, not all 20 000 brackets.
    assert!(stderr.len() < 2000, "{}", stderr.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The commands of the README's and the CLI guide's shell blocks run as
/// printed (`kinematics …` and `cargo run --release -p kinematics-cli --
/// …` alike, with this build of the command), from a folder where
/// `examples/` is the project's, and succeed; `sweep` writes its table,
/// `report` its page.
#[cfg(unix)]
#[test]
fn the_readme_and_guide_commands_run_as_printed() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = std::env::temp_dir().join(format!("kinematics-cli-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    std::os::unix::fs::symlink(root.join("examples"), dir.join("examples")).expect("a link");
    let mut ran = 0;
    for page in ["README.md", "kinematics-core/docs/cli.md"] {
        let page_text = std::fs::read_to_string(root.join(page)).expect("the page");
        for block in page_text.split("```sh\n").skip(1) {
            let block = block.split("```").next().unwrap_or("");
            let joined = block.replace("\\\n", " ");
            for line in joined.lines() {
                let command = line.split(" #").next().unwrap_or("").trim();
                let args = command
                    .strip_prefix("kinematics ")
                    .or_else(|| command.strip_prefix("cargo run --release -p kinematics-cli -- "));
                let Some(args) = args else { continue };
                let args: Vec<&str> = args.split_whitespace().collect();
                let out = Command::new(env!("CARGO_BIN_EXE_kinematics"))
                    .args(&args)
                    .current_dir(&dir)
                    .output()
                    .expect("the command runs");
                assert!(
                    out.status.success(),
                    "{page}: `{command}` failed: {}",
                    text(&out.stderr)
                );
                ran += 1;
            }
        }
    }
    assert!(ran >= 6, "{ran} commands");
    assert!(dir.join("out/sweep.csv").exists());
    assert!(dir.join("out/report.html").exists());
    assert!(dir.join("out/best.toml").exists());
    assert!(dir.join("out/press/energy.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The parallelogram four-bar swept over a turn in 360 steps from 30°, so
/// that samples land exactly on its folds: `--change-points smooth` left
/// it at a misleading "dead-centre … or redundant constraint" (exit 1);
/// it now passes both folds, writes 358 rows and names the change points.
#[test]
fn a_parallelogram_swept_onto_its_folds_passes_them() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-fold-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let params = dir.join("parallelogram.toml");
    std::fs::write(
        &params,
        "a = 0.04\nb = 0.09\nc = 0.04\nd = 0.09\np = 0.0\nbeta = 0.0\n\n[start]\n\
         phi = 0.5235987755982988\nth3 = 0.0\nth4 = 0.5235987755982988\n",
    )
    .expect("written");
    let four_bar = mechanisms().join("four_bar.mech");
    let out_dir = dir.join("out");
    let out = run(&[
        "sweep",
        four_bar.to_str().expect("a UTF-8 path"),
        "--params",
        params.to_str().expect("a UTF-8 path"),
        "--turn",
        "--steps",
        "360",
        "--rpm",
        "120",
        "--change-points",
        "smooth",
        "--out",
        out_dir.to_str().expect("a UTF-8 path"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (_, rows) = read_csv(&out_dir.join("sweep.csv"));
    assert_eq!(rows.len(), 358);
    let _ = std::fs::remove_dir_all(&dir);
}
