//! Cost of one simulation step, for four mechanisms and five ways of
//! getting the derivatives, and the cost of the macro expansion.
//!
//! A step: set the driver to its next value (3600 steps per turn), assemble
//! from the previous pose by Newton–Raphson to max|Φ| < 1e-12, solve
//! velocities and accelerations, and evaluate a point's (and for the arm a
//! frame's) position, velocity and acceleration; the outputs are summed into
//! a checksum. The variants:
//!
//! 1. the code `mechanism!` generates, through its public API (`step`:
//!    assemble and analyse in one call), and through the stepping handle
//!    (`stepper().step`, which checks the options, parameters and scales
//!    once and carries sines and cosines from step to step);
//! 2. hand-written, hand-differentiated code (`hand.rs`);
//! 3. forward-mode dual numbers, `num-dual` (`generic.rs`);
//! 4. central finite differences (`generic.rs`);
//! 5. the macro's expression DAG interpreted at run time (`interp.rs`);
//! 6. the same definition compiled at run time
//!    (`kinematics_core::runtime::Model`, machine code from Cranelift),
//!    through its stepper.
//!
//! Before timing, every variant's checksum over a full turn is compared with
//! the hand-written one. `cargo bench -p kinematics-bench --bench steps`
//! prints the table; with `KINEMATICS_BENCH_README=1` it also rewrites the
//! table in the performance guide (`kinematics-core/docs/performance.md`).

// Benchmark code: a failed setup should stop the run (panics), and the
// numerical loops index several arrays in step, as in the formulas.
#![allow(clippy::expect_used, clippy::panic, clippy::needless_range_loop)]

mod generic;
mod hand;
mod interp;
mod models;
mod positions;

pub(crate) use kinematics_bench::thread_cpu_ns;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::Criterion;
use kinematics_core::runtime::Model;
use kinematics_core::sweep::{Angle, Driver, SweepBuilder};
use kinematics_core::Options;

use models::{m1, m2, m3, m4, ARM_OFFSET, ARM_SPEED, M1, M2, M3, M4};

pub(crate) const STEPS: usize = 3600;

pub(crate) fn angle(k: usize) -> f64 {
    // Exact for the integers involved.
    #[allow(clippy::cast_precision_loss)]
    let k = k as f64;
    k * TAU / STEPS as f64
}

/// The mechanisms and their driver rates as run-time data, as in an
/// application: every variant reads them through `black_box` once per
/// turn, so that none has its parameters or rates folded into its code as
/// constants.
pub(crate) fn data<T>(x: T) -> T {
    black_box(x)
}

/// Driver rates and accelerations of the planar and RSSR sweeps.
const M1_RATES: (f64, f64) = (10.0, 2.0);
const M2_RATES: (f64, f64) = (8.0 * std::f64::consts::PI, 0.0); // 240 rev/min
const M3_RATES: (f64, f64) = (10.0, 2.0);

/// Starting unknowns at φ = 0.
const M1_START: [f64; 2] = [1.0, 1.6];
const M2_START: [f64; 1] = [1.2];
const M3_START: [f64; 4] = [1.0, 1.6, 0.3, 1.9];

// ───────────────────────── variant 1: generated ─────────────────────────

/// A full turn of M1 through `step` (the public `step`, or a stepper's).
fn turn_m1(
    mut step: impl FnMut(&m1::FourBarCoords) -> Result<m1::FourBarMotion, kinematics_core::Error>,
) -> f64 {
    let mut pose = m1::FourBarCoords::from([0.0, M1_START[0], M1_START[1]]);
    let mut sum = 0.0;
    for k in 0..STEPS {
        pose.phi = angle(k);
        let s = step(&pose).expect("step");
        pose = s.q;
        let p = s.point_p();
        sum += pose.th3 + pose.th4 + s.qd.th3 + s.qd.th4 + s.qdd.th3 + s.qdd.th4;
        sum += p.position.sum() + p.velocity.sum() + p.acceleration.sum();
    }
    sum
}

fn gen_m1() -> f64 {
    let (m, rates) = data((M1, M1_RATES));
    turn_m1(|pose| m.step(pose, rates.0, rates.1))
}

/// As the generated variant, through the stepping handle.
fn gen_m1s() -> f64 {
    let (m, rates) = data((M1, M1_RATES));
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    turn_m1(|pose| stepper.step(pose, rates.0, rates.1))
}

