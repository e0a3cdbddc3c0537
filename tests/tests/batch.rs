//! Batches of designs of a run-time model (`runtime::Batch`): each
//! design's record equals the sweep or step of the same model with its
//! values, value for value, with the same samples and stop; the slider's
//! position against its closed form; the layout of several outputs; and
//! the errors of a batch set up wrong.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic, clippy::cast_precision_loss)]

use kinematics_core::runtime::{Batch, BatchResults, BatchSweep, Early, Model, Output, Reduce};
use kinematics_core::sweep::ChangePoints;
use kinematics_core::{Error, Options};

const SLIDER_CRANK: &str = "struct SliderCrank {
    params   { a, b }
    drivers  { phi }
    unknowns { th, x }
    points   { B = polar(a, phi); C = vec2(x, 0.0); }
    loops    { B + polar(b, th) == C; }
}";

fn turn(steps: usize, change_points: ChangePoints) -> BatchSweep {
    BatchSweep {
        driver: 0,
        from: None,
        to: None,
        turns: Some(1.0),
        steps,
        change_points,
    }
}

fn four_bar() -> Model {
    let text = kinematics_examples::definition("FourBar").expect("an example");
    let mut m = Model::compile(text).expect("it compiles");
    m.set_values(&[0.04, 0.12, 0.10, 0.11, 0.06, 0.5])
        .expect("six values");
    m
}

#[test]
fn each_design_is_its_own_sweep_value_for_value() {
    let m = four_bar();
    let start = m.assemble(&[0.0, 0.5, 1.5]).expect("assembles");
    let outputs = [
        Output::Coordinate(2),
        Output::Rate(1),
        Output::Acceleration(2),
        Output::Position(4),
        Output::Velocity(4),
        Output::PointAcceleration(4),
        Output::Conditioning,
    ];
    // A crank-rocker, a longer crank, and a crank too long to turn (a
    // limit position: the sweep stops there).
    let designs = [
        [0.04, 0.12, 0.10, 0.11, 0.06, 0.5],
        [0.05, 0.13, 0.09, 0.11, 0.04, 0.2],
        [0.09, 0.12, 0.10, 0.11, 0.06, 0.5],
    ];
    let flat: Vec<f64> = designs.iter().flatten().copied().collect();
    for change_points in [
        ChangePoints::Stop,
        ChangePoints::Smooth,
        ChangePoints::Switch,
    ] {
        let batch = Batch::new(
            &m,
            &start,
            &[7.0],
            &[3.0],
            Some(turn(90, change_points)),
            &outputs,
            &Options::DEFAULT,
        )
        .expect("a valid batch");
        let results = batch.run(&flat);
        assert_eq!(results.samples.len(), 3);
        for (d, values) in designs.iter().enumerate() {
            let mut one = m.clone();
            one.set_values(values).expect("six values");
            let mut rows: Vec<Vec<f64>> = Vec::new();
            let end = one
                .sweep("phi", &start)
                .expect("a driver")
                .steps(90)
                .turns(1.0)
                .rate(7.0)
                .acceleration(3.0)
                .change_points(change_points)
                .for_each(|_, s| {
                    let p = &s.points[4];
                    let mut row = vec![s.q[2], s.qd[1], s.qdd[2]];
                    row.extend_from_slice(&p.position);
                    row.extend_from_slice(&p.velocity);
                    row.extend_from_slice(&p.acceleration);
                    row.push(s.conditioning);
                    rows.push(row);
                });
            assert_eq!(results.samples[d], rows.len(), "design {d}");
            assert_eq!(
                results.early[d].as_ref().map(ToString::to_string),
                end.stop.as_ref().map(ToString::to_string),
                "design {d}"
            );
            // Output by output, row by row, bit for bit; NaN past the
            // samples.
            let mut column = 0;
            for k in 0..outputs.len() {
                let width = batch.width(k);
                let got = results.output(&batch, d, k);
                assert_eq!(got.len(), batch.rows() * width);
                for r in 0..batch.rows() {
                    for c in 0..width {
                        let v = got[r * width + c];
                        match rows.get(r) {
                            Some(row) => assert_eq!(
                                v.to_bits(),
                                row[column + c].to_bits(),
                                "design {d}, output {k}, row {r}"
                            ),
                            None => assert!(
                                v.is_nan(),
                                "design {d}, output {k}, row {r} past the samples: {v}"
                            ),
                        }
                    }
                }
                column += width;
            }
        }
        // The third design stops at a limit position (its crank is longer
        // than the ground less the rocker can follow).
        assert!(
            matches!(results.early[2], Some(Early::Stopped(_))),
            "{:?}",
            results.early[2]
        );
        assert!(results.early[0].is_none() && results.early[1].is_none());
    }
}

