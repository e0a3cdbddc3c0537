//! `kinematics report` on a Stephenson III six-bar written here from the
//! language guide (a crank-rocker four-bar A B C D and a dyad E F G hung
//! from the coupler point E to a third ground pivot G), swept in degrees
//! with no guess; its transmission angle at φ = 0 read back from the CSV
//! against the law of cosines in the triangle B C D, and the page opened
//! in headless Chromium: it loads without a script error and shows its
//! figures.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{path, run, text};

const STEPHENSON_III: &str = "\
/// Stephenson III six-bar: a crank-rocker four-bar A B C D, and a dyad
/// E F G hung from the coupler point E to the ground pivot G.
pub struct StephensonIII {
    params { a, b, c, d, e, gamma, f, g, gx, gy }
    drivers  { phi }
    unknowns { th3, th4, th5, th6 }
    points {
        A = vec2(0.0, 0.0);
        B = polar(a, phi);
        D = vec2(d, 0.0);
        C = D + polar(c, th4);
        E = B + polar(e, th3 + gamma);
        G = vec2(gx, gy);
        F = G + polar(g, th6);
    }
    loops {
        B + polar(b, th3) == C;
        E + polar(f, th5) == F;
    }
}
";

/// The dimensions, the coupler's angle in degrees.
const PARAMS: &str = "\
a = 0.04
b = 0.12
c = 0.10
d = 0.11
e = 0.09
gamma = \"30deg\"
f = 0.10
g = 0.08
gx = 0.02
gy = 0.17
";

/// The folder of test `name`'s files, emptied.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinematics-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// Chromium from the system's packages, if there is one: `CI` makes its
/// absence a failure (the CI script installs it).
fn chromium() -> Option<PathBuf> {
    let found = ["chromium", "chromium-browser"].iter().find_map(|name| {
        std::env::var_os("PATH").and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|p| p.join(name))
                .find(|p| p.is_file())
        })
    });
    assert!(
        found.is_some() || std::env::var_os("CI").is_none(),
        "CI needs Chromium to open the report (apt-get install chromium)"
    );
    found
}

/// Headless Chromium on `page` with `args` (the flags of a closed
/// network and a fresh profile): its standard output and error.
fn headless(chromium: &Path, profile: &Path, page: &Path, args: &[&str]) -> (String, String) {
    let o = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
            "--virtual-time-budget=3000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("Chromium runs");
    assert!(o.status.success(), "Chromium failed: {}", text(&o.stderr));
    (text(&o.stdout), text(&o.stderr))
}

