//! A batch of designs against the steps it is made of: designs of the
//! four-bar (its coupler point P) and of the Strider leg (its foot H),
//! each swept over a turn of 360 positions with velocities and
//! accelerations, run-time models from the examples' text.
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin batch [rounds]
//! ```
//!
//! The reference is what a user writes with the stepper: for each design,
//! its values set in one model, a stepper, and 360 `step_flat` calls
//! from the previous pose with the crank advanced a degree, the point's
//! acceleration copied into an array kept for the design (no check of
//! limits or change points). The batch ([`Batch::run`] on a one-thread
//! pool) does the same work through the sweep driver, which also
//! predicts, tests for limits and change points and keeps the samples'
//! count and stops: design by design ([`Batch::in_lanes`] off) and in
//! pairs in vector lanes (on). Interleaved rounds, process CPU time; the
//! median ratios and the ranges of the rounds are printed. The results
//! are first checked equal (to 1e-12 of the largest value).
//!
//! Then positions only: the same designs, each posed over the turn by
//! the stepper's `pose` and `positions` (the point's position copied
//! into the design's array), against the batch of positions only
//! ([`Batch::positions_only`]) keeping the point's position, design by
//! design ([`Batch::in_lanes`] off) and in pairs in vector lanes (on),
//! checked equal first and timed the same way.
// A measuring harness: a failed step should stop it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::cast_precision_loss)]

use std::f64::consts::{FRAC_PI_2, TAU};
use std::hint::black_box;

use kinematics_bench::process_cpu_ns;
use kinematics_core::runtime::{Batch, BatchResults, BatchSweep, Model, Output};
use kinematics_core::sweep::ChangePoints;
use kinematics_core::{Coordinates, Options};
use kinematics_examples::Strider;

const STEPS: usize = 360;

/// A study: the model, its start, the point kept, the designs
/// (row-major) and their count.
struct Study {
    name: &'static str,
    model: Model,
    start: Vec<f64>,
    point: usize,
    designs: Vec<f64>,
    count: usize,
}

/// Uniform numbers in [0, 1), seeded (a linear congruential generator:
/// the designs need only be the same from run to run).
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn four_bar(count: usize) -> Study {
    let text = kinematics_examples::definition("FourBar").expect("an example");
    let mut model = Model::compile(text).expect("it compiles");
    model
        .set_values(&[0.04, 0.12, 0.10, 0.11, 0.06, 0.5])
        .unwrap();
    let start = model.assemble(&[0.0, 0.5, 1.5]).unwrap();
    let mut r = uniform(1);
    // Crank, coupler, rocker and coupler point drawn as in
    // `python/benchmarks/batch_million.py`; ground 0.11, β = 0.5.
    let designs = (0..count)
        .flat_map(|_| {
            let (a, b, c, p) = (
                0.02 + 0.04 * r(),
                0.10 + 0.04 * r(),
                0.08 + 0.04 * r(),
                0.03 + 0.06 * r(),
            );
            [a, b, c, 0.11, p, 0.5]
        })
        .collect();
    Study {
        name: "four-bar, P",
        point: model.point_names().iter().position(|p| *p == "P").unwrap(),
        model,
        start,
        designs,
        count,
    }
}

fn strider(count: usize) -> Study {
    let text = kinematics_examples::definition("Strider").expect("an example");
    let mut model = Model::compile(text).expect("it compiles");
    let base = Strider::PYLINKAGE;
    let values = [
        base.tri,
        base.ape,
        base.femur,
        base.rocker_l,
        base.rocker_s,
        base.phi,
        base.tibia,
        base.foot,
    ];
    model.set_values(&values).unwrap();
    let guess = Strider::pylinkage_guess(-FRAC_PI_2);
    let guess: Vec<f64> = (0..model.coordinates().len())
        .map(|j| guess.get(j).unwrap())
        .collect();
    let start = model.assemble(&guess).unwrap();
    let mut r = uniform(2);
    // Every length within ±2 % of pylinkage's example.
    let designs = (0..count)
        .flat_map(|_| {
            let mut v = values;
            for (k, x) in v.iter_mut().enumerate() {
                if ![1, 5].contains(&k) {
                    *x *= 0.98 + 0.04 * r();
                }
            }
            v
        })
        .collect();
    Study {
        name: "Strider, H",
        point: model.point_names().iter().position(|p| *p == "H").unwrap(),
        model,
        start,
        designs,
        count,
    }
}

