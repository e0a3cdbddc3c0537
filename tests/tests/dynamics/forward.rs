//! Forward dynamics (`Dynamics::forward`) against closed forms written
//! here: the compound pendulum's period at small amplitude and, by the
//! complete elliptic integral, at large amplitude; a flywheel started by a
//! constant torque; the energy kept to 1e-9 of its value over 10 s on a
//! four-bar under gravity and a spring and on a spatial RSSR with inertia
//! tensors; and, at every sample, the inverse dynamics of the motion
//! found: no effort on a free driver.

use std::f64::consts::{FRAC_PI_2, PI};

use kinematics_core::dynamics::{Body, Dynamics, Ended, Event, Motor, Spring};
use kinematics_core::{mechanism, Error};

use super::efforts::{close, G};
use super::energy::{rssr_description, MassRssr, MassRssrCoords};

mechanism! {
    /// A crank whose centre of mass is at distance r from its pivot.
    pub struct Swing {
        params   { r }
        drivers  { phi }
        unknowns { }
        points   { G = polar(r, phi); }
    }
}

/// The pendulum of the tests: 2 kg at 0.1 m (with [`Swing`]'s r), 0.01
/// kg·m² about its centre, under gravity.
fn swing_dynamics() -> Result<Dynamics, Error> {
    Dynamics::builder()
        .body(
            Body::new("pendulum", 2.0)
                .center("G")
                .angle("phi")
                .inertia(0.01),
        )
        .gravity([0.0, -G, 0.0])
        .build::<Swing>()
}

/// K(k) = π / (2 AGM(1, √(1 − k²))), the complete elliptic integral of the
/// first kind.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// A compound pendulum of mass m, centre of mass at r from the pivot and
/// inertia J about it, released at rest `amplitude` from the bottom: the
/// time of its first half swing (the rate back to zero), and its
/// undamped natural frequency √(m g r / (J + m r²)).
fn half_swing(amplitude: f64) -> Result<(f64, f64), Error> {
    let (mass, r, j) = (2.0, 0.1, 0.01);
    let m = Swing { r };
    let dynamics = Dynamics::builder()
        .body(
            Body::new("pendulum", mass)
                .center("G")
                .angle("phi")
                .inertia(j),
        )
        .gravity([0.0, -G, 0.0])
        .build::<Swing>()?;
    let start = SwingCoords {
        phi: -FRAC_PI_2 + amplitude,
    };
    let run = dynamics
        .forward(&m, &start)
        .until(5.0)
        .samples(50)
        .tolerance(1e-12)
        .stop_when(Event::rate_reaches("phi", 0.0))
        .run()?;
    let Ended::Event { index: 0, at } = run.ended else {
        panic!("no half swing: {:?}", run.ended);
    };
    // At the far end of the swing, by symmetry.
    let last = run.sweep.samples.last().expect("samples");
    close(last.motion.q.phi, -FRAC_PI_2 - amplitude, 1e-9, "far end");
    for s in &run.sweep.samples {
        let f = dynamics.inverse(&m, &s.motion)?;
        assert!(
            f.effort.phi.abs() < 1e-10,
            "a free driver's effort {}",
            f.effort.phi
        );
    }
    // Of the energy that moves in the swing (1e-7 J at 1 mrad).
    assert!(run.energy_error() < 1e-9, "{}", run.energy_error());
    Ok((at, (mass * G * r / (j + mass * r * r)).sqrt()))
}

#[test]
fn a_compound_pendulum_swings_with_its_small_amplitude_period() -> Result<(), Error> {
    let amplitude = 1e-3;
    let (half, omega) = half_swing(amplitude)?;
    // T = 2π/ω (1 + θ₀²/16 + …): 6.25e-8 longer at 1 mrad, which the
    // run resolves.
    close(2.0 * half, 2.0 * PI / omega, 1e-7, "small-amplitude period");
    close(
        2.0 * half,
        2.0 * PI / omega * (1.0 + amplitude * amplitude / 16.0),
        1e-10,
        "with its first correction",
    );
    Ok(())
}

