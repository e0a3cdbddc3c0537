//! The description of masses and loads by name ([`DynamicsBuilder`]),
//! before it is resolved against a mechanism.

use super::*;

/// Masses and loads on a mechanism, described by its names: start with
/// [`Dynamics::builder`], add bodies and loads, then resolve the names
/// against a mechanism with [`DynamicsBuilder::build`] (or, for a
/// mechanism defined at run time, `runtime::Model::dynamics`). See the
/// [module](crate::dynamics) for the mathematics.
pub struct DynamicsBuilder {
    pub(super) bodies: Vec<Body>,
    pub(super) gravity: [f64; 3],
    pub(super) forces: Vec<(String, Option<String>, VectorLoad)>,
    pub(super) joints: Vec<Joint>,
    pub(super) torques: Vec<(String, VectorLoad)>,
    pub(super) coordinate_forces: Vec<(String, ScalarLoad)>,
    /// Motors on coordinates ([`DynamicsBuilder::motor`]), made coordinate
    /// forces when the names are resolved.
    pub(super) motors: Vec<(String, Motor)>,
    pub(super) springs: Vec<Spring>,
    /// The design parameters and the constants' partial derivatives
    /// ([`DynamicsBuilder::design_parameters`]).
    pub(super) design: Option<(Vec<String>, Vec<f64>)>,
    pub(super) load_partials: PartialsOfLoads,
    pub(super) frame_partials: Vec<(String, FramePartials)>,
}

impl fmt::Debug for DynamicsBuilder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let forces: Vec<&String> = self.forces.iter().map(|(p, _, _)| p).collect();
        f.debug_struct("DynamicsBuilder")
            .field("bodies", &self.bodies)
            .field("gravity", &self.gravity)
            .field("forces at", &forces)
            .field("torques on", &names_of(&self.torques))
            .field("coordinate forces on", &names_of(&self.coordinate_forces))
            .field("springs", &self.springs)
            .field("joints", &self.joints)
            .field("design parameters", &self.design.as_ref().map(|d| &d.0))
            .finish_non_exhaustive()
    }
}

/// The names the loads of `v` act on (the loads themselves are functions).
fn names_of<T>(v: &[(String, T)]) -> Vec<&String> {
    v.iter().map(|(n, _)| n).collect()
}

impl Default for DynamicsBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl DynamicsBuilder {
    /// No bodies, no loads, no gravity.
    #[must_use]
    pub fn new() -> Self {
        DynamicsBuilder {
            bodies: Vec::new(),
            gravity: [0.0; 3],
            forces: Vec::new(),
            joints: Vec::new(),
            torques: Vec::new(),
            coordinate_forces: Vec::new(),
            motors: Vec::new(),
            springs: Vec::new(),
            design: None,
            load_partials: PartialsOfLoads::default(),
            frame_partials: Vec::new(),
        }
    }

    /// A moving link with mass.
    #[must_use]
    pub fn body(mut self, body: Body) -> Self {
        self.bodies.push(body);
        self
    }

    /// Gravity g (m/s², in the fixed axes; a planar mechanism reads x and
    /// y), acting on every body.
    #[must_use]
    pub fn gravity(mut self, g: [f64; 3]) -> Self {
        self.gravity = g;
        self
    }