/// A full turn of M2 through `step`.
fn turn_m2(
    mut step: impl FnMut(&m2::RssrCoords) -> Result<m2::RssrMotion, kinematics_core::Error>,
) -> f64 {
    let mut pose = m2::RssrCoords::from([0.0, M2_START[0]]);
    let mut sum = 0.0;
    for k in 0..STEPS {
        pose.phi = angle(k);
        let s = step(&pose).expect("step");
        pose = s.q;
        let p = s.point_b();
        sum += pose.psi + s.qd.psi + s.qdd.psi;
        sum += p.position.sum() + p.velocity.sum() + p.acceleration.sum();
    }
    sum
}

fn gen_m2() -> f64 {
    let (m, rates) = data((M2, M2_RATES));
    turn_m2(|pose| m.step(pose, rates.0, rates.1))
}

/// As the generated variant, through the stepping handle.
fn gen_m2s() -> f64 {
    let (m, rates) = data((M2, M2_RATES));
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    turn_m2(|pose| stepper.step(pose, rates.0, rates.1))
}

/// A full turn of M3 through `step`.
fn turn_m3(
    mut step: impl FnMut(&m3::WattCoords) -> Result<m3::WattMotion, kinematics_core::Error>,
) -> f64 {
    let [th3, th4, th5, th6] = M3_START;
    let mut pose = m3::WattCoords::from([0.0, th3, th4, th5, th6]);
    let mut sum = 0.0;
    for k in 0..STEPS {
        pose.phi = angle(k);
        let s = step(&pose).expect("step");
        pose = s.q;
        let p = s.point_f();
        sum += pose.th3 + pose.th4 + pose.th5 + pose.th6;
        sum += s.qd.th3 + s.qd.th4 + s.qd.th5 + s.qd.th6;
        sum += s.qdd.th3 + s.qdd.th4 + s.qdd.th5 + s.qdd.th6;
        sum += p.position.sum() + p.velocity.sum() + p.acceleration.sum();
    }
    sum
}

fn gen_m3() -> f64 {
    let (m, rates) = data((M3, M3_RATES));
    turn_m3(|pose| m.step(pose, rates.0, rates.1))
}

/// As the generated variant, through the stepping handle.
fn gen_m3s() -> f64 {
    let (m, rates) = data((M3, M3_RATES));
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    turn_m3(|pose| stepper.step(pose, rates.0, rates.1))
}

/// A full turn of `driver` through a sweep (`m.sweep(driver, &start)
/// .turn()`, 3600 samples).
fn turn_sweep<M: kinematics_core::Mechanism>(
    m: &M,
    driver: Driver<M, Angle>,
    start: M::Coords,
    rates: (f64, f64),
) -> SweepBuilder<'_, M, Angle> {
    SweepBuilder::new(m, driver, &start)
        .turn()
        .steps(STEPS)
        .rate(rates.0)
        .acceleration(rates.1)
}

/// The turn through a sweep, summed by `turn` over its samples: streamed
/// from its iterator, or collected into its `Vec` first.
macro_rules! swept {
    ($m:expr, $driver:expr, $start:expr, $rates:expr, $collected:expr, $turn:ident) => {{
        let sweep = turn_sweep($m, $driver, $start, $rates);
        if $collected {
            let s = sweep.run();
            assert!(s.stop.is_none(), "the sweep stopped: {:?}", s.stop);
            let mut samples = s.samples.into_iter();
            $turn(|_| Ok(samples.next().expect("a sample per step").motion))
        } else {
            let mut samples = sweep.into_iter();
            $turn(|_| {
                Ok(samples
                    .next()
                    .expect("a sample per step")
                    .expect("no stop")
                    .motion)
            })
        }
    }};
}

fn sweep_m1(collected: bool) -> f64 {
    let start = m1::FourBarCoords::from([0.0, M1_START[0], M1_START[1]]);
    let (m, rates) = data((M1, M1_RATES));
    swept!(&m, m1::FourBar::PHI, start, rates, collected, turn_m1)
}

fn sweep_m2(collected: bool) -> f64 {
    let start = m2::RssrCoords::from([0.0, M2_START[0]]);
    let (m, rates) = data((M2, M2_RATES));
    swept!(&m, m2::Rssr::PHI, start, rates, collected, turn_m2)
}

fn sweep_m3(collected: bool) -> f64 {
    let [th3, th4, th5, th6] = M3_START;
    let start = m3::WattCoords::from([0.0, th3, th4, th5, th6]);
    let (m, rates) = data((M3, M3_RATES));
    swept!(&m, m3::Watt::PHI, start, rates, collected, turn_m3)
}