#[test]
fn a_compound_pendulum_swings_with_its_elliptic_integral_period_at_large_amplitude(
) -> Result<(), Error> {
    let amplitude = 150f64.to_radians();
    let (half, omega) = half_swing(amplitude)?;
    // T = 4 K(sin(θ₀/2)) / ω.
    let period = 4.0 * elliptic_k((amplitude / 2.0).sin()) / omega;
    close(2.0 * half, period, 1e-9, "large-amplitude period");
    // 1.76 times the small-amplitude one.
    assert!(period * omega / (2.0 * PI) > 1.7);
    Ok(())
}

mechanism! {
    /// A flywheel turning about its centre O, a point P on its rim.
    pub struct Flywheel {
        params   { }
        drivers  { phi }
        unknowns { }
        points   { O = vec2(0.0, 0.0); P = polar(0.2, phi); }
    }
}

#[test]
fn a_balanced_flywheel_under_a_constant_torque_accelerates_uniformly() -> Result<(), Error> {
    let (torque, j) = (3.0, 0.4);
    let dynamics = Dynamics::builder()
        .body(Body::new("wheel", 25.0).center("O").angle("phi").inertia(j))
        .gravity([0.0, -G, 0.0])
        .motor("phi", Motor::Constant(torque))
        .build::<Flywheel>()?;
    let run = dynamics
        .forward(&Flywheel {}, &FlywheelCoords { phi: 0.0 })
        .until(3.0)
        .samples(30)
        .tolerance(1e-11)
        .run()?;
    assert!(run.is_complete());
    assert_eq!(run.sweep.samples.len(), 31);
    let alpha = torque / j;
    for (s, e) in run.sweep.samples.iter().zip(&run.energy) {
        let t = s.at;
        close(s.motion.q.phi, 0.5 * alpha * t * t, 1e-10, "φ = ½ α t²");
        close(s.motion.qd.phi, alpha * t, 1e-10, "ω = α t");
        assert!((s.motion.qdd.phi - alpha).abs() < 1e-12);
        // The motor's work is the kinetic energy: T φ = ½ J ω².
        close(e.work[0], torque * 0.5 * alpha * t * t, 1e-10, "work");
        close(
            e.kinetic,
            0.5 * j * (alpha * t).powi(2),
            1e-10,
            "kinetic energy",
        );
    }
    assert_eq!(run.work_names, ["force on phi"]);
    Ok(())
}

mechanism! {
    /// A four-bar with the centres of mass of its links and a fixed
    /// anchor P0 for a spring to the coupler.
    pub struct SpringFourBar {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            G2 = polar(a / 2.0, phi);
            G3 = polar(a, phi) + polar(b / 2.0, th3);
            G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
            P0 = vec2(0.05, 0.15);
        }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
    }
}

/// The bodies of the four-bar of the tests, gravity and a spring from P0
/// to G3 of stiffness k, free length 0.10 and damping c.
fn four_bar_loads(k: f64, c: f64) -> kinematics_core::dynamics::DynamicsBuilder {
    Dynamics::builder()
        .body(
            Body::new("crank", 0.3)
                .center("G2")
                .angle("phi")
                .inertia(2.0e-3),
        )
        .body(
            Body::new("coupler", 0.5)
                .center("G3")
                .angle("th3")
                .inertia(6.0e-4),
        )
        .body(
            Body::new("rocker", 0.4)
                .center("G4")
                .angle("th4")
                .inertia(3.5e-4),
        )
        .gravity([0.0, -G, 0.0])
        .spring(
            Spring::new("P0", "G3")
                .stiffness(k)
                .free_length(0.10)
                .damping(c),
        )
}

/// The four-bar of the tests with [`four_bar_loads`].
fn spring_four_bar(
    k: f64,
    c: f64,
) -> Result<(SpringFourBar, Dynamics, SpringFourBarCoords), Error> {
    let m = SpringFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let dynamics = four_bar_loads(k, c).build::<SpringFourBar>()?;
    let start = m.assemble(&SpringFourBarCoords {
        phi: 0.0,
        th3: 1.2,
        th4: 1.9,
    })?;
    Ok((m, dynamics, start))
}

