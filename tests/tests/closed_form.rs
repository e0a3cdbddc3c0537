//! Closed-form assembly: which blocks are solved exactly, assembly with no
//! guess in both modes of each block, against Newton–Raphson on the same
//! equations written independently here from a good guess; modes kept by
//! the stepper over a turn.
#![allow(missing_docs, clippy::expect_used, clippy::panic)]

use kinematics_core::closed::Mode;
use kinematics_core::nalgebra::{DMatrix, DVector};
use kinematics_core::{mechanism, Coordinates, Error, Mechanism, MotionState};
use kinematics_tests::{SlotSixBar, SlotSixBarCoords, SlotSixBarModes};

mechanism! {
    pub struct FourBar {
        params { a, b, c, d, p, beta }
        drivers { phi }
        unknowns { th3, th4 }
        points { P = polar(a, phi) + polar(p, th3 + beta); }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    }
}

mechanism! {
    /// Offset slider-crank: θ from the vertical equation, then x.
    pub struct SliderCrank {
        params { a, b, e }
        drivers { phi }
        unknowns { th, x }
        loops { polar(a, phi) + polar(b, th) == vec2(x, e); }
    }
}

mechanism! {
    /// Inverted slider-crank: the slider s on the turning link θ (RTR).
    pub struct Inverted {
        params { a, d }
        drivers { phi }
        unknowns { th, s }
        loops { polar(a, phi) == vec2(d, 0.0) + polar(s, th); }
    }
}

mechanism! {
    /// RTR dyad with the slider's line offset h from the pivot.
    pub struct OffsetRtr {
        params { a, d, h }
        drivers { phi }
        unknowns { th, s }
        loops { polar(a, phi) == vec2(d, 0.0) + polar(s, th) + polar(h, th + 1.5707963267948966); }
    }
}

mechanism! {
    /// RRT dyad with an inclined slider line (circle–line).
    pub struct Rrt {
        params { a, b, e, gamma }
        drivers { phi }
        unknowns { th, x }
        loops { polar(a, phi) + polar(b, th) == vec2(0.0, e) + polar(x, gamma); }
    }
}

mechanism! {
    /// TRT dyad: two sliders on fixed lines (line–line).
    pub struct Trt {
        params { a, h, gamma }
        drivers { phi }
        unknowns { x, y }
        loops { polar(a, phi) + polar(x, gamma) == vec2(0.0, h) + y * vec2(0.6, 0.8); }
    }
}

mechanism! {
    /// Watt six-bar: two RRR dyads in series.
    pub struct Watt {
        params { a, b, c, d, e, f, g, gx, gy, al }
        drivers { phi }
        unknowns { th3, th4, th5, th6 }
        loops {
            polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4);
            vec2(d, 0.0) + polar(e, th4 + al) + polar(f, th5) == vec2(gx, gy) + polar(g, th6);
        }
    }
}

mechanism! {
    /// RSSR: the output angle from one distance equation.
    pub struct Rssr {
        params { a, b, c, d }
        drivers { phi }
        unknowns { psi }
        points { B = vec3(-d - c * cos(psi), c * sin(psi), 0.0); }
        constraints {
            dot(B - vec3(-a * cos(phi), 0.0, a * sin(phi)), B - vec3(-a * cos(phi), 0.0, a * sin(phi)))
                == b * b;
        }
    }
}

mechanism! {
    /// A slider-crank whose slider runs in a parabolic guide y = h + k x²
    /// (Newton–Raphson on (θ, x)), its connecting rod driving an RRR dyad
    /// to a rocker at (gx, gy) (closed form, after it).
    pub struct CurvedGuide {
        params { a, f, h, k, e, al, g, r, gx, gy }
        drivers { phi }
        unknowns { th, x, th5, th6 }
        loops {
            polar(a, phi) + polar(f, th) == vec2(x, h + k * x * x);
            polar(a, phi) + polar(e, th + al) + polar(g, th5) == vec2(gx, gy) + polar(r, th6);
        }
    }
}

