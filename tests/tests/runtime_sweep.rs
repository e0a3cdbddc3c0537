//! Sweeps of models defined at run time against the sweeps of the same
//! definitions compiled by `mechanism!`, both read through the one
//! `Table` trait that the CSV, the text table, the plots and the
//! animation read: the same columns, the same values to 1e-12 of each
//! column's largest magnitude; and the stops at a limit position and at a
//! change point.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use kinematics_core::runtime::Model;
use kinematics_core::sweep::{StopReason, Table};
use kinematics_examples::{FourBar, Rssr, SliderCrank, Watt};

/// The run-time model of the example `name` with the values `values`.
fn model(name: &str, values: &[f64]) -> Model {
    let text = kinematics_examples::definition(name).expect("an example definition");
    let mut m = Model::compile(text).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.set_values(values)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    m
}

/// Every column of `a` and `b` agrees within 1e-12 of its largest
/// magnitude over the sweep (1 at least), and the headers are identical.
fn same_table(a: &impl Table, b: &impl Table) {
    same_table_within(a, b, 1e-12);
}

/// [`same_table`] within `tolerance` of each column's largest magnitude.
fn same_table_within(a: &impl Table, b: &impl Table, tolerance: f64) {
    assert_eq!(a.headers_in("m"), b.headers_in("m"));
    assert_eq!(a.rows(), b.rows(), "{:?} / {:?}", a.stop(), b.stop());
    let rows_a: Vec<Vec<f64>> = (0..a.rows()).map(|i| a.row(i)).collect();
    let rows_b: Vec<Vec<f64>> = (0..b.rows()).map(|i| b.row(i)).collect();
    columns_agree_within(&a.headers_in("m"), &rows_a, &rows_b, tolerance);
}

/// Every column c of `got` within 1e-12 of the largest |want[·][c]| (1 at
/// least) of `want`; `names` name the columns in the messages.
fn columns_agree(names: &[String], want: &[Vec<f64>], got: &[Vec<f64>]) {
    columns_agree_within(names, want, got, 1e-12);
}

/// [`columns_agree`] within `tolerance`.
fn columns_agree_within(names: &[String], want: &[Vec<f64>], got: &[Vec<f64>], tolerance: f64) {
    assert_eq!(want.len(), got.len());
    for (c, name) in names.iter().enumerate() {
        let scale = want.iter().map(|r| r[c].abs()).fold(1.0f64, f64::max);
        for (i, (w, g)) in want.iter().zip(got).enumerate() {
            assert!(
                (w[c] - g[c]).abs() <= tolerance * scale,
                "{name} at row {i}: {} / {}",
                w[c],
                g[c]
            );
        }
    }
}

/// One parameter's sensitivities as compared: ∂q, ∂q', ∂q'' and every
/// point's ∂r, ∂v, ∂a.
type Derivatives = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<[Vec<f64>; 3]>);

#[test]
fn four_bar_sweeps_agree_both_ways() {
    let g = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    let r = model("FourBar", &g.parameter_values());
    let start = g.assemble(&[0.0, 1.0, 1.6].into()).expect("assembles");
    let generated = g
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(360)
        .rpm(600.0)
        .acceleration(-3.0)
        .run();
    let run_time = r
        .sweep("phi", &[start.phi, start.th3, start.th4])
        .expect("phi is a driver")
        .turn()
        .steps(360)
        .rpm(600.0)
        .acceleration(-3.0)
        .run();
    assert!(generated.stop.is_none() && run_time.stop.is_none());
    assert_eq!(run_time.rows(), 360);
    same_table(&generated, &run_time);
    assert_eq!(
        generated.to_csv().lines().next(),
        run_time.csv_in("m").lines().next()
    );
}