#[test]
fn a_four_bar_under_gravity_and_a_spring_keeps_its_energy() -> Result<(), Error> {
    let (m, dynamics, start) = spring_four_bar(50.0, 0.0)?;
    let run = dynamics
        .forward(&m, &start)
        .until(10.0)
        .samples(1000)
        .tolerance(1e-11)
        .run()?;
    assert!(run.is_complete(), "{:?}", run.ended);
    // It moves: the crank swings through more than a radian.
    let (lo, hi) = run
        .sweep
        .samples
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), s| {
            (l.min(s.motion.q.phi), h.max(s.motion.q.phi))
        });
    assert!(hi - lo > 1.0, "the crank moves {lo}..{hi}");
    assert!(
        run.energy_error() < 1e-9,
        "energy drift {}",
        run.energy_error()
    );
    // The damper's work column is there, and zero.
    assert_eq!(run.work_names, ["damper P0-G3"]);
    assert!(run.energy.iter().all(|e| e.work[0] == 0.0));
    for s in &run.sweep.samples {
        let f = dynamics.inverse(&m, &s.motion)?;
        assert!(f.effort.phi.abs() < 1e-10, "{}", f.effort.phi);
        assert!(
            s.motion.residual < 1e-14,
            "the loop closes: {}",
            s.motion.residual
        );
    }
    println!("{:?}", run.statistics);
    Ok(())
}

#[test]
fn a_spatial_rssr_with_inertia_tensors_keeps_its_energy() -> Result<(), Error> {
    let m = MassRssr {
        a: 0.03,
        b: 0.12,
        c: 0.08,
        d: 0.1,
    };
    let dynamics = rssr_description().build::<MassRssr>()?;
    let start = m.assemble(&MassRssrCoords { phi: 0.7, psi: 1.1 })?;
    let run = dynamics
        .forward(&m, &start)
        .rates(&MassRssrCoords { phi: 5.0, psi: 0.0 })
        .until(10.0)
        .samples(500)
        .tolerance(1e-11)
        .run()?;
    assert!(run.is_complete(), "{:?} {:?}", run.ended, run.sweep.stop);
    assert!(
        run.energy_error() < 1e-9,
        "energy drift {}",
        run.energy_error()
    );
    let kinetic = run.energy.iter().map(|e| e.kinetic).fold(0.0, f64::max);
    assert!(kinetic > 1e-3, "it moves: T up to {kinetic} J");
    for s in &run.sweep.samples {
        let f = dynamics.inverse(&m, &s.motion)?;
        assert!(f.effort.phi.abs() < 1e-10, "{}", f.effort.phi);
    }
    Ok(())
}

/// The four-bar of [`SpringFourBar`] as text, for a run-time model.
const SPRING_FOUR_BAR: &str = "struct SpringFourBar {
    params   { a, b, c, d }
    drivers  { phi }
    unknowns { th3, th4 }
    points {
        G2 = polar(a / 2.0, phi);
        G3 = polar(a, phi) + polar(b / 2.0, th3);
        G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
        P0 = vec2(0.05, 0.15);
    }
    loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
}";

#[test]
fn a_run_time_model_moves_as_the_generated_mechanism() -> Result<(), Box<dyn std::error::Error>> {
    use kinematics_core::runtime::Model;
    let (m, _, start) = spring_four_bar(50.0, 2.0)?;
    let description = || four_bar_loads(50.0, 2.0).motor("phi", Motor::dc(0.5, 60.0));
    let generated = description().build::<SpringFourBar>()?;
    let model = Model::compile(SPRING_FOUR_BAR)?.with_values(&[0.04, 0.12, 0.10, 0.11])?;
    let run_time = description().build_for(&model)?;
    let a = generated
        .forward(&m, &start)
        .until(2.0)
        .samples(40)
        .tolerance(1e-10)
        .run()?;
    let b = run_time
        .forward_of(&model, &[start.phi, start.th3, start.th4])
        .until(2.0)
        .samples(40)
        .tolerance(1e-10)
        .run()?;
    assert!(a.is_complete() && b.ended == a.ended);
    assert_eq!(a.sweep.samples.len(), b.sweep.samples.len());
    assert_eq!(a.work_names, b.work_names);
    assert_eq!(a.work_names, ["force on phi", "damper P0-G3"]);
    // The motor drives it past a full turn, the damper takes energy out.
    let last = a.energy.last().expect("samples");
    assert!(
        a.sweep.samples[40].motion.q.phi > 6.3,
        "{}",
        a.sweep.samples[40].motion.q.phi
    );
    assert!(last.work[0] > 0.0 && last.work[1] < 0.0, "{:?}", last.work);
    assert!(a.energy_error() < 1e-8 && b.energy_error() < 1e-8);
    for (x, y) in a.sweep.samples.iter().zip(&b.sweep.samples) {
        assert_eq!(x.at, y.at);
        for (u, v) in [
            (x.motion.q.phi, y.motion.q[0]),
            (x.motion.q.th4, y.motion.q[2]),
            (x.motion.qd.phi, y.motion.qd[0]),
            (x.motion.qdd.phi, y.motion.qdd[0]),
        ] {
            assert!(
                (u - v).abs() < 1e-9 * (1.0 + u.abs()),
                "{u} against {v} at {}",
                x.at
            );
        }
    }
    Ok(())
}

