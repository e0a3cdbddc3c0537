//! One sweep driver under both kinds of model: every example, swept as
//! the generated mechanism and as the same definition compiled at run
//! time, at 360 and at 361 steps, with every `ChangePoints` option, gives
//! the same number of rows, the same stop (its kind and value), the same
//! change points passed, and the same table (every column within 1e-12
//! of its largest value). Among them the parallelogram four-bar whose
//! two folds fall exactly on samples at 360 steps (and between samples at
//! 361), and a slider-crank whose crank is longer than its rod, which
//! stops at a limit position.
//!
//! The expected values are the generated sweep's, an independent back end
//! (straight-line Rust from the macro, where the run-time model runs
//! machine code from Cranelift or the library's general solver); the row
//! counts of the parallelogram are checked against the grid's geometry
//! (358 = 360 − the two samples on its folds).

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use kinematics_core::runtime::Model;
use kinematics_core::sweep::{ChangePoints, Stop, StopReason, Table};
use kinematics_examples::{
    Crane, CraneCoords, FiveBar, FiveBarCoords, FourBar, GasEngine, GasEngineCoords, PlacedFourBar,
    RRtrRrt, RTrr, RobotArm, RobotArmCoords, Rssr, SatelliteDish, SatelliteDishCoords, SixAxisArm,
    SixAxisArmCoords, SliderCrank, SpatialSlider, SpatialSliderCoords, Strider, Watt,
};

/// The run-time model of the example `name` with the values `values`.
fn model(name: &str, values: &[f64]) -> Model {
    let text = kinematics_examples::definition(name).expect("an example definition");
    let mut m = Model::compile(text).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.set_values(values)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    m
}

/// The kind of a stop, and its value.
fn stop_of(stop: Option<&Stop>) -> Option<(&'static str, f64)> {
    stop.map(|s| {
        let kind = match &s.reason {
            StopReason::LimitPosition { .. } => "limit position",
            StopReason::ChangePoint { .. } => "change point",
            StopReason::Singular(_) => "singular",
            StopReason::NotAssembled(_) => "not assembled",
            StopReason::Invalid(_) => "invalid",
        };
        (kind, s.at)
    })
}

/// Both sweeps end alike and pass the same change points: the same kind
/// of stop at the same value (to 1e-9 of its size: a limit position is
/// bisected on the two back ends' arithmetic, a change point estimated
/// from their conditionings), the same number of change points at the
/// same values.
fn same_ends(case: &str, stops: [Option<&Stop>; 2], passed: [&[f64]; 2]) {
    let [a, b] = stops.map(stop_of);
    assert_eq!(a.map(|s| s.0), b.map(|s| s.0), "{case}: {a:?} / {b:?}");
    if let (Some(a), Some(b)) = (a, b) {
        assert!(
            (a.1 - b.1).abs() <= 1e-9 * (1.0 + a.1.abs()),
            "{case}: {a:?} / {b:?}"
        );
    }
    assert_eq!(passed[0].len(), passed[1].len(), "{case}: {passed:?}");
    for (x, y) in passed[0].iter().zip(passed[1]) {
        assert!(
            (x - y).abs() <= 1e-9 * (1.0 + x.abs()),
            "{case}: {passed:?}"
        );
    }
}

/// The same headers, the same number of rows and every column within
/// `tolerance` of its largest magnitude (1 at least).
fn same_table(case: &str, a: &impl Table, b: &impl Table, tolerance: f64) {
    assert_eq!(a.headers_in("m"), b.headers_in("m"), "{case}");
    assert_eq!(
        a.rows(),
        b.rows(),
        "{case}: {:?} / {:?}",
        a.stop(),
        b.stop()
    );
    let names = a.headers_in("m");
    let rows_a: Vec<Vec<f64>> = (0..a.rows()).map(|i| a.row(i)).collect();
    let rows_b: Vec<Vec<f64>> = (0..b.rows()).map(|i| b.row(i)).collect();
    for (c, name) in names.iter().enumerate() {
        let scale = rows_a.iter().map(|r| r[c].abs()).fold(1.0f64, f64::max);
        for (i, (x, y)) in rows_a.iter().zip(&rows_b).enumerate() {
            assert!(
                (x[c] - y[c]).abs() <= tolerance * scale,
                "{case}: {name} at row {i}: {} / {}",
                x[c],
                y[c]
            );
        }
    }
}