    /// A force (N, fixed axes) applied at the point `point`, as a function
    /// of the instant (e.g. a gas force that depends on a piston's
    /// position).
    #[must_use]
    pub fn force(
        mut self,
        point: &str,
        force: impl Fn(&Instant<'_>) -> [f64; 3] + Send + Sync + 'static,
    ) -> Self {
        self.forces.push((point.to_string(), None, Box::new(force)));
        self.load_partials.add(LoadKind::Force);
        self
    }

    /// A force at the point `point` acting on the body `body` ([`Self::force`]
    /// with the body named): where a point is a pin shared by two bodies,
    /// the joint reactions ([`Dynamics::reactions`]) depend on which of
    /// them the force acts on.
    #[must_use]
    pub fn force_on(
        mut self,
        body: &str,
        point: &str,
        force: impl Fn(&Instant<'_>) -> [f64; 3] + Send + Sync + 'static,
    ) -> Self {
        self.forces
            .push((point.to_string(), Some(body.to_string()), Box::new(force)));
        self.load_partials.add(LoadKind::Force);
        self
    }

    /// A joint between two bodies (or a body and the ground), for the
    /// joint reactions ([`Dynamics::reactions`]).
    #[must_use]
    pub fn joint(mut self, joint: Joint) -> Self {
        self.joints.push(joint);
        self
    }

    /// A torque (N·m, fixed axes; a planar mechanism reads z) applied to the
    /// body named `body`.
    #[must_use]
    pub fn torque(
        mut self,
        body: &str,
        torque: impl Fn(&Instant<'_>) -> [f64; 3] + Send + Sync + 'static,
    ) -> Self {
        self.torques.push((body.to_string(), Box::new(torque)));
        self.load_partials.add(LoadKind::Torque);
        self
    }

    /// A generalised force on the coordinate `coordinate`: a force (N)
    /// along a length (a slider's actuator, a load on a piston), or a torque
    /// (N·m) about an angle (a torsion spring in a joint), in the direction
    /// the coordinate grows.
    #[must_use]
    pub fn coordinate_force(
        mut self,
        coordinate: &str,
        force: impl Fn(&Instant<'_>) -> f64 + Send + Sync + 'static,
    ) -> Self {
        self.coordinate_forces
            .push((coordinate.to_string(), Box::new(force)));
        self.load_partials.add(LoadKind::Coordinate);
        self
    }

    /// A motor on the coordinate `coordinate` (usually a driver left free
    /// in a forward simulation, [`Dynamics::forward`]): its torque (or
    /// force) at the coordinate's speed, T(q̇), in the direction the
    /// coordinate grows. It is a coordinate force, reported in the work of
    /// the loads as `force on <coordinate>`.
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics, Motor};
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A flywheel.
    ///     pub struct Wheel { params { } drivers { phi } unknowns { } points { O = vec2(0.0, 0.0); P = polar(0.2, phi); } }
    /// }
    /// let m = Wheel {};
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("wheel", 10.0).center("O").angle("phi").inertia(0.5))
    ///     .motor("phi", Motor::dc(2.0, 100.0))
    ///     .build::<Wheel>()?;
    /// // Held at 50 rad/s, the motor gives half its stall torque: the
    /// // driver must take 1 N·m to keep the speed.
    /// let motion = m.analyze(&WheelCoords { phi: 0.0 }, 50.0, 0.0)?;
    /// assert!((dynamics.inverse(&m, &motion)?.effort.phi + 1.0).abs() < 1e-12);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    #[must_use]
    pub fn motor(mut self, coordinate: &str, motor: Motor) -> Self {
        self.motors.push((coordinate.to_string(), motor));
        self
    }

    /// A spring and damper between two points.
    #[must_use]
    pub fn spring(mut self, spring: Spring) -> Self {
        self.springs.push(spring);
        self
    }

    /// The design parameters p_0 … p_{K−1} the efforts' sensitivities are
    /// taken with respect to ([`Dynamics::effort_sensitivities`]), in the
    /// order of the mechanism's `sensitivities` section, and how this
    /// description's constants change with each: `constants` holds, for
    /// each parameter in turn, ∂/∂p_k of
    ///
    /// * gravity's three components;
    /// * for each body in the order given: its mass, the coefficient of
    ///   each term of its angle (in the order of [`Body::angle_sum`]'s
    ///   terms; none for a body turning with a frame or not at all), and
    ///   the nine entries of its inertia row by row (a planar moment of
    ///   inertia is the entry (2, 2));
    /// * for each spring in the order given: its stiffness, free length
    ///   and damping.
    ///
    /// An empty `constants` says that no constant depends on the
    /// parameters. A definition with `bodies` and `sensitivities` sections
    /// declares both itself (its `dynamics_builder`); a description written
    /// in Rust whose masses are numbers needs only the names, or nothing
    /// when the mechanism's `sensitivities` section is meant.
    ///
    /// ```
    /// use kinematics_core::dynamics::{Body, Dynamics};
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A crank turning about its centre of mass O; its length a
    ///     /// changes only its moment of inertia.
    ///     pub struct Spin {
    ///         params   { a }
    ///         drivers  { phi }
    ///         unknowns { }
    ///         points   { O = vec2(0.0, 0.0); B = polar(a, phi); }
    ///         sensitivities { a }
    ///     }
    /// }
    /// let (m, a) = (2.0, 0.1);
    /// // J = m a²/3, so ∂J/∂a = 2 m a/3, the constant at index 3 + 1 + 1 + 8
    /// // (gravity, the mass, the angle's one coefficient, the inertia's
    /// // entry (2, 2)).
    /// let mut partials = [0.0; 3 + 1 + 1 + 9];
    /// partials[13] = 2.0 * m * a / 3.0;
    /// let dynamics = Dynamics::builder()
    ///     .body(Body::new("crank", m).center("O").angle("phi").inertia(m * a * a / 3.0))
    ///     .design_parameters(&["a"], &partials)
    ///     .build::<Spin>()?;
    /// // Q = J φ'', so ∂Q/∂a = (2 m a/3) φ''.
    /// let spin = Spin { a };
    /// let motion = spin.analyze(&SpinCoords { phi: 0.4 }, 3.0, 5.0)?;
    /// let s = dynamics.effort_sensitivities(&spin, &motion)?;
    /// assert!((s[0].effort[0] - 2.0 * m * a / 3.0 * 5.0).abs() < 1e-14);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    #[must_use]
    pub fn design_parameters(mut self, parameters: &[&str], constants: &[f64]) -> Self {
        self.design = Some((
            parameters.iter().map(|p| p.to_string()).collect(),
            constants.to_vec(),
        ));
        self
    }

    /// The partial derivatives of the load added last (by
    /// [`Self::force`], [`Self::force_on`], [`Self::torque`] or
    /// [`Self::coordinate_force`]), for the efforts' sensitivities: the
    /// function writes, for each variable x in turn, ∂(load)/∂x into
    /// `out[x]`, over the K design parameters
    /// ([`Self::design_parameters`], or the mechanism's `sensitivities`
    /// section), then q_0 … q_{n−1}, then q̇_0 …, then q̈_0 … (`out` has
    /// K + 3n entries): a force's or torque's three components as the
    /// load gives them, a force on a coordinate in entry 0. These are the
    /// load's explicit dependences; one that reads the instant's
    /// `position` or `velocity` includes their derivatives through the
    /// coordinates. Without them, [`Dynamics::effort_sensitivities`]
    /// reports the load as not differentiable.
    ///
    /// ```
    /// use kinematics_core::dynamics::Dynamics;
    /// use kinematics_core::mechanism;
    /// mechanism! {
    ///     /// A slider following x = a cos φ.
    ///     pub struct Follower {
    ///         params   { a }
    ///         drivers  { phi }
    ///         unknowns { x }
    ///         constraints { x == a * cos(phi); }
    ///         sensitivities { a }
    ///     }
    /// }
    /// // A damper −c ẋ on the slider: its one partial is ∂/∂ẋ = −c, at
    /// // x = K + n + 1 (K = 1 parameter, n = 2 coordinates, x the second).
    /// let c = 40.0;
    /// let dynamics = Dynamics::builder()
    ///     .coordinate_force("x", move |s| -c * s.qd(1))
    ///     .load_partials(move |_, out| out[1 + 2 + 1][0] = -c)
    ///     .build::<Follower>()?;
    /// // Q = c ẋ ∂ẋ/∂φ' = c a² sin²φ φ', so ∂Q/∂a = 2 c a sin²φ φ'.
    /// let (a, phi, w) = (0.1, 0.7, 3.0);
    /// let m = Follower { a };
    /// let pose = m.assemble(&FollowerCoords { phi, x: 0.07 })?;
    /// let s = dynamics.effort_sensitivities(&m, &m.analyze(&pose, w, 0.0)?)?;
    /// let expected = 2.0 * c * a * phi.sin().powi(2) * w;
    /// assert!((s[0].effort[0] - expected).abs() < 1e-12);
    /// # Ok::<(), kinematics_core::Error>(())
    /// ```
    #[must_use]
    pub fn load_partials(
        mut self,
        partials: impl Fn(&Instant<'_>, &mut [[f64; 3]]) + Send + Sync + 'static,
    ) -> Self {
        match self.load_partials.last {
            Some(kind) => {
                if let Some(slot) = self.load_partials.of(kind).last_mut() {
                    *slot = Some(Box::new(partials));
                }
            }
            None => self.load_partials.orphan = true,
        }
        self
    }

    /// The partial derivatives of the frame `frame`'s rotation R, angular
    /// velocity ω and angular acceleration α, for the efforts'
    /// sensitivities of the spatial bodies that turn with it and have
    /// inertia or a torque: the function writes, for each variable x of
    /// [`Self::load_partials`] in turn (the K design parameters, then q,
    /// q̇, q̈), ∂/∂x of R's nine entries row by row, then ω's three, then
    /// α's three, into `out[x]`, at the coordinates, rates and
    /// accelerations of the instant. A definition's `bodies` section
    /// gives them for its frames.
    #[must_use]
    pub fn frame_partials(
        mut self,
        frame: &str,
        partials: impl Fn(&Instant<'_>, &mut [[f64; 15]]) + Send + Sync + 'static,
    ) -> Self {
        self.frame_partials
            .push((frame.to_string(), Box::new(partials)));
        self
    }

    /// [`DynamicsBuilder::build`] of a generated mechanism's own sections
    /// (its `dynamics()`), marked as made by the type `M` at the parameter
    /// values `values`: a forward simulation of a mechanism of that type
    /// with those values then evaluates its compiled equations of motion
    /// ([`Mechanism::equations_of_motion`]) instead of the sums.
    ///
    /// # Errors
    /// As [`DynamicsBuilder::build`].
    #[doc(hidden)]
    pub fn build_sections<M: Mechanism>(self, values: &[f64]) -> Result<Dynamics, Error> {
        let mut d = self.build::<M>()?;
        d.mark_sections(core::any::type_name::<M>(), values);
        Ok(d)
    }

    /// Resolves the names against the generated mechanism `M`, and checks
    /// the values: masses, moments of inertia, stiffnesses and dampings
    /// finite and not negative, inertia tensors symmetric, free lengths
    /// and gravity finite, planar bodies turning with coordinates and
    /// spatial ones with frames.
    ///
    /// # Errors
    /// [`Error::InvalidDynamics`] naming the item and what is wrong.
    pub fn build<M: Mechanism>(self) -> Result<Dynamics, Error> {
        let coordinates: Vec<(String, Role, Kind)> = M::COORDINATES
            .iter()
            .map(|c| (c.name.to_string(), c.role, c.kind))
            .collect();
        let points: Vec<String> = M::POINT_NAMES.iter().map(|n| n.to_string()).collect();
        let frames: Vec<String> = M::FRAME_NAMES.iter().map(|n| n.to_string()).collect();
        self.resolve(&Names {
            coordinates: &coordinates,
            points: &points,
            frames: &frames,
            dim: M::POINT_DIM,
        })
    }

    /// Resolves the names against `names`, checking the values.
    pub(crate) fn resolve(mut self, names: &Names<'_>) -> Result<Dynamics, Error> {
        let invalid = |item: String, detail: String| Error::InvalidDynamics { item, detail };
        let find = |list: &[String], what: &str, name: &str, item: &str| {
            list.iter().position(|n| n == name).ok_or_else(|| {
                invalid(
                    item.to_string(),
                    format!(
                        "the mechanism has no {what} `{name}` (its {what}s: {})",
                        list.join(", ")
                    ),
                )
            })
        };
        let coordinate_names: Vec<String> = names
            .coordinates
            .iter()
            .map(|(n, _, _)| n.clone())
            .collect();
        let finite_nonnegative = |item: &str, what: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(invalid(
                    item.to_string(),
                    format!("{what} is {v}; it must be a finite number, zero or more"),
                ))
            }
        };
        let planar = names.dim == 2;
        if !self.gravity.iter().all(|g| g.is_finite()) {
            return Err(invalid(
                "gravity".to_string(),
                format!("{:?} must be finite", self.gravity),
            ));
        }
        let mut bodies = Vec::with_capacity(self.bodies.len());
        for b in &self.bodies {
            let item = format!("body `{}`", b.name);
            finite_nonnegative(&item, "its mass", b.mass)?;
            let Some(center) = &b.center else {
                return Err(invalid(
                    item,
                    "has no centre of mass: give the point with `.center(\"G\")`".to_string(),
                ));
            };
            let center = find(names.points, "point", center, &item)?;
            let inertia = b.inertia;
            if !inertia.iter().all(|v| v.is_finite())
                || (0..3).any(|i| inertia[(i, i)] < 0.0)
                || (inertia - inertia.transpose()).amax() > 1e-12 * inertia.amax()
            {
                return Err(invalid(
                    item,
                    format!(
                        "its inertia {inertia:?} must be finite and symmetric, with moments \
                         zero or more"
                    ),
                ));
            }
            let turning = match &b.turning {
                Turning::No => Turns::No,
                Turning::Angle(_) if !planar => {
                    return Err(invalid(
                        item,
                        "turns with coordinates, but the mechanism is spatial: give its frame \
                         with `.frame(\"name\")`"
                            .to_string(),
                    ));
                }
                Turning::Frame(_) if planar => {
                    return Err(invalid(
                        item,
                        "turns with a frame, but the mechanism is planar: give its angle with \
                         `.angle(\"coordinate\")`"
                            .to_string(),
                    ));
                }
                Turning::Angle(terms) => {
                    let mut resolved = Vec::with_capacity(terms.len());
                    for (name, c) in terms {
                        let j = find(&coordinate_names, "coordinate", name, &item)?;
                        if names.coordinates[j].2 != Kind::Angle {
                            return Err(invalid(
                                item,
                                format!("its angle is made of `{name}`, which is a length"),
                            ));
                        }
                        if !c.is_finite() {
                            return Err(invalid(
                                item,
                                format!("the coefficient {c} of `{name}` must be finite"),
                            ));
                        }
                        resolved.push((j, *c));
                    }
                    Turns::Angle(resolved)
                }
                Turning::Frame(f) => Turns::Frame(find(names.frames, "frame", f, &item)?),
            };
            if matches!(turning, Turns::No) && inertia.amax() > 0.0 {
                return Err(invalid(
                    item,
                    "has a moment of inertia but does not turn: give its angle (planar) or \
                     frame (spatial)"
                        .to_string(),
                ));
            }
            bodies.push(ResolvedBody {
                name: b.name.clone(),
                mass: b.mass,
                center,
                turning,
                inertia,
            });
        }
        let body_names: Vec<String> = self.bodies.iter().map(|b| b.name.clone()).collect();
        let mut forces = Vec::with_capacity(self.forces.len());
        for (point, body, f) in self.forces {
            let item = format!("force at `{point}`");
            let p = find(names.points, "point", &point, &item)?;
            let b = match body {
                Some(b) => Some(find(&body_names, "body", &b, &item)?),
                None => None,
            };
            forces.push((p, b, f));
        }
        let joints = joints::resolve(&self.joints, names, &body_names, &bodies)?;
        let mut torques = Vec::with_capacity(self.torques.len());
        for (body, t) in self.torques {
            let item = format!("torque on `{body}`");
            let k = find(&body_names, "body", &body, &item)?;
            if matches!(
                bodies.get(k).map(|b: &ResolvedBody| &b.turning),
                Some(Turns::No)
            ) {
                return Err(invalid(item, format!("body `{body}` does not turn")));
            }
            torques.push((k, t));
        }
        let mut coordinate_forces = Vec::with_capacity(self.coordinate_forces.len());
        for (name, f) in self.coordinate_forces {
            let item = format!("force on coordinate `{name}`");
            coordinate_forces.push((find(&coordinate_names, "coordinate", &name, &item)?, f));
        }
        for (name, motor) in core::mem::take(&mut self.motors) {
            let item = format!("motor on coordinate `{name}`");
            let j = find(&coordinate_names, "coordinate", &name, &item)?;
            if let Some(detail) = motor.invalid() {
                return Err(invalid(item, format!("{motor:?}: {detail}")));
            }
            let torque: ScalarLoad = Box::new(move |s: &Instant<'_>| motor.torque(s.qd(j)));
            coordinate_forces.push((j, torque));
            self.load_partials.coordinate_forces.push(None);
        }
        let mut springs = Vec::with_capacity(self.springs.len());
        for s in &self.springs {
            let item = format!("spring from `{}` to `{}`", s.from, s.to);
            finite_nonnegative(&item, "its stiffness", s.stiffness)?;
            finite_nonnegative(&item, "its damping", s.damping)?;
            finite_nonnegative(&item, "its free length", s.free_length)?;
            let bodies = match &s.bodies {
                None => None,
                Some(pair) => {
                    let mut ends = [None; 2];
                    for (end, name) in ends.iter_mut().zip(pair) {
                        if name != GROUND {
                            *end = Some(find(&body_names, "body", name, &item)?);
                        }
                    }
                    Some(ends)
                }
            };
            springs.push(ResolvedSpring {
                from: find(names.points, "point", &s.from, &item)?,
                to: find(names.points, "point", &s.to, &item)?,
                stiffness: s.stiffness,
                free_length: s.free_length,
                damping: s.damping,
                bodies,
            });
        }
        if self.load_partials.orphan {
            return Err(invalid(
                "load partials".to_string(),
                "`load_partials` was called before any load was added: call it after the \
                 `force`, `torque` or `coordinate_force` it differentiates"
                    .to_string(),
            ));
        }
        let mut frame_partials = Vec::with_capacity(self.frame_partials.len());
        for (frame, f) in self.frame_partials {
            let item = format!("partials of frame `{frame}`");
            frame_partials.push((find(names.frames, "frame", &frame, &item)?, f));
        }
        let design = match self.design {
            None => None,
            Some((parameters, constants)) => {
                Some(Design::new(parameters, &constants, &bodies, springs.len())?)
            }
        };
        Ok(Dynamics {
            drivers: names
                .coordinates
                .iter()
                .filter(|(_, r, _)| *r == Role::Driver)
                .count(),
            coordinates: names.coordinates.len(),
            points: names.points.len(),
            load_names: LoadNames {
                forces: forces
                    .iter()
                    .map(|(p, _, _)| names.points[*p].clone())
                    .collect(),
                coordinate_forces: coordinate_forces
                    .iter()
                    .map(|(j, _)| coordinate_names[*j].clone())
                    .collect(),
                points: names.points.to_vec(),
            },
            frames: names.frames.len(),
            dim: names.dim,
            gravity: Vector3::from(self.gravity),
            bodies,
            forces,
            torques,
            coordinate_forces,
            springs,
            joints,
            design,
            load_partials: self.load_partials,
            frame_partials,
            sections: None,
        })
    }
}
