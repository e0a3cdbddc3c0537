//! Sweeps over full cycles, stops at toggle positions, tables, plots and
//! batch evaluation.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use std::f64::consts::{PI, TAU};

use kinematics_core::plot::{plot_motion, plot_path, plot_skeleton, Projection};
use kinematics_core::sweep::{constant_acceleration, constant_speed, simulate, sweep};
use kinematics_core::{batch, Error, Options};
use kinematics_examples::{FourBar, FourBarCoords, SliderCrank, SliderCrankCoords};
use kinematics_tests::Rng;

#[test]
fn crank_rocker_full_cycle_closes_and_is_periodic() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = sweep(&m, &start, 0, 0.0, TAU, 3600, 10.0, 0.0, &Options::DEFAULT);
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.samples.len(), 3601);
    for sample in &s.samples {
        assert!(
            sample.residual < 1e-10,
            "residual {} at φ = {}",
            sample.residual,
            sample.at
        );
    }
    assert_eq!(s.is_periodic(1e-9), Some(true));
    // The rocker stays on its branch: θ4 in (0, π) all the way round.
    assert!(s
        .samples
        .iter()
        .all(|x| x.motion.q.th4 > 0.0 && x.motion.q.th4 < PI));
}

#[test]
fn non_grashof_four_bar_stops_at_its_toggle_position() {
    // d + a = 0.16 > b + c = 0.14: the crank cannot pass the angle where BD
    // = b + c (coupler and rocker in line), cos φ = (a² + d² − (b + c)²)/(2ad).
    let m = FourBar {
        a: 0.05,
        b: 0.08,
        c: 0.06,
        d: 0.11,
        p: 0.0,
        beta: 0.0,
    };
    let limit = ((m.a * m.a + m.d * m.d - (m.b + m.c).powi(2)) / (2.0 * m.a * m.d)).acos();
    let start = m
        .assemble(&FourBarCoords {
            phi: 0.0,
            th3: 0.5,
            th4: 1.5,
        })
        .expect("assembles");
    let s = sweep(&m, &start, 0, 0.0, TAU, 3600, 1.0, 0.0, &Options::DEFAULT);
    let stop = s.stop.as_ref().expect("the crank cannot turn fully");
    let step = TAU / 3600.0;
    let last = s.samples.last().expect("samples before the stop").at;
    assert!(
        last < limit && last > limit - 2.0 * step,
        "last {last}, limit {limit}"
    );
    // The loop is solved in closed form: the sweep locates the limit, where
    // its discriminant vanishes, by bisection, and says it is a limit.
    match &stop.reason {
        Error::LimitPosition {
            variable,
            at,
            unknowns,
        } => {
            assert_eq!((*variable, *unknowns), ("phi", "th3, th4"));
            assert!((at - limit).abs() < 1e-10, "{at} against {limit}");
            assert_eq!(stop.at, *at);
        }
        other => panic!("unexpected {other:?}"),
    }
    let text = stop.reason.to_string();
    assert!(text.contains("limit position at phi = "), "{text}");
    assert_eq!(s.is_periodic(1e-9), None);
}

#[test]
fn slider_crank_passes_its_dead_centres_on_one_branch() {
    let m = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.0,
    };
    let start = m
        .assemble(&SliderCrankCoords {
            phi: 0.0,
            th: 0.0,
            x: 0.35,
        })
        .expect("assembles");
    let s = sweep(&m, &start, 0, 0.0, TAU, 720, 6.0, 0.0, &Options::DEFAULT);
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.is_periodic(1e-9), Some(true));
    for sample in &s.samples {
        let phi = sample.at;
        // The branch with the slider on the +x side: x = a cos φ + √(b² − a² sin² φ).
        let x = m.a * phi.cos() + (m.b * m.b - (m.a * phi.sin()).powi(2)).sqrt();
        assert!((sample.motion.q.x - x).abs() < 1e-12, "φ = {phi}");
    }
    // At the dead centres (φ = 0, π) the slider is at rest.
    for k in [0, 360] {
        assert!(s.samples[k].motion.qd.x.abs() < 1e-12);
    }
}

