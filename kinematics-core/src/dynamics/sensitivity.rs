//! The sensitivities of the drivers' efforts to the design parameters:
//! the virtual-power sum of [`Dynamics::inverse`] differentiated exactly,
//! at a fixed motion of the drivers.
//!
//! With the motion's own sensitivities (∂q/∂p, ∂q'/∂p, ∂q''/∂p and every
//! point's ∂r/∂p, ∂v/∂p, ∂a/∂p, from the mechanism's `sensitivities`
//! section), those of each unit-rate motion (whose velocities are the
//! partial velocities v_G^k, ω^k), the constants' partial derivatives
//! (masses, inertias, gravity, springs) and the loads' (with respect to
//! the parameters, the coordinates, their rates and accelerations),
//! every term of
//!
//! Q_k = Σ_b [ m (a_G − g) · v_G^k + J α ω^k ] − Σ F · v_P^k − Σ T ω^k
//!       − Σ f q̇_j^k + Σ f_s e · (v_B^k − v_A^k)
//!
//! is differentiated by the product rule: for a body,
//! ∂m (a_G − g) · v_G^k + m (∂a_G − ∂g) · v_G^k + m (a_G − g) · ∂v_G^k +
//! (∂J α + J ∂α) ω^k + J α ∂ω^k, with α = Σ c_j q̈_j and ω^k = Σ c_j q̇_j^k
//! for a planar body's angle Σ c_j q_j; for a load, ∂F = F_p + F_q ∂q +
//! F_q' ∂q' + F_q'' ∂q''; for a spring of length L = |r_B − r_A|,
//! ∂L = e · ∂(r_B − r_A), ∂e = (∂(r_B − r_A) − e ∂L)/L and
//! ∂f_s = ∂k (L − L₀) + k (∂L − ∂L₀) + ∂c e · Δv + c (∂e · Δv + e · ∂Δv).

use core::cell::Cell;

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::{Matrix3, Vector3};

use super::evaluate::{Generated, Instant, LoadAt, View, padded};
use super::{ConstantPartials, Dynamics, LoadPartials, Turns};
use crate::error::{Error, Input};
use crate::mechanism::{FrameState, MotionState};
use crate::options::Options;
use crate::tolerance::Sensitive;

/// How the drivers' efforts at one motion change with one design
/// parameter p ([`Dynamics::effort_sensitivities`]), the drivers' motion
/// held: ∂Q_k/∂p for each driver.
#[derive(Clone, Debug, PartialEq)]
pub struct EffortSensitivity {
    /// The parameter p.
    pub parameter: String,
    /// ∂Q_k/∂p for each driver k, in declaration order (N·m per unit of
    /// p for an angle driver, N per unit of p for a length).
    pub effort: Vec<f64>,
}

/// The derivative of a motion with respect to one parameter, as a view:
/// ∂q, ∂q', ∂q'' of each coordinate and ∂r, ∂v, ∂a of each point (a
/// frame's derivatives are not known).
pub(crate) struct Tangent {
    pub(crate) coordinates: Vec<[f64; 3]>,
    pub(crate) points: Vec<[Vector3<f64>; 3]>,
}

impl View for Tangent {
    fn point(&self, i: usize) -> Option<[Vector3<f64>; 3]> {
        self.points.get(i).copied()
    }
    fn frame(&self, _: usize) -> Option<&FrameState> {
        None
    }
    fn coordinate(&self, j: usize) -> [f64; 3] {
        self.coordinates.get(j).copied().unwrap_or([f64::NAN; 3])
    }
}

impl Tangent {
    /// The tangents of `k` parameters from flat arrays: `coordinates` as
    /// `[parameter][q, q', q''][coordinate]` of `n` coordinates, `points`
    /// as `[parameter][point][r, v, a][component]` of `np` points of `dim`
    /// components.
    pub(crate) fn from_flat(
        k: usize,
        n: usize,
        np: usize,
        dim: usize,
        coordinates: &[f64],
        points: &[f64],
    ) -> Vec<Tangent> {
        let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(f64::NAN);
        (0..k)
            .map(|p| Tangent {
                coordinates: (0..n)
                    .map(|j| {
                        let base = p * 3 * n;
                        [
                            at(coordinates, base + j),
                            at(coordinates, base + n + j),
                            at(coordinates, base + 2 * n + j),
                        ]
                    })
                    .collect(),
                points: (0..np)
                    .map(|i| {
                        let base = (p * np + i) * 3 * dim;
                        let v = |w: usize| {
                            let c: Vec<f64> =
                                (0..dim).map(|c| at(points, base + w * dim + c)).collect();
                            padded(&c)
                        };
                        [v(0), v(1), v(2)]
                    })
                    .collect(),
            })
            .collect()
    }
}