fn arm_joints(k: usize) -> ([f64; 6], [f64; 6], [f64; 6]) {
    let s = angle(k);
    (
        std::array::from_fn(|i| ARM_OFFSET[i] + ARM_SPEED[i] * s),
        ARM_SPEED,
        std::array::from_fn(|i| 0.3 * ARM_SPEED[i]),
    )
}

/// A full turn of M4 through `step`.
fn turn_m4(
    mut step: impl FnMut(
        &m4::ArmCoords,
        [f64; 6],
        [f64; 6],
    ) -> Result<m4::ArmMotion, kinematics_core::Error>,
) -> f64 {
    let mut sum = 0.0;
    for k in 0..STEPS {
        let (q, qd, qdd) = arm_joints(k);
        let s = step(&m4::ArmCoords::from(q), qd, qdd).expect("step");
        let (p, f) = (s.point_tcp(), s.frame_tool());
        sum += q.iter().sum::<f64>();
        sum += p.position.sum() + p.velocity.sum() + p.acceleration.sum();
        sum += f.rotation.sum() + f.angular_velocity.sum() + f.angular_acceleration.sum();
    }
    sum
}

fn gen_m4() -> f64 {
    let m = data(M4);
    turn_m4(|q, qd, qdd| m.step(q, qd, qdd))
}

/// As the generated variant, through the stepping handle.
fn gen_m4s() -> f64 {
    let m = data(M4);
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    turn_m4(|q, qd, qdd| stepper.step(q, qd, qdd))
}

// ───────────────────────── variant 2: hand-written ─────────────────────────

fn hand_m1() -> f64 {
    let (m, rates) = data((M1, M1_RATES));
    let mut st = hand::Carried::new(M1_START);
    let beta = m.beta.sin_cos();
    (0..STEPS)
        .map(|k| hand::m1_step(&m, beta, angle(k), &mut st, rates.0, rates.1))
        .sum()
}

fn hand_m2() -> f64 {
    let (m, rates) = data((M2, M2_RATES));
    let mut st = hand::Carried::new(M2_START);
    (0..STEPS)
        .map(|k| hand::m2_step(&m, angle(k), &mut st, rates.0, rates.1))
        .sum()
}

fn hand_m3() -> f64 {
    let (m, rates) = data((M3, M3_RATES));
    let mut th = M3_START;
    (0..STEPS)
        .map(|k| hand::m3_step(&m, angle(k), &mut th, rates.0, rates.1))
        .sum()
}

fn hand_m4() -> f64 {
    let m = data(M4);
    (0..STEPS)
        .map(|k| {
            let (q, qd, qdd) = arm_joints(k);
            hand::m4_step(&m, &q, &qd, &qdd)
        })
        .sum()
}

// ───────────────────────── variant 6: run-time model ─────────────────────────

/// The definition `tokens` compiled at run time, with the parameters
/// `params` (in declaration order).
fn runtime_model(tokens: &proc_macro2::TokenStream, params: &[f64]) -> Model {
    let mut m = Model::compile(&tokens.to_string()).expect("the definition compiles");
    m.set_values(params).expect("one value per parameter");
    m
}

/// M3's pose to start from: the driver, then [`M3_START`].
fn m3_start() -> [f64; 5] {
    let [a, b, c, d] = M3_START;
    [0.0, a, b, c, d]
}

