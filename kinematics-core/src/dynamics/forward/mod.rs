//! Forward dynamics: the motion that the loads produce.
//!
//! Some drivers move freely (by default all of them); the others follow a
//! prescribed profile of time, as in a kinematic simulation. The state is
//! y = (d_f, ḋ_f), the free drivers and their rates; at every evaluation
//! the mechanism is assembled at the drivers (closed form or
//! Newton–Raphson from the last accepted pose) and analysed, so that the
//! loops close to round-off at every instant with no drift and no
//! constraint stabilisation. The accelerations of the free drivers solve
//!
//! M_ff(q) d̈_f = −b_f(q, q̇, t),
//!
//! M the mass matrix from the exact partial velocities and b the efforts
//! at zero free acceleration, by virtual power. The
//! integrator is Dormand and Prince's explicit pair of orders 5(4) with
//! error control on the positions and velocities and dense output
//! (or, for stiff motions, the implicit TR-BDF2, [`Method`]); the work of
//! each load is integrated beside the motion, so
//! that every run reports its energy balance, T + V − Σ W = T₀ + V₀.
//!
//! ```
//! use kinematics_core::dynamics::{Body, Dynamics};
//! use kinematics_core::mechanism;
//!
//! mechanism! {
//!     /// A pendulum: a crank of length l with its mass at the end.
//!     pub struct Pendulum { params { l } drivers { phi } unknowns { } points { G = polar(l, phi); } }
//! }
//! let m = Pendulum { l: 1.0 };
//! let dynamics = Dynamics::builder()
//!     .body(Body::new("bob", 1.0).center("G").angle("phi"))
//!     .gravity([0.0, -9.81, 0.0])
//!     .build::<Pendulum>()?;
//! // Released at rest 1° from the bottom (φ = −90°): a small swing.
//! let start = PendulumCoords { phi: (-89.0f64).to_radians() };
//! let run = dynamics.forward(&m, &start).until(2.0).samples(200).tolerance(1e-10).run()?;
//! assert!(run.ended.is_complete());
//! // Half a period later (π √(l/g)) it is at the other end of its swing.
//! let half = core::f64::consts::PI * (1.0 / 9.81f64).sqrt();
//! let i = run.sweep.samples.iter().position(|s| s.at >= half).unwrap();
//! assert!(run.sweep.samples[i].motion.q.phi < (-90.0f64).to_radians());
//! // The energy is kept to the tolerance.
//! assert!(run.energy_error() < 1e-8);
//! # Ok::<(), kinematics_core::Error>(())
//! ```

mod eom;
pub(crate) mod equations;
mod generated;
mod motor;
pub(crate) mod ode;
pub(crate) mod run;
mod stiff;

use alloc::string::String;
use alloc::vec::Vec;

pub use generated::Forward;
pub use motor::Motor;

use crate::mechanism::Mechanism;
use crate::sweep::Sweep;

/// What ends a forward simulation before its end time: a coordinate, or
/// its rate, reaching a value (a stop, a limit switch, the end of a
/// deployment, a speed reached).
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    pub(crate) coordinate: String,
    pub(crate) rate: bool,
    pub(crate) value: f64,
    /// The direction it is reached in: 1 increasing, −1 decreasing, 0
    /// either.
    pub(crate) direction: i8,
    /// Where the event is a stop the motion bounces off: the coefficient
    /// of restitution.
    pub(crate) restitution: Option<f64>,
}

/// An event is looked for at the end of every step, located on the dense
/// output by the Illinois method to the resolution of the time, from
/// either side unless [`Event::increasing`] or [`Event::decreasing`] says
/// which. One whose value is already reached at the start counts from
/// when the motion leaves it; a crossing there and back within one step
/// is not seen (bound the step with `max_step` where that matters).
impl Event {
    /// The coordinate `coordinate` (a driver or an unknown, by name)
    /// reaching `value`, from either side (an angle in radians, not
    /// wrapped: a crank's second turn ends at 4π).
    #[must_use]
    pub fn reaches(coordinate: &str, value: f64) -> Self {
        Event {
            coordinate: coordinate.into(),
            rate: false,
            value,
            direction: 0,
            restitution: None,
        }
    }