#[test]
fn the_slider_follows_its_closed_form_in_every_design() {
    let m = Model::compile(SLIDER_CRANK).expect("it compiles");
    let start = [0.0, 0.0, 0.3];
    let batch = Batch::new(
        &m,
        &start,
        &[1.0],
        &[0.0],
        Some(turn(360, ChangePoints::Stop)),
        &[Output::Coordinate(2)],
        &Options::DEFAULT,
    )
    .expect("a valid batch");
    let designs: Vec<[f64; 2]> = (0..50)
        .map(|k| [0.05 + 0.001 * k as f64, 0.2 + 0.002 * k as f64])
        .collect();
    let flat: Vec<f64> = designs.iter().flatten().copied().collect();
    let results = batch.run(&flat);
    for (d, [a, b]) in designs.iter().enumerate() {
        assert_eq!(results.samples[d], 360);
        for (k, x) in results.output(&batch, d, 0).iter().enumerate() {
            let phi = std::f64::consts::TAU * k as f64 / 360.0;
            // x = a cos φ + √(b² − a² sin² φ).
            let want = a * phi.cos() + (b * b - a * a * phi.sin().powi(2)).sqrt();
            assert!(
                (x - want).abs() < 1e-14,
                "design {d}, φ = {phi}: {x} against {want}"
            );
        }
    }
}

#[test]
fn a_step_batch_is_the_step_of_each_design() {
    let m = Model::compile(SLIDER_CRANK).expect("it compiles");
    let start = [1.0, -0.3, 0.35];
    let batch = Batch::new(
        &m,
        &start,
        &[2.0],
        &[0.5],
        None,
        &[Output::Acceleration(2), Output::Velocity(1)],
        &Options::DEFAULT,
    )
    .expect("a valid batch");
    assert_eq!(batch.rows(), 1);
    // The last design's rod cannot reach the slider's line at φ = 1.
    let flat = [0.1, 0.3, 0.12, 0.33, 0.1, 0.05];
    let results = batch.run(&flat);
    for d in 0..2 {
        let mut one = m.clone();
        one.set_values(&flat[2 * d..2 * d + 2]).expect("two values");
        let s = one.step(&start, &[2.0], &[0.5]).expect("a step");
        assert_eq!(results.output(&batch, d, 0), [s.qdd[2]]);
        assert_eq!(results.output(&batch, d, 1), &s.points[1].velocity[..]);
        assert_eq!(results.samples[d], 1);
    }
    assert_eq!(results.samples[2], 0);
    assert!(
        matches!(
            results.early[2],
            Some(Early::Failed(Error::CannotAssemble { .. }))
        ),
        "{:?}",
        results.early[2]
    );
    assert!(results.output(&batch, 2, 0)[0].is_nan());
}

#[test]
fn a_batch_set_up_wrong_says_what_is_wrong() {
    let m = Model::compile(SLIDER_CRANK).expect("it compiles");
    let new = |start: &[f64], outputs: &[Output], sweep| {
        Batch::new(&m, start, &[1.0], &[0.0], sweep, outputs, &Options::DEFAULT).map(|_| ())
    };
    let start = [0.0, 0.0, 0.3];
    assert!(matches!(
        new(&start[..2], &[], None),
        Err(Error::WrongLength {
            expected: 3,
            found: 2,
            ..
        })
    ));
    for bad in [
        Output::Coordinate(3),
        Output::Position(2),
        Output::PointAcceleration(7),
    ] {
        let e = new(&start, &[bad], None).expect_err("an index the model lacks");
        assert!(e.to_string().contains("index"), "{e}");
    }
    let e = new(&start, &[], None).expect_err("nothing to keep");
    assert!(e.to_string().contains("at least one output"), "{e}");
    let mut sweep = turn(10, ChangePoints::Stop);
    sweep.driver = 1;
    assert!(
        new(&start, &[], Some(sweep)).is_err(),
        "an unknown is not a driver"
    );
    let options = Options {
        tolerance: -1.0,
        ..Options::DEFAULT
    };
    assert!(Batch::new(&m, &start, &[1.0], &[0.0], None, &[], &options).is_err());
    // A design with a value that is not finite fails alone.
    let batch = Batch::new(
        &m,
        &start,
        &[1.0],
        &[0.0],
        Some(turn(10, ChangePoints::Stop)),
        &[Output::Coordinate(2)],
        &Options::DEFAULT,
    )
    .expect("a valid batch");
    let results = batch.run(&[0.1, f64::NAN, 0.1, 0.3]);
    assert!(results.early[0].is_some(), "a NaN rod is refused");
    assert_eq!(results.samples[0], 0);
    assert!(results.early[1].is_none());
    assert_eq!(results.samples[1], 10);
}