/// A full turn of a run-time model with one driver through its stepper,
/// from the pose `start` (the driver first, then the unknowns) with the
/// driver's rate and acceleration `rates`; the checksum sums the same
/// values as the generated turns (the unknowns, their rates and
/// accelerations, and point `point`). With `FLAT`, each step's motion is
/// read from the stepper's flat arrays (`Stepper::step_flat`) instead of
/// its `Motion` (`Stepper::step`).
///
/// The counts are known when the harness is compiled, as they are in the
/// generated turns: `Q` coordinates and points of `D` components (checked
/// against the model's before the turn). So both checksums are the same
/// fixed run of loads and additions, and the ratio is the library's,
/// not the harness's: summed over slices of lengths known only at run
/// time (short loops of one to three values), the checksum alone made
/// the RSSR's turn about 10 % longer.
fn runtime_turn<const Q: usize, const D: usize, const FLAT: bool>(
    m: &Model,
    start: [f64; Q],
    rates: (f64, f64),
    point: &str,
) -> f64 {
    let (m, rates) = data((m, rates));
    assert_eq!(
        (m.drivers() + m.unknowns(), m.point_dimension()),
        (Q, D),
        "the harness's counts"
    );
    let p = m
        .point_names()
        .iter()
        .position(|n| *n == point)
        .expect("the point");
    let at = 3 * D * p;
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    let mut pose = start;
    let mut sum = 0.0;
    for k in 0..STEPS {
        pose[0] = angle(k);
        if FLAT {
            let s = stepper
                .step_flat(&pose, &[rates.0], &[rates.1])
                .expect("step");
            pose.copy_from_slice(s.q);
            sum += s.q[1..Q].iter().sum::<f64>()
                + s.qd[1..Q].iter().sum::<f64>()
                + s.qdd[1..Q].iter().sum::<f64>();
            sum += grouped_sum::<D>(&s.outputs[at..at + 3 * D], 3);
        } else {
            let s = stepper.step(&pose, &[rates.0], &[rates.1]).expect("step");
            pose.copy_from_slice(&s.q);
            let pt = &s.points[p];
            sum += s.q[1..Q].iter().sum::<f64>()
                + s.qd[1..Q].iter().sum::<f64>()
                + s.qdd[1..Q].iter().sum::<f64>();
            sum += pt.position[..D].iter().sum::<f64>()
                + pt.velocity[..D].iter().sum::<f64>()
                + pt.acceleration[..D].iter().sum::<f64>();
        }
    }
    sum
}

/// The sum of the first `groups` groups of `W` values of `values`, as the
/// generated turns sum a motion's vectors: each group summed on its own,
/// then the sums added (`p.position.sum() + p.velocity.sum() + …`), so
/// that both checksums are the same chain of additions.
fn grouped_sum<const W: usize>(values: &[f64], groups: usize) -> f64 {
    values
        .chunks_exact(W)
        .take(groups)
        .map(|g| g.iter().sum::<f64>())
        .sum()
}

/// A full turn of the arm, a run-time model, through its stepper (with
/// `FLAT`, read from the flat arrays, as in [`runtime_turn`], whose
/// fixed counts it shares: a 3-D point and a frame).
fn runtime_m4<const FLAT: bool>(m: &Model) -> f64 {
    let m = data(m);
    assert_eq!(m.point_dimension(), 3, "the harness's counts");
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    let mut sum = 0.0;
    for k in 0..STEPS {
        let (q, qd, qdd) = arm_joints(k);
        sum += q.iter().sum::<f64>();
        if FLAT {
            let s = stepper.step_flat(&q, &qd, &qdd).expect("step");
            // The point's 3d values, then the frame's rotation, ω and α.
            let o = &s.outputs[..24];
            sum += grouped_sum::<3>(&o[..9], 3)
                + o[9..18].iter().sum::<f64>()
                + grouped_sum::<3>(&o[18..], 2);
        } else {
            let s = stepper.step(&q, &qd, &qdd).expect("step");
            let (p, f) = (&s.points[0], &s.frames[0]);
            sum += p.position[..3].iter().sum::<f64>()
                + p.velocity[..3].iter().sum::<f64>()
                + p.acceleration[..3].iter().sum::<f64>();
            sum += f.rotation.sum() + f.angular_velocity.sum() + f.angular_acceleration.sum();
        }
    }
    sum
}

// ───────────────── variants 3–5: dual numbers, differences, DAG ─────────────────

/// A closed-loop sweep with one driver and NU unknowns, for a step function
/// of the generic variants.
fn sweep<const NQ: usize, const NU: usize>(
    start: [f64; NU],
    rates: (f64, f64),
    mut step: impl FnMut(&mut [f64; NQ], &mut [f64; NQ], &mut [f64; NQ]) -> f64,
) -> f64 {
    let rates = data(rates);
    let mut q = [0.0; NQ];
    q[1..].copy_from_slice(&start);
    let mut sum = 0.0;
    for k in 0..STEPS {
        q[0] = angle(k);
        let mut qd = [0.0; NQ];
        let mut qdd = [0.0; NQ];
        qd[0] = rates.0;
        qdd[0] = rates.1;
        sum += step(&mut q, &mut qd, &mut qdd);
    }
    sum
}