#[test]
fn slider_crank_spatial_and_six_bar_sweeps_agree() {
    let g = SliderCrank {
        a: 0.1,
        b: 0.3,
        e: 0.02,
    };
    let r = model("SliderCrank", &g.parameter_values());
    let start = g.assemble(&[0.0, 0.0, 0.4].into()).expect("assembles");
    let generated = g
        .sweep(SliderCrank::PHI, &start)
        .turn()
        .steps(180)
        .rate(5.0)
        .run();
    let run_time = r
        .sweep("phi", &[start.phi, start.th, start.x])
        .expect("phi is a driver")
        .turn()
        .steps(180)
        .rate(5.0)
        .run();
    same_table(&generated, &run_time);

    let g = Rssr {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let r = model("Rssr", &g.parameter_values());
    let start = g.assemble(&[0.0, 1.0].into()).expect("assembles");
    let generated = g
        .sweep(Rssr::PHI, &start)
        .turn()
        .steps(180)
        .rpm(300.0)
        .run();
    let run_time = r
        .sweep("phi", &[start.phi, start.psi])
        .expect("phi is a driver")
        .turn()
        .steps(180)
        .rpm(300.0)
        .run();
    same_table(&generated, &run_time);

    let g = Watt::EXAMPLE;
    let r = model("Watt", &g.parameter_values());
    let start = g.assemble(&Watt::EXAMPLE_GUESS).expect("assembles");
    let q: Vec<f64> = (0..5)
        .map(|j| kinematics_core::Coordinates::get(&start, j).expect("a coordinate"))
        .collect();
    let generated = g.sweep(Watt::PHI, &start).turn().steps(120).rate(2.0).run();
    let run_time = r
        .sweep("phi", &q)
        .expect("phi is a driver")
        .turn()
        .steps(120)
        .rate(2.0)
        .run();
    same_table(&generated, &run_time);
}

/// A slider-crank whose crank is longer than its rod: past sin φ = b/a the
/// rod cannot reach the guide. The run-time sweep stops at the limit
/// position, found by bisection as the generated sweep finds it, with the
/// samples before it.
#[test]
fn a_run_time_sweep_stops_at_a_limit_position() {
    let g = SliderCrank {
        a: 0.3,
        b: 0.2,
        e: 0.0,
    };
    let r = model("SliderCrank", &g.parameter_values());
    let s = r
        .sweep("phi", &[0.0, 0.0, 0.5])
        .expect("phi is a driver")
        .turn()
        .steps(360)
        .run();
    let limit = (0.2f64 / 0.3).asin();
    let stop = s.stop.as_ref().expect("stops at the limit");
    assert!(
        matches!(stop.reason, StopReason::LimitPosition { .. }),
        "{stop}"
    );
    assert!((stop.at - limit).abs() < 1e-12, "{} / {limit}", stop.at);
    assert_eq!(s.samples.len(), 42); // 0°, 1°, …, 41° (the limit is at 41.8°)
    let start = g.assemble(&[0.0, 0.0, 0.5].into()).expect("assembles");
    let generated = g.sweep(SliderCrank::PHI, &start).turn().steps(360).run();
    let other = generated.stop.as_ref().expect("stops at the limit");
    assert_eq!(stop.reason, other.reason);
    assert!(
        (stop.at - other.at).abs() <= 4.0 * f64::EPSILON,
        "{} / {}",
        stop.at,
        other.at
    );
    same_table(&generated, &s);
}

/// A parallelogram four-bar (a = c, b = d) folds at φ = 0, where its two
/// branches meet and det Φ_u = b c sin(θ3 − θ4) changes sign along the
/// parallelogram branch (θ3 = 0, θ4 = φ): both kinds of model stop there
/// instead of crossing silently (nine steps, so that the fold lies midway
/// between the samples at ±1/18: no dip of the conditioning at a sample,
/// no change of sign of det Φ_u in the closed form's carried mode, but
/// the pose off the extrapolation by the order of a step).
#[test]
fn a_run_time_sweep_stops_at_a_change_point() {
    let g = FourBar {
        a: 0.05,
        b: 0.12,
        c: 0.05,
        d: 0.12,
        p: 0.0,
        beta: 0.0,
    };
    let r = model("FourBar", &g.parameter_values());
    let s = r
        .sweep("phi", &[-0.5, 0.0, -0.5])
        .expect("phi is a driver")
        .to(0.5)
        .steps(9)
        .run();
    let start = g.assemble(&[-0.5, 0.0, -0.5].into()).expect("assembles");
    let generated = g.sweep(FourBar::PHI, &start).to(0.5).steps(9).run();
    for (stop, samples) in [
        (
            s.stop.as_ref(),
            s.samples.iter().map(|x| x.at).collect::<Vec<_>>(),
        ),
        (
            generated.stop.as_ref(),
            generated.samples.iter().map(|x| x.at).collect(),
        ),
    ] {
        let stop = stop.expect("stops at the fold");
        match stop.reason {
            StopReason::ChangePoint { from, to } => {
                assert!(from < 1e-12 && to > -1e-12 && from < to, "{from} {to}");
                // The fold (φ = 0) estimated between the two samples.
                assert!(from <= stop.at && stop.at <= to, "{from} {} {to}", stop.at);
                assert!(stop.at.abs() < 0.06, "{}", stop.at);
            }
            ref other => panic!("{other:?}"),
        }
        assert!(samples.iter().all(|&at| at <= 1e-12));
        assert_eq!(samples.len(), 5);
    }
}

#[test]
fn a_run_time_sweep_reports_bad_input_as_a_stop_or_an_error() {
    let r = model("FourBar", &[0.04, 0.12, 0.10, 0.11, 0.06, 0.5]);
    assert!(r.sweep("th3", &[0.0, 1.0, 1.6]).is_err());
    let s = r.sweep("phi", &[0.0, 1.0]).expect("phi is a driver").run();
    assert!(s.samples.is_empty());
    assert!(matches!(
        s.stop.expect("a pose of the wrong length").reason,
        StopReason::Invalid(_) | StopReason::NotAssembled(_)
    ));
    let s = r
        .sweep("phi", &[0.0, 1.0, 1.6])
        .expect("phi is a driver")
        .to(f64::NAN)
        .run();
    assert!(matches!(
        s.stop.expect("a range not finite").reason,
        StopReason::Invalid(_)
    ));
}

/// Every example compiled at run time describes its blocks as the
/// generated mechanism's `BLOCKS` does: the same unknowns, method and
/// modes, block by block in solve order.
#[test]
fn every_example_describes_its_blocks_as_blocks_does() {
    use kinematics_examples::{
        Crane, FiveBar, GasEngine, PlacedFourBar, RRtrRrt, RTrr, RobotArm, SatelliteDish,
        SixAxisArm, SpatialSlider, Strider,
    };
    let generated: [(&str, &[kinematics_core::closed::Block]); 15] = [
        ("FourBar", FourBar::BLOCKS),
        ("SliderCrank", SliderCrank::BLOCKS),
        ("RTrr", RTrr::BLOCKS),
        ("RRtrRrt", RRtrRrt::BLOCKS),
        ("Rssr", Rssr::BLOCKS),
        ("SpatialSlider", SpatialSlider::BLOCKS),
        ("SatelliteDish", SatelliteDish::BLOCKS),
        ("Crane", Crane::BLOCKS),
        ("RobotArm", RobotArm::BLOCKS),
        ("SixAxisArm", SixAxisArm::BLOCKS),
        ("Watt", Watt::BLOCKS),
        ("FiveBar", FiveBar::BLOCKS),
        ("Strider", Strider::BLOCKS),
        ("PlacedFourBar", PlacedFourBar::BLOCKS),
        ("GasEngine", GasEngine::BLOCKS),
    ];
    assert_eq!(generated.len(), kinematics_examples::definitions().len());
    for (name, blocks) in generated {
        let text = kinematics_examples::definition(name).expect("an example definition");
        let m = Model::compile(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.blocks(), blocks, "{name}");
    }
    // Not a vacuous comparison: the examples have blocks of every kind.
    let all: Vec<String> = generated
        .iter()
        .flat_map(|(_, b)| b.iter().map(ToString::to_string))
        .collect();
    for method in [
        "RRR dyad",
        "RRT dyad",
        "RTR dyad",
        "a cos θ",
        "Newton–Raphson",
    ] {
        assert!(all.iter().any(|b| b.contains(method)), "{method}: {all:?}");
    }
}

/// Every assembly of a generated mechanism and of the same definition
/// compiled at run time, at the same drivers: the same modes in the same
/// order, and the same poses to 1e-13 (or both an error).
fn same_assemblies<M, I>(name: &str, values: &[f64], generated: I, start: &[f64])
where
    M: kinematics_core::Coordinates + std::fmt::Debug,
    I: Iterator<
        Item = (
            Vec<kinematics_core::closed::Mode>,
            Result<M, kinematics_core::Error>,
        ),
    >,
{
    let r = model(name, values);
    let run_time: Vec<_> = r.assemble_all(start).collect();
    let generated: Vec<_> = generated.collect();
    assert_eq!(generated.len(), run_time.len(), "{name}");
    assert_eq!(generated.len(), 1 << r.mode_count(), "{name}");
    let mut assembled = 0;
    for ((gm, gq), (rm, rq)) in generated.iter().zip(&run_time) {
        assert_eq!(gm, rm, "{name}");
        match (gq, rq) {
            (Ok(g), Ok(q)) => {
                assembled += 1;
                for (j, v) in q.iter().enumerate() {
                    let want = g.get(j).expect("a coordinate");
                    assert!(
                        (v - want).abs() <= 1e-13 * want.abs().max(1.0),
                        "{name} {rm:?}, coordinate {j}: {v} / {want}"
                    );
                }
            }
            (Err(_), Err(_)) => {}
            other => panic!("{name} {rm:?}: {other:?}"),
        }
    }
    assert!(assembled >= 2, "{name}: {assembled} assemblies");
}

/// The assembly modes and every assembly, both ways: the four-bar (two
/// assemblies), the slider-crank (two), the R-RTR-RRT six-bar (four) and
/// the Watt six-bar (four).
#[test]
fn every_assembly_agrees_both_ways() {
    use kinematics_core::closed::ModeSet;
    use kinematics_examples::RRtrRrt;
    fn signs<M: ModeSet>(m: &M) -> Vec<kinematics_core::closed::Mode> {
        (0..M::BLOCKS).map(|j| m.mode(j)).collect()
    }
    let g = FourBar::CRANK_ROCKER;
    same_assemblies(
        "FourBar",
        &g.parameter_values(),
        g.assemble_all(0.7).map(|(m, q)| (signs(&m), q)),
        &[0.7, 0.0, 0.0],
    );
    let g = SliderCrank {
        a: 0.1,
        b: 0.3,
        e: 0.02,
    };
    same_assemblies(
        "SliderCrank",
        &g.parameter_values(),
        g.assemble_all(0.4).map(|(m, q)| (signs(&m), q)),
        &[0.4, 0.0, 0.0],
    );
    let g = RRtrRrt::EXAMPLE_4_2;
    same_assemblies(
        "RRtrRrt",
        &g.parameter_values(),
        g.assemble_all(0.3).map(|(m, q)| (signs(&m), q)),
        &[0.3, 0.0, 0.0, 0.0, 0.0],
    );
    let g = Watt::EXAMPLE;
    same_assemblies(
        "Watt",
        &g.parameter_values(),
        g.assemble_all(0.5).map(|(m, q)| (signs(&m), q)),
        &[0.5, 0.0, 0.0, 0.0, 0.0],
    );
}

/// `assemble` from the examples' guesses gives the generated mechanism's
/// pose (the closed forms in the modes the guess lies in) to 1e-13.
#[test]
fn assembling_from_a_guess_agrees_both_ways() {
    let g = Watt::EXAMPLE;
    let r = model("Watt", &g.parameter_values());
    let guess = Watt::EXAMPLE_GUESS;
    let q: Vec<f64> = (0..5)
        .map(|j| kinematics_core::Coordinates::get(&guess, j).expect("a coordinate"))
        .collect();
    let want = g.assemble(&guess).expect("assembles");
    let got = r.assemble(&q).expect("assembles");
    for (j, v) in got.iter().enumerate() {
        let w = kinematics_core::Coordinates::get(&want, j).expect("a coordinate");
        assert!((v - w).abs() <= 1e-13 * w.abs().max(1.0), "{j}: {v} / {w}");
    }
    // The crossed four-bar from a guess near it.
    let g = FourBar::CRANK_ROCKER;
    let r = model("FourBar", &g.parameter_values());
    let want = g.assemble(&[0.7, -1.0, -1.5].into()).expect("assembles");
    let got = r.assemble(&[0.7, -1.0, -1.5]).expect("assembles");
    assert!((got[1] - want.th3).abs() < 1e-13 && (got[2] - want.th4).abs() < 1e-13);
}

/// Declares a mechanism with `mechanism!` and keeps the text of its
/// definition, for the same model built both ways.
macro_rules! both {
    ($text:ident, $($t:tt)*) => {
        kinematics_core::mechanism! { $($t)* }
        const $text: &str = stringify!($($t)*);
    };
}

both! {
    MIXED,
    /// A four-bar whose rocker angle drives a third unknown through a
    /// cubic: a closed-form block, then a block solved by Newton–Raphson.
    pub struct Mixed {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Rocker.
            c,
            /// Ground.
            d
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns {
            /// Coupler angle.
            th3,
            /// Rocker angle.
            th4,
            /// The root of y³ + y = θ4.
            y
        }
        loops    { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
        constraints { y * y * y + y == th4; }
    }
}

/// A model with a closed-form block and a Newton block, both ways: the
/// same blocks, the same assemblies from a guess and in both modes, and
/// y solving y³ + y = θ4 (checked here by the cubic's own residual).
#[test]
fn a_mixed_model_assembles_block_by_block_both_ways() {
    let g = Mixed {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let mut r = Model::compile(MIXED).expect("compiles");
    r.set_values(&g.parameter_values()).expect("four values");
    assert_eq!(r.blocks(), Mixed::BLOCKS);
    assert!(r.blocks()[1].method == "Newton–Raphson");
    let guess = [0.7, 1.0, 1.6, 0.5];
    let want = g
        .assemble(&MixedCoords {
            phi: 0.7,
            th3: 1.0,
            th4: 1.6,
            y: 0.5,
        })
        .expect("assembles");
    let got = r.assemble(&guess).expect("assembles");
    let want = [want.phi, want.th3, want.th4, want.y];
    for (v, w) in got.iter().zip(want) {
        assert!((v - w).abs() < 1e-13, "{got:?} / {want:?}");
    }
    assert!((got[3].powi(3) + got[3] - got[2]).abs() < 1e-15);
    use kinematics_core::closed::{Mode, ModeSet};
    for mode in [Mode::Plus, Mode::Minus] {
        let q = r.assemble_in(&guess, &[mode]).expect("assembles");
        let mut modes = MixedModes::all_plus();
        modes.set_mode(0, mode);
        let start = MixedCoords {
            phi: 0.7,
            th3: 1.0,
            th4: 1.6,
            y: 0.5,
        };
        let w = g.assemble_in(&start, &modes).expect("assembles");
        assert!(
            (q[2] - w.th4).abs() < 1e-13 && (q[3] - w.y).abs() < 1e-13,
            "{mode:?}"
        );
        assert!((q[3].powi(3) + q[3] - q[2]).abs() < 1e-15);
    }
}

/// The design sensitivities both ways, at every sample of a turn: the
/// four-bar (six parameters) and the placed four-bar (nine, with the
/// ground pivot's place and angle), in every coordinate, rate and
/// acceleration and every point's position, velocity and acceleration, to
/// 1e-12 of the largest value of each quantity over the turn.
#[test]
fn sensitivities_agree_both_ways() {
    use kinematics_core::{Coordinates, Mechanism, MotionState};
    use kinematics_examples::PlacedFourBar;

    /// Compares the sensitivities of every sample of `generated` (a sweep
    /// of `g`) with those of the run-time model `r` at the same motions.
    fn compare<M: Mechanism>(
        name: &str,
        r: &Model,
        generated: &kinematics_core::sweep::Sweep<M>,
        of: impl Fn(&M::Motion) -> Vec<Derivatives>,
    ) {
        let n = M::COORDINATES.len();
        let mut rows: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
        for sample in &generated.samples {
            let m = &sample.motion;
            let motion = kinematics_core::runtime::Motion {
                q: (0..n).map(|j| m.q().get(j).expect("q")).collect(),
                qd: (0..n).map(|j| m.qd().get(j).expect("q'")).collect(),
                qdd: (0..n).map(|j| m.qdd().get(j).expect("q''")).collect(),
                points: Vec::new(),
                frames: Vec::new(),
                conditioning: m.conditioning(),
                det_sign: m.det_sign(),
                residual: m.residual(),
            };
            let run_time = r.sensitivities(&motion).expect("sensitivities");
            let want = of(m);
            assert_eq!(run_time.len(), want.len(), "{name}");
            let flat = |q: &[f64], qd: &[f64], qdd: &[f64], pts: &[[Vec<f64>; 3]]| -> Vec<f64> {
                let mut v: Vec<f64> = q.iter().chain(qd).chain(qdd).copied().collect();
                for p in pts {
                    for x in p {
                        v.extend(x);
                    }
                }
                v
            };
            for (got, (q, qd, qdd, pts)) in run_time.iter().zip(&want) {
                let got_pts: Vec<[Vec<f64>; 3]> = got
                    .points
                    .iter()
                    .map(|p| {
                        [
                            p.position.to_vec(),
                            p.velocity.to_vec(),
                            p.acceleration.to_vec(),
                        ]
                    })
                    .collect();
                rows.push((
                    flat(&got.q, &got.qd, &got.qdd, &got_pts),
                    flat(q, qd, qdd, pts),
                ));
            }
        }
        let (got, want): (Vec<Vec<f64>>, Vec<Vec<f64>>) = rows.into_iter().unzip();
        let names: Vec<String> = (0..want[0].len())
            .map(|c| format!("{name}, column {c}"))
            .collect();
        columns_agree(&names, &want, &got);
    }

    /// A generated sensitivity as the rows `compare` reads.
    fn flatten<C: Coordinates>(
        q: &C,
        qd: &C,
        qdd: &C,
        points: &[kinematics_core::PointMotion],
    ) -> Derivatives {
        let get = |c: &C| -> Vec<f64> { (0..3).map(|j| c.get(j).expect("a coordinate")).collect() };
        let point = |p: &kinematics_core::PointMotion| {
            use kinematics_core::PointState as _;
            [
                p.position().to_vec(),
                p.velocity().to_vec(),
                p.acceleration().to_vec(),
            ]
        };
        (
            get(q),
            get(qd),
            get(qdd),
            points.iter().map(point).collect(),
        )
    }

    let g = FourBar::CRANK_ROCKER;
    let r = model("FourBar", &g.parameter_values());
    assert_eq!(
        r.sensitivity_parameters(),
        ["a", "b", "c", "d", "p", "beta"]
    );
    let start = g.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let sweep = g
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(72)
        .rpm(600.0)
        .acceleration(50.0)
        .run();
    compare("FourBar", &r, &sweep, |m| {
        let all = g.sensitivities(m).expect("sensitivities");
        all.to_array()
            .iter()
            .map(|s| flatten(&s.q, &s.qd, &s.qdd, &s.points))
            .collect()
    });

    let g = PlacedFourBar {
        x0: 0.2,
        y0: -0.1,
        theta0: 0.3,
        d: 0.11,
        a: 0.04,
        b: 0.12,
        c: 0.10,
        p: 0.06,
        beta: 0.5,
    };
    let r = model("PlacedFourBar", &g.parameter_values());
    let start = g.assemble(&[0.0, 1.3, 1.9].into()).expect("assembles");
    let sweep = g
        .sweep(PlacedFourBar::PHI, &start)
        .turn()
        .steps(72)
        .rate(5.0)
        .run();
    assert!(sweep.stop.is_none());
    compare("PlacedFourBar", &r, &sweep, |m| {
        let all = g.sensitivities(m).expect("sensitivities");
        all.to_array()
            .iter()
            .map(|s| flatten(&s.q, &s.qd, &s.qdd, &s.points))
            .collect()
    });
}

/// Tolerance analysis both ways: the worst-case and root-sum-square
/// deviations of the four-bar's coupler point over a turn, for tolerances
/// on every length and on β, agree to 1e-12 of their largest value.
#[test]
fn tolerance_analysis_agrees_both_ways() {
    use kinematics_core::tolerance::point_deviations;
    let g = FourBar::CRANK_ROCKER;
    let r = model("FourBar", &g.parameter_values());
    let start = g.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let tolerances = [
        ("a", 1e-4),
        ("b", 1e-4),
        ("c", 2e-4),
        ("d", 1e-4),
        ("p", 5e-5),
        ("beta", 0.002),
    ];
    let generated = g
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(72)
        .rate(10.0)
        .run();
    let want = point_deviations(&g, &generated, "P", &tolerances).expect("deviations");
    let sweep = r
        .sweep("phi", &[start.phi, start.th3, start.th4])
        .expect("phi is a driver")
        .turn()
        .steps(72)
        .rate(10.0)
        .run();
    let got = r
        .point_deviations(&sweep, "P", &tolerances)
        .expect("deviations");
    assert_eq!(got.len(), want.len());
    let flat = |d: &kinematics_core::tolerance::Deviation| -> Vec<f64> {
        let mut v = vec![d.at, d.position_worst, d.velocity_worst];
        v.extend(&d.position_components);
        v.extend(&d.position_rss);
        v.extend(&d.velocity_components);
        v.extend(&d.velocity_rss);
        v
    };
    let (got, want): (Vec<Vec<f64>>, Vec<Vec<f64>>) = (
        got.iter().map(flat).collect(),
        want.iter().map(flat).collect(),
    );
    for c in 0..want[0].len() {
        let scale = want.iter().map(|w| w[c].abs()).fold(0.0f64, f64::max);
        assert!(scale > 0.0, "column {c} is zero throughout");
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g[c] - w[c]).abs() <= 1e-12 * scale,
                "column {c}: {} / {}",
                g[c],
                w[c]
            );
        }
    }
    assert!(r.point_deviations(&sweep, "Q", &tolerances).is_err());
    assert!(r.point_deviations(&sweep, "P", &[("e", 1e-4)]).is_err());
}