#[test]
fn time_driven_simulation_follows_the_profile() {
    let m = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.0,
    };
    let start = SliderCrankCoords {
        phi: 0.0,
        th: 0.0,
        x: 0.35,
    };
    let times: Vec<f64> = (0..=200).map(|k| f64::from(k) * 0.005).collect();
    let s = simulate(
        &m,
        &start,
        &times,
        constant_acceleration(0.2, 1.0, 4.0),
        &Options::DEFAULT,
    );
    assert!(s.stop.is_none());
    for (t, sample) in times.iter().zip(&s.samples) {
        let q = &sample.motion;
        assert!((q.q.phi - (0.2 + t + 2.0 * t * t)).abs() < 1e-12);
        assert!((q.qd.phi - (1.0 + 4.0 * t)).abs() < 1e-12 && (q.qdd.phi - 4.0).abs() < 1e-15);
    }
    // A constant speed equals a sweep at that rate.
    let by_time = simulate(
        &m,
        &start,
        &times,
        constant_speed(0.0, 2.0),
        &Options::DEFAULT,
    );
    let by_angle = sweep(&m, &start, 0, 0.0, 2.0, 200, 2.0, 0.0, &Options::DEFAULT);
    for (a, b) in by_time.samples.iter().zip(&by_angle.samples) {
        assert!((a.motion.qdd.x - b.motion.qdd.x).abs() < 1e-9);
    }
    // A closure profile.
    let custom = simulate(
        &m,
        &start,
        &times,
        |t, d, dd, ddd| {
            d[0] = t.sin();
            dd[0] = t.cos();
            ddd[0] = -t.sin();
        },
        &Options::DEFAULT,
    );
    assert!(custom.stop.is_none());
    assert!((custom.samples[100].motion.qd.phi - 0.5f64.cos()).abs() < 1e-15);
}

#[test]
fn csv_and_text_tables() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = sweep(&m, &start, 0, 0.0, TAU, 36, 10.0, 0.0, &Options::DEFAULT);
    let csv = s.to_csv();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + 37);
    let header: Vec<&str> = lines[0].split(',').collect();
    // φ, 3 coordinates × 3, 5 points × 6.
    assert_eq!(header.len(), 1 + 9 + 30);
    assert!(header.contains(&"th3' (rad/s)") && header.contains(&"P.ay"));
    for line in &lines[1..] {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("a number"))
            .collect();
        assert_eq!(values.len(), header.len());
    }
    let text = s.to_text(12);
    assert_eq!(text.lines().count(), 1 + 4);
}

fn stroke_2_polylines(svg: &str) -> usize {
    let doc = roxmltree::Document::parse(svg).expect("valid SVG (XML)");
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke-width") == Some("2"))
        .count()
}

