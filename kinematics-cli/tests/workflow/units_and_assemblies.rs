//! The command in an engineer's units and without guesses: angles,
//! rates and accelerations with units (`30deg`, `120rpm`, `10deg/s2`) in
//! options and parameter files, output in degrees, a pose assembled in a
//! named assembly where every block has a closed form, every assembly at
//! a crank angle listed by `check --at`; each against the four-bar's
//! closed form written here (the two intersections of the circles about
//! B and D).

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use crate::common::{mechanisms, path, run, text};

/// The crank-rocker of the examples: a, b, c, d, p, β.
const FOUR_BAR: [f64; 6] = [0.04, 0.12, 0.10, 0.11, 0.06, 0.523_598_775_598_298_8];

/// The four-bar's two assemblies at crank angle φ, by hand: B on the
/// crank, C on both the circle of radius b about B and of radius c about
/// D = (d, 0); θ3 the angle of BC, θ4 of DC. The first has C to the left
/// of the line from B to D, the second to its right.
fn closed_form(phi: f64) -> [(f64, f64); 2] {
    let [a, b, c, d, _, _] = FOUR_BAR;
    let (bx, by) = (a * phi.cos(), a * phi.sin());
    let (ex, ey) = (d - bx, -by);
    let f = ex.hypot(ey);
    // Along BD from B to the foot of C, and across.
    let along = (b * b - c * c + f * f) / (2.0 * f);
    let across = (b * b - along * along).sqrt();
    let (ux, uy) = (ex / f, ey / f);
    [1.0, -1.0].map(|side| {
        let cx = bx + along * ux - side * across * uy;
        let cy = by + along * uy + side * across * ux;
        ((cy - by).atan2(cx - bx), cy.atan2(cx - d))
    })
}

/// A parameters file of the crank-rocker with β in degrees and no start
/// pose: no guess anywhere.
fn params_without_guesses(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).expect("a scratch folder");
    let file = dir.join("four_bar.toml");
    let [a, b, c, d, p, _] = FOUR_BAR;
    std::fs::write(
        &file,
        format!("a = {a}\nb = {b}\nc = {c}\nd = {d}\np = {p}\nbeta = \"30deg\"\n"),
    )
    .expect("written");
    file
}

/// Angles within 1e-4° (as `check` prints them, to four decimals).
fn same_angle(printed_deg: f64, rad: f64) -> bool {
    let d = (printed_deg - rad.to_degrees()).rem_euclid(360.0);
    d.min(360.0 - d) < 1.5e-4
}

/// `name = value°` of a line of `check --at`.
fn degrees_of(line: &str, name: &str) -> f64 {
    let start = line
        .find(&format!("{name} = "))
        .unwrap_or_else(|| panic!("no {name} in {line}"))
        + name.len()
        + 3;
    let rest = &line[start..];
    rest[..rest.find('°').expect("a degree sign")]
        .parse()
        .expect("a number")
}