fn arm_sweep(mut step: impl FnMut(&mut [f64; 6], &mut [f64; 6], &mut [f64; 6]) -> f64) -> f64 {
    (0..STEPS)
        .map(|k| {
            let (mut q, mut qd, mut qdd) = arm_joints(k);
            step(&mut q, &mut qd, &mut qdd)
        })
        .sum()
}

type Sweep = Box<dyn FnMut() -> f64>;

fn interp(tokens: proc_macro2::TokenStream, params: &[f64]) -> interp::Interp {
    interp::Interp::new(tokens, params.to_vec())
}

/// The twenty sweeps: (mechanism, variant, sweep).
fn sweeps() -> Vec<(&'static str, &'static str, Sweep)> {
    let p1 = vec![M1.a, M1.b, M1.c, M1.d, M1.p, M1.beta];
    let p2 = vec![M2.a, M2.b, M2.c, M2.d];
    let p3 = vec![
        M3.a, M3.b, M3.c, M3.d, M3.e, M3.gamma, M3.f, M3.g, M3.gx, M3.gy,
    ];
    let p4 = vec![M4.d1, M4.a2, M4.a3, M4.d5, M4.d6];
    let mut i1 = interp(m1::tokens(), &p1);
    let mut i2 = interp(m2::tokens(), &p2);
    let mut i3 = interp(m3::tokens(), &p3);
    let mut i4 = interp(m4::tokens(), &p4);
    let r1 = runtime_model(&m1::tokens(), &p1);
    let r2 = runtime_model(&m2::tokens(), &p2);
    let r3 = runtime_model(&m3::tokens(), &p3);
    let r4 = runtime_model(&m4::tokens(), &p4);
    let (f1, f2, f3, f4) = (r1.clone(), r2.clone(), r3.clone(), r4.clone());
    vec![
        (
            "M1 four-bar",
            "run-time stepper",
            Box::new(move || {
                runtime_turn::<3, 2, false>(&r1, [0.0, M1_START[0], M1_START[1]], M1_RATES, "P")
            }),
        ),
        (
            "M2 RSSR",
            "run-time stepper",
            Box::new(move || runtime_turn::<2, 3, false>(&r2, [0.0, M2_START[0]], M2_RATES, "B")),
        ),
        (
            "M3 Watt six-bar",
            "run-time stepper",
            Box::new(move || runtime_turn::<5, 2, false>(&r3, m3_start(), M3_RATES, "F")),
        ),
        (
            "M4 six-axis arm",
            "run-time stepper",
            Box::new(move || runtime_m4::<false>(&r4)),
        ),
        (
            "M1 four-bar",
            "run-time flat",
            Box::new(move || {
                runtime_turn::<3, 2, true>(&f1, [0.0, M1_START[0], M1_START[1]], M1_RATES, "P")
            }),
        ),
        (
            "M2 RSSR",
            "run-time flat",
            Box::new(move || runtime_turn::<2, 3, true>(&f2, [0.0, M2_START[0]], M2_RATES, "B")),
        ),
        (
            "M3 Watt six-bar",
            "run-time flat",
            Box::new(move || runtime_turn::<5, 2, true>(&f3, m3_start(), M3_RATES, "F")),
        ),
        (
            "M4 six-axis arm",
            "run-time flat",
            Box::new(move || runtime_m4::<true>(&f4)),
        ),
        ("M1 four-bar", "generated", Box::new(gen_m1)),
        ("M1 four-bar", "stepper", Box::new(gen_m1s)),
        ("M1 four-bar", "sweep", Box::new(|| sweep_m1(false))),
        (
            "M1 four-bar",
            "sweep collected",
            Box::new(|| sweep_m1(true)),
        ),
        ("M1 four-bar", "hand-written", Box::new(hand_m1)),
        (
            "M1 four-bar",
            "dual numbers",
            Box::new(|| {
                let m = data(M1);
                sweep::<3, 2>(M1_START, M1_RATES, |q, d, a| {
                    generic::dual_step::<_, 3, 2>(&m, q, d, a)
                })
            }),
        ),
        (
            "M1 four-bar",
            "finite differences",
            Box::new(|| {
                let m = data(M1);
                sweep::<3, 2>(M1_START, M1_RATES, |q, d, a| {
                    generic::fd_step::<_, 3, 2>(&m, q, d, a)
                })
            }),
        ),
        (
            "M1 four-bar",
            "interpreted DAG",
            Box::new(move || sweep::<3, 2>(M1_START, M1_RATES, |q, d, a| i1.step::<3, 2>(q, d, a))),
        ),
        ("M2 RSSR", "generated", Box::new(gen_m2)),
        ("M2 RSSR", "stepper", Box::new(gen_m2s)),
        ("M2 RSSR", "sweep", Box::new(|| sweep_m2(false))),
        ("M2 RSSR", "sweep collected", Box::new(|| sweep_m2(true))),
        ("M2 RSSR", "hand-written", Box::new(hand_m2)),
        (
            "M2 RSSR",
            "dual numbers",
            Box::new(|| {
                let m = data(M2);
                sweep::<2, 1>(M2_START, M2_RATES, |q, d, a| {
                    generic::dual_step::<_, 2, 1>(&m, q, d, a)
                })
            }),
        ),
        (
            "M2 RSSR",
            "finite differences",
            Box::new(|| {
                let m = data(M2);
                sweep::<2, 1>(M2_START, M2_RATES, |q, d, a| {
                    generic::fd_step::<_, 2, 1>(&m, q, d, a)
                })
            }),
        ),
        (
            "M2 RSSR",
            "interpreted DAG",
            Box::new(move || sweep::<2, 1>(M2_START, M2_RATES, |q, d, a| i2.step::<2, 1>(q, d, a))),
        ),
        ("M3 Watt six-bar", "generated", Box::new(gen_m3)),
        ("M3 Watt six-bar", "stepper", Box::new(gen_m3s)),
        ("M3 Watt six-bar", "sweep", Box::new(|| sweep_m3(false))),
        (
            "M3 Watt six-bar",
            "sweep collected",
            Box::new(|| sweep_m3(true)),
        ),
        ("M3 Watt six-bar", "hand-written", Box::new(hand_m3)),
        (
            "M3 Watt six-bar",
            "dual numbers",
            Box::new(|| {
                let m = data(M3);
                sweep::<5, 4>(M3_START, M3_RATES, |q, d, a| {
                    generic::dual_step::<_, 5, 4>(&m, q, d, a)
                })
            }),
        ),
        (
            "M3 Watt six-bar",
            "finite differences",
            Box::new(|| {
                let m = data(M3);
                sweep::<5, 4>(M3_START, M3_RATES, |q, d, a| {
                    generic::fd_step::<_, 5, 4>(&m, q, d, a)
                })
            }),
        ),
        (
            "M3 Watt six-bar",
            "interpreted DAG",
            Box::new(move || sweep::<5, 4>(M3_START, M3_RATES, |q, d, a| i3.step::<5, 4>(q, d, a))),
        ),
        ("M4 six-axis arm", "generated", Box::new(gen_m4)),
        ("M4 six-axis arm", "stepper", Box::new(gen_m4s)),
        ("M4 six-axis arm", "hand-written", Box::new(hand_m4)),
        (
            "M4 six-axis arm",
            "dual numbers",
            Box::new(|| {
                let m = data(M4);
                arm_sweep(|q, d, a| generic::dual_step::<_, 6, 0>(&m, q, d, a))
            }),
        ),
        (
            "M4 six-axis arm",
            "finite differences",
            Box::new(|| {
                let m = data(M4);
                arm_sweep(|q, d, a| generic::fd_step::<_, 6, 0>(&m, q, d, a))
            }),
        ),
        (
            "M4 six-axis arm",
            "interpreted DAG",
            Box::new(move || arm_sweep(|q, d, a| i4.step::<6, 0>(q, d, a))),
        ),
    ]
}

