//! The joint reactions at a motion: the Newton–Euler equations of every
//! body at once, linear in the reactions of the joints resolved in
//! the `joints` module (see there for the mathematics), solved in the
//! least-squares sense where the joints over-constrain the bodies.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::evaluate::{Generated, Instant, View, WithUnit};
use super::joints::*;
use super::{Dynamics, ResolvedBody, Turns};
use crate::error::Error;
use crate::mechanism::{Mechanism, MotionState};

/// The reaction at one joint.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JointReaction {
    /// The joint's name.
    pub name: String,
    /// The force the first body exerts on the second, in the fixed axes
    /// (N; z = 0 in a planar mechanism). At a prismatic or cylindrical
    /// joint, normal to the axis (plus the driver's force along it where
    /// a driver acts there).
    pub force: Vector3<f64>,
    /// The same force in the second body's axes (turned by minus its
    /// angle, or by the transpose of its frame's rotation; the fixed axes
    /// for a body that does not turn).
    pub force_in_body: Vector3<f64>,
    /// The moment the first body exerts on the second, in the fixed axes
    /// (N·m), other than the driver's torque: in a planar mechanism, along
    /// z at a prismatic joint and zero at a revolute one; in a spatial
    /// one, normal to the axis at a revolute or cylindrical joint, any at
    /// a prismatic joint, zero at a spherical one.
    pub moment: Vector3<f64>,
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
    /// Whether the mechanism is spatial (the forces and moments then have
    /// three components).
    pub spatial: bool,
}

impl Reactions {
    /// The reaction at the joint named `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&JointReaction> {
        self.joints.iter().find(|j| j.name == name)
    }
}

/// The rotation from body `b`'s axes to the fixed axes: its frame's, a
/// turn about z by its angle, or none for a body that does not turn (and
/// for the ground, `None`).
fn rotation_of(bodies: &[ResolvedBody], b: Option<usize>, s: &dyn View) -> Matrix3<f64> {
    let Some(b) = b.and_then(|b| bodies.get(b)) else {
        return Matrix3::identity();
    };
    match &b.turning {
        Turns::No => Matrix3::identity(),
        Turns::Angle(terms) => {
            let angle: f64 = terms.iter().map(|&(j, c)| c * s.coordinate(j)[0]).sum();
            let (sin, cos) = crate::math::sin_cos(angle);
            Matrix3::new(cos, -sin, 0.0, sin, cos, 0.0, 0.0, 0.0, 1.0)
        }
        Turns::Frame(f) => s
            .frame(*f)
            .map_or(Matrix3::repeat(f64::NAN), |f| f.rotation),
    }
}

/// Two unit vectors normal to the unit vector `e` and to each other, with
/// (n₁, n₂, e) right-handed.
fn normals(e: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    // The fixed axis least aligned with e.
    let pick = if e.x.abs() <= e.y.abs() && e.x.abs() <= e.z.abs() {
        Vector3::x()
    } else if e.y.abs() <= e.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let n1 = e.cross(&pick).normalize();
    (n1, e.cross(&n1))
}

/// What one unknown of a joint is: a unit force and a unit moment (in the
/// fixed axes), applied to the second body at the joint and opposite on
/// the first, and whether it is the driver's.
#[derive(Clone, Copy)]
struct Unit {
    force: Vector3<f64>,
    moment: Vector3<f64>,
    driver: bool,
}

impl Unit {
    fn force(force: Vector3<f64>) -> Self {
        Unit {
            force,
            moment: Vector3::zeros(),
            driver: false,
        }
    }
    fn moment(moment: Vector3<f64>) -> Self {
        Unit {
            force: Vector3::zeros(),
            moment,
            driver: false,
        }
    }
    fn driving(self) -> Self {
        Unit {
            driver: true,
            ..self
        }
    }
}