/// The batch of `study`: every design over a turn of `STEPS` positions
/// at `omega`, its point's acceleration kept.
fn turns(study: &Study, omega: f64) -> Batch<'_> {
    turn_keeping(study, omega, Output::PointAcceleration(study.point))
}

/// A turn of [`STEPS`] positions of each design at `omega`, keeping
/// `output`.
fn turn_keeping(study: &Study, omega: f64, output: Output) -> Batch<'_> {
    let sweep = BatchSweep {
        driver: 0,
        from: None,
        to: None,
        turns: Some(1.0),
        steps: STEPS,
        change_points: ChangePoints::Stop,
    };
    Batch::new(
        &study.model,
        &study.start,
        &[omega],
        &[0.0],
        Some(sweep),
        &[output],
        &Options::DEFAULT,
    )
    .unwrap()
}

/// One run of one side on 200 designs of the four-bar, for instruction
/// counts under callgrind (`count-step`, `count-batch-alone`,
/// `count-batch-lanes`, and for positions
/// only `count-pose`, `count-poses-alone`, `count-poses-lanes`; the
/// difference with `count-none`, the set-up alone, is the run's).
fn count(which: &str, pool: &rayon::ThreadPool, omega: f64) {
    let study = four_bar(200);
    let dim = study.model.point_dimension();
    let mut reference = vec![f64::NAN; study.count * STEPS * dim];
    let batch = turns(&study, omega);
    match which {
        "count-step" => by_stepper(&study, omega, &mut reference),
        "count-batch-alone" | "count-batch-lanes" => {
            let batch = batch.in_lanes(which == "count-batch-lanes");
            black_box(pool.install(|| batch.run(&study.designs)));
        }
        "count-pose" => by_poses(&study, &mut reference),
        "count-poses-alone" | "count-poses-lanes" => {
            let poses = turn_keeping(&study, 1.0, Output::Position(study.point))
                .positions_only()
                .unwrap()
                .in_lanes(which == "count-poses-lanes");
            black_box(pool.install(|| poses.run(&study.designs)));
        }
        _ => {}
    }
    black_box(reference);
}

/// The reference: each design through the stepper, the point's
/// acceleration kept; the kept values, NaN past a failed step.
fn by_stepper(s: &Study, omega: f64, out: &mut [f64]) {
    let dim = s.model.point_dimension();
    let width = s.model.parameters().len();
    let at = (3 * s.point + 2) * dim;
    let mut m = s.model.clone();
    for (d, kept) in out.chunks_mut(STEPS * dim).enumerate() {
        m.set_values(&s.designs[d * width..(d + 1) * width])
            .unwrap();
        let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
        let mut q = s.start.clone();
        let phi0 = q[0];
        for (k, row) in kept.chunks_mut(dim).enumerate() {
            q[0] = phi0 + TAU * k as f64 / STEPS as f64;
            let Ok(f) = stepper.step_flat(&q, &[omega], &[0.0]) else {
                break;
            };
            row.copy_from_slice(&f.outputs[at..at + dim]);
            q.copy_from_slice(f.q);
        }
    }
}