#[test]
fn check_at_lists_every_assembly_against_the_closed_form() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-asm-{}", std::process::id()));
    let params = params_without_guesses(&dir);
    let mech = mechanisms().join("four_bar.mech");
    let out = run(&[
        "check",
        path(&mech),
        "--params",
        path(&params),
        "--at",
        "phi=30deg",
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let lines: Vec<&str> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("assemblies at phi = 30.0000°"))
        .skip(1)
        .collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    let exact = closed_form(30f64.to_radians());
    // Each printed assembly is one of the two intersections, and both
    // are printed.
    let mut found = [false; 2];
    for line in &lines {
        let (t3, t4) = (degrees_of(line, "th3"), degrees_of(line, "th4"));
        let k = exact
            .iter()
            .position(|&(e3, e4)| same_angle(t3, e3) && same_angle(t4, e4))
            .unwrap_or_else(|| panic!("{line} is neither of {exact:?}"));
        found[k] = true;
        // The angle at C between the two links, as printed.
        let d = degrees_of(line, "th4 − th3");
        assert!(same_angle(d, exact[k].1 - exact[k].0), "{line}");
        // The side of C named as the closed form builds it.
        let side = ["C left of B→D", "C right of B→D"][k];
        assert!(line.contains(side), "{line} does not say {side}");
    }
    assert_eq!(found, [true, true]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn analyze_in_degrees_with_no_guesses_in_each_assembly() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-deg-{}", std::process::id()));
    let params = params_without_guesses(&dir);
    let mech = mechanisms().join("four_bar.mech");
    let exact = closed_form(30f64.to_radians());
    let mut seen = Vec::new();
    for assembly in ["1", "2", "+", "-"] {
        let out = run(&[
            "analyze",
            path(&mech),
            "--params",
            path(&params),
            "--at",
            "phi=30deg",
            "--assembly",
            assembly,
            "--rate",
            "phi=120rpm",
            "--acceleration",
            "phi=90deg/s2",
            "--degrees",
        ]);
        let stdout = text(&out.stdout);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let numbers = |label: &str| -> Vec<f64> {
            let line = stdout
                .lines()
                .find(|l| l.split_whitespace().next() == Some(label))
                .unwrap_or_else(|| panic!("no line {label} in:\n{stdout}"));
            line.split_whitespace()
                .filter_map(|w| w.trim_end_matches(',').parse().ok())
                .collect()
        };
        // 120 rpm = 720°/s; 90°/s² as given; φ = 30°.
        let phi = numbers("phi");
        for (got, want) in phi.iter().zip([30.0, 720.0, 90.0]) {
            assert!((got - want).abs() < 1e-12 * want, "{phi:?}");
        }
        let (t3, t4) = (numbers("th3")[0], numbers("th4")[0]);
        let k = exact
            .iter()
            .position(|&(e3, e4)| same_angle(t3, e3) && same_angle(t4, e4))
            .unwrap_or_else(|| panic!("assembly {assembly}: {t3}, {t4} against {exact:?}"));
        seen.push(k);
    }
    // 1 and + are one assembly, 2 and − the other.
    assert_eq!(seen[0], seen[2]);
    assert_eq!(seen[1], seen[3]);
    assert_ne!(seen[0], seen[1]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sweep_from_and_to_in_degrees_writes_degrees() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-sdeg-{}", std::process::id()));
    let params = params_without_guesses(&dir);
    let out_dir = dir.join("out");
    let mech = mechanisms().join("four_bar.mech");
    let out = run(&[
        "sweep",
        path(&mech),
        "--params",
        path(&params),
        "--from",
        "30deg",
        "--to",
        "60deg",
        "--steps",
        "30",
        "--rate",
        "30deg/s",
        "--assembly",
        "2",
        "--degrees",
        "--out",
        path(&out_dir),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("31 samples of phi from 30° to 60°"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out_dir.join("sweep.csv")).expect("the CSV");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    assert_eq!(
        header[..6],
        [
            "phi_deg",
            "phi_deg_s",
            "phi_deg_s2",
            "th3_deg",
            "th3_deg_s",
            "th3_deg_s2"
        ]
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    assert_eq!(rows.len(), 31);
    // The same assembly as `--assembly 2` at φ = 30°, followed to 60°.
    let k = {
        let first = &rows[0];
        let exact = closed_form(30f64.to_radians());
        exact
            .iter()
            .position(|&(e3, _)| same_angle(first[3], e3))
            .expect("one of the two")
    };
    for (i, r) in rows.iter().enumerate() {
        let phi = 30.0 + f64::from(u8::try_from(i).expect("small"));
        assert!((r[0] - phi).abs() < 1e-9, "{r:?}");
        assert!((r[1] - 30.0).abs() < 1e-9, "30°/s: {}", r[1]);
        let (e3, e4) = closed_form(phi.to_radians())[k];
        assert!(same_angle(r[3], e3) && same_angle(r[6], e4), "{phi}: {r:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn units_guesses_and_assemblies_that_are_wrong_say_what_to_give() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-uerr-{}", std::process::id()));
    let params = params_without_guesses(&dir);
    let mech = mechanisms().join("four_bar.mech");
    let fails = |args: &[&str], says: &str| {
        let mut all = vec!["analyze", path(&mech), "--params", path(&params)];
        all.extend_from_slice(args);
        let out = run(&all);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    };
    fails(
        &["--at", "phi=30degs"],
        "the unit `degs` is not known: give deg, rad or rev",
    );
    fails(
        &["--rate", "phi=30deg"],
        "`deg` is not the unit of a rate: give deg/s",
    );
    fails(
        &["--param", "a=40mm"],
        "parameter `a` = `40mm`: the unit `mm` is not known",
    );
    fails(
        &["--assembly", "3"],
        "give a number from 1 to 2, or 1 sign (+ or -)",
    );
    fails(&["--assembly", "+-"], "2 signs for 1 blocks with two modes");
    // A length driver takes no angle's unit.
    let slider = mechanisms().join("slider_crank.mech");
    let out = run(&[
        "analyze",
        path(&slider),
        "--param",
        "a=1",
        "--param",
        "b=3",
        "--param",
        "e=0",
        "--at",
        "phi=1",
        "--at",
        "x=3deg",
    ]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("(x is a length)"), "{stderr}");
    // An angle in radians that looks like degrees is read as written,
    // with a warning.
    let out = run(&[
        "analyze",
        path(&mech),
        "--params",
        path(&params),
        "--at",
        "phi=90",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains(
            "warning: --at `phi=90` is read as 90 rad (14.3 turns); write 90deg for degrees"
        ),
        "{}",
        text(&out.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_newton_block_needs_its_guess_and_says_so() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-newton-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    // A slider in a curved guide x = h + k y²: no closed form.
    let mech = dir.join("curved.mech");
    std::fs::write(
        &mech,
        "pub struct CurvedSlider {\n    params { a, b, h, k }\n    drivers { phi }\n    \
         unknowns { th, y }\n    loops { polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y); }\n}\n",
    )
    .expect("written");
    let base = [
        "analyze",
        path(&mech),
        "--param",
        "a=1",
        "--param",
        "b=3",
        "--param",
        "h=3.5",
        "--param",
        "k=0.05",
        "--at",
        "phi=20deg",
    ];
    let out = run(&base);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("give a guess for `th` with --at th=<value>")
            && stderr.contains("solved by Newton–Raphson"),
        "{stderr}"
    );
    let mut with_guesses = base.to_vec();
    with_guesses.extend(["--at", "th=-0.2", "--at", "y=0.1"]);
    let out = run(&with_guesses);
    assert!(out.status.success(), "{}", text(&out.stderr));
    std::fs::remove_dir_all(&dir).ok();
}