/// φ, φ̇, θ₃, θ₄ and T of the four-bar of [`spring_four_bar`] with a DC
/// motor (0.5 N·m at stall, no torque at 60 rad/s) on the crank and the
/// damper of 2 N·s/m, from rest at φ = 0, by an independent derivation:
/// the Lagrange equation in φ alone, M(φ) φ̈ + ½ M'(φ) φ̇² + V'(φ) = Q,
/// with the closed-form positions and their derivatives differentiated
/// symbolically, integrated by a 6-stage Gauss–Legendre method at 34
/// digits, converged to 5e-16 (`tests/reference/four_bar_forward.py`).
// The reference's 17 digits as it printed them.
#[allow(clippy::excessive_precision)]
const LAGRANGE: [[f64; 6]; 8] = [
    [
        0.25,
        3.3560632674773675,
        30.612428586128006,
        0.78735258044431677,
        2.2704693146920470,
        1.2169719835519341,
    ],
    [
        0.50,
        12.532291902910316,
        38.426410445380159,
        1.0035918730705494,
        1.6263254648060711,
        2.5650162664075452,
    ],
    [
        0.75,
        24.178238752533962,
        47.450009397192642,
        1.3062393672778519,
        2.1591786118581914,
        3.5638114205097977,
    ],
    [
        1.00,
        36.819794024413326,
        49.147263243076653,
        1.3034927071508241,
        2.1270061639218854,
        3.9642895018134124,
    ],
    [
        1.25,
        49.899232128337858,
        45.567378721633435,
        1.1757511405549455,
        1.8386989232625117,
        4.0661118052175379,
    ],
    [
        1.50,
        63.207476847653535,
        57.020816200474412,
        0.78194818622848520,
        1.4469176588753675,
        4.0689058225036175,
    ],
    [
        1.75,
        76.707316162770101,
        52.207742041885490,
        0.53615719092111646,
        1.5356847241697627,
        3.9997387334896955,
    ],
    [
        2.00,
        90.162193834372381,
        51.099813639845865,
        0.54920883965538004,
        1.8871445979770761,
        4.1173190682453180,
    ],
];

#[test]
fn a_motor_driven_four_bar_with_a_damper_moves_as_its_lagrange_equation() -> Result<(), Error> {
    let (m, _, start) = spring_four_bar(50.0, 2.0)?;
    let dynamics = four_bar_loads(50.0, 2.0)
        .motor("phi", Motor::dc(0.5, 60.0))
        .build::<SpringFourBar>()?;
    let run = dynamics
        .forward(&m, &start)
        .until(2.0)
        .samples(8)
        .tolerance(1e-12)
        .run()?;
    assert!(run.is_complete());
    let wrap = |x: f64| (x + PI).rem_euclid(2.0 * PI) - PI;
    for (s, (e, row)) in run.sweep.samples[1..]
        .iter()
        .zip(run.energy[1..].iter().zip(&LAGRANGE))
    {
        let [t, phi, rate, th3, th4, kinetic] = *row;
        assert_eq!(s.at, t);
        close(s.motion.q.phi, phi, 1e-9, "φ");
        close(s.motion.qd.phi, rate, 1e-9, "φ̇");
        assert!((wrap(s.motion.q.th3) - th3).abs() < 1e-9, "θ₃ at {t}");
        assert!((wrap(s.motion.q.th4) - th4).abs() < 1e-9, "θ₄ at {t}");
        close(e.kinetic, kinetic, 1e-9, "T");
    }
    Ok(())
}

/// φ(t) of J φ'' + c φ' + k φ = 0 from φ = 1 at rest, overdamped.
fn overdamped(j: f64, c: f64, k: f64, t: f64) -> f64 {
    let root = (c * c - 4.0 * j * k).sqrt();
    let (s1, s2) = ((-c + root) / (2.0 * j), (-c - root) / (2.0 * j));
    let a = s2 / (s2 - s1);
    a * (s1 * t).exp() + (1.0 - a) * (s2 * t).exp()
}