/// Many designs of one definition compiled once: `with_values` shares the
/// machine code, and `batch` runs the designs on all cores, each result
/// equal to the generated mechanism's (to 1e-13), the designs whose links
/// cannot close failing alike.
#[test]
fn a_batch_of_run_time_designs_agrees_with_the_generated_one() {
    use kinematics_core::batch;
    let base = model("FourBar", &FourBar::CRANK_ROCKER.parameter_values());
    let designs: Vec<FourBar> = (0..200)
        // |b − c| = 0.18 − 0.001 k: beyond |BD| ≈ 0.0835 at φ = 0.7 (k
        // below 97) the coupler and rocker cannot meet.
        .map(|k| FourBar {
            b: 0.2 - 0.0005 * f64::from(k),
            c: 0.02 + 0.0005 * f64::from(k),
            ..FourBar::CRANK_ROCKER
        })
        .collect();
    let models: Vec<Model> = designs
        .iter()
        .map(|g| base.with_values(&g.parameter_values()).expect("six values"))
        .collect();
    let guess = [0.7, 1.0, 1.6];
    let run_time = batch(&models, |m| m.assemble(&guess));
    let generated = batch(&designs, |g| g.assemble(&guess.into()));
    let (mut ok, mut failed) = (0, 0);
    for (r, g) in run_time.iter().zip(&generated) {
        match (r, g) {
            (Ok(q), Ok(w)) => {
                ok += 1;
                assert!((q[1] - w.th3).abs() < 1e-13 && (q[2] - w.th4).abs() < 1e-13);
            }
            (Err(a), Err(b)) => {
                failed += 1;
                assert_eq!(std::mem::discriminant(a), std::mem::discriminant(b));
            }
            other => panic!("{other:?}"),
        }
    }
    assert!(ok > 50 && failed > 10, "{ok} assembled, {failed} did not");
}