/// Newton–Raphson on the mechanism's residual and Jacobian (the
/// generated Φ and Φ_u, not the closed forms), dense, from `guess`.
fn newton<M: Mechanism>(m: &M, guess: &M::Coords) -> M::Coords {
    let (nd, nu) = (M::DRIVERS, M::UNKNOWNS);
    let mut q = *guess;
    let (mut phi, mut jac) = (vec![0.0; nu], vec![0.0; nu * nu]);
    for _ in 0..50 {
        m.residual_into(&q, &mut phi);
        m.jacobian_into(&q, &mut jac);
        let a = DMatrix::from_row_slice(nu, nu, &jac);
        let dx = a
            .lu()
            .solve(&DVector::from_column_slice(&phi))
            .expect("regular Jacobian");
        for k in 0..nu {
            let u = q.get(nd + k).expect("unknown");
            q.set(nd + k, u - dx[k]);
        }
        if dx.amax() < 1e-15 {
            break;
        }
    }
    q
}

/// Checks every assembly at `drivers`: the blocks' methods are `methods`;
/// there are 2^k assemblies, all distinct, each equal to Newton–Raphson
/// from a guess 0.02 off it to 1e-12 relative, each reproduced by
/// `assemble` from that guess.
/// The assemblies of `assemble_all`, in the order of the modes.
fn results<M, C>(all: impl Iterator<Item = (M, Result<C, Error>)>) -> Vec<Result<C, Error>> {
    all.map(|(_, r)| r).collect()
}

fn check_all<M: Mechanism>(
    m: &M,
    blocks: &[kinematics_core::closed::Block],
    methods: &[&str],
    all: &[Result<M::Coords, kinematics_core::Error>],
    assemble: impl Fn(&M::Coords) -> M::Coords,
) {
    let found: Vec<&str> = blocks.iter().map(|b| b.method).collect();
    assert_eq!(found, methods);
    let modes = blocks.iter().filter(|b| b.modes).count();
    assert_eq!(all.len(), 1 << modes);
    let (nd, nu) = (M::DRIVERS, M::UNKNOWNS);
    let poses: Vec<M::Coords> = all
        .iter()
        .map(|r| *r.as_ref().expect("assembles in every mode"))
        .collect();
    for (i, pose) in poses.iter().enumerate() {
        let mut guess = *pose;
        for k in 0..nu {
            guess.set(nd + k, pose.get(nd + k).expect("unknown") + 0.02);
        }
        let reference = newton(m, &guess);
        let again = assemble(&guess);
        for k in nd..nd + nu {
            let (x, y, z) = (
                pose.get(k).expect("q"),
                reference.get(k).expect("q"),
                again.get(k).expect("q"),
            );
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(1.0),
                "mode {i}, coordinate {k}: {x} closed form, {y} Newton"
            );
            assert!((x - z).abs() <= 1e-12 * x.abs().max(1.0), "assemble");
        }
        for other in &poses[..i] {
            let gap = (nd..nd + nu)
                .map(|k| (pose.get(k).expect("q") - other.get(k).expect("q")).abs())
                .fold(0.0, f64::max);
            assert!(gap > 1e-3, "two modes give one pose");
        }
    }
}

#[test]
fn four_bar_both_modes() {
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    check_all(
        &m,
        FourBar::BLOCKS,
        &["closed form: RRR dyad (circle–circle)"],
        &results(m.assemble_all(0.7)),
        |g| m.assemble(g).expect("assembles"),
    );
    // The modes are the two sides of the line through the dyad's ends:
    // the open and the crossed four-bar, mirror images about the diagonal.
    let [plus, minus]: [FourBarCoords; 2] = results(m.assemble_all(0.7))
        .into_iter()
        .map(|r| r.expect("assembles"))
        .collect::<Vec<_>>()
        .try_into()
        .expect("two assemblies");
    let (bx, by) = (m.a * 0.7f64.cos(), m.a * 0.7f64.sin());
    let side = |q: &FourBarCoords| {
        let (cx, cy) = (bx + m.b * q.th3.cos(), by + m.b * q.th3.sin());
        (m.d - bx) * (cy - by) - (0.0 - by) * (cx - bx)
    };
    assert!(side(&plus) * side(&minus) < 0.0);
    assert_eq!(
        m.assemble_in(
            0.7,
            &FourBarModes {
                th3_th4: Mode::Minus
            }
        )
        .expect("assembles"),
        minus
    );
}

