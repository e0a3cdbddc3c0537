//! Loads of the time (`time` in `loads { … }`) against closed forms
//! written here, through a generated mechanism and a run-time model of
//! the same text: a flywheel under a torque that grows with the time,
//! k t, turns at ω = k t² / (2 J); a block on a line pushed by
//! F₀ sin(Ω t) from rest moves x = F₀ / (m Ω²) (Ω t − sin Ω t). An
//! inverse analysis has no time, so a load of it is reported there, and
//! `time` outside a load's value is an error at its token.

use kinematics_core::runtime::Model;
use kinematics_core::{mechanism, Error};

use super::efforts::close;

mechanism! {
    /// A balanced flywheel (inertia j about its centre) under a torque
    /// k t.
    pub struct RampedWheel {
        params   { j, k }
        drivers  { phi }
        unknowns { }
        points   { O = vec2(0.0, 0.0); P = polar(0.2, phi); }
        bodies   { wheel(mass = 25.0, center = O, angle = phi, inertia = j); }
        sensitivities { j, k }
        loads    { force(phi, k * time); }
    }
}

const RAMPED_WHEEL: &str = "struct RampedWheel {
    params   { j, k }
    drivers  { phi }
    unknowns { }
    points   { O = vec2(0.0, 0.0); P = polar(0.2, phi); }
    bodies   { wheel(mass = 25.0, center = O, angle = phi, inertia = j); }
    sensitivities { j, k }
    loads    { force(phi, k * time); }
}";

mechanism! {
    /// A block of mass m on a line, pushed by F₀ sin(Ω t).
    pub struct ShakenBlock {
        params   { m, f0, w }
        drivers  { x }
        unknowns { }
        points   { C = vec2(x, 0.0); }
        bodies   { block(mass = m, center = C); }
        loads    { force(C, vec2(f0 * sin(w * time), 0.0)); }
    }
}

const SHAKEN_BLOCK: &str = "struct ShakenBlock {
    params   { m, f0, w }
    drivers  { x }
    unknowns { }
    points   { C = vec2(x, 0.0); }
    bodies   { block(mass = m, center = C); }
    loads    { force(C, vec2(f0 * sin(w * time), 0.0)); }
}";

/// ω = k t² / (2J), φ = k t³ / (6J), and the torque's work ∫ k t ω dt =
/// k² t⁴ / (8J), which is ½ J ω².
fn wheel_closed_form(j: f64, k: f64, t: f64) -> [f64; 3] {
    [
        k * t.powi(3) / (6.0 * j),
        k * t * t / (2.0 * j),
        k * k * t.powi(4) / (8.0 * j),
    ]
}

#[test]
fn a_flywheel_under_a_torque_growing_with_the_time_turns_as_its_closed_form(
) -> Result<(), Box<dyn std::error::Error>> {
    let (j, k) = (0.4, 3.0);
    let m = RampedWheel { j, k };
    let generated = m
        .dynamics()?
        .forward(&m, &RampedWheelCoords { phi: 0.0 })
        .until(2.0)
        .samples(20)
        .tolerance(1e-11)
        .run()?;
    assert!(generated.is_complete());
    assert_eq!(generated.sweep.samples.len(), 21);
    for (s, e) in generated.sweep.samples.iter().zip(&generated.energy) {
        let [phi, w, work] = wheel_closed_form(j, k, s.at);
        close(s.motion.q.phi, phi, 1e-10, "φ = k t³ / 6J");
        close(s.motion.qd.phi, w, 1e-10, "ω = k t² / 2J");
        close(e.work[0], work, 1e-10, "the torque's work");
    }
    let model = Model::compile(RAMPED_WHEEL)?.with_values(&[j, k])?;
    let run_time = model
        .dynamics()?
        .forward_of(&model, &[0.0])
        .until(2.0)
        .samples(20)
        .tolerance(1e-11)
        .run()?;
    assert_eq!(run_time.sweep.samples.len(), 21);
    for (s, e) in run_time.sweep.samples.iter().zip(&run_time.energy) {
        let [phi, w, work] = wheel_closed_form(j, k, s.at);
        close(s.motion.q[0], phi, 1e-10, "φ (run-time model)");
        close(s.motion.qd[0], w, 1e-10, "ω (run-time model)");
        close(e.work[0], work, 1e-10, "the work (run-time model)");
    }
    assert!(generated.energy_error() < 1e-9 && run_time.energy_error() < 1e-9);
    Ok(())
}