/// Sweeps the generated mechanism `$g` (from `$guess`, assembled) and the
/// run-time model of the example `$name`, each over `$range` (given the
/// builder and the number of steps) at 360 and 361 steps with every
/// `ChangePoints` option, and compares them; the rows compared.
macro_rules! swept_alike {
    ($name:literal, $g:expr, $handle:expr, $guess:expr, |$b:ident, $n:ident| $range:expr) => {
        swept_alike!($name, $g, $handle, $guess, |$b, $n| $range, 1e-12)
    };
    ($name:literal, $g:expr, $handle:expr, $guess:expr, |$b:ident, $n:ident| $range:expr, $tolerance:expr) => {{
        use kinematics_core::Coordinates as _;
        let g = $g;
        let r = model($name, &g.parameter_values());
        let start = g.assemble(&$guess).expect("assembles");
        let q: Vec<f64> = (0..r.coordinates().len())
            .map(|j| start.get(j).expect("a coordinate"))
            .collect();
        let mut rows = Vec::new();
        for $n in [360, 361] {
            for how in [
                ChangePoints::Stop,
                ChangePoints::Smooth,
                ChangePoints::Switch,
            ] {
                let case = format!("{}, {} steps, {how:?}", $name, $n);
                let generated = {
                    let $b = g.sweep($handle, &start).change_points(how);
                    $range.run()
                };
                let run_time = {
                    let $b = r
                        .sweep($handle.name(), &q)
                        .expect("a driver")
                        .change_points(how);
                    $range.run()
                };
                same_ends(
                    &case,
                    [generated.stop.as_ref(), run_time.stop.as_ref()],
                    [&generated.change_points, &run_time.change_points],
                );
                same_table(&case, &generated, &run_time, $tolerance);
                rows.push((
                    case,
                    generated.samples.len(),
                    stop_of(generated.stop.as_ref()),
                ));
            }
        }
        rows
    }};
}