/// A simulation in time both ways: the Watt six-bar's crank from rest with
/// constant angular acceleration for half a second, as the generated
/// `simulate` with `constant_acceleration` and as a run-time profile; the
/// same table (time first) to 1e-12 of each column's largest value.
#[test]
fn a_simulation_agrees_both_ways() {
    use kinematics_core::sweep::constant_acceleration;
    let g = Watt::EXAMPLE;
    let r = model("Watt", &g.parameter_values());
    let start = g.assemble(&Watt::EXAMPLE_GUESS).expect("assembles");
    let q: Vec<f64> = (0..5)
        .map(|j| kinematics_core::Coordinates::get(&start, j).expect("a coordinate"))
        .collect();
    let phi0 = start.phi;
    let generated = g
        .simulate(&start)
        .duration(0.5)
        .steps(200)
        .profile(constant_acceleration(Watt::PHI, phi0, 0.0, 40.0))
        .run();
    let run_time = r
        .simulate(&q)
        .duration(0.5)
        .steps(200)
        .profile(|t, d, dd, ddd| {
            d[0] = phi0 + 20.0 * t * t;
            dd[0] = 40.0 * t;
            ddd[0] = 40.0;
        })
        .run();
    assert!(generated.stop.is_none() && run_time.stop.is_none());
    assert_eq!(run_time.headers_in("m")[0], "t_s");
    same_table(&generated, &run_time);
}

