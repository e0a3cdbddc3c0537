//! One full turn (3600 steps) of M1–M4 through the public `step`, for
//! instruction counts under callgrind, which do not move with the load of
//! the machine:
//!
//! ```sh
//! cargo build --release -p kinematics-bench --bin count_steps
//! valgrind --tool=callgrind target/release/count_steps m1
//! ```
//!
//! `m1a` and `m2a` run M1 and M2 with the absolute convergence test, `m1s`,
//! `m2s` and `m3s` through the stepping handle (`stepper().step`). A
//! second argument repeats the turn and prints the wall time per step.
// A measuring harness: a failed step should stop it.
#![allow(clippy::unwrap_used, clippy::panic, clippy::cast_precision_loss)]

use std::f64::consts::TAU;
use std::hint::black_box;

use kinematics_core::{Convergence, Options};
use kinematics_examples::{FourBar, Rssr, RssrCoords, SixAxisArm, SixAxisArmCoords, Watt};

const STEPS: usize = 3600;

fn angle(k: usize) -> f64 {
    k as f64 * TAU / STEPS as f64
}

/// One turn of mechanism `which`; returns a checksum of the outputs.
fn turn(which: &str) -> f64 {
    let absolute = Options {
        convergence: Convergence::Absolute,
        ..Options::DEFAULT
    };
    let mut sum = 0.0;
    match which {
        "m1" | "m1a" => {
            let m = black_box(FourBar::CRANK_ROCKER);
            let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).unwrap();
            for k in 0..STEPS {
                pose.phi = angle(k);
                // `step` itself (default options, folded at compile time),
                // or `step_with` the absolute test.
                let s = if which == "m1" {
                    m.step(black_box(&pose), 10.0, 0.0)
                } else {
                    m.step_with(black_box(&pose), 10.0, 0.0, &absolute)
                }
                .unwrap();
                pose = s.q;
                sum += s.qdd.th4 + s.points[2].acceleration.x;
            }
        }
        "m2" | "m2a" => {
            let m = black_box(Rssr {
                a: 0.102,
                b: 0.381,
                c: 0.254,
                d: 0.314,
            });
            let mut pose = m.assemble(&RssrCoords { phi: 0.0, psi: 1.2 }).unwrap();
            for k in 0..STEPS {
                pose.phi = angle(k);
                let s = if which == "m2" {
                    m.step(black_box(&pose), 25.0, 0.0)
                } else {
                    m.step_with(black_box(&pose), 25.0, 0.0, &absolute)
                }
                .unwrap();
                pose = s.q;
                sum += s.qdd.psi;
            }
        }
        "m1s" => {
            let m = black_box(FourBar::CRANK_ROCKER);
            let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
            let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).unwrap();
            for k in 0..STEPS {
                pose.phi = angle(k);
                let s = stepper.step(black_box(&pose), 10.0, 0.0).unwrap();
                pose = s.q;
                sum += s.qdd.th4 + s.points[2].acceleration.x;
            }
        }
        "m2s" => {
            let m = black_box(Rssr {
                a: 0.102,
                b: 0.381,
                c: 0.254,
                d: 0.314,
            });
            let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
            let mut pose = m.assemble(&RssrCoords { phi: 0.0, psi: 1.2 }).unwrap();
            for k in 0..STEPS {
                pose.phi = angle(k);
                let s = stepper.step(black_box(&pose), 25.0, 0.0).unwrap();
                pose = s.q;
                sum += s.qdd.psi;
            }
        }
        "m3s" => {
            let m = black_box(Watt::EXAMPLE);
            let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
            let mut pose = m.assemble(&Watt::EXAMPLE_GUESS).unwrap();
            for k in 0..STEPS {
                pose.phi = angle(k);
                let s = stepper.step(black_box(&pose), 10.0, 0.0).unwrap();
                pose = s.q;
                sum += s.qdd.th6 + s.points[0].acceleration.x;
            }
        }
        "m3" => {
            let m = black_box(Watt::EXAMPLE);
            let mut pose = m.assemble(&Watt::EXAMPLE_GUESS).unwrap();
            for k in 0..STEPS {
                pose.phi = angle(k);
                let s = m.step(black_box(&pose), 10.0, 0.0).unwrap();
                pose = s.q;
                sum += s.qdd.th6 + s.points[0].acceleration.x;
            }
        }
        "m4" => {
            let m = black_box(SixAxisArm {
                d1: 0.4,
                a2: 0.45,
                a3: 0.4,
                d5: 0.08,
                d6: 0.1,
            });
            let rates = [1.0, 0.3, -0.2, 0.5, 1.0, -1.0];
            for k in 0..STEPS {
                let q = SixAxisArmCoords::from(rates.map(|r| r * angle(k)));
                let s = m.step(black_box(&q), rates, [0.0; 6]).unwrap();
                sum += s.points[0].acceleration.x + s.frames[2].angular_acceleration.z;
            }
        }
        other => panic!("unknown mechanism `{other}`: m1, m1a, m1s, m2, m2a, m2s, m3, m3s or m4"),
    }
    sum
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "m1".into());
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let start = std::time::Instant::now();
    let mut sum = 0.0;
    for _ in 0..reps {
        sum += turn(&which);
    }
    black_box(sum);
    if reps > 1 {
        let ns = start.elapsed().as_nanos() as f64 / (reps * STEPS) as f64;
        println!("{ns:.1} ns per step");
    }
}