#[test]
fn every_example_is_swept_alike_by_the_one_driver() {
    let mut all = Vec::new();
    all.extend(swept_alike!(
        "FourBar",
        FourBar {
            a: 0.04,
            b: 0.12,
            c: 0.10,
            d: 0.11,
            p: 0.06,
            beta: 0.5,
        },
        FourBar::PHI,
        [0.0, 1.0, 1.6].into(),
        |b, n| b.turn().steps(n).rpm(600.0).acceleration(-3.0)
    ));
    all.extend(swept_alike!(
        "SliderCrank",
        SliderCrank {
            a: 0.1,
            b: 0.3,
            e: 0.02,
        },
        SliderCrank::PHI,
        [0.0, 0.0, 0.4].into(),
        |b, n| b.turn().steps(n).rate(5.0)
    ));
    all.extend(swept_alike!(
        "Rssr",
        Rssr {
            a: 0.04,
            b: 0.12,
            c: 0.10,
            d: 0.11,
        },
        Rssr::PHI,
        [0.0, 1.0].into(),
        |b, n| b.turn().steps(n).rpm(300.0)
    ));
    all.extend(swept_alike!(
        "Watt",
        Watt::EXAMPLE,
        Watt::PHI,
        Watt::EXAMPLE_GUESS,
        |b, n| b.turn().steps(n).rate(2.0)
    ));
    all.extend(swept_alike!(
        "RTrr",
        RTrr::EXAMPLE_4_1,
        RTrr::PHI,
        RTrr::example_4_1_guess(),
        |b, n| b.from(0.2).to(1.2).steps(n).rate(3.0)
    ));
    all.extend(swept_alike!(
        "RRtrRrt",
        RRtrRrt::EXAMPLE_4_2,
        RRtrRrt::PHI,
        RRtrRrt::example_4_2_guess(),
        |b, n| b.turn().steps(n).rate(5.0)
    ));
    all.extend(swept_alike!(
        "SpatialSlider",
        SpatialSlider {
            a: 50.0,
            b: 175.0,
            h: 75.0
        },
        SpatialSlider::PHI,
        SpatialSliderCoords {
            phi: std::f64::consts::FRAC_PI_2,
            y: 140.0
        },
        |b, n| b.turn().steps(n).rate(10.0),
        // Its poses a few 1e-8 mm off the root of its inflated term scale
        // (the same both ways), where its velocities are sensitive to the
        // back ends' round-off (see `runtime_sweep.rs`).
        1e-9
    ));
    all.extend(swept_alike!(
        "SatelliteDish",
        SatelliteDish { r: 1.4 },
        SatelliteDish::PHI,
        SatelliteDishCoords { phi: 0.0, th: 0.4 },
        |b, n| b.turn().steps(n).rate(6.0).acceleration(3.0)
    ));
    all.extend(swept_alike!(
        "Crane",
        Crane { l: 12.0 },
        Crane::PHI,
        CraneCoords { phi: 0.0, th: 0.5 },
        |b, n| b.turn().steps(n).rate(0.3)
    ));
    all.extend(swept_alike!(
        "RobotArm",
        RobotArm {
            l1: 1.2,
            l2: 0.6,
            l3: 0.2,
            alpha: std::f64::consts::FRAC_PI_3
        },
        RobotArm::Q1,
        RobotArmCoords {
            q1: 0.0,
            q4: 0.3,
            q5: -0.2
        },
        |b, n| b.turn().steps(n).rate(1.0)
    ));
    all.extend(swept_alike!(
        "SixAxisArm",
        SixAxisArm {
            d1: 0.4,
            a2: 0.35,
            a3: 0.3,
            d5: 0.08,
            d6: 0.1
        },
        SixAxisArm::Q1,
        SixAxisArmCoords {
            q1: 0.1,
            q2: -0.4,
            q3: 0.7,
            q4: 0.2,
            q5: -0.3,
            q6: 0.5
        },
        |b, n| b.turn().steps(n).rate(2.0)
    ));
    // The five-bar of the simulation tests, closed at φ1 = 1, φ2 = 2.
    let (a, b, c, d) = (0.05, 0.12, 0.12, 0.05);
    let (phi1, phi2, th2, th3) = (1.0f64, 2.0f64, 0.9f64, 2.2f64);
    let ex = a * phi1.cos() + b * th2.cos() - c * th3.cos() - d * phi2.cos();
    let ey = a * phi1.sin() + b * th2.sin() - c * th3.sin() - d * phi2.sin();
    all.extend(swept_alike!(
        "FiveBar",
        FiveBar { a, b, c, d, ex, ey },
        FiveBar::PHI1,
        FiveBarCoords {
            phi1,
            phi2,
            th2,
            th3
        },
        |b, n| b.to(1.3).steps(n).rate(2.0)
    ));
    all.extend(swept_alike!(
        "Strider",
        Strider::PYLINKAGE,
        Strider::TH,
        Strider::pylinkage_guess(0.0),
        |b, n| b.turn().steps(n).rate(4.0)
    ));
    all.extend(swept_alike!(
        "PlacedFourBar",
        PlacedFourBar {
            x0: 0.2,
            y0: -0.1,
            theta0: 0.3,
            d: 0.11,
            a: 0.04,
            b: 0.12,
            c: 0.10,
            p: 0.06,
            beta: 0.5
        },
        PlacedFourBar::PHI,
        [0.0, 1.3, 1.9].into(),
        |b, n| b.turn().steps(n).rate(5.0)
    ));
    all.extend(swept_alike!(
        "GasEngine",
        GasEngine::SMALL,
        GasEngine::PHI,
        GasEngineCoords {
            phi: 0.0,
            th: 0.0,
            x: 0.125
        },
        |b, n| b.turn().steps(n).rpm(3000.0)
    ));
    // Every example of the library, and each sweep through a full turn
    // (or the range it assembles over) without a stop.
    assert_eq!(all.len(), 6 * kinematics_examples::definitions().len());
    for (case, rows, stop) in &all {
        assert!(stop.is_none(), "{case}: {stop:?}");
        assert!(
            *rows == 360 || *rows == 361 || *rows == 362,
            "{case}: {rows}"
        );
    }
}

