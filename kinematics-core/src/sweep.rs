//! Full-cycle sweeps and time-driven simulations, and their results as
//! tables.
//!
//! A sweep advances one driver in equal steps. At each step the unknowns
//! are predicted from the previous step's rates (u + (du/dd)·Δd) and
//! corrected by Newton–Raphson, which keeps the assembly branch. It never
//! switches branch silently: it stops, returning the samples it has and the
//! reason, when the mechanism cannot be assembled, when Φ_u is singular, or
//! when det Φ_u changes sign between two steps (the mechanism passed a dead
//! or toggle position, where the branches meet).

use alloc::borrow::ToOwned;
use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;
use core::fmt::Write as _;

use crate::{Coordinates, Error, Kind, Mechanism, MotionState, Options, PointState, Role};

/// One instant of a sweep.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # use kinematics_core::{sweep::sweep, Options};
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = sweep(&m, &start, 0, 0.0, 1.0, 10, 6.0, 0.0, &Options::DEFAULT);
/// let last = &s.samples[10];
/// assert_eq!((last.at, last.motion.q.phi), (1.0, 1.0));
/// assert!(last.residual < 1e-12);
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Sample<M: Mechanism> {
    /// Value of the swept driver (or the time, for a simulation).
    pub at: f64,
    /// Coordinates, rates, accelerations, points and frames.
    pub motion: M::Motion,
    /// max|Φ_i| at the solved pose: how well the loops close.
    pub residual: f64,
}

/// Why and where a sweep stopped before its end.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// use kinematics_core::{sweep::sweep, Options};
/// // a > b: the rod cannot follow the crank past sin φ = b / a.
/// let m = SliderCrank { a: 0.3, b: 0.2 };
/// let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.5 };
/// let s = sweep(&m, &start, 0, 0.0, 1.5, 150, 1.0, 0.0, &Options::DEFAULT);
/// let stop = s.stop.expect("stops before 1.5 rad");
/// assert!(stop.at > 0.6 && stop.at < 0.8); // asin(2/3) = 0.73
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Stop {
    /// Value of the swept driver (or the time) at which it could not go on.
    pub at: f64,
    /// The reason.
    pub reason: Error,
}

/// The samples of a sweep, and how it ended.
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # use kinematics_core::{sweep::sweep, Options};
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = sweep(&m, &start, 0, 0.0, std::f64::consts::TAU, 360, 6.0, 0.0, &Options::DEFAULT);
/// assert_eq!((s.variable, s.samples.len()), ("phi", 361));
/// assert!(s.stop.is_none());
/// ```
#[derive(Debug, Clone)]
pub struct Sweep<M: Mechanism> {
    /// Name of the swept driver, or "t" for a simulation.
    pub variable: &'static str,
    /// The samples, in order.
    pub samples: Vec<Sample<M>>,
    /// `Some` when the sweep stopped early.
    pub stop: Option<Stop>,
}

