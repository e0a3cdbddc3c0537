//! The interface every `mechanism!` definition implements.

use nalgebra::{Matrix3, SVector};

use crate::error::Error;

use crate::options::Options;

mod frame;
pub use frame::FrameState;

/// Role of a coordinate in the model.
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
/// use kinematics_core::{Mechanism, Role};
/// let roles: Vec<Role> = SliderCrank::COORDINATES.iter().map(|c| c.role).collect();
/// assert_eq!(roles, [Role::Driver, Role::Unknown, Role::Unknown]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Role {
    /// Prescribed input (its value, rate and acceleration are given).
    Driver,
    /// Solved for from the loop-closure equations.
    Unknown,
}

/// Whether a coordinate is an angle or a length.
///
/// A coordinate is an angle when it appears inside `sin`, `cos`, `tan` or as
/// the angle of `polar`; its rate is then an angular velocity ω (rad/s, about
/// the axis normal to the plane, counter-clockwise positive) and its second
/// derivative an angular acceleration α (rad/s²). Otherwise it is a length
/// (a slider position) with linear rate and acceleration.
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
/// use kinematics_core::{Kind, Mechanism};
/// let kinds: Vec<Kind> = SliderCrank::COORDINATES.iter().map(|c| c.kind).collect();
/// assert_eq!(kinds, [Kind::Angle, Kind::Angle, Kind::Length]); // φ, θ, x
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Kind {
    /// An angle in radians.
    Angle,
    /// A length, in the units of the parameters.
    Length,
}

/// Static description of one coordinate.
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
/// use kinematics_core::{Kind, Mechanism, Role};
/// let x = &SliderCrank::COORDINATES[2];
/// assert_eq!((x.name, x.role, x.kind), ("x", Role::Unknown, Kind::Length));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Coordinate {
    /// Name as declared.
    pub name: &'static str,
    /// Driver or unknown.
    pub role: Role,
    /// Angle or length.
    pub kind: Kind,
}

/// Position, velocity and acceleration of a point in the fixed frame
/// (D = 2 for planar mechanisms, 3 for spatial ones):
/// r, v = dr/dt = r_q q', a = dv/dt = r_q q'' + (r_q q')_q q'.
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
/// # fn main() -> Result<(), kinematics_core::Error> {
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let pose = m.assemble(&SliderCrankCoords { phi: 0.5, th: 0.0, x: 0.4 })?;
/// let b = *m.analyze(&pose, 10.0, 0.0)?.point_b();
/// // The crank pin at constant speed: |v| = aω, |a| = aω², all normal.
/// assert!((b.speed() - 1.0).abs() < 1e-12);
/// assert!((b.normal_acceleration() - 10.0).abs() < 1e-12);
/// assert!(b.tangential_acceleration().abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PointMotion<const D: usize = 2> {
    /// Position r.
    pub position: SVector<f64, D>,
    /// Velocity v = dr/dt.
    pub velocity: SVector<f64, D>,
    /// Acceleration a = d²r/dt².
    pub acceleration: SVector<f64, D>,
}

impl<const D: usize> PointMotion<D> {
    /// Speed |v|.
    ///
    /// ```
    /// use kinematics_core::{nalgebra::Vector2, PointMotion};
    /// let p = PointMotion { position: Vector2::zeros(), velocity: Vector2::new(3.0, 4.0), acceleration: Vector2::zeros() };
    /// assert_eq!(p.speed(), 5.0);
    /// ```
    #[must_use]
    pub fn speed(&self) -> f64 {
        self.velocity.norm()
    }

    /// Magnitude of the acceleration |a|.
    ///
    /// ```
    /// use kinematics_core::{nalgebra::Vector2, PointMotion};
    /// let p = PointMotion { position: Vector2::zeros(), velocity: Vector2::zeros(), acceleration: Vector2::new(6.0, 8.0) };
    /// assert_eq!(p.acceleration_magnitude(), 10.0);
    /// ```
    #[must_use]
    pub fn acceleration_magnitude(&self) -> f64 {
        self.acceleration.norm()
    }