    /// A stop: where `coordinate` reaches `value` the motion does not end
    /// but bounces off it, with the coefficient of restitution
    /// `restitution` (0 plastic, 1 elastic). The impact is instantaneous:
    /// the free drivers' rates jump by Δḋ = λ M⁻¹ Gᵀ, G = ∂q̇_j/∂ḋ_f the
    /// coordinate's partial velocities and M the mass matrix, with λ such
    /// that the coordinate's rate w becomes −e w (Newton's law with the
    /// mechanism's own inertia); the kinetic energy lost is reported as the
    /// work `impacts at <coordinate>` and each impact in
    /// [`Trajectory::impacts`]. The run ends there when the rate after an
    /// impact is below 1e-9 of the first's (it has come to rest at the
    /// stop), or after a thousand impacts.
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics, Event};
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A pendulum of length 1.
    ///     pub struct Pendulum { params { } drivers { phi } unknowns { } points { G = polar(1.0, phi); } }
    /// }
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("bob", 1.0).center("G").angle("phi"))
    ///     .gravity([0.0, -9.81, 0.0])
    ///     .build::<Pendulum>()?;
    /// // Released from horizontal onto a stop at the bottom, e = 0.5.
    /// let run = dynamics
    ///     .forward(&Pendulum {}, &PendulumCoords { phi: 0.0 })
    ///     .until(0.6)
    ///     .tolerance(1e-11)
    ///     .stop_when(Event::stop("phi", -std::f64::consts::FRAC_PI_2, 0.5))
    ///     .run()?;
    /// let hit = &run.impacts[0];
    /// // It hits at √(2 g l) / l and leaves at half that, backwards.
    /// assert!((hit.before + (2.0f64 * 9.81).sqrt()).abs() < 1e-8);
    /// assert!((hit.after + 0.5 * hit.before).abs() < 1e-12);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    #[must_use]
    pub fn stop(coordinate: &str, value: f64, restitution: f64) -> Self {
        Event {
            coordinate: coordinate.into(),
            rate: false,
            value,
            direction: 0,
            restitution: Some(restitution),
        }
    }

    /// The rate of `coordinate` reaching `value`, from either side.
    #[must_use]
    pub fn rate_reaches(coordinate: &str, value: f64) -> Self {
        Event {
            coordinate: coordinate.into(),
            rate: true,
            value,
            direction: 0,
            restitution: None,
        }
    }

    /// The same event, counted only where the coordinate (or its rate)
    /// reaches the value while increasing: a crank passing an angle
    /// forward, a speed reached on the way up. A value already reached at
    /// the start counts from when the motion leaves it, whichever way it
    /// leaves. On a stop ([`Event::stop`]) it makes a one-way stop: the
    /// motion bounces off it coming from below and passes it coming from
    /// above.
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics, Ended, Event};
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A pendulum of length 1.
    ///     pub struct Pendulum { params { } drivers { phi } unknowns { } points { G = polar(1.0, phi); } }
    /// }
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("bob", 1.0).center("G").angle("phi"))
    ///     .gravity([0.0, -9.81, 0.0])
    ///     .build::<Pendulum>()?;
    /// // Released from horizontal (φ = 0), it swings down through −π/2
    /// // and up to −π on the far side, then back: φ = −2 is passed first
    /// // decreasing, and increasing only on the way back.
    /// let run = |event: Event| {
    ///     dynamics
    ///         .forward(&Pendulum {}, &PendulumCoords { phi: 0.0 })
    ///         .until(5.0)
    ///         .tolerance(1e-11)
    ///         .stop_when(event)
    ///         .run()
    /// };
    /// let down = run(Event::reaches("phi", -2.0))?;
    /// let back = run(Event::reaches("phi", -2.0).increasing())?;
    /// let (Ended::Event { at: t1, .. }, Ended::Event { at: t2, .. }) = (down.ended, back.ended) else {
    ///     panic!("both end at the event");
    /// };
    /// assert!(t2 > t1);
    /// assert!(back.sweep.samples.last().unwrap().motion.qd.phi > 0.0);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    #[must_use]
    pub fn increasing(self) -> Self {
        Event {
            direction: 1,
            ..self
        }
    }

    /// The same event, counted only where the value is reached while
    /// decreasing ([`Event::increasing`]'s converse).
    #[must_use]
    pub fn decreasing(self) -> Self {
        Event {
            direction: -1,
            ..self
        }
    }
}

