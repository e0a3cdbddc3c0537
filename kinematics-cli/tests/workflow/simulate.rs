//! `kinematics simulate`: a flywheel started by a DC motor against its
//! closed form, ω(t) = ω₀ (1 − e^(−t T_s / (J ω₀))), read back from the
//! CSV it writes; the crank press of the examples run to a speed (an
//! event) with its energy balance from `energy.csv`; a definition with no
//! masses refused.

use std::path::Path;

use crate::common::{path, run, text};

/// A flywheel of inertia j driven by a DC motor of stall torque ts and
/// no-load speed w0, in the definition language.
const FLYWHEEL: &str = "pub struct Flywheel {
    params   { j, ts, w0 }
    drivers  { phi }
    unknowns { }
    points   { O = vec2(0.0, 0.0); P = polar(0.1, phi); }
    bodies   { wheel(mass = 5.0, center = O, angle = phi, inertia = j); }
    loads    { force(phi, ts * (1.0 - rate(phi) / w0)); }
}";

/// The columns of a CSV file: its header and its rows of numbers.
fn columns(file: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let csv = std::fs::read_to_string(file).expect("written");
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

#[test]
fn a_flywheel_started_by_a_dc_motor_follows_its_exponential() {
    let dir = std::env::temp_dir().join(format!("kinematics-simulate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("flywheel.mech");
    std::fs::write(&mech, FLYWHEEL).unwrap();
    let out = dir.join("out");
    let (j, ts, w0) = (0.5, 4.0, 100.0);
    let o = run(&[
        "simulate",
        path(&mech),
        "--param",
        &format!("j={j}"),
        "--param",
        &format!("ts={ts}"),
        "--param",
        &format!("w0={w0}"),
        "--until",
        "40s",
        "--samples",
        "80",
        "--tolerance",
        "1e-11",
        "--out",
        path(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("81 samples from t = 0 to 40 s"), "{stdout}");
    let (header, rows) = columns(&out.join("sweep.csv"));
    assert_eq!(&header[..3], ["t_s", "phi_rad", "phi_rad_s"]);
    let tau = j * w0 / ts;
    for r in &rows {
        let t = r[0];
        let omega = w0 * (1.0 - (-t / tau).exp());
        let phi = w0 * (t - tau * (1.0 - (-t / tau).exp()));
        assert!(
            (r[2] - omega).abs() < 1e-8 * w0,
            "ω {} against {omega} at {t}",
            r[2]
        );
        assert!(
            (r[1] - phi).abs() < 1e-8 * w0 * 40.0,
            "φ {} against {phi} at {t}",
            r[1]
        );
    }
    for f in [
        "energy.csv",
        "motion.svg",
        "simulation.svg",
        "animation.html",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_sensitivity_to_the_inertia_is_written_as_its_closed_form() {
    let dir = std::env::temp_dir().join(format!("kinematics-sens-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("flywheel.mech");
    std::fs::write(
        &mech,
        FLYWHEEL.replace("    loads", "    sensitivities { j }\n    loads"),
    )
    .unwrap();
    let out = dir.join("out");
    let (j, ts, w0) = (0.5, 4.0, 100.0);
    let o = run(&[
        "simulate",
        path(&mech),
        "--param",
        "j=0.5",
        "--param",
        "ts=4",
        "--param",
        "w0=100",
        "--until",
        "20s",
        "--samples",
        "20",
        "--tolerance",
        "1e-11",
        "--sensitivities",
        "--out",
        path(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let (header, rows) = columns(&out.join("sensitivities.csv"));
    assert_eq!(header, ["t (s)", "dphi/dj", "dphi_rate/dj"]);
    // ω = ω₀ (1 − e^(−t/τ)), τ = J ω₀ / T_s: ∂ω/∂J = −ω₀ e^(−t/τ) t / (τ J).
    let tau = j * w0 / ts;
    for r in &rows {
        let t = r[0];
        let exact = -w0 * (-t / tau).exp() * t / (tau * j);
        assert!(
            (r[2] - exact).abs() < 1e-7 * 80.0,
            "{} against {exact} at {t}",
            r[2]
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_pendulum_bounces_off_a_stop_given_on_the_command_line() {
    let dir = std::env::temp_dir().join(format!("kinematics-stop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("swing.mech");
    std::fs::write(
        &mech,
        "pub struct Swing {
            params   { }
            drivers  { phi }
            unknowns { }
            points   { G = polar(1.0, phi); }
            bodies   { bob(mass = 1.0, center = G, angle = phi); }
            loads    { gravity(vec2(0.0, -9.81)); }
        }",
    )
    .unwrap();
    let o = run(&[
        "simulate",
        path(&mech),
        "--until",
        "1s",
        "--tolerance",
        "1e-11",
        "--stop",
        "phi=-90deg,0.5",
        "--out",
        path(&dir.join("out")),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    // Released from horizontal: it hits the bottom at √(2 g) and leaves
    // at half that.
    let line = stdout
        .lines()
        .find(|l| l.contains("impact at"))
        .expect("an impact");
    let rates: Vec<f64> = line
        .split("rate ")
        .nth(1)
        .expect("the rates")
        .split(" → ")
        .map(|v| v.trim().parse().expect("a number"))
        .collect();
    assert!((rates[0] + (2.0f64 * 9.81).sqrt()).abs() < 1e-5, "{line}");
    assert!((rates[1] + 0.5 * rates[0]).abs() < 1e-5, "{line}");
    let (header, _) = columns(&dir.join("out").join("energy.csv"));
    assert!(
        header.iter().any(|h| h == "work of impacts at phi (J)"),
        "{header:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_press_runs_up_to_a_speed_and_keeps_its_energy_balance() {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/dynamics");
    let out = std::env::temp_dir().join(format!("kinematics-press-{}", std::process::id()));
    let o = run(&[
        "simulate",
        path(&examples.join("press.mech")),
        "--params",
        path(&examples.join("press.toml")),
        "--until",
        "10s",
        "--stop-when",
        "rate(phi)=1400rpm",
        "--out",
        path(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("rate(phi)=1400rpm reached"), "{stdout}");
    let (_, rows) = columns(&out.join("sweep.csv"));
    let last = rows.last().expect("rows");
    let target = 1400.0 * std::f64::consts::TAU / 60.0;
    assert!(
        (last[2] - target).abs() < 1e-6,
        "{} against {target}",
        last[2]
    );
    // T + V − ΣW, the last column, stays at its start value (0) to 1e-7
    // of the kinetic energy reached.
    let (header, energy) = columns(&out.join("energy.csv"));
    assert_eq!(header.last().map(String::as_str), Some("balance (J)"));
    let kinetic = energy.last().expect("rows")[1];
    assert!(kinetic > 1000.0, "{kinetic}");
    for e in &energy {
        let balance = e.last().copied().expect("a balance");
        assert!(
            balance.abs() < 1e-7 * kinetic,
            "balance {balance} at t = {}",
            e[0]
        );
    }
    std::fs::remove_dir_all(&out).ok();
}

/// A block on a spring to the frame, in the definition language: released
/// from x = A at rest it moves x = A cos ω t, ω = √(k/m).
const OSCILLATOR: &str = "pub struct Oscillator {
    params   { m, k }
    drivers  { x }
    unknowns { }
    points   { C = vec2(x, 0.0); }
    bodies   { block(mass = m, center = C); }
    loads    { force(x, -k * x); }
}";

#[test]
fn an_event_given_with_its_direction_ends_the_run_there() {
    let dir = std::env::temp_dir().join(format!("kinematics-events-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("oscillator.mech");
    std::fs::write(&mech, OSCILLATOR).unwrap();
    let out = dir.join("out");
    let simulate = |event: &str| {
        run(&[
            "simulate",
            path(&mech),
            "--param",
            "m=2",
            "--param",
            "k=50",
            "--at",
            "x=0.1",
            "--until",
            "10s",
            "--tolerance",
            "1e-12",
            "--stop-when",
            event,
            "--out",
            path(&out),
        ])
    };
    // Released at x = 0.1 m, it passes x = 0.05 m decreasing at ω t = π/3
    // and increasing at 5π/3.
    let o = simulate("x=0.05,increasing");
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("reached"), "{}", text(&o.stdout));
    let (_, rows) = columns(&out.join("sweep.csv"));
    let w = 5.0f64;
    let end = rows.last().expect("rows")[0];
    let want = 5.0 * std::f64::consts::PI / 3.0 / w;
    assert!((end - want).abs() < 1e-9, "{end} against {want}");
    let o = simulate("rate(x)=0,upward");
    assert!(!o.status.success());
    let stderr = text(&o.stderr);
    assert!(
        stderr.contains("`rate(x)=0,upward`") && stderr.contains("`increasing`"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_torque_of_the_time_turns_the_flywheel_as_its_closed_form() {
    // force(phi, k * time) on the inertia j: ω = k t² / (2 j).
    let dir = std::env::temp_dir().join(format!("kinematics-ramp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("ramp.mech");
    let definition = FLYWHEEL
        .replace("params   { j, ts, w0 }", "params   { j, k }")
        .replace("ts * (1.0 - rate(phi) / w0)", "k * time");
    std::fs::write(&mech, definition).unwrap();
    let out = dir.join("out");
    let o = run(&[
        "simulate",
        path(&mech),
        "--param",
        "j=0.4",
        "--param",
        "k=3",
        "--until",
        "2s",
        "--samples",
        "20",
        "--tolerance",
        "1e-11",
        "--out",
        path(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let (_, rows) = columns(&out.join("sweep.csv"));
    assert_eq!(rows.len(), 21);
    for r in &rows {
        let w = 3.0 * r[0] * r[0] / (2.0 * 0.4);
        assert!(
            (r[2] - w).abs() < 1e-9 * 15.0,
            "ω {} against {w} at {}",
            r[2],
            r[0]
        );
    }
    // A kinematic sweep of it has no time: the kinematics are written, the
    // forces skipped with a note.
    let swept = dir.join("swept");
    let o = run(&[
        "sweep",
        path(&mech),
        "--param",
        "j=0.4",
        "--param",
        "k=3",
        "--out",
        path(&swept),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("forces not computed: the loads read the time"));
    assert!(swept.join("sweep.csv").exists() && !swept.join("forces.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_definition_without_masses_is_not_simulated() {
    let o = run(&[
        "simulate",
        path(&crate::common::mechanisms().join("four_bar.mech")),
        "--out",
        path(&std::env::temp_dir().join("kinematics-no-masses")),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("no `bodies` or `loads` section"),
        "{}",
        text(&o.stderr)
    );
}