/// A unit-rate motion handed to the sums with its tangents (one per
/// parameter).
pub(crate) type WithUnitTangents<'a> = &'a mut dyn FnMut(&dyn View, &[Tangent]);

/// A load's value at the motion and its derivative along each parameter.
struct Differentiated {
    value: Vector3<f64>,
    tangents: Vec<Vector3<f64>>,
}

impl Dynamics {
    /// How each driver's effort at `motion` changes with each parameter
    /// of the mechanism's `sensitivities` section, the drivers' motion
    /// (d, d', d'') held ([`EffortSensitivity`], in the section's order):
    /// the exact derivative of [`Dynamics::inverse`]'s efforts, from the
    /// motion's sensitivities and those of one unit-rate analysis per
    /// driver. What a link length, a counterweight or a spring changes in
    /// the driving torque, for design by gradient.
    ///
    /// Every term of the virtual-power sum is differentiated by the
    /// product rule: for a body, ∂m (a_G − g) · v_G^k + m (∂a_G − ∂g) ·
    /// v_G^k + m (a_G − g) · ∂v_G^k + (∂J α + J ∂α) ω^k + J α ∂ω^k
    /// (planar), or ∂h · ω^k + h · ∂ω^k with h = J_w α + ω × J_w ω,
    /// J_w = R J Rᵀ, ∂J_w = ∂R J Rᵀ + R ∂J Rᵀ + R J ∂Rᵀ and ∂h = ∂J_w α +
    /// J_w ∂α + ∂ω × J_w ω + ω × (∂J_w ω + J_w ∂ω) (spatial, with the
    /// frame's ∂R, ∂ω, ∂α from its partial derivatives), where
    /// v_G^k and ω^k are the unit-rate motion's and ∂v_G^k, ∂ω^k its
    /// sensitivities, α = Σ c_j q̈_j and ω^k = Σ c_j q̇_j^k for a planar
    /// body's angle Σ c_j q_j; for a load F(p, q, q', q''), ∂F = F_p +
    /// F_q ∂q + F_q' ∂q' + F_q'' ∂q''; for a spring of length L = |r_B −
    /// r_A| along e, ∂L = e · ∂(r_B − r_A), ∂e = (∂(r_B − r_A) − e ∂L)/L
    /// and ∂f = ∂k (L − L₀) + k (∂L − ∂L₀) + ∂c e · Δv + c (∂e · Δv + e ·
    /// ∂Δv).
    ///
    /// The constants (masses, inertias, gravity, springs) change with the
    /// parameters as [`DynamicsBuilder::design_parameters`] says (a
    /// definition's `dynamics()` declares it; a description written in
    /// Rust holds its numbers fixed), and every load must have its partial
    /// derivatives ([`DynamicsBuilder::load_partials`]; a definition's
    /// `loads` section has them).
    ///
    /// ```
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A crank of length a carrying a mass m at its end, under gravity.
    ///     pub struct Crank {
    ///         params   { a, m }
    ///         drivers  { phi }
    ///         unknowns { }
    ///         points   { G = polar(a, phi); }
    ///         bodies   { crank(mass = m, center = G, angle = phi); }
    ///         loads    { gravity(vec2(0.0, -9.81)); }
    ///         sensitivities { a, m }
    ///     }
    /// }
    /// let c = Crank { a: 0.1, m: 2.0 };
    /// // At φ = 0.3, φ' = 4, φ'' = 0: Q = m g a cos φ (the weight; the
    /// // centripetal force does no work), so ∂Q/∂a = m g cos φ and
    /// // ∂Q/∂m = g a cos φ.
    /// let motion = c.analyze(&CrankCoords { phi: 0.3 }, 4.0, 0.0)?;
    /// let s = c.dynamics()?.effort_sensitivities(&c, &motion)?;
    /// assert!((s[0].effort[0] - 2.0 * 9.81 * 0.3f64.cos()).abs() < 1e-12);
    /// assert!((s[1].effort[0] - 9.81 * 0.1 * 0.3f64.cos()).abs() < 1e-12);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidDynamics`] when the description's design parameters
    /// are not the mechanism's, a load has no partial derivatives, or a
    /// body turning with a frame has a moment of inertia or a torque and
    /// its frame has none ([`DynamicsBuilder::frame_partials`]);
    /// otherwise as [`Dynamics::inverse`] and the generated
    /// `sensitivities`.
    ///
    /// [`DynamicsBuilder::design_parameters`]: super::DynamicsBuilder::design_parameters
    /// [`DynamicsBuilder::load_partials`]: super::DynamicsBuilder::load_partials
    /// [`DynamicsBuilder::frame_partials`]: super::DynamicsBuilder::frame_partials
    pub fn effort_sensitivities<M: Sensitive>(
        &self,
        m: &M,
        motion: &M::Motion,
    ) -> Result<Vec<EffortSensitivity>, Error> {
        self.effort_sensitivities_at(m, motion, f64::NAN)
    }

