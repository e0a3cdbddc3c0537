//! Models defined at run time against the same definitions compiled by
//! `mechanism!`: every definition of `examples/src/lib.rs`, read as text
//! from that file, compiles at run time; six of them (planar and spatial,
//! closed forms and Newton blocks, loops and a serial arm with frames) are
//! stepped both ways over a turn of their drivers, and agree in q, q', q'',
//! every point's r, v, a, every frame's motion and the conditioning; the
//! run-time stepper takes the same steps as the run-time `step`, exactly.

// Test code: a failed check should stop the test.
#![allow(clippy::expect_used, clippy::panic)]

use kinematics_core::runtime::{CompileError, Model};
use kinematics_core::{Coordinates, Error, Mechanism, MotionState, Options, PointState};
use kinematics_examples::{FourBar, RRtrRrt, Rssr, SixAxisArm, SliderCrank, Watt};

// The chains of four-bars of the large-model tests, as text.
#[path = "../src/four_bar_chain.rs"]
mod four_bar_chain;

/// The run-time model of the example `name` with the parameters of `g`,
/// the generated mechanism of the same definition (its parameters' names
/// checked against the model's).
fn model<const N: usize>(name: &str, names: [&str; N], values: [f64; N]) -> Model {
    let Some(text) = kinematics_examples::definition(name) else {
        panic!("no definition of {name} in the examples");
    };
    let mut m = Model::compile(text).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(m.parameters(), names);
    m.set_values(&values)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    m
}

/// |a − b| within 1e-13 of the larger magnitude (or of 1, near zero).
fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-13 * scale.max(a.abs()).max(b.abs())
}

