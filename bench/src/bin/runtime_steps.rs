//! Models defined at run time (`kinematics_core::runtime::Model`, machine
//! code from Cranelift) against the code `mechanism!` generates from the
//! same definitions (the examples' text): a turn of 3600 steps of M1 (the
//! four-bar), M2 (the RSSR), M3 (the Watt six-bar) and M4 (the six-axis
//! arm), each step assembling from the previous pose and analysing the
//! motion. Interleaved rounds (generated stepper, generated `step`, run-time
//! `step`, run-time stepper, in turn), thread CPU time; per mechanism the median ratio to the
//! generated stepper and the range of the middle 80 % of rounds. Also the
//! time to compile each definition at run time (text to machine code).
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin runtime_steps
//! ```
// A measuring harness: a failed step should stop it.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::cast_precision_loss
)]

use kinematics_bench::thread_cpu_ns;
use std::hint::black_box;
use std::time::Instant;

use kinematics_core::runtime::Model;
use kinematics_core::{Coordinates, Mechanism, MotionState, Options};
use kinematics_examples::{FourBar, Rssr, SixAxisArm, Watt};

// The chains of four-bars of the large-model tests, as text.
#[path = "../../../tests/src/four_bar_chain.rs"]
#[allow(dead_code)]
mod four_bar_chain;

const STEPS: usize = 3600;
const ROUNDS: usize = 21;

/// The run-time model of the example `name` with the parameters `values`
/// of the generated mechanism, named `names`.
fn model<const N: usize>(name: &str, names: [&str; N], values: [f64; N]) -> Model {
    let text = kinematics_examples::definition(name).expect("an example");
    let mut m = Model::compile(text).expect("it compiles");
    assert_eq!(m.parameters(), names);
    m.set_values(&values).expect("one value per parameter");
    m
}

/// One turn: every driver advanced by `delta` per step from `start`;
/// returns a checksum, the last coordinate's acceleration summed over the
/// turn (one value read per step, as in the run-time turns: the harness
/// costs both sides the same).
fn turn_generated<M: Mechanism>(
    mut step: impl FnMut(&M::Coords) -> M::Motion,
    start: M::Coords,
    delta: f64,
) -> f64 {
    let last = M::DRIVERS + M::UNKNOWNS - 1;
    let mut pose = start;
    let mut sum = 0.0;
    for _ in 0..STEPS {
        let s = step(&pose);
        sum += s.qdd().get(last).unwrap_or(0.0);
        pose = *s.q();
        for j in 0..M::DRIVERS {
            let d = pose.get(j).unwrap_or(0.0) + delta;
            pose.set(j, d);
        }
    }
    sum
}

fn turn_runtime(m: &Model, start: &[f64], rates: &[f64], delta: f64) -> f64 {
    let accels = vec![0.0; rates.len()];
    let mut pose = start.to_vec();
    let mut sum = 0.0;
    for _ in 0..STEPS {
        let s = m.step(&pose, rates, &accels).expect("a step");
        sum += s.qdd.last().copied().unwrap_or(0.0);
        pose = s.q;
        for d in &mut pose[..m.drivers()] {
            *d += delta;
        }
    }
    sum
}

/// As [`turn_runtime`], with the run-time stepper (its arrays kept).
fn turn_runtime_stepper(m: &Model, start: &[f64], rates: &[f64], delta: f64) -> f64 {
    let accels = vec![0.0; rates.len()];
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    let mut pose = start.to_vec();
    let mut sum = 0.0;
    for _ in 0..STEPS {
        let s = stepper.step(&pose, rates, &accels).expect("a step");
        sum += s.qdd.last().copied().unwrap_or(0.0);
        pose.copy_from_slice(&s.q);
        for d in &mut pose[..m.drivers()] {
            *d += delta;
        }
    }
    sum
}

fn summary(mut r: Vec<f64>) -> String {
    r.sort_by(f64::total_cmp);
    let (lo, mid, hi) = (r[ROUNDS / 10], r[ROUNDS / 2], r[ROUNDS - 1 - ROUNDS / 10]);
    format!("{mid:.2}× ({lo:.2}–{hi:.2})")
}