#[test]
fn a_stiff_torsion_spring_and_damper_are_integrated_implicitly() -> Result<(), Error> {
    use kinematics_core::dynamics::Method;
    // Rates −k/c ≈ −0.25 /s and −c/J = −1e5 /s: stiff.
    let (j, c, k) = (0.4, 4.0e4, 1.0e4);
    let dynamics = Dynamics::builder()
        .body(Body::new("wheel", 25.0).center("O").angle("phi").inertia(j))
        .coordinate_force("phi", move |s| -k * s.q(0) - c * s.qd(0))
        .build::<Flywheel>()?;
    let start = FlywheelCoords { phi: 1.0 };
    let implicit = dynamics
        .forward(&Flywheel {}, &start)
        .until(10.0)
        .samples(20)
        .tolerance(1e-7)
        .method(Method::Implicit)
        .run()?;
    assert!(implicit.is_complete());
    for s in &implicit.sweep.samples {
        let exact = overdamped(j, c, k, s.at);
        assert!(
            (s.motion.q.phi - exact).abs() < 1e-5,
            "{} against {exact} at {}",
            s.motion.q.phi,
            s.at
        );
    }
    // The damper's work is the energy lost: T + V − ΣW stays at V₀ = 0
    // (the spring is a coordinate load here, its work counted too). The
    // works are quadratures of the method's stages, of its order (2) and
    // not error-controlled: 1.7e-4 of the largest term here.
    assert!(
        implicit.energy_error() < 1e-3,
        "{}",
        implicit.energy_error()
    );
    assert!(implicit.statistics.steps < 300, "{:?}", implicit.statistics);
    // The explicit pair is held by its stability, |h λ| ≲ 3.3: over a
    // hundredth of the time it takes more steps than the implicit method
    // over all of it.
    let explicit = dynamics
        .forward(&Flywheel {}, &start)
        .until(0.1)
        .samples(1)
        .tolerance(1e-7)
        .run()?;
    assert!(
        explicit.statistics.steps > 5 * implicit.statistics.steps,
        "{:?} against {:?}",
        explicit.statistics,
        implicit.statistics
    );
    Ok(())
}

#[test]
fn a_forward_simulation_refuses_what_cannot_be_run_by_name() -> Result<(), Error> {
    let m = Swing { r: 0.1 };
    let dynamics = swing_dynamics()?;
    let start = SwingCoords { phi: 0.3 };
    let message = |r: Result<kinematics_core::dynamics::Trajectory<Swing>, Error>| {
        r.expect_err("refused").to_string()
    };
    let forward = || dynamics.forward(&m, &start);
    assert!(message(forward().until(0.0).run()).contains("until"));
    assert!(message(forward().until(f64::NAN).run()).contains("until"));
    assert!(message(forward().tolerance(f64::NAN).run()).contains("tolerance"));
    assert!(message(forward().samples(0).run()).contains("samples"));
    assert!(message(forward().samples(usize::MAX).run()).contains("samples"));
    assert!(message(forward().max_step(-1.0).run()).contains("max_step"));
    let e = message(forward().stop_when(Event::reaches("psi", 1.0)).run());
    assert!(
        e.contains("no coordinate `psi`") && e.contains("phi"),
        "{e}"
    );
    assert!(message(forward().stop_when(Event::reaches("phi", f64::NAN)).run()).contains("finite"));
    // A driver that moves no mass: its mass matrix is zero.
    let massless = Dynamics::builder()
        .body(Body::new("pendulum", 0.0).center("G").angle("phi"))
        .build::<Swing>()?;
    let e = massless
        .forward(&m, &start)
        .run()
        .expect_err("refused")
        .to_string();
    assert!(e.contains("moves no mass"), "{e}");
    // Built for another mechanism.
    let other = Dynamics::builder()
        .body(
            Body::new("wheel", 1.0)
                .center("O")
                .angle("phi")
                .inertia(0.1),
        )
        .build::<Flywheel>()?;
    assert!(other.forward(&m, &start).run().is_err());
    // A load that is not finite mid-run ends it there, named.
    let blowing = Dynamics::builder()
        .body(
            Body::new("pendulum", 2.0)
                .center("G")
                .angle("phi")
                .inertia(0.01),
        )
        .coordinate_force("phi", |s| if s.time() > 0.5 { f64::NAN } else { 1.0 })
        .build::<Swing>()?;
    let run = blowing.forward(&m, &start).until(1.0).run()?;
    let Ended::Failed { at } = run.ended else {
        panic!("{:?}", run.ended)
    };
    assert!((at - 0.5).abs() < 1e-9, "{at}");
    let stop = run.sweep.stop.expect("a stop");
    assert!(
        stop.to_string().contains("force on coordinate `phi`"),
        "{stop}"
    );
    Ok(())
}

