//! Assembling near a known pose and analysing velocities and accelerations
//! allocate nothing on the heap.
//!
//! A counting global allocator records every allocation, per thread (the
//! tests run on parallel threads); the hot path must leave the count of its
//! own thread unchanged.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]
// Implementing `GlobalAlloc` requires `unsafe`; it only forwards to the
// system allocator and counts.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use kinematics_examples::{FourBar, RRtrRrt, Rssr, RssrCoords, SixAxisArm, SixAxisArmCoords};
use kinematics_tests::{DistanceFourBar, DistanceFourBarCoords, SlotSixBar, SlotSixBarModes};

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    ALLOCATIONS.with(|c| c.set(c.get() + 1));
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

/// Asserts that `hot_path` leaves this thread's allocation count unchanged,
/// after checking that the counter does see this thread's allocations (so
/// the zero means something).
fn assert_allocates_nothing(hot_path: impl FnOnce()) {
    counter_works();
    let before = allocations();
    hot_path();
    let allocated = allocations() - before;
    assert_eq!(allocated, 0, "the hot path allocated {allocated} times");
}

/// The counter sees this thread's allocations.
fn counter_works() {
    let before = allocations();
    let v = std::hint::black_box(vec![1u8; 16]);
    assert!(
        allocations() > before && v.len() == 16,
        "the counting allocator is not in use"
    );
}

// SAFETY: every method forwards to `System` with the caller's arguments,
// which upholds the `GlobalAlloc` contract unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: same layout as requested.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by `System` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: forwarded unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn assemble_and_analyze_allocate_nothing() {
    let m = FourBar::CRANK_ROCKER;
    let mut pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let six = RRtrRrt::EXAMPLE_4_2;
    let mut pose6 = six
        .assemble(&RRtrRrt::example_4_2_guess())
        .expect("assembles");
    let mut checksum = 0.0;
    assert_allocates_nothing(|| {
        for k in 0..3600 {
            let phi = f64::from(k) * std::f64::consts::TAU / 3600.0;
            pose.phi = phi;
            pose = m.assemble(&pose).expect("assembles");
            let s = m.analyze(&pose, 10.0, 2.0).expect("analysis");
            checksum += s.qdd.th4 + s.point_p().acceleration.x;
            pose6.phi = std::f64::consts::FRAC_PI_4 + 0.1 * phi.sin();
            pose6 = six.assemble(&pose6).expect("assembles");
            let s6 = six.analyze(&pose6, 4.712, 0.0).expect("analysis");
            checksum += s6.qdd.phi4 + s6.point_e().acceleration.x;
        }
    });
    assert!(checksum.is_finite());
}

#[test]
fn fused_step_of_spatial_mechanisms_allocates_nothing() {
    let rssr = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.315,
    };
    let mut pose = rssr
        .assemble(&RssrCoords { phi: 0.0, psi: 1.2 })
        .expect("assembles");
    let arm = SixAxisArm {
        d1: 0.4,
        a2: 0.45,
        a3: 0.4,
        d5: 0.08,
        d6: 0.1,
    };
    let mut checksum = 0.0;
    assert_allocates_nothing(|| {
        for k in 0..3600 {
            let s = f64::from(k) * std::f64::consts::TAU / 3600.0;
            pose.phi = s;
            let m = rssr.step(&pose, 25.13, 0.0).expect("step");
            pose = m.q;
            checksum += m.qdd.psi + m.point_b().acceleration.x;
            let q = SixAxisArmCoords {
                q1: s,
                q2: 0.5 * s,
                q3: -s,
                q4: s,
                q5: 0.2,
                q6: -s,
            };
            let a = arm.step(&q, [1.0; 6], [0.1; 6]).expect("step");
            checksum += a.frame_tool().angular_acceleration.z + a.point_tcp().acceleration.y;
        }
    });
    assert!(checksum.is_finite());
}

#[test]
fn a_stepper_allocates_nothing() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let mut stepper = m
        .stepper(&kinematics_core::Options::DEFAULT)
        .expect("a stepper");
    assert_allocates_nothing(|| {
        let mut pose = start;
        for k in 0..360 {
            pose.phi = f64::from(k) * 0.0175;
            pose = stepper.step(&pose, 10.0, 0.0).expect("steps").q;
        }
        std::hint::black_box(pose);
    });
}

