//! The evaluation of [`Dynamics`] at one motion: the views of a motion it
//! reads, the loads' view of the instant, and the sums of virtual power.

use core::cell::Cell;

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;
use core::ops::Deref;

use nalgebra::{Matrix3, Vector3};

use super::terms::Terms;
use super::totals::Totals;
use super::{Dynamics, DynamicsBuilder, ResolvedBody, ResolvedSpring, Turns};
use crate::error::{Error, Input};
use crate::mechanism::{Coordinates, FrameState, Mechanism, MotionState, PointState};
use crate::options::Options;

/// What a load sees of the instant it acts at: the coordinates, their
/// rates and accelerations (by index, in declaration order: drivers first,
/// then unknowns), and the position and velocity of the point it acts at
/// (for a torque, of the body's centre of mass; zero for a force on a
/// coordinate).
///
/// ```
/// use kinematics_core::{dynamics::Dynamics, mechanism};
/// mechanism! {
///     /// A slider driven along x.
///     pub struct Slide {
///         params   { }
///         drivers  { x }
///         unknowns { }
///         points   { P = vec2(x, 0.0); }
///     }
/// }
/// // A damper on the slider, −c ẋ with c = 40 N·s/m: at ẋ = 0.5 m/s the
/// // driver must push with c ẋ = 20 N.
/// let dynamics = Dynamics::builder()
///     .coordinate_force("x", |s| -40.0 * s.qd(0))
///     .build::<Slide>()?;
/// let m = Slide {};
/// let motion = m.analyze(&SlideCoords { x: 0.1 }, 0.5, 0.0)?;
/// assert!((dynamics.inverse(&m, &motion)?.effort.x - 20.0).abs() < 1e-12);
/// # Ok::<(), kinematics_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Instant<'a> {
    pub(super) q: &'a [f64],
    pub(super) qd: &'a [f64],
    pub(super) qdd: &'a [f64],
    /// Position of the point the load acts at (z = 0 in a planar mechanism).
    pub position: Vector3<f64>,
    /// Velocity of that point.
    pub velocity: Vector3<f64>,
    /// The time, in a forward simulation (NaN otherwise).
    pub(super) time: f64,
    /// Set when the load reads the time, for the message of a load that
    /// is not finite for want of one.
    pub(super) read: Option<&'a Cell<bool>>,
}

impl<'a> Instant<'a> {
    /// The instant of the coordinates `[q, q', q'']` at a point whose
    /// position, velocity and acceleration are `at` (the origin at rest
    /// where the load acts at no point).
    pub(super) fn of(coords: [&'a [f64]; 3], at: Option<[Vector3<f64>; 3]>) -> Self {
        let [position, velocity, _] = at.unwrap_or([Vector3::zeros(); 3]);
        Instant {
            q: coords[0],
            qd: coords[1],
            qdd: coords[2],
            position,
            velocity,
            time: f64::NAN,
            read: None,
        }
    }

    /// The same instant at time `t`.
    pub(super) fn at_time(mut self, t: f64) -> Self {
        self.time = t;
        self
    }

    /// The same instant, `read` set when the load reads the time.
    pub(super) fn watched(mut self, read: &'a Cell<bool>) -> Self {
        self.read = Some(read);
        self
    }
}

impl Instant<'_> {
    /// Coordinate j (NaN past the last: the load's value is then
    /// reported as not finite).
    #[must_use]
    pub fn q(&self, j: usize) -> f64 {
        self.q.get(j).copied().unwrap_or(f64::NAN)
    }

    /// The rate of coordinate j.
    #[must_use]
    pub fn qd(&self, j: usize) -> f64 {
        self.qd.get(j).copied().unwrap_or(f64::NAN)
    }

    /// The acceleration of coordinate j; NaN in a forward simulation
    /// ([`Dynamics::forward`]), where the accelerations are what the loads
    /// determine (a load that reads it is then reported as not finite).
    #[must_use]
    pub fn qdd(&self, j: usize) -> f64 {
        self.qdd.get(j).copied().unwrap_or(f64::NAN)
    }

    /// The time (s) in a forward simulation ([`Dynamics::forward`]), from
    /// its start; NaN elsewhere (an inverse analysis has no time), so
    /// that a load of the time used there is reported as not finite.
    #[must_use]
    pub fn time(&self) -> f64 {
        if let Some(read) = self.read {
            read.set(true);
        }
        self.time
    }
}

