//! Large mechanisms: chains of 20, 100 and 250 crank-rocker four-bars (40,
//! 200 and 500 unknowns; 2^20, 2^100 and 2^250 assemblies), written out by
//! `kinematics_tests::four_bar_chain` and compiled by `mechanism!` like any
//! other definition. Each loop is checked against the four-bar's own
//! closed form (law of cosines), computed here from the loop's input angle.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic, missing_docs)]

use core::f64::consts::{PI, TAU};

use kinematics_core::closed::{Mode, ModeSet};
use kinematics_core::Coordinates;

include!(concat!(env!("OUT_DIR"), "/chain20.rs"));
include!(concat!(env!("OUT_DIR"), "/chain100.rs"));
include!(concat!(env!("OUT_DIR"), "/chain250.rs"));

/// Crank 1, coupler 3, rocker 2.5, ground 3: 1 + 3 ≤ 2.5 + 3, the crank
/// shortest, so every loop is a crank-rocker.
const A: f64 = 1.0;
const B: f64 = 3.0;
const C: f64 = 2.5;
const D: f64 = 3.0;

/// x − y wrapped into (−π, π].
fn angle_diff(x: f64, y: f64) -> f64 {
    let d = (x - y).rem_euclid(TAU);
    if d > PI {
        d - TAU
    } else {
        d
    }
}

/// The two assemblies (coupler, rocker) of one four-bar with crank angle
/// `x`, by the law of cosines in triangle D–A'–C: with A' = a·e(x) the
/// crank pin and v = A' − D, the rocker makes the angle
/// γ = acos((c² + |v|² − b²) / (2 c |v|)) with v on either side, and the
/// coupler points from A' to the rocker pin.
fn four_bar(x: f64) -> [(f64, f64); 2] {
    let (px, py) = (A * x.cos(), A * x.sin());
    let (vx, vy) = (px - D, py);
    let r = vx.hypot(vy);
    let gamma = ((C * C + r * r - B * B) / (2.0 * C * r)).acos();
    let alpha = vy.atan2(vx);
    [alpha + gamma, alpha - gamma].map(|rocker| {
        let (cx, cy) = (D + C * rocker.cos(), C * rocker.sin());
        ((cy - py).atan2(cx - px), rocker)
    })
}

/// Checks every loop of a chain at one pose: the coupler and rocker
/// angles `(u_k, r_k)` with crank angles `inputs` (φ, r₁, …) match one of
/// the four-bar's two closed-form assemblies to `tol`, the same one for
/// every loop (all solved in the same mode); returns which.
fn check_chain(inputs: &[f64], solved: &[(f64, f64)], tol: f64) -> usize {
    let mut side = None;
    for (k, (&x, &(u, r))) in inputs.iter().zip(solved).enumerate() {
        let both = four_bar(x);
        let err = |i: usize| {
            angle_diff(u, both[i].0)
                .abs()
                .max(angle_diff(r, both[i].1).abs())
        };
        let i = usize::from(err(1) < err(0));
        assert!(
            err(i) < tol,
            "loop {}: ({u}, {r}) against {:?}: {:e}",
            k + 1,
            both[i],
            err(i)
        );
        assert_eq!(
            *side.get_or_insert(i),
            i,
            "loop {} in the other mode",
            k + 1
        );
    }
    side.unwrap_or(0)
}

/// The chain's loop angles (u_k, r_k) and crank angles (φ, r₁, …, r_{n−1})
/// of a pose, through the generated coordinate arrays.
macro_rules! chain_angles {
    ($q:expr) => {{
        let q: Vec<f64> = (0..).map_while(|j| $q.get(j)).collect();
        let solved: Vec<(f64, f64)> = q[1..].chunks(2).map(|p| (p[0], p[1])).collect();
        let mut inputs = vec![q[0]];
        inputs.extend(solved.iter().take(solved.len() - 1).map(|p| p.1));
        (inputs, solved)
    }};
}