/// The unknowns of joint `j` whose axis is `e` in the fixed axes.
fn unknowns(j: &ResolvedJoint, e: Vector3<f64>, spatial: bool) -> Vec<Unit> {
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let mut u = match (j.kind, spatial) {
        (JointKind::Revolute, false) => vec![Unit::force(x), Unit::force(y)],
        (JointKind::Prismatic, false) => {
            vec![Unit::force(Vector3::new(-e.y, e.x, 0.0)), Unit::moment(z)]
        }
        (JointKind::Spherical, _) => vec![Unit::force(x), Unit::force(y), Unit::force(z)],
        (JointKind::Revolute, true) => {
            let (n1, n2) = normals(e);
            vec![
                Unit::force(x),
                Unit::force(y),
                Unit::force(z),
                Unit::moment(n1),
                Unit::moment(n2),
            ]
        }
        (JointKind::Prismatic, true) => {
            let (n1, n2) = normals(e);
            vec![
                Unit::force(n1),
                Unit::force(n2),
                Unit::moment(x),
                Unit::moment(y),
                Unit::moment(z),
            ]
        }
        (JointKind::Cylindrical, _) => {
            let (n1, n2) = normals(e);
            vec![
                Unit::force(n1),
                Unit::force(n2),
                Unit::moment(n1),
                Unit::moment(n2),
            ]
        }
    };
    if j.driver.is_some() {
        u.push(match j.kind {
            JointKind::Prismatic => Unit::force(e).driving(),
            _ => Unit::moment(e).driving(),
        });
    }
    u
}

impl Dynamics {
    /// The reaction at every joint given with [`super::DynamicsBuilder::joint`]
    /// at `motion`, a motion of `m`, by the Newton–Euler equations of
    /// every body (see the [module](super)): the force and moment each
    /// joint's first body exerts on its second, and the driver's effort in
    /// its joint, which equals [`Dynamics::inverse`]'s. A force that names
    /// no body ([`super::DynamicsBuilder::force`], `force(P, …)` without
    /// `on`) acts on the one body its point moves rigidly with (v_P = v_G +
    /// ω × (r_P − r_G) for every driver's partial velocities, from one
    /// analysis of `m` per driver, run only then), or on the frame where
    /// the point does not move.
    ///
    /// # Errors
    /// [`Error::InvalidDynamics`] when the joints do not determine the
    /// reactions (in a planar mechanism, the count of unknowns is not
    /// three per body; in a spatial one, more unknowns than six per body,
    /// or equations no reactions satisfy; or the system is singular at
    /// this pose), when a force that names no body has a point on two
    /// bodies (a pin between them) or on none
    /// ([`super::DynamicsBuilder::force_on`] names it), a spring the bodies of its
    /// ends ([`super::Spring::between`]), or a force on a coordinate the
    /// joint it acts in ([`Joint::coordinate`]).
    pub fn reactions<M: Mechanism>(&self, m: &M, motion: &M::Motion) -> Result<Reactions, Error> {
        self.fits_mechanism::<M>()?;
        self.reactions_in(
            &Generated(motion),
            &mut super::evaluate::unit_analyses(m, motion.q(), self.drivers),
        )
    }