/// Steps `m` (generated) and `r` (run time) from `start` through `steps`
/// driver increments of `delta` each (all drivers together), with the
/// drivers' rates and accelerations, and compares every output. Returns
/// the number of steps compared.
fn agree<M: Mechanism>(
    m: &M,
    r: &Model,
    start: M::Coords,
    delta: f64,
    steps: usize,
    rates: &[f64],
    accelerations: &[f64],
) -> usize {
    let n = M::DRIVERS + M::UNKNOWNS;
    let name = r.name().to_string();
    let mut g_start = start;
    let mut r_start: Vec<f64> = (0..n).map(|j| start.get(j).unwrap_or(f64::NAN)).collect();
    let options = Options::DEFAULT;
    let mut stepper = r.stepper(&options).expect("valid options and parameters");
    let mut flat = r.stepper(&options).expect("valid options and parameters");
    let d = r.point_dimension();
    for k in 0..steps {
        let g = m
            .step_slices(&g_start, rates, accelerations, &options)
            .unwrap_or_else(|e| panic!("{name}, step {k}, generated: {e}"));
        let s = r
            .step(&r_start, rates, accelerations)
            .unwrap_or_else(|e| panic!("{name}, step {k}, run time: {e}"));
        // The stepper, which keeps its arrays (and, for a model whose
        // blocks all have closed forms, steps through its fused code),
        // takes the same step to round-off: both are compared with the
        // generated step.
        let kept = stepper
            .step(&r_start, rates, accelerations)
            .unwrap_or_else(|e| panic!("{name}, step {k}, run-time stepper: {e}"))
            .clone();
        // The same step read from the flat arrays: the same numbers.
        let f = flat
            .step_flat(&r_start, rates, accelerations)
            .unwrap_or_else(|e| panic!("{name}, step {k}, run-time flat step: {e}"));
        assert_eq!(
            (f.q, f.qd, f.qdd),
            (&kept.q[..], &kept.qd[..], &kept.qdd[..])
        );
        let mut outputs: Vec<f64> = Vec::new();
        for p in &kept.points {
            outputs.extend(p.position.iter().chain(&p.velocity).chain(&p.acceleration));
        }
        for fr in &kept.frames {
            outputs.extend(fr.rotation.transpose().iter());
            outputs.extend(
                fr.angular_velocity
                    .iter()
                    .chain(fr.angular_acceleration.iter()),
            );
            outputs.extend(
                fr.origin
                    .iter()
                    .chain(fr.velocity.iter())
                    .chain(fr.acceleration.iter()),
            );
        }
        assert_eq!(f.outputs, &outputs[..], "{name} {k}: flat outputs");
        assert_eq!(
            f.outputs.len(),
            kept.points.len() * 3 * d + kept.frames.len() * 24
        );
        assert_eq!(
            (f.conditioning, f.det_sign, f.residual),
            (kept.conditioning, kept.det_sign, kept.residual)
        );
        for (how, s) in [("step", &s), ("stepper", &kept)] {
            let name = format!("{name} ({how})");
            // The length scale of the positions: the largest |q| and point
            // coordinate; rates and accelerations compared at their own.
            let qs = (0..n)
                .map(|j| g.q().get(j).unwrap_or(0.0).abs())
                .fold(1.0, f64::max);
            let qds = (0..n)
                .map(|j| g.qd().get(j).unwrap_or(0.0).abs())
                .fold(1.0, f64::max);
            let qdds = (0..n)
                .map(|j| g.qdd().get(j).unwrap_or(0.0).abs())
                .fold(1.0, f64::max);
            for j in 0..n {
                let (gq, gqd, gqdd) = (
                    g.q().get(j).unwrap_or(f64::NAN),
                    g.qd().get(j).unwrap_or(f64::NAN),
                    g.qdd().get(j).unwrap_or(f64::NAN),
                );
                assert!(
                    close(gq, s.q[j], qs),
                    "{name} {k}: q[{j}] {gq} against {}",
                    s.q[j]
                );
                assert!(
                    close(gqd, s.qd[j], qds),
                    "{name} {k}: q'[{j}] {gqd} against {}",
                    s.qd[j]
                );
                assert!(
                    close(gqdd, s.qdd[j], qdds),
                    "{name} {k}: q''[{j}] {gqdd} against {}",
                    s.qdd[j]
                );
            }
            assert_eq!(g.points().len(), s.points.len());
            // Each quantity at the scale of the mechanism's: the largest
            // position, velocity or acceleration component of any point.
            let largest = |f: fn(&<M::Motion as MotionState>::Point) -> &[f64]| {
                g.points()
                    .iter()
                    .flat_map(|p| f(p).iter().map(|v| v.abs()))
                    .fold(1e-3, f64::max)
            };
            let scales = [
                largest(|p| p.position()),
                largest(|p| p.velocity()),
                largest(|p| p.acceleration()),
            ];
            for (i, (gp, sp)) in g.points().iter().zip(&s.points).enumerate() {
                for (scale, (what, a, b)) in scales.into_iter().zip([
                    ("r", gp.position(), &sp.position),
                    ("v", gp.velocity(), &sp.velocity),
                    ("a", gp.acceleration(), &sp.acceleration),
                ]) {
                    for (x, y) in a.iter().zip(b) {
                        assert!(
                            close(*x, *y, scale),
                            "{name} {k}: point {i} {what}: {a:?} against {b:?}"
                        );
                    }
                }
            }
            assert_eq!(g.frames().len(), s.frames.len());
            for (i, (gf, sf)) in g.frames().iter().zip(&s.frames).enumerate() {
                let pairs = [
                    (gf.rotation.as_slice(), sf.rotation.as_slice()),
                    (gf.origin.as_slice(), sf.origin.as_slice()),
                    (gf.velocity.as_slice(), sf.velocity.as_slice()),
                    (gf.acceleration.as_slice(), sf.acceleration.as_slice()),
                    (
                        gf.angular_velocity.as_slice(),
                        sf.angular_velocity.as_slice(),
                    ),
                    (
                        gf.angular_acceleration.as_slice(),
                        sf.angular_acceleration.as_slice(),
                    ),
                ];
                for (a, b) in pairs {
                    let scale = a.iter().map(|v| v.abs()).fold(1e-3, f64::max);
                    for (x, y) in a.iter().zip(b) {
                        assert!(
                            close(*x, *y, scale),
                            "{name} {k}: frame {i}: {a:?} against {b:?}"
                        );
                    }
                }
            }
            // The same scaled diagonal blocks, inverted in another order.
            assert!(
                (g.conditioning() - s.conditioning).abs() <= 1e-12 * g.conditioning(),
                "{name} {k}: conditioning {} against {}",
                g.conditioning(),
                s.conditioning
            );
            assert_eq!(g.det_sign(), s.det_sign, "{name} {k}: branch");
            assert!(
                s.residual <= 64.0 * f64::EPSILON,
                "{name} {k}: |Φ|/S = {}",
                s.residual
            );
        }
        // The next start: this pose with the drivers advanced.
        g_start = *g.q();
        r_start.clone_from(&s.q);
        for (j, r) in r_start.iter_mut().enumerate().take(M::DRIVERS) {
            let d = g_start.get(j).unwrap_or(f64::NAN) + delta;
            g_start.set(j, d);
            *r = d;
        }
    }
    steps
}

