//! Joint reactions of planar mechanisms by the Newton–Euler equations of
//! every body at once: the joints ([`Joint`]) between the bodies and the
//! ground, the reaction of each as unknowns, and the driver's effort at
//! its joint.
//!
//! For each body b with centre of mass G, the sum of the forces on it and
//! their moment about G equal its rate of momentum:
//!
//! Σ F_joints + Σ F_applied + m g = m a_G,
//! Σ (r_J − r_G) × F_joints + Σ M_joints + Σ (r_P − r_G) × F_applied + Σ T = J α,
//!
//! three equations per body, linear in the reactions: at a revolute joint
//! the force (2 components) the first body exerts on the second; at a
//! prismatic joint the force normal to its axis and the moment (2); at the
//! joint a driver acts in, its effort (a torque about a revolute, a force
//! along a prismatic axis). With every moving link a body and every joint
//! declared, a mechanism of one degree of freedom has as many unknowns as
//! equations (Grübler's count), and the system is solved by LU.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

use nalgebra::{DMatrix, DVector, Vector3};

use super::evaluate::{Generated, Instant, View};
use super::{Dynamics, Names, ResolvedBody, Turns};
use crate::error::Error;
use crate::mechanism::{Kind, Mechanism, Role};

/// The name that stands for the fixed frame in a joint.
pub const GROUND: &str = "ground";

/// What a joint lets move.
#[derive(Clone, Debug, PartialEq)]
enum JointKind {
    /// A pin: relative rotation.
    Revolute,
    /// A slider along the axis fixed in the first body (in its axes).
    Prismatic([f64; 2]),
}

/// A joint of a planar mechanism between two bodies (or a body and
/// [`GROUND`]), at one of the mechanism's points: a revolute joint (a pin)
/// or a prismatic one (a slider), and the driver acting in it if any.
///
/// ```
/// use kinematics_core::dynamics::Joint;
/// // The crank's bearing, where the motor drives φ.
/// let a = Joint::revolute("A", "A", "ground", "crank").driven_by("phi");
/// // The piston in its cylinder, sliding along x.
/// let c = Joint::prismatic("cylinder", "C", "ground", "piston", [1.0, 0.0]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    name: String,
    at: String,
    bodies: [String; 2],
    kind: JointKind,
    driver: Option<String>,
    coordinate: Option<String>,
}

impl Joint {
    /// A revolute joint named `name` at the point `at`, between the bodies
    /// `first` and `second` ([`GROUND`] for the fixed frame); its reaction
    /// is the force `first` exerts on `second`.
    #[must_use]
    pub fn revolute(name: &str, at: &str, first: &str, second: &str) -> Self {
        Joint {
            name: name.to_string(),
            at: at.to_string(),
            bodies: [first.to_string(), second.to_string()],
            kind: JointKind::Revolute,
            driver: None,
            coordinate: None,
        }
    }

    /// A prismatic joint: `second` slides along `axis`, fixed in `first`
    /// and given in its axes (the fixed axes for [`GROUND`]; for a body,
    /// the axes turned by its angle), through the point `at`. Its reaction
    /// is the force normal to the axis and the moment `first` exerts on
    /// `second`.
    #[must_use]
    pub fn prismatic(name: &str, at: &str, first: &str, second: &str, axis: [f64; 2]) -> Self {
        Joint {
            name: name.to_string(),
            at: at.to_string(),
            bodies: [first.to_string(), second.to_string()],
            kind: JointKind::Prismatic(axis),
            driver: None,
            coordinate: None,
        }
    }

    /// The driver `driver` acts in this joint: its effort is a torque
    /// (revolute joint, angle driver) or a force along the axis (prismatic
    /// joint, length driver) that `first` exerts on `second`.
    #[must_use]
    pub fn driven_by(mut self, driver: &str) -> Self {
        self.driver = Some(driver.to_string());
        self
    }

    /// The coordinate that measures this joint's motion (an unknown or a
    /// driver): a force on it
    /// ([`DynamicsBuilder::coordinate_force`](super::DynamicsBuilder::coordinate_force))
    /// acts in this joint, a torque (revolute) or a force along the axis
    /// (prismatic) that `first` exerts on `second`, which the joint
    /// reactions then take.
    #[must_use]
    pub fn coordinate(mut self, coordinate: &str) -> Self {
        self.coordinate = Some(coordinate.to_string());
        self
    }
}