#[test]
fn slider_cranks_and_dyads_both_modes() {
    let m = SliderCrank {
        a: 0.1,
        b: 0.3,
        e: 0.02,
    };
    check_all(
        &m,
        SliderCrank::BLOCKS,
        &[
            "closed form: a cos θ + b sin θ + c = 0",
            "closed form: linear in one length",
        ],
        &results(m.assemble_all(0.4)),
        |g| m.assemble(g).expect("assembles"),
    );
    let m = Inverted { a: 0.1, d: 0.3 };
    check_all(
        &m,
        Inverted::BLOCKS,
        &["closed form: RTR dyad (slider on a turning link)"],
        &results(m.assemble_all(0.4)),
        |g| m.assemble(g).expect("assembles"),
    );
    let m = OffsetRtr {
        a: 0.1,
        d: 0.3,
        h: 0.03,
    };
    check_all(
        &m,
        OffsetRtr::BLOCKS,
        &["closed form: RTR dyad (slider on a turning link)"],
        &results(m.assemble_all(0.4)),
        |g| m.assemble(g).expect("assembles"),
    );
    let m = Rrt {
        a: 0.1,
        b: 0.3,
        e: 0.05,
        gamma: 0.3,
    };
    check_all(
        &m,
        Rrt::BLOCKS,
        &["closed form: RRT dyad (circle–line)"],
        &results(m.assemble_all(0.4)),
        |g| m.assemble(g).expect("assembles"),
    );
    let m = Trt {
        a: 0.1,
        h: 0.05,
        gamma: 0.3,
    };
    check_all(
        &m,
        Trt::BLOCKS,
        &["closed form: TRT dyad (line–line)"],
        &results(m.assemble_all(0.4)),
        |g| m.assemble(g).expect("assembles"),
    );
}

#[test]
fn watt_six_bar_four_assemblies() {
    let m = Watt {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        e: 0.03,
        f: 0.12,
        g: 0.10,
        gx: 0.18,
        gy: 0.08,
        al: 0.4,
    };
    check_all(
        &m,
        Watt::BLOCKS,
        &["closed form: RRR dyad (circle–circle)"; 2],
        &results(m.assemble_all(0.3)),
        |g| m.assemble(g).expect("assembles"),
    );
}

#[test]
fn rssr_both_modes() {
    let m = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.315,
    };
    check_all(
        &m,
        Rssr::BLOCKS,
        &["closed form: a cos θ + b sin θ + c = 0"],
        &results(m.assemble_all(0.3)),
        |g| m.assemble(g).expect("assembles"),
    );
}

#[test]
fn the_stepper_keeps_the_mode_over_a_turn() {
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    for mode in [Mode::Plus, Mode::Minus] {
        let modes = FourBarModes { th3_th4: mode };
        let mut pose = m.assemble_in(0.0, &modes).expect("assembles");
        let mut stepper = m
            .stepper(&kinematics_core::Options::DEFAULT)
            .expect("valid");
        assert_eq!(stepper.modes(), None);
        for k in 1..=360 {
            pose.phi = f64::from(k).to_radians();
            let motion = stepper.step(&pose, 10.0, 0.0).expect("steps");
            let exact = m.assemble_in(pose.phi, &modes).expect("assembles");
            let wrap = |x: f64| (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU);
            assert!((wrap(motion.q.th3) - wrap(exact.th3)).abs() < 1e-12);
            assert!((wrap(motion.q.th4) - wrap(exact.th4)).abs() < 1e-12);
            assert!(motion.conditioning() > 0.0);
            pose = motion.q;
        }
        assert_eq!(stepper.modes(), Some(modes));
        // Angles stay continuous over the turn (no jump of 2π).
        assert!((pose.phi - std::f64::consts::TAU).abs() < 1e-12);
    }
}

#[test]
fn mechanisms_without_closed_forms_say_so() {
    mechanism! {
        pub struct Ellipse {
            params { a, b, c, d }
            drivers { phi }
            unknowns { th3, th4 }
            loops { polar(a, phi) + vec2(2.0 * b * cos(th3), b * sin(th3)) == vec2(d, 0.0) + polar(c, th4); }
        }
    }
    assert_eq!(Ellipse::BLOCKS.len(), 1);
    assert_eq!(Ellipse::BLOCKS[0].method, "Newton–Raphson");
    assert!(!Ellipse::BLOCKS[0].is_closed_form());
    assert_eq!(Ellipse::BLOCKS[0].to_string(), "th3, th4: Newton–Raphson");
}

