//! Forces from the motion: the effort each driver must supply, the kinetic
//! and potential energy, and the shaking force and moment on the frame,
//! for a mechanism whose links carry mass and loads.
//!
//! The masses and loads are described once, by the names of the
//! mechanism's points, frames and coordinates ([`Dynamics::builder`]);
//! then [`Dynamics::inverse`] takes a motion (q, q', q'') and returns its
//! [`Forces`]. Nothing is differentiated numerically: the velocities and
//! accelerations are the mechanism's exact ones, and the partial
//! velocities are its velocity solution at a unit rate of each driver.
//!
//! # The mathematics (virtual power)
//!
//! For each driver d_k, let v_P^k = ∂v_P/∂ḋ_k and ω_b^k = ∂ω_b/∂ḋ_k be the
//! velocity of point P and the angular velocity of body b when d_k moves
//! at unit rate and the other drivers are held (the partial velocities;
//! velocities are linear in the driver rates at a given pose). The effort
//! Q_k the driver must supply (a torque for an angle, a force for a
//! length) is, by the principle of virtual power (d'Alembert's principle
//! with the loop constraints workless),
//!
//! Q_k = Σ_b [ m_b (a_G − g) · v_G^k + (J_b α_b + ω_b × J_b ω_b) · ω_b^k ]
//!       − Σ_forces F · v_P^k − Σ_torques T · ω_b^k − Σ_coordinate forces f · q̇_j^k
//!       + Σ_springs f_s (e · (v_B^k − v_A^k)),
//!
//! with G each body's centre of mass, J_b its inertia about G in the fixed
//! axes (R J Rᵀ for a frame of rotation R; a scalar about the normal in a
//! planar mechanism, where the gyroscopic term vanishes), g gravity, and
//! for a spring from A to B of stiffness k, free length L₀ and damping c:
//! L = |r_B − r_A|, e = (r_B − r_A)/L and tension f_s = k (L − L₀) + c L̇.
//!
//! The energies are T = Σ_b ½ m_b |v_G|² + ½ ω_b · J_b ω_b and
//! V = −Σ_b m_b g · r_G + Σ_springs ½ k (L − L₀)², and the drivers' power
//! is Σ_k Q_k ḋ_k, which equals d(T + V)/dt when the only other loads are
//! gravity and springs without damping. The shaking force is the force the
//! moving links exert on the frame through its bearings and the drivers'
//! reactions, from their inertia alone: F_s = −Σ_b m_b a_G; the shaking
//! moment about the fixed origin is M_s = −Σ_b (r_G × m_b a_G + J_b α_b +
//! ω_b × J_b ω_b). The total force of the mechanism on the frame (what
//! Norton calls the shaking force, the sum of the forces in the frame's
//! bearings and guides) adds the weights and the point loads,
//! F_f = F_s + Σ_b m_b g + Σ_P F_P, and its moment
//! M_f = M_s + Σ_b r_G × m_b g + Σ_P r_P × F_P + Σ T_b, which holds the
//! drivers' reactions ([`Forces::frame_force`]).
//!
//! # Joint reactions (planar)
//!
//! With the joints declared ([`Joint`]: revolute or prismatic, between two
//! bodies or a body and [`GROUND`], the driver's joint marked),
//! [`Dynamics::reactions`] writes the Newton–Euler equations of every body,
//!
//! Σ F_joints + Σ F_applied + m g = m a_G,
//! Σ (r_J − r_G) × F_joints + Σ M_joints + Σ (r_P − r_G) × F_applied + Σ T = J α,
//!
//! three per body and linear in the unknowns: the force each revolute
//! joint's first body exerts on its second, the normal force and moment
//! at each prismatic joint, and the driver's effort in its joint. With
//! every moving link a body and every joint declared, a mechanism of one
//! degree of freedom has as many unknowns as equations, solved by LU; the
//! effort found equals [`Dynamics::inverse`]'s.
//!
//! ```
//! use kinematics_core::{dynamics::{Body, Dynamics}, mechanism};
//!
//! mechanism! {
//!     /// A slider-crank with the rod's centre of mass G3 at its middle.
//!     pub struct Engine {
//!         params   { a, b }
//!         drivers  { phi }
//!         unknowns { th, x }
//!         points   { B = polar(a, phi); G3 = polar(a, phi) + polar(b / 2.0, th); C = vec2(x, 0.0); }
//!         loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
//!     }
//! }
//!
//! let m = Engine { a: 0.05, b: 0.2 };
//! let dynamics = Dynamics::builder()
//!     .body(Body::new("rod", 0.5).center("G3").angle("th").inertia(0.5 * 0.2 * 0.2 / 12.0))
//!     .body(Body::new("piston", 0.3).center("C"))
//!     // The gas pushes the piston toward the crank with 1 kN.
//!     .force("C", |_| [-1000.0, 0.0, 0.0])
//!     .build::<Engine>()?;
//! let pose = m.assemble(&EngineCoords { phi: 1.0, th: -0.2, x: 0.2 })?;
//! let motion = m.analyze(&pose, 100.0, 0.0)?;
//! let forces = dynamics.inverse(&m, &motion)?;
//! println!("crank torque {:.2} N·m", forces.effort.phi);
//! # Ok::<(), kinematics_core::Error>(())
//! ```