    /// [`Dynamics::effort_sensitivities`] at the time `time` of a forward
    /// simulation (NaN: none), which the loads of the time read.
    pub(crate) fn effort_sensitivities_at<M: Sensitive>(
        &self,
        m: &M,
        motion: &M::Motion,
        time: f64,
    ) -> Result<Vec<EffortSensitivity>, Error> {
        self.fits_mechanism::<M>()?;
        let (k, n, np, dim) = (
            M::PARAMETERS.len(),
            M::COORDINATES.len(),
            M::POINT_NAMES.len(),
            M::POINT_DIM,
        );
        let tangents = |x: &M::Motion| -> Result<Vec<Tangent>, Error> {
            let mut coordinates = vec![0.0; k * 3 * n];
            let mut points = vec![0.0; k * np * 3 * dim];
            m.motion_sensitivities_into(x, &mut coordinates, &mut points)?;
            Ok(Tangent::from_flat(k, n, np, dim, &coordinates, &points))
        };
        let ds = tangents(motion)?;
        let pose = motion.q();
        let mut rates = vec![0.0; self.drivers];
        let zeros = vec![0.0; self.drivers];
        let view = Generated(motion);
        let view = crate::dynamics::forward::run::Timed(&view, time);
        self.effort_partials(M::PARAMETERS, &view, &ds, &mut |d, with| {
            rates
                .iter_mut()
                .enumerate()
                .for_each(|(i, r)| *r = f64::from(u8::from(i == d)));
            let u = m.analyze_slices(pose, &rates, &zeros, &Options::DEFAULT)?;
            with(&Generated(&u), &tangents(&u)?);
            Ok(())
        })
    }