/// The parallelogram four-bar (AB = CD = 0.04, AD = BC = 0.09), its crank
/// from 30°, over a turn at 120 rev/min: at 360 steps two samples land
/// exactly on its folds (φ = π and 2π), where Φ_u is singular; at 361
/// none does, and the second fold lies a tenth of a step before a sample.
/// Both kinds of model alike in every case (next to a fold Φ_u is nearly
/// singular, its conditioning about the step, and the back ends'
/// round-off is amplified by it: the table to 1e-9). From the grid's
/// geometry: with `Stop` the sweep ends at the first fold, after the
/// 150 samples from 30° up to 179°; with `Smooth` at 360 steps the two
/// samples on the folds are left out (358 rows) and the four-bar stays a
/// parallelogram (θ3 = 0, θ4 = φ) all the way; with `Smooth` at 361 it
/// passes both folds between samples (361 rows), a parallelogram too.
#[test]
fn the_parallelogram_is_swept_alike_onto_and_between_its_folds() {
    let g = FourBar {
        a: 0.04,
        b: 0.09,
        c: 0.04,
        d: 0.09,
        p: 0.0,
        beta: 0.0,
    };
    let phi0 = 30f64.to_radians();
    let rows = swept_alike!(
        "FourBar",
        g,
        FourBar::PHI,
        [phi0, 0.0, phi0].into(),
        |b, n| b.turn().steps(n).rpm(120.0),
        1e-9
    );
    let count = |case: &str| {
        rows.iter()
            .find(|r| r.0 == format!("FourBar, {case}"))
            .map(|r| (r.1, r.2.map(|s| s.0)))
            .expect("a case swept")
    };
    assert_eq!(
        count("360 steps, Stop"),
        (150, Some("change point")),
        "{rows:?}"
    );
    assert_eq!(count("360 steps, Smooth"), (358, None), "{rows:?}");
    assert_eq!(count("360 steps, Switch").1, None, "{rows:?}");
    assert_eq!(count("361 steps, Smooth"), (361, None), "{rows:?}");
    assert_eq!(count("361 steps, Switch").1, None, "{rows:?}");
    // With `Smooth`, a parallelogram at every sample (θ3 = 0, θ4 = φ).
    let r = model("FourBar", &g.parameter_values());
    for steps in [360, 361] {
        let s = r
            .sweep("phi", &[phi0, 0.0, phi0])
            .expect("a driver")
            .turn()
            .steps(steps)
            .rpm(120.0)
            .change_points(ChangePoints::Smooth)
            .run();
        assert_eq!(s.change_points.len(), 2, "{steps}: {:?}", s.change_points);
        for x in &s.samples {
            let q = &x.motion.q;
            let turned = (q[2] - q[0]).rem_euclid(std::f64::consts::TAU);
            assert!(
                q[1].abs() < 1e-9 && turned.min(std::f64::consts::TAU - turned) < 1e-9,
                "{steps}: {q:?}"
            );
        }
    }
}

/// A slider-crank whose crank is longer than its rod (a = 0.3, b = 0.2,
/// no offset) cannot follow past sin φ = b/a: both kinds of model stop at
/// that limit position, bisected to the resolution of `f64`, at every
/// grid and option, within 1e-12 rad of asin(2/3).
#[test]
fn a_limit_position_stops_both_alike() {
    let rows = swept_alike!(
        "SliderCrank",
        SliderCrank {
            a: 0.3,
            b: 0.2,
            e: 0.0
        },
        SliderCrank::PHI,
        [0.0, 0.0, 0.5].into(),
        |b, n| b.turn().steps(n).rate(1.0)
    );
    let limit = (2.0f64 / 3.0).asin();
    assert_eq!(rows.len(), 6);
    for (case, _, stop) in &rows {
        let (kind, at) = stop.expect("stops");
        assert_eq!(kind, "limit position", "{case}");
        assert!((at - limit).abs() < 1e-12, "{case}: {at} / {limit}");
    }
}
