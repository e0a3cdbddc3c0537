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
//! `m2s`, `m3s` and `m4s` through the stepping handle (`stepper().step`), `m1w`
//! and `m2w` through a sweep collected (`run()`), `m1i` and `m2i` through a
//! sweep streamed (its iterator), `m1p`, `m2p` and `m3p` through a sweep of
//! positions only (`poses()`); `r1s`–`r4s` run M1–M4 compiled at run time
//! from the examples' text through the run-time stepper (the model is
//! compiled before the turns: count two runs with different repeats and
//! take the difference), `r1f`–`r4f` the same with the motion read from
//! the flat arrays of `Stepper::step_flat`. `n`, `np` and `na` run a slider-crank in a
//! curved guide, which no closed form covers (Newton–Raphson on the whole
//! system), through a sweep, a sweep of poses, and `assemble` from the
//! previous pose. A second argument repeats the turn and prints the wall
//! time per step.
// A measuring harness: a failed step should stop it.
#![allow(clippy::unwrap_used, clippy::panic, clippy::cast_precision_loss)]

use std::f64::consts::TAU;
use std::hint::black_box;

use kinematics_core::{mechanism, Convergence, Options};
use kinematics_examples::{FourBar, Rssr, RssrCoords, SixAxisArm, SixAxisArmCoords, Watt};

const STEPS: usize = 3600;

mechanism! {
    /// A slider-crank whose slider runs in a curved guide, the parabola
    /// x = h + k y²: no closed form covers it (Newton–Raphson on the whole
    /// system).
    pub struct CurvedSlider {
        params {
            /// Crank.
            a,
            /// Connecting rod.
            b,
            /// Vertex of the guide.
            h,
            /// Curvature of the guide.
            k
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns {
            /// Rod angle.
            th,
            /// Slider height along the guide.
            y
        }
        loops {
            polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y);
        }
    }
}

fn angle(k: usize) -> f64 {
    k as f64 * TAU / STEPS as f64
}

/// A turn of a one-driver mechanism from `start`, each step from the
/// previous pose with the driver advanced; `out` picks the checksum's terms.
fn turn_from<C: Copy, S>(
    mut start: C,
    set_driver: impl Fn(&mut C, f64),
    mut step: impl FnMut(&C) -> Result<S, kinematics_core::Error>,
    pose_of: impl Fn(&S) -> C,
    out: impl Fn(&S) -> f64,
) -> f64 {
    let mut sum = 0.0;
    for k in 0..STEPS {
        set_driver(&mut start, angle(k));
        let s = step(black_box(&start)).unwrap();
        start = pose_of(&s);
        sum += out(&s);
    }
    sum
}