/// Times the three variants of one mechanism, interleaved, and prints its
/// row.
fn row<M: Mechanism>(label: &str, m: &M, r: &Model, start: M::Coords, rates: &[f64], delta: f64) {
    let options = Options::DEFAULT;
    let zeros = vec![0.0; rates.len()];
    let start = m.assemble_with(&start, &options).expect("assembles");
    let start_vec: Vec<f64> = (0..M::DRIVERS + M::UNKNOWNS)
        .map(|j| start.get(j).unwrap_or(0.0))
        .collect();
    let mut state = m.step_state(&options).expect("a stepper");
    // The stepper takes the drivers' rates in a coordinates value.
    let mut rate_coords = M::Coords::default();
    for (j, v) in rates.iter().enumerate() {
        rate_coords.set(j, *v);
    }
    let zero_coords = M::Coords::default();
    let mut stepper = |p: &M::Coords| {
        m.step_carried(p, &rate_coords, &zero_coords, &mut state)
            .expect("a step")
    };
    let mut plain = |p: &M::Coords| m.step_slices(p, rates, &zeros, &options).expect("a step");
    // The four agree before they are timed.
    let (a, b, c, d) = (
        turn_generated::<M>(&mut stepper, start, delta),
        turn_generated::<M>(&mut plain, start, delta),
        turn_runtime(r, &start_vec, rates, delta),
        turn_runtime_stepper(r, &start_vec, rates, delta),
    );
    let near = |x: f64| (a - x).abs() <= 1e-9 * a.abs().max(1.0);
    assert!(
        near(b) && near(c) && near(d),
        "{label}: checksums {a} {b} {c} {d}"
    );
    let (mut plain_ratio, mut runtime_ratio, mut kept_ratio) = (Vec::new(), Vec::new(), Vec::new());
    let mut per_step = Vec::new();
    for _ in 0..ROUNDS {
        let t0 = thread_cpu_ns();
        black_box(turn_generated::<M>(&mut stepper, black_box(start), delta));
        let t1 = thread_cpu_ns();
        black_box(turn_generated::<M>(&mut plain, black_box(start), delta));
        let t2 = thread_cpu_ns();
        black_box(turn_runtime(r, black_box(&start_vec), rates, delta));
        let t3 = thread_cpu_ns();
        black_box(turn_runtime_stepper(r, black_box(&start_vec), rates, delta));
        let t4 = thread_cpu_ns();
        plain_ratio.push((t2 - t1) / (t1 - t0));
        runtime_ratio.push((t3 - t2) / (t1 - t0));
        kept_ratio.push((t4 - t3) / (t1 - t0));
        per_step.push((t4 - t3) / STEPS as f64);
    }
    per_step.sort_by(f64::total_cmp);
    println!(
        "| {label} | {} | {} | {} | {:.0} ns |",
        summary(plain_ratio),
        summary(runtime_ratio),
        summary(kept_ratio),
        per_step[ROUNDS / 2]
    );
}

/// The medians of `runs` times (ms) to compile `text` and to make the
/// compiled model's first stepper (which compiles its fused step), with
/// every parameter 1.
fn compile_times(text: &str, runs: usize) -> (f64, f64) {
    let (mut compile, mut first): (Vec<f64>, Vec<f64>) = (0..runs)
        .map(|_| {
            let t0 = Instant::now();
            let mut m = black_box(Model::compile(black_box(text)).expect("compiles"));
            let t1 = Instant::now();
            m.set_values(&vec![1.0; m.parameters().len()])
                .expect("one value each");
            let t2 = Instant::now();
            let stepper = black_box(m.stepper(&Options::DEFAULT).expect("valid"));
            let t3 = Instant::now();
            assert!(stepper.is_fused(), "the fused step applies");
            ((t1 - t0).as_secs_f64() * 1e3, (t3 - t2).as_secs_f64() * 1e3)
        })
        .unzip();
    compile.sort_by(f64::total_cmp);
    first.sort_by(f64::total_cmp);
    (compile[runs / 2], first[runs / 2])
}

fn main() {
    // Compile times: text to machine code, median of 11; the first
    // stepper compiles the fused step.
    println!(
        "| definition | compile at run time (median of 11) | first stepper (compiles the fused step) |\n|---|---|---|"
    );
    for name in ["FourBar", "Rssr", "Watt", "SixAxisArm"] {
        let text = kinematics_examples::definition(name).expect("an example");
        let (compile, first) = compile_times(text, 11);
        println!("| {name} | {compile:.1} ms | {first:.1} ms |");
    }
    // The chains of 100 and 250 four-bars (200 and 500 unknowns), median
    // of 5.
    for n in [100, 250] {
        let source = four_bar_chain::source("Chain", n);
        let bodies = kinematics_examples::mechanism_bodies(&source);
        let text = bodies.first().expect("a definition").0;
        let (compile, first) = compile_times(text, 5);
        println!(
            "| chain of {n} four-bars ({} unknowns) | {compile:.0} ms | {first:.0} ms |",
            2 * n,
        );
    }
    println!(
        "\n| mechanism | generated `step` / stepper | run-time `step` / stepper | run-time stepper / stepper | run-time stepper per step |\n|---|---|---|---|---|"
    );
    let turn = std::f64::consts::TAU / STEPS as f64;
    let g = FourBar::CRANK_ROCKER;
    let r = model("FourBar", FourBar::PARAMETERS, g.parameter_values());
    row(
        "M1 four-bar",
        &g,
        &r,
        FourBar::CRANK_ROCKER_GUESS,
        &[10.0],
        turn,
    );
    let g = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.314,
    };
    let r = model("Rssr", Rssr::PARAMETERS, g.parameter_values());
    row("M2 RSSR", &g, &r, [0.0, 1.2].into(), &[25.0], turn);
    let g = Watt::EXAMPLE;
    let r = model("Watt", Watt::PARAMETERS, g.parameter_values());
    row(
        "M3 Watt six-bar",
        &g,
        &r,
        Watt::EXAMPLE_GUESS,
        &[10.0],
        turn,
    );
    let g = SixAxisArm {
        d1: 0.4,
        a2: 0.35,
        a3: 0.3,
        d5: 0.08,
        d6: 0.1,
    };
    let r = model("SixAxisArm", SixAxisArm::PARAMETERS, g.parameter_values());
    row(
        "M4 six-axis arm",
        &g,
        &r,
        [0.1, -0.4, 0.7, 0.2, -0.3, 0.5].into(),
        &[0.5, -0.2, 0.3, 1.0, -0.7, 0.4],
        turn,
    );
}
