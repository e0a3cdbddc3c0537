//! The masses, loads and joints of the `bodies`, `loads` and (item form)
//! `joints` sections, as roots of the graph both back ends evaluate: the
//! constants (from the parameters, the joints' axes among them) and each
//! load's value (from the parameters, the coordinates and their rates).
//!
//! A planar body's angle must be Σ c_j q_j plus a constant, the c_j
//! constants (its angular velocity is then Σ c_j q̇_j); each c_j = ∂θ/∂q_j
//! is found here by differentiating the angle as written, which must not
//! depend on the coordinates, and every q_j with c_j ≠ 0 must be an angle.

use crate::diff::{partial, Memo};
use crate::ir::{Id, Leaf};
use crate::lower::dynamics::LoweredDynamics;
use crate::lower::{CoordKind, Model};
use crate::names::Errors;
use crate::parse::Definition;

pub use crate::lower::dynamics::{JointKind, Load, LoadTarget, Spring};

/// How a body turns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Turning {
    /// It does not (a slider): no rotational inertia.
    No,
    /// Planar: its angle is Σ c_j q_j plus a constant, as (coordinate
    /// name, c_j) with c_j a root (an expression of the parameters).
    Angle(Vec<(String, Id)>),
    /// Spatial: it moves with the frame of this name.
    Frame(String),
}

/// A rigid link with mass.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MassBody {
    /// Its name in the `bodies` section.
    pub name: String,
    /// m (a root of the parameters).
    pub mass: Id,
    /// The point at its centre of mass.
    pub center: String,
    /// How it turns.
    pub turning: Turning,
    /// Its inertia about the centre of mass: empty (none), one root
    /// (planar: about the plane's normal) or nine, row by row (spatial: in
    /// its frame's axes).
    pub inertia: Vec<Id>,
}

/// A joint of the `joints` section, for the reactions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Joint {
    /// Its name.
    pub name: String,
    /// What it lets move.
    pub kind: JointKind,
    /// The point it is at.
    pub point: String,
    /// The two bodies it joins, either of them `ground`: the reaction is
    /// the force the first exerts on the second.
    pub between: [String; 2],
    /// Its axis in the first body's axes: empty (a planar revolute or a
    /// spherical joint), 2 or 3 roots of the parameters.
    pub axis: Vec<Id>,
    /// The driver acting in it.
    pub driver: Option<String>,
    /// The coordinate measuring its motion.
    pub coordinate: Option<String>,
}

/// The `bodies`, `loads` and (item form) `joints` sections of a
/// definition.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Dynamics {
    /// g (2 or 3 roots of the parameters), empty without gravity.
    pub gravity: Vec<Id>,
    /// The bodies, in declaration order.
    pub bodies: Vec<MassBody>,
    /// The forces and torques, in declaration order.
    pub loads: Vec<Load>,
    /// The springs, in declaration order.
    pub springs: Vec<Spring>,
    /// The joints of the `joints` section, in declaration order.
    pub joints: Vec<Joint>,
    /// The partial derivatives the efforts' sensitivities need, with a
    /// `sensitivities` section.
    pub partials: Option<Partials>,
}

/// The partial derivatives of the sections with respect to the parameters
/// of the `sensitivities` section (K of them, in its order), for the
/// sensitivities of the efforts: the loads' also with respect to the
/// coordinates, their rates and accelerations (n coordinates), through
/// which the parameters act on them along a motion.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Partials {
    /// The parameters p_k (indices among the definition's parameters).
    pub params: Vec<u32>,
    /// ∂c/∂p_k of every root of [`Dynamics::constants`], flattened
    /// `[k][constant]`.
    pub constants: Vec<Id>,
    /// For each load, ∂value/∂x flattened `[x][component]`, over the
    /// K + 3n variables x: p_0 … p_{K−1}, then q_0 … q_{n−1}, q̇_0 …,
    /// q̈_0 ….
    pub loads: Vec<Vec<Id>>,
    /// For each frame a body turns with (by name, in the order of first
    /// use), ∂/∂x of its rotation R (row by row), angular velocity ω and
    /// angular acceleration α, flattened `[x][15]` over the same
    /// variables.
    pub frames: Vec<(String, Vec<Id>)>,
}

/// Where each constant of the sections stands in the list
/// [`Dynamics::constants`]: the one layout every back end reads, made by
/// the same walk that makes the list.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ConstantPlaces {
    /// Gravity's components (none, 2 or 3).
    pub gravity: Vec<usize>,
    /// Each body's constants, in the order of [`Dynamics::bodies`].
    pub bodies: Vec<BodyPlaces>,
    /// Each spring's constants, in the order of [`Dynamics::springs`].
    pub springs: Vec<SpringPlaces>,
    /// Each joint's axis components, in the order of [`Dynamics::joints`].
    pub joints: Vec<Vec<usize>>,
}