mechanism! {
    /// A pendulum of length l hanging from a cart that moves along x.
    pub struct Cart {
        params   { l }
        drivers  { x, phi }
        unknowns { }
        points   { C = vec2(x, 0.0); G = vec2(x, 0.0) + polar(l, phi); }
    }
}

/// A pendulum (bob m at G, inertia J about it) on a cart of mass M whose
/// position is prescribed, x = ½ a t², the angle φ free. By Lagrange's
/// equation in φ, with G = (x + l cos φ, l sin φ):
/// (m l² + J) φ̈ = m l (a sin φ − g cos φ), and the cart's driving force
/// Q_x = (M + m) a − m l (sin φ φ̈ + cos φ φ̇²).
#[test]
fn a_pendulum_on_a_prescribed_cart_moves_and_pulls_as_its_lagrange_equations() -> Result<(), Error>
{
    let (l, mass, j, cart, a) = (0.5, 2.0, 0.01, 5.0, 3.0);
    let m = Cart { l };
    let dynamics = Dynamics::builder()
        .body(Body::new("cart", cart).center("C"))
        .body(Body::new("bob", mass).center("G").angle("phi").inertia(j))
        .gravity([0.0, -G, 0.0])
        .build::<Cart>()?;
    let start = CartCoords { x: 0.0, phi: -1.2 };
    let run = dynamics
        .forward(&m, &start)
        .free(Cart::PHI)
        .profile(kinematics_core::sweep::constant_acceleration(
            Cart::X,
            0.0,
            0.0,
            a,
        ))
        .until(2.0)
        .samples(40)
        .tolerance(1e-11)
        .run()?;
    assert!(run.is_complete(), "{:?}", run.ended);
    assert_eq!(run.work_names, ["driver x"]);
    for (s, e) in run.sweep.samples.iter().zip(&run.energy) {
        let (t, q, qd, qdd) = (s.at, s.motion.q, s.motion.qd, s.motion.qdd);
        close(q.x, 0.5 * a * t * t, 1e-12, "x");
        let phi_dd = mass * l * (a * q.phi.sin() - G * q.phi.cos()) / (mass * l * l + j);
        assert!(
            (qdd.phi - phi_dd).abs() < 1e-9 * (1.0 + phi_dd.abs()),
            "φ'' at {t}"
        );
        let pull =
            (cart + mass) * a - mass * l * (q.phi.sin() * qdd.phi + q.phi.cos() * qd.phi * qd.phi);
        assert!(
            (e.effort[0] - pull).abs() < 1e-9 * (1.0 + pull.abs()),
            "Q_x {} against {pull}",
            e.effort[0]
        );
        assert_eq!(e.effort[1], 0.0);
        // The inverse dynamics of the motion found: the same pull, no
        // effort on φ.
        let f = dynamics.inverse(&m, &s.motion)?;
        assert!((f.effort.x - pull).abs() < 1e-9 * (1.0 + pull.abs()));
        assert!(f.effort.phi.abs() < 1e-9, "{}", f.effort.phi);
    }
    // The cart's work is the energy the pendulum and the cart gain.
    assert!(run.energy_error() < 1e-9, "{}", run.energy_error());
    // A rate given for the prescribed cart is refused.
    let e = dynamics
        .forward(&m, &start)
        .free(Cart::PHI)
        .rates(&CartCoords { x: 1.0, phi: 0.0 })
        .run()
        .expect_err("refused");
    assert!(e.to_string().contains("`x` is not free"), "{e}");
    Ok(())
}