#[test]
fn every_example_definition_compiles_at_run_time() {
    let defs = kinematics_examples::definitions();
    assert!(defs.len() >= 14, "{} definitions found", defs.len());
    for (name, text) in &defs {
        let m = Model::compile(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.name(), *name);
    }
}

#[test]
fn four_bar_agrees_with_the_generated_code_over_a_turn() {
    let g = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    let r = model("FourBar", FourBar::PARAMETERS, g.parameter_values());
    let start = g
        .assemble(&[0.0, 1.0, 1.6].into())
        .expect("the crank-rocker assembles");
    let steps = agree(
        &g,
        &r,
        start,
        std::f64::consts::TAU / 72.0,
        72,
        &[10.0],
        &[-3.0],
    );
    assert_eq!(steps, 72);
}

#[test]
fn slider_crank_textbook_and_spatial_models_agree() {
    let g = SliderCrank {
        a: 0.1,
        b: 0.3,
        e: 0.02,
    };
    let r = model("SliderCrank", SliderCrank::PARAMETERS, g.parameter_values());
    let start = g.assemble(&[0.0, 0.0, 0.4].into()).expect("assembles");
    agree(
        &g,
        &r,
        start,
        std::f64::consts::TAU / 72.0,
        72,
        &[5.0],
        &[1.0],
    );

    let g = RRtrRrt::EXAMPLE_4_2;
    let r = model("RRtrRrt", RRtrRrt::PARAMETERS, g.parameter_values());
    let start = g
        .assemble(&RRtrRrt::example_4_2_guess())
        .expect("assembles");
    agree(
        &g,
        &r,
        start,
        std::f64::consts::TAU / 72.0,
        72,
        &[5.0],
        &[0.0],
    );

    let g = Rssr {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let r = model("Rssr", Rssr::PARAMETERS, g.parameter_values());
    let start = g.assemble(&[0.0, 1.0].into()).expect("assembles");
    agree(
        &g,
        &r,
        start,
        std::f64::consts::TAU / 72.0,
        72,
        &[10.0],
        &[2.0],
    );
}

#[test]
fn six_bar_and_arm_agree() {
    let g = Watt::EXAMPLE;
    let r = model("Watt", Watt::PARAMETERS, g.parameter_values());
    let start = g.assemble(&Watt::EXAMPLE_GUESS).expect("assembles");
    agree(
        &g,
        &r,
        start,
        std::f64::consts::TAU / 72.0,
        72,
        &[10.0],
        &[0.0],
    );

    let g = SixAxisArm {
        d1: 0.4,
        a2: 0.35,
        a3: 0.3,
        d5: 0.08,
        d6: 0.1,
    };
    let r = model("SixAxisArm", SixAxisArm::PARAMETERS, g.parameter_values());
    let start = [0.1, -0.4, 0.7, 0.2, -0.3, 0.5].into();
    let rates = [0.5, -0.2, 0.3, 1.0, -0.7, 0.4];
    let accels = [0.1, 0.0, -0.2, 0.3, 0.05, -0.1];
    agree(&g, &r, start, 0.05, 40, &rates, &accels);
}

/// Bad definitions, bad parameters and bad arrays are errors that say what
/// is wrong, never panics or NaN.
#[test]
fn errors_are_reported_not_panics() {
    let text = "pub struct M { params { a } drivers { phi } unknowns { x } \
                loops { polar(a, phi) == vec2(x, b); } }";
    match Model::compile(text) {
        Err(CompileError::Definition(d)) => {
            assert_eq!(d.0.len(), 1, "{d}");
            assert!(d.0[0].message.contains("`b`"), "{d}");
            assert_eq!((d.0[0].line, d.0[0].column), (1, 93), "{d}");
        }
        other => panic!("expected a definition error, got {other:?}"),
    }
    let text = kinematics_examples::definition("SliderCrank").expect("an example");
    let mut m = Model::compile(text).expect("compiles");
    m.set("a", 0.1).expect("a parameter");
    m.set("b", 0.3).expect("a parameter");
    // `e` not set: NaN is refused by name.
    assert!(matches!(
        m.assemble(&[0.0, 0.0, 0.4]),
        Err(Error::NonFinite { name: "e", .. })
    ));
    assert!(matches!(
        m.set("f", 1.0),
        Err(Error::InvalidParameter { name: "f", .. })
    ));
    m.set("e", 0.0).expect("e is a parameter");
    assert!(matches!(
        m.assemble(&[0.0, 0.0]),
        Err(Error::WrongLength {
            expected: 3,
            found: 2,
            ..
        })
    ));
    assert!(matches!(
        m.analyze(&[0.0, 0.0, 0.4], &[], &[0.0]),
        Err(Error::WrongLength {
            expected: 1,
            found: 0,
            ..
        })
    ));
    // Past the crank's reach (a sin φ > b: the rod cannot reach the
    // guide): the closed form of (th, x) says so, with the discriminant
    // b² − a² sin² φ = 0.09 − 1 of the block's equation, as the generated
    // code does.
    m.set("a", 1.0).expect("a is a parameter");
    m.set("b", 0.3).expect("b is a parameter");
    match m.assemble(&[std::f64::consts::FRAC_PI_2, 0.0, 0.4]) {
        Err(Error::CannotAssemble {
            unknowns,
            discriminant,
            drivers,
        }) => {
            assert!(unknowns.starts_with("th"), "{unknowns}");
            assert!((discriminant + 0.91).abs() < 1e-12, "{discriminant}");
            assert_eq!(drivers, [("phi", std::f64::consts::FRAC_PI_2)]);
        }
        other => panic!("expected a limit position, got {other:?}"),
    }
}

/// A chain of 100 four-bars (200 unknowns) compiled from text at run time:
/// assembled from a guess 0.01 rad off the closed form of every loop,
/// each loop's coupler and rocker angles match the law of cosines
/// (computed here, loop by loop, from the loop before) to 1e-12, and the
/// pose closes to round-off.
#[test]
fn a_chain_of_a_hundred_four_bars_assembles_at_run_time() {
    let (a, b, c, d) = (1.0f64, 3.0f64, 2.5f64, 3.0f64);
    let source = four_bar_chain::source("Chain100", 100);
    let text = kinematics_examples::mechanism_bodies(&source)[0].0;
    let mut m = Model::compile(text).expect("the chain compiles");
    for (p, v) in [("a", a), ("b", b), ("c", c), ("d", d)] {
        m.set(p, v).expect("a parameter");
    }
    // One loop's (coupler, rocker) for crank angle x, elbow up: γ from
    // the triangle D–A'–C by the law of cosines.
    let four_bar = |x: f64| {
        let (px, py) = (a * x.cos(), a * x.sin());
        let (vx, vy) = (px - d, py);
        let r = vx.hypot(vy);
        let gamma = ((c * c + r * r - b * b) / (2.0 * c * r)).acos();
        let rocker = vy.atan2(vx) + gamma;
        let (cx, cy) = (d + c * rocker.cos(), c * rocker.sin());
        ((cy - py).atan2(cx - px), rocker)
    };
    let phi = 0.7;
    let mut exact = vec![phi];
    let mut input = phi;
    for _ in 0..100 {
        let (u, r) = four_bar(input);
        exact.extend([u, r]);
        input = r;
    }
    let guess: Vec<f64> = exact
        .iter()
        .enumerate()
        .map(|(j, v)| if j == 0 { *v } else { v + 0.01 })
        .collect();
    let q = m.assemble(&guess).expect("assembles");
    for (j, (x, e)) in q.iter().zip(&exact).enumerate() {
        let diff =
            (x - e + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        assert!(diff.abs() < 1e-12, "coordinate {j}: {x} against {e}");
    }
    let residual = m.residual(&q).expect("evaluates");
    assert!(residual.iter().all(|r| r.abs() < 1e-13), "{residual:?}");
}

/// A model is shared by threads: the same steps from four threads at once
/// give the same motions as from one.
#[test]
fn a_model_is_shared_by_threads() {
    fn shared<T: Send + Sync>(_: &T) {}
    let g = FourBar::CRANK_ROCKER;
    let r = model("FourBar", FourBar::PARAMETERS, g.parameter_values());
    shared(&r);
    let start = g
        .assemble(&[0.0, 1.0, 1.6].into())
        .expect("the crank-rocker assembles");
    let turn = |r: &Model| -> Vec<f64> {
        let mut q: Vec<f64> = (0..3).map(|j| start.get(j).unwrap_or(0.0)).collect();
        let mut out = Vec::new();
        for _ in 0..100 {
            let s = r.step(&q, &[10.0], &[0.0]).expect("a step");
            out.extend(s.qdd.iter().chain(&s.points[4].velocity));
            q = s.q;
            q[0] += 0.05;
        }
        out
    };
    let alone = turn(&r);
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..4).map(|_| scope.spawn(|| turn(&r))).collect();
        for h in handles {
            assert_eq!(h.join().expect("no panic"), alone);
        }
    });
}