#[test]
fn the_carried_angles_do_not_drift() {
    // 10 000 steps of 0.01 rad (16 turns): each angle is the previous one
    // plus an arcsine series, refreshed by atan2 every 64 steps, and the
    // driver's sine and cosine the previous ones rotated by the increment,
    // refreshed every 16 steps. Against a fresh closed-form assembly at
    // every step, modulo 2π, and against the coupler point computed from
    // it (relative to the crank length).
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    let modes = FourBarModes {
        th3_th4: Mode::Plus,
    };
    let mut pose = m.assemble_in(0.0, &modes).expect("assembles");
    let mut stepper = m
        .stepper(&kinematics_core::Options::DEFAULT)
        .expect("valid");
    let mut worst = 0.0f64;
    for k in 1..=10_000 {
        pose.phi = f64::from(k) * 0.01;
        let motion = stepper.step(&pose, 10.0, 0.0).expect("steps");
        let exact = m.assemble_in(pose.phi, &modes).expect("assembles");
        for (x, y) in [(motion.q.th3, exact.th3), (motion.q.th4, exact.th4)] {
            let d = (x - y).rem_euclid(std::f64::consts::TAU);
            let d = d.min(std::f64::consts::TAU - d);
            worst = worst.max(d / x.abs().max(1.0));
        }
        let [p] = m.point_positions(&exact);
        worst = worst.max((motion.point_p().position - p).amax() / m.a);
        // Continuous: no jump of 2π between steps.
        assert!((motion.q.th3 - pose.th3).abs() < 0.1 && (motion.q.th4 - pose.th4).abs() < 0.1);
        pose = motion.q;
    }
    eprintln!("largest difference from a fresh closed form: {worst:e}");
    assert!(worst <= 1e-14, "drift {worst:e}");
    assert!(pose.phi > 99.0);
}

#[test]
fn mixed_mechanisms_solve_their_closed_form_blocks_exactly() {
    let m = SlotSixBar::EXAMPLE;
    // The pin's side of the slot follows the four-bar's mode: a guess for
    // the Newton block per mode.
    let all: Vec<_> = SlotSixBarModes::all()
        .map(|modes| m.assemble_in(&SlotSixBar::guess(0.7, modes.th3_th4.sign()), &modes))
        .collect();
    check_all(
        &m,
        SlotSixBar::BLOCKS,
        &["closed form: RRR dyad (circle–circle)", "Newton–Raphson"],
        &all,
        |g| m.assemble(g).expect("assembles"),
    );
    assert!(SlotSixBar::BLOCKS[0].is_closed_form() && !SlotSixBar::BLOCKS[1].is_closed_form());
    assert_eq!(SlotSixBar::BLOCKS[1].to_string(), "th5, y: Newton–Raphson");
    // The closed-form block is the four-bar's, in the same modes.
    let four_bar = FourBar {
        a: m.a,
        b: m.b,
        c: m.c,
        d: m.d,
        p: 0.0,
        beta: 0.0,
    };
    for (modes, pose) in SlotSixBarModes::all().zip(&all) {
        let pose = pose.as_ref().expect("assembles");
        let alone = four_bar
            .assemble_in(
                0.7,
                &FourBarModes {
                    th3_th4: modes.th3_th4,
                },
            )
            .expect("assembles");
        assert!((pose.th3 - alone.th3).abs() < 1e-15 && (pose.th4 - alone.th4).abs() < 1e-15);
        // The pin at distance f from the rocker's end, on the parabola.
        let q = (m.d + m.e * pose.th4.cos(), m.e * pose.th4.sin());
        let pin = (m.h + m.k * pose.y * pose.y, pose.y);
        assert!(((pin.0 - q.0).hypot(pin.1 - q.1) - m.f).abs() < 1e-15);
        assert!(pose.y * modes.th3_th4.sign() > 0.0);
    }

    // The Newton block first, the closed form after it.
    let m = CurvedGuide {
        a: 0.04,
        f: 0.12,
        h: 0.05,
        k: 3.0,
        e: 0.06,
        al: 0.8,
        g: 0.10,
        r: 0.08,
        gx: 0.02,
        gy: 0.14,
    };
    let start = CurvedGuideCoords {
        phi: 0.3,
        th: 0.8,
        x: 0.12,
        th5: 0.0,
        th6: 0.0,
    };
    check_all(
        &m,
        CurvedGuide::BLOCKS,
        &["Newton–Raphson", "closed form: RRR dyad (circle–circle)"],
        &results(m.assemble_all(&start)),
        |g| m.assemble(g).expect("assembles"),
    );
}