/// Sweeps driver `driver` (index among the drivers) from `from` to `to` in
/// `steps` equal steps, the other drivers held at their values in `start`
/// (at rest), with the swept driver's rate d' = `rate` and acceleration
/// d'' = `acceleration` at every sample. `start` gives the first pose's
/// guess. A `driver` that is not the index of a driver gives no samples and
/// a [`Stop`] with [`Error::InvalidOption`].
///
/// ```
/// use kinematics_core::{mechanism, sweep::sweep, Options};
/// mechanism! {
///     /// A slider-crank.
///     pub struct SliderCrank {
///         params { a, b }
///         drivers { phi }
///         unknowns { th, x }
///         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///     }
/// }
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = sweep(&m, &start, 0, 0.0, std::f64::consts::TAU, 360, 10.0, 0.0, &Options::DEFAULT);
/// assert!(s.stop.is_none() && s.samples.len() == 361);
/// assert_eq!(s.is_periodic(1e-9), Some(true));
/// ```
#[allow(clippy::too_many_arguments)]
pub fn sweep<M: Mechanism>(
    m: &M,
    start: &M::Coords,
    driver: usize,
    from: f64,
    to: f64,
    steps: usize,
    rate: f64,
    acceleration: f64,
    options: &Options,
) -> Sweep<M> {
    if driver >= M::DRIVERS {
        return Sweep {
            variable: "?",
            samples: Vec::new(),
            stop: Some(Stop {
                at: from,
                reason: Error::InvalidOption {
                    name: "driver",
                    #[allow(clippy::cast_precision_loss)]
                    value: driver as f64,
                    requirement: "must be the index of a driver, from 0 to DRIVERS − 1 in \
                                  declaration order",
                },
            }),
        };
    }
    let variable = M::COORDINATES.get(driver).map_or("?", |c| c.name);
    let steps = steps.max(1);
    #[allow(clippy::cast_precision_loss)]
    let value = |k: usize| from + (to - from) * (k as f64) / (steps as f64);
    let drive = |pose: &mut M::Coords, v: f64, rates: &mut [f64], accels: &mut [f64]| {
        pose.set(driver, v);
        if let (Some(r), Some(a)) = (rates.get_mut(driver), accels.get_mut(driver)) {
            *r = rate;
            *a = acceleration;
        }
    };
    run(
        m, start, variable, steps, value, drive, driver, rate, options,
    )
}

/// Simulates the motion at the times `times` with the drivers following a
/// profile: `profile(t, d, d', d'')` writes the drivers' values, rates and
/// accelerations at time t (see [`constant_speed`] and
/// [`constant_acceleration`] for the common cases, which drive the first
/// driver). A driver the profile does not write keeps its value in `start`,
/// at rest (d' = d'' = 0).
///
/// ```
/// use kinematics_core::{mechanism, sweep::{simulate, constant_acceleration}, Options};
/// mechanism! {
///     /// A slider-crank.
///     pub struct SliderCrank {
///         params { a, b }
///         drivers { phi }
///         unknowns { th, x }
///         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///     }
/// }
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let times: Vec<f64> = (0..=100).map(|k| f64::from(k) * 0.01).collect();
/// // The crank starts from rest with φ'' = 20 rad/s².
/// let s = simulate(&m, &start, &times, constant_acceleration(0.0, 0.0, 20.0), &Options::DEFAULT);
/// assert!(s.stop.is_none());
/// let last = &s.samples[100].motion;
/// assert!((last.qd.phi - 20.0).abs() < 1e-12 && (last.q.phi - 10.0).abs() < 1e-12);
/// ```
pub fn simulate<M: Mechanism>(
    m: &M,
    start: &M::Coords,
    times: &[f64],
    mut profile: impl FnMut(f64, &mut [f64], &mut [f64], &mut [f64]),
    options: &Options,
) -> Sweep<M> {
    let mut d: Vec<f64> = (0..M::DRIVERS)
        .map(|j| start.get(j).unwrap_or(0.0))
        .collect();
    let steps = times.len().saturating_sub(1);
    let value = |k: usize| times.get(k).copied().unwrap_or(f64::NAN);
    if times.is_empty() {
        return Sweep {
            variable: "t",
            samples: Vec::new(),
            stop: None,
        };
    }
    let drive = |pose: &mut M::Coords, t: f64, rates: &mut [f64], accels: &mut [f64]| {
        profile(t, &mut d, rates, accels);
        for (j, v) in d.iter().enumerate() {
            pose.set(j, *v);
        }
    };
    run(m, start, "t", steps, value, drive, usize::MAX, 0.0, options)
}

/// The first driver turning at constant speed ω from d₀: d = d₀ + ω t,
/// d' = ω, d'' = 0 (the others keep their start values).
///
/// ```
/// # use kinematics_core::mechanism;
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # use kinematics_core::{sweep::sweep, Options};
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// use kinematics_core::sweep::{constant_speed, simulate};
/// let times: Vec<f64> = (0..=10).map(|k| f64::from(k) * 0.01).collect();
/// let s = simulate(&m, &start, &times, constant_speed(0.0, 6.0), &Options::DEFAULT);
/// assert!((s.samples[10].motion.q.phi - 0.6).abs() < 1e-15);
/// ```
pub fn constant_speed(d0: f64, speed: f64) -> impl FnMut(f64, &mut [f64], &mut [f64], &mut [f64]) {
    constant_acceleration(d0, speed, 0.0)
}