/// Models whose every block has a closed form step through their fused
/// machine code; a model with a block solved by Newton–Raphson takes the
/// general path, and both close every step to round-off.
#[test]
fn closed_form_models_step_through_fused_code() {
    for name in ["FourBar", "Rssr", "Watt", "SixAxisArm", "SliderCrank"] {
        let text = kinematics_examples::definition(name).expect("an example");
        let mut m = Model::compile(text).expect("compiles");
        m.set_values(&vec![1.0; m.parameters().len()])
            .expect("one value each");
        let stepper = m.stepper(&Options::DEFAULT).expect("valid");
        assert!(stepper.is_fused(), "{name}");
    }
    // A slider in the parabolic guide x = h + k y², driven by a crank
    // through a rod: no closed form.
    let text = "struct Curved {
        params   { a, b, h, k }
        drivers  { phi }
        unknowns { th, y }
        loops    { polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y); }
    }";
    let mut m = Model::compile(text).expect("compiles");
    m.set_values(&[0.1, 0.3, 0.15, 0.5]).expect("four values");
    let mut stepper = m.stepper(&Options::DEFAULT).expect("valid");
    assert!(!stepper.is_fused());
    let mut q = vec![0.0, 1.2, 0.28];
    for k in 0..72 {
        q[0] = f64::from(k) * 5f64.to_radians();
        let s = stepper.step(&q, &[1.0], &[0.0]).expect("steps");
        let (phi, th, y) = (s.q[0], s.q[1], s.q[2]);
        let x = 0.15 + 0.5 * y * y;
        // Round-off of terms of about 0.4: 64 ε of the term scale.
        let (rx, ry) = (
            0.1 * phi.cos() + 0.3 * th.cos() - x,
            0.1 * phi.sin() + 0.3 * th.sin() - y,
        );
        assert!(rx.abs() < 1e-14 && ry.abs() < 1e-14, "{k}: {rx:e}, {ry:e}");
        q.copy_from_slice(&s.q);
    }
}

