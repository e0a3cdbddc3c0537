//! The run-time stepper entered with the upper halves of the vector
//! registers in use, against the same stepper entered with them clear.
//!
//! On an x86-64 host with AVX, Cranelift encodes the arithmetic with VEX
//! and some moves and spills with legacy SSE. After 256-bit code that did
//! not end with `vzeroupper` (in the same thread), each legacy instruction
//! would pay the processor's transition between the two encodings; the
//! library clears the upper halves before it enters the machine code. The
//! program times one turn of 3600 steps of the RSSR (M2) through
//! `Stepper::step_flat`, in rounds of four turns in turn: the generated
//! stepper and the run-time one, each once with the upper halves clear
//! and once after a 256-bit instruction set them; thread CPU time. It
//! prints, per variant, the median time per step and the range of the
//! middle 80 % of rounds, and the ratio of each run-time turn to the
//! generated turn entered in the same state.
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin upper_halves
//! ```
// A measuring harness: a failed step should stop it; the inline assembly
// sets and clears the upper halves.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::cast_precision_loss,
    unsafe_code
)]

use kinematics_bench::thread_cpu_ns;
use std::f64::consts::TAU;
use std::hint::black_box;

use kinematics_core::runtime::Model;
use kinematics_core::Options;
use kinematics_examples::{Rssr, RssrCoords};

const STEPS: usize = 3600;
const ROUNDS: usize = 41;
const OMEGA: f64 = 8.0 * std::f64::consts::PI;
const RSSR: Rssr = Rssr {
    a: 0.102,
    b: 0.381,
    c: 0.254,
    d: 0.314,
};

fn angle(k: usize) -> f64 {
    k as f64 * TAU / STEPS as f64
}

/// One turn of the generated stepper: the output angle and the second
/// point's position, velocity and acceleration summed.
#[inline(never)]
fn generated(m: &Rssr) -> f64 {
    let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
    let mut q = RssrCoords { phi: 0.0, psi: 1.2 };
    let mut sum = 0.0;
    for k in 0..STEPS {
        q.phi = angle(k);
        let s = stepper.step(&q, OMEGA, 0.0).unwrap();
        q = s.q;
        let b = &s.points[1];
        sum += q.psi + s.qd.psi + s.qdd.psi;
        sum += b.position.sum() + b.velocity.sum() + b.acceleration.sum();
    }
    sum
}

/// The same turn through the run-time stepper's flat arrays.
#[inline(never)]
fn run_time(m: &Model) -> f64 {
    let mut stepper = m.stepper(&Options::DEFAULT).unwrap();
    let mut q = [0.0, 1.2];
    let mut sum = 0.0;
    for k in 0..STEPS {
        q[0] = angle(k);
        let s = stepper.step_flat(&q, &[OMEGA], &[0.0]).unwrap();
        q.copy_from_slice(s.q);
        sum += s.q[1] + s.qd[1] + s.qdd[1];
        // The second point: after the first's nine values.
        sum += s.outputs[9..18].iter().sum::<f64>();
    }
    sum
}

/// Leaves the upper halves of the vector registers in use (`dirty`) or
/// clear.
#[cfg(target_arch = "x86_64")]
fn upper_halves(dirty: bool) {
    // SAFETY: called only where the host has AVX (checked by `has_avx`);
    // the first instruction writes ymm15, the second clears the upper
    // halves of ymm0–ymm15: all sixteen are declared clobbered.
    unsafe {
        if dirty {
            core::arch::asm!("vpcmpeqd ymm15, ymm15, ymm15", out("xmm15") _, options(nomem, nostack));
        } else {
            core::arch::asm!(
                "vzeroupper",
                out("xmm0") _, out("xmm1") _, out("xmm2") _, out("xmm3") _,
                out("xmm4") _, out("xmm5") _, out("xmm6") _, out("xmm7") _,
                out("xmm8") _, out("xmm9") _, out("xmm10") _, out("xmm11") _,
                out("xmm12") _, out("xmm13") _, out("xmm14") _, out("xmm15") _,
                options(nomem, nostack),
            );
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn upper_halves(_: bool) {}

/// Whether the host has AVX (the measurement's premise).
#[cfg(target_arch = "x86_64")]
fn has_avx() -> bool {
    std::arch::is_x86_feature_detected!("avx")
}

#[cfg(not(target_arch = "x86_64"))]
fn has_avx() -> bool {
    false
}

fn main() {
    if !has_avx() {
        println!("This measurement needs an x86-64 host with AVX.");
        return;
    }
    let text = kinematics_examples::definition("Rssr").unwrap();
    let mut model = Model::compile(text).unwrap();
    model.set_values(&[RSSR.a, RSSR.b, RSSR.c, RSSR.d]).unwrap();
    // Per round: generated clear, run-time clear, generated dirty,
    // run-time dirty (ns per step).
    let mut times = vec![[0.0; 4]; ROUNDS];
    for (round, t) in times.iter_mut().enumerate() {
        for i in 0..4 {
            // Rotate the order so that no variant always runs first.
            let v = (i + round) % 4;
            let dirty = v >= 2;
            let t0 = thread_cpu_ns();
            upper_halves(dirty);
            black_box(if v % 2 == 0 {
                generated(black_box(&RSSR))
            } else {
                run_time(black_box(&model))
            });
            upper_halves(false);
            t[v] = (thread_cpu_ns() - t0) / STEPS as f64;
        }
    }
    let spread = |mut v: Vec<f64>, unit: &str| {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        format!(
            "{:.2}{unit} ({:.2}–{:.2})",
            v[n / 2],
            v[n / 10],
            v[n - 1 - n / 10]
        )
    };
    let column = |i: usize| times.iter().map(|t| t[i]).collect::<Vec<_>>();
    let ratio = |a: usize, b: usize| times.iter().map(|t| t[a] / t[b]).collect::<Vec<_>>();
    println!(
        "M2 RSSR, {ROUNDS} rounds of one turn of {STEPS} steps; ns per step, median (middle 80 %)"
    );
    println!("| upper halves | generated | run-time flat | run-time / generated |");
    println!("|---|---|---|---|");
    for (name, g, r) in [("clear", 0, 1), ("in use", 2, 3)] {
        println!(
            "| {name} | {} | {} | {} |",
            spread(column(g), ""),
            spread(column(r), ""),
            spread(ratio(r, g), "×")
        );
    }
    println!("run-time in use / clear: {}", spread(ratio(3, 1), "×"));
}
