//! Joint reactions by the Newton–Euler equations of every body at once:
//! the joints ([`Joint`]) between the bodies and the ground, the reaction
//! of each as unknowns, and the driver's effort at its joint.
//!
//! For each body b with centre of mass G, the sum of the forces on it and
//! their moment about G equal its rate of momentum and of angular
//! momentum:
//!
//! Σ F_joints + Σ F_applied + m g = m a_G,
//! Σ (r_J − r_G) × F_joints + Σ M_joints + Σ (r_P − r_G) × F_applied + Σ T = J α + ω × J ω,
//!
//! linear in the reactions. In a planar mechanism that is three equations
//! per body (the force's x and y, the moment's z); at a revolute joint the
//! force (2 components) the first body exerts on the second, at a
//! prismatic joint the force normal to its axis and the moment (2), at
//! the joint a driver acts in its effort (a torque about a revolute, a
//! force along a prismatic axis). With every moving link a body and every
//! joint declared, a mechanism of one degree of freedom has as many
//! unknowns as equations (Grübler's count), solved by LU.
//!
//! In a spatial mechanism it is six equations per body, and a joint
//! carries what it does not let move: a spherical joint a force (3), a
//! revolute joint a force and the moment normal to its axis (5), a
//! prismatic joint the force normal to its axis and a moment (5), a
//! cylindrical joint the force and the moment normal to its axis (4). A
//! link between two spherical joints may spin about the line through
//! them without changing the mechanism: one of its moment equations then
//! holds whatever the reactions are (a slender rod, or a body without
//! inertia), the equations outnumber the unknowns by one, and they are
//! solved by least squares, which must then satisfy every one of them.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

use nalgebra::Vector3;

use super::{Names, ResolvedBody, Turns};
use crate::error::Error;
use crate::mechanism::{Kind, Role};

/// The name that stands for the fixed frame in a joint.
pub const GROUND: &str = "ground";

/// What a joint lets move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum JointKind {
    /// A pin: relative rotation (about z in a planar mechanism, about
    /// its axis in a spatial one).
    Revolute,
    /// A slider along its axis, fixed in the first body.
    Prismatic,
    /// A ball joint: relative rotation about every axis (spatial).
    Spherical,
    /// Rotation about its axis and sliding along it (spatial).
    Cylindrical,
}

impl JointKind {
    pub(super) fn word(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
            JointKind::Spherical => "spherical",
            JointKind::Cylindrical => "cylindrical",
        }
    }
}

/// The axis of a joint, in its first body's axes: `[x, y]` in a planar
/// mechanism, `[x, y, z]` in a spatial one (any length but zero).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis(pub [f64; 3]);

impl From<[f64; 2]> for Axis {
    fn from(a: [f64; 2]) -> Self {
        Axis([a[0], a[1], 0.0])
    }
}

impl From<[f64; 3]> for Axis {
    fn from(a: [f64; 3]) -> Self {
        Axis(a)
    }
}

/// A joint between two bodies (or a body and [`GROUND`]), at one of the
/// mechanism's points, and the driver acting in it if any: revolute or
/// prismatic in a planar mechanism; also spherical and cylindrical in a
/// spatial one, where a revolute, prismatic or cylindrical joint has an
/// axis.
///
/// ```
/// use kinematics_core::dynamics::Joint;
/// // The crank's bearing, where the motor drives φ.
/// let a = Joint::revolute("A", "A", "ground", "crank").driven_by("phi");
/// // The piston in its cylinder, sliding along x.
/// let c = Joint::prismatic("cylinder", "C", "ground", "piston", [1.0, 0.0]);
/// // In space: a bearing about y, and a ball joint.
/// let o = Joint::revolute("O", "O", "ground", "crank").about([0.0, 1.0, 0.0]);
/// let b = Joint::spherical("B", "B", "crank", "coupler");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    name: String,
    at: String,
    bodies: [String; 2],
    kind: JointKind,
    axis: Option<[f64; 3]>,
    driver: Option<String>,
    coordinate: Option<String>,
}

impl Joint {
    fn new(name: &str, at: &str, first: &str, second: &str, kind: JointKind) -> Self {
        Joint {
            name: name.to_string(),
            at: at.to_string(),
            bodies: [first.to_string(), second.to_string()],
            kind,
            axis: None,
            driver: None,
            coordinate: None,
        }
    }

    /// A revolute joint named `name` at the point `at`, between the bodies
    /// `first` and `second` ([`GROUND`] for the fixed frame); its reaction
    /// is the force (and in space the moment) `first` exerts on `second`.
    /// In a spatial mechanism give its axis with [`Joint::about`].
    #[must_use]
    pub fn revolute(name: &str, at: &str, first: &str, second: &str) -> Self {
        Self::new(name, at, first, second, JointKind::Revolute)
    }

    /// A prismatic joint: `second` slides along `axis`, fixed in `first`
    /// and given in its axes (the fixed axes for [`GROUND`]; for a body,
    /// the axes turned by its angle or its frame), through the point
    /// `at`: `[x, y]` in a planar mechanism, `[x, y, z]` in a spatial one.
    /// Its reaction is the force normal to the axis and the moment
    /// `first` exerts on `second`.
    #[must_use]
    pub fn prismatic(
        name: &str,
        at: &str,
        first: &str,
        second: &str,
        axis: impl Into<Axis>,
    ) -> Self {
        let mut j = Self::new(name, at, first, second, JointKind::Prismatic);
        j.axis = Some(axis.into().0);
        j
    }