const VARIANTS: [&str; 10] = [
    "generated",
    "stepper",
    "sweep",
    "sweep collected",
    "hand-written",
    "dual numbers",
    "finite differences",
    "interpreted DAG",
    "run-time stepper",
    "run-time flat",
];
const MECHANISMS: [&str; 4] = [
    "M1 four-bar",
    "M2 RSSR",
    "M3 Watt six-bar",
    "M4 six-axis arm",
];

/// Every variant computes the same motion: their checksums over a full turn
/// agree with the hand-written one (finite differences to their truncation
/// error).
fn check_agreement(all: &mut [(&'static str, &'static str, Sweep)]) {
    for mech in MECHANISMS {
        let reference = all
            .iter_mut()
            .find(|(m, v, _)| *m == mech && *v == "hand-written")
            .map(|(_, _, f)| f())
            .expect("a hand-written variant");
        for (m, v, f) in all.iter_mut().filter(|(m, _, _)| *m == mech) {
            let got = f();
            let tol = if *v == "finite differences" {
                1e-3
            } else {
                1e-8
            };
            let rel = (got - reference).abs() / reference.abs().max(1.0);
            assert!(
                rel < tol,
                "{m} {v}: checksum {got} vs hand-written {reference} (relative {rel:e})"
            );
        }
    }
}