/// The integrator of a forward simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Dormand and Prince's explicit pair of orders 5(4), with dense
    /// output of order 4: the default, for motions that are not stiff.
    #[default]
    Explicit,
    /// TR-BDF2, implicit and L-stable, of order 2 with an embedded
    /// third-order error estimate, its Jacobian by finite differences:
    /// for stiff motions (a stiff spring, large damping), where the
    /// explicit pair's steps are held by its stability, not by the
    /// accuracy asked for.
    Implicit,
}

/// How a forward simulation ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Ended {
    /// At its end time.
    Complete,
    /// At the event of this index (in the order given), located at the
    /// time `at` to the resolution of the time.
    Event {
        /// The event's index.
        index: usize,
        /// When.
        at: f64,
    },
    /// The motion could not go on past `at` (the sweep's `stop` says why:
    /// a limit position or a singular pose met, located by shortening the
    /// step to the resolution of the time; a load not finite).
    Failed {
        /// The last time reached.
        at: f64,
    },
    /// The step limit ([`Forward::max_steps`]) was reached at `at`.
    StepLimit {
        /// The last time reached.
        at: f64,
    },
}

impl Ended {
    /// Whether the simulation reached its end time.
    #[must_use]
    pub fn is_complete(&self) -> bool {
        *self == Ended::Complete
    }
}

/// An impact at a stop ([`Event::stop`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// When (s).
    pub t: f64,
    /// The stop's index among the events.
    pub event: usize,
    /// The coordinate's rate before and after.
    pub before: f64,
    /// After: −e times `before`.
    pub after: f64,
}

/// The energies and works at one sample of a forward simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Energy {
    /// The time (s).
    pub t: f64,
    /// T = Σ ½ m |v_G|² + ½ ω · J ω (J).
    pub kinetic: f64,
    /// V = −Σ m g · r_G + Σ ½ k (L − L₀)² (J).
    pub potential: f64,
    /// The work done since the start by each load and prescribed driver
    /// ([`Trajectory::work_names`]), J.
    pub work: Vec<f64>,
    /// Each driver's effort at the sample (zero for a free one; for a
    /// prescribed one, what it must supply to follow its profile).
    pub effort: Vec<f64>,
}

impl Energy {
    /// T + V − Σ W: constant in an exact solution.
    #[must_use]
    pub fn balance(&self) -> f64 {
        self.kinetic + self.potential - self.work.iter().sum::<f64>()
    }
}

/// The sensitivities of a trajectory at one sample: ∂d_f/∂p and ∂ḋ_f/∂p
/// of the free drivers for each sensitivity parameter p, by the forward
/// sensitivity equations integrated with the motion: with S = ∂(d_f,
/// ḋ_f)/∂p, Ṡ = (S_ḋ, ∂d̈_f/∂(d_f, ḋ_f) S + ∂d̈_f/∂p), where
/// ∂d̈_f/∂p = −M_ff⁻¹ ∂Q_f/∂p comes from the compiled partial derivatives
/// of the efforts (the definition's `sensitivities` section; exact) and
/// ∂d̈_f/∂(d_f, ḋ_f) from central differences of the equations of motion
/// at the state (to about 1e-10 of it). S starts at zero: the start pose
/// and rates are given, not derived from p.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivities {
    /// The time (s).
    pub t: f64,
    /// ∂d_f/∂p, parameter-major: entry `p * free + i` for parameter p and
    /// free driver i (in the order the drivers are declared).
    pub position: Vec<f64>,
    /// ∂ḋ_f/∂p, laid out as `position`.
    pub rate: Vec<f64>,
}