    /// The body each force acts on: the one named, or where none is, the
    /// one body the force's point moves rigidly with, `v_P = v_G + ω ×
    /// (r_P − r_G)` and `a_P = a_G + α × d + ω × (ω × d)` in the unit
    /// analysis of every driver (the frame, `None`, for a point that does
    /// not move and is on no body); an error naming
    /// the point where no body or more than one (a pin between two) fits.
    /// `unit` provides the unit analyses ([`WithUnit`]), run only where a
    /// force names no body.
    fn force_bodies(
        &self,
        s: &dyn View,
        unit: &mut dyn FnMut(usize, WithUnit<'_>) -> Result<(), Error>,
    ) -> Result<Vec<Option<usize>>, Error> {
        if self.forces.iter().all(|(_, b, _)| b.is_some()) {
            return Ok(self.forces.iter().map(|(_, b, _)| *b).collect());
        }
        let nan = [Vector3::repeat(f64::NAN); 3];
        let position = |p: usize| s.point(p).unwrap_or(nan)[0];
        // fits[f][b]: whether force f's point moves with body b; still[f]:
        // whether it does not move at all.
        let mut fits = vec![vec![true; self.bodies.len()]; self.forces.len()];
        let mut still = vec![true; self.forces.len()];
        for k in 0..self.drivers {
            unit(k, &mut |u| {
                let motion = |p: usize| {
                    u.point(p)
                        .map_or([Vector3::zeros(); 3], |[_, v, a]| [v, v, a])
                };
                let scale = self
                    .bodies
                    .iter()
                    .map(|b| {
                        let [_, v, a] = motion(b.center);
                        v.norm() + a.norm()
                    })
                    .fold(0.0, f64::max)
                    .max(f64::MIN_POSITIVE);
                for (f, (p, named, _)) in self.forces.iter().enumerate() {
                    if named.is_some() {
                        continue;
                    }
                    let [_, vp, ap] = motion(*p);
                    still[f] &= vp.norm() + ap.norm() <= 1e-12 * scale;
                    for (b, body) in self.bodies.iter().enumerate() {
                        // Rigid with the body in velocity and in
                        // acceleration (at unit rate, the convective
                        // terms): v_P = v_G + ω × d, a_P = a_G + α × d
                        // + ω × (ω × d). A body momentarily translating
                        // or at rest meets the first by chance, seldom
                        // both.
                        let d = position(*p) - position(body.center);
                        let (omega, alpha, _) = super::evaluate::turning(body, u);
                        let [_, vg, ag] = motion(body.center);
                        let v = vg + omega.cross(&d);
                        let a = ag + alpha.cross(&d) + omega.cross(&omega.cross(&d));
                        let size = vp.norm()
                            + v.norm()
                            + ap.norm()
                            + a.norm()
                            + (omega.norm() + alpha.norm()) * d.norm();
                        fits[f][b] &=
                            (vp - v).norm() + (ap - a).norm() <= 1e-9 * size.max(f64::MIN_POSITIVE);
                    }
                }
            })?;
        }
        let mut out = Vec::with_capacity(self.forces.len());
        for (f, (_, named, _)) in self.forces.iter().enumerate() {
            if named.is_some() {
                out.push(*named);
                continue;
            }
            let point = self.load_names.forces.get(f).map_or("?", String::as_str);
            let on: Vec<usize> = (0..self.bodies.len()).filter(|&b| fits[f][b]).collect();
            let bodies = |list: &[usize]| -> String {
                list.iter()
                    .map(|&b| format!("`{}`", self.bodies[b].name))
                    .collect::<Vec<_>>()
                    .join(" and ")
            };
            match on.as_slice() {
                [] if still[f] => out.push(None),
                [b] if still[f] => {
                    return Err(Error::InvalidDynamics {
                        item: "a force".to_string(),
                        detail: format!(
                            "the force at point `{point}` names no body, and `{point}` is a \
                             pivot of `{}` on the frame: say which it acts on \
                             (`force({point}, …, on = body)` in the definition's `loads`, or \
                             `.force_on(\"body\", \"{point}\", …)` with the builder; a force \
                             on the frame enters no reaction)",
                            self.bodies[*b].name
                        ),
                    });
                }
                [b] => out.push(Some(*b)),
                [] => {
                    return Err(Error::InvalidDynamics {
                        item: "a force".to_string(),
                        detail: format!(
                            "the force at point `{point}` names no body, and none of the \
                             bodies moves rigidly with `{point}`: say which body it acts on \
                             (`force({point}, …, on = body)` in the definition's `loads`, or \
                             `.force_on(\"body\", \"{point}\", …)` with the builder)"
                        ),
                    });
                }
                several => {
                    return Err(Error::InvalidDynamics {
                        item: "a force".to_string(),
                        detail: format!(
                            "the force at point `{point}` names no body, and `{point}` moves \
                             with {} (a pin between them): say which one it acts on \
                             (`force({point}, …, on = body)` in the definition's `loads`, or \
                             `.force_on(\"body\", \"{point}\", …)` with the builder)",
                            bodies(several)
                        ),
                    });
                }
            }
        }
        Ok(out)
    }

    /// [`Dynamics::reactions`] over a view of the motion, `unit`
    /// providing the unit analyses where a force's body is inferred.
    pub(crate) fn reactions_in(
        &self,
        s: &dyn View,
        unit: &mut dyn FnMut(usize, WithUnit<'_>) -> Result<(), Error>,
    ) -> Result<Reactions, Error> {
        let invalid = |item: &str, detail: String| Error::InvalidDynamics {
            item: item.to_string(),
            detail,
        };
        if self.joints.is_empty() {
            return Err(invalid(
                "joints",
                "none given: declare them in the definition's `joints` section \
                 (`bearing(revolute, O, between = (ground, crank));`) or with \
                 `.joint(Joint::revolute(…))`"
                    .to_string(),
            ));
        }
        // The joint each force on a coordinate acts in.
        let mut in_joints = Vec::with_capacity(self.coordinate_forces.len());
        for (i, (c, f)) in self.coordinate_forces.iter().enumerate() {
            // The joint a driver acts in is measured by that driver.
            let measured = |j: &&ResolvedJoint| j.coordinate == Some(*c) || j.driver == Some(*c);
            let Some(j) = self.joints.iter().find(measured) else {
                return Err(invalid("a force on a coordinate", {
                    let name = self
                        .load_names
                        .coordinate_forces
                        .get(i)
                        .map_or("?", String::as_str);
                    format!(
                        "no joint is measured by coordinate `{name}`: name it on its \
                             joint (`coordinate = {name}` in the definition's `joints` \
                             section, or `.coordinate(\"{name}\")`) for the joint reactions"
                    )
                }));
            };
            if !matches!(j.kind, JointKind::Revolute | JointKind::Prismatic) {
                return Err(invalid(
                    "a force on a coordinate",
                    format!(
                        "it acts in joint `{}`, a {} joint, which transmits no effort along or \
                         about one axis: measure the coordinate on a revolute or prismatic joint",
                        j.name,
                        j.kind.word()
                    ),
                ));
            }
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
        let on = self.force_bodies(s, unit)?;
        let spatial = self.dim == 3;
        // Rows per body: the force's x and y and the moment's z in a
        // planar mechanism; every component in a spatial one.
        let w = if spatial { 6 } else { 3 };
        let nb = self.bodies.len();
        let rows = w * nb;
        let nan = [Vector3::repeat(f64::NAN); 3];
        let point = |p: usize| s.point(p).unwrap_or(nan);
        let centre = |b: usize| point(self.bodies[b].center)[0];
        // Each joint's axis in the fixed axes, and its unknowns.
        let mut units = Vec::with_capacity(self.joints.len());
        for j in &self.joints {
            let e = rotation_of(&self.bodies, j.bodies[0], s) * j.axis;
            units.push((e, unknowns(j, e, spatial)));
        }
        let cols: usize = units.iter().map(|(_, u)| u.len()).sum();
        if (!spatial && cols != rows) || cols > rows {
            return Err(invalid(
                "joints",
                format!(
                    "they give {cols} unknown reaction components for the {rows} equations of \
                     motion of {nb} bodies: declare every moving link as a body and every joint \
                     between them (with the driver's), so that the reactions are determined"
                ),
            ));
        }
        // A force f with moment m about G, on body b, into the rows of b.
        let rows_of = |f: Vector3<f64>, m: Vector3<f64>| -> [f64; 6] {
            if spatial {
                [f.x, f.y, f.z, m.x, m.y, m.z]
            } else {
                [f.x, f.y, m.z, 0.0, 0.0, 0.0]
            }
        };
        let mut a = DMatrix::<f64>::zeros(rows, cols);
        let mut rhs = DVector::<f64>::zeros(rows);
        let mut load = |b: usize, f: Vector3<f64>, m: Vector3<f64>| {
            for (k, v) in rows_of(f, m).iter().take(w).enumerate() {
                rhs[w * b + k] += v;
            }
        };
        // Each body's rate of momentum less gravity, and of angular
        // momentum about G: J α + ω × J ω.
        for (i, b) in self.bodies.iter().enumerate() {
            let [_, _, acc] = point(b.center);
            let (omega, alpha, inertia) = super::evaluate::turning(b, s);
            load(
                i,
                (acc - self.gravity) * b.mass,
                inertia * alpha + omega.cross(&(inertia * omega)),
            );
        }
        // The applied loads, moved to the right-hand side.
        let [q, qd, qdd] = self.coordinates_of(s);
        let instant = |at| Instant::of([&q, &qd, &qdd], Some(at)).at_time(s.time());
        let planar = |v: Vector3<f64>| {
            if spatial {
                v
            } else {
                Vector3::new(v.x, v.y, 0.0)
            }
        };
        for ((p, _, f), body) in self.forces.iter().zip(&on) {
            // A force on the frame enters no body's equations.
            let Some(b) = *body else {
                continue;
            };
            let at = point(*p);
            let f = planar(Vector3::from(f(&instant(at))));
            if let Some(v) = f.iter().find(|v| !v.is_finite()) {
                return Err(invalid(
                    "a force",
                    format!(
                        "the force at point `{}` is {v} at this pose; a load must be finite",
                        self.point_name(*p)
                    ),
                ));
            }
            load(b, -f, -(at[0] - centre(b)).cross(&f));
        }
        for (b, t) in &self.torques {
            let at = point(self.bodies[*b].center);
            let t = Vector3::from(t(&instant(at)));
            if let Some(v) = t.iter().find(|v| !v.is_finite()) {
                return Err(invalid(
                    "a torque",
                    format!(
                        "the torque on body `{}` is {v} at this pose; a load must be finite",
                        self.bodies[*b].name
                    ),
                ));
            }
            let t = if spatial {
                t
            } else {
                Vector3::new(0.0, 0.0, t.z)
            };
            load(*b, Vector3::zeros(), -t);
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
                    load(b, -f, -(at - centre(b)).cross(&f));
                }
            }
        }
        // A force on a coordinate: a torque about its revolute joint's
        // axis, or a force along its prismatic joint's axis, on the second
        // body, and its opposite on the first.
        for (j, f) in in_joints {
            let value = f(&instant([Vector3::zeros(); 3]));
            let r = point(j.at)[0];
            let e = rotation_of(&self.bodies, j.bodies[0], s) * j.axis;
            let (force, torque) = match j.kind {
                JointKind::Prismatic => (e * value, Vector3::zeros()),
                _ => (Vector3::zeros(), e * value),
            };
            for (body, sign) in [(j.bodies[1], 1.0), (j.bodies[0], -1.0)] {
                if let Some(b) = body {
                    let arm = r - centre(b);
                    load(b, -force * sign, -(arm.cross(&force) + torque) * sign);
                }
            }
        }
        // The joints' unknowns: a force and moment on the second body,
        // their opposites on the first.
        let mut col = 0;
        for (j, (_, us)) in self.joints.iter().zip(&units) {
            let r = point(j.at)[0];
            for u in us {
                for (body, sign) in [(j.bodies[1], 1.0), (j.bodies[0], -1.0)] {
                    if let Some(b) = body {
                        let arm = r - centre(b);
                        let v = rows_of(u.force * sign, (arm.cross(&u.force) + u.moment) * sign);
                        for (k, x) in v.iter().take(w).enumerate() {
                            a[(w * b + k, col)] += x;
                        }
                    }
                }
                col += 1;
            }
        }
        if !(a.iter().all(|v| v.is_finite()) && rhs.iter().all(|v| v.is_finite())) {
            return Err(invalid("joints", self.not_finite(s)));
        }
        let x = solve(&a, &rhs).map_err(|why| invalid("joints", why))?;
        let mut out = Vec::with_capacity(self.joints.len());
        let mut col = 0;
        for (j, (_, us)) in self.joints.iter().zip(&units) {
            let (mut force, mut moment, mut effort) = (Vector3::zeros(), Vector3::zeros(), None);
            for u in us {
                let v = x[col];
                col += 1;
                force += u.force * v;
                if u.driver {
                    effort = Some(v);
                } else {
                    moment += u.moment * v;
                }
            }
            let force_in_body = rotation_of(&self.bodies, j.bodies[1], s).transpose() * force;
            if let Some(v) = force
                .iter()
                .chain(&moment)
                .chain(&force_in_body)
                .find(|v| !v.is_finite())
            {
                return Err(Error::NonFinite {
                    input: crate::error::Input::Computed,
                    name: "a joint's reaction",
                    value: *v,
                });
            }
            out.push(JointReaction {
                name: j.name.clone(),
                force,
                force_in_body,
                moment,
                effort,
            });
        }
        Ok(Reactions {
            joints: out,
            spatial,
        })
    }
}

/// The reactions x of A x = b: by LU for a square system; by least
/// squares for one with more equations than unknowns (a link that spins
/// freely), which must then satisfy every equation to round-off.
fn solve(a: &DMatrix<f64>, b: &DVector<f64>) -> Result<DVector<f64>, String> {
    let singular = || {
        "the equations of motion do not determine the reactions at this pose (a singular \
         pose, or a joint missing and another repeated)"
            .to_string()
    };
    if a.nrows() == a.ncols() {
        return a
            .clone()
            .lu()
            .solve(b)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or_else(singular);
    }
    let svd = a.clone().svd(true, true);
    let largest = svd.singular_values.max();
    let rank = svd
        .singular_values
        .iter()
        .filter(|&&v| v > largest * 1e-10)
        .count();
    if rank < a.ncols() {
        return Err(singular());
    }
    let x = svd
        .solve(b, largest * 1e-10)
        .map_err(|_| singular())?
        .into_iter()
        .copied()
        .collect::<Vec<f64>>();
    let x = DVector::from_vec(x);
    // The scale of the equations' terms, for the residual's test.
    let scale = (0..a.nrows())
        .map(|i| {
            (0..a.ncols())
                .map(|k| (a[(i, k)] * x[k]).abs())
                .sum::<f64>()
                .max(b[i].abs())
        })
        .fold(0.0, f64::max);
    let residual = (a * &x - b).amax();
    if !(x.iter().all(|v| v.is_finite()) && residual <= 1e-9 * scale) {
        return Err(format!(
            "no reactions satisfy every equation of motion at this pose (residual {residual:.3e} \
             of terms up to {scale:.3e}): a link turns freely about an axis no joint holds (a \
             link between two spherical joints spins about the line through them) and its \
             inertia about that axis is not zero; make it a slender rod (no inertia about that \
             axis), or hold it with a revolute or universal-like pair of joints"
        ));
    }
    Ok(x)
}

impl Dynamics {
    /// Point `p`'s name, for messages.
    fn point_name(&self, p: usize) -> &str {
        self.load_names.points.get(p).map_or("?", String::as_str)
    }