/// Reads criterion's median estimate (ns per sweep) of one benchmark.
fn median_ns(group: &str, id: &str) -> Option<f64> {
    let base = std::env::var("CARGO_TARGET_DIR").map_or_else(
        |_| std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")),
        std::path::PathBuf::from,
    );
    let dir = |s: &str| s.replace('/', "_");
    let path = base
        .join("criterion")
        .join(dir(group))
        .join(dir(id))
        .join("new/estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    json["median"]["point_estimate"].as_f64()
}

/// Median wall time of `f` over `n` runs.
fn median_time(n: usize, mut f: impl FnMut()) -> Duration {
    let mut t: Vec<Duration> = (0..n)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    t.sort();
    t[n / 2]
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".to_owned());
    let cores = std::thread::available_parallelism().map_or(0, std::num::NonZero::get);
    format!("{cpu}, {cores} cores")
}

/// Today's date (UTC), from days since 1970-01-01 (civil calendar).
fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let z = i64::try_from(secs / 86_400).unwrap_or(0) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}")
}

fn expansion_table() -> String {
    let defs = [
        ("M1 four-bar", m1::tokens()),
        ("M2 RSSR", m2::tokens()),
        ("M3 Watt six-bar", m3::tokens()),
        ("M4 six-axis arm", m4::tokens()),
    ];
    let mut out = String::from(
        "| mechanism | expansion time | Newton step ops: trees → shared | analysis ops: trees → shared |\n|---|---|---|---|\n",
    );
    for (name, tokens) in defs {
        let t = median_time(11, || {
            black_box(kinematics_compiler::expand(black_box(tokens.clone())));
        });
        let counts = kinematics_compiler::op_counts(tokens).expect("a valid definition");
        let [(_, n), (_, a)] = counts;
        out += &format!(
            "| {name} | {:.2} ms | {} → {} | {} → {} |\n",
            t.as_secs_f64() * 1e3,
            n.tree,
            n.shared,
            a.tree,
            a.shared
        );
    }
    out
}

fn main() {
    let mut all = sweeps();
    check_agreement(&mut all);
    if std::env::var_os("KINEMATICS_BENCH_INTERLEAVED").is_some() {
        // The interleaved ratios only (about a minute).
        println!("{}", interleaved(&mut all));
        println!("{}", positions::table());
        return;
    }
    let mut c = Criterion::default()
        .configure_from_args()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(20);
    for (mech, variant, f) in &mut all {
        let mut group = c.benchmark_group(*mech);
        group.bench_function(*variant, |b| b.iter(|| black_box(f())));
        group.finish();
    }
    c.final_summary();

    #[allow(clippy::cast_precision_loss)]
    let per_step = |ns: f64| ns / STEPS as f64;
    let mut table = format!(
        "ns per step (one step: assemble from the previous pose, velocities, accelerations, one point{}), \
         median of criterion's samples; in brackets, the ratio to the hand-written code. \
         Each variant is timed in a run of its own, one after another: as the load of the \
         machine varies, their ratios can be off by as much as a third; the interleaved table below \
         compares them in the same rounds. Measured on {}, {}.\n\n| mechanism | {} |\n|---|{}\n",
        " and for the arm its tool frame",
        machine(),
        today(),
        VARIANTS.join(" | "),
        "---|".repeat(VARIANTS.len())
    );
    let mut complete = true;
    for mech in MECHANISMS {
        let hand = median_ns(mech, "hand-written");
        table += &format!("| {mech} |");
        for v in VARIANTS {
            match (median_ns(mech, v), hand) {
                (Some(ns), Some(h)) => table += &format!(" {:.0} ({:.2}×) |", per_step(ns), ns / h),
                // `sweep` drives one driver; the arm's six follow a profile.
                _ if v.starts_with("sweep") && mech == "M4 six-axis arm" => table += " – |",
                _ => {
                    complete = false;
                    table += " – |";
                }
            }
        }
        table += "\n";
    }
    table += "\n";
    table += &interleaved(&mut all);
    table += "\n";
    table += &positions::table();
    table += "\nMacro expansion (the whole `proc_macro2` pipeline, median of 11 runs) and floating-point \
              operation counts, written out as expression trees and after common-subexpression elimination:\n\n";
    table += &expansion_table();
    println!("\n{table}");
    if std::env::var_os("KINEMATICS_BENCH_README").is_some() {
        if complete {
            write_readme(&table);
        } else {
            eprintln!("not all benchmarks ran (a filter was given?); the performance guide left unchanged");
        }
    }
}

