//! The positions-only path: a stepper's `pose`, sweeps of poses, and
//! `assemble` of a mechanism solved by Newton–Raphson, against the full
//! step and against the four-bar's geometry.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use std::f64::consts::{PI, TAU};

use kinematics_core::sweep::{PoseSample, Sample, StopReason, SweepBuilder};
use kinematics_core::{mechanism, Coordinates, Kind, Mechanism, MotionState, Options};
use kinematics_examples::{FourBar, Strider};
use kinematics_tests::{
    non_grashof_four_bar, DistanceFourBar, DistanceFourBarCoords, SlotSixBar, SlotSixBarModes,
};

/// The difference of two values of coordinate `j`, angles modulo 2π.
fn diff<M: Mechanism>(j: usize, a: f64, b: f64) -> f64 {
    let d = a - b;
    if M::COORDINATES[j].kind == Kind::Angle {
        (d + PI).rem_euclid(TAU) - PI
    } else {
        d
    }
}

mechanism! {
    /// A slider-crank whose slider runs in the curved guide x = h + k y²
    /// (no closed form: Newton–Raphson on the whole system), with a point P
    /// on its rod at p from the crank pin, β off the rod's line.
    pub struct CurvedSlider {
        params {
            /// Crank.
            a,
            /// Rod.
            b,
            /// Vertex of the guide.
            h,
            /// Curvature of the guide.
            k,
            /// Distance of P from the crank pin.
            p,
            /// Angle of P off the rod's line.
            beta
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns { th, y }
        points {
            B = polar(a, phi);
            S = vec2(h + k * y * y, y);
            P = B + polar(p, th + beta);
        }
        loops { B + polar(b, th) == S; }
    }
}

const CURVED: CurvedSlider = CurvedSlider {
    a: 0.05,
    b: 0.2,
    h: 0.05,
    k: 2.0,
    p: 0.12,
    beta: 0.3,
};

/// The points of a pose against the mechanism's own evaluation of them at
/// its coordinates (sines and cosines called afresh), to `tol`.
fn same_points(a: &[f64], b: &[f64], tol: f64) {
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= tol, "{a:?} against {b:?}");
    }
}

/// A sweep of poses and the full sweep of the same range: the same
/// samples, poses equal to `tol`, the same diagnostics, the same end;
/// `points` checks each pose's points.
fn poses_match_the_full_sweep<M: Mechanism>(
    m: &M,
    driver: kinematics_core::sweep::Driver<M, kinematics_core::sweep::Angle>,
    start: &M::Coords,
    tol: f64,
    points: impl Fn(&PoseSample<M>),
) -> usize {
    let full: Vec<Result<Sample<M>, _>> = SweepBuilder::new(m, driver, start)
        .turn()
        .steps(720)
        .into_iter()
        .collect();
    let poses: Vec<Result<PoseSample<M>, _>> = SweepBuilder::new(m, driver, start)
        .turn()
        .steps(720)
        .poses()
        .collect();
    assert_eq!(full.len(), poses.len());
    for (f, p) in full.iter().zip(&poses) {
        let (f, p) = (f.as_ref().expect("no stop"), p.as_ref().expect("no stop"));
        assert_eq!(f.at, p.at);
        for j in 0..M::DRIVERS + M::UNKNOWNS {
            let (a, b) = (f.motion.q().get(j).expect("q"), p.pose.q.get(j).expect("q"));
            assert!(
                diff::<M>(j, a, b).abs() <= tol,
                "at {}: coordinate {j}: {a} against {b}",
                f.at
            );
        }
        assert_eq!(f.motion.det_sign(), p.pose.det_sign);
        let (c, d) = (f.motion.conditioning(), p.pose.conditioning);
        assert!((c - d).abs() <= 1e-9 * c, "conditioning {c} against {d}");
        // The residual reported is that of the pose, to round-off (the
        // closed forms give sines and cosines without a call), and small:
        // both sweeps stop Newton–Raphson at a relative residual of 1e-12.
        let mut r = vec![0.0; M::EQUATIONS];
        m.residual_into(&p.pose.q, &mut r);
        let max = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(
            (max - p.pose.residual).abs() <= 1e-15,
            "{max} against {}",
            p.pose.residual
        );
        assert!(max < 1e-11, "residual {max}");
        points(p);
    }
    poses.len()
}