/// One turn of mechanism `which`; returns a checksum of the outputs.
fn turn(which: &str) -> f64 {
    let absolute = Options {
        convergence: Convergence::Absolute,
        ..Options::DEFAULT
    };
    let four_bar = black_box(FourBar::CRANK_ROCKER);
    let rssr = black_box(Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.314,
    });
    let watt = black_box(Watt::EXAMPLE);
    // `step` itself (default options, folded at compile time), `step_with`
    // the absolute test, or a stepper.
    macro_rules! run {
        ($m:expr, $start:expr, $out:expr, |$pose:ident| $step:expr) => {{
            let m = &$m;
            let start = m.assemble(&$start).unwrap();
            turn_from(start, |p, phi| p.phi = phi, |$pose| $step, |s| s.q, $out)
        }};
    }
    match which {
        "m1" | "m1a" | "m1s" => {
            let out =
                |s: &kinematics_examples::FourBarMotion| s.qdd.th4 + s.points[2].acceleration.x;
            let mut stepper = four_bar.stepper(&Options::DEFAULT).unwrap();
            match which {
                "m1" => run!(four_bar, FourBar::CRANK_ROCKER_GUESS, out, |p| {
                    four_bar.step(p, 10.0, 0.0)
                }),
                "m1a" => run!(four_bar, FourBar::CRANK_ROCKER_GUESS, out, |p| {
                    four_bar.step_with(p, 10.0, 0.0, &absolute)
                }),
                _ => run!(four_bar, FourBar::CRANK_ROCKER_GUESS, out, |p| {
                    stepper.step(p, 10.0, 0.0)
                }),
            }
        }
        "m2" | "m2a" | "m2s" => {
            let out = |s: &kinematics_examples::RssrMotion| s.qdd.psi;
            let start = RssrCoords { phi: 0.0, psi: 1.2 };
            let mut stepper = rssr.stepper(&Options::DEFAULT).unwrap();
            match which {
                "m2" => run!(rssr, start, out, |p| rssr.step(p, 25.0, 0.0)),
                "m2a" => run!(rssr, start, out, |p| rssr
                    .step_with(p, 25.0, 0.0, &absolute)),
                _ => run!(rssr, start, out, |p| stepper.step(p, 25.0, 0.0)),
            }
        }
        "m3" | "m3s" => {
            let out = |s: &kinematics_examples::WattMotion| s.qdd.th6 + s.points[0].acceleration.x;
            let mut stepper = watt.stepper(&Options::DEFAULT).unwrap();
            if which == "m3" {
                run!(watt, Watt::EXAMPLE_GUESS, out, |p| watt.step(p, 10.0, 0.0))
            } else {
                run!(watt, Watt::EXAMPLE_GUESS, out, |p| stepper
                    .step(p, 10.0, 0.0))
            }
        }
        "m1w" | "m2w" => {
            // The same turns through `sweep` (3600 samples into its Vec).
            let s = if which == "m1w" {
                let start = four_bar.assemble(&FourBar::CRANK_ROCKER_GUESS).unwrap();
                let s = four_bar
                    .sweep(FourBar::PHI, &start)
                    .turn()
                    .steps(STEPS)
                    .rate(10.0)
                    .run();
                s.samples
                    .iter()
                    .map(|x| x.motion.qdd.th4 + x.motion.points[2].acceleration.x)
                    .sum()
            } else {
                let start = rssr.assemble(&RssrCoords { phi: 0.0, psi: 1.2 }).unwrap();
                let s = rssr
                    .sweep(Rssr::PHI, &start)
                    .turn()
                    .steps(STEPS)
                    .rate(25.0)
                    .run();
                s.samples.iter().map(|x| x.motion.qdd.psi).sum()
            };
            s
        }
        "m1p" | "m2p" | "m3p" => {
            // The same turns, positions only.
            let mut sum = 0.0;
            if which == "m1p" {
                let start = four_bar.assemble(&FourBar::CRANK_ROCKER_GUESS).unwrap();
                for x in four_bar
                    .sweep(FourBar::PHI, &start)
                    .turn()
                    .steps(STEPS)
                    .poses()
                {
                    sum += x.unwrap().pose.q.th4;
                }
            } else if which == "m2p" {
                let start = rssr.assemble(&RssrCoords { phi: 0.0, psi: 1.2 }).unwrap();
                for x in rssr.sweep(Rssr::PHI, &start).turn().steps(STEPS).poses() {
                    sum += x.unwrap().pose.q.psi;
                }
            } else {
                let start = watt.assemble(&Watt::EXAMPLE_GUESS).unwrap();
                for x in watt.sweep(Watt::PHI, &start).turn().steps(STEPS).poses() {
                    sum += x.unwrap().pose.q.th6;
                }
            }
            sum
        }
        "n" | "np" | "na" => {
            let m = black_box(CurvedSlider {
                a: 0.05,
                b: 0.2,
                h: 0.05,
                k: 2.0,
            });
            let start = m
                .assemble(&CurvedSliderCoords {
                    phi: 0.0,
                    th: 1.2,
                    y: 0.19,
                })
                .unwrap();
            let mut sum = 0.0;
            match which {
                "n" => {
                    for x in m
                        .sweep(CurvedSlider::PHI, &start)
                        .turn()
                        .steps(STEPS)
                        .rate(10.0)
                    {
                        sum += x.unwrap().motion.qdd.y;
                    }
                }
                "np" => {
                    for x in m
                        .sweep(CurvedSlider::PHI, &start)
                        .turn()
                        .steps(STEPS)
                        .poses()
                    {
                        sum += x.unwrap().pose.q.y;
                    }
                }
                _ => {
                    let mut pose = start;
                    for k in 0..STEPS {
                        pose.phi = angle(k);
                        pose = m.assemble(black_box(&pose)).unwrap();
                        sum += pose.y;
                    }
                }
            }
            sum
        }
        "m1i" | "m2i" => {
            // The same turns through a sweep's iterator (streamed).
            let mut sum = 0.0;
            if which == "m1i" {
                let start = four_bar.assemble(&FourBar::CRANK_ROCKER_GUESS).unwrap();
                for x in four_bar
                    .sweep(FourBar::PHI, &start)
                    .turn()
                    .steps(STEPS)
                    .rate(10.0)
                {
                    let x = x.unwrap();
                    sum += x.motion.qdd.th4 + x.motion.points[2].acceleration.x;
                }
            } else {
                let start = rssr.assemble(&RssrCoords { phi: 0.0, psi: 1.2 }).unwrap();
                for x in rssr.sweep(Rssr::PHI, &start).turn().steps(STEPS).rate(25.0) {
                    sum += x.unwrap().motion.qdd.psi;
                }
            }
            sum
        }
        "m4" | "m4s" => {
            let m = black_box(SixAxisArm {
                d1: 0.4,
                a2: 0.45,
                a3: 0.4,
                d5: 0.08,
                d6: 0.1,
            });
            let rates = [1.0, 0.3, -0.2, 0.5, 1.0, -1.0];
            let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
            let mut sum = 0.0;
            for k in 0..STEPS {
                let q = SixAxisArmCoords::from(rates.map(|r| r * angle(k)));
                let s = if which == "m4" {
                    m.step(black_box(&q), rates, [0.0; 6])
                } else {
                    stepper.step(black_box(&q), rates, [0.0; 6])
                };
                let s = s.unwrap();
                sum += s.points[0].acceleration.x + s.frames[2].angular_acceleration.z;
            }
            sum
        }
        other => panic!(
            "unknown mechanism `{other}`: m1, m1a, m1s, m2, m2a, m2s, m3, m3s, m1w, m2w, m1i, m2i, \
             m1p, m2p, m3p, n, np, na, m4 or m4s"
        ),
    }
}