#[test]
fn a_reduced_batch_keeps_the_extremes_of_every_design() {
    let m = Model::compile(SLIDER_CRANK).expect("it compiles");
    let start = [0.0, 0.0, 0.3];
    let outputs = [Output::Coordinate(2), Output::PointAcceleration(0)];
    let batch = |reduce| {
        Batch::new(
            &m,
            &start,
            &[3.0],
            &[0.0],
            Some(turn(360, ChangePoints::Stop)),
            &outputs,
            &Options::DEFAULT,
        )
        .expect("a valid batch")
        .reduced(reduce)
    };
    let designs: Vec<f64> = (0..20)
        .flat_map(|k| [0.05 + 0.002 * f64::from(k), 0.25])
        .collect();
    let every = batch(Reduce::Samples);
    let all = every.run(&designs);
    for (reduce, name) in [
        (Reduce::Max, "max"),
        (Reduce::Min, "min"),
        (Reduce::Peak, "peak"),
    ] {
        let b = batch(reduce);
        assert_eq!(b.rows(), 1);
        let r = b.run(&designs);
        for d in 0..20 {
            let a = designs[2 * d];
            let x = r.output(&b, d, 0)[0];
            // The slider's extremes in closed form: a + b at φ = 0, b − a
            // at φ = π (both on the grid of 360 steps).
            let want = match reduce {
                Reduce::Min => 0.25 - a,
                _ => 0.25 + a,
            };
            assert!(
                (x - want).abs() < 1e-15,
                "{name}, design {d}: {x} against {want}"
            );
            // The crank pin's acceleration: a ω² in magnitude everywhere,
            // its components between −a ω² and a ω².
            let pin = r.output(&b, d, 1);
            let full = all.output(&every, d, 1);
            match reduce {
                Reduce::Peak => {
                    assert_eq!(pin.len(), 1);
                    assert!((pin[0] - a * 9.0).abs() < 1e-13, "{pin:?}");
                }
                Reduce::Max => {
                    assert_eq!(
                        pin,
                        [
                            full.iter().step_by(2).copied().fold(f64::MIN, f64::max),
                            full.iter()
                                .skip(1)
                                .step_by(2)
                                .copied()
                                .fold(f64::MIN, f64::max)
                        ]
                    );
                }
                _ => {
                    assert_eq!(
                        pin,
                        [
                            full.iter().step_by(2).copied().fold(f64::MAX, f64::min),
                            full.iter()
                                .skip(1)
                                .step_by(2)
                                .copied()
                                .fold(f64::MAX, f64::min)
                        ]
                    );
                }
            }
        }
    }
    // A design with no sample reduces to NaN.
    let r = batch(Reduce::Peak).run(&[0.1, f64::NAN]);
    assert!(r.output(&batch(Reduce::Peak), 0, 0)[0].is_nan());
}