#[test]
fn plots_are_valid_svg_with_one_curve_per_unknown_and_one_line_per_link() {
    let dir = std::env::temp_dir().join(format!("kinematics-plots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = sweep(&m, &start, 0, 0.0, TAU, 360, 10.0, 0.0, &Options::DEFAULT);
    let motion = dir.join("motion.svg");
    plot_motion(&s, &motion).expect("written");
    // Three panels (q, q', q''), one curve per unknown (θ3, θ4).
    assert_eq!(
        stroke_2_polylines(&std::fs::read_to_string(&motion).expect("read")),
        3 * 2
    );
    let path = dir.join("path.svg");
    plot_path(&s, "P", Projection::XY, &path).expect("written");
    assert_eq!(
        stroke_2_polylines(&std::fs::read_to_string(&path).expect("read")),
        1
    );
    let skeleton = dir.join("skeleton.svg");
    let poses: Vec<FourBarCoords> = s.samples.iter().step_by(90).map(|x| x.motion.q).collect();
    assert_eq!(poses.len(), 5);
    plot_skeleton(&m, &poses, &FourBar::LINKS, Projection::XY, &skeleton).expect("written");
    let svg = std::fs::read_to_string(&skeleton).expect("read");
    assert_eq!(stroke_2_polylines(&svg), FourBar::LINKS.len() * poses.len());
    // The two fixed pivots, A and D, are marked.
    let doc = roxmltree::Document::parse(&svg).expect("valid SVG");
    let markers = doc
        .descendants()
        .filter(|n| n.has_tag_name("polygon"))
        .count();
    assert_eq!(markers, 2);
    // An unknown point is an error, not a panic.
    assert!(plot_skeleton(&m, &poses, &[("A", "Q")], Projection::XY, &skeleton).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn batch_reports_every_design() {
    let mut rng = Rng::new(0xBA7C);
    let designs: Vec<FourBar> = (0..10_000)
        .map(|_| FourBar {
            a: rng.range(0.02, 0.06),
            b: rng.range(0.05, 0.15),
            c: rng.range(0.05, 0.15),
            ..FourBar::CRANK_ROCKER
        })
        .collect();
    let results = batch(&designs, |m| {
        m.step(&FourBar::CRANK_ROCKER_GUESS, 10.0, 0.0)
    });
    assert_eq!(results.len(), designs.len());
    let failed = results.iter().filter(|r| r.is_err()).count();
    assert!(failed > 100 && failed < 5_000, "{failed} failed");
    // Each result is the one of its own design, in order.
    for (m, r) in designs.iter().zip(&results).step_by(97) {
        match r {
            Ok(s) => assert!(m.residual(&s.q).iter().all(|v| v.abs() < 1e-10)),
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn a_sweep_of_a_driver_that_does_not_exist_is_refused() {
    // Driver 1 of a one-driver four-bar is the unknown θ3: this swept θ3
    // and returned 11 samples with φ never moving.
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = sweep(&m, &start, 1, 0.0, 1.0, 10, 1.0, 0.0, &Options::DEFAULT);
    assert!(s.samples.is_empty());
    match s.stop {
        Some(stop) => assert!(
            matches!(stop.reason, Error::InvalidOption { name: "driver", .. }),
            "{:?}",
            stop.reason
        ),
        None => panic!("no stop"),
    }
}

#[test]
fn a_profile_of_one_driver_holds_the_others_at_their_start_values() {
    use kinematics_examples::{FiveBar, FiveBarCoords};
    // A five-bar whose second crank stands at φ2 = 2.0: driving the first
    // at constant speed must leave φ2 there (it was set to 0, and the
    // simulation failed with a misleading NotConverged).
    let (a, b, c, d) = (0.05, 0.12, 0.12, 0.05);
    let (phi1, phi2, th2, th3) = (1.0, 2.0, 0.9, 2.2);
    let ex = a * f64::cos(phi1) + b * f64::cos(th2) - c * f64::cos(th3) - d * f64::cos(phi2);
    let ey = a * f64::sin(phi1) + b * f64::sin(th2) - c * f64::sin(th3) - d * f64::sin(phi2);
    let m = FiveBar { a, b, c, d, ex, ey };
    let start = FiveBarCoords {
        phi1,
        phi2,
        th2,
        th3,
    };
    let times: Vec<f64> = (0..=50).map(|k| f64::from(k) * 0.002).collect();
    let s = simulate(
        &m,
        &start,
        &times,
        constant_speed(phi1, 1.0),
        &Options::DEFAULT,
    );
    assert!(s.stop.is_none(), "{:?}", s.stop);
    for sample in &s.samples {
        assert_eq!(sample.motion.q.phi2, phi2);
        assert_eq!((sample.motion.qd.phi2, sample.motion.qdd.phi2), (0.0, 0.0));
        assert!((sample.motion.q.phi1 - (phi1 + sample.at)).abs() < 1e-15);
    }
}