/// The output samples land on the end time exactly (until·n/n rounds
/// above it for these), and the earliest of two events in one step ends
/// the run, whatever their order.
#[test]
fn the_last_sample_is_at_the_end_and_the_earliest_event_ends_the_run() -> Result<(), Error> {
    let m = Swing { r: 0.1 };
    let dynamics = swing_dynamics()?;
    let start = SwingCoords { phi: 0.3 };
    for (until, samples) in [(0.1, 3), (0.4, 6), (1.6, 12), (2.7, 24)] {
        let run = dynamics
            .forward(&m, &start)
            .until(until)
            .samples(samples)
            .run()?;
        assert_eq!(run.sweep.samples.len(), samples + 1, "{until} in {samples}");
        assert_eq!(run.sweep.samples.last().map(|s| s.at), Some(until));
    }
    // Falling from 0.3 rad: φ passes 0.2 before 0.1, in one long step.
    for order in [[0.1, 0.2], [0.2, 0.1]] {
        let run = dynamics
            .forward(&m, &start)
            .until(1.0)
            .max_step(1.0)
            .stop_when(Event::reaches("phi", order[0]))
            .stop_when(Event::reaches("phi", order[1]))
            .run()?;
        let Ended::Event { index, .. } = run.ended else {
            panic!("{:?}", run.ended)
        };
        assert_eq!(order[index], 0.2, "{order:?}");
        let last = run.sweep.samples.last().expect("samples");
        assert!((last.motion.q.phi - 0.2).abs() < 1e-9);
    }
    Ok(())
}

/// A pendulum released from rest at θ₀ onto a stop at the bottom: it hits
/// at ω₀ = √(2 m g r (1 − cos θ₀) / I_O) and leaves at −e ω₀; with e = 1
/// it swings back to θ₀, with e = 0.6 the kinetic energy lost, (1 − e²)
/// of it, is the impacts' work, so the balance still holds.
#[test]
fn a_pendulum_bounces_off_a_stop_as_newtons_law_of_restitution() -> Result<(), Error> {
    let (mass, r, j) = (2.0, 0.1, 0.01);
    let m = Swing { r };
    let dynamics = swing_dynamics()?;
    let theta = 0.8;
    let start = SwingCoords {
        phi: -FRAC_PI_2 + theta,
    };
    let omega = (2.0 * mass * G * r * (1.0 - theta.cos()) / (j + mass * r * r)).sqrt();
    for e in [1.0, 0.6] {
        let run = dynamics
            .forward(&m, &start)
            .until(3.0)
            .samples(300)
            .tolerance(1e-11)
            .stop_when(Event::stop("phi", -FRAC_PI_2, e))
            .run()?;
        assert!(run.is_complete(), "{:?}", run.ended);
        assert!(run.impacts.len() >= 3, "{}", run.impacts.len());
        let first = run.impacts[0];
        close(first.before, -omega, 1e-8, "impact speed");
        assert!(
            (first.after + e * first.before).abs() < 1e-12 * omega,
            "{first:?}"
        );
        // Between impacts it swings as a pendulum: back to the stop at
        // the speed it left with, reversed again.
        for w in run.impacts.windows(2) {
            close(w[1].before.abs(), w[0].after.abs(), 1e-7, "the return");
        }
        // It never passes the stop.
        assert!(run
            .sweep
            .samples
            .iter()
            .all(|s| s.motion.q.phi >= -FRAC_PI_2 - 1e-9));
        assert_eq!(run.work_names, ["impacts at phi"]);
        let lost = run.energy.last().expect("samples").work[0];
        let expected: f64 = run
            .impacts
            .iter()
            .map(|i| 0.5 * (j + mass * r * r) * (i.after * i.after - i.before * i.before))
            .sum();
        close(lost, expected, 1e-9, "the impacts' work");
        if e == 1.0 {
            assert!(lost.abs() < 1e-12, "{lost}");
            let highest = run
                .sweep
                .samples
                .iter()
                .map(|s| s.motion.q.phi)
                .fold(f64::MIN, f64::max);
            close(
                highest,
                -FRAC_PI_2 + theta,
                1e-6,
                "back to the release angle",
            );
        }
        assert!(run.energy_error() < 1e-9, "{}", run.energy_error());
    }
    let e = dynamics
        .forward(&m, &start)
        .stop_when(Event::stop("phi", 0.0, 1.5))
        .run()
        .expect_err("refused");
    assert!(e.to_string().contains("restitution"), "{e}");
    Ok(())
}