    /// ∂Q_k/∂p_i at the motion `s` with tangents `ds` (one per parameter
    /// of `parameters`), from the unit analyses and their tangents that
    /// `unit` provides.
    pub(crate) fn effort_partials(
        &self,
        parameters: &[&str],
        s: &dyn View,
        ds: &[Tangent],
        unit: &mut dyn FnMut(usize, WithUnitTangents<'_>) -> Result<(), Error>,
    ) -> Result<Vec<EffortSensitivity>, Error> {
        let k = parameters.len();
        if k == 0 {
            return Ok(Vec::new());
        }
        let constants = self.design_for(parameters)?;
        self.differentiable()?;
        let planar = self.dim == 2;
        let [q, qd, qdd] = self.coordinates_of(s);
        let instant = |at| Instant::of([&q, &qd, &qdd], at).at_time(s.time());
        let n = self.coordinates;
        let mut scratch = vec![[0.0; 3]; k + 3 * n];
        // A load's value and its tangents along each parameter.
        let mut differentiate = |value: Vector3<f64>,
                                 partials: Option<&LoadPartials>,
                                 at: &Instant<'_>,
                                 mask: fn(Vector3<f64>) -> Vector3<f64>|
         -> Differentiated {
            scratch.iter_mut().for_each(|x| *x = [0.0; 3]);
            if let Some(p) = partials {
                p(at, &mut scratch);
            }
            let tangents = ds
                .iter()
                .enumerate()
                .map(|(i, t)| mask(Vector3::from(along(&scratch, i, k, n, t))))
                .collect();
            Differentiated {
                value: mask(value),
                tangents,
            }
        };
        let force_mask: fn(Vector3<f64>) -> Vector3<f64> = if planar {
            |v| Vector3::new(v.x, v.y, 0.0)
        } else {
            |v| v
        };
        let torque_mask: fn(Vector3<f64>) -> Vector3<f64> = if planar {
            |v| Vector3::new(0.0, 0.0, v.z)
        } else {
            |v| v
        };
        let scalar_mask: fn(Vector3<f64>) -> Vector3<f64> = |v| Vector3::new(v.x, 0.0, 0.0);
        let mut forces = Vec::with_capacity(self.forces.len());
        for (i, ((p, _, f), partials)) in self
            .forces
            .iter()
            .zip(&self.load_partials.forces)
            .enumerate()
        {
            let read = Cell::new(false);
            let at = instant(s.point(*p)).watched(&read);
            let value = Vector3::from(f(&at));
            self.finite_load(value.iter().copied(), LoadAt::Force(i), read.get())?;
            forces.push(differentiate(value, partials.as_ref(), &at, force_mask));
        }
        let mut torques = Vec::with_capacity(self.torques.len());
        for (i, ((b, t), partials)) in self
            .torques
            .iter()
            .zip(&self.load_partials.torques)
            .enumerate()
        {
            let read = Cell::new(false);
            let at = instant(self.bodies.get(*b).and_then(|b| s.point(b.center))).watched(&read);
            let value = Vector3::from(t(&at));
            self.finite_load(value.iter().copied(), LoadAt::Torque(i), read.get())?;
            torques.push(differentiate(value, partials.as_ref(), &at, torque_mask));
        }
        let mut coordinate_forces = Vec::with_capacity(self.coordinate_forces.len());
        for (i, ((_, f), partials)) in self
            .coordinate_forces
            .iter()
            .zip(&self.load_partials.coordinate_forces)
            .enumerate()
        {
            let read = Cell::new(false);
            let at = instant(None).watched(&read);
            let value = Vector3::new(f(&at), 0.0, 0.0);
            self.finite_load(value.iter().copied(), LoadAt::Coordinate(i), read.get())?;
            coordinate_forces.push(differentiate(value, partials.as_ref(), &at, scalar_mask));
        }
        // The frames' R, ω, α and their partials at the motion, per body.
        let at_frames = |x: &dyn View, coords: [&[f64]; 3]| -> Vec<Option<FrameDiff>> {
            let at = Instant {
                q: coords[0],
                qd: coords[1],
                qdd: coords[2],
                position: Vector3::zeros(),
                velocity: Vector3::zeros(),
                time: x.time(),
                read: None,
            };
            self.bodies
                .iter()
                .map(|b| {
                    let Turns::Frame(f) = b.turning else {
                        return None;
                    };
                    let state = x.frame(f)?;
                    let (_, partials) = self.frame_partials.iter().find(|(g, _)| *g == f)?;
                    let mut out = vec![[0.0; 15]; k + 3 * n];
                    partials(&at, &mut out);
                    Some(FrameDiff {
                        rotation: state.rotation,
                        omega: state.angular_velocity,
                        alpha: state.angular_acceleration,
                        partials: out,
                    })
                })
                .collect()
        };
        let frames_s = at_frames(s, [&q, &qd, &qdd]);
        let mut out: Vec<EffortSensitivity> = parameters
            .iter()
            .map(|p| EffortSensitivity {
                parameter: p.to_string(),
                effort: vec![0.0; self.drivers],
            })
            .collect();
        let loads = Loads {
            parameters: k,
            forces: &forces,
            torques: &torques,
            coordinate_forces: &coordinate_forces,
        };
        let any_frames = frames_s.iter().any(Option::is_some);
        for d in 0..self.drivers {
            unit(d, &mut |u, du| {
                let frames_u = if any_frames {
                    let [uq, uqd, uqdd] = self.coordinates_of(u);
                    at_frames(u, [&uq, &uqd, &uqdd])
                } else {
                    Vec::new()
                };
                for (i, o) in out.iter_mut().enumerate() {
                    let (Some(t), Some(ut)) = (ds.get(i), du.get(i)) else {
                        continue;
                    };
                    let c = constants.as_ref().and_then(|c| c.get(i));
                    if let Some(x) = o.effort.get_mut(d) {
                        *x = self.effort_tangent(
                            [s, t],
                            [u, ut],
                            [&frames_s, &frames_u],
                            c,
                            &loads,
                            i,
                        );
                    }
                }
            })?;
        }
        for o in &out {
            for &value in &o.effort {
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        input: Input::Computed,
                        name: "the sensitivity of an effort to a parameter",
                        value,
                    });
                }
            }
        }
        Ok(out)
    }

    /// The constants' partials for `parameters`, checked against the
    /// description's design parameters (`None`: constant).
    fn design_for(&self, parameters: &[&str]) -> Result<Option<&[ConstantPartials]>, Error> {
        let Some(design) = &self.design else {
            return Ok(None);
        };
        if design.parameters.len() != parameters.len()
            || design
                .parameters
                .iter()
                .zip(parameters)
                .any(|(a, b)| a != b)
        {
            return Err(Error::InvalidDynamics {
                item: "design parameters".to_string(),
                detail: format!(
                    "the description's constants are differentiated with respect to [{}], but \
                     the mechanism's sensitivities are with respect to [{}]: build the \
                     description for this mechanism",
                    design.parameters.join(", "),
                    parameters.join(", ")
                ),
            });
        }
        Ok((!design.constants.is_empty()).then_some(design.constants.as_slice()))
    }

    /// Checks that every term can be differentiated: each load has its
    /// partial derivatives, and so has the frame of each body turning
    /// with one that has inertia or a torque.
    fn differentiable(&self) -> Result<(), Error> {
        let missing = |what: String| Error::InvalidDynamics {
            item: what,
            detail: "its partial derivatives are not known (a function written in Rust): give \
                     them with `load_partials` after it, or declare the load in the \
                     definition's `loads` section, which differentiates it"
                .to_string(),
        };
        let unknown = |names: &[String], partials: &[Option<LoadPartials>]| {
            names
                .iter()
                .zip(partials)
                .find(|(_, d)| d.is_none())
                .map(|(n, _)| n.clone())
        };
        if let Some(p) = unknown(&self.load_names.forces, &self.load_partials.forces) {
            return Err(missing(format!("the force at `{p}`")));
        }
        for ((b, _), d) in self.torques.iter().zip(&self.load_partials.torques) {
            if d.is_none() {
                let name = self.bodies.get(*b).map_or("?", |b| b.name.as_str());
                return Err(missing(format!("the torque on `{name}`")));
            }
        }
        if let Some(c) = unknown(
            &self.load_names.coordinate_forces,
            &self.load_partials.coordinate_forces,
        ) {
            return Err(missing(format!("the force on coordinate `{c}`")));
        }
        for (i, b) in self.bodies.iter().enumerate() {
            let Turns::Frame(f) = b.turning else {
                continue;
            };
            let torqued = self.torques.iter().any(|(t, _)| *t == i);
            let known = self.frame_partials.iter().any(|(g, _)| *g == f);
            if (b.inertia.amax() > 0.0 || torqued) && !known {
                return Err(Error::InvalidDynamics {
                    item: format!("body `{}`", b.name),
                    detail: "turns with a frame and has a moment of inertia or a torque, but the \
                             partial derivatives of its frame's rotation, angular velocity and \
                             acceleration are not known: give them with `frame_partials`, or \
                             declare the body in the definition's `bodies` section"
                        .to_string(),
                });
            }
        }
        Ok(())
    }

    /// ∂Q_k/∂p_i: `s` the motion and `t` its tangent, `u` the unit
    /// analysis of driver k and `ut` its tangent, `c` the constants'
    /// partials (`None`: constant), `loads` the loads' values and tangents.
    fn effort_tangent(
        &self,
        [s, t]: [&dyn View; 2],
        [u, ut]: [&dyn View; 2],
        [frames_s, frames_u]: [&[Option<FrameDiff>]; 2],
        c: Option<&ConstantPartials>,
        loads: &Loads<'_>,
        i: usize,
    ) -> f64 {
        let (k, n) = (loads.parameters, self.coordinates);
        let nan = [Vector3::repeat(f64::NAN); 3];
        let velocity = |v: &dyn View, p: usize| v.point(p).map_or(Vector3::zeros(), |[_, v, _]| v);
        let g = self.gravity;
        let dg = c.map_or(Vector3::zeros(), |c| c.gravity);
        let mut dq = 0.0;
        // ω_z and its tangent of a planar body's angle Σ c_j q_j, from the
        // coordinates' rates (w = 1) or accelerations (w = 2) of `x` and
        // `dx`, with the coefficients' partials `dc`.
        let turning =
            |terms: &[(usize, f64)], dc: &[f64], x: &dyn View, dx: &dyn View, w: usize| {
                let (mut value, mut tangent) = (0.0, 0.0);
                for (n, &(j, cj)) in terms.iter().enumerate() {
                    let (v, dv) = (x.coordinate(j)[w], dx.coordinate(j)[w]);
                    value += cj * v;
                    tangent += dc.get(n).copied().unwrap_or(0.0) * v + cj * dv;
                }
                (value, tangent)
            };
        for (b_index, b) in self.bodies.iter().enumerate() {
            let (dm, dc, dj): (f64, &[f64], Matrix3<f64>) = c
                .and_then(|c| c.bodies.get(b_index))
                .map_or((0.0, &[], Matrix3::zeros()), |(m, a, j)| {
                    (*m, a.as_slice(), *j)
                });
            let [_, _, a] = s.point(b.center).unwrap_or(nan);
            let [_, _, da] = t.point(b.center).unwrap_or(nan);
            let (v, dv) = (velocity(u, b.center), velocity(ut, b.center));
            dq += dm * (a - g).dot(&v) + b.mass * (da - dg).dot(&v) + b.mass * (a - g).dot(&dv);
            match &b.turning {
                Turns::Angle(terms) => {
                    let (alpha, dalpha) = turning(terms, dc, s, t, 2);
                    let (omega, domega) = turning(terms, dc, u, ut, 1);
                    let (j, djz) = (b.inertia[(2, 2)], dj[(2, 2)]);
                    dq += (djz * alpha + j * dalpha) * omega + j * alpha * domega;
                }
                Turns::Frame(f) => {
                    let (fs, fu) = (frames_s.get(b_index), frames_u.get(b_index));
                    if let (Some(Some(fs)), Some(Some(fu))) = (fs, fu) {
                        // dJ_w = dR J Rᵀ + R dJ Rᵀ + R J dRᵀ, h = J_w α + ω × J_w ω.
                        let x = along(&fs.partials, i, k, n, t);
                        let dr = Matrix3::from_row_slice(&x[..9]);
                        let dw = Vector3::new(x[9], x[10], x[11]);
                        let da = Vector3::new(x[12], x[13], x[14]);
                        let (r, w, a) = (fs.rotation, fs.omega, fs.alpha);
                        let jw = r * b.inertia * r.transpose();
                        let djw = dr * b.inertia * r.transpose()
                            + r * dj * r.transpose()
                            + r * b.inertia * dr.transpose();
                        let h = jw * a + w.cross(&(jw * w));
                        let dh =
                            djw * a + jw * da + dw.cross(&(jw * w)) + w.cross(&(djw * w + jw * dw));
                        let xu = along(&fu.partials, i, k, n, ut);
                        let dwk = Vector3::new(xu[9], xu[10], xu[11]);
                        dq += dh.dot(&fu.omega) + h.dot(&dwk);
                    } else if let (Some(fs), Some(fu)) = (s.frame(*f), u.frame(*f)) {
                        // A point mass in rotation (checked): only ∂J acts.
                        let dj = fs.rotation * dj * fs.rotation.transpose();
                        let w = fs.angular_velocity;
                        let h = dj * fs.angular_acceleration + w.cross(&(dj * w));
                        dq += h.dot(&fu.angular_velocity);
                    }
                }
                Turns::No => {}
            }
        }
        for ((p, _, _), f) in self.forces.iter().zip(loads.forces) {
            let (v, dv) = (velocity(u, *p), velocity(ut, *p));
            dq -= f.tangents[i].dot(&v) + f.value.dot(&dv);
        }
        for ((b, _), tq) in self.torques.iter().zip(loads.torques) {
            if let (Some(Some(_)), Some(Some(fu))) = (frames_s.get(*b), frames_u.get(*b)) {
                let xu = along(&fu.partials, i, k, n, ut);
                let dwk = Vector3::new(xu[9], xu[10], xu[11]);
                dq -= tq.tangents[i].dot(&fu.omega) + tq.value.dot(&dwk);
                continue;
            }
            if let Some(body) = self.bodies.get(*b)
                && let Turns::Angle(terms) = &body.turning
            {
                let dc = c
                    .and_then(|c| c.bodies.get(*b))
                    .map_or(&[][..], |(_, a, _)| a.as_slice());
                let (omega, domega) = turning(terms, dc, u, ut, 1);
                dq -= tq.tangents[i].z * omega + tq.value.z * domega;
            }
        }
        for ((j, _), f) in self.coordinate_forces.iter().zip(loads.coordinate_forces) {
            let (rate, drate) = (u.coordinate(*j)[1], ut.coordinate(*j)[1]);
            dq -= f.tangents[i].x * rate + f.value.x * drate;
        }
        for (n, sp) in self.springs.iter().enumerate() {
            let [dk, dl0, dcc] = c
                .and_then(|c| c.springs.get(n))
                .copied()
                .unwrap_or([0.0; 3]);
            let [ra, va, _] = s.point(sp.from).unwrap_or(nan);
            let [rb, vb, _] = s.point(sp.to).unwrap_or(nan);
            let [dra, dva, _] = t.point(sp.from).unwrap_or(nan);
            let [drb, dvb, _] = t.point(sp.to).unwrap_or(nan);
            let (d, dd) = (rb - ra, drb - dra);
            let length = d.norm();
            let (e, de, dl) = if length > 0.0 {
                let e = d / length;
                let dl = e.dot(&dd);
                (e, (dd - e * dl) / length, dl)
            } else {
                (Vector3::zeros(), Vector3::zeros(), 0.0)
            };
            let (dv, ddv) = (vb - va, dvb - dva);
            let tension = sp.stiffness * (length - sp.free_length) + sp.damping * e.dot(&dv);
            let dtension = dk * (length - sp.free_length)
                + sp.stiffness * (dl - dl0)
                + dcc * e.dot(&dv)
                + sp.damping * (de.dot(&dv) + e.dot(&ddv));
            let uk = velocity(u, sp.to) - velocity(u, sp.from);
            let duk = velocity(ut, sp.to) - velocity(ut, sp.from);
            dq += dtension * e.dot(&uk) + tension * (de.dot(&uk) + e.dot(&duk));
        }
        dq
    }
}