/// The ratios of `variants` to the hand-written code, measured interleaved:
/// 41 rounds, each timing one turn of every variant in turn (thread CPU
/// time), the ratio taken within each round; per variant the median ratio
/// and the range of the middle 80 % of rounds.
fn interleaved(all: &mut [(&'static str, &'static str, Sweep)]) -> String {
    const ROUNDS: usize = 41;
    const SHOWN: [&str; 7] = [
        "generated",
        "stepper",
        "sweep",
        "sweep collected",
        "run-time stepper",
        "run-time flat",
        "hand-written",
    ];
    let mut out = String::from(
        "Interleaved (41 rounds; in each, one turn of every variant in turn, thread CPU time; \
         the ratio to the hand-written turn of the same round): median ratio, and the range \
         of the middle 80 % of rounds. `sweep` streams the samples from its iterator, \
         `collected` gathers them into its `Vec` first (the arm, whose six drivers follow a \
         profile, has no sweep); `run-time` is the stepper of the same definition compiled \
         at run time (`runtime::Model`), its motion read from the `Motion` of \
         `Stepper::step` or from the flat arrays of `Stepper::step_flat`.\n\n| mechanism | \
         generated | stepper | sweep | collected | run-time | run-time flat | \
         sweep / stepper | collected / stepper | run-time / stepper | \
         run-time flat / stepper |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let summary = |mut r: Vec<f64>| {
        if r.is_empty() {
            return "–".to_string();
        }
        r.sort_by(f64::total_cmp);
        let (lo, mid, hi) = (r[ROUNDS / 10], r[ROUNDS / 2], r[ROUNDS - 1 - ROUNDS / 10]);
        format!("{mid:.2}× ({lo:.2}–{hi:.2})")
    };
    for mech in MECHANISMS {
        // The variants this mechanism has, in the order of `SHOWN`.
        let shown: Vec<usize> = (0..SHOWN.len())
            .filter(|&i| all.iter().any(|(m, w, _)| *m == mech && *w == SHOWN[i]))
            .collect();
        let hand = SHOWN.len() - 1;
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); SHOWN.len()];
        let (mut streamed, mut collected) = (Vec::new(), Vec::new());
        let (mut runtime, mut flat) = (Vec::new(), Vec::new());
        for _ in 0..ROUNDS {
            let mut round = [f64::NAN; SHOWN.len()];
            for &i in &shown {
                let (_, _, f) = all
                    .iter_mut()
                    .find(|(m, w, _)| *m == mech && *w == SHOWN[i])
                    .expect("a variant");
                let t0 = thread_cpu_ns();
                black_box(f());
                round[i] = thread_cpu_ns() - t0;
            }
            for &i in &shown {
                times[i].push(round[i] / round[hand]);
            }
            if shown.contains(&2) {
                streamed.push(round[2] / round[1]);
                collected.push(round[3] / round[1]);
            }
            if shown.contains(&4) {
                runtime.push(round[4] / round[1]);
            }
            if shown.contains(&5) {
                flat.push(round[5] / round[1]);
            }
        }
        let mut cells = times.into_iter().take(6).map(summary);
        let mut cell = || cells.next().unwrap_or_default();
        out += &format!(
            "| {mech} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            cell(),
            cell(),
            cell(),
            cell(),
            cell(),
            cell(),
            summary(streamed),
            summary(collected),
            summary(runtime),
            summary(flat)
        );
    }
    out
}

fn write_readme(table: &str) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../kinematics-core/docs/performance.md"
    );
    let (start, end) = (
        "<!-- benchmark table: start -->",
        "<!-- benchmark table: end -->",
    );
    let Ok(readme) = std::fs::read_to_string(path) else {
        eprintln!("the performance guide not found at {path}");
        return;
    };
    let (Some(a), Some(b)) = (readme.find(start), readme.find(end)) else {
        eprintln!("the performance guide has no benchmark table markers");
        return;
    };
    let new = format!("{}{start}\n{table}{}", &readme[..a], &readme[b..]);
    if std::fs::write(path, new).is_ok() {
        eprintln!("{path} updated");
    }
}