    /// What is not finite in the motion `s` where the reactions' system
    /// is: the first body's centre of mass, joint or spring end whose
    /// position, velocity or acceleration is not, named.
    fn not_finite(&self, s: &dyn View) -> String {
        let bad = |p: usize| {
            s.point(p)
                .is_none_or(|[r, v, a]| !r.iter().chain(&v).chain(&a).all(|x| x.is_finite()))
        };
        let tail = "at this pose: check the parameters and the motion given (a parameter or a \
                    rate that is NaN or infinite)";
        if let Some(b) = self.bodies.iter().find(|b| bad(b.center)) {
            return format!(
                "the centre of mass `{}` of body `{}` has a position, velocity or acceleration \
                 that is not finite {tail}",
                self.point_name(b.center),
                b.name
            );
        }
        if let Some(j) = self.joints.iter().find(|j| bad(j.at)) {
            return format!(
                "the point `{}` of joint `{}` has a position, velocity or acceleration that is \
                 not finite {tail}",
                self.point_name(j.at),
                j.name
            );
        }
        if let Some(sp) = self.springs.iter().find(|sp| bad(sp.from) || bad(sp.to)) {
            return format!(
                "the spring from `{}` to `{}` has an end that is not finite {tail}",
                self.point_name(sp.from),
                self.point_name(sp.to)
            );
        }
        if let Some(b) = self.bodies.iter().find(|b| {
            let (omega, alpha, _) = super::evaluate::turning(b, s);
            !omega.iter().chain(&alpha).all(|x| x.is_finite())
        }) {
            return format!(
                "the angular velocity or acceleration of body `{}` is not finite {tail}",
                b.name
            );
        }
        format!("a value of the equations of motion is not finite {tail}")
    }
}
