//! A `#![no_std]` crate that declares a planar four-bar and a six-axis arm
//! with `mechanism!` and calls their generated code: built on its own
//! (`cargo build -p kinematics-no-std`), it proves that `kinematics-core`
//! without its `std` feature, and the code the macro generates, need
//! neither the standard library nor its floating-point functions.
#![no_std]
// The parameters of these test mechanisms are described in the struct docs.
#![allow(missing_docs)]

use kinematics_core::{mechanism, Error};

mechanism! {
    /// Crank-rocker four-bar with a coupler point.
    pub struct FourBar {
        params   { a: length, b: length, c: length, d: length, p, beta }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            B = polar(a, phi);
            C = vec2(d, 0.0) + polar(c, th4);
            P = B + polar(p, th3 + beta);
        }
        loops { B + polar(b, th3) == C; }
    }
}

mechanism! {
    /// Six-axis arm from elementary joint matrices.
    pub struct Arm {
        params { d1, a2, a3, d5, d6 }
        drivers { q1, q2, q3, q4, q5, q6 }
        unknowns { }
        frames {
            upper = t3(0.0, 0.0, d1, q1) * t2(0.0, 0.0, 0.0, q2);
            fore = upper * t2(a2, 0.0, 0.0, q3) * t1(0.0, 0.0, 0.0, q4);
            tool = fore * t2(a3, 0.0, 0.0, q5) * t1(d5, 0.0, 0.0, q6);
        }
        points { TCP = tool * vec3(d6, 0.0, 0.0); }
    }
}

/// The coupler point's speed at crank angle `phi`, for a crank turning at
/// `omega`, from a guess of the coupler and rocker angles.
///
/// # Errors
/// As `FourBar::step`.
pub fn coupler_speed(phi: f64, omega: f64, th3: f64, th4: f64) -> Result<f64, Error> {
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    let s = m.step(&FourBarCoords { phi, th3, th4 }, omega, 0.0)?;
    Ok(s.point_p().speed())
}

/// The tool point's acceleration norm for joint angles `q` and rates `qd`.
///
/// # Errors
/// As `Arm::analyze`.
pub fn tool_acceleration(q: [f64; 6], qd: [f64; 6]) -> Result<f64, Error> {
    let m = Arm {
        d1: 0.4,
        a2: 0.45,
        a3: 0.4,
        d5: 0.08,
        d6: 0.1,
    };
    let pose = ArmCoords::from(q);
    let s = m.analyze(&pose, qd, [0.0; 6])?;
    Ok(s.point_tcp().acceleration.norm())
}