#[test]
fn the_sensitivities_of_a_motion_under_a_load_of_the_time_are_its_closed_forms(
) -> Result<(), Box<dyn std::error::Error>> {
    // φ = k t³ / (6J), ω = k t² / (2J): ∂φ/∂J = −φ/J, ∂φ/∂k = φ/k, and so
    // for ω; the parameters in the order of `sensitivities { j, k }`.
    let (j, k) = (0.4, 3.0);
    let m = RampedWheel { j, k };
    let generated = m
        .dynamics()?
        .forward(&m, &RampedWheelCoords { phi: 0.0 })
        .until(2.0)
        .samples(10)
        .tolerance(1e-11)
        .sensitivities()
        .run()?;
    let model = Model::compile(RAMPED_WHEEL)?.with_values(&[j, k])?;
    let run_time = model
        .dynamics()?
        .forward_of(&model, &[0.0])
        .until(2.0)
        .samples(10)
        .tolerance(1e-11)
        .sensitivities()
        .run()?;
    for run in [&generated.sensitivities, &run_time.sensitivities] {
        assert_eq!(run.len(), 11);
        for s in run {
            let [phi, w, _] = wheel_closed_form(j, k, s.t);
            close(s.position[0], -phi / j, 1e-9, "∂φ/∂J");
            close(s.position[1], phi / k, 1e-9, "∂φ/∂k");
            close(s.rate[0], -w / j, 1e-9, "∂ω/∂J");
            close(s.rate[1], w / k, 1e-9, "∂ω/∂k");
        }
    }
    Ok(())
}

#[test]
fn a_block_pushed_by_a_sine_force_of_the_time_moves_as_its_closed_form(
) -> Result<(), Box<dyn std::error::Error>> {
    let (mass, f0, w) = (2.0, 5.0, 3.0);
    let x = |t: f64| f0 / (mass * w * w) * (w * t - (w * t).sin());
    let v = |t: f64| f0 / (mass * w) * (1.0 - (w * t).cos());
    let m = ShakenBlock { m: mass, f0, w };
    let generated = m
        .dynamics()?
        .forward(&m, &ShakenBlockCoords { x: 0.0 })
        .until(4.0)
        .samples(40)
        .tolerance(1e-11)
        .run()?;
    assert!(generated.is_complete());
    for s in &generated.sweep.samples {
        close(s.motion.q.x, x(s.at), 1e-9, "x");
        close(s.motion.qd.x, v(s.at), 1e-9, "v");
    }
    let model = Model::compile(SHAKEN_BLOCK)?.with_values(&[mass, f0, w])?;
    let run_time = model
        .dynamics()?
        .forward_of(&model, &[0.0])
        .until(4.0)
        .samples(40)
        .tolerance(1e-11)
        .run()?;
    assert_eq!(run_time.sweep.samples.len(), 41);
    for s in &run_time.sweep.samples {
        close(s.motion.q[0], x(s.at), 1e-9, "x (run-time model)");
        close(s.motion.qd[0], v(s.at), 1e-9, "v (run-time model)");
    }
    Ok(())
}

#[test]
fn an_inverse_analysis_has_no_time_and_says_so() -> Result<(), Error> {
    let m = RampedWheel { j: 0.4, k: 3.0 };
    let pose = m.assemble(&RampedWheelCoords { phi: 0.3 })?;
    let motion = m.analyze(&pose, 2.0, 0.0)?;
    let Err(e) = m.dynamics()?.inverse(&m, &motion) else {
        panic!("a load of the time has no value in an inverse analysis");
    };
    assert!(
        matches!(e, Error::InvalidDynamics { .. })
            && e.to_string().contains("`phi`")
            && e.to_string().contains("only in a forward simulation"),
        "{e}"
    );
    Ok(())
}

#[test]
fn a_load_not_finite_for_another_reason_is_not_blamed_on_the_time(
) -> Result<(), Box<dyn std::error::Error>> {
    // f = f0/x on a block at x = 0: infinite, and nothing to do with time.
    let text = SHAKEN_BLOCK.replace("vec2(f0 * sin(w * time), 0.0)", "vec2(f0 / x, 0.0)");
    let m = Model::compile(&text)?.with_values(&[2.0, 5.0, 3.0])?;
    let motion = m.analyze(&[0.0], &[1.0], &[0.0])?;
    let Err(e) = m.dynamics()?.inverse_of(&m, &motion) else {
        panic!("an infinite load is an error");
    };
    let message = e.to_string();
    assert!(
        message.contains("must be finite") && !message.contains("time"),
        "{message}"
    );
    Ok(())
}