impl Sensitivities {
    /// The sensitivities at time t from the integrated state `s` (for each
    /// parameter, ∂d_f then ∂ḋ_f), `free` drivers.
    pub(crate) fn from_state(t: f64, s: &[f64], free: usize) -> Self {
        let (mut position, mut rate) = (Vec::new(), Vec::new());
        for chunk in s.chunks(2 * free.max(1)) {
            position.extend_from_slice(&chunk[..free.min(chunk.len())]);
            rate.extend_from_slice(&chunk[free.min(chunk.len())..]);
        }
        Sensitivities { t, position, rate }
    }
}

/// The counts of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Statistics {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (the error too large, or a stage past a limit).
    pub rejected: usize,
    /// Evaluations of the equations of motion (each an assembly, an
    /// analysis, M and b, and a solve with M).
    pub evaluations: usize,
    /// The evaluations of M and b (the integrator's, and those at the
    /// output samples, the impacts and, with sensitivities, the
    /// differences of the accelerations) that the model's compiled
    /// equations of motion gave: M = Cᵀ M̃ C, b = Cᵀ f̃ from one call of
    /// the code compiled from its `bodies` and `loads` sections. All of
    /// them where the description is the model's own sections
    /// (`dynamics()`, at the model's parameter values), none where it
    /// was built or changed otherwise.
    pub compiled: usize,
    /// The evaluations of M and b that summed the bodies and loads, with
    /// one unit analysis per driver (a description not the model's own
    /// sections, or a pose where the compiled equations gave no finite
    /// value and the sums say why).
    pub summed: usize,
}

/// The result of a forward simulation: its samples as a sweep in time
/// (variable `t`; every output of a sweep applies: CSV, plots,
/// animation), the energies and works at each sample, and how it ended.
#[derive(Debug, Clone)]
pub struct Trajectory<M: Mechanism> {
    /// The samples at the output times (and at the event that ended it,
    /// if one did), each with q, q̇, q̈ and every point's motion.
    pub sweep: Sweep<M>,
    /// The energies and works at each sample.
    pub energy: Vec<Energy>,
    /// The names of the works of [`Energy::work`]: `force at P`,
    /// `torque on body`, `force on coordinate`, `damper A-B`, then
    /// `driver d` for each prescribed driver.
    pub work_names: Vec<String>,
    /// The impacts at the stops, in order.
    pub impacts: Vec<Impact>,
    /// The sensitivity parameters (empty unless
    /// [`Forward::sensitivities`] asked for them).
    pub parameters: Vec<String>,
    /// At each sample, the sensitivities of the free drivers' positions
    /// and rates to each of `parameters`.
    pub sensitivities: Vec<Sensitivities>,
    /// How it ended.
    pub ended: Ended,
    /// Steps and evaluations.
    pub statistics: Statistics,
}

impl<M: Mechanism> Trajectory<M> {
    /// The largest change of T + V − Σ W over the run, relative to the
    /// energy that moves in it, max T + (max V − min V) + max |W| (so that
    /// where the origin of V lies does not matter; 0 for a run of one
    /// sample): how well the energy balance holds. With
    /// [`Method::Implicit`] the works are quadratures of its order 2,
    /// not error-controlled, and this measures them too.
    #[must_use]
    pub fn energy_error(&self) -> f64 {
        energy_error(&self.energy)
    }
}

/// The largest change of T + V − Σ W over `energy`, relative to
/// max T + (max V − min V) + max |W|.
pub(crate) fn energy_error(energy: &[Energy]) -> f64 {
    let Some(first) = energy.first() else {
        return 0.0;
    };
    let e0 = first.balance();
    let (mut kinetic, mut works): (f64, f64) = (0.0, 0.0);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut worst: f64 = 0.0;
    for e in energy {
        kinetic = kinetic.max(e.kinetic.abs());
        (low, high) = (low.min(e.potential), high.max(e.potential));
        for w in &e.work {
            works = works.max(w.abs());
        }
        worst = worst.max((e.balance() - e0).abs());
    }
    let scale = kinetic + (high - low) + works;
    if scale > 0.0 { worst / scale } else { worst }
}