#[test]
fn a_mixed_stepper_allocates_nothing() {
    let m = SlotSixBar::EXAMPLE;
    let guess = SlotSixBar::guess(0.0, 1.0);
    let modes = SlotSixBarModes {
        th3_th4: kinematics_core::closed::Mode::Plus,
    };
    let start = m.assemble_in(&guess, &modes).expect("assembles");
    let mut stepper = m
        .stepper(&kinematics_core::Options::DEFAULT)
        .expect("a stepper");
    assert_allocates_nothing(|| {
        let mut pose = start;
        for k in 0..360 {
            pose.phi = f64::from(k) * 0.0175;
            pose = stepper.step(&pose, 10.0, 0.0).expect("steps").q;
        }
        let again = m.assemble_in(&pose, &modes).expect("assembles");
        std::hint::black_box((pose, again));
    });
}

#[test]
fn positions_only_steps_allocate_nothing() {
    // A stepper's positions-only steps, in closed form and by Newton's
    // inline path, and the assembly of a mechanism without closed forms.
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let mut stepper = m
        .stepper(&kinematics_core::Options::DEFAULT)
        .expect("a stepper");
    let n = DistanceFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let n_start = n
        .assemble(&DistanceFourBarCoords { phi: 0.0, th4: 1.5 })
        .expect("assembles");
    let mut n_stepper = n
        .stepper(&kinematics_core::Options::DEFAULT)
        .expect("a stepper");
    assert_allocates_nothing(|| {
        let (mut pose, mut n_pose) = (start, n_start);
        for k in 0..360 {
            let phi = f64::from(k) * 0.0175;
            pose.phi = phi;
            pose = stepper.pose(&pose).expect("assembles").q;
            n_pose.phi = phi;
            n_pose = n_stepper.pose(&n_pose).expect("assembles").q;
            n_pose = n.assemble(&n_pose).expect("assembles");
        }
        std::hint::black_box((pose, n_pose));
    });
}

#[test]
fn a_sweeps_samples_allocate_nothing_each() {
    // A sweep allocates its sample vector (once, with its capacity) and its
    // rate buffers; the number of allocations does not grow with the number
    // of samples, so the per-sample work allocates nothing.
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let count_for = |steps: usize| {
        let before = allocations();
        let s = m
            .sweep(FourBar::PHI, &start)
            .to(1.0)
            .steps(steps)
            .rate(10.0)
            .run();
        assert!(s.stop.is_none() && s.samples.len() == steps + 1);
        allocations() - before
    };
    let (few, many) = (count_for(10), count_for(1000));
    assert_eq!(
        few, many,
        "allocations grow with the samples: {few} for 11, {many} for 1001"
    );
    // Streamed, the samples allocate nothing either: only the sweep's own
    // buffers, made when it starts.
    let streamed = |steps: usize| {
        let before = allocations();
        let mut n = 0;
        for sample in m.sweep(FourBar::PHI, &start).to(1.0).steps(steps) {
            std::hint::black_box(sample.expect("no stop"));
            n += 1;
        }
        assert_eq!(n, steps + 1);
        allocations() - before
    };
    let (few, many) = (streamed(10), streamed(1000));
    assert_eq!(few, many, "streamed: {few} for 11, {many} for 1001");
    // A sweep of poses likewise.
    let poses = |steps: usize| {
        let before = allocations();
        let mut n = 0;
        for sample in m.sweep(FourBar::PHI, &start).to(1.0).steps(steps).poses() {
            std::hint::black_box(sample.expect("no stop"));
            n += 1;
        }
        assert_eq!(n, steps + 1);
        allocations() - before
    };
    let (few, many) = (poses(10), poses(1000));
    assert_eq!(few, many, "poses: {few} for 11, {many} for 1001");
}