    /// A spherical (ball) joint of a spatial mechanism: its reaction is
    /// the force `first` exerts on `second`, and no moment.
    #[must_use]
    pub fn spherical(name: &str, at: &str, first: &str, second: &str) -> Self {
        Self::new(name, at, first, second, JointKind::Spherical)
    }

    /// A cylindrical joint of a spatial mechanism, turning about and
    /// sliding along `axis` (in `first`'s axes): its reaction is the force
    /// and the moment normal to the axis.
    #[must_use]
    pub fn cylindrical(name: &str, at: &str, first: &str, second: &str, axis: [f64; 3]) -> Self {
        let mut j = Self::new(name, at, first, second, JointKind::Cylindrical);
        j.axis = Some(axis);
        j
    }

    /// The joint's axis, in `first`'s axes (the fixed axes for
    /// [`GROUND`]; for a body, turned by its frame or angle): for a
    /// revolute joint of a spatial mechanism, directed so that its driver
    /// or coordinate grows as `second` turns positively about it relative
    /// to `first` (right-hand rule). In a planar mechanism a revolute
    /// joint's axis is z.
    #[must_use]
    pub fn about(mut self, axis: [f64; 3]) -> Self {
        self.axis = Some(axis);
        self
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
    /// driver; the driver acting in the joint measures it without this):
    /// a force on it
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
    pub(super) name: String,
    pub(super) at: usize,
    /// The two bodies; `None` for the ground.
    pub(super) bodies: [Option<usize>; 2],
    pub(super) kind: JointKind,
    /// The unit axis in the first body's axes (z for a planar revolute
    /// joint; unused at a spherical one).
    pub(super) axis: Vector3<f64>,
    pub(super) driver: Option<usize>,
    /// The coordinate measuring the joint's motion, where given.
    pub(super) coordinate: Option<usize>,
}

/// Resolves `joints` against the mechanism's names and the bodies.
pub(super) fn resolve(
    joints: &[Joint],
    names: &Names<'_>,
    body_names: &[String],
    bodies: &[ResolvedBody],
) -> Result<Vec<ResolvedJoint>, Error> {
    let invalid = |item: String, detail: String| Error::InvalidDynamics { item, detail };
    let planar = names.dim == 2;
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
        let axis = joint_axis(j, planar).map_err(|detail| invalid(item.clone(), detail))?;
        if planar
            && j.kind == JointKind::Prismatic
            && let Some(b) = pair[0].and_then(|b| bodies.get(b))
            && matches!(b.turning, Turns::Frame(_))
        {
            return Err(invalid(
                item,
                "its first body turns with a frame".to_string(),
            ));
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
                    JointKind::Prismatic => Kind::Length,
                    JointKind::Spherical | JointKind::Cylindrical => {
                        return Err(invalid(
                            item,
                            format!(
                                "a {} joint transmits no driver's effort: a driver acts in a \
                                 revolute joint (an angle) or a prismatic one (a length)",
                                j.kind.word()
                            ),
                        ));
                    }
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
            kind: j.kind,
            axis,
            driver,
            coordinate,
        });
    }
    Ok(out)
}

/// The unit axis of joint `j` in its first body's axes, checked against
/// the kind of mechanism; or what is wrong with it.
fn joint_axis(j: &Joint, planar: bool) -> Result<Vector3<f64>, String> {
    let kind = j.kind.word();
    let axis = match (j.kind, j.axis, planar) {
        (JointKind::Spherical | JointKind::Cylindrical, _, true) => {
            return Err(format!(
                "a planar mechanism's joints are revolute or prismatic, not {kind}"
            ));
        }
        (JointKind::Revolute, None, true) => return Ok(Vector3::z()),
        (JointKind::Revolute, Some(a), true) => {
            if a[0] == 0.0 && a[1] == 0.0 && a[2] > 0.0 {
                return Ok(Vector3::z());
            }
            return Err(format!(
                "its axis {a:?}: a planar mechanism's revolute joints turn about z; leave out \
                 `.about(…)`"
            ));
        }
        (JointKind::Spherical, None, false) => return Ok(Vector3::zeros()),
        (JointKind::Spherical, Some(a), false) => {
            return Err(format!(
                "a spherical joint turns about every axis: leave out its axis {a:?}"
            ));
        }
        (_, None, _) => {
            return Err(format!(
                "a {kind} joint of a spatial mechanism needs its axis: give it with \
                 `.about([x, y, z])` (in the first body's axes)"
            ));
        }
        (JointKind::Prismatic, Some(a), true) if a[2] != 0.0 => {
            return Err(format!(
                "its axis {a:?} leaves the plane: give `[x, y]` in a planar mechanism"
            ));
        }
        (_, Some(a), _) => Vector3::from(a),
    };
    let norm = axis.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(format!(
            "its axis {:?} must be finite and not zero",
            <[f64; 3]>::from(axis)
        ));
    }
    Ok(axis / norm)
}