/// A driver that appears only inside an offset angle, polar(a, φ + β):
/// the fused step reads cos φ and sin φ (sin(φ + β) by the addition
/// theorem) where no stage of the general path does, and still gives the
/// slider's closed form x = a cos(φ + β) + √(b² − a² sin²(φ + β)) and its
/// rate x' = −a s ω − a² s c ω / √(b² − a² s²), with s, c of φ + β.
#[test]
fn a_driver_inside_an_offset_steps_through_fused_code() {
    let text = "struct OffsetCrank {
        params   { a, b, beta }
        drivers  { phi }
        unknowns { th, x }
        loops    { polar(a, phi + beta) + polar(b, th) == vec2(x, 0.0); }
    }";
    let mut m = Model::compile(text).expect("compiles");
    let (a, b, beta, omega) = (0.1, 0.3, 0.4, 2.0);
    m.set_values(&[a, b, beta]).expect("three values");
    let mut stepper = m.stepper(&Options::DEFAULT).expect("valid");
    assert!(stepper.is_fused());
    let mut q = vec![0.0, 0.0, 0.4];
    for k in 0..80 {
        q[0] = f64::from(k) * 0.1;
        let s = stepper.step(&q, &[omega], &[0.0]).expect("steps");
        let (sn, cs) = (q[0] + beta).sin_cos();
        let r = (b * b - a * a * sn * sn).sqrt();
        let x = a * cs + r;
        let xd = -a * sn * omega - a * a * sn * cs * omega / r;
        assert!((s.q[2] - x).abs() < 1e-15, "{k}: x {} against {x}", s.q[2]);
        assert!(
            (s.qd[2] - xd).abs() < 1e-14,
            "{k}: x' {} against {xd}",
            s.qd[2]
        );
        q.copy_from_slice(&s.q);
    }
}