#[test]
fn a_sweep_of_poses_has_the_positions_of_the_full_sweep() {
    // Closed form (the four-bar's RRR dyad): the same arithmetic, so equal
    // to rounding.
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    assert_eq!(
        poses_match_the_full_sweep(&m, FourBar::PHI, &start, 1e-15, |s| {
            let (got, exact) = (s.pose.points, m.positions(&s.pose.q));
            for (a, b) in [(got.B, exact.B), (got.C, exact.C), (got.P, exact.P)] {
                same_points(a.as_slice(), b.as_slice(), 1e-15);
            }
        }),
        720
    );
    // Mixed: the dyad in closed form, the slot's block by Newton–Raphson
    // (stopped at a relative residual of 1e-12 in both).
    let m = SlotSixBar::EXAMPLE;
    let modes = SlotSixBarModes {
        th3_th4: kinematics_core::closed::Mode::Plus,
    };
    let start = m
        .assemble_in(&SlotSixBar::guess(0.0, 1.0), &modes)
        .expect("assembles");
    assert_eq!(
        poses_match_the_full_sweep(&m, SlotSixBar::PHI, &start, 1e-11, |_| {}),
        720
    );
    // Newton–Raphson on the whole system, the poses' predictor along the
    // secant, the full sweep's along the rates.
    let m = distance_four_bar();
    let start = m
        .assemble(&DistanceFourBarCoords { phi: 0.0, th4: 1.5 })
        .expect("assembles");
    assert_eq!(
        poses_match_the_full_sweep(&m, DistanceFourBar::PHI, &start, 1e-11, |_| {}),
        720
    );
    // With points: each from the solve's last sines and cosines, against
    // the points evaluated afresh at the pose, and the slider on its guide
    // at the rod's length from the crank pin.
    let m = CURVED;
    assert_eq!(CurvedSlider::BLOCKS[0].method, "Newton–Raphson");
    let start = m
        .assemble(&CurvedSliderCoords {
            phi: 0.0,
            th: 1.2,
            y: 0.19,
        })
        .expect("assembles");
    assert_eq!(
        poses_match_the_full_sweep(&m, CurvedSlider::PHI, &start, 1e-11, |s| {
            let (got, exact) = (s.pose.points, m.positions(&s.pose.q));
            for (a, b) in [(got.B, exact.B), (got.S, exact.S), (got.P, exact.P)] {
                same_points(a.as_slice(), b.as_slice(), 1e-15);
            }
            assert!((got.S.x - (m.h + m.k * got.S.y * got.S.y)).abs() < 1e-15);
            assert!(((got.S - got.B).norm() - m.b).abs() < 1e-12);
        }),
        720
    );
}

/// A crank-rocker written as a distance (no closed form: every block by
/// Newton–Raphson): crank a, coupler b, rocker c, ground d.
fn distance_four_bar() -> DistanceFourBar {
    DistanceFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    }
}

/// The rocker angle of the four-bar at crank angle φ on the branch `sign`,
/// from its geometry: with k = (a cos φ − d, a sin φ) = |k| e(α), the
/// coupler's length |k − c e(θ)| = b gives cos(θ − α) = (|k|² + c² − b²) /
/// (2 c |k|).
fn rocker_angle(a: f64, b: f64, c: f64, d: f64, phi: f64, sign: f64) -> f64 {
    let (kx, ky) = (a * phi.cos() - d, a * phi.sin());
    let k = kx.hypot(ky);
    ky.atan2(kx) + sign * ((k * k + c * c - b * b) / (2.0 * c * k)).acos()
}

#[test]
fn assemble_without_closed_forms_reaches_the_geometrys_angle() {
    // From guesses up to 0.6 rad away: Newton's common path inline, then
    // the polish to round-off.
    let m = distance_four_bar();
    for k in 0..36 {
        let phi = f64::from(k) * TAU / 36.0;
        let exact = rocker_angle(m.a, m.b, m.c, m.d, phi, -1.0);
        for off in [-0.6, -0.1, 0.0, 0.05, 0.4] {
            let pose = m
                .assemble(&DistanceFourBarCoords {
                    phi,
                    th4: exact + off,
                })
                .expect("assembles");
            let e = diff::<DistanceFourBar>(1, pose.th4, exact);
            // Polished past the tolerance to round-off: the reference's own
            // rounding (an arc cosine) is of the order of 1e-15.
            assert!(e.abs() < 1e-14, "φ = {phi}, guess {off} off: {e:e}");
        }
    }
}

