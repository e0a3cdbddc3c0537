//! The cost of positions only on a run-time model: a turn of 3600 poses
//! of the four-bar and of the Strider leg of the examples, by the
//! stepper's `pose` and `positions` in a loop (each pose from the last,
//! the driver advanced by hand) against the sweep's `for_each_pose` (the
//! same poses with the grid, the limit search and the callback), in
//! interleaved rounds of thread CPU time: the median and the range of
//! nine rounds, ns per pose.
//!
//! ```text
//! cargo run --release -p kinematics-bench --bin poses
//! ```
//!
//! With `count four-bar` (or `count Strider`) it runs ten turns of that
//! mechanism's loop of poses only, untimed, for an instruction count
//! (`valgrind --tool=callgrind`): `Stepper::pose`'s inclusive count over
//! 36 000 is the instructions of a pose. With `count-sweep four-bar` it
//! runs ten sweeps of a turn through `for_each_pose` (the sweep's
//! instructions a pose: `for_each_pose`'s inclusive count, less the
//! first stepper's compilation, over 36 000), with `count-fixed
//! four-bar` 10 000 sweeps of one step (a sweep's fixed cost).

// A benchmark program: a failed set-up should stop it.
#![allow(clippy::expect_used, missing_docs)]

use std::f64::consts::TAU;
use std::hint::black_box;

use kinematics_core::Options;

const STEPS: usize = 3600;

/// The first assembly of `m` found from the crank at 0.3 rad.
fn start_of(m: &kinematics_core::runtime::Model) -> Vec<f64> {
    let mut guess = vec![0.0; m.coordinates().len()];
    guess[0] = 0.3;
    m.assemble_all(&guess)
        .find_map(|(_, p)| p.ok())
        .expect("an assembly")
}

/// Ten turns of poses and positions, untimed (for callgrind).
fn count_poses(m: &kinematics_core::runtime::Model, o: &Options) {
    let start = start_of(m);
    let mut positions = vec![0.0; m.point_names().len() * m.point_dimension()];
    let mut stepper = m.stepper(o).expect("a stepper");
    let mut q = start;
    let h = TAU / STEPS as f64;
    for _ in 0..10 * STEPS {
        q[0] += h;
        let p = stepper.pose(&q).expect("a pose");
        q.copy_from_slice(p);
        stepper.positions(&mut positions).expect("positions");
        black_box(&positions);
    }
}

/// Ten sweeps of a turn of poses (`count-sweep`), or 10 000 sweeps of
/// one step (`count-fixed`), untimed, for an instruction count.
fn count_sweeps(m: &kinematics_core::runtime::Model, fixed: bool) {
    let start = start_of(m);
    let (sweeps, steps, to) = if fixed {
        (10_000, 1, Some(start[0] + 0.01))
    } else {
        (10, STEPS, None)
    };
    for _ in 0..sweeps {
        let sweep = m.sweep(m.coordinates()[0].name, &start).expect("a sweep");
        let sweep = match to {
            Some(to) => sweep.to(to),
            None => sweep.turns(1.0),
        };
        let end = sweep.steps(steps).for_each_pose(|at, q, r| {
            black_box((at, q, r));
        });
        black_box(end);
    }
}

fn main() {
    use std::f64::consts::{FRAC_PI_4, PI};
    let four_bar =
        kinematics_bench::example_model("four_bar.mech", &[0.04, 0.12, 0.10, 0.11, 0.06, 0.5]);
    let strider = kinematics_bench::example_model(
        "strider.mech",
        &[2.0, FRAC_PI_4, 1.8, 2.6, 1.4, PI + 0.2, 2.5, 1.8],
    );
    let args: Vec<String> = std::env::args().collect();
    let count = args.get(1).is_some_and(|a| a == "count");
    for (name, m) in [("four-bar", &four_bar), ("Strider", &strider)] {
        let o = Options::default();
        if count {
            if args.get(2).is_some_and(|a| a == name) {
                count_poses(m, &o);
            }
            continue;
        }
        if let Some(which) = args
            .get(1)
            .filter(|a| ["count-sweep", "count-fixed"].contains(&a.as_str()))
        {
            if args.get(2).is_some_and(|a| a == name) {
                count_sweeps(m, which == "count-fixed");
            }
            continue;
        }
        let start = start_of(m);
        let d = m.point_names().len() * m.point_dimension();
        let mut positions = vec![0.0; d];
        let h = TAU / STEPS as f64;
        let (mut raw, mut swept) = (Vec::new(), Vec::new());
        for _ in 0..9 {
            let mut stepper = m.stepper(&o).expect("a stepper");
            let mut q = start.clone();
            let t0 = kinematics_bench::thread_cpu_ns();
            for _ in 0..STEPS {
                q[0] += h;
                let p = stepper.pose(&q).expect("a pose");
                q.copy_from_slice(p);
                stepper.positions(&mut positions).expect("positions");
                black_box(&positions);
            }
            raw.push((kinematics_bench::thread_cpu_ns() - t0) / STEPS as f64);
            let t0 = kinematics_bench::thread_cpu_ns();
            // Its first sample is the start itself: the steps are the
            // samples after it.
            let mut n = 0usize;
            let end = m
                .sweep(m.coordinates()[0].name, &start)
                .expect("a sweep")
                .turns(1.0)
                .steps(STEPS)
                .for_each_pose(|at, q, r| {
                    n += 1;
                    black_box((at, q, r));
                });
            swept.push((kinematics_bench::thread_cpu_ns() - t0) / (n - 1) as f64);
            assert!(end.stop.is_none(), "{name}: {:?}", end.stop);
        }
        // The fixed cost of a sweep: one of a single step.
        let mut fixed = Vec::new();
        for _ in 0..9 {
            let t0 = kinematics_bench::thread_cpu_ns();
            for _ in 0..1000 {
                let end = m
                    .sweep(m.coordinates()[0].name, &start)
                    .expect("a sweep")
                    .to(start[0] + 0.01)
                    .steps(1)
                    .for_each_pose(|at, q, r| {
                        black_box((at, q, r));
                    });
                black_box(end);
            }
            fixed.push((kinematics_bench::thread_cpu_ns() - t0) / 1000.0);
        }
        let (c, c0, c1) = kinematics_bench::spread(&mut fixed);
        println!(
            "{name:9} a sweep of one step: {:.2} µs ({:.2}–{:.2})",
            c * 1e-3,
            c0 * 1e-3,
            c1 * 1e-3
        );
        let (a, a0, a1) = kinematics_bench::spread(&mut raw);
        let (b, b0, b1) = kinematics_bench::spread(&mut swept);
        println!(
            "{name:9} pose + positions {a:6.1} ns ({a0:.1}–{a1:.1}), for_each_pose {b:6.1} ns \
             ({b0:.1}–{b1:.1}): {:.2}×",
            b / a
        );
    }
}