    /// Tangential acceleration a·v/|v| (the rate of change of speed); zero
    /// when the point is at rest.
    ///
    /// ```
    /// use kinematics_core::{nalgebra::Vector2, PointMotion};
    /// // Moving along x and speeding up at 2 m/s² while turning at 3 m/s².
    /// let p = PointMotion { position: Vector2::zeros(), velocity: Vector2::new(1.0, 0.0), acceleration: Vector2::new(2.0, 3.0) };
    /// assert_eq!(p.tangential_acceleration(), 2.0);
    /// ```
    #[must_use]
    pub fn tangential_acceleration(&self) -> f64 {
        let s = self.speed();
        if s > 0.0 {
            self.acceleration.dot(&self.velocity) / s
        } else {
            0.0
        }
    }

    /// Normal (centripetal) acceleration √(|a|² − a_t²), toward the centre of
    /// curvature of the path; zero when the point is at rest.
    ///
    /// ```
    /// use kinematics_core::{nalgebra::Vector2, PointMotion};
    /// let p = PointMotion { position: Vector2::zeros(), velocity: Vector2::new(1.0, 0.0), acceleration: Vector2::new(2.0, 3.0) };
    /// assert!((p.normal_acceleration() - 3.0).abs() < 1e-15);
    /// ```
    #[must_use]
    pub fn normal_acceleration(&self) -> f64 {
        if self.speed() > 0.0 {
            let at = self.tangential_acceleration();
            crate::math::sqrt((self.acceleration.norm_squared() - at * at).max(0.0))
        } else {
            0.0
        }
    }
}

/// Read access to a point's motion as slices, for code generic over the
/// dimension.
///
/// ```
/// use kinematics_core::{nalgebra::Vector3, PointMotion, PointState};
/// fn height(p: &impl PointState) -> f64 {
///     p.position().last().copied().unwrap_or(0.0)
/// }
/// let p = PointMotion { position: Vector3::new(1.0, 2.0, 3.0), velocity: Vector3::zeros(), acceleration: Vector3::zeros() };
/// assert_eq!(height(&p), 3.0);
/// ```
pub trait PointState: Copy + core::fmt::Debug {
    /// Position components.
    fn position(&self) -> &[f64];
    /// Velocity components.
    fn velocity(&self) -> &[f64];
    /// Acceleration components.
    fn acceleration(&self) -> &[f64];
}

impl<const D: usize> PointState for PointMotion<D> {
    fn position(&self) -> &[f64] {
        self.position.as_slice()
    }
    fn velocity(&self) -> &[f64] {
        self.velocity.as_slice()
    }
    fn acceleration(&self) -> &[f64] {
        self.acceleration.as_slice()
    }
}

/// Access to a coordinates struct by index (drivers first, then unknowns,
/// in declaration order).
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
/// use kinematics_core::Coordinates;
/// let mut q = SliderCrankCoords { phi: 0.5, th: 0.1, x: 0.4 };
/// assert_eq!(q.get(2), Some(0.4));
/// assert!(q.set(0, 0.7) && q.phi == 0.7);
/// assert!(!q.set(3, 1.0) && q.get(3).is_none());
/// ```
pub trait Coordinates: Copy {
    /// Value of coordinate `j`, or `None` past the last coordinate.
    fn get(&self, j: usize) -> Option<f64>;
    /// Sets coordinate `j`; returns `false` (and changes nothing) past the
    /// last coordinate.
    fn set(&mut self, j: usize, value: f64) -> bool;
}