#[test]
fn a_batch_of_positions_only_is_each_designs_poses_and_its_closed_form() {
    let m = Model::compile(SLIDER_CRANK).expect("it compiles");
    let start = [0.0, 0.0, 0.3];
    let c = m.point_names().iter().position(|p| *p == "C").expect("C");
    let of = |second: Output| {
        Batch::new(
            &m,
            &start,
            &[1.0],
            &[0.0],
            Some(turn(360, ChangePoints::Stop)),
            &[Output::Coordinate(2), second],
            &Options::DEFAULT,
        )
        .expect("a valid batch")
        .positions_only()
    };
    let batch = of(Output::Position(c)).expect("positions only");
    // 50 designs that turn, and one whose rod is shorter than its crank
    // (a limit position where a sin φ = b).
    let mut designs: Vec<[f64; 2]> = (0..50)
        .map(|k| [0.05 + 0.001 * k as f64, 0.2 + 0.002 * k as f64])
        .collect();
    designs.push([0.1, 0.05]);
    let flat: Vec<f64> = designs.iter().flatten().copied().collect();
    let results = batch.run(&flat);
    for (d, &[a, b]) in designs.iter().enumerate() {
        // The same as the design's own sweep of poses, value for value.
        let own = m.with_values(&[a, b]).expect("the values");
        let (mut xs, mut cs) = (Vec::new(), Vec::new());
        let end = own
            .sweep("phi", &start)
            .expect("a sweep")
            .turns(1.0)
            .steps(360)
            .for_each_pose(|_, q, r| {
                xs.push(q[2]);
                cs.extend_from_slice(&r[2 * c..2 * c + 2]);
            });
        assert_eq!(results.samples[d], xs.len(), "design {d}");
        assert_eq!(results.early[d].is_some(), end.stop.is_some(), "design {d}");
        let (x, p) = (results.output(&batch, d, 0), results.output(&batch, d, 1));
        assert_eq!(&x[..xs.len()], &xs[..], "design {d}");
        assert_eq!(&p[..cs.len()], &cs[..], "design {d}");
        if d < 50 {
            assert_eq!(xs.len(), 360);
            for (k, x) in xs.iter().enumerate() {
                let phi = std::f64::consts::TAU * k as f64 / 360.0;
                let want = a * phi.cos() + (b * b - a * a * phi.sin().powi(2)).sqrt();
                assert!((x - want).abs() < 1e-14, "design {d}, φ = {phi}");
            }
        }
    }
    // It stops at the limit, a sin φ = b: φ = 30°.
    let short = results.samples[50];
    assert!((30..=31).contains(&short), "{short}");
    // Without a sweep, the one pose at the start: x = a + b at φ = 0.
    let one = Batch::new(
        &m,
        &start,
        &[1.0],
        &[0.0],
        None,
        &[Output::Coordinate(2), Output::Position(c)],
        &Options::DEFAULT,
    )
    .expect("a valid batch")
    .positions_only()
    .expect("positions only");
    let posed = one.run(&[0.1, 0.25, 0.05, 0.2]);
    assert_eq!(posed.samples, [1, 1]);
    for (d, want) in [(0, 0.35), (1, 0.25)] {
        assert!((posed.output(&one, d, 0)[0] - want).abs() < 1e-15);
        assert!((posed.output(&one, d, 1)[0] - want).abs() < 1e-15);
    }
    // Reduced, the extremes of the same samples.
    let high = of(Output::Position(c))
        .expect("positions only")
        .reduced(Reduce::Max);
    let extremes = high.run(&flat);
    for d in 0..designs.len() {
        let x = results.output(&batch, d, 0);
        let n = results.samples[d];
        let max = x[..n].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(extremes.output(&high, d, 0), [max], "design {d}");
    }
    // Anything but a coordinate's value or a point's position is refused,
    // with what it may keep.
    for other in [
        Output::Velocity(c),
        Output::PointAcceleration(c),
        Output::Rate(2),
        Output::Acceleration(2),
        Output::Conditioning,
    ] {
        let Err(Error::InvalidOption { requirement, .. }) = of(other) else {
            panic!("{other:?} in a batch of positions only");
        };
        assert!(requirement.contains("a point's position"), "{requirement}");
    }
}

/// Every value of two batches' records the same, bit for bit (NaN for
/// NaN), the first `a` in lanes, the second `b` design by design.
fn same_records(a: &BatchResults, b: &BatchResults, what: &str) {
    for (d, (x, y)) in a
        .values
        .chunks(a.record)
        .zip(b.values.chunks(b.record))
        .enumerate()
    {
        for (i, (x, y)) in x.iter().zip(y).enumerate() {
            assert!(
                x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
                "{what}, design {d}, value {i}: {x} in lanes, {y} alone"
            );
        }
    }
}