/// The first driver with constant acceleration: d = d₀ + ω₀ t + ½ α t²,
/// d' = ω₀ + α t, d'' = α (the others keep their start values).
///
/// ```
/// use kinematics_core::sweep::constant_acceleration;
/// let mut profile = constant_acceleration(0.0, 1.0, 2.0);
/// let (mut d, mut dd, mut ddd) = ([0.0], [0.0], [0.0]);
/// profile(3.0, &mut d, &mut dd, &mut ddd);
/// assert_eq!((d[0], dd[0], ddd[0]), (12.0, 7.0, 2.0));
/// ```
pub fn constant_acceleration(
    d0: f64,
    speed: f64,
    acceleration: f64,
) -> impl FnMut(f64, &mut [f64], &mut [f64], &mut [f64]) {
    move |t, d, dd, ddd| {
        if let (Some(d), Some(dd), Some(ddd)) = (d.first_mut(), dd.first_mut(), ddd.first_mut()) {
            *d = d0 + speed * t + 0.5 * acceleration * t * t;
            *dd = speed + acceleration * t;
            *ddd = acceleration;
        }
    }
}

/// The common loop: at sample k, `drive` sets the drivers of the guess for
/// the value `value(k)` and returns their rates and accelerations.
#[allow(clippy::too_many_arguments)]
fn run<M: Mechanism>(
    m: &M,
    start: &M::Coords,
    variable: &'static str,
    steps: usize,
    value: impl Fn(usize) -> f64,
    mut drive: impl FnMut(&mut M::Coords, f64, &mut [f64], &mut [f64]),
    swept: usize,
    rate: f64,
    options: &Options,
) -> Sweep<M> {
    let nd = M::DRIVERS;
    let nq = nd + M::UNKNOWNS;
    let mut samples: Vec<Sample<M>> = Vec::with_capacity(steps + 1);
    let mut rates = vec![0.0; nd];
    let mut accels = vec![0.0; nd];
    let mut previous: Option<(M::Coords, M::Coords, f64, f64)> = None; // pose, rates, at, det sign
                                                                       // The stepper's state: options and parameters checked once, the modes
                                                                       // and the sines and cosines of each pose carried to the next.
    let mut state = match m.step_state(options) {
        Ok(state) => state,
        Err(reason) => {
            return Sweep {
                variable,
                samples,
                stop: Some(Stop {
                    at: value(0),
                    reason,
                }),
            }
        }
    };
    for k in 0..=steps {
        let at = value(k);
        let mut guess = previous.as_ref().map_or(*start, |(pose, _, _, _)| *pose);
        drive(&mut guess, at, &mut rates, &mut accels);
        // Predictor: u + (du/dd) Δd along the swept driver (or the time).
        if let Some((pose, qd, prev_at, _)) = &previous {
            let delta = at - prev_at;
            let scale = if swept == usize::MAX {
                delta
            } else if rate != 0.0 {
                delta / rate
            } else {
                0.0
            };
            for j in nd..nq {
                if let (Some(u), Some(ud)) = (pose.get(j), qd.get(j)) {
                    guess.set(j, u + ud * scale);
                }
            }
        }
        let motion = match m.step_carried(&guess, &rates, &accels, &mut state) {
            Ok(motion) => motion,
            Err(reason) => {
                let stop = match (&reason, &previous) {
                    (Error::CannotAssemble { unknowns, .. }, Some((pose, _, prev_at, _))) => {
                        let limit = limit_position(m, pose, *prev_at, at, &mut drive, options);
                        Stop {
                            at: limit,
                            reason: Error::LimitPosition {
                                variable,
                                at: limit,
                                unknowns,
                            },
                        }
                    }
                    _ => Stop { at, reason },
                };
                return Sweep {
                    variable,
                    samples,
                    stop: Some(stop),
                };
            }
        };
        let pose = *motion.q();
        let sign = motion.det_sign();
        if let Some((_, _, prev_at, prev_sign)) = &previous {
            if sign * prev_sign < 0.0 {
                return Sweep {
                    variable,
                    samples,
                    stop: Some(Stop {
                        at,
                        reason: Error::PassedSingularity {
                            variable,
                            from: *prev_at,
                            to: at,
                        },
                    }),
                };
            }
        }
        samples.push(Sample {
            at,
            motion,
            residual: motion.residual(),
        });
        previous = Some((pose, *motion.qd(), at, sign));
    }
    Sweep {
        variable,
        samples,
        stop: None,
    }
}

