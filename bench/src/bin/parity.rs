//! The work of the Python package's calls, done in Rust through the same
//! run-time model: what `bench/python/parity.py` compares each Python
//! call against. On the four-bar and the Strider leg of the examples: a
//! sweep of one turn of 360 steps with velocities and accelerations,
//! each sample pushed into columns as the Python sweep keeps them (q,
//! q', q'', every point's position, velocity and acceleration, the
//! conditioning, the sign and the residual), and one turn of 360 poses
//! with the points' positions pushed into columns; and on the four-bar a
//! batch of 10⁴ designs (crank, coupler and rocker drawn at random) over
//! one turn of 360 positions keeping C's position, velocity and
//! acceleration at every sample. Prints one line per call, `name µs`,
//! the median of `rounds` rounds of 200 calls (thread CPU time; the
//! batch's, one call a round, in process CPU time, on every core).
//!
//! ```text
//! cargo run --release -p kinematics-bench --bin parity [rounds]
//! ```

// A benchmark program: a failed set-up should stop it.
#![allow(clippy::expect_used, missing_docs, clippy::cast_precision_loss)]

use std::f64::consts::{FRAC_PI_4, PI};
use std::hint::black_box;

use kinematics_core::runtime::{Batch, BatchSweep, Model, Output};
use kinematics_core::sweep::ChangePoints;
use kinematics_core::Options;

/// The median over `rounds` of `f`'s time (µs a call, `calls` calls a
/// round), by `clock` (ns).
fn median(rounds: usize, calls: u32, clock: fn() -> f64, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<f64> = (0..rounds)
        .map(|_| {
            let t0 = clock();
            for _ in 0..calls {
                f();
            }
            (clock() - t0) * 1e-3 / f64::from(calls)
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// One turn of 360 samples from `start`, kept in columns.
fn sweep(m: &Model, start: &[f64]) -> usize {
    let (nc, np, dim) = (
        m.coordinates().len(),
        m.point_names().len(),
        m.point_dimension(),
    );
    let rows = 361;
    let mut at = Vec::with_capacity(rows);
    let mut q: [Vec<f64>; 3] = core::array::from_fn(|_| Vec::with_capacity(rows * nc));
    let mut points = Vec::with_capacity(rows * np * 3 * dim);
    let mut diagnostics: [Vec<f64>; 3] = core::array::from_fn(|_| Vec::with_capacity(rows));
    let end = m
        .sweep(m.coordinates()[0].name, start)
        .expect("a sweep")
        .turns(1.0)
        .steps(360)
        .rate(1.0)
        .for_each_flat(|value, s| {
            at.push(value);
            q[0].extend_from_slice(s.q);
            q[1].extend_from_slice(s.qd);
            q[2].extend_from_slice(s.qdd);
            points.extend_from_slice(&s.outputs[..np * 3 * dim]);
            diagnostics[0].push(s.conditioning);
            diagnostics[1].push(s.det_sign);
            diagnostics[2].push(s.residual);
        });
    assert!(end.stop.is_none());
    black_box((&q, &points, &diagnostics));
    at.len()
}

/// One turn of 360 poses from `start`, kept in columns.
fn poses(m: &Model, start: &[f64]) -> usize {
    let (nc, np, dim) = (
        m.coordinates().len(),
        m.point_names().len(),
        m.point_dimension(),
    );
    let rows = 361;
    let mut at = Vec::with_capacity(rows);
    let mut qs = Vec::with_capacity(rows * nc);
    let mut points = Vec::with_capacity(rows * np * dim);
    let end = m
        .sweep(m.coordinates()[0].name, start)
        .expect("a sweep")
        .turns(1.0)
        .steps(360)
        .for_each_pose(|value, q, r| {
            at.push(value);
            qs.extend_from_slice(q);
            points.extend_from_slice(r);
        });
    assert!(end.stop.is_none());
    black_box((&qs, &points));
    at.len()
}

fn main() {
    let rounds = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(9);
    let four_bar =
        kinematics_bench::example_model("four_bar.mech", &[0.04, 0.12, 0.10, 0.11, 0.06, 0.5]);
    let strider = kinematics_bench::example_model(
        "strider.mech",
        &[2.0, FRAC_PI_4, 1.8, 2.6, 1.4, PI + 0.2, 2.5, 1.8],
    );
    let thread = kinematics_bench::thread_cpu_ns;
    for (name, m) in [("four-bar", &four_bar), ("Strider", &strider)] {
        let mut guess = vec![0.0; m.coordinates().len()];
        guess[0] = 0.3;
        let start = m
            .assemble_all(&guess)
            .find_map(|(_, p)| p.ok())
            .expect("an assembly");
        let s = median(rounds, 200, thread, || {
            black_box(sweep(m, &start));
        });
        let p = median(rounds, 200, thread, || {
            black_box(poses(m, &start));
        });
        println!("{name} sweep 360 {s:.2}");
        println!("{name} poses 360 {p:.2}");
    }
    // The batch: 10⁴ crank-rockers, as the Python side draws them (its
    // rows hand the batch every parameter, the fixed ones repeated).
    let designs = 10_000;
    let mut seed = 7u64;
    let mut uniform = |lo: f64, hi: f64| {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let rows: Vec<f64> = (0..designs)
        .flat_map(|_| {
            let (a, b, c) = (
                uniform(0.030, 0.045),
                uniform(0.115, 0.125),
                uniform(0.095, 0.105),
            );
            [a, b, c, 0.11, 0.06, 0.5]
        })
        .collect();
    // The start the Python side assembles from.
    let start = four_bar
        .assemble(&[2.0 * PI / 360.0, 0.9, 1.6])
        .expect("an assembly");
    let c = four_bar
        .point_names()
        .iter()
        .position(|p| *p == "C")
        .expect("C");
    let batch = Batch::new(
        &four_bar,
        &start,
        &[10.0],
        &[0.0],
        Some(BatchSweep {
            driver: 0,
            from: None,
            to: None,
            turns: Some(1.0),
            steps: 360,
            change_points: ChangePoints::Stop,
        }),
        &[
            Output::Position(c),
            Output::Velocity(c),
            Output::PointAcceleration(c),
        ],
        &Options::DEFAULT,
    )
    .expect("a batch");
    let results = batch.run(&rows);
    assert!(
        results.early.iter().all(Option::is_none),
        "a design stopped"
    );
    let b = median(rounds.min(5), 1, kinematics_bench::process_cpu_ns, || {
        black_box(batch.run(&rows));
    });
    println!("four-bar batch 10000x360 {b:.2}");
}