fn main() {
    let arg = std::env::args().nth(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let omega = 600.0 / 60.0 * TAU;
    if arg.as_deref() == Some("compile") {
        compile_times(omega);
        return;
    }
    if let Some(which) = arg.as_deref().filter(|a| a.starts_with("count")) {
        count(which, &pool, omega);
        return;
    }
    let rounds: usize = arg.and_then(|v| v.parse().ok()).unwrap_or(21);
    for study in [four_bar(2000), strider(500)] {
        steps_study(&study, &pool, omega, rounds);
        poses_study(&study, &pool, rounds);
    }
}

/// The machine code in lanes compiled for a model's first batch of
/// steps, and of positions only: thread CPU time of the first
/// [`Batch::in_pairs`] of a model compiled afresh, the median of nine.
fn compile_times(omega: f64) {
    for (name, study) in [
        ("four-bar", four_bar as fn(usize) -> Study),
        ("Strider", strider),
    ] {
        let mut times = [Vec::new(), Vec::new()];
        for _ in 0..9 {
            for (poses, t) in times.iter_mut().enumerate() {
                let s = study(2);
                let batch = turns(&s, omega);
                let batch = if poses == 1 {
                    turn_keeping(&s, 1.0, Output::Position(s.point))
                        .positions_only()
                        .unwrap()
                } else {
                    batch
                };
                let t0 = kinematics_bench::thread_cpu_ns();
                assert!(batch.in_pairs());
                t.push((kinematics_bench::thread_cpu_ns() - t0) * 1e-6);
            }
        }
        for (what, mut t) in ["steps", "poses"].into_iter().zip(times) {
            let (m, lo, hi) = kinematics_bench::spread(&mut t);
            println!("{name:9} {what}: the code in lanes compiled in {m:.2} ms ({lo:.2}–{hi:.2})");
        }
    }
}

/// Full steps: the stepper's `step_flat` against the batch, design by
/// design and in pairs in vector lanes, checked equal on the designs that
/// turn, then timed in interleaved rounds (the three in turn).
fn steps_study(study: &Study, pool: &rayon::ThreadPool, omega: f64, rounds: usize) {
    let (alone, paired) = (
        turns(study, omega).in_lanes(false),
        turns(study, omega).in_lanes(true),
    );
    let what = format!(
        "{}: {} designs × {STEPS} positions",
        study.name, study.count
    );
    three_ways(
        study,
        (pool, rounds),
        &mut |s, out| by_stepper(s, omega, out),
        [&alone, &paired],
        (&what, ["step_flat", "batch", "in lanes"]),
    );
}

/// `reference` (each design by the stepper, the point's values kept)
/// against the batch design by design and in pairs in lanes (`batches`):
/// checked equal on the designs that turn, then timed in interleaved
/// rounds (the three in turn) and printed as `what`, its variants named
/// `names`.
fn three_ways(
    study: &Study,
    (pool, rounds): (&rayon::ThreadPool, usize),
    reference: &mut dyn FnMut(&Study, &mut [f64]),
    batches: [&Batch<'_>; 2],
    (what, names): (&str, [&str; 3]),
) {
    let dim = study.model.point_dimension();
    let mut kept = vec![f64::NAN; study.count * STEPS * dim];
    reference(study, &mut kept);
    let mut compared = 0;
    for b in batches {
        let results = pool.install(|| b.run(&study.designs));
        compared = compare(b, &results, &kept, STEPS * dim);
    }
    let [alone, paired] = batches;
    let t = three_rounds(
        rounds,
        (study.count * STEPS) as f64,
        [
            &mut || {
                reference(study, &mut kept);
                black_box(&kept);
            },
            &mut || {
                black_box(pool.install(|| alone.run(black_box(&study.designs))));
            },
            &mut || {
                black_box(pool.install(|| paired.run(black_box(&study.designs))));
            },
        ],
    );
    let what = format!(
        "{what} ({compared} turn fully, equal to 1e-12, lanes: {})",
        paired.in_pairs()
    );
    print_study(&what, names, t, rounds);
}

/// Prints a study's three timings and two ratios ([`three_rounds`]),
/// `names` the three variants.
fn print_study(what: &str, names: [&str; 3], t: [(f64, f64, f64); 5], rounds: usize) {
    let [p, a, l, ra, rl] = t;
    let [n0, n1, n2] = names;
    println!(
        "{what}: {n0} {:.1} ns ({:.1}–{:.1}), {n1} {:.1} ns ({:.1}–{:.1}), {n2} {:.1} ns \
         ({:.1}–{:.1}) per position; {n1} / {n0} {:.3} ({:.3}–{:.3}), {n2} / {n0} {:.3} \
         ({:.3}–{:.3}) over {rounds} rounds",
        p.0, p.1, p.2, a.0, a.1, a.2, l.0, l.1, l.2, ra.0, ra.1, ra.2, rl.0, rl.1, rl.2
    );
}

/// `rounds` rounds of the three `runs` in turn (process CPU time, ns per
/// position over `positions`): the median and range of each, then of the
/// second's and the third's ratio to the first.
fn three_rounds(
    rounds: usize,
    positions: f64,
    runs: [&mut dyn FnMut(); 3],
) -> [(f64, f64, f64); 5] {
    let (mut t, mut ratio) = ([vec![], vec![], vec![]], [vec![], vec![]]);
    let [first, second, third] = runs;
    for _ in 0..rounds {
        let t0 = process_cpu_ns();
        first();
        let t1 = process_cpu_ns();
        second();
        let t2 = process_cpu_ns();
        third();
        let t3 = process_cpu_ns();
        for (v, dt) in t.iter_mut().zip([t1 - t0, t2 - t1, t3 - t2]) {
            v.push(dt / positions);
        }
        ratio[0].push((t2 - t1) / (t1 - t0));
        ratio[1].push((t3 - t2) / (t1 - t0));
    }
    let [p, a, l] = t.map(|mut v| kinematics_bench::spread(&mut v));
    let [ra, rl] = ratio.map(|mut v| kinematics_bench::spread(&mut v));
    [p, a, l, ra, rl]
}

/// The reference of positions only: each design posed by the stepper,
/// the point's position kept (NaN past a failed pose).
fn by_poses(s: &Study, out: &mut [f64]) {
    let dim = s.model.point_dimension();
    let width = s.model.parameters().len();
    let at = s.point * dim;
    let mut m = s.model.clone();
    let mut r = vec![0.0; m.point_names().len() * dim];
    for (d, kept) in out.chunks_mut(STEPS * dim).enumerate() {
        m.set_values(&s.designs[d * width..(d + 1) * width])
            .unwrap();
        let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
        let mut q = s.start.clone();
        let phi0 = q[0];
        for (k, row) in kept.chunks_mut(dim).enumerate() {
            q[0] = phi0 + TAU * k as f64 / STEPS as f64;
            let Ok(p) = stepper.pose(&q) else {
                break;
            };
            q.copy_from_slice(p);
            if stepper.positions(&mut r).is_err() {
                break;
            }
            row.copy_from_slice(&r[at..at + dim]);
        }
    }
}

/// Positions only: the stepper's poses against the batch of positions
/// only, design by design and in pairs in vector lanes, checked equal on
/// the designs that turn, then timed in interleaved rounds (the three in
/// turn).
fn poses_study(study: &Study, pool: &rayon::ThreadPool, rounds: usize) {
    let batch = |lanes: bool| {
        turn_keeping(study, 1.0, Output::Position(study.point))
            .positions_only()
            .unwrap()
            .in_lanes(lanes)
    };
    let (alone, paired) = (batch(false), batch(true));
    let what = format!("{}, positions only", study.name);
    three_ways(
        study,
        (pool, rounds),
        &mut by_poses,
        [&alone, &paired],
        (&what, ["pose", "batch", "in lanes"]),
    );
}

/// Checks the batch's one output against `reference` (`per` values a
/// design) on every design that ran to its end, to 1e-12 of the largest
/// reference value; returns how many designs were compared.
fn compare(batch: &Batch<'_>, results: &BatchResults, reference: &[f64], per: usize) -> usize {
    let scale = reference
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mut compared = 0;
    for d in (0..results.samples.len()).filter(|&d| results.early[d].is_none()) {
        let want = &reference[d * per..(d + 1) * per];
        for (x, y) in results.output(batch, d, 0).iter().zip(want) {
            assert!(
                (x - y).abs() <= 1e-12 * scale,
                "design {d}: {x} against {y}"
            );
        }
        compared += 1;
    }
    compared
}