/// `Options::branch` both ways: asked for the other sign of det Φ_u, a
/// closed-form model assembles in the other modes (the slider-crank's rod
/// reaching back past the crank's pivot), as the generated code does; the
/// stepper keeps the branch asked for.
#[test]
fn the_branch_asked_for_is_kept_both_ways() {
    use kinematics_core::{Branch, Options};
    let g = SliderCrank {
        a: 0.1,
        b: 0.3,
        e: 0.02,
    };
    let r = model("SliderCrank", &g.parameter_values());
    let wants = |branch| Options {
        branch,
        ..Options::DEFAULT
    };
    for branch in [Branch::Positive, Branch::Negative] {
        let want = g
            .assemble_with(&[1.0, 0.0, 0.3].into(), &wants(branch))
            .expect("assembles");
        let got = r
            .assemble_with(&[1.0, 0.0, 0.3], &wants(branch))
            .expect("assembles");
        assert!(
            (got[1] - want.th).abs() < 1e-13 && (got[2] - want.x).abs() < 1e-13,
            "{branch:?}: {got:?} / {want:?}"
        );
        let mut stepper = r.stepper(&wants(branch)).expect("valid");
        let s = stepper
            .step(&[1.1, 0.0, 0.3], &[1.0], &[0.0])
            .expect("steps");
        let sign = if branch == Branch::Positive {
            1.0
        } else {
            -1.0
        };
        assert_eq!(s.det_sign, sign);
    }
    let positive = r
        .assemble_with(&[1.0, 0.0, 0.3], &wants(Branch::Positive))
        .expect("assembles");
    let negative = r
        .assemble_with(&[1.0, 0.0, 0.3], &wants(Branch::Negative))
        .expect("assembles");
    assert!(positive[2] > 0.0 && negative[2] < 0.0);
}