/// Where one body's constants stand in [`Dynamics::constants`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BodyPlaces {
    /// Its mass.
    pub mass: usize,
    /// The coefficients of its angle, one per term (a body that turns
    /// with a sum of coordinates).
    pub angle: Vec<usize>,
    /// Its inertia: none, one planar moment, or the 9 entries of the
    /// tensor row by row.
    pub inertia: Vec<usize>,
}

/// Where one spring's constants stand in [`Dynamics::constants`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpringPlaces {
    /// Its stiffness.
    pub stiffness: usize,
    /// Its free length.
    pub free_length: usize,
    /// Its damping.
    pub damping: usize,
}

impl Dynamics {
    /// Every root that depends on the parameters only (gravity, then each
    /// body's mass, angle coefficients and inertia, then each spring's
    /// stiffness, free length and damping, then each joint's axis), and
    /// where each stands in that list. Both back ends evaluate the list
    /// once per parameter set and read it through the places.
    #[must_use]
    pub fn constant_layout(&self) -> (Vec<Id>, ConstantPlaces) {
        let mut out: Vec<Id> = Vec::new();
        let mut put = |id: Id| {
            out.push(id);
            out.len() - 1
        };
        let gravity = self.gravity.iter().map(|&g| put(g)).collect();
        let bodies = self
            .bodies
            .iter()
            .map(|b| BodyPlaces {
                mass: put(b.mass),
                angle: match &b.turning {
                    Turning::Angle(terms) => terms.iter().map(|(_, c)| put(*c)).collect(),
                    Turning::No | Turning::Frame(_) => Vec::new(),
                },
                inertia: b.inertia.iter().map(|&i| put(i)).collect(),
            })
            .collect();
        let springs = self
            .springs
            .iter()
            .map(|s| SpringPlaces {
                stiffness: put(s.stiffness),
                free_length: put(s.free_length),
                damping: put(s.damping),
            })
            .collect();
        let joints = self
            .joints
            .iter()
            .map(|j| j.axis.iter().map(|&a| put(a)).collect())
            .collect();
        let places = ConstantPlaces {
            gravity,
            bodies,
            springs,
            joints,
        };
        (out, places)
    }

    /// The constants of [`Dynamics::constant_layout`].
    #[must_use]
    pub fn constants(&self) -> Vec<Id> {
        self.constant_layout().0
    }

    /// The places of [`Dynamics::constant_layout`].
    #[must_use]
    pub fn places(&self) -> ConstantPlaces {
        self.constant_layout().1
    }
}

impl Dynamics {
    /// One parameter's partials of the constants, `chunk` (laid out as
    /// [`Dynamics::constants`]), in the layout the runtime's
    /// `DynamicsBuilder::design_parameters` reads: gravity's 3
    /// components, then for each body its mass, its angle's coefficients
    /// and the 9 entries of its inertia (a planar moment at entry 8), then
    /// each spring's stiffness, free length and damping. `None` where the
    /// definition has no such constant (zero).
    #[must_use]
    pub fn design_layout<T: Copy>(&self, chunk: &[T]) -> Vec<Option<T>> {
        let places = self.places();
        let at = |i: usize| chunk.get(i).copied();
        let mut out = Vec::new();
        let mut gravity: Vec<Option<T>> = places.gravity.iter().map(|&i| at(i)).collect();
        gravity.resize(3, None);
        out.extend(gravity);
        for b in &places.bodies {
            out.push(at(b.mass));
            out.extend(b.angle.iter().map(|&i| at(i)));
            let mut inertia = [None; 9];
            match b.inertia.as_slice() {
                [] => {}
                [moment] => inertia[8] = at(*moment),
                all => {
                    for (x, &i) in inertia.iter_mut().zip(all) {
                        *x = at(i);
                    }
                }
            }
            out.extend(inertia);
        }
        for s in &places.springs {
            out.extend([at(s.stiffness), at(s.free_length), at(s.damping)]);
        }
        out
    }
}

impl Load {
    /// Where component `c` of this load's value goes in the three the
    /// runtime's loads carry: a scalar torque about z, a scalar force on a
    /// coordinate first, a vector's components in place.
    #[must_use]
    pub fn slot(&self, c: usize) -> usize {
        match (self.value.len(), &self.target) {
            (1, LoadTarget::Coordinate { .. }) => 0,
            (1, _) => 2,
            _ => c,
        }
    }
}