#[test]
fn time_is_a_reserved_name() {
    let text = RAMPED_WHEEL.replace("params   { j, k }", "params   { j, k, time }");
    let message = match Model::compile(&text) {
        Ok(_) => panic!("a parameter named `time` compiled"),
        Err(e) => e.to_string(),
    };
    assert!(
        message.contains("`time` is the time of a forward simulation") && message.contains("2:22"),
        "{message}"
    );
}

#[test]
fn time_outside_a_loads_value_is_an_error_at_its_token() {
    let cases = [
        (
            "points   { O = vec2(0.0, 0.0); P = polar(0.2, phi + time); }",
            "only in the value of a `force(…)`",
        ),
        (
            "bodies   { wheel(mass = time, center = O, angle = phi); }",
            "only in the value of a `force(…)`",
        ),
        (
            "bodies   { wheel(mass = 1.0, center = O, angle = phi + time); }",
            "or `time`",
        ),
    ];
    for (line, expected) in cases {
        let text = format!(
            "struct Bad {{
    params   {{ }}
    drivers  {{ phi }}
    unknowns {{ }}
    {}
    {}
    loads    {{ force(phi, 1.0); }}
}}",
            if line.starts_with("points") {
                line
            } else {
                "points   { O = vec2(0.0, 0.0); P = polar(0.2, phi); }"
            },
            if line.starts_with("bodies") {
                line
            } else {
                "bodies   { wheel(mass = 1.0, center = O, angle = phi, inertia = 1.0); }"
            },
        );
        let message = match Model::compile(&text) {
            Ok(_) => panic!("{line}: compiled"),
            Err(e) => e.to_string(),
        };
        assert!(message.contains(expected), "{line}: {message}");
        // The error is at the token `time` (at the angle that holds it):
        // its line and column.
        let token = if line.contains("angle = phi + time") {
            "phi + time)"
        } else {
            "time"
        };
        let row = text
            .lines()
            .position(|l| l.contains(token))
            .expect("a line")
            + 1;
        let column = text
            .lines()
            .nth(row - 1)
            .and_then(|l| l.find(token))
            .expect("a column")
            + 1;
        assert!(
            message.contains(&format!("{row}:{column}")),
            "{line}: {message}"
        );
    }
}

#[test]
fn mutated_definitions_with_loads_compile_at_run_time_or_are_errors_never_a_panic() {
    // The mutants of the bases with bodies and loads (`time` and `rate(…)`
    // among them), as text: each compiles to a model whose forces at its
    // first assembled pose are computed (an error where a load reads the
    // time) and whose motion over a millisecond is integrated (its loads
    // of the time then read it), or fails with an error; nothing panics.
    let (mut compiled, mut errors, mut simulated) = (0, 0, 0);
    let bases = kinematics_compiler::fuzz::dynamics_definitions();
    for ts in kinematics_compiler::fuzz::mutants_of(&bases, 0xD1B, 600) {
        let text = ts.to_string();
        let outcome = std::panic::catch_unwind(|| -> Result<bool, String> {
            let m = Model::compile(&text).map_err(|e| e.to_string())?;
            let values = vec![0.5; m.parameters().len()];
            let m = m.with_values(&values).map_err(|e| e.to_string())?;
            let dynamics = m.dynamics().map_err(|e| e.to_string())?;
            let guess = vec![0.3; m.coordinates().len()];
            if let Some(pose) = m.assemble_all(&guess).find_map(|(_, p)| p.ok()) {
                let rates = vec![1.0; m.drivers()];
                let zeros = vec![0.0; m.drivers()];
                if let Ok(motion) = m.analyze(&pose, &rates, &zeros) {
                    // A load of the time has no value at one motion.
                    let forces = dynamics.inverse_of(&m, &motion);
                    assert!(forces.is_err() || !m.loads_read_time(), "{text}");
                }
                let run = dynamics.forward_of(&m, &pose).until(1e-3).samples(2).run();
                return Ok(run.is_ok_and(|r| r.sweep.samples.len() == 3));
            }
            Ok(false)
        });
        match outcome {
            Ok(Ok(ran)) => {
                compiled += 1;
                simulated += usize::from(ran);
            }
            Ok(Err(_)) => errors += 1,
            Err(_) => panic!("a panic on: {text}"),
        }
    }
    assert!(
        compiled > 30 && errors > 100 && simulated > 10,
        "{compiled} / {errors} / {simulated}"
    );
}
