//! Lowering of the `bodies` and `loads` sections and of the item form of
//! `joints`: each body's mass, centre of mass, orientation and inertia,
//! each load, and each joint's axis, as roots of the graph, with their
//! names, kinds and dimensions checked.
//!
//! The constants (masses, inertias, gravity, a spring's stiffness, free
//! length and damping) may use the parameters only; a load's value may
//! also use the coordinates, their rates (`rate(x)`) and the time of a
//! forward simulation (`time`, in seconds from its start).

mod args;

use syn::spanned::Spanned;
use syn::{Expr, Ident};

use super::Lowerer;
use crate::ir::{Id, Leaf};
use crate::names::Binding;
use crate::parse::{Call, Definition};

/// The name of the fixed frame, which no body may take.
pub const GROUND: &str = "ground";

/// The `bodies` and `loads` sections, lowered.
pub struct LoweredDynamics {
    /// g, 2 or 3 roots (empty without a `gravity` load).
    pub gravity: Vec<Id>,
    pub bodies: Vec<LoweredBody>,
    pub loads: Vec<Load>,
    pub springs: Vec<Spring>,
    pub joints: Vec<LoweredJoint>,
}

/// A body as written: its angle still an expression (its coefficients
/// are found by differentiating it, after lowering).
pub struct LoweredBody {
    pub name: String,
    pub mass: Id,
    /// The point at its centre of mass.
    pub center: String,
    /// Planar: its angle, with the tokens errors about it point at.
    pub angle: Option<(Id, proc_macro2::TokenStream)>,
    /// Spatial: the frame it moves with.
    pub frame: Option<String>,
    /// Its inertia about the centre of mass: empty, one root (planar) or
    /// nine, row by row, in the axes of its frame (spatial).
    pub inertia: Vec<Id>,
}

/// What a load acts on (names checked against the definition).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LoadTarget {
    /// A force at a point (on the named body, where given).
    Point {
        /// The point.
        point: String,
        /// The body it acts on, where named.
        body: Option<String>,
    },
    /// A generalised force on a coordinate (a force along a length, a
    /// torque about an angle).
    Coordinate {
        /// The coordinate.
        coordinate: String,
    },
    /// A torque on a body.
    Torque {
        /// The body.
        body: String,
    },
}

/// A load: what it acts on and its value, roots of the parameters, the
/// coordinates and their rates (a force at a point: 2 or 3 components; a
/// force on a coordinate: one; a torque: one about the normal of a planar
/// mechanism, three in a spatial one).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Load {
    /// What it acts on.
    pub target: LoadTarget,
    /// Its value.
    pub value: Vec<Id>,
}

/// A linear spring and viscous damper between two points.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Spring {
    /// The point at its first end.
    pub from: String,
    /// The point at its second end.
    pub to: String,
    /// k (a root of the parameters; zero where not given).
    pub stiffness: Id,
    /// L₀.
    pub free_length: Id,
    /// c.
    pub damping: Id,
    /// The bodies its ends are fixed to, where given (`ground` for the
    /// frame).
    pub between: Option<[String; 2]>,
}

/// What a joint lets move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// A pin: rotation about z (planar) or about its axis (spatial).
    Revolute,
    /// A slider along its axis.
    Prismatic,
    /// A ball joint (spatial).
    Spherical,
    /// Rotation about and sliding along its axis (spatial).
    Cylindrical,
}

impl JointKind {
    /// The word for it in the language.
    #[must_use]
    pub fn word(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
            JointKind::Spherical => "spherical",
            JointKind::Cylindrical => "cylindrical",
        }
    }
}

/// A joint of the `joints` section, for the reactions: its kind, the
/// point it is at, the bodies it joins (the reaction is the force the
/// first exerts on the second), its axis in the first body's axes (roots
/// of the parameters: none for a planar revolute or a spherical joint),
/// and the driver acting in it and the coordinate measuring it, where
/// given.
pub struct LoweredJoint {
    /// Its name.
    pub name: String,
    /// What it lets move.
    pub kind: JointKind,
    /// The point it is at.
    pub point: String,
    /// The two bodies, either of them `ground`.
    pub between: [String; 2],
    /// Its axis: empty, 2 or 3 roots.
    pub axis: Vec<Id>,
    /// The driver acting in it: its index among the coordinates, its
    /// name and the tokens naming it.
    pub driver: Option<(u32, String, proc_macro2::TokenStream)>,
    /// The coordinate measuring its motion.
    pub coordinate: Option<String>,
}

