//! The Strider walking leg over turns of its crank, positions only,
//! against pylinkage's numba-compiled solver on the same linkage
//! (`bench/python/strider_pylinkage.py`):
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin strider [turns]
//! python3 bench/python/strider_pylinkage.py [turns]
//! ```
//!
//! Prints the feet's positions at the samples the Python script prints
//! (the two must agree), then the time per step over five repetitions of
//! `turns` turns of 3600 steps (thread CPU time) of a sweep of poses, with
//! every joint's position (what pylinkage returns) as each pose carries
//! it, or evaluated again from the pose's coordinates.
// A measuring harness: a failed step should stop it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::cast_precision_loss)]

use kinematics_bench::thread_cpu_ns;
use std::f64::consts::{FRAC_PI_2, TAU};
use std::hint::black_box;

use kinematics_examples::{Strider, StriderCoords, StriderPositions};

const STEPS: usize = 3600;

/// The first pose of the Python script's turn: the crank at the angle of
/// its first step, in the modes of the example's starting positions.
fn start() -> StriderCoords {
    let guess = Strider::pylinkage_guess(-FRAC_PI_2 + TAU / STEPS as f64);
    Strider::PYLINKAGE.assemble(&guess).expect("assembles")
}

/// A turn of the leg's poses (the sweep's iterator), each passed to
/// `use_pose`.
fn turn(
    m: &Strider,
    start: &StriderCoords,
    mut use_pose: impl FnMut(&kinematics_core::Pose<StriderCoords, StriderPositions>),
) {
    for s in m
        .sweep(Strider::TH, start)
        .from(start.th)
        .to(start.th + TAU)
        .steps(STEPS)
        .poses()
        .take(STEPS)
    {
        use_pose(&s.expect("no stop").pose);
    }
}

fn main() {
    let turns: usize = std::env::args()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(10);
    let m = black_box(Strider::PYLINKAGE);
    let start = start();
    let mut k = 0;
    turn(&m, &start, |pose| {
        if [0, 1, 900, 1800, 2700].contains(&k) {
            let p = pose.points;
            println!(
                "step {k}: H = ({:.15}, {:.15}), I = ({:.15}, {:.15})",
                p.H.x, p.H.y, p.I.x, p.I.y
            );
        }
        k += 1;
    });
    // Each pose's joints: those the pose carries (from the solve's own
    // sines and cosines), or evaluated afresh from its coordinates.
    for (name, joints) in [
        ("poses with every joint", 0),
        ("poses, every joint evaluated again", 1),
    ] {
        let mut times = Vec::new();
        for _ in 0..5 {
            let mut sum = 0.0;
            let t0 = thread_cpu_ns();
            for _ in 0..turns {
                turn(&m, &start, |pose| {
                    sum += if joints == 0 {
                        let p = &pose.points;
                        [p.C, p.D, p.E, p.F, p.G, p.H, p.I]
                            .iter()
                            .map(|v| v.x + v.y)
                            .sum::<f64>()
                    } else {
                        let p = m.point_positions(&pose.q);
                        p.iter().map(|v| v.x + v.y).sum::<f64>()
                    };
                });
            }
            times.push((thread_cpu_ns() - t0) / (turns * STEPS) as f64);
            black_box(sum);
        }
        let shown: Vec<String> = times.iter().map(|t| format!("{t:.1}")).collect();
        println!("{name}: ns per step: {}", shown.join(" "));
    }
}
