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

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};
use std::hint::black_box;

use kinematics_core::mechanism;

mechanism! {
    /// The Strider leg (diywalkers.com), with the joints of pylinkage's
    /// example: the frame A, B, B′ (B, B′ at `tri` from A, `ape` either
    /// side of the vertical), the crank A–C of unit length, the knees D
    /// and E (a femur from B′ and B, a long rocker arm from C), F and G
    /// fixed to the rocker arms (a short arm at `phi` from the long one),
    /// the feet H and I (a tibia from D and E, a foot link from F and G).
    pub struct Strider {
        params {
            /// Distance of B and B′ from A.
            tri,
            /// Angle of AB and AB′ from the vertical.
            ape,
            /// B′D and BE.
            femur,
            /// CD and CE.
            rocker_l,
            /// CF and CG.
            rocker_s,
            /// Angle of CF from CE (of CG from CD, the other way).
            phi,
            /// DH and EI.
            tibia,
            /// FH and GI.
            foot
        }
        drivers {
            /// Crank angle.
            th
        }
        unknowns { d1, d2, e1, e2, h1, h2, i1, i2 }
        points {
            C = polar(1.0, th);
            D = C + polar(rocker_l, d2);
            E = C + polar(rocker_l, e2);
            F = C + polar(rocker_s, e2 - phi);
            G = C + polar(rocker_s, d2 + phi);
            H = D + polar(tibia, h1);
            I = E + polar(tibia, i1);
        }
        loops {
            polar(tri, 0.5 * pi + ape) + polar(femur, d1) == C + polar(rocker_l, d2);
            polar(tri, 0.5 * pi - ape) + polar(femur, e1) == C + polar(rocker_l, e2);
            D + polar(tibia, h1) == F + polar(foot, h2);
            E + polar(tibia, i1) == G + polar(foot, i2);
        }
    }
}

const STEPS: usize = 3600;

/// The dimensions of pylinkage's example.
const LEG: Strider = Strider {
    tri: 2.0,
    ape: FRAC_PI_4,
    femur: 1.8,
    rocker_l: 2.6,
    rocker_s: 1.4,
    phi: PI + 0.2,
    tibia: 2.5,
    foot: 1.8,
};

/// The angle of the segment from p to q.
fn angle(p: (f64, f64), q: (f64, f64)) -> f64 {
    (q.1 - p.1).atan2(q.0 - p.0)
}

/// The first pose of the Python script's turn: its starting positions
/// (the crank pin below A, the knees outside, the feet below) as a guess,
/// which picks the assembly modes, at the crank angle of its first step.
fn start() -> StriderCoords {
    let (c, d, e) = ((0.0, -1.0), (-2.25, 0.0), (2.25, 0.0));
    let (f, g, h, i) = ((-1.4, -1.2), (1.4, -1.2), (-2.7, -2.7), (2.7, -2.7));
    let b = (2.0 * FRAC_PI_4.cos(), 2.0 * FRAC_PI_4.sin());
    let bp = (-b.0, b.1);
    let guess = StriderCoords {
        th: -FRAC_PI_2 + TAU / STEPS as f64,
        d1: angle(bp, d),
        d2: angle(c, d),
        e1: angle(b, e),
        e2: angle(c, e),
        h1: angle(d, h),
        h2: angle(f, h),
        i1: angle(e, i),
        i2: angle(g, i),
    };
    LEG.assemble(&guess).expect("assembles")
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

/// CPU time of the calling thread, in nanoseconds.
#[allow(unsafe_code)]
fn thread_cpu_ns() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to write into.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &raw mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    t.tv_sec as f64 * 1e9 + t.tv_nsec as f64
}

fn main() {
    let turns: usize = std::env::args()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(10);
    let m = black_box(LEG);
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