/// The forces at one motion ([`Dynamics::inverse`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Forces<C> {
    /// The effort Q_k each driver must supply, at the driver's entry (a
    /// torque in N·m for an angle, a force in N for a length; positive
    /// when it drives the coordinate's growth); the unknowns' entries are
    /// zero: no actuator acts there.
    pub effort: C,
    /// T = Σ ½ m |v_G|² + ½ ω · J ω (J).
    pub kinetic_energy: f64,
    /// V = −Σ m g · r_G + Σ ½ k (L − L₀)² (J; zero with the centres of
    /// mass at the origin and the springs at their free lengths).
    pub potential_energy: f64,
    /// Σ Q_k ḋ_k, the power the drivers supply (W).
    pub power: f64,
    /// The force the moving links exert on the frame from their inertia,
    /// −Σ m a_G (N).
    pub shaking_force: Vector3<f64>,
    /// Its moment about the fixed origin, −Σ (r_G × m a_G + J α + ω × J ω)
    /// (N·m; a planar mechanism's is along z).
    pub shaking_moment: Vector3<f64>,
    /// The total force of the mechanism on the frame, what Norton calls
    /// the shaking force: the inertial part above plus the weights and
    /// the point loads, F_f = −Σ m a_G + Σ m g + Σ F_P (N), the sum of the
    /// forces in the frame's bearings and guides (and of the springs
    /// anchored to it). Every declared point load counts as coming from
    /// outside the machine; a load whose reaction also bears on the frame
    /// (a gas force, which pushes on the cylinder head as well as on the
    /// piston) cancels there in the machine: declare such a load as a
    /// force on its joint's coordinate (`force(x, …)` with `coordinate =
    /// x` on the cylinder), which acts between the frame and the body and
    /// is left out here, or subtract it.
    pub frame_force: Vector3<f64>,
    /// The total moment of the mechanism on the frame about the fixed
    /// origin, the drivers' reactions included: the inertial part above
    /// plus Σ r_G × m g + Σ r_P × F_P + Σ T_b over the weights, point
    /// loads and torques on bodies (N·m; along z when planar).
    pub frame_moment: Vector3<f64>,
}

impl<C> Forces<C> {
    /// The forces of the efforts `effort`, the totals and the power.
    pub(crate) fn new(effort: C, totals: &Totals, power: f64) -> Self {
        Forces {
            effort,
            kinetic_energy: totals.kinetic_energy,
            potential_energy: totals.potential_energy,
            power,
            shaking_force: totals.shaking_force,
            shaking_moment: totals.shaking_moment,
            frame_force: totals.frame_force,
            frame_moment: totals.frame_moment,
        }
    }
}

/// How the drivers' efforts change with one body's mass and moment of
/// inertia ([`Dynamics::mass_sensitivities`]): the efforts are linear in
/// both, Q_k = Σ_b [m_b (a_G − g) · ∂v_G/∂ḋ_k + (I_b α + ω × I_b ω) ·
/// ∂ω/∂ḋ_k] − (the loads' terms), so that ∂Q_k/∂m_b = (a_G − g) ·
/// ∂v_G/∂ḋ_k exactly, and for a body turning by an angle in a planar
/// mechanism (I_b = J_b about z) ∂Q_k/∂J_b = α_z ∂ω_z/∂ḋ_k: what a
/// counterweight's or a link's mass changes in the driving torque, at the
/// same motion.
#[derive(Clone, Debug, PartialEq)]
pub struct MassSensitivity {
    /// The body's name.
    pub body: String,
    /// ∂Q_k/∂m for each driver k, in declaration order (N·m/kg for an
    /// angle driver, N/kg for a length).
    pub mass: Vec<f64>,
    /// ∂Q_k/∂J for each driver (N·m/(kg·m²) for an angle driver, N/(kg·m²)
    /// for a length), for a body that turns by an angle in a planar
    /// mechanism; `None` for one that does not turn or turns with a frame.
    pub inertia: Option<Vec<f64>>,
}