/// The limit position between `good` (where the mechanism assembled, at
/// `pose`) and `bad` (where a closed-form block has no real solution): the
/// last value that assembles, by bisection to the resolution of `f64`.
fn limit_position<M: Mechanism>(
    m: &M,
    pose: &M::Coords,
    mut good: f64,
    mut bad: f64,
    drive: &mut impl FnMut(&mut M::Coords, f64, &mut [f64], &mut [f64]),
    options: &Options,
) -> f64 {
    let nd = M::DRIVERS;
    let (mut rates, mut accels) = (vec![0.0; nd], vec![0.0; nd]);
    for _ in 0..200 {
        let mid = good + 0.5 * (bad - good);
        if mid == good || mid == bad {
            break;
        }
        let mut guess = *pose;
        drive(&mut guess, mid, &mut rates, &mut accels);
        match m.step_slices(&guess, &rates, &accels, options) {
            Err(Error::CannotAssemble { .. }) => bad = mid,
            // Assembled, or assembled at a pose too near the limit for its
            // velocities (a singular Jacobian): this side of the limit.
            _ => good = mid,
        }
    }
    good
}

impl<M: Mechanism> Sweep<M> {
    /// Whether the last sample returns to the first pose: every unknown
    /// within `tolerance`, angles compared modulo 2π. `None` for a sweep that
    /// stopped early or has fewer than two samples.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # use kinematics_core::{sweep::sweep, Options};
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = sweep(&m, &start, 0, 0.0, std::f64::consts::TAU, 360, 6.0, 0.0, &Options::DEFAULT);
    /// assert_eq!(s.is_periodic(1e-9), Some(true));
    /// ```
    #[must_use]
    pub fn is_periodic(&self, tolerance: f64) -> Option<bool> {
        if self.stop.is_some() || self.samples.len() < 2 {
            return None;
        }
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        let ok = M::COORDINATES.iter().enumerate().all(|(j, c)| {
            if c.role == Role::Driver {
                return true;
            }
            let (a, b) = (first.motion.q().get(j), last.motion.q().get(j));
            let (Some(a), Some(b)) = (a, b) else {
                return false;
            };
            let d = if c.kind == Kind::Angle {
                crate::math::rem_euclid(b - a + core::f64::consts::PI, core::f64::consts::TAU)
                    - core::f64::consts::PI
            } else {
                b - a
            };
            d.abs() <= tolerance
        });
        Some(ok)
    }

    /// Largest closure residual over the samples.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # use kinematics_core::{sweep::sweep, Options};
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = sweep(&m, &start, 0, 0.0, 1.0, 100, 6.0, 0.0, &Options::DEFAULT);
    /// assert!(s.max_residual() < 1e-12);
    /// ```
    #[must_use]
    pub fn max_residual(&self) -> f64 {
        self.samples.iter().fold(0.0f64, |a, s| a.max(s.residual))
    }