/// Values given for the drivers: a bare `f64` for a single driver, an
/// array in declaration order, or the mechanism's coordinates struct (its
/// drivers' fields are read, the unknowns' ignored), so that the rates of
/// several drivers are given by name.
///
/// ```
/// use kinematics_core::{mechanism, DriverValues};
/// assert_eq!(10.0.into_array(), [10.0]);
/// assert_eq!([0.3, 0.5].into_array(), [0.3, 0.5]);
/// mechanism! {
///     /// A five-bar with two cranks.
///     pub struct FiveBar {
///         params { a, b, c, d, e }
///         drivers { phi1, phi2 }
///         unknowns { th2, th3 }
///         loops { polar(a, phi1) + polar(b, th2) == vec2(e, 0.0) + polar(d, phi2) + polar(c, th3); }
///     }
/// }
/// let rates = FiveBarCoords { phi1: 2.0, phi2: -1.0, ..Default::default() };
/// assert_eq!(DriverValues::<2>::into_array(rates), [2.0, -1.0]);
/// ```
pub trait DriverValues<const N: usize> {
    /// The values in declaration order.
    fn into_array(self) -> [f64; N];
}

impl<const N: usize> DriverValues<N> for [f64; N] {
    fn into_array(self) -> [f64; N] {
        self
    }
}

impl<const N: usize> DriverValues<N> for &[f64; N] {
    fn into_array(self) -> [f64; N] {
        *self
    }
}

impl DriverValues<1> for f64 {
    fn into_array(self) -> [f64; 1] {
        [self]
    }
}

/// Read access to the result of an analysis, for code generic over
/// mechanisms.
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
/// # fn main() -> Result<(), kinematics_core::Error> {
/// use kinematics_core::{Coordinates, MotionState};
/// /// The largest rate among the unknowns, for any mechanism.
/// fn fastest<S: MotionState>(s: &S, drivers: usize) -> f64 {
///     (drivers..).map_while(|j| s.qd().get(j)).fold(0.0, |a: f64, v| a.max(v.abs()))
/// }
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let pose = m.assemble(&SliderCrankCoords { phi: 1.0, th: 0.0, x: 0.3 })?;
/// let s = m.analyze(&pose, 10.0, 0.0)?;
/// assert_eq!(fastest(&s, 1), s.qd.th.abs().max(s.qd.x.abs()));
/// assert!(s.conditioning() > 0.0 && s.det_sign().abs() == 1.0);
/// # Ok(())
/// # }
/// ```
pub trait MotionState: Copy + core::fmt::Debug {
    /// The mechanism's coordinates struct.
    type Coords: Coordinates;
    /// Coordinates q.
    fn q(&self) -> &Self::Coords;
    /// Rates q'.
    fn qd(&self) -> &Self::Coords;
    /// Accelerations q''.
    fn qdd(&self) -> &Self::Coords;
    /// The coordinates q, to change (a sweep wraps the angles it reports).
    fn q_mut(&mut self) -> &mut Self::Coords;
    /// The point type: `PointMotion<2>` or `PointMotion<3>`.
    type Point: PointState;
    /// Every point's motion, in declaration order.
    fn points(&self) -> &[Self::Point];
    /// Every frame's state, in declaration order.
    fn frames(&self) -> &[FrameState];
    /// Conditioning of Φ_u at this pose: how far the configuration is from
    /// a singular one (a dead-centre or toggle position), measured so that
    /// the number means the same for any mechanism and any units.
    ///
    /// Φ_u is scaled first, Φ̃_u = diag(1/S) Φ_u diag(unit): each equation
    /// by its term scale S_i (the sum of the sizes of its terms, e.g.
    /// |a| + |b| + |c| + |d| for a four-bar loop), each unknown by its
    /// natural unit (1 rad for an angle, the mechanism's characteristic
    /// length for a length); see [`Scaling`](crate::solve::Scaling). The
    /// conditioning is then 1 / ‖Φ̃_u⁻¹‖_∞, the distance (in the ∞-norm) from
    /// Φ̃_u to the nearest singular matrix; when Φ_u is block triangular, as
    /// for a six-bar solved loop by loop, the smallest of those of its
    /// diagonal blocks. It is of order one at a well-conditioned pose and
    /// falls to 0 in proportion to the distance from a toggle position, for
    /// one unknown as for several, and it is unchanged when the mechanism
    /// is drawn in millimetres instead of metres.
    ///
    /// It bounds the accuracy of the pose: every relative residual |Φ_i| /
    /// S_i being within the tolerance τ, each unknown is within τ /
    /// conditioning of the exact pose (in radians, or in units of the
    /// characteristic length), to first order and up to twice that next to
    /// a toggle; velocities and accelerations inherit the same factor.
    /// [`Options::singularity_threshold`](crate::options::Options) refuses poses at or
    /// below a chosen value (`Error::Singular`).
    fn conditioning(&self) -> f64;
    /// Sign of det Φ_u at this pose, ±1 (1 when there are no unknowns): the
    /// assembly branch, which changes only through a singular
    /// configuration (see [`Options::branch`](crate::options::Options)).
    fn det_sign(&self) -> f64;
    /// max |Φ_i| at this pose, in the equations' units (metres for a
    /// planar loop): how well the loops close.
    fn residual(&self) -> f64;
}