/// The loads' values and tangents at one motion.
struct Loads<'a> {
    /// The number of design parameters, K.
    parameters: usize,
    forces: &'a [Differentiated],
    torques: &'a [Differentiated],
    coordinate_forces: &'a [Differentiated],
}

/// A frame's R, ω and α at a motion, with the partial derivatives of its
/// 15 values with respect to the K + 3n variables.
struct FrameDiff {
    rotation: Matrix3<f64>,
    omega: Vector3<f64>,
    alpha: Vector3<f64>,
    partials: Vec<[f64; 15]>,
}

/// The derivative along parameter `i` of values whose partials with
/// respect to the K = `k` parameters and the q, q̇, q̈ of `n` coordinates
/// are `x`, with `t` the motion's tangent along p_i: x_p + Σ_j (x_q ∂q_j
/// + x_q̇ ∂q̇_j + x_q̈ ∂q̈_j).
fn along<const N: usize>(x: &[[f64; N]], i: usize, k: usize, n: usize, t: &dyn View) -> [f64; N] {
    let mut d = x.get(i).copied().unwrap_or([0.0; N]);
    for j in 0..n {
        let dx = t.coordinate(j);
        for (w, dx) in dx.into_iter().enumerate() {
            if dx == 0.0 {
                continue;
            }
            if let Some(row) = x.get(k + w * n + j) {
                for (o, v) in d.iter_mut().zip(row) {
                    *o += v * dx;
                }
            }
        }
    }
    d
}