    /// Column headers: the sweep variable, every coordinate's q, q', q''
    /// (with units for angles), every point's position, velocity and
    /// acceleration components, every frame's ω and α.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # use kinematics_core::{sweep::sweep, Options};
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = sweep(&m, &start, 0, 0.0, 1.0, 10, 6.0, 0.0, &Options::DEFAULT);
    /// let h = s.headers();
    /// assert_eq!(h.len(), s.row(&s.samples[0]).len());
    /// assert!(h.iter().any(|c| c.contains("phi")));
    /// ```
    #[must_use]
    pub fn headers(&self) -> Vec<String> {
        let unit = |k: Kind, d: &str| match k {
            Kind::Angle => format!(" (rad{d})"),
            Kind::Length => String::new(),
        };
        let mut h = vec![self.variable.to_owned()];
        for c in M::COORDINATES {
            h.push(format!("{}{}", c.name, unit(c.kind, "")));
            h.push(format!("{}'{}", c.name, unit(c.kind, "/s")));
            h.push(format!("{}''{}", c.name, unit(c.kind, "/s^2")));
        }
        let axes = ["x", "y", "z"];
        for p in M::POINT_NAMES {
            // Position, velocity (v) and acceleration (a) components.
            for prefix in ["", "v", "a"] {
                for axis in axes.iter().take(M::POINT_DIM) {
                    h.push(format!("{p}.{prefix}{axis}"));
                }
            }
        }
        for f in M::FRAME_NAMES {
            for (short, unit) in [("w", "rad/s"), ("alpha", "rad/s^2")] {
                for axis in axes {
                    h.push(format!("{f}.{short}{axis} ({unit})"));
                }
            }
        }
        h
    }

    /// The values of one sample, in the order of [`Sweep::headers`].
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # use kinematics_core::{sweep::sweep, Options};
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = sweep(&m, &start, 0, 0.0, 1.0, 10, 6.0, 0.0, &Options::DEFAULT);
    /// assert_eq!(s.row(&s.samples[10])[0], 1.0); // the swept value first
    /// ```
    #[must_use]
    pub fn row(&self, sample: &Sample<M>) -> Vec<f64> {
        let mo = &sample.motion;
        let mut r = vec![sample.at];
        for j in 0..M::COORDINATES.len() {
            for c in [mo.q(), mo.qd(), mo.qdd()] {
                r.push(c.get(j).unwrap_or(f64::NAN));
            }
        }
        for p in mo.points() {
            r.extend_from_slice(p.position());
            r.extend_from_slice(p.velocity());
            r.extend_from_slice(p.acceleration());
        }
        for f in mo.frames() {
            r.extend(
                f.angular_velocity
                    .iter()
                    .chain(f.angular_acceleration.iter()),
            );
        }
        r
    }

    /// The samples as CSV: a header line, then one line per sample.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # use kinematics_core::{sweep::sweep, Options};
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = sweep(&m, &start, 0, 0.0, 1.0, 10, 6.0, 0.0, &Options::DEFAULT);
    /// assert_eq!(s.to_csv().lines().count(), 1 + 11); // a header, then a line per sample
    /// ```
    #[must_use]
    pub fn to_csv(&self) -> String {
        let mut out = self.headers().join(",");
        out.push('\n');
        for s in &self.samples {
            let row: Vec<String> = self.row(s).iter().map(|v| format!("{v:.12e}")).collect();
            out += &row.join(",");
            out.push('\n');
        }
        out
    }

    /// The samples as an aligned plain-text table, every `every`-th sample
    /// (the last one always included).
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # use kinematics_core::{sweep::sweep, Options};
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = sweep(&m, &start, 0, 0.0, 1.0, 10, 6.0, 0.0, &Options::DEFAULT);
    /// print!("{}", s.to_text(5)); // every fifth sample, in aligned columns
    /// ```
    #[must_use]
    pub fn to_text(&self, every: usize) -> String {
        let headers = self.headers();
        let width = headers
            .iter()
            .map(|h| h.chars().count())
            .max()
            .unwrap_or(8)
            .max(12);
        let mut out = String::new();
        for h in &headers {
            let _ = write!(out, "{h:>width$} ");
        }
        out.push('\n');
        let n = self.samples.len();
        for (k, s) in self.samples.iter().enumerate() {
            if k % every.max(1) != 0 && k + 1 != n {
                continue;
            }
            for v in self.row(s) {
                let _ = write!(out, "{v:>width$.5} ");
            }
            out.push('\n');
        }
        out
    }
}