#[test]
fn a_newton_block_that_cannot_close_is_an_error_in_the_modes_asked_for() {
    // A link f too short to reach the slot: no assembly in either mode,
    // and Newton–Raphson on the whole system is not asked to find one in
    // another.
    let m = SlotSixBar {
        f: 0.02,
        ..SlotSixBar::EXAMPLE
    };
    for (_, r) in m.assemble_all(&SlotSixBar::guess(0.7, 1.0)) {
        // The error names the slot's loop, where Newton–Raphson stopped.
        let e = r.expect_err("the pin cannot reach the slot");
        let kinematics_core::Error::NotConverged { equation, .. } = &e else {
            panic!("{e:?}");
        };
        assert!(equation.contains("polar(f, th5)"), "{e}");
    }
}

#[test]
fn a_mixed_stepper_keeps_its_modes_and_matches_finite_differences() {
    let m = SlotSixBar::EXAMPLE;
    let (rate, acc) = (3.0, 0.0);
    for mode in [Mode::Plus, Mode::Minus] {
        let modes = SlotSixBarModes { th3_th4: mode };
        let s = mode.sign();
        let exact = |phi: f64| {
            m.assemble_in(&SlotSixBar::guess(phi, s), &modes)
                .expect("assembles")
        };
        let mut pose = exact(0.0);
        let mut stepper = m
            .stepper(&kinematics_core::Options::DEFAULT)
            .expect("valid");
        for k in 1..=72 {
            pose.phi = f64::from(k * 5).to_radians();
            let motion = stepper.step(&pose, rate, acc).expect("steps");
            let (h1, h2) = (1e-6, 1e-4);
            let (p, m1, p1) = (exact(pose.phi), exact(pose.phi - h1), exact(pose.phi + h1));
            let (m2, p2) = (exact(pose.phi - h2), exact(pose.phi + h2));
            let fields = |q: &SlotSixBarCoords| [q.th3, q.th4, q.th5, q.y];
            let (q, qd, qdd) = (fields(&motion.q), fields(&motion.qd), fields(&motion.qdd));
            for j in 0..4 {
                let at = |c: &SlotSixBarCoords| fields(c)[j];
                // The Newton block stops once its relative residual is
                // below 1e-12 (Options::DEFAULT), from another guess than
                // the fresh assembly's.
                assert!(
                    (q[j] - at(&p)).abs() < 1e-11,
                    "position {j} at step {k}: {} {}",
                    q[j],
                    at(&p)
                );
                let v = (at(&p1) - at(&m1)) / (2.0 * h1) * rate;
                assert!(
                    (qd[j] - v).abs() < 1e-7 * v.abs().max(1.0),
                    "velocity {j}: {} {v}",
                    qd[j]
                );
                let a = (at(&p2) - 2.0 * at(&p) + at(&m2)) / (h2 * h2) * rate * rate;
                assert!(
                    (qdd[j] - a).abs() < 1e-5 * a.abs().max(1.0),
                    "acceleration {j}: {} {a}",
                    qdd[j]
                );
            }
            pose = motion.q;
        }
        assert_eq!(stepper.modes(), Some(modes));
        // Small steps, over which the sines and cosines of the Newton
        // block's angle are carried from step to step and iterate to
        // iterate: against a fresh assembly polished to round-off by the
        // dense Newton–Raphson above, at every step. The stepper's Newton
        // block stops below a relative residual of 1e-12, a few 1e-12 in
        // the unknowns here.
        let mut worst = 0.0f64;
        for k in 1..=2000 {
            pose.phi = f64::from(k) * 0.01;
            let motion = stepper.step(&pose, rate, acc).expect("steps");
            let fresh = newton(&m, &exact(pose.phi));
            let wrap = |x: f64| {
                let d = x.rem_euclid(std::f64::consts::TAU);
                d.min(std::f64::consts::TAU - d)
            };
            worst = worst
                .max(wrap(motion.q.th5 - fresh.th5))
                .max(wrap(motion.q.th4 - fresh.th4))
                .max((motion.q.y - fresh.y).abs());
            pose = motion.q;
        }
        eprintln!("largest difference from a fresh assembly (rad, m): {worst:e}");
        assert!(worst <= 1e-11, "drift {worst:e}");
    }
}