#[test]
fn a_steppers_pose_is_its_steps_position() {
    // The rocker angle of the geometry on the branch of the start, through
    // a stepper's positions-only steps, and the same stepper's full steps.
    let m = distance_four_bar();
    let start = DistanceFourBarCoords { phi: 0.0, th4: 1.5 };
    let sign = if diff::<DistanceFourBar>(1, 1.5, rocker_angle(m.a, m.b, m.c, m.d, 0.0, 1.0)).abs()
        < 0.5
    {
        1.0
    } else {
        -1.0
    };
    let mut poses = m.stepper(&Options::DEFAULT).expect("a stepper");
    let mut steps = m.stepper(&Options::DEFAULT).expect("a stepper");
    let (mut p, mut s) = (start, start);
    for k in 0..=720 {
        let phi = f64::from(k) * TAU / 720.0;
        (p.phi, s.phi) = (phi, phi);
        let pose = poses.pose(&p).expect("assembles");
        let motion = steps.step(&s, 1.0, 0.0).expect("steps");
        let exact = rocker_angle(m.a, m.b, m.c, m.d, phi, sign);
        // Within the tolerance's bound, τ / conditioning (the step stops
        // at a relative residual of τ = 1e-12), with twice the margin.
        let bound = 2e-12 / pose.conditioning;
        let e = diff::<DistanceFourBar>(1, pose.q.th4, exact);
        assert!(e.abs() < bound, "φ = {phi}: {e:e} against {bound:e}");
        assert!(diff::<DistanceFourBar>(1, pose.q.th4, motion.q.th4).abs() < 1e-12);
        assert_eq!(pose.det_sign, motion.det_sign());
        (p, s) = (pose.q, motion.q);
    }
    // In closed form, with named modes: equal to the assembly in the
    // stepper's modes, which it keeps.
    let m = FourBar::CRANK_ROCKER;
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    let mut q = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    for k in 0..=360 {
        q.phi = f64::from(k).to_radians();
        let pose = stepper.pose(&q).expect("assembles");
        let modes = stepper.modes().expect("modes after a step");
        let exact = m.assemble_in(q.phi, &modes).expect("assembles");
        assert!(diff::<FourBar>(1, pose.q.th3, exact.th3).abs() < 1e-13);
        assert!(diff::<FourBar>(2, pose.q.th4, exact.th4).abs() < 1e-13);
        q = pose.q;
    }
}

#[test]
fn a_sweep_of_poses_stops_at_the_limit_position() {
    // The non-Grashof four-bar of the simulation tests.
    let (m, start, limit) = non_grashof_four_bar();
    let mut last = None;
    let mut stop = None;
    for item in m.sweep(FourBar::PHI, &start).turn().steps(3600).poses() {
        match item {
            Ok(s) => last = Some(s.at),
            Err(e) => stop = Some(e),
        }
    }
    let stop = stop.expect("the crank cannot turn fully");
    assert_eq!(
        stop.reason,
        StopReason::LimitPosition {
            unknowns: "th3, th4"
        }
    );
    assert!(
        (stop.at - limit).abs() < 1e-10,
        "{} against {limit}",
        stop.at
    );
    let last = last.expect("samples before the stop");
    assert!(last < limit && last > limit - 2.0 * TAU / 3600.0);
}

#[test]
fn a_sweep_of_poses_follows_pylinkages_strider() {
    // The feet of the Strider leg at steps 0, 900, 1800 and 2700 of a turn
    // of 3600 steps, as pylinkage 1.3's numba solver computes them
    // (circle intersections in Cartesian coordinates, each joint nearest
    // its previous position; `bench/python/strider_pylinkage.py` prints
    // them). Its crank angle accumulates a step at a time, ours is from +
    // k·step: hence the 1e-12.
    let pylinkage: [(usize, [f64; 4]); 4] = [
        (
            0,
            [
                -2.582_748_307_752_058,
                -2.568_626_542_988_897,
                2.587_458_703_155_555,
                -2.566_615_120_591_06,
            ],
        ),
        (
            900,
            [
                0.106_814_718_970_229,
                -2.231_316_900_850_534,
                3.120_724_762_250_088,
                -1.132_655_027_631_859,
            ],
        ),
        (
            1800,
            [
                0.075_641_046_441_651,
                0.498_177_639_426_165,
                -0.079_765_569_585_372,
                0.498_275_798_631_585,
            ],
        ),
        (
            2700,
            [
                -3.124_981_013_729_512,
                -1.136_152_133_743_815,
                -0.100_640_783_849_303,
                -2.236_378_479_867_035,
            ],
        ),
    ];
    let m = Strider::PYLINKAGE;
    assert!(Strider::BLOCKS.iter().all(|b| b.is_closed_form()));
    let th0 = -std::f64::consts::FRAC_PI_2 + TAU / 3600.0;
    let start = m
        .assemble(&Strider::pylinkage_guess(th0))
        .expect("assembles");
    let poses: Vec<_> = m
        .sweep(Strider::TH, &start)
        .from(th0)
        .to(th0 + TAU)
        .steps(3600)
        .poses()
        .collect();
    assert_eq!(poses.len(), 3601);
    for (k, [hx, hy, ix, iy]) in pylinkage {
        let p = poses[k].as_ref().expect("no stop").pose.points;
        for (got, want) in [(p.H.x, hx), (p.H.y, hy), (p.I.x, ix), (p.I.y, iy)] {
            assert!((got - want).abs() < 1e-12, "step {k}: {got} against {want}");
        }
    }
}