/// A joint with its names resolved.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ResolvedJoint {
    name: String,
    at: usize,
    /// The two bodies; `None` for the ground.
    bodies: [Option<usize>; 2],
    kind: JointKind,
    driver: Option<usize>,
    /// The coordinate measuring the joint's motion, where given.
    coordinate: Option<usize>,
}

/// Resolves `joints` against the mechanism's names and the bodies.
pub(super) fn resolve(
    joints: &[Joint],
    names: &Names<'_>,
    body_names: &[String],
    bodies: &[ResolvedBody],
) -> Result<Vec<ResolvedJoint>, Error> {
    let invalid = |item: String, detail: String| Error::InvalidDynamics { item, detail };
    if !joints.is_empty() && names.dim != 2 {
        return Err(invalid(
            "joints".to_string(),
            "joint reactions are computed for planar mechanisms only".to_string(),
        ));
    }
    let mut out = Vec::with_capacity(joints.len());
    for j in joints {
        let item = format!("joint `{}`", j.name);
        let at = names
            .points
            .iter()
            .position(|p| *p == j.at)
            .ok_or_else(|| {
                invalid(
                    item.clone(),
                    format!(
                        "the mechanism has no point `{}` (its points: {})",
                        j.at,
                        names.points.join(", ")
                    ),
                )
            })?;
        let body = |name: &str| -> Result<Option<usize>, Error> {
            if name == GROUND {
                return Ok(None);
            }
            body_names
                .iter()
                .position(|b| b == name)
                .map(Some)
                .ok_or_else(|| {
                    invalid(
                        item.clone(),
                        format!(
                            "there is no body `{name}` (the bodies: {}; `{GROUND}` for the frame)",
                            body_names.join(", ")
                        ),
                    )
                })
        };
        let pair = [body(&j.bodies[0])?, body(&j.bodies[1])?];
        if pair[0] == pair[1] {
            return Err(invalid(item, format!("joins `{}` to itself", j.bodies[0])));
        }
        if let JointKind::Prismatic(axis) = j.kind {
            let norm = crate::math::sqrt(axis[0] * axis[0] + axis[1] * axis[1]);
            if !(norm.is_finite() && norm > 0.0) {
                return Err(invalid(
                    item,
                    format!("its axis {axis:?} must be finite and not zero"),
                ));
            }
            if let Some(b) = pair[0].and_then(|b| bodies.get(b)) {
                if matches!(b.turning, Turns::Frame(_)) {
                    return Err(invalid(
                        item,
                        "its first body turns with a frame".to_string(),
                    ));
                }
            }
        }
        let driver = match &j.driver {
            None => None,
            Some(d) => {
                let k = names
                    .coordinates
                    .iter()
                    .position(|(n, role, _)| n == d && *role == Role::Driver)
                    .ok_or_else(|| invalid(item.clone(), format!("there is no driver `{d}`")))?;
                let want = match j.kind {
                    JointKind::Revolute => Kind::Angle,
                    JointKind::Prismatic(_) => Kind::Length,
                };
                if names.coordinates[k].2 != want {
                    return Err(invalid(
                        item,
                        format!(
                            "driver `{d}` is {}, which a {} joint cannot transmit",
                            if want == Kind::Angle {
                                "a length"
                            } else {
                                "an angle"
                            },
                            if want == Kind::Angle {
                                "revolute"
                            } else {
                                "prismatic"
                            }
                        ),
                    ));
                }
                Some(k)
            }
        };
        let coordinate = match &j.coordinate {
            None => None,
            Some(c) => Some(
                names
                    .coordinates
                    .iter()
                    .position(|(n, _, _)| n == c)
                    .ok_or_else(|| {
                        invalid(item.clone(), format!("there is no coordinate `{c}`"))
                    })?,
            ),
        };
        out.push(ResolvedJoint {
            name: j.name.clone(),
            at,
            bodies: pair,
            kind: j.kind.clone(),
            driver,
            coordinate,
        });
    }
    Ok(out)
}