/// What the guide says of the spatial slider's term scale: the poses of
/// both sweeps are within the tolerance by the scaled residual
/// (|Φ|/S ≤ 1e-14), yet their raw residuals of |B − A|² − b² reach more
/// than 1e-12 of b² + h² + y² (about 6·10⁴ mm², what the terms of the
/// equation measure), and Newton–Raphson stops up to about 3e-8 mm off
/// the root (the residual over its derivative in y, the derivative by a
/// central difference, exact for this quadratic in y). Both kinds of
/// model, stepped by the one sweep driver from the same predictions, stop
/// at the same poses (to 1e-12 mm). (When the characteristic length is
/// made a length for equations in length², this test fails, and the
/// guide's note goes.)
#[test]
fn the_spatial_sliders_inflated_scale_is_as_the_readme_says() {
    use kinematics_examples::{SpatialSlider, SpatialSliderCoords};
    let g = SpatialSlider {
        a: 50.0,
        b: 175.0,
        h: 75.0,
    };
    let r = model("SpatialSlider", &g.parameter_values());
    let start = g
        .assemble(&SpatialSliderCoords {
            phi: std::f64::consts::FRAC_PI_2,
            y: 140.0,
        })
        .expect("assembles");
    let generated = g
        .sweep(SpatialSlider::PHI, &start)
        .turn()
        .steps(120)
        .rate(10.0)
        .run();
    let run_time = r
        .sweep("phi", &[start.phi, start.y])
        .expect("a driver")
        .turn()
        .steps(120)
        .rate(10.0)
        .run();
    assert_eq!(generated.samples.len(), run_time.samples.len());
    let (mut apart, mut off_root, mut raw_max) = (0.0f64, 0.0f64, 0.0f64);
    let raw = |pose: &[f64]| r.residual(pose).expect("a residual")[0];
    for (gs, rs) in generated.samples.iter().zip(&run_time.samples) {
        let q = [gs.motion.q.phi, gs.motion.q.y];
        for pose in [&q[..], &rs.motion.q[..]] {
            let scaled = r.analyze(pose, &[10.0], &[0.0]).expect("analyses").residual;
            assert!(scaled <= 1e-14, "{scaled:e}");
            let value = raw(pose);
            raw_max = raw_max.max(value.abs());
            let h = 1e-3;
            let slope = (raw(&[pose[0], pose[1] + h]) - raw(&[pose[0], pose[1] - h])) / (2.0 * h);
            off_root = off_root.max((value / slope).abs());
        }
        apart = apart.max((q[1] - rs.motion.q[1]).abs());
    }
    let terms = 175.0f64.powi(2) + 75.0f64.powi(2) + 150.0f64.powi(2);
    assert!(raw_max > 1e-12 * terms, "{raw_max:e} mm²");
    assert!(off_root > 1e-10 && off_root < 1e-7, "{off_root:e} mm");
    assert!(apart <= 1e-12, "{apart:e} mm");
}