/// The batch `batch(lanes)` of `designs` in pairs in lanes and design by
/// design: every design turns fully (`samples` each) either way, and the
/// records are the same bit for bit; the results in lanes, and that
/// batch.
fn turn_in_pairs<'m>(
    batch: impl Fn(bool) -> Batch<'m>,
    designs: &[f64],
    samples: usize,
    what: &str,
) -> (BatchResults, Batch<'m>) {
    let (paired, alone) = (batch(true), batch(false));
    assert!(paired.in_pairs(), "{what}");
    let (a, b) = (paired.run(designs), alone.run(designs));
    assert!(
        a.samples.iter().all(|&n| n == samples),
        "{what}: {:?}",
        a.samples
    );
    assert!(a.early.iter().all(Option::is_none), "{what}: {:?}", a.early);
    assert_eq!((&a.samples, &a.early), (&b.samples, &b.early), "{what}");
    same_records(&a, &b, what);
    (a, paired)
}

/// 37 four-bar designs: crank-rockers, and every ninth a long crank: it
/// assembles at φ = 0, and stops where |BD| = b + c if a + d exceeds it
/// (its pair is then swept alone, design by design); its unknowns turn
/// by more than 1/32 rad in some steps, which each design's stepper
/// takes.
fn cranks_and_long_cranks() -> Vec<f64> {
    (0..37)
        .flat_map(|k| {
            let t = f64::from(k);
            let (a, c) = if k % 9 == 4 {
                (0.15, 0.13)
            } else {
                (0.03 + 0.0004 * t, 0.10)
            };
            [
                a,
                0.12 + 0.001 * t,
                c,
                0.11,
                0.06 - 0.001 * t,
                0.5 + 0.01 * t,
            ]
        })
        .collect()
}

/// A batch of positions only of the four-bar runs its designs in pairs in
/// vector lanes; every design's samples, stop and values are those of
/// the same batch design by design, bit for bit (and of its own sweep of
/// poses): designs that turn, designs that stop at a limit position, an
/// odd count, and a sweep long enough for the carried cosines and sines
/// to be refreshed many times.
#[test]
fn a_batch_of_poses_in_lanes_is_each_designs_sweep() {
    let m = four_bar();
    let start = m.assemble(&[0.0, 0.5, 1.5]).expect("assembles");
    let outputs = [
        Output::Coordinate(1),
        Output::Coordinate(2),
        Output::Position(4),
    ];
    let designs = cranks_and_long_cranks();
    for (steps, turns) in [(360, 1.0), (3600, 2.0)] {
        let sweep = BatchSweep {
            turns: Some(turns),
            ..turn(steps, ChangePoints::Stop)
        };
        for reduce in [Reduce::Samples, Reduce::Peak, Reduce::Max, Reduce::Min] {
            let batch = |lanes: bool| {
                Batch::new(
                    &m,
                    &start,
                    &[1.0],
                    &[0.0],
                    Some(sweep.clone()),
                    &outputs,
                    &Options::DEFAULT,
                )
                .expect("a valid batch")
                .positions_only()
                .expect("positions only")
                .reduced(reduce)
                .in_lanes(lanes)
            };
            let (paired, alone) = (batch(true), batch(false));
            assert!(paired.in_pairs() && !alone.in_pairs());
            let (a, b) = (paired.run(&designs), alone.run(&designs));
            assert_eq!(a.samples, b.samples, "{steps} steps");
            let stopped = |r: &kinematics_core::runtime::BatchResults| {
                r.early.iter().map(Option::is_some).collect::<Vec<_>>()
            };
            assert_eq!(stopped(&a), stopped(&b));
            // A long crank stops where a + d > b + c (|BD| reaches b + c).
            let long = designs
                .chunks(6)
                .filter(|p| p[0] + p[3] > p[1] + p[2])
                .count();
            assert!(long > 0);
            assert_eq!(stopped(&a).iter().filter(|s| **s).count(), long);
            same_records(&a, &b, &format!("{steps} steps"));
            // A design's own sweep of poses: the same samples.
            if reduce == Reduce::Samples {
                let own = m.with_values(&designs[6..12]).expect("its values");
                let mut th3 = Vec::new();
                own.sweep("phi", &start)
                    .expect("a sweep")
                    .turns(turns)
                    .steps(steps)
                    .for_each_pose(|_, q, _| th3.push(q[1]));
                assert_eq!(th3.len(), a.samples[1]);
                for (x, y) in th3.iter().zip(a.output(&paired, 1, 0)) {
                    assert!((x - y).abs() <= 1e-12, "{x} {y}");
                }
            }
        }
    }
}

