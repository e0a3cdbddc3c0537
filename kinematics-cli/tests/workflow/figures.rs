//! The figures of merit `kinematics sweep` prints, read from its output
//! against closed forms written here: the offset slider-crank's stroke
//! √((a + b)² − e²) − √((b − a)² − e²) and time ratio (π + α)/(π − α),
//! α = asin(e/(b − a)) − asin(e/(a + b)); the four-bar's transmission
//! angle at φ = 0 and π from the law of cosines in the triangle B C D.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

use crate::common::mechanisms;

/// `kinematics sweep` of `file` with `args`: its standard output.
fn sweep(file: &str, args: &[&str], out: &Path) -> String {
    let mech = mechanisms().join(file);
    let mut all = vec!["sweep", mech.to_str().expect("UTF-8")];
    all.extend_from_slice(args);
    all.extend(["--out", out.to_str().expect("UTF-8")]);
    let o = Command::new(env!("CARGO_BIN_EXE_kinematics"))
        .args(&all)
        .output()
        .expect("the command runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The number after `label` on the line starting (after spaces) with
/// `line`, up to a space, `°` or `;`.
fn after(stdout: &str, line: &str, label: &str) -> f64 {
    let l = stdout
        .lines()
        .find(|l| l.trim_start().starts_with(line))
        .unwrap_or_else(|| panic!("no line {line} in:\n{stdout}"));
    let rest = &l[l.find(label).unwrap_or_else(|| panic!("no {label} in {l}")) + label.len()..];
    let end = rest.find([' ', '°', ';']).unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|_| panic!("not a number after {label} in {l}"))
}

#[test]
fn the_slider_cranks_stroke_and_time_ratio_as_printed() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-fig-{}", std::process::id()));
    let (a, b, e) = (1.0f64, 3.0f64, 1.0f64);
    let stdout = sweep(
        "slider_crank.mech",
        &[
            "--param",
            "a=1",
            "--param",
            "b=3",
            "--param",
            "e=1",
            "--at",
            "phi=30deg",
            "--turn",
        ],
        &dir,
    );
    let stroke = ((a + b).powi(2) - e * e).sqrt() - ((b - a).powi(2) - e * e).sqrt();
    let alpha = (e / (b - a)).asin() - (e / (a + b)).asin();
    let ratio = (PI + alpha) / (PI - alpha);
    // Printed to six decimals.
    assert!(
        (after(&stdout, "x:", "stroke ") - stroke).abs() < 1e-6,
        "{stdout}"
    );
    assert!(
        (after(&stdout, "x:", "time ratio ") - ratio).abs() < 1e-6,
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_four_bars_transmission_angle_as_printed() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-fig4-{}", std::process::id()));
    let stdout = sweep(
        "four_bar.mech",
        &[
            "--params",
            mechanisms().join("four_bar.toml").to_str().expect("UTF-8"),
            "--turn",
            "--degrees",
        ],
        &dir,
    );
    let (a, b, c, d) = (0.04f64, 0.12f64, 0.10f64, 0.11f64);
    let mu = |phi: f64| {
        let f2 = a * a + d * d - 2.0 * a * d * phi.cos();
        ((b * b + c * c - f2) / (2.0 * b * c)).acos().to_degrees()
    };
    let line = "th3, th4: transmission angle";
    assert!(
        (after(&stdout, line, "from ") - mu(0.0)).abs() < 1e-4,
        "{stdout}"
    );
    assert!(
        (after(&stdout, line, "° at phi = 0° to ") - mu(PI)).abs() < 1e-4,
        "{stdout}"
    );
    // The least mechanical advantage of the rocker, ω2/ω4 = c sin(θ4 −
    // θ3) / (a sin(φ − θ3)) from the velocity loop, at the sample the
    // line names, its angles read from the CSV.
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("th4:"))
        .expect("a th4 line");
    let label = "mechanical advantage |phi'/th4'| at least ";
    let rest = &line[line.find(label).expect("the advantage") + label.len()..];
    // "1.524191 at phi = 344°; …"
    let (least, rest) = rest.split_once(" at phi = ").expect("where");
    let least: f64 = least.parse().expect("a number");
    let phi_deg: f64 = rest[..rest.find('°').expect("°")]
        .parse()
        .expect("a number");
    let csv = std::fs::read_to_string(dir.join("sweep.csv")).expect("the CSV");
    let mut lines = csv.lines();
    let headers: Vec<&str> = lines.next().expect("headers").split(',').collect();
    let column = |name: &str| headers.iter().position(|h| *h == name).expect("a column");
    let (k3, k4) = (column("th3_deg"), column("th4_deg"));
    let row: Vec<f64> = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().expect("a number"))
                .collect::<Vec<f64>>()
        })
        .find(|r| (r[0] - phi_deg).abs() < 1e-9)
        .expect("the sample");
    let (phi, t3, t4) = (
        row[0].to_radians(),
        row[k3].to_radians(),
        row[k4].to_radians(),
    );
    let exact = (c * (t4 - t3).sin() / (a * (phi - t3).sin())).abs();
    assert!((least - exact).abs() < 1e-6, "{least} against {exact}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The Grashof class `kinematics sweep` prints for four four-bars, one per
/// class, classified here by hand from S + L against P + Q and which link
/// is the shortest; the links it finds from the motion (no `[draw]`
/// table given) are the four-bar's, and the animation draws them.
#[test]
fn the_grashof_class_of_four_four_bars_as_printed() {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-gr-{}", std::process::id()));
    // (a crank AB, b coupler BC, c rocker DC, d ground AD), a crank angle
    // where each assembles, and the class.
    let cases = [
        ((0.04, 0.12, 0.10, 0.11), "30deg", "Grashof crank-rocker"), // 0.16 < 0.21, input shortest
        ((4.0, 5.0, 4.5, 2.0), "30deg", "Grashof double-crank"),     // 7 < 8.5, ground shortest
        ((4.5, 2.0, 5.0, 4.0), "60deg", "Grashof double-rocker"),    // 7 < 8.5, coupler shortest
        ((3.0, 4.0, 4.5, 6.0), "60deg", "non-Grashof triple-rocker"), // 9 > 8.5
    ];
    for ((a, b, c, d), at, class) in cases {
        let mut owned: Vec<String> = Vec::new();
        for (n, v) in [
            ("a", a),
            ("b", b),
            ("c", c),
            ("d", d),
            ("p", 0.5 * b),
            ("beta", 0.3),
        ] {
            owned.extend(["--param".to_string(), format!("{n}={v}")]);
        }
        // The start pose at --from (no --at: the crank is at its value).
        owned.extend([
            format!("--from={at}"),
            "--to=75deg".to_string(),
            "--steps=5".to_string(),
        ]);
        let args: Vec<&str> = owned.iter().map(String::as_str).collect();
        let stdout = sweep("four_bar.mech", &args, &dir);
        let line = stdout
            .lines()
            .find(|l| l.trim_start().starts_with("four-bar:"))
            .unwrap_or_else(|| panic!("no four-bar line in:\n{stdout}"));
        assert!(line.contains(class), "{line}");
        assert!(
            line.contains("ground AD") && line.contains("input AB") && line.contains("coupler BC"),
            "{line}"
        );
        assert!(
            stdout.contains(
                "links (points moving together): frame {A, D}, {A, B}, {B, C, P}, {D, C}"
            ),
            "{stdout}"
        );
    }
    // The animation draws the links found: AB, the coupler's triangle
    // B C P and DC, five lines.
    let html = std::fs::read_to_string(dir.join("animation.html")).expect("the animation");
    assert!(
        html.contains("id=\"link4\"") && !html.contains("id=\"link5\""),
        "five links drawn"
    );
    std::fs::remove_dir_all(&dir).ok();
}