#[test]
fn a_stephenson_six_bar_is_reported_in_degrees_without_guesses_and_opens_in_chromium() {
    let dir = folder("report");
    let (mech, params, out) = (
        dir.join("six_bar.mech"),
        dir.join("six_bar.toml"),
        dir.join("out"),
    );
    std::fs::write(&mech, STEPHENSON_III).expect("written");
    std::fs::write(&params, PARAMS).expect("written");
    let o = run(&[
        "report",
        path(&mech),
        "--params",
        path(&params),
        "--from",
        "0deg",
        "--turn",
        "--steps",
        "360",
        "--rpm",
        "60",
        "--degrees",
        "--out",
        path(&out),
    ]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{stdout}{}", text(&o.stderr));
    assert!(
        stdout.contains("360 samples of phi from 0° to 359°"),
        "{stdout}"
    );
    assert!(stdout.contains("th5, th6: transmission angle"), "{stdout}");
    // The four-bar loop inside the six-bar, found from the motion: its
    // crank AB = 0.04 the shortest, BC = 0.12 the longest, and
    // S + L = 0.16 ≤ P + Q = 0.10 + 0.11: a crank-rocker.
    assert!(
        stdout.contains(
            "four-bar: ground AD = 0.110000, input AB = 0.040000, coupler BC = 0.120000, \
             output DC = 0.100000: Grashof crank-rocker"
        ),
        "{stdout}"
    );

    // The transmission angle at φ = 0, where B = (a, 0): the angle at C
    // between CB and CD, from the law of cosines, against th4 − th3 of
    // the CSV's first row (in degrees).
    let (a, b, c, d) = (0.04f64, 0.12f64, 0.10f64, 0.11f64);
    let bd = d - a;
    let mu = ((b * b + c * c - bd * bd) / (2.0 * b * c))
        .acos()
        .to_degrees();
    let csv = std::fs::read_to_string(out.join("sweep.csv")).expect("the CSV");
    let mut lines = csv.lines();
    let headers: Vec<&str> = lines.next().expect("headers").split(',').collect();
    let row: Vec<f64> = lines
        .next()
        .expect("a row")
        .split(',')
        .map(|v| v.parse().expect("a number"))
        .collect();
    let col = |name: &str| {
        let k = headers
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name} in {headers:?}"));
        row[k]
    };
    assert!(col("phi_deg").abs() < 1e-12);
    let transmission = (col("th4_deg") - col("th3_deg")).abs();
    assert!(
        (transmission - mu).abs() < 1e-9,
        "{transmission}° against {mu}°"
    );

    let page = out.join("report.html");
    let html = std::fs::read_to_string(&page).expect("the report");
    // The assembly the page says the sweep starts in is the one whose
    // angles are the CSV's first row (to the listing's four decimals).
    let listed = html
        .lines()
        .find(|l| l.starts_with("  2. "))
        .expect("a second assembly");
    let degrees = |name: &str| -> f64 {
        let rest = &listed[listed.find(&format!("{name} = ")).expect(name) + name.len() + 3..];
        rest[..rest.find('°').expect("°")]
            .parse()
            .expect("a number")
    };
    for name in ["th3", "th4", "th5", "th6"] {
        let first = col(&format!("{name}_deg"));
        assert!((degrees(name) - first).abs() < 1e-4, "{name}: {listed}");
    }
    for part in [
        "StephensonIII: kinematic report",
        "id=\"merit\"",
        "id=\"assemblies\"",
        "id=\"skeleton\"",
        "id=\"animation\"",
        "E + polar(f, th5) == F;",
        "RRR dyad, two modes",
        "C left of B→D",
        "the sweep starts in assembly 2",
    ] {
        assert!(html.contains(part), "the report has no {part}");
    }
    // Offline: nothing is loaded from anywhere (the SVG namespace is a
    // name, not a request).
    for fetch in ["src=\"http", "href=\"http", "url(http", "<link "] {
        assert!(!html.contains(fetch), "the report loads {fetch}");
    }

    let Some(chromium) = chromium() else {
        eprintln!("no Chromium here: the report was not opened");
        return;
    };
    let profile = dir.join("profile");
    let (dom, log) = headless(&chromium, &profile, &page, &["--dump-dom"]);
    assert!(
        !log.contains("Uncaught") && !log.contains(":ERROR:CONSOLE"),
        "the page logged an error:\n{log}"
    );
    // The figures are in the rendered document, and the animation's
    // script ran inside its frame (its slider and play button exist
    // only in the frame's document, which the outer DOM holds as text).
    for part in [
        "<svg",
        "skeleton.svg",
        "transmission.svg",
        "path-E.svg",
        "<iframe",
    ] {
        assert!(dom.contains(part), "the rendered page has no {part}");
    }
    let shot = dir.join("report.png");
    headless(
        &chromium,
        &profile,
        &page,
        &[
            "--window-size=1000,2400",
            &format!("--screenshot={}", shot.display()),
        ],
    );
    let png = std::fs::read(&shot).expect("the screenshot");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "a PNG");
    // A blank page of that size compresses to a few kilobytes; one with
    // the plots to far more.
    assert!(png.len() > 100_000, "the screenshot is {} bytes", png.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Forces that cannot be computed (a load not finite anywhere) fail the
/// command, but the page still holds the kinematics and says why.
#[test]
fn a_report_whose_forces_fail_still_shows_the_kinematics() {
    let dir = folder("report-forces");
    let mech = dir.join("crank.mech");
    std::fs::write(
        &mech,
        "pub struct Crank {
             params { a } drivers { phi } unknowns { }
             points { O = vec2(0.0, 0.0); B = polar(a, phi); }
             bodies { crank(mass = 1.0, center = B, angle = phi, inertia = 0.1); }
             loads { force(B, vec2(ln(a - 2.0), 0.0)); }
         }",
    )
    .expect("written");
    let out = dir.join("out");
    let o = run(&[
        "report",
        path(&mech),
        "--param",
        "a=1",
        "--turn",
        "--steps",
        "12",
        "--out",
        path(&out),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let stderr = text(&o.stderr);
    assert!(
        stderr.contains("the force at point `B`")
            && stderr.contains("the report holds the kinematics"),
        "{stderr}"
    );
    let html = std::fs::read_to_string(out.join("report.html")).expect("the page");
    assert!(html.contains("The forces could not be computed") && html.contains("id=\"skeleton\""));
    assert!(!out.join("forces.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
