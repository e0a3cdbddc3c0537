//! Events by direction against the closed form of a harmonic oscillator,
//! a block of mass m on a spring of stiffness k released from x = A at
//! rest: x = A cos ω t, ω = √(k/m). x = A/2 is reached decreasing at
//! ω t = π/3 and increasing at 5π/3; x = −A/2 decreasing at 2π/3 and
//! increasing at 4π/3; the rate, 0 at the start, reaches 0 increasing
//! at ω t = π and decreasing at 2π.

use std::f64::consts::PI;

use kinematics_core::dynamics::{Ended, Event};
use kinematics_core::runtime::Model;
use kinematics_core::{mechanism, Error};

mechanism! {
    /// A block on a spring to the frame along its line.
    pub struct Oscillator {
        params   { m, k }
        drivers  { x }
        unknowns { }
        points   { C = vec2(x, 0.0); }
        bodies   { block(mass = m, center = C); }
        loads    { force(x, -k * x); }
    }
}

const OSCILLATOR: &str = "struct Oscillator {
    params   { m, k }
    drivers  { x }
    unknowns { }
    points   { C = vec2(x, 0.0); }
    bodies   { block(mass = m, center = C); }
    loads    { force(x, -k * x); }
}";

const A: f64 = 0.1;
const MASS: f64 = 2.0;
const K: f64 = 50.0;

/// When the first of `events` happens, and which: a generated mechanism
/// and a run-time model, which must agree.
fn first(events: &[Event]) -> Result<(usize, f64), Box<dyn std::error::Error>> {
    let o = Oscillator { m: MASS, k: K };
    let dynamics = o.dynamics()?;
    let mut run = dynamics
        .forward(&o, &OscillatorCoords { x: A })
        .until(10.0)
        .tolerance(1e-12);
    let model = Model::compile(OSCILLATOR)?.with_values(&[MASS, K])?;
    let model_dynamics = model.dynamics()?;
    let mut model_run = model_dynamics
        .forward_of(&model, &[A])
        .until(10.0)
        .tolerance(1e-12);
    for e in events {
        run = run.stop_when(e.clone());
        model_run = model_run.stop_when(e.clone());
    }
    let (a, b) = (run.run()?.ended, model_run.run()?.ended);
    let (Ended::Event { index, at }, Ended::Event { index: i, at: t }) = (a.clone(), b.clone())
    else {
        return Err(format!("no event: {a:?}, {b:?}").into());
    };
    assert_eq!(index, i);
    assert!((at - t).abs() < 1e-9, "{at} {t}");
    Ok((index, at))
}

#[test]
fn an_event_counts_in_the_direction_asked_for() -> Result<(), Box<dyn std::error::Error>> {
    let w = (K / MASS).sqrt();
    let close = |(index, at): (usize, f64), want: (usize, f64), what: &str| {
        assert_eq!(index, want.0, "{what}");
        assert!(
            (at - want.1).abs() < 1e-9,
            "{what}: {at} against {}",
            want.1
        );
    };
    let half = 0.5 * A;
    close(
        first(&[Event::reaches("x", half)])?,
        (0, PI / 3.0 / w),
        "either way",
    );
    close(
        first(&[Event::reaches("x", half).decreasing()])?,
        (0, PI / 3.0 / w),
        "decreasing",
    );
    close(
        first(&[Event::reaches("x", half).increasing()])?,
        (0, 5.0 * PI / 3.0 / w),
        "increasing",
    );
    close(
        first(&[Event::rate_reaches("x", 0.0).increasing()])?,
        (0, PI / w),
        "the rate, increasing",
    );
    // The rate is 0 at the start, which does not count: decreasing, it is
    // reached next at ω t = 2π (at π it is reached increasing).
    close(
        first(&[Event::rate_reaches("x", 0.0).decreasing()])?,
        (0, 2.0 * PI / w),
        "the rate, decreasing",
    );
    // Two events on one coordinate: the earliest ends the run.
    close(
        first(&[
            Event::reaches("x", half).increasing(),
            Event::reaches("x", -half).increasing(),
        ])?,
        (1, 4.0 * PI / 3.0 / w),
        "two on one coordinate",
    );
    Ok(())
}

#[test]
fn a_stop_reached_from_its_side_bounces_the_block_back() -> Result<(), Error> {
    // A stop at x = −A/2 counted only increasing is never hit on the way
    // down: the block passes it at 2π/3 and comes back through it at 4π/3,
    // where it bounces (e = 1) and goes back down.
    let o = Oscillator { m: MASS, k: K };
    let w = (K / MASS).sqrt();
    let run = o
        .dynamics()?
        .forward(&o, &OscillatorCoords { x: A })
        .until(4.5 / w)
        .tolerance(1e-12)
        .stop_when(Event::stop("x", -0.5 * A, 1.0).increasing())
        .run()?;
    assert_eq!(run.impacts.len(), 1);
    let hit = &run.impacts[0];
    assert!((hit.t - 4.0 * PI / 3.0 / w).abs() < 1e-9, "{}", hit.t);
    // It arrives at −A ω sin(4π/3) = A ω √3/2 and leaves at the opposite.
    let v = A * w * 3f64.sqrt() / 2.0;
    assert!((hit.before - v).abs() < 1e-9 * v && (hit.after + v).abs() < 1e-9 * v);
    Ok(())
}