/// A motion as the sums read it: points' r, v, a (padded to three
/// components), frames, coordinates' q, q', q''.
pub(crate) trait View {
    /// r, v, a of point i.
    fn point(&self, i: usize) -> Option<[Vector3<f64>; 3]>;
    /// v of point i alone (what the partial velocities are read as).
    fn velocity(&self, i: usize) -> Option<Vector3<f64>> {
        self.point(i).map(|[_, v, _]| v)
    }
    /// a of point i alone (what the inertial terms read).
    fn acceleration(&self, i: usize) -> Option<Vector3<f64>> {
        self.point(i).map(|[_, _, a]| a)
    }
    /// q' of coordinate j alone (NaN when there is none).
    fn rate(&self, j: usize) -> f64 {
        self.coordinate(j)[1]
    }
    /// Frame i.
    fn frame(&self, i: usize) -> Option<&FrameState>;
    /// q, q', q'' of coordinate j (NaN when there is none).
    fn coordinate(&self, j: usize) -> [f64; 3];
    /// The time of the motion, where it is one of a forward simulation
    /// (NaN otherwise).
    fn time(&self) -> f64 {
        f64::NAN
    }
}

/// Three components from two or three.
pub(crate) fn padded(v: &[f64]) -> Vector3<f64> {
    let c = |i: usize| v.get(i).copied().unwrap_or(0.0);
    Vector3::new(c(0), c(1), c(2))
}

/// The view of a generated mechanism's motion.
pub(crate) struct Generated<'a, S>(pub(crate) &'a S);

impl<S: MotionState> View for Generated<'_, S> {
    fn point(&self, i: usize) -> Option<[Vector3<f64>; 3]> {
        let p = self.0.points().get(i)?;
        Some([
            padded(p.position()),
            padded(p.velocity()),
            padded(p.acceleration()),
        ])
    }
    fn velocity(&self, i: usize) -> Option<Vector3<f64>> {
        self.0.points().get(i).map(|p| padded(p.velocity()))
    }
    fn acceleration(&self, i: usize) -> Option<Vector3<f64>> {
        self.0.points().get(i).map(|p| padded(p.acceleration()))
    }
    fn rate(&self, j: usize) -> f64 {
        self.0.qd().get(j).unwrap_or(f64::NAN)
    }
    fn frame(&self, i: usize) -> Option<&FrameState> {
        self.0.frames().get(i)
    }
    fn coordinate(&self, j: usize) -> [f64; 3] {
        let get = |c: &S::Coords| c.get(j).unwrap_or(f64::NAN);
        [get(self.0.q()), get(self.0.qd()), get(self.0.qdd())]
    }
}

/// Up to 32 values on the stack, more on the heap: the driver rates of
/// the unit analyses and the coordinates the loads read, without an
/// allocation for the mechanisms of everyday size.
// The large variant is the point: it keeps the values off the heap.
#[allow(clippy::large_enum_variant)]
pub(crate) enum Buffer {
    Stack([f64; 32], usize),
    Heap(Vec<f64>),
}

impl Buffer {
    /// n zeros.
    pub(crate) fn zeros(n: usize) -> Self {
        if n <= 32 {
            Buffer::Stack([0.0; 32], n)
        } else {
            Buffer::Heap(vec![0.0; n])
        }
    }

    /// The values, mutably.
    pub(crate) fn as_mut_slice(&mut self) -> &mut [f64] {
        match self {
            Buffer::Stack(a, n) => &mut a[..*n],
            Buffer::Heap(v) => v,
        }
    }
}

impl Deref for Buffer {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        match self {
            Buffer::Stack(a, n) => &a[..*n],
            Buffer::Heap(v) => v,
        }
    }
}

/// A driver's unit analysis handed to the sums: `unit(k, with)` analyses
/// the pose at a unit rate of driver k and calls `with` on its view.
pub(crate) type WithUnit<'a> = &'a mut dyn FnMut(&dyn View);

impl Dynamics {
    /// A description with no bodies, no loads and no gravity, to which
    /// [`DynamicsBuilder`]'s methods add them.
    #[must_use]
    pub fn builder() -> DynamicsBuilder {
        DynamicsBuilder::new()
    }

