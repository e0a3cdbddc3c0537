//! `kinematics synthesize` on the data file of Problem B of the published
//! path-generation benchmarks (five points, prescribed crank angles): the
//! best design it writes is re-scored here by the sources' closed form of
//! the coupler point (a circle intersection on their branch, written
//! here), beats the best published error, 1.284e-6, and is read back by
//! `kinematics analyze --params`, which puts C at the first target.

use std::f64::consts::PI;

use crate::common::{path, run, text};

/// The coupler point C of the benchmark four-bar with the crank pivot at
/// the origin and the ground link along x, on the sources' branch
/// ((A − O4) × (B − O4) < 0): B the intersection of the circles of radius
/// r3 about A = r2∠θ2 and r4 about O4 = (r1, 0), C = A + rcx·u + rcy·n
/// with u along AB and n its left normal.
fn coupler(x: &[f64; 6], th2: f64) -> [f64; 2] {
    let [r1, r2, r3, r4, rcx, rcy] = *x;
    let a = [r2 * th2.cos(), r2 * th2.sin()];
    let (dx, dy) = (r1 - a[0], -a[1]);
    let l = dx.hypot(dy);
    let along = (r3 * r3 - r4 * r4 + l * l) / (2.0 * l);
    let h = (r3 * r3 - along * along).sqrt();
    let (ux, uy) = (dx / l, dy / l);
    // Both intersections; the branch picks one.
    let branch = [1.0, -1.0]
        .map(|s| {
            [
                a[0] + along * ux - s * h * uy,
                a[1] + along * uy + s * h * ux,
            ]
        })
        .into_iter()
        .find(|b| (a[0] - r1) * b[1] - a[1] * (b[0] - r1) < 0.0)
        .expect("one intersection is on the branch");
    let (bx, by) = ((branch[0] - a[0]) / r3, (branch[1] - a[1]) / r3);
    [a[0] + rcx * bx - rcy * by, a[1] + rcx * by + rcy * bx]
}

#[test]
fn synthesize_beats_the_published_error_and_its_parameters_read_back() {
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/synthesis");
    let out = std::env::temp_dir().join(format!("kinematics-synthesize-{}", std::process::id()));
    let problem = examples.join("problem_b.toml");
    let o = run(&["synthesize", path(&problem), "--quiet", "--out", path(&out)]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("best design:"), "{stdout}");
    let best = std::fs::read_to_string(out.join("best.toml")).expect("best.toml");
    let value = |name: &str| -> f64 {
        best.lines()
            .find_map(|l| l.strip_prefix(&format!("{name} = ")))
            .unwrap_or_else(|| panic!("no {name} in {best}"))
            .parse()
            .expect("a number")
    };
    let x = ["r1", "r2", "r3", "r4", "rcx", "rcy"].map(value);
    assert_eq!([value("x0"), value("y0"), value("t0")], [0.0; 3]);
    let targets = [
        [3.0, 3.0],
        [2.759, 3.363],
        [2.372, 3.663],
        [1.890, 3.862],
        [1.355, 3.943],
    ];
    let e: f64 = [30.0f64, 45.0, 60.0, 75.0, 90.0]
        .iter()
        .zip(&targets)
        .map(|(deg, t)| {
            let c = coupler(&x, deg * PI / 180.0);
            (c[0] - t[0]).powi(2) + (c[1] - t[1]).powi(2)
        })
        .sum();
    assert!(e <= 1.284e-6, "E = {e:e}");
    // The E printed first in the table is the same.
    let printed: f64 = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("1 "))
        .and_then(|l| l.split_whitespace().nth(1))
        .expect("the table's first row")
        .parse()
        .expect("E");
    assert!((printed - e).abs() <= 1e-6 * e, "{printed} against {e}");
    // The design, its pose at the first target, read back.
    let mech = examples.join("benchmark_four_bar.mech");
    let best_file = out.join("best.toml");
    let o = run(&["analyze", path(&mech), "--params", path(&best_file)]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let shown = text(&o.stdout);
    let line = shown
        .lines()
        .find(|l| l.starts_with("C ") && l.contains("position"))
        .expect("C's position");
    let c: Vec<f64> = line
        .split_whitespace()
        .skip(2)
        .map(|v| v.parse().expect("a number"))
        .collect();
    let first = coupler(&x, PI / 6.0);
    assert!(
        (c[0] - first[0]).abs() < 1e-9 && (c[1] - first[1]).abs() < 1e-9,
        "{c:?}"
    );
    assert!(out.join("synthesis.svg").exists());
    std::fs::remove_dir_all(&out).ok();
}