/// A five-bar, two drivers: a batch of steps and one of positions only in
/// lanes sweep either driver with the other held, and every design's
/// record is that of the same batch design by design, bit for bit (each
/// driver's carried cosine and sine refreshed in lanes as its stepper
/// refreshes them).
#[test]
fn a_batch_of_poses_in_lanes_of_two_drivers_is_each_designs_sweep() {
    let text = "struct FiveBar {
        params   { a, b, c, d, e }
        drivers  { phi1, phi2 }
        unknowns { th3, th4 }
        points   { B = polar(a, phi1); P = B + polar(b, th3); }
        loops    { polar(a, phi1) + polar(b, th3) == vec2(d, 0.0) + polar(c, phi2) + polar(e, th4); }
    }";
    let mut m = Model::compile(text).expect("it compiles");
    m.set_values(&[0.03, 0.10, 0.03, 0.10, 0.10])
        .expect("five values");
    let start = m.assemble(&[1.5, 1.6, 0.6, 2.5]).expect("assembles");
    // |BD| stays within (0.04, 0.16), inside (|b − e|, b + e): every
    // design turns either crank whole.
    let designs: Vec<f64> = (0..11)
        .flat_map(|k| {
            let t = f64::from(k);
            [
                0.03 + 0.0005 * t,
                0.10 + 0.001 * t,
                0.03,
                0.10,
                0.10 - 0.0005 * t,
            ]
        })
        .collect();
    for driver in [0, 1] {
        let sweep = BatchSweep {
            driver,
            ..turn(720, ChangePoints::Stop)
        };
        // And the batch of steps, the held driver at rest.
        let steps = |lanes: bool| {
            Batch::new(
                &m,
                &start,
                &[
                    if driver == 0 { 6.0 } else { 0.0 },
                    if driver == 1 { -4.0 } else { 0.0 },
                ],
                &[0.0, 0.0],
                Some(sweep.clone()),
                &[
                    Output::Rate(3),
                    Output::PointAcceleration(1),
                    Output::Conditioning,
                ],
                &Options::DEFAULT,
            )
            .expect("a valid batch")
            .in_lanes(lanes)
        };
        turn_in_pairs(steps, &designs, 720, &format!("steps of driver {driver}"));
        let batch = |lanes: bool| {
            Batch::new(
                &m,
                &start,
                &[1.0, 0.0],
                &[0.0, 0.0],
                Some(sweep.clone()),
                &[Output::Coordinate(2), Output::Position(1)],
                &Options::DEFAULT,
            )
            .expect("a valid batch")
            .positions_only()
            .expect("positions only")
            .in_lanes(lanes)
        };
        let (a, paired) = turn_in_pairs(batch, &designs, 720, &format!("poses of driver {driver}"));
        // The held driver stays at its start, the swept one turns.
        let held = 1 - driver;
        let own = m.with_values(&designs[5..10]).expect("its values");
        let mut poses = Vec::new();
        own.sweep(own.coordinates()[driver].name, &start)
            .expect("a sweep")
            .turns(1.0)
            .steps(720)
            .for_each_pose(|_, q, _| poses.push((q[held], q[2])));
        assert_eq!(poses.len(), 720);
        for ((h, th3), y) in poses.iter().zip(a.output(&paired, 1, 0)) {
            assert!(h.to_bits() == start[held].to_bits());
            assert!((th3 - y).abs() <= 1e-12, "{th3} {y}");
        }
    }
}