/// A fused stepper checks its inputs as it copies them into its buffer
/// and reports a bad one as the general path does (by name, for the right
/// input), then steps on from its last pose as if the bad call had not
/// been made.
#[test]
fn a_fused_stepper_reports_bad_inputs_and_steps_on() {
    use kinematics_core::Input;
    let text = kinematics_examples::definition("SliderCrank").expect("an example");
    let mut m = Model::compile(text).expect("compiles");
    let (a, b) = (0.1, 0.3);
    m.set_values(&[a, b, 0.0]).expect("three values");
    let mut stepper = m.stepper(&Options::DEFAULT).expect("valid");
    assert!(stepper.is_fused());
    let mut q = vec![0.0, 0.0, 0.4];
    // x = a cos φ + √(b² − a² sin² φ), on the branch of x > 0.
    let slider = |phi: f64| a * phi.cos() + (b * b - a * a * phi.sin().powi(2)).sqrt();
    for k in 0..40 {
        q[0] = f64::from(k) * 0.05;
        match k % 10 {
            3 => assert!(matches!(
                stepper.step(&q, &[f64::NAN], &[0.0]),
                Err(Error::NonFinite {
                    input: Input::DriverRate,
                    name: "phi",
                    ..
                })
            )),
            5 => assert!(matches!(
                stepper.step(&q, &[1.0], &[f64::INFINITY]),
                Err(Error::NonFinite {
                    input: Input::DriverAcceleration,
                    name: "phi",
                    ..
                })
            )),
            7 => {
                let mut bad = q.clone();
                bad[1] = f64::NAN;
                assert!(matches!(
                    stepper.step(&bad, &[1.0], &[0.0]),
                    Err(Error::NonFinite {
                        input: Input::Guess,
                        name: "th",
                        ..
                    })
                ));
            }
            9 => assert!(matches!(
                stepper.step(&q[..2], &[1.0], &[0.0]),
                Err(Error::WrongLength {
                    expected: 3,
                    found: 2,
                    ..
                })
            )),
            _ => {}
        }
        let s = stepper.step(&q, &[1.0], &[0.0]).expect("steps");
        assert!((s.q[2] - slider(q[0])).abs() < 1e-15, "{k}");
        q.copy_from_slice(&s.q);
    }
}