/// Assembles a chain in every block's `Plus` mode with no guess, steps it
/// over a turn with the plain `step` and with a stepper, and checks every
/// loop against its closed form after each step, and the rates of the
/// first rockers against finite differences of the positions.
macro_rules! assemble_and_step {
    ($name:ident, $modes:ident, $n:expr) => {{
        let m = $name {
            a: A,
            b: B,
            c: C,
            d: D,
        };
        let modes = $modes::all_plus();
        let q0 = m
            .assemble_in(0.3, &modes)
            .expect("every loop is a crank-rocker");
        let (inputs, solved) = chain_angles!(q0);
        assert_eq!(solved.len(), $n);
        let side = check_chain(&inputs, &solved, 1e-12);
        let mut stepper = m
            .stepper(&kinematics_core::Options::DEFAULT)
            .expect("valid parameters");
        let (mut plain, mut carried) = (q0, q0);
        let n_steps = 72;
        for i in 1..=n_steps {
            let phi = 0.3 + TAU * f64::from(i) / f64::from(n_steps);
            let mut at = plain;
            at.phi = phi;
            let s = m.step(&at, 1.0, 0.0).expect("steps");
            let mut at = carried;
            at.phi = phi;
            let t = stepper.step(&at, 1.0, 0.0).expect("steps");
            for q in [s.q, t.q] {
                let (inputs, solved) = chain_angles!(q);
                assert_eq!(
                    check_chain(&inputs, &solved, 1e-12),
                    side,
                    "mode kept at step {i}"
                );
                let r = m.residual(&q);
                assert!(r.iter().all(|x| x.abs() < 1e-13), "residual {r:?}");
            }
            (plain, carried) = (s.q, t.q);
            if i == n_steps / 3 {
                // The first three rockers' rates by central differences
                // of the assembly (h = 1e-6: error ~h² r''' + ε/h); the
                // rates further down the chain are products of ever more
                // ratios below one, too small for the test to mean much.
                let h = 1e-6;
                for k in 1..=3 {
                    let j = 2 * k;
                    let at = |phi: f64| {
                        m.assemble_in(phi, &modes)
                            .expect("assembles")
                            .get(j)
                            .expect("a rocker")
                    };
                    let fd = (at(phi + h) - at(phi - h)) / (2.0 * h);
                    let rate = s.qd.get(j).expect("a rocker");
                    assert!(fd.abs() > 1e-3, "r{k}' = {fd} is not a test");
                    assert!(
                        (rate - fd).abs() < 1e-7 * (1.0 + fd.abs()),
                        "r{k}' = {rate}, finite differences {fd}"
                    );
                }
            }
        }
    }};
}

/// Runs `f` on a thread with the default test stack of 2 MiB (what a
/// debug build of a user's program gets on a spawned thread).
fn on_small_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .expect("spawns")
        .join()
        .expect("does not overflow its stack");
}

#[test]
fn a_chain_of_100_four_bars_assembles_and_steps_on_a_small_stack() {
    on_small_stack(|| assemble_and_step!(Chain100, Chain100Modes, 100));
}

#[test]
fn a_chain_of_250_four_bars_assembles_and_steps() {
    on_small_stack(|| assemble_and_step!(Chain250, Chain250Modes, 250));
}

#[test]
fn the_assemblies_of_a_20_block_chain_are_yielded_lazily() {
    let m = Chain20 {
        a: A,
        b: B,
        c: C,
        d: D,
    };
    assert_eq!(<Chain20Modes as ModeSet>::BLOCKS, 20);
    assert_eq!(m.assemble_all(0.3).size_hint(), (1 << 20, Some(1 << 20)));
    // Combination i has block j in `Minus` where bit j of i is set: these
    // from the middle of the 2^20, named block by block.
    let named = [
        (
            (1 << 19) + (1 << 3) + 1,
            Chain20Modes {
                u1_r1: Mode::Minus,
                u4_r4: Mode::Minus,
                u20_r20: Mode::Minus,
                ..Chain20Modes::default()
            },
        ),
        (
            (1 << 19) + (1 << 3) + 2,
            Chain20Modes {
                u2_r2: Mode::Minus,
                u4_r4: Mode::Minus,
                u20_r20: Mode::Minus,
                ..Chain20Modes::default()
            },
        ),
        (
            (1 << 12) - 1,
            Chain20Modes {
                u1_r1: Mode::Minus,
                u2_r2: Mode::Minus,
                u3_r3: Mode::Minus,
                u4_r4: Mode::Minus,
                u5_r5: Mode::Minus,
                u6_r6: Mode::Minus,
                u7_r7: Mode::Minus,
                u8_r8: Mode::Minus,
                u9_r9: Mode::Minus,
                u10_r10: Mode::Minus,
                u11_r11: Mode::Minus,
                u12_r12: Mode::Minus,
                ..Chain20Modes::default()
            },
        ),
    ];
    for (index, modes) in named {
        let mut all = m.assemble_all(0.3);
        let (got, pose) = all.nth(index).expect("fewer than 2^20");
        assert_eq!(got, modes);
        let pose = pose.expect("every combination assembles");
        assert_eq!(pose, m.assemble_in(0.3, &modes).expect("assembles"));
        assert_eq!(all.size_hint().0, (1 << 20) - index - 1);
        // The loops in `Minus` are on the other side of their closed form
        // from those in `Plus`.
        let (inputs, solved) = chain_angles!(pose);
        let plus = check_chain(&inputs[..1], &solved[..1], 1e-12);
        for (j, (x, &(u, r))) in inputs.iter().zip(&solved).enumerate() {
            let both = four_bar(*x);
            let same = usize::from(modes.mode(j) == modes.mode(0));
            let i = if same == 1 { plus } else { 1 - plus };
            assert!(
                angle_diff(u, both[i].0).abs() < 1e-12 && angle_diff(r, both[i].1).abs() < 1e-12,
                "loop {} of combination {index}",
                j + 1
            );
        }
        // The next one follows without skipping.
        let (next, _) = all.next().expect("not the last");
        assert_eq!(Chain20Modes::all().nth(index + 1).expect("in range"), next);
    }
    // The last, and nothing after it.
    let mut all = Chain20Modes::all();
    let last = all.nth((1 << 20) - 1).expect("the last");
    assert!((0..20).all(|j| last.mode(j) == Mode::Minus));
    assert_eq!(all.next(), None);
    assert_eq!(Chain20Modes::all().nth(1 << 20), None);
}