/// A batch of full steps (rates and accelerations) of the four-bar runs
/// its designs in pairs in vector lanes; every design's samples, stop and
/// values are those of the same batch design by design, bit for bit:
/// designs that turn, designs that stop at a limit position (the pair's
/// sweeps then part, the stopping one bisecting alone), an odd count,
/// sweeps long enough for many refreshes of the carried values, every
/// reduction, and every kind of output.
#[test]
fn a_batch_of_steps_in_lanes_is_each_designs_sweep() {
    let m = four_bar();
    let start = m.assemble(&[0.0, 0.5, 1.5]).expect("assembles");
    let outputs = [
        Output::Coordinate(1),
        Output::Rate(2),
        Output::Acceleration(1),
        Output::Position(4),
        Output::Velocity(4),
        Output::PointAcceleration(4),
        Output::Conditioning,
    ];
    let designs = cranks_and_long_cranks();
    for (steps, turns) in [(360, 1.0), (3600, 2.0)] {
        let sweep = BatchSweep {
            turns: Some(turns),
            ..turn(steps, ChangePoints::Stop)
        };
        for reduce in [Reduce::Samples, Reduce::Peak, Reduce::Max, Reduce::Min] {
            let batch = |lanes: bool| {
                Batch::new(
                    &m,
                    &start,
                    &[12.0],
                    &[-4.0],
                    Some(sweep.clone()),
                    &outputs,
                    &Options::DEFAULT,
                )
                .expect("a valid batch")
                .reduced(reduce)
                .in_lanes(lanes)
            };
            let (paired, alone) = (batch(true), batch(false));
            assert!(paired.in_pairs() && !alone.in_pairs());
            let (a, b) = (paired.run(&designs), alone.run(&designs));
            assert_eq!(a.samples, b.samples, "{steps} steps");
            assert_eq!(a.early, b.early, "{steps} steps");
            let long = designs
                .chunks(6)
                .filter(|p| p[0] + p[3] > p[1] + p[2])
                .count();
            assert!(long > 0);
            assert_eq!(a.early.iter().filter(|e| e.is_some()).count(), long);
            same_records(&a, &b, &format!("{steps} steps, {reduce:?}"));
            // A design's own sweep: the same samples.
            if reduce == Reduce::Samples {
                let own = m.with_values(&designs[6..12]).expect("its values");
                let mut rates = Vec::new();
                own.sweep("phi", &start)
                    .expect("a sweep")
                    .turns(turns)
                    .steps(steps)
                    .rate(12.0)
                    .acceleration(-4.0)
                    .for_each(|_, s| rates.push(s.qd[2]));
                assert_eq!(rates.len(), a.samples[1]);
                for (x, y) in rates.iter().zip(a.output(&paired, 1, 1)) {
                    assert!(x.to_bits() == y.to_bits(), "{x} {y}");
                }
            }
        }
    }
}

/// Designs at and near a parallelogram (change points at φ = 0 and π)
/// in a batch of steps in lanes: passed on the smooth branch, on the
/// other, or stopped at, each design's record is the batch's design by
/// design, bit for bit.
#[test]
fn a_batch_of_steps_in_lanes_through_change_points_is_each_designs_sweep() {
    let m = four_bar();
    let start = m.assemble(&[0.3, 1.2, 1.6]).expect("assembles");
    // a = c and b = d: a parallelogram; then ever further from one.
    let designs: Vec<f64> = (0..9)
        .flat_map(|k| {
            let t = f64::from(k);
            [0.05, 0.11, 0.05 + 0.002 * t, 0.11, 0.06, 0.5]
        })
        .collect();
    for change_points in [
        ChangePoints::Stop,
        ChangePoints::Smooth,
        ChangePoints::Switch,
    ] {
        let sweep = BatchSweep {
            turns: Some(1.0),
            ..turn(720, change_points)
        };
        let batch = |lanes: bool| {
            Batch::new(
                &m,
                &start,
                &[5.0],
                &[0.0],
                Some(sweep.clone()),
                &[
                    Output::Coordinate(2),
                    Output::Rate(1),
                    Output::PointAcceleration(4),
                ],
                &Options::DEFAULT,
            )
            .expect("a valid batch")
            .in_lanes(lanes)
        };
        let (paired, alone) = (batch(true), batch(false));
        assert!(paired.in_pairs());
        let (a, b) = (paired.run(&designs), alone.run(&designs));
        assert_eq!(a.samples, b.samples, "{change_points:?}");
        assert_eq!(a.early, b.early, "{change_points:?}");
        for (i, (x, y)) in a.values.iter().zip(&b.values).enumerate() {
            assert!(
                x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
                "{change_points:?}, value {i}: {x} in lanes, {y} alone"
            );
        }
        if change_points == ChangePoints::Stop {
            assert!(
                a.early[0].is_some(),
                "the parallelogram stops at its change point"
            );
        } else {
            assert_eq!(a.samples[0], 720, "{change_points:?}: passed");
        }
    }
}