/// Past a parallelogram's fold both ways: with `ChangePoints::Smooth` the
/// four-bar stays a parallelogram (θ3 = 0, θ4 = φ), with `Switch` it folds
/// into the crossed form; each the same table as the generated sweep's (to
/// 1e-12) and one change point, near φ = 0, passed.
#[test]
fn change_points_are_passed_both_ways() {
    use kinematics_core::sweep::ChangePoints;
    let g = FourBar {
        a: 0.05,
        b: 0.12,
        c: 0.05,
        d: 0.12,
        p: 0.0,
        beta: 0.0,
    };
    let r = model("FourBar", &g.parameter_values());
    let start = g.assemble(&[-0.5, 0.0, -0.5].into()).expect("assembles");
    for how in [ChangePoints::Smooth, ChangePoints::Switch] {
        let generated = g
            .sweep(FourBar::PHI, &start)
            .to(0.5)
            .steps(19)
            .rate(2.0)
            .change_points(how)
            .run();
        let run_time = r
            .sweep("phi", &[start.phi, start.th3, start.th4])
            .expect("a driver")
            .to(0.5)
            .steps(19)
            .rate(2.0)
            .change_points(how)
            .run();
        assert!(
            generated.stop.is_none() && run_time.stop.is_none(),
            "{how:?}"
        );
        same_table(&generated, &run_time);
        assert_eq!(run_time.change_points.len(), 1, "{how:?}");
        assert!(
            run_time.change_points[0].abs() < 0.06,
            "{:?}",
            run_time.change_points
        );
        let last = &run_time.samples[19].motion;
        let parallelogram = last.q[1].abs() < 1e-12 && (last.q[2] - 0.5).abs() < 1e-12;
        assert_eq!(
            parallelogram,
            how == ChangePoints::Smooth,
            "{how:?}: {:?}",
            last.q
        );
    }
}

/// A streamed sweep hands over exactly the samples the collected one
/// keeps, and ends the same way: through a full turn, and to a limit
/// position.
#[test]
fn a_streamed_sweep_gives_the_collected_ones_samples() {
    for (values, start) in [
        (vec![0.1, 0.3, 0.0], [0.0, 0.0, 0.4]),
        (vec![0.3, 0.2, 0.0], [0.0, 0.0, 0.5]),
    ] {
        let m = model("SliderCrank", &values);
        let sweep = || {
            m.sweep("phi", &start)
                .expect("phi is a driver")
                .turn()
                .steps(120)
                .rate(7.0)
        };
        let collected = sweep().run();
        let mut streamed = Vec::new();
        let end = sweep().for_each(|at, motion| streamed.push((at, motion.clone())));
        assert_eq!(streamed.len(), collected.samples.len());
        for ((at, motion), sample) in streamed.iter().zip(&collected.samples) {
            assert_eq!(*at, sample.at);
            assert_eq!(motion, &sample.motion);
        }
        assert_eq!(end.stop, collected.stop);
        assert_eq!(end.change_points, collected.change_points);
    }
}

/// A stepper's poses and positions are its steps' (x = a cos φ + √(b² −
/// a² sin² φ) for the slider, independently), and tolerance deviations
/// over motions kept outside a sweep are those of the sweep.
#[test]
fn poses_positions_and_deviations_over_kept_motions() {
    let text = "struct Crank {
        params   { a, b }
        drivers  { phi }
        unknowns { th, x }
        points   { B = polar(a, phi); C = vec2(x, 0.0); D = B + polar(b, th); }
        loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
        sensitivities { a, b }
    }";
    let mut m = Model::compile(text).expect("compiles");
    m.set_values(&[0.1, 0.3]).expect("two parameters");
    let options = kinematics_core::Options::DEFAULT;
    let mut poser = m.stepper(&options).expect("valid");
    let mut stepper = m.stepper(&options).expect("valid");
    let mut q = vec![0.0, 0.0, 0.4];
    let mut r = vec![0.0; 6];
    for k in 1..=72 {
        q[0] = f64::from(k) * 5f64.to_radians();
        let pose = poser.pose(&q).expect("assembles").to_vec();
        poser.positions(&mut r).expect("finite");
        let s = stepper.step(&q, &[3.0], &[0.0]).expect("steps");
        assert_eq!(pose, s.q);
        let x = 0.1 * q[0].cos() + (0.09 - 0.01 * q[0].sin().powi(2)).sqrt();
        assert!((pose[2] - x).abs() < 1e-15 && (r[2] - x).abs() < 1e-15);
        assert_eq!(r[..2], s.points[0].position[..]);
        // D, at the end of the rod (through θ's cosine and sine), is C.
        assert!((r[4] - x).abs() < 1e-15 && r[5].abs() < 1e-15, "{r:?}");
        q.copy_from_slice(&pose);
    }
    assert!(poser.positions(&mut [0.0; 3]).is_err());
    let sweep = m
        .sweep("phi", &[0.0, 0.0, 0.4])
        .expect("phi is a driver")
        .steps(24)
        .rate(3.0)
        .run();
    let t = [("a", 1e-4), ("b", 2e-4)];
    let direct = m.point_deviations(&sweep, "C", &t).expect("deviations");
    let kept: Vec<_> = sweep
        .samples
        .iter()
        .map(|s| (s.at, s.motion.clone()))
        .collect();
    let over = m
        .point_deviations_over(
            kept.len(),
            |i, motion| {
                motion.clone_from(&kept[i].1);
                kept[i].0
            },
            "C",
            &t,
        )
        .expect("deviations");
    assert_eq!(direct, over);
    // The slider's worst case: |∂x/∂a| t_a + |∂x/∂b| t_b, with ∂x/∂a =
    // cos φ − a sin² φ / √(b² − a² sin² φ) and ∂x/∂b = b / √(…).
    for d in &over {
        let (s, c) = d.at.sin_cos();
        let root = (0.09 - 0.01 * s * s).sqrt();
        let worst = (c - 0.1 * s * s / root).abs() * 1e-4 + (0.3 / root) * 2e-4;
        assert!((d.position_components[0] - worst).abs() < 1e-16, "{d:?}");
    }
}