/// The run-time model of the example `name` (compiled from its text)
/// with `values`, its start pose and the drivers' rates, for `r1s`–`r4s`.
fn runtime_model(which: &str) -> (kinematics_core::runtime::Model, Vec<f64>, Vec<f64>) {
    let (name, values, start, rates): (&str, Vec<f64>, Vec<f64>, Vec<f64>) = match which {
        "r1s" => (
            "FourBar",
            FourBar::CRANK_ROCKER.parameter_values().to_vec(),
            vec![0.0, 1.0, 1.6],
            vec![10.0],
        ),
        "r2s" => (
            "Rssr",
            vec![0.102, 0.381, 0.254, 0.314],
            vec![0.0, 1.0],
            vec![10.0],
        ),
        "r3s" => (
            "Watt",
            Watt::EXAMPLE.parameter_values().to_vec(),
            (0..5)
                .map(|j| kinematics_core::Coordinates::get(&Watt::EXAMPLE_GUESS, j).unwrap())
                .collect(),
            vec![10.0],
        ),
        _ => (
            "SixAxisArm",
            vec![0.4, 0.35, 0.3, 0.08, 0.1],
            vec![0.1, -0.4, 0.7, 0.2, -0.3, 0.5],
            vec![0.5, -0.2, 0.3, 1.0, -0.7, 0.4],
        ),
    };
    let text = kinematics_examples::definition(name).unwrap();
    let mut m = kinematics_core::runtime::Model::compile(text).unwrap();
    m.set_values(&values).unwrap();
    let start = m.assemble(&start).unwrap();
    (m, start, rates)
}

/// One turn of a run-time model through its stepper (every driver set
/// to the turn's angle), with `flat` through `Stepper::step_flat`;
/// returns a checksum.
fn runtime_turn(
    m: &kinematics_core::runtime::Model,
    start: &[f64],
    rates: &[f64],
    flat: bool,
) -> f64 {
    let accels = vec![0.0; rates.len()];
    let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
    let mut q = start.to_vec();
    let mut sum = 0.0;
    for k in 0..STEPS {
        for d in &mut q[..m.drivers()] {
            *d = angle(k);
        }
        if flat {
            let s = stepper.step_flat(black_box(&q), rates, &accels).unwrap();
            q.copy_from_slice(s.q);
            sum += s.qdd.iter().sum::<f64>();
        } else {
            let s = stepper.step(black_box(&q), rates, &accels).unwrap();
            q.copy_from_slice(&s.q);
            sum += s.qdd.iter().sum::<f64>();
        }
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
    if which.starts_with('r') {
        // `r1f`–`r4f`: as `r1s`–`r4s`, the motion read from the flat
        // arrays of `Stepper::step_flat`.
        let (which, flat) = match which.strip_suffix('f') {
            Some(w) => (format!("{w}s"), true),
            None => (which.clone(), false),
        };
        // The model is compiled once, before the turns (whose instruction
        // count is the difference of two runs with different repeats).
        let (m, q, rates) = runtime_model(&which);
        let start = std::time::Instant::now();
        for _ in 0..reps {
            sum += runtime_turn(&m, &q, &rates, flat);
        }
        black_box(sum);
        if reps > 1 {
            let ns = start.elapsed().as_nanos() as f64 / (reps * STEPS) as f64;
            println!("{ns:.1} ns per step");
        }
        return;
    }
    for _ in 0..reps {
        sum += turn(&which);
    }
    black_box(sum);
    if reps > 1 {
        let ns = start.elapsed().as_nanos() as f64 / (reps * STEPS) as f64;
        println!("{ns:.1} ns per step");
    }
}
