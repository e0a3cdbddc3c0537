//! The library's own time for the calls whose cost from Python
//! `bench/python/per_call.py` measures: a run-time model's `assemble`,
//! `analyze_with` and a 360-sample sweep of one turn, on the four-bar of
//! the examples and on pylinkage's Strider, in thread CPU time (the
//! median and the range of seven rounds).
//!
//! ```text
//! cargo run --release -p kinematics-bench --bin per_call
//! ```

// A benchmark program: a failed set-up should stop it.
#![allow(clippy::expect_used)]

use std::hint::black_box;

use kinematics_core::runtime::Model;
use kinematics_core::Options;

fn thread_time() -> f64 {
    kinematics_bench::thread_cpu_ns() * 1e-9
}

/// The median and range over seven rounds of `n` calls of `f` (µs a call).
fn rounds(n: u32, mut f: impl FnMut()) -> (f64, f64, f64) {
    f();
    let mut t: Vec<f64> = (0..7)
        .map(|_| {
            let start = thread_time();
            for _ in 0..n {
                f();
            }
            (thread_time() - start) / f64::from(n) * 1e6
        })
        .collect();
    t.sort_by(f64::total_cmp);
    (t[3], t[0], t[6])
}

fn main() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/mechanisms/");
    let cases: [(&str, &str, Vec<f64>, f64); 2] = [
        (
            "four-bar",
            "four_bar.mech",
            vec![0.04, 0.12, 0.10, 0.11, 0.06, 0.5],
            0.3,
        ),
        (
            "Strider",
            "strider.mech",
            vec![
                2.0,
                std::f64::consts::FRAC_PI_4,
                1.8,
                2.6,
                1.4,
                std::f64::consts::PI + 0.2,
                2.5,
                1.8,
            ],
            0.3,
        ),
    ];
    println!("library call (µs: median, range of 7 rounds, thread CPU time)");
    for (name, file, values, at) in cases {
        let text = std::fs::read_to_string(format!("{root}{file}")).expect("the definition");
        let m = Model::compile(&text)
            .expect("compiles")
            .with_values(&values)
            .expect("valid values");
        let driver = m.coordinates()[0].name;
        let mut q = vec![0.0; m.coordinates().len()];
        q[0] = at;
        let start = m
            .assemble_all(&q)
            .find_map(|(_, p)| p.ok())
            .expect("an assembly");
        let show = |what: &str, (med, lo, hi): (f64, f64, f64)| {
            println!("{name:9} {what:12} {med:9.3} ({lo:.3}–{hi:.3})");
        };
        show(
            "assemble",
            rounds(20_000, || {
                black_box(m.assemble(black_box(&start)).ok());
            }),
        );
        show(
            "analyze",
            rounds(20_000, || {
                black_box(
                    m.analyze_with(&start, &[10.0], &[0.0], &Options::DEFAULT)
                        .ok(),
                );
            }),
        );
        show(
            "sweep 360",
            rounds(300, || {
                let s = m
                    .sweep(driver, &start)
                    .expect("a driver")
                    .turn()
                    .steps(360)
                    .run();
                black_box(s.samples.len());
            }),
        );
    }
}