#[test]
fn a_mixed_sweep_stops_at_the_limit_of_its_closed_form_block() {
    // The four-bar block of the slot mechanism, not Grashof: d + a = 0.16 >
    // b + c = 0.14, so the crank stops where coupler and rocker are in
    // line, cos φ = (a² + d² − (b + c)²)/(2ad); the slot's Newton block
    // follows the rocker up to there.
    let m = SlotSixBar {
        a: 0.05,
        b: 0.08,
        c: 0.06,
        d: 0.11,
        ..SlotSixBar::EXAMPLE
    };
    let limit = ((m.a * m.a + m.d * m.d - (m.b + m.c).powi(2)) / (2.0 * m.a * m.d)).acos();
    let guess = SlotSixBarCoords {
        th3: 0.5,
        th4: 1.5,
        ..SlotSixBar::guess(0.0, 1.0)
    };
    let start = m.assemble(&guess).expect("assembles");
    let s = m.sweep(SlotSixBar::PHI, &start).turn().steps(3600).run();
    let stop = s.stop.as_ref().expect("the crank cannot turn fully");
    assert_eq!(
        stop.reason,
        kinematics_core::sweep::StopReason::LimitPosition {
            unknowns: "th3, th4"
        }
    );
    assert!(
        (stop.at - limit).abs() < 1e-10,
        "{} against {limit}",
        stop.at
    );
    let last = s.samples.last().expect("samples before the stop");
    assert!(last.at < limit && last.at > limit - 2.0 * std::f64::consts::TAU / 3600.0);
}

#[test]
fn a_newton_block_after_blocks_solved_out_of_declaration_order() {
    // ψ is declared first but solved after the four-bar's dyad (its
    // equation involves θ4), and the slot's Newton block (whose vertex
    // moves with cos ψ) after both: the block is handed the cosines and
    // sines of the angles solved before it by name, whatever their order.
    mechanism! {
        pub struct Reordered {
            params { a, b, c, d, e, f, h, k }
            drivers { phi }
            unknowns { psi, th3, th4, th5, y }
            loops {
                polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4);
                vec2(d, 0.0) + polar(e, th4) + polar(f, th5)
                    == vec2(h + 0.01 * cos(psi) + k * y * y, y);
            }
            constraints { cos(psi) == 0.5 * cos(th4); }
        }
    }
    let names: Vec<String> = Reordered::BLOCKS.iter().map(ToString::to_string).collect();
    assert_eq!(
        names,
        [
            "th3, th4: closed form: RRR dyad (circle–circle)",
            "psi: closed form: a cos θ + b sin θ + c = 0",
            "th5, y: Newton–Raphson"
        ]
    );
    let SlotSixBar {
        a,
        b,
        c,
        d,
        e,
        f,
        h,
        k,
    } = SlotSixBar::EXAMPLE;
    let m = Reordered {
        a,
        b,
        c,
        d,
        e,
        f,
        h,
        k,
    };
    let modes = ReorderedModes {
        th3_th4: Mode::Plus,
        psi: Mode::Plus,
    };
    let mut pose = ReorderedCoords {
        phi: 0.0,
        psi: 0.0,
        th3: 0.0,
        th4: 0.0,
        th5: 0.6,
        y: 0.13,
    };
    pose = m.assemble_in(&pose, &modes).expect("assembles");
    let mut stepper = m
        .stepper(&kinematics_core::Options::DEFAULT)
        .expect("valid");
    for step in 1..=36 {
        pose.phi = f64::from(step * 10).to_radians();
        let q = stepper.step(&pose, 1.0, 0.0).expect("steps").q;
        // The dyad as the four-bar's, ψ and the pin from their equations.
        let alone = FourBar {
            a,
            b,
            c,
            d,
            p: 0.0,
            beta: 0.0,
        }
        .assemble_in(
            pose.phi,
            &FourBarModes {
                th3_th4: Mode::Plus,
            },
        )
        .expect("assembles");
        assert!((q.th3 - alone.th3).abs() < 1e-12 && (q.th4 - alone.th4).abs() < 1e-12);
        assert!((q.psi.cos() - 0.5 * q.th4.cos()).abs() < 1e-15);
        // (The Newton block stops below 1e-12 of its terms' size, 0.6 m.)
        let x = h + 0.01 * q.psi.cos() + k * q.y * q.y;
        assert!((d + e * q.th4.cos() + f * q.th5.cos() - x).abs() < 1e-12);
        assert!((e * q.th4.sin() + f * q.th5.sin() - q.y).abs() < 1e-12);
        pose = q;
    }
    // Had the block been handed another angle's cosine and sine, every
    // step would have failed the residual check and left the closed-form
    // path, forgetting the modes.
    assert_eq!(stepper.modes(), Some(modes));
}