/// The stepper of a model compiled at run time keeps its arrays: a turn of
/// steps (Newton–Raphson, Φ_u's factors and conditioning, q', q'', every
/// point and frame), into its `Motion` or as flat arrays, allocates nothing, for a planar loop, a spatial loop,
/// a six-bar and a serial arm with frames.
#[test]
fn a_run_time_stepper_allocates_nothing() {
    use kinematics_core::runtime::Model;
    use kinematics_core::Options;
    let cases: [(&str, Vec<f64>, Vec<f64>); 4] = [
        (
            "FourBar",
            FourBar::CRANK_ROCKER.parameter_values().to_vec(),
            vec![0.0, 1.0, 1.6],
        ),
        ("Rssr", vec![0.04, 0.12, 0.10, 0.11], vec![0.0, 1.0]),
        (
            "Watt",
            kinematics_examples::Watt::EXAMPLE
                .parameter_values()
                .to_vec(),
            (0..5)
                .map(|j| {
                    kinematics_core::Coordinates::get(&kinematics_examples::Watt::EXAMPLE_GUESS, j)
                        .expect("a coordinate")
                })
                .collect(),
        ),
        (
            "SixAxisArm",
            vec![0.4, 0.35, 0.3, 0.08, 0.1],
            vec![0.1, -0.4, 0.7, 0.2, -0.3, 0.5],
        ),
    ];
    for (name, values, start) in cases {
        let mut m = Model::compile(kinematics_examples::definition(name).expect("an example"))
            .expect("compiles");
        m.set_values(&values).expect("one value per parameter");
        let mut stepper = m.stepper(&Options::DEFAULT).expect("valid");
        let nd = m.drivers();
        let rates = vec![1.0; nd];
        let accels = vec![0.5; nd];
        let mut q = start;
        // A first step outside the count: the pose settles on its branch.
        let s = stepper.step(&q, &rates, &accels).expect("assembles");
        q.copy_from_slice(&s.q);
        assert_allocates_nothing(|| {
            for _ in 0..360 {
                for d in &mut q[..nd] {
                    *d += std::f64::consts::TAU / 360.0;
                }
                let s = stepper.step(&q, &rates, &accels).expect("steps");
                q.copy_from_slice(&s.q);
            }
            // The motion as flat arrays, likewise.
            for _ in 0..360 {
                for d in &mut q[..nd] {
                    *d += std::f64::consts::TAU / 360.0;
                }
                let s = stepper.step_flat(&q, &rates, &accels).expect("steps");
                q.copy_from_slice(s.q);
            }
        });
    }
}

/// A run-time model's sweeps go through the one sweep driver, their
/// samples read from the stepper: the number of allocations does not grow
/// with the number of samples, streamed as motions, as flat arrays or as
/// poses, for a model in closed form (its fused step) and for one solved
/// by Newton–Raphson (a slider in the curved guide x = h + k y², the
/// general path and its block solve).
#[test]
fn a_run_time_sweeps_samples_allocate_nothing_each() {
    use kinematics_core::runtime::Model;
    let curved = "struct CurvedSlider {
        params   { a, b, h, k }
        drivers  { phi }
        unknowns { th, y }
        loops    { polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y); }
    }";
    let four_bar = kinematics_examples::definition("FourBar").expect("an example");
    let cases: [(&str, Vec<f64>, Vec<f64>); 2] = [
        (
            four_bar,
            FourBar::CRANK_ROCKER.parameter_values().to_vec(),
            vec![0.0, 1.0, 1.6],
        ),
        (curved, vec![0.05, 0.2, 0.05, 2.0], vec![0.0, 1.2, 0.19]),
    ];
    for (text, values, start) in cases {
        let mut m = Model::compile(text).expect("compiles");
        m.set_values(&values).expect("one value per parameter");
        let sweep = |steps: usize| {
            m.sweep("phi", &start)
                .expect("a driver")
                .to(1.0)
                .steps(steps)
                .rate(10.0)
        };
        let count = |run: &dyn Fn(usize) -> usize, steps: usize| {
            let before = allocations();
            let n = run(steps);
            assert_eq!(n, steps + 1);
            allocations() - before
        };
        let motions = |steps: usize| {
            let mut n = 0usize;
            let end = sweep(steps).for_each(|_, s| {
                std::hint::black_box(s);
                n += 1;
            });
            assert!(end.stop.is_none(), "{:?}", end.stop);
            n
        };
        let flats = |steps: usize| {
            let mut n = 0usize;
            let end = sweep(steps).for_each_flat(|_, s| {
                std::hint::black_box(s);
                n += 1;
            });
            assert!(end.stop.is_none(), "{:?}", end.stop);
            n
        };
        let poses = |steps: usize| {
            let mut n = 0usize;
            let end = sweep(steps).for_each_pose(|_, q, p| {
                std::hint::black_box((q, p));
                n += 1;
            });
            assert!(end.stop.is_none(), "{:?}", end.stop);
            n
        };
        for (what, run) in [
            ("motions", &motions as &dyn Fn(usize) -> usize),
            ("flat", &flats),
            ("poses", &poses),
        ] {
            // Once first: the model's machine code is made on first use.
            run(10);
            let (few, many) = (count(run, 10), count(run, 1000));
            assert_eq!(few, many, "{what}: {few} for 11, {many} for 1001");
        }
    }
}