/// The reaction at one joint.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JointReaction {
    /// The joint's name.
    pub name: String,
    /// The force the first body exerts on the second, in the fixed axes
    /// (N; z = 0). At a prismatic joint, normal to the axis (plus the
    /// driver's force along it where a driver acts there).
    pub force: Vector3<f64>,
    /// The same force in the second body's axes (turned by minus its
    /// angle; the fixed axes for a body that does not turn).
    pub force_in_body: Vector3<f64>,
    /// The moment the first body exerts on the second at a prismatic
    /// joint (N·m); zero at a revolute joint.
    pub moment: f64,
    /// The driver's effort transmitted in this joint, where one acts.
    pub effort: Option<f64>,
}

/// The reactions at every joint ([`Dynamics::reactions`]), in the order
/// the joints were given.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Reactions {
    /// One per joint.
    pub joints: Vec<JointReaction>,
}

impl Reactions {
    /// The reaction at the joint named `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&JointReaction> {
        self.joints.iter().find(|j| j.name == name)
    }
}

/// The angle of body `b` (Σ c_j q_j; zero for one that does not turn).
fn body_angle(b: &ResolvedBody, s: &dyn View) -> f64 {
    match &b.turning {
        Turns::Angle(terms) => terms.iter().map(|&(j, c)| c * s.coordinate(j)[0]).sum(),
        Turns::No | Turns::Frame(_) => 0.0,
    }
}

impl Dynamics {
    /// The reaction at every joint given with [`super::DynamicsBuilder::joint`]
    /// at `motion`, a motion of `m` (planar mechanisms), by the
    /// Newton–Euler equations of every body (see the [module](super)): the
    /// force each joint's first body exerts on its second, the moment at a
    /// prismatic joint, and the driver's effort in its joint, which equals
    /// [`Dynamics::inverse`]'s. The motion is all it reads: `m` names the
    /// mechanism's type, and no analysis is repeated.
    ///
    /// # Errors
    /// [`Error::InvalidDynamics`] when the joints do not determine the
    /// reactions (the count of unknowns is not three per body, or the
    /// system is singular at this pose), when a force does not name the
    /// body it acts on ([`super::DynamicsBuilder::force_on`]), a spring
    /// the bodies of its ends ([`super::Spring::between`]), or a force on a
    /// coordinate the joint it acts in ([`Joint::coordinate`]).
    pub fn reactions<M: Mechanism>(&self, m: &M, motion: &M::Motion) -> Result<Reactions, Error> {
        let _ = m;
        self.fits_mechanism::<M>()?;
        self.reactions_in(&Generated(motion))
    }