mod builder;
mod cycle;
pub(crate) mod evaluate;
pub mod forward;
mod joints;
mod reactions;
pub(crate) mod sensitivity;
pub(crate) mod terms;
pub(crate) mod totals;

use alloc::boxed::Box;
use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt;

use nalgebra::{Matrix3, Vector3};

pub use builder::DynamicsBuilder;
pub use cycle::{ForceSample, ForceSweep};
pub use evaluate::{Forces, Instant, MassSensitivity};
pub use forward::{
    Ended, Energy, Event, Forward, Impact, Method, Motor, Sensitivities, Statistics, Trajectory,
};
pub use joints::{Axis, GROUND, Joint};
pub use reactions::{JointReaction, Reactions};
pub use sensitivity::EffortSensitivity;

use crate::error::Error;
use crate::mechanism::{Kind, Mechanism, Role};

/// A load given as a function of the instant: a force (3 components; a
/// planar mechanism reads x and y) or a torque (3 components; a planar
/// mechanism reads z).
type VectorLoad = Box<dyn Fn(&Instant<'_>) -> [f64; 3] + Send + Sync>;
/// A scalar load on one coordinate: a force along a length, a torque about
/// an angle.
type ScalarLoad = Box<dyn Fn(&Instant<'_>) -> f64 + Send + Sync>;
/// The partial derivatives of a load ([`DynamicsBuilder::load_partials`]).
type LoadPartials = Box<dyn Fn(&Instant<'_>, &mut [[f64; 3]]) + Send + Sync>;
/// The partial derivatives of a frame's R, ω and α
/// ([`DynamicsBuilder::frame_partials`]).
type FramePartials = Box<dyn Fn(&Instant<'_>, &mut [[f64; 15]]) + Send + Sync>;

/// The partial derivatives of the loads, where given: one entry per load
/// of each kind, in the order the loads were added.
#[derive(Default)]
struct PartialsOfLoads {
    forces: Vec<Option<LoadPartials>>,
    torques: Vec<Option<LoadPartials>>,
    coordinate_forces: Vec<Option<LoadPartials>>,
    /// The kind of the load added last.
    last: Option<LoadKind>,
    /// Whether partials were given before any load.
    orphan: bool,
}

/// The three kinds of load.
#[derive(Clone, Copy)]
enum LoadKind {
    Force,
    Torque,
    Coordinate,
}

impl PartialsOfLoads {
    /// Room for the partials of a load of kind `kind` just added.
    fn add(&mut self, kind: LoadKind) {
        self.of(kind).push(None);
        self.last = Some(kind);
    }

    /// The partials of the loads of kind `kind`.
    fn of(&mut self, kind: LoadKind) -> &mut Vec<Option<LoadPartials>> {
        match kind {
            LoadKind::Force => &mut self.forces,
            LoadKind::Torque => &mut self.torques,
            LoadKind::Coordinate => &mut self.coordinate_forces,
        }
    }
}

/// How a body turns.
#[derive(Clone, Debug, PartialEq)]
enum Turning {
    /// It does not (a slider): no rotational inertia.
    No,
    /// Planar: its angle is Σ c_j q_j plus a constant, by coordinate name.
    Angle(Vec<(String, f64)>),
    /// Spatial: it moves with the frame of this name.
    Frame(String),
}

/// A rigid link with mass: its mass, its centre of mass (a point of the
/// mechanism), how it turns and its moment of inertia about the centre of
/// mass.
///
/// ```
/// use kinematics_core::dynamics::Body;
/// // A planar coupler of 1.2 kg whose angle is the coordinate th3, with
/// // its centre of mass at the mechanism's point G3.
/// let coupler = Body::new("coupler", 1.2).center("G3").angle("th3").inertia(0.004);
/// // A link of a spatial mechanism, moving with the frame `rocker`, with
/// // its inertia tensor about G in the frame's axes.
/// let rocker = Body::new("rocker", 0.8)
///     .center("G4")
///     .frame("rocker")
///     .inertia_tensor([[2e-3, 0.0, 0.0], [0.0, 2e-3, 0.0], [0.0, 0.0, 1e-4]]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    name: String,
    mass: f64,
    center: Option<String>,
    turning: Turning,
    inertia: Matrix3<f64>,
}

impl Body {
    /// A body of mass `mass` (kg), named `name` in error messages; give its
    /// centre of mass with [`Body::center`].
    #[must_use]
    pub fn new(name: &str, mass: f64) -> Self {
        Body {
            name: name.to_string(),
            mass,
            center: None,
            turning: Turning::No,
            inertia: Matrix3::zeros(),
        }
    }

    /// The centre of mass: the point of the mechanism of this name.
    #[must_use]
    pub fn center(mut self, point: &str) -> Self {
        self.center = Some(point.to_string());
        self
    }

    /// Planar: the body's angle is the coordinate `coordinate` (plus any
    /// constant offset, which does not move).
    #[must_use]
    pub fn angle(self, coordinate: &str) -> Self {
        self.angle_sum(&[(coordinate, 1.0)])
    }

    /// Planar: the body's angle is Σ c_j q_j (plus a constant), for the
    /// `(coordinate, c_j)` pairs given: e.g. `[("th1", 1.0), ("th2", 1.0)]`
    /// for the second link of a serial arm whose joint angles are
    /// relative.
    #[must_use]
    pub fn angle_sum(mut self, terms: &[(&str, f64)]) -> Self {
        self.turning = Turning::Angle(terms.iter().map(|&(n, c)| (n.to_string(), c)).collect());
        self
    }

    /// Spatial: the body moves with the mechanism's frame of this name.
    #[must_use]
    pub fn frame(mut self, frame: &str) -> Self {
        self.turning = Turning::Frame(frame.to_string());
        self
    }

    /// Planar: the moment of inertia about the centre of mass, about the
    /// plane's normal (kg·m²).
    #[must_use]
    pub fn inertia(mut self, moment: f64) -> Self {
        self.inertia = Matrix3::zeros();
        self.inertia[(2, 2)] = moment;
        self
    }

    /// Spatial: the inertia tensor about the centre of mass, in the axes of
    /// the body's frame (kg·m²; symmetric).
    #[must_use]
    pub fn inertia_tensor(mut self, tensor: [[f64; 3]; 3]) -> Self {
        self.inertia = Matrix3::from_fn(|i, j| tensor[i][j]);
        self
    }
}

/// A linear spring and viscous damper between two points of the mechanism:
/// tension f = k (L − L₀) + c L̇ along the line between them (pulling them
/// together when positive).
///
/// ```
/// use kinematics_core::dynamics::Spring;
/// let s = Spring::new("O4", "P").stiffness(500.0).free_length(0.08).damping(2.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    from: String,
    to: String,
    stiffness: f64,
    free_length: f64,
    damping: f64,
    bodies: Option<[String; 2]>,
}

impl Spring {
    /// A spring from point `from` to point `to`, of zero stiffness, free
    /// length and damping until set.
    #[must_use]
    pub fn new(from: &str, to: &str) -> Self {
        Spring {
            from: from.to_string(),
            to: to.to_string(),
            stiffness: 0.0,
            free_length: 0.0,
            damping: 0.0,
            bodies: None,
        }
    }

    /// The bodies the ends are fixed to: `from` on `first`, `to` on
    /// `second` ([`GROUND`] for the frame). The efforts do not need them;
    /// the joint reactions ([`Dynamics::reactions`]) do.
    #[must_use]
    pub fn between(mut self, first: &str, second: &str) -> Self {
        self.bodies = Some([first.to_string(), second.to_string()]);
        self
    }

    /// Stiffness k (N/m).
    #[must_use]
    pub fn stiffness(mut self, k: f64) -> Self {
        self.stiffness = k;
        self
    }

    /// Free length L₀ (m).
    #[must_use]
    pub fn free_length(mut self, length: f64) -> Self {
        self.free_length = length;
        self
    }

    /// Damping coefficient c (N·s/m).
    #[must_use]
    pub fn damping(mut self, c: f64) -> Self {
        self.damping = c;
        self
    }
}

/// The names a description is resolved against.
pub(crate) struct Names<'a> {
    /// Every coordinate: name, driver or unknown, angle or length.
    pub(crate) coordinates: &'a [(String, Role, Kind)],
    /// The points' names.
    pub(crate) points: &'a [String],
    /// The frames' names.
    pub(crate) frames: &'a [String],
    /// 2 (planar) or 3 (spatial).
    pub(crate) dim: usize,
}

/// How a resolved body turns.
#[derive(Clone, Debug, PartialEq)]
enum Turns {
    No,
    /// (coordinate index, coefficient).
    Angle(Vec<(usize, f64)>),
    /// Frame index.
    Frame(usize),
}

/// A body with its names resolved to indices.
#[derive(Clone, Debug, PartialEq)]
struct ResolvedBody {
    name: String,
    mass: f64,
    center: usize,
    turning: Turns,
    inertia: Matrix3<f64>,
}

/// A spring with its points resolved to indices.
#[derive(Clone, Debug, PartialEq)]
struct ResolvedSpring {
    from: usize,
    to: usize,
    stiffness: f64,
    free_length: f64,
    damping: f64,
    /// The bodies of the ends, where given (`None` inside: the ground).
    bodies: Option<[Option<usize>; 2]>,
}

/// Masses and loads resolved against one mechanism, ready to evaluate:
/// [`Dynamics::inverse`]. Built by [`DynamicsBuilder::build`].
pub struct Dynamics {
    pub(crate) drivers: usize,
    pub(crate) coordinates: usize,
    points: usize,
    frames: usize,
    dim: usize,
    gravity: Vector3<f64>,
    bodies: Vec<ResolvedBody>,
    /// (point, body it acts on if named, force).
    forces: Vec<(usize, Option<usize>, VectorLoad)>,
    torques: Vec<(usize, VectorLoad)>,
    coordinate_forces: Vec<(usize, ScalarLoad)>,
    springs: Vec<ResolvedSpring>,
    joints: Vec<joints::ResolvedJoint>,
    /// The design parameters and the constants' partials, where declared.
    design: Option<Design>,
    /// The names of the points and coordinates the loads act on.
    load_names: LoadNames,
    /// (frame index, the partials of its R, ω, α).
    frame_partials: Vec<(usize, FramePartials)>,
    load_partials: PartialsOfLoads,
    /// Where this is a model's own sections unchanged (a run-time model's
    /// `Model::dynamics`, a generated mechanism's `dynamics()`): which
    /// model made it (a generated type's name, a run-time model's
    /// compiled sections' number) and the parameter values it was made
    /// at, so that a forward simulation of that model at those values
    /// may use its compiled equations of motion instead.
    sections: Option<(String, Vec<f64>)>,
}

/// The names of the points the forces act at and of the coordinates the
/// coordinate forces act on, in the order given, for messages.
#[derive(Clone, Debug, PartialEq, Default)]
struct LoadNames {
    forces: Vec<String>,
    coordinate_forces: Vec<String>,
    /// Every point's name, in the mechanism's order.
    points: Vec<String>,
}

/// The design parameters of a description and its constants' partial
/// derivatives ([`DynamicsBuilder::design_parameters`]).
#[derive(Clone, Debug, PartialEq)]
struct Design {
    parameters: Vec<String>,
    /// One per parameter (empty: no constant depends on them).
    constants: Vec<ConstantPartials>,
}

impl Dynamics {
    /// Marks this description as the sections of the model `owner` at
    /// the parameter values `values`.
    pub(crate) fn mark_sections(&mut self, owner: &str, values: &[f64]) {
        self.sections = Some((owner.to_string(), values.to_vec()));
    }

    /// The values of [`Dynamics::mark_sections`], where marked as the
    /// sections of `owner`.
    pub(crate) fn sections_values(&self, owner: &str) -> Option<&[f64]> {
        match &self.sections {
            Some((by, values)) if by == owner => Some(values),
            _ => None,
        }
    }
}

/// ∂/∂p of a description's constants, for one parameter p.
#[derive(Clone, Debug, PartialEq)]
struct ConstantPartials {
    gravity: Vector3<f64>,
    /// Per body: ∂m, ∂c_j of its angle's terms, ∂J (in the body's axes).
    bodies: Vec<(f64, Vec<f64>, Matrix3<f64>)>,
    /// Per spring: ∂k, ∂L₀, ∂c.
    springs: Vec<[f64; 3]>,
}

impl Design {
    /// The design of `parameters` with the flat partials `constants`
    /// (laid out as [`DynamicsBuilder::design_parameters`] says) for
    /// `bodies` and `springs` springs.
    fn new(
        parameters: Vec<String>,
        constants: &[f64],
        bodies: &[ResolvedBody],
        springs: usize,
    ) -> Result<Self, Error> {
        let terms = |b: &ResolvedBody| match &b.turning {
            Turns::Angle(t) => t.len(),
            _ => 0,
        };
        let per: usize = 3 + bodies.iter().map(|b| 1 + terms(b) + 9).sum::<usize>() + 3 * springs;
        if !constants.is_empty() && constants.len() != per * parameters.len() {
            return Err(Error::InvalidDynamics {
                item: "design parameters".to_string(),
                detail: format!(
                    "{} partial derivatives of the constants were given for {} parameters; \
                     this description has {per} constants per parameter (gravity 3, each body \
                     1 + its angle's terms + 9, each spring 3)",
                    constants.len(),
                    parameters.len()
                ),
            });
        }
        if let Some(v) = constants.iter().find(|v| !v.is_finite()) {
            return Err(Error::InvalidDynamics {
                item: "design parameters".to_string(),
                detail: format!("a partial derivative of the constants is {v}; it must be finite"),
            });
        }
        let constants = constants
            .chunks(per)
            .map(|c| {
                let mut next = c.iter().copied();
                let mut take = || next.next().unwrap_or(0.0);
                let gravity = Vector3::new(take(), take(), take());
                let bodies = bodies
                    .iter()
                    .map(|b| {
                        let mass = take();
                        let angle = (0..terms(b)).map(|_| take()).collect();
                        let mut inertia = Matrix3::zeros();
                        for i in 0..3 {
                            for j in 0..3 {
                                inertia[(i, j)] = take();
                            }
                        }
                        (mass, angle, inertia)
                    })
                    .collect();
                let springs = (0..springs).map(|_| [take(), take(), take()]).collect();
                ConstantPartials {
                    gravity,
                    bodies,
                    springs,
                }
            })
            .collect();
        Ok(Design {
            parameters,
            constants,
        })
    }
}

impl fmt::Debug for Dynamics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Dynamics")
            .field("bodies", &self.bodies)
            .field("gravity", &self.gravity)
            .field("forces", &self.forces.len())
            .field("torques", &self.torques.len())
            .field("coordinate_forces", &self.coordinate_forces.len())
            .field("springs", &self.springs)
            .field("joints", &self.joints)
            .finish_non_exhaustive()
    }
}