/// The partial derivatives of the sections `d` of `model` with respect to
/// the parameters `params` (indices among the definition's parameters),
/// in the layout of [`Partials`]; `frames` are the frames' names with
/// their R (row by row), ω and α.
pub fn partials(
    model: &mut Model,
    d: &Dynamics,
    params: &[u32],
    frames: &[(String, [Id; 15])],
) -> Partials {
    let mut memo = Memo::default();
    let g = &mut model.graph;
    let constants = d.constants();
    let mut out = Partials {
        params: params.to_vec(),
        ..Partials::default()
    };
    for &k in params {
        for &c in &constants {
            let p = partial(g, c, Leaf::Param(k), &mut memo);
            out.constants.push(p);
        }
    }
    let n = model.kinds.len();
    let variables: Vec<Leaf> = params
        .iter()
        .map(|&k| Leaf::Param(k))
        .chain((0..n as u32).map(Leaf::Q))
        .chain((0..n as u32).map(Leaf::Qd))
        .chain((0..n as u32).map(Leaf::Qdd))
        .collect();
    for load in &d.loads {
        let mut one = Vec::with_capacity(variables.len() * load.value.len());
        for &x in &variables {
            for &v in &load.value {
                one.push(partial(g, v, x, &mut memo));
            }
        }
        out.loads.push(one);
    }
    for b in &d.bodies {
        let Turning::Frame(name) = &b.turning else {
            continue;
        };
        if out.frames.iter().any(|(n, _)| n == name) {
            continue;
        }
        let Some((_, roots)) = frames.iter().find(|(n, _)| n == name) else {
            continue;
        };
        let mut one = Vec::with_capacity(variables.len() * 15);
        for &x in &variables {
            for &r in roots {
                one.push(partial(g, r, x, &mut memo));
            }
        }
        out.frames.push((name.clone(), one));
    }
    out
}

/// The sections of `model`, their angles resolved into coefficients;
/// errors at the angle's tokens.
pub fn resolve(def: &Definition, model: &mut Model, errors: &mut Errors) -> Option<Dynamics> {
    let LoweredDynamics {
        gravity,
        bodies,
        loads,
        springs,
        joints,
    } = model.dynamics.take()?;
    let coords = model.coords();
    let coordinate_name = |j: u32| -> String {
        def.drivers
            .iter()
            .chain(&def.unknowns)
            .nth(j as usize)
            .map(|d| syn::ext::IdentExt::unraw(&d.name).to_string())
            .unwrap_or_default()
    };
    let mut memo = Memo::default();
    let mut out = Dynamics {
        gravity,
        ..Dynamics::default()
    };
    let mut failed = false;
    'bodies: for b in bodies {
        let turning = match (&b.angle, &b.frame) {
            (Some((angle, tokens)), _) => {
                let mut terms = Vec::new();
                for j in 0..coords {
                    let c = partial(&mut model.graph, *angle, Leaf::Q(j), &mut memo);
                    if model.graph.as_const(c) == Some(0.0) {
                        continue;
                    }
                    let name = coordinate_name(j);
                    if model
                        .graph
                        .leaves_under(c)
                        .any(|l| !matches!(l, Leaf::Param(_)))
                    {
                        errors.spanned(
                            tokens,
                            format!(
                                "the angle of body `{}` must be a sum of coordinates times \
                                 constants (as `th3` or `th1 + th2`); this one is not linear in \
                                 `{name}`",
                                b.name
                            ),
                        );
                        failed = true;
                        continue 'bodies;
                    }
                    if model.kinds.get(j as usize) != Some(&CoordKind::Angle) {
                        errors.spanned(
                            tokens,
                            format!(
                                "the angle of body `{}` is made of `{name}`, which is a length \
                                 (no sine or cosine of it appears in the mechanism)",
                                b.name
                            ),
                        );
                        failed = true;
                        continue 'bodies;
                    }
                    terms.push((name, c));
                }
                Turning::Angle(terms)
            }
            (None, Some(frame)) => Turning::Frame(frame.clone()),
            (None, None) => Turning::No,
        };
        out.bodies.push(MassBody {
            name: b.name,
            mass: b.mass,
            center: b.center,
            turning,
            inertia: b.inertia,
        });
    }
    out.loads = loads;
    out.springs = springs;
    for j in joints {
        let driver = match j.driver {
            None => None,
            Some((index, name, tokens)) => {
                let want = match j.kind {
                    JointKind::Prismatic => CoordKind::Length,
                    _ => CoordKind::Angle,
                };
                if model.kinds.get(index as usize) != Some(&want) {
                    let (is, kind, must) = if want == CoordKind::Angle {
                        ("a length", "revolute", "an angle")
                    } else {
                        ("an angle", "prismatic", "a length")
                    };
                    errors.spanned(
                        &tokens,
                        format!(
                            "driver `{name}` is {is}, but joint `{}` is {kind}: a driver acting \
                             in it is {must}",
                            j.name
                        ),
                    );
                    failed = true;
                    continue;
                }
                Some(name)
            }
        };
        out.joints.push(Joint {
            name: j.name,
            kind: j.kind,
            point: j.point,
            between: j.between,
            axis: j.axis,
            driver,
            coordinate: j.coordinate,
        });
    }
    (!failed).then_some(out)
}