/// Every assembly of a run-time model with no guess, for the four-bar
/// drawn 10^±100 times larger or smaller: the loop equations are
/// homogeneous in the lengths, so the angles are the unscaled design's
/// (the closed forms' squares would overflow or underflow as given).
#[test]
fn every_assembly_at_extreme_scales() {
    let text = kinematics_examples::definition("FourBar").expect("the four-bar");
    let at = |scale: f64| {
        let mut m = Model::compile(text).expect("compiles");
        m.set_values(&[
            0.04 * scale,
            0.12 * scale,
            0.10 * scale,
            0.11 * scale,
            0.06 * scale,
            0.5,
        ])
        .expect("values");
        m.assemble_all(&[0.5, 0.0, 0.0])
            .map(|(_, pose)| pose.expect("assembles"))
            .collect::<Vec<_>>()
    };
    let base = at(1.0);
    assert_eq!(base.len(), 2);
    for scale in [1e-100, 1e100] {
        for (got, want) in at(scale).iter().zip(&base) {
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() < 1e-14, "{scale}: {got:?} against {want:?}");
            }
        }
    }
}

/// A fused stepper's `pose` reports a bad pose as the general path does
/// (by name, for the right input, or its length), then poses on.
#[test]
fn a_fused_pose_reports_bad_inputs_and_poses_on() {
    use kinematics_core::Input;
    let text = kinematics_examples::definition("SliderCrank").expect("an example");
    let mut m = Model::compile(text).expect("compiles");
    let (a, b) = (0.1, 0.3);
    m.set_values(&[a, b, 0.0]).expect("three values");
    let mut stepper = m.stepper(&Options::DEFAULT).expect("valid");
    assert!(stepper.is_fused());
    let slider = |phi: f64| a * phi.cos() + (b * b - a * a * phi.sin().powi(2)).sqrt();
    let mut q = vec![0.0, 0.0, 0.4];
    for k in 0..40 {
        q[0] = f64::from(k) * 0.05;
        let mut bad = q.clone();
        match k % 10 {
            3 => {
                bad[0] = f64::NAN;
                assert!(matches!(
                    stepper.pose(&bad),
                    Err(Error::NonFinite {
                        input: Input::Driver,
                        name: "phi",
                        ..
                    })
                ));
            }
            7 => {
                bad[2] = f64::INFINITY;
                assert!(matches!(
                    stepper.pose(&bad),
                    Err(Error::NonFinite {
                        input: Input::Guess,
                        name: "x",
                        ..
                    })
                ));
            }
            9 => assert!(matches!(
                stepper.pose(&q[..2]),
                Err(Error::WrongLength {
                    expected: 3,
                    found: 2,
                    ..
                })
            )),
            _ => {}
        }
        let pose = stepper.pose(&q).expect("assembles");
        assert!((pose[2] - slider(q[0])).abs() < 1e-15, "{k}");
        q.copy_from_slice(pose);
    }
}