    /// The forces at `motion`, a motion of `m` (from `analyze`, `step`, a
    /// stepper or a sweep): each driver's effort by virtual power, the
    /// energies, the drivers' power and the shaking force and moment (see
    /// the [module](super) for the formulas). The partial velocities come
    /// from one analysis of `m` at `motion`'s pose per driver, at unit
    /// rate; each load's function is called once per driver.
    ///
    /// # Errors
    /// [`Error::InvalidDynamics`] when this description was built for a
    /// mechanism of other sizes, or a load's value is not finite; the
    /// analysis' errors (a singular pose); [`Error::NonFinite`] for a
    /// result that is not finite.
    pub fn inverse<M: Mechanism>(
        &self,
        m: &M,
        motion: &M::Motion,
    ) -> Result<Forces<M::Coords>, Error> {
        self.fits_mechanism::<M>()?;
        let mut effort = M::Coords::default();
        let (totals, power) = self.sums(
            &Generated(motion),
            &mut unit_analyses(m, motion.q(), self.drivers),
            &mut |k, q| {
                effort.set(k, q);
            },
        )?;
        Ok(Forces::new(effort, &totals, power))
    }

    /// How each driver's effort at `motion` changes with each body's mass
    /// and moment of inertia, in the order the bodies were given
    /// ([`MassSensitivity`]), from the same unit analyses as
    /// [`Dynamics::inverse`].
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics};
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A crank whose centre of mass is at distance r.
    ///     pub struct Crank { params { r } drivers { phi } unknowns { } points { G = polar(r, phi); } }
    /// }
    /// let m = Crank { r: 0.1 };
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("crank", 2.0).center("G").angle("phi").inertia(0.01))
    ///     .gravity([0.0, -9.81, 0.0])
    ///     .build::<Crank>()?;
    /// // Horizontal, at rest, α = 3 rad/s²: Q = (m r² + J) α + m g r, so
    /// // ∂Q/∂m = r² α + g r and ∂Q/∂J = α.
    /// let motion = m.analyze(&CrankCoords { phi: 0.0 }, 0.0, 3.0)?;
    /// let s = &dynamics.mass_sensitivities(&m, &motion)?[0];
    /// assert!((s.mass[0] - (0.01 * 3.0 + 9.81 * 0.1)).abs() < 1e-12);
    /// assert!((s.inertia.as_ref().unwrap()[0] - 3.0).abs() < 1e-12);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// As [`Dynamics::inverse`].
    pub fn mass_sensitivities<M: Mechanism>(
        &self,
        m: &M,
        motion: &M::Motion,
    ) -> Result<Vec<MassSensitivity>, Error> {
        self.fits_mechanism::<M>()?;
        self.mass_partials(
            &Generated(motion),
            &mut unit_analyses(m, motion.q(), self.drivers),
        )
    }

    /// ∂Q_k/∂m_b and ∂Q_k/∂J_b at the motion `s`, from the unit analyses
    /// `unit` provides.
    pub(crate) fn mass_partials(
        &self,
        s: &dyn View,
        unit: &mut dyn FnMut(usize, WithUnit<'_>) -> Result<(), Error>,
    ) -> Result<Vec<MassSensitivity>, Error> {
        let g = self.gravity;
        let mut out: Vec<MassSensitivity> = self
            .bodies
            .iter()
            .map(|b| MassSensitivity {
                body: b.name.clone(),
                mass: vec![0.0; self.drivers],
                inertia: (self.dim == 2 && matches!(b.turning, Turns::Angle(_)))
                    .then(|| vec![0.0; self.drivers]),
            })
            .collect();
        for k in 0..self.drivers {
            unit(k, &mut |u| {
                for (b, o) in self.bodies.iter().zip(out.iter_mut()) {
                    let [_, _, a] = s.point(b.center).unwrap_or([Vector3::repeat(f64::NAN); 3]);
                    let v = u.point(b.center).map_or(Vector3::zeros(), |[_, v, _]| v);
                    if let Some(x) = o.mass.get_mut(k) {
                        *x = (a - g).dot(&v);
                    }
                    if let Some(x) = o.inertia.as_mut().and_then(|i| i.get_mut(k)) {
                        *x = turning(b, s).1.z * turning(b, u).0.z;
                    }
                }
            })?;
        }
        for o in &out {
            for &value in o.mass.iter().chain(o.inertia.iter().flatten()) {
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        input: Input::Computed,
                        name: "the sensitivity of an effort to a body's mass or inertia",
                        value,
                    });
                }
            }
        }
        Ok(out)
    }

    /// q, q' and q'' of every coordinate of `s`, as the loads read them.
    pub(crate) fn coordinates_of(&self, s: &dyn View) -> [Buffer; 3] {
        let n = self.coordinates;
        let mut out = [Buffer::zeros(n), Buffer::zeros(n), Buffer::zeros(n)];
        for j in 0..n {
            let values = s.coordinate(j);
            for (buffer, v) in out.iter_mut().zip(values) {
                buffer.as_mut_slice()[j] = v;
            }
        }
        out
    }

    /// Checks that this description was resolved against a mechanism of
    /// `M`'s sizes.
    pub(super) fn fits_mechanism<M: Mechanism>(&self) -> Result<(), Error> {
        self.fits(
            M::COORDINATES.len(),
            M::POINT_NAMES.len(),
            M::FRAME_NAMES.len(),
            M::POINT_DIM,
        )
    }

    /// Checks the sizes this description was resolved against.
    pub(crate) fn fits(
        &self,
        coordinates: usize,
        points: usize,
        frames: usize,
        dim: usize,
    ) -> Result<(), Error> {
        if (coordinates, points, frames, dim)
            == (self.coordinates, self.points, self.frames, self.dim)
        {
            Ok(())
        } else {
            Err(Error::InvalidDynamics {
                item: "dynamics".to_string(),
                detail: format!(
                    "built for a mechanism of {} coordinates, {} points and {} frames, used \
                     with one of {coordinates}, {points} and {frames}: build it for this one",
                    self.coordinates, self.points, self.frames
                ),
            })
        }
    }

    /// The sums over the motion `s`: the totals and the drivers' power,
    /// with each driver's effort handed to `effort(k, Q_k)`; `unit`
    /// provides the unit analyses ([`WithUnit`]).
    pub(crate) fn sums(
        &self,
        s: &dyn View,
        unit: &mut dyn FnMut(usize, WithUnit<'_>) -> Result<(), Error>,
        effort: &mut dyn FnMut(usize, f64),
    ) -> Result<(Totals, f64), Error> {
        let [q, qd, qdd] = self.coordinates_of(s);
        let totals = self.totals(s, [&q, &qd, &qdd])?;
        let mut terms = Terms::default();
        self.terms(s, [&q, &qd, &qdd], &mut terms)?;
        let mut power = 0.0;
        for k in 0..self.drivers {
            let mut effort_k = f64::NAN;
            unit(k, &mut |u| effort_k = self.effort(&terms, u))?;
            if !effort_k.is_finite() {
                return Err(Error::NonFinite {
                    input: Input::Computed,
                    name: "the effort of a driver",
                    value: effort_k,
                });
            }
            power += effort_k * s.coordinate(k)[1];
            effort(k, effort_k);
        }
        if !power.is_finite() {
            return Err(Error::NonFinite {
                input: Input::Computed,
                name: "the drivers' power",
                value: power,
            });
        }
        Ok((totals, power))
    }
}