    /// [`Dynamics::reactions`] over a view of the motion.
    pub(super) fn reactions_in(&self, s: &dyn View) -> Result<Reactions, Error> {
        let invalid = |item: &str, detail: String| Error::InvalidDynamics {
            item: item.to_string(),
            detail,
        };
        if self.joints.is_empty() {
            return Err(invalid(
                "joints",
                "none given: declare them with `.joint(Joint::revolute(…))`".to_string(),
            ));
        }
        // The joint each force on a coordinate acts in.
        let mut in_joints = Vec::with_capacity(self.coordinate_forces.len());
        for (c, f) in &self.coordinate_forces {
            let Some(j) = self.joints.iter().find(|j| j.coordinate == Some(*c)) else {
                return Err(invalid(
                    "a force on a coordinate",
                    format!(
                        "no joint is measured by coordinate {}: name it on its joint with \
                         `.coordinate(\"…\")` for the joint reactions",
                        c + 1
                    ),
                ));
            };
            in_joints.push((j, f));
        }
        if self.springs.iter().any(|s| s.bodies.is_none()) {
            return Err(invalid(
                "a spring",
                "it does not name the bodies its ends are fixed to: give them with \
                 `.between(\"first\", \"second\")` for the joint reactions"
                    .to_string(),
            ));
        }
        let nb = self.bodies.len();
        let rows = 3 * nb;
        // The columns of each joint's unknowns.
        let mut cols = 0;
        let mut first_col = Vec::with_capacity(self.joints.len());
        for j in &self.joints {
            first_col.push(cols);
            cols += 2 + usize::from(j.driver.is_some());
        }
        if cols != rows {
            return Err(invalid(
                "joints",
                format!(
                    "they give {cols} unknown reaction components for the {rows} equations of \
                     motion of {nb} bodies: declare every moving link as a body and every joint \
                     between them (with the driver's), so that the reactions are determined"
                ),
            ));
        }
        let nan = [Vector3::repeat(f64::NAN); 3];
        let point = |p: usize| s.point(p).unwrap_or(nan);
        let angles: Vec<f64> = self.bodies.iter().map(|b| body_angle(b, s)).collect();
        let mut a = DMatrix::<f64>::zeros(rows, cols);
        let mut rhs = DVector::<f64>::zeros(rows);
        // Each body's rate of momentum less gravity, and J α.
        for (i, b) in self.bodies.iter().enumerate() {
            let [_, _, acc] = point(b.center);
            let f = (acc - self.gravity) * b.mass;
            let (_, alpha, inertia) = super::evaluate::turning(b, s);
            rhs[3 * i] = f.x;
            rhs[3 * i + 1] = f.y;
            rhs[3 * i + 2] = (inertia * alpha).z;
        }
        // The applied loads, moved to the right-hand side.
        let [q, qd, qdd] = self.coordinates_of(s);
        let instant = |at: [Vector3<f64>; 3]| Instant {
            q: &q,
            qd: &qd,
            qdd: &qdd,
            position: at[0],
            velocity: at[1],
        };
        for (p, body, f) in &self.forces {
            let Some(b) = *body else {
                return Err(invalid(
                    "a force",
                    format!(
                        "the force at point {} does not name the body it acts on: give it with \
                         `.force_on(\"body\", \"point\", …)` for the joint reactions",
                        p + 1
                    ),
                ));
            };
            let at = point(*p);
            let f = Vector3::from(f(&instant(at)));
            let f = Vector3::new(f.x, f.y, 0.0);
            let r = at[0] - point(self.bodies[b].center)[0];
            rhs[3 * b] -= f.x;
            rhs[3 * b + 1] -= f.y;
            rhs[3 * b + 2] -= r.cross(&f).z;
        }
        for (b, t) in &self.torques {
            let at = point(self.bodies[*b].center);
            rhs[3 * b + 2] -= t(&instant(at))[2];
        }
        // Each spring pulls its ends together with its tension
        // f = k (L − L₀) + c L' along e, from A to B: +f e on A's body at A,
        // −f e on B's at B.
        for sp in &self.springs {
            let pull = sp.pull(s);
            let (f, [ra, rb]) = (pull.e * pull.tension, pull.ends);
            let ends = sp.bodies.unwrap_or([None; 2]);
            for (body, at, f) in [(ends[0], ra, f), (ends[1], rb, -f)] {
                if let Some(b) = body {
                    let r = at - point(self.bodies[b].center)[0];
                    rhs[3 * b] -= f.x;
                    rhs[3 * b + 1] -= f.y;
                    rhs[3 * b + 2] -= r.cross(&f).z;
                }
            }
        }
        // A force on a coordinate: a torque about its revolute joint, or a
        // force along its prismatic joint's axis, on the second body, and
        // its opposite on the first.
        for (j, f) in in_joints {
            let value = f(&instant([Vector3::zeros(); 3]));
            let r = point(j.at)[0];
            let (force, torque) = match j.kind {
                JointKind::Revolute => (Vector3::zeros(), value),
                JointKind::Prismatic(axis) => (self.axis_of(j, axis, &angles) * value, 0.0),
            };
            for (body, sign) in [(j.bodies[1], 1.0), (j.bodies[0], -1.0)] {
                if let Some(b) = body {
                    let arm = r - point(self.bodies[b].center)[0];
                    rhs[3 * b] -= sign * force.x;
                    rhs[3 * b + 1] -= sign * force.y;
                    rhs[3 * b + 2] -= sign * (arm.cross(&force).z + torque);
                }
            }
        }
        // The joints' unknowns: a force (and moment) on the second body,
        // their opposites on the first.
        let mut place = |body: Option<usize>,
                         sign: f64,
                         col: usize,
                         r: Vector3<f64>,
                         f: Vector3<f64>,
                         m: f64| {
            if let Some(b) = body {
                let arm = r - point(self.bodies[b].center)[0];
                a[(3 * b, col)] += sign * f.x;
                a[(3 * b + 1, col)] += sign * f.y;
                a[(3 * b + 2, col)] += sign * (arm.cross(&f).z + m);
            }
        };
        let mut directions = Vec::with_capacity(self.joints.len());
        for (j, &c) in self.joints.iter().zip(&first_col) {
            let r = point(j.at)[0];
            let [first, second] = j.bodies;
            let (u, v) = match j.kind {
                JointKind::Revolute => (Vector3::x(), Vector3::y()),
                JointKind::Prismatic(axis) => {
                    let e = self.axis_of(j, axis, &angles);
                    (e, Vector3::new(-e.y, e.x, 0.0))
                }
            };
            directions.push((u, v));
            match j.kind {
                JointKind::Revolute => {
                    for (k, d) in [u, v].into_iter().enumerate() {
                        place(second, 1.0, c + k, r, d, 0.0);
                        place(first, -1.0, c + k, r, d, 0.0);
                    }
                    if j.driver.is_some() {
                        place(second, 1.0, c + 2, r, Vector3::zeros(), 1.0);
                        place(first, -1.0, c + 2, r, Vector3::zeros(), 1.0);
                    }
                }
                JointKind::Prismatic(_) => {
                    // The normal force, the moment, and the driver's force
                    // along the axis.
                    place(second, 1.0, c, r, v, 0.0);
                    place(first, -1.0, c, r, v, 0.0);
                    place(second, 1.0, c + 1, r, Vector3::zeros(), 1.0);
                    place(first, -1.0, c + 1, r, Vector3::zeros(), 1.0);
                    if j.driver.is_some() {
                        place(second, 1.0, c + 2, r, u, 0.0);
                        place(first, -1.0, c + 2, r, u, 0.0);
                    }
                }
            }
        }
        if !(a.iter().all(|v| v.is_finite()) && rhs.iter().all(|v| v.is_finite())) {
            return Err(invalid(
                "joints",
                "a position, acceleration or load at this pose is not finite".to_string(),
            ));
        }
        let x = a
            .lu()
            .solve(&rhs)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or_else(|| {
                invalid(
                    "joints",
                    "the equations of motion do not determine the reactions at this pose (a \
                 singular pose, or a joint missing and another repeated)"
                        .to_string(),
                )
            })?;
        let mut out = Vec::with_capacity(self.joints.len());
        for ((j, &c), (u, v)) in self.joints.iter().zip(&first_col).zip(directions) {
            let effort = j.driver.map(|_| x[c + 2]);
            let (force, moment) = match j.kind {
                JointKind::Revolute => (u * x[c] + v * x[c + 1], 0.0),
                JointKind::Prismatic(_) => (v * x[c] + u * effort.unwrap_or(0.0), x[c + 1]),
            };
            let turn = j.bodies[1].map_or(0.0, |b| angles[b]);
            let (s, co) = crate::math::sin_cos(turn);
            let force_in_body =
                Vector3::new(co * force.x + s * force.y, -s * force.x + co * force.y, 0.0);
            out.push(JointReaction {
                name: j.name.clone(),
                force,
                force_in_body,
                moment,
                effort,
            });
        }
        Ok(Reactions { joints: out })
    }
}

impl Dynamics {
    /// The unit vector, in the fixed axes, of the prismatic joint `j`'s
    /// `axis` (given in its first body's axes, turned by that body's angle
    /// among `angles`).
    fn axis_of(&self, j: &ResolvedJoint, axis: [f64; 2], angles: &[f64]) -> Vector3<f64> {
        let turn = j.bodies[0]
            .and_then(|b| angles.get(b))
            .copied()
            .unwrap_or(0.0);
        let (s, c) = crate::math::sin_cos(turn);
        let norm = crate::math::sqrt(axis[0] * axis[0] + axis[1] * axis[1]);
        Vector3::new(
            (c * axis[0] - s * axis[1]) / norm,
            (s * axis[0] + c * axis[1]) / norm,
            0.0,
        )
    }
}