/// A sweep of poses gives the full sweep's poses and positions, and stops
/// at the same limit position (by the same bisection).
#[test]
fn a_sweep_of_poses_follows_the_full_sweep_to_its_limit() {
    let m = model("SliderCrank", &[0.3, 0.2, 0.0]);
    let sweep = || {
        m.sweep("phi", &[0.0, 0.0, 0.5])
            .expect("phi is a driver")
            .turn()
            .steps(360)
    };
    let full = sweep().run();
    let mut poses = Vec::new();
    let end = sweep().for_each_pose(|at, q, r| poses.push((at, q.to_vec(), r.to_vec())));
    assert_eq!(poses.len(), full.samples.len());
    for ((at, q, r), s) in poses.iter().zip(&full.samples) {
        assert_eq!(*at, s.at);
        assert!(
            q.iter()
                .zip(&s.motion.q)
                .all(|(x, y)| (x - y).abs() <= 1e-15),
            "{q:?} / {:?}",
            s.motion.q
        );
        // The drivers' cosines and sines are carried from step to step
        // (rotated by each increment): the two sweeps may carry them
        // through different steps, to round-off.
        assert!(
            r[..2]
                .iter()
                .zip(&s.motion.points[0].position)
                .all(|(x, y)| (x - y).abs() <= 1e-15),
            "{r:?} / {:?}",
            s.motion.points[0].position
        );
    }
    let (a, b) = (end.stop.expect("stops"), full.stop.expect("stops"));
    assert_eq!(a.reason, b.reason);
    assert!(
        (a.at - b.at).abs() <= 4.0 * f64::EPSILON,
        "{} / {}",
        a.at,
        b.at
    );
}

/// A sweep handed over as flat arrays (`for_each_flat`) gives exactly the
/// motions `for_each` gives: through a full turn of the six-axis arm (its
/// frames among the outputs), and past a parallelogram's fold, where the
/// sample after the change point is a motion chosen among the
/// assemblies, not the stepper's.
#[test]
fn flat_samples_are_the_motions() {
    use kinematics_core::sweep::ChangePoints;
    fn check<'m>(
        m: &'m Model,
        sweep: &dyn Fn() -> kinematics_core::runtime::SweepBuilder<'m>,
    ) -> kinematics_core::runtime::SweepEnd {
        let mut motions = Vec::new();
        let end = sweep().for_each(|at, motion| motions.push((at, motion.clone())));
        let mut flats = Vec::new();
        let flat_end = sweep().for_each_flat(|at, s| {
            flats.push((
                at,
                s.q.to_vec(),
                s.qd.to_vec(),
                s.qdd.to_vec(),
                s.outputs.to_vec(),
                [s.conditioning, s.det_sign, s.residual],
            ));
        });
        assert_eq!(end, flat_end);
        assert_eq!(motions.len(), flats.len());
        let d = m.point_dimension();
        for ((at, motion), (flat_at, q, qd, qdd, outputs, scalars)) in motions.iter().zip(&flats) {
            assert_eq!(at, flat_at);
            assert_eq!((&motion.q, &motion.qd, &motion.qdd), (q, qd, qdd));
            assert_eq!(
                [motion.conditioning, motion.det_sign, motion.residual],
                *scalars
            );
            let points = motion.points.len() * 3 * d;
            for (i, p) in motion.points.iter().enumerate() {
                let at = 3 * i * d;
                assert_eq!(p.position[..], outputs[at..at + d]);
                assert_eq!(p.velocity[..], outputs[at + d..at + 2 * d]);
                assert_eq!(p.acceleration[..], outputs[at + 2 * d..at + 3 * d]);
            }
            assert_eq!(outputs.len(), points + 24 * motion.frames.len());
            for (f, values) in motion.frames.iter().zip(outputs[points..].chunks_exact(24)) {
                let values: &[f64; 24] = values.try_into().expect("24 values");
                assert_eq!(*f, kinematics_core::FrameState::from_values(values));
            }
        }
        end
    }
    let arm = model("SixAxisArm", &[0.4, 0.35, 0.3, 0.08, 0.1]);
    let end = check(&arm, &|| {
        arm.sweep("q1", &[0.1, -0.4, 0.7, 0.2, -0.3, 0.5])
            .expect("q1 is a driver")
            .turn()
            .steps(90)
            .rate(1.5)
    });
    assert!(end.stop.is_none());
    let four_bar = model("FourBar", &[0.05, 0.12, 0.05, 0.12, 0.0, 0.0]);
    let start = four_bar.assemble(&[-0.5, 0.0, -0.5]).expect("assembles");
    let end = check(&four_bar, &|| {
        four_bar
            .sweep("phi", &start)
            .expect("phi is a driver")
            .to(0.5)
            .steps(19)
            .rate(2.0)
            .change_points(ChangePoints::Smooth)
    });
    assert_eq!(end.change_points.len(), 1);
}