/// A pose solved without its motion: what a positions-only step
/// ([`Mechanism::pose_carried`], a stepper's `pose`, a sweep's
/// [`poses`](crate::sweep::SweepBuilder::poses)) returns: the coordinates,
/// the points' positions (the mechanism's `…Positions`, a field per point
/// by name), and the diagnostics of [`MotionState`] at the same pose. The
/// points come from the sines and cosines the solve already has, with no
/// trigonometric call of their own.
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
/// # fn main() -> Result<(), kinematics_core::Error> {
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// let mut stepper = m.stepper(&kinematics_core::Options::DEFAULT)?;
/// let pose = stepper.pose(&SliderCrankCoords { phi: 0.5, th: 0.0, x: 0.4 })?;
/// // x = a cos φ + √(b² − a² sin² φ) on the branch of the guess.
/// let x = 0.1 * 0.5f64.cos() + (0.09 - 0.01 * 0.5f64.sin().powi(2)).sqrt();
/// assert!((pose.q.x - x).abs() < 1e-15);
/// assert!((pose.points.C.x - x).abs() < 1e-15 && pose.points.C.y == 0.0);
/// assert!(pose.conditioning > 0.0 && pose.residual < 1e-15);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Pose<C, P> {
    /// The drivers and the solved unknowns.
    pub q: C,
    /// The points' positions, by name.
    pub points: P,
    /// The conditioning of Φ_u at `q` (see [`MotionState::conditioning`]).
    pub conditioning: f64,
    /// The sign of det Φ_u at `q`, ±1 (see [`MotionState::det_sign`]).
    pub det_sign: f64,
    /// max |Φ_i| at `q`, in the equations' units.
    pub residual: f64,
}