/// The unit analyses of a generated mechanism `m` at `pose`: for driver
/// k, the motion at unit rate of k (the other drivers at rest, every
/// acceleration zero), whose velocities are the partial velocities
/// ∂v/∂ḋ_k and ∂ω/∂ḋ_k, handed to the closure.
pub(super) fn unit_analyses<'a, M: Mechanism>(
    m: &'a M,
    pose: &'a M::Coords,
    drivers: usize,
) -> impl FnMut(usize, WithUnit<'_>) -> Result<(), Error> + 'a {
    let mut rates = Buffer::zeros(drivers);
    let zeros = Buffer::zeros(drivers);
    move |k, with| {
        let r = rates.as_mut_slice();
        r.iter_mut().for_each(|x| *x = 0.0);
        if let Some(x) = r.get_mut(k) {
            *x = 1.0;
        }
        let u = m.analyze_slices(pose, &rates, &zeros, &Options::DEFAULT)?;
        with(&Generated(&u));
        Ok(())
    }
}

/// ω of body `b` in the motion `s` alone (what a unit analysis's partial
/// angular velocity is read as).
pub(super) fn angular_velocity(b: &ResolvedBody, s: &dyn View) -> Vector3<f64> {
    match &b.turning {
        Turns::No => Vector3::zeros(),
        Turns::Angle(terms) => {
            let mut w = 0.0;
            for &(j, c) in terms {
                w += c * s.rate(j);
            }
            Vector3::new(0.0, 0.0, w)
        }
        Turns::Frame(f) => s
            .frame(*f)
            .map_or(Vector3::repeat(f64::NAN), |f| f.angular_velocity),
    }
}

/// ω, α and the inertia tensor about G in the fixed axes of body `b` in
/// the motion `s`.
pub(super) fn turning(
    b: &ResolvedBody,
    s: &dyn View,
) -> (Vector3<f64>, Vector3<f64>, Matrix3<f64>) {
    match &b.turning {
        Turns::No => (Vector3::zeros(), Vector3::zeros(), Matrix3::zeros()),
        Turns::Angle(terms) => {
            let (mut w, mut a) = (0.0, 0.0);
            for &(j, c) in terms {
                let [_, qd, qdd] = s.coordinate(j);
                w += c * qd;
                a += c * qdd;
            }
            (
                Vector3::new(0.0, 0.0, w),
                Vector3::new(0.0, 0.0, a),
                b.inertia,
            )
        }
        Turns::Frame(f) => match s.frame(*f) {
            Some(f) => (
                f.angular_velocity,
                f.angular_acceleration,
                f.rotation * b.inertia * f.rotation.transpose(),
            ),
            None => (
                Vector3::repeat(f64::NAN),
                Vector3::repeat(f64::NAN),
                b.inertia,
            ),
        },
    }
}

/// A spring's state at a motion: its ends, the unit vector e from the
/// first to the second, and its tension.
pub(super) struct Pull {
    pub(super) ends: [Vector3<f64>; 2],
    pub(super) e: Vector3<f64>,
    pub(super) tension: f64,
}

impl ResolvedSpring {
    /// The spring at the motion `s`: L = |r_B − r_A|, e = (r_B − r_A)/L and
    /// f = k (L − L₀) + c e · (v_B − v_A).
    pub(super) fn pull(&self, s: &dyn View) -> Pull {
        let nan = [Vector3::repeat(f64::NAN); 3];
        let [ra, va, _] = s.point(self.from).unwrap_or(nan);
        let [rb, vb, _] = s.point(self.to).unwrap_or(nan);
        let d = rb - ra;
        let length = d.norm();
        let e = if length > 0.0 {
            d / length
        } else {
            Vector3::zeros()
        };
        Pull {
            ends: [ra, rb],
            e,
            tension: self.stiffness * (length - self.free_length)
                + self.damping * e.dot(&(vb - va)),
        }
    }
}

/// A load by its kind and its number among those of its kind.
#[derive(Clone, Copy)]
pub(super) enum LoadAt {
    Force(usize),
    Torque(usize),
    Coordinate(usize),
}

impl Dynamics {
    /// Checks that the values of the load `at` are finite; the error
    /// names it by its point, body or coordinate, and says so where the
    /// load read the time (`read`) and there is none (outside a forward
    /// simulation).
    pub(super) fn finite_load(
        &self,
        values: impl IntoIterator<Item = f64>,
        at: LoadAt,
        read: bool,
    ) -> Result<(), Error> {
        let Some(v) = values.into_iter().find(|v| !v.is_finite()) else {
            return Ok(());
        };
        let name =
            |names: &[String], i: usize| names.get(i).map_or("?", String::as_str).to_string();
        let item = match at {
            LoadAt::Force(i) => {
                format!("the force at point `{}`", name(&self.load_names.forces, i))
            }
            LoadAt::Torque(i) => format!(
                "the torque on body `{}`",
                self.torques
                    .get(i)
                    .and_then(|(b, _)| self.bodies.get(*b))
                    .map_or("?", |b| b.name.as_str())
            ),
            LoadAt::Coordinate(i) => format!(
                "the force on coordinate `{}`",
                name(&self.load_names.coordinate_forces, i)
            ),
        };
        Err(Error::InvalidDynamics {
            item,
            detail: if read && v.is_nan() {
                format!(
                    "its value is {v} at this pose: it reads the `time`, which has a value \
                     only in a forward simulation (an inverse analysis or a kinematic sweep \
                     has none)"
                )
            } else {
                format!("its value is {v} at this pose; a load must be finite")
            },
        })
    }
}