/// What an expression may depend on.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Allowed {
    /// Parameters and numbers.
    Constant,
    /// Also the coordinates, their rates and the time.
    Motion,
}

impl Lowerer<'_> {
    /// The two sections, lowered; `None` when neither is written.
    pub(super) fn dynamics(&mut self, def: &Definition, dim: usize) -> Option<LoweredDynamics> {
        def.dynamics_span?;
        // Gravity or a force written as a 3-D vector in a planar mechanism
        // is a dimension error below, not a sign of a spatial mechanism.
        let spatial = self.spatial;
        let mut out = LoweredDynamics {
            gravity: Vec::new(),
            bodies: Vec::new(),
            loads: Vec::new(),
            springs: Vec::new(),
            joints: Vec::new(),
        };
        let mut body_names: Vec<&Ident> = Vec::new();
        for item in &def.bodies {
            let name = syn::ext::IdentExt::unraw(&item.name).to_string();
            if let Some(first) = body_names.iter().find(|b| **b == &item.name) {
                let mut err = syn::Error::new(
                    item.name.span(),
                    format!("body `{name}` is declared twice; give each body its own name"),
                );
                err.combine(syn::Error::new(first.span(), "first declared here"));
                self.errors.push(err);
                continue;
            }
            if name == GROUND {
                self.errors.at(
                    item.name.span(),
                    "`ground` is the fixed frame, which has no mass; name the moving link \
                     otherwise",
                );
                continue;
            }
            body_names.push(&item.name);
            if let Some(b) = self.body_item(item, name, dim) {
                out.bodies.push(b);
            }
        }
        let bodies: Vec<String> = out.bodies.iter().map(|b| b.name.clone()).collect();
        for item in &def.loads {
            self.load_item(item, dim, &bodies, &mut out);
        }
        let mut joint_names: Vec<&Ident> = Vec::new();
        for item in &def.joint_items {
            if let Some(first) = joint_names.iter().find(|j| **j == &item.name) {
                let mut err = syn::Error::new(
                    item.name.span(),
                    format!(
                        "joint `{}` is declared twice; give each joint its own name",
                        syn::ext::IdentExt::unraw(&item.name)
                    ),
                );
                err.combine(syn::Error::new(first.span(), "first declared here"));
                self.errors.push(err);
                continue;
            }
            joint_names.push(&item.name);
            if let Some(j) = self.joint_item(item, dim, def.drivers.len(), &bodies) {
                out.joints.push(j);
            }
        }
        self.spatial = spatial;
        Some(out)
    }

    /// One item of the `joints` section.
    fn joint_item(
        &mut self,
        item: &Call,
        dim: usize,
        drivers: usize,
        bodies: &[String],
    ) -> Option<LoweredJoint> {
        let name = syn::ext::IdentExt::unraw(&item.name).to_string();
        let usage = if dim == 2 {
            "`bearing(revolute, O, between = (ground, crank), driver = phi)` or \
             `cylinder(prismatic, C, between = (ground, piston), axis = vec2(1.0, 0.0))`"
        } else {
            "`bearing(revolute, O, between = (ground, crank), axis = vec3(0.0, 0.0, 1.0))` or \
             `ball(spherical, A, between = (crank, coupler))`"
        };
        let [kind_expr, point_expr] = item.positional.as_slice() else {
            self.errors.spanned(
                &item.tokens,
                format!(
                    "joint `{name}` is written with its kind and its point, then the bodies it \
                     joins: {usage}"
                ),
            );
            return None;
        };
        self.known_keys(item, &["between", "axis", "driver", "coordinate"])?;
        let word = match kind_expr {
            Expr::Path(p) => p.path.get_ident().map(ToString::to_string),
            _ => None,
        };
        let kind = match word.as_deref() {
            Some("revolute") => JointKind::Revolute,
            Some("prismatic") => JointKind::Prismatic,
            Some("spherical") => JointKind::Spherical,
            Some("cylindrical") => JointKind::Cylindrical,
            _ => {
                self.errors.spanned(
                    kind_expr,
                    "a joint's kind is `revolute`, `prismatic`, `spherical` or `cylindrical`",
                );
                return None;
            }
        };
        if dim == 2 && matches!(kind, JointKind::Spherical | JointKind::Cylindrical) {
            self.errors.spanned(
                kind_expr,
                format!(
                    "the mechanism is planar: its joints are `revolute` or `prismatic`, not `{}`",
                    kind.word()
                ),
            );
            return None;
        }
        let point = self.point_name(point_expr, &format!("the point of joint `{name}`"))?;
        let Some(pair) = self.named(item, "between") else {
            self.errors.spanned(
                &item.tokens,
                format!(
                    "joint `{name}` does not say which bodies it joins: add `between = (first, \
                     second)` (the reaction is the force the first exerts on the second; \
                     `ground` for the frame)"
                ),
            );
            return None;
        };
        let between = self.body_pair(pair, bodies, "joint")?;
        if between[0] == between[1] {
            self.errors.spanned(
                pair,
                format!("joint `{name}` joins `{}` to itself", between[0]),
            );
            return None;
        }
        let needs_axis = match kind {
            JointKind::Revolute => dim == 3,
            JointKind::Prismatic | JointKind::Cylindrical => true,
            JointKind::Spherical => false,
        };
        let axis = match (self.named(item, "axis"), needs_axis) {
            (Some(e), true) => self.vector(
                e,
                dim,
                Allowed::Constant,
                &format!("the axis of joint `{name}`"),
            )?,
            (Some(e), false) => {
                let why = if kind == JointKind::Spherical {
                    "a spherical joint turns about every axis"
                } else {
                    "a planar mechanism's revolute joints turn about z"
                };
                self.errors
                    .spanned(e, format!("{why}: remove `axis = …` from joint `{name}`"));
                return None;
            }
            (None, true) => {
                let write = if dim == 2 {
                    "axis = vec2(1.0, 0.0)"
                } else {
                    "axis = vec3(0.0, 0.0, 1.0)"
                };
                self.errors.spanned(
                    &item.tokens,
                    format!(
                        "joint `{name}`, a {} joint, needs its axis, in the axes of its first \
                         body (`{write}`)",
                        kind.word()
                    ),
                );
                return None;
            }
            (None, false) => Vec::new(),
        };
        let transmits = matches!(kind, JointKind::Revolute | JointKind::Prismatic);
        let mut coordinate_of = |key: &str| -> Option<Option<(u32, String, &Expr)>> {
            let Some(e) = self.named(item, key) else {
                return Some(None);
            };
            if !transmits {
                self.errors.spanned(
                    e,
                    format!(
                        "a {} joint transmits no effort along or about one axis: a `{key}` acts \
                         in a revolute or prismatic joint",
                        kind.word()
                    ),
                );
                return None;
            }
            match self.binding(e) {
                Some((n, Binding::Coord(j))) if key == "coordinate" || (j as usize) < drivers => {
                    Some(Some((j, n, e)))
                }
                _ => {
                    let what = if key == "driver" {
                        "a driver of `drivers { … }`"
                    } else {
                        "a coordinate (a driver or an unknown)"
                    };
                    self.errors.spanned(e, format!("`{key} = …` names {what}"));
                    None
                }
            }
        };
        let driver =
            coordinate_of("driver")?.map(|(j, n, e)| (j, n, quote::ToTokens::to_token_stream(e)));
        let coordinate = coordinate_of("coordinate")?.map(|(_, n, _)| n);
        Some(LoweredJoint {
            name,
            kind,
            point,
            between,
            axis,
            driver,
            coordinate,
        })
    }

    /// One item of `bodies`.
    fn body_item(&mut self, item: &Call, name: String, dim: usize) -> Option<LoweredBody> {
        const KEYS: [&str; 5] = ["mass", "center", "angle", "frame", "inertia"];
        if let Some(extra) = item.positional.first() {
            self.errors.spanned(
                extra,
                format!(
                    "a body's properties are given by name: `{name}(mass = m, center = G, \
                     angle = th, inertia = j)`"
                ),
            );
            return None;
        }
        self.known_keys(item, &KEYS)?;
        let mass = match self.named(item, "mass") {
            Some(e) => self.scalar(e, Allowed::Constant, &format!("the mass of body `{name}`"))?,
            None => {
                self.errors.spanned(
                    &item.tokens,
                    format!("body `{name}` has no mass: give it as `mass = m`"),
                );
                return None;
            }
        };
        let center = match self.named(item, "center") {
            Some(e) => self.point_name(e, &format!("the centre of mass of body `{name}`"))?,
            None => {
                self.errors.spanned(
                    &item.tokens,
                    format!(
                        "body `{name}` has no centre of mass: give the point of `points {{ … }}` \
                         at it as `center = G`"
                    ),
                );
                return None;
            }
        };
        let angle = match self.named(item, "angle") {
            Some(e) if dim == 3 => {
                self.errors.spanned(
                    e,
                    "the mechanism is spatial: a body turns with a frame (`frame = name`), not \
                     an angle",
                );
                return None;
            }
            Some(e) => {
                let what = format!("the angle of body `{name}`");
                let id = self.scalar(e, Allowed::Motion, &what)?;
                // An angle is a function of the pose: its rate is found
                // from it, never written.
                if self
                    .g
                    .leaves_under(id)
                    .any(|l| matches!(l, Leaf::Qd(_) | Leaf::Qdd(_) | Leaf::Time))
                {
                    self.errors.spanned(
                        e,
                        format!(
                            "{what} is a function of the coordinates; it may not use `rate(…)` \
                             or `time`"
                        ),
                    );
                    return None;
                }
                Some((id, quote::ToTokens::to_token_stream(e)))
            }
            None => None,
        };
        let frame = match self.named(item, "frame") {
            Some(e) if dim == 2 => {
                self.errors.spanned(
                    e,
                    "the mechanism is planar: a body turns by an angle (`angle = th3`), not \
                     with a frame",
                );
                return None;
            }
            Some(e) => Some(self.frame_name(e)?),
            None => None,
        };
        let inertia = match self.named(item, "inertia") {
            None => Vec::new(),
            Some(e) if angle.is_none() && frame.is_none() => {
                let how = if dim == 2 {
                    "angle = th"
                } else {
                    "frame = name"
                };
                self.errors.spanned(
                    e,
                    format!(
                        "body `{name}` has a moment of inertia but does not turn: give how it \
                         turns (`{how}`)"
                    ),
                );
                return None;
            }
            Some(e) if dim == 2 => {
                vec![self.scalar(
                    e,
                    Allowed::Constant,
                    &format!("the inertia of body `{name}`"),
                )?]
            }
            Some(e) => self.tensor(e, &name)?,
        };
        Some(LoweredBody {
            name,
            mass,
            center,
            angle,
            frame,
            inertia,
        })
    }

    /// A 3×3 inertia tensor written `[[…], […], […]]`, constant.
    fn tensor(&mut self, e: &Expr, body: &str) -> Option<Vec<Id>> {
        let rows: Option<Vec<&Expr>> = match e {
            Expr::Array(a) if a.elems.len() == 3 => Some(a.elems.iter().collect()),
            _ => None,
        };
        let entries: Option<Vec<&Expr>> = rows.and_then(|rows| {
            let mut out = Vec::new();
            for r in rows {
                match r {
                    Expr::Array(a) if a.elems.len() == 3 => out.extend(a.elems.iter()),
                    _ => return None,
                }
            }
            Some(out)
        });
        let Some(entries) = entries else {
            self.errors.spanned(
                e,
                format!(
                    "the inertia of body `{body}` in a spatial mechanism is a 3×3 tensor about \
                     its centre of mass in its frame's axes, written row by row: \
                     `[[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]`"
                ),
            );
            return None;
        };
        let what = format!("the inertia of body `{body}`");
        let mut out = Vec::with_capacity(9);
        for x in entries {
            out.push(self.scalar(x, Allowed::Constant, &what)?);
        }
        Some(out)
    }

    /// One item of `loads`.
    fn load_item(&mut self, item: &Call, dim: usize, bodies: &[String], out: &mut LoweredDynamics) {
        let kind = item.name.to_string();
        let (positional, keys): (usize, &[&str]) = match kind.as_str() {
            "gravity" => (1, &[]),
            "force" => (2, &["on"]),
            "torque" => (2, &[]),
            "spring" => (2, &["stiffness", "free_length", "damping", "between"]),
            _ => {
                self.errors.at(
                    item.name.span(),
                    format!(
                        "unknown load `{kind}`: the loads are `gravity(g)`, `force(P, f)` (at \
                         a point, or on a coordinate), `torque(body, t)` and `spring(A, B, \
                         stiffness = k, free_length = l0, damping = c)`"
                    ),
                );
                return;
            }
        };
        if item.positional.len() != positional {
            let usage = match kind.as_str() {
                "gravity" => "gravity(vec2(0.0, -9.81))",
                "force" => "force(C, vec2(fx, fy))` or `force(x, f)",
                "torque" => "torque(rod, t)",
                _ => "spring(A, B, stiffness = k, free_length = l0, damping = c)",
            };
            self.errors.spanned(
                &item.tokens,
                format!(
                    "`{kind}` takes {positional} argument{} without a key, but {} {} given; \
                     write `{usage}`",
                    if positional == 1 { "" } else { "s" },
                    item.positional.len(),
                    if item.positional.len() == 1 {
                        "was"
                    } else {
                        "were"
                    },
                ),
            );
            return;
        }
        if self.known_keys(item, keys).is_none() {
            return;
        }
        let args = &item.positional;
        match kind.as_str() {
            "gravity" => {
                if !out.gravity.is_empty() {
                    self.errors
                        .spanned(&item.tokens, "gravity is given twice; give it once");
                    return;
                }
                if let Some(g) = self.vector(&args[0], dim, Allowed::Constant, "gravity") {
                    out.gravity = g;
                }
            }
            "force" => {
                let body = match self.named(item, "on") {
                    Some(e) => match self.body_name(e, bodies) {
                        Some(b) => Some(b),
                        None => return,
                    },
                    None => None,
                };
                let target = self.binding(&args[0]);
                match target {
                    Some((name, Binding::Point(_))) => {
                        let what = format!("the force at `{name}`");
                        if let Some(value) = self.vector(&args[1], dim, Allowed::Motion, &what) {
                            out.loads.push(Load {
                                target: LoadTarget::Point { point: name, body },
                                value,
                            });
                        }
                    }
                    Some((name, Binding::Coord(_))) if body.is_none() => {
                        let what = format!("the force on coordinate `{name}`");
                        if let Some(v) = self.scalar(&args[1], Allowed::Motion, &what) {
                            out.loads.push(Load {
                                target: LoadTarget::Coordinate { coordinate: name },
                                value: vec![v],
                            });
                        }
                    }
                    Some((_, Binding::Coord(_))) => self.errors.spanned(
                        &item.tokens,
                        "a force on a coordinate acts in its joint, not on one body: remove \
                         `on = …`",
                    ),
                    _ => self.errors.spanned(
                        &args[0],
                        "a force acts at a point of `points { … }` (`force(C, vec2(fx, fy))`) \
                         or on a coordinate (`force(x, f)`, along a length or about an angle)",
                    ),
                }
            }
            "torque" => {
                let Some(body) = self.body_name(&args[0], bodies) else {
                    return;
                };
                let what = format!("the torque on `{body}`");
                let value = if dim == 2 {
                    self.scalar(&args[1], Allowed::Motion, &what)
                        .map(|v| vec![v])
                } else {
                    self.vector(&args[1], 3, Allowed::Motion, &what)
                };
                if let Some(value) = value {
                    out.loads.push(Load {
                        target: LoadTarget::Torque { body },
                        value,
                    });
                }
            }
            _ => {
                let ends = [
                    self.point_name(&args[0], "the first end of a spring"),
                    self.point_name(&args[1], "the second end of a spring"),
                ];
                let mut constant = |key: &str| match self.named(item, key) {
                    Some(e) => self.scalar(e, Allowed::Constant, &format!("a spring's {key}")),
                    None => Some(self.g.constant(0.0)),
                };
                let (stiffness, free_length, damping) = (
                    constant("stiffness"),
                    constant("free_length"),
                    constant("damping"),
                );
                let between = match self.named(item, "between") {
                    None => None,
                    Some(e) => match self.body_pair(e, bodies, "spring") {
                        Some(pair) => Some(pair),
                        None => return,
                    },
                };
                if let ([Some(from), Some(to)], Some(stiffness), Some(free_length), Some(damping)) =
                    (ends, stiffness, free_length, damping)
                {
                    out.springs.push(Spring {
                        from,
                        to,
                        stiffness,
                        free_length,
                        damping,
                        between,
                    });
                }
            }
        }
    }
}