/// A mechanism declared with [`mechanism!`](crate::mechanism).
///
/// Coordinates q = (d, u): drivers d then unknowns u. Constraints Φ(q) = 0,
/// as many scalar equations as unknowns. The macro generates Φ, the Jacobian
/// Φ_u, the velocity right-hand side −Φ_d d' and the acceleration right-hand
/// side −Φ_d d'' − γ with γ = (Φ_q q')_q q', all differentiated exactly at
/// compile time. The generated type also has inherent methods with typed
/// arguments (`assemble`, `analyze`, …); this trait is for code generic over
/// mechanisms.
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
/// # fn main() -> Result<(), kinematics_core::Error> {
/// use kinematics_core::{Mechanism, Options};
/// /// The largest loop residual after assembling any mechanism.
/// fn closure<M: Mechanism>(m: &M, start: &M::Coords) -> Result<f64, kinematics_core::Error> {
///     let pose = m.assemble_with(start, &Options::DEFAULT)?;
///     let mut r = vec![0.0; M::EQUATIONS];
///     m.residual_into(&pose, &mut r);
///     Ok(r.iter().fold(0.0, |a: f64, v| a.max(v.abs())))
/// }
/// let m = SliderCrank { a: 0.1, b: 0.3 };
/// assert!(closure(&m, &SliderCrankCoords { phi: 1.0, th: 0.0, x: 0.3 })? < 1e-15);
/// assert_eq!(SliderCrank::POINT_NAMES, ["B", "C"]);
/// # Ok(())
/// # }
/// ```
pub trait Mechanism {
    /// Named coordinates (drivers then unknowns).
    type Coords: Coordinates + core::fmt::Debug + PartialEq + Default;
    /// Result of [`Mechanism::analyze_slices`]: q, q', q'' and every point's motion.
    type Motion: MotionState<Coords = Self::Coords>;
    /// Number of drivers (degrees of freedom prescribed).
    const DRIVERS: usize;
    /// Number of unknowns.
    const UNKNOWNS: usize;
    /// Number of scalar equations (equal to the number of unknowns).
    const EQUATIONS: usize;
    /// Number of points of interest.
    const POINTS: usize;
    /// Dimension of the points: 2 (planar) or 3 (spatial).
    const POINT_DIM: usize;
    /// Number of body frames.
    const FRAMES: usize;
    /// Description of each coordinate, drivers first.
    const COORDINATES: &'static [Coordinate];
    /// Point names in declaration order.
    const POINT_NAMES: &'static [&'static str];
    /// Frame names in declaration order.
    const FRAME_NAMES: &'static [&'static str];
    /// Each scalar equation as written in the definition.
    const EQUATION_NAMES: &'static [&'static str];
    /// Whether a step's guess of the unknowns sets where Newton–Raphson
    /// starts (some block is not solved in closed form), so that a sweep
    /// predicts it along the rates; where every block is in closed form,
    /// the guess only names the branch, and the previous pose does.
    #[doc(hidden)]
    const NEWTON_GUESS: bool = true;

    /// The number of values [`Mechanism::equations_of_motion`] writes, 0
    /// where the definition has no `bodies` and `loads` sections or the
    /// compiler did not form their equations (more than 24 coordinates, a
    /// loop system that is not square).
    const MOTION_OUTPUTS: usize = 0;

    /// Whether [`Mechanism::equations_of_motion`] writes the driver's M and
    /// b themselves (one driver and at most two unknowns) rather than the
    /// equations in all the coordinates.
    const MOTION_REDUCED: bool = false;

    /// The equations of motion of the definition's `bodies` and `loads`
    /// sections at this parameter set, the coordinates `q`, their rates
    /// `qd` and accelerations `qdd` and the time, as compiled. In all n
    /// coordinates: Φ_q (one row per loop equation, row-major), the upper
    /// triangle of the mass matrix M̃_ij = Σ m v_G^i · v_G^j + ω^iᵀ J ω^j
    /// row by row, the generalized forces f̃_j (the inertia and the loads
    /// at `qdd`, on coordinate j's partial velocities), then the power of
    /// each load whose work a forward simulation reports; the drivers'
    /// M = Cᵀ M̃ C and b = Cᵀ f̃ follow with the kinematic coefficients C
    /// (C_d = I, Φ_u C_u = −Φ_d). Where [`Mechanism::MOTION_REDUCED`] (one
    /// driver, at most two unknowns), M and b themselves, C written out by
    /// Cramer's rule (not finite where Φ_u is singular), then the powers.
    /// `false`, with nothing written, where `out` has not
    /// [`Mechanism::MOTION_OUTPUTS`] entries (always, without the
    /// sections).
    fn equations_of_motion(
        &self,
        q: &Self::Coords,
        qd: &Self::Coords,
        qdd: &Self::Coords,
        time: f64,
        out: &mut [f64],
    ) -> bool {
        let _ = (q, qd, qdd, time, out);
        false
    }

    /// Whether `values` are this mechanism's parameter values in
    /// declaration order, bit for bit: a description marked as made from
    /// the sections at `values` is then this mechanism's own, and its
    /// forward simulation may use [`Mechanism::equations_of_motion`].
    fn has_parameter_values(&self, values: &[f64]) -> bool {
        let _ = values;
        false
    }

    /// Solves Φ(d, u) = 0 for u, with d and a guess of u taken from
    /// `start`: each block with a closed form exactly (in the mode the
    /// guess lies in), each other block by Newton–Raphson on that block;
    /// without closed-form blocks by Newton–Raphson on the whole system,
    /// which finds the assembly branch nearest the guess.
    ///
    /// # Errors
    /// Non-finite inputs, invalid options, a singular Jacobian or no
    /// convergence, each naming the item involved.
    fn assemble_with(&self, start: &Self::Coords, options: &Options)
    -> Result<Self::Coords, Error>;

    /// Velocities and accelerations at an assembled `pose`: solves
    /// Φ_u u' = −Φ_d d' and Φ_u u'' = −Φ_d d'' − γ, then every point's
    /// velocity and acceleration. `rates` and `accelerations` hold d' and d''
    /// in declaration order.
    ///
    /// # Errors
    /// As [`Mechanism::assemble_with`]; a slice of the wrong length is an
    /// [`Error::InvalidOption`].
    fn analyze_slices(
        &self,
        pose: &Self::Coords,
        rates: &[f64],
        accelerations: &[f64],
        options: &Options,
    ) -> Result<Self::Motion, Error>;

    /// Assembles at the drivers of `start` from its unknowns and analyses
    /// the motion there, in one pass (the generated `step`): `rates` and
    /// `accelerations` hold d' and d''.
    ///
    /// # Errors
    /// As [`Mechanism::assemble_with`] and [`Mechanism::analyze_slices`].
    fn step_slices(
        &self,
        start: &Self::Coords,
        rates: &[f64],
        accelerations: &[f64],
        options: &Options,
    ) -> Result<Self::Motion, Error>;

    /// What a sweep carries from one step to the next: the state of the
    /// generated stepper (options, parameters and scaling checked once;
    /// the assembly modes; the sines and cosines of the last pose).
    type StepState: Clone + core::fmt::Debug;

    /// A fresh step state for `options`, checking them and the parameters.
    ///
    /// # Errors
    /// Invalid options or parameters.
    fn step_state(&self, options: &Options) -> Result<Self::StepState, Error>;

    /// The assembly modes a step state follows, one ±1 per block with two
    /// closed-form solutions (NaN: from the next guess); empty unless every
    /// block is solved in closed form. For sweeps that choose a branch at a
    /// change point.
    #[doc(hidden)]
    fn step_modes(state: &mut Self::StepState) -> &mut [f64];

    /// A step as the mechanism's stepper takes it, carrying `state` to the
    /// next step: the drivers' entries of `rates` and `accelerations` hold
    /// d' and d'' (their unknowns' entries are not read).
    ///
    /// # Errors
    /// As [`Mechanism::step_slices`].
    fn step_carried(
        &self,
        start: &Self::Coords,
        rates: &Self::Coords,
        accelerations: &Self::Coords,
        state: &mut Self::StepState,
    ) -> Result<Self::Motion, Error>;

    /// The positions of the points by name, the `points` of a [`Pose`]:
    /// the generated `…Positions`.
    type Positions: Copy + core::fmt::Debug;

    /// A positions-only step as the mechanism's stepper takes it
    /// (its `pose`): assembles at the drivers of `start` from the state of
    /// the previous step, carrying `state` to the next, with no velocity
    /// or acceleration computed.
    ///
    /// # Errors
    /// As [`Mechanism::assemble_with`].
    fn pose_carried(
        &self,
        start: &Self::Coords,
        state: &mut Self::StepState,
    ) -> Result<Pose<Self::Coords, Self::Positions>, Error>;

    /// Residuals Φ_i at `pose`, written into `out` (as many as fit).
    fn residual_into(&self, pose: &Self::Coords, out: &mut [f64]);

    /// The Jacobian Φ_u = ∂Φ/∂u at `pose`, row-major (row i is equation i,
    /// column k unknown k), written into `out` (as many entries as fit).
    fn jacobian_into(&self, pose: &Self::Coords, out: &mut [f64]);

    /// Point positions r_P(q) at `pose`, in declaration order, written into
    /// `out` as consecutive components ([`Mechanism::POINT_DIM`] per point;
    /// as many as fit).
    fn point_positions_into(&self, pose: &Self::Coords, out: &mut [f64]);

    /// Frame rotations R(q) at `pose`, in declaration order, written into
    /// `out` (as many as fit).
    fn frame_rotations_into(&self, pose: &Self::Coords, out: &mut [Matrix3<f64>]);
}
