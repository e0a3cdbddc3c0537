//! The equations of motion of the `bodies` and `loads` sections in the
//! coordinates, as roots of the graph: what a forward simulation
//! evaluates at every step, in one pass of straight-line code, instead of
//! walking the bodies and loads at run time.
//!
//! For coordinates q (n of them) the partial velocities of a point P and
//! the angular velocity of a body are v_P^j = ∂v_P/∂q̇_j and
//! ω^j = ∂ω/∂q̇_j (the velocities are linear in the rates). By virtual
//! power, the generalized force each coordinate would need to move as it
//! does is
//!
//! f̃_j = Σ_b [m (a_G − g) · v_G^j + (J α + ω × J ω) · ω^j]
//! − Σ F · v_P^j − Σ T · ω^j − f_j + Σ f_s e · (v_B^j − v_A^j),
//!
//! with J in the fixed axes, f_j the loads on coordinate j and
//! f_s = k (L − L₀) + c L̇ each spring's tension along its unit vector e.
//! The mass matrix in the coordinates is
//!
//! M̃_ij = Σ_b m v_G^i · v_G^j + ω^iᵀ J ω^j.
//!
//! With C = ∂q̇/∂ḋ, the kinematic coefficients (C_d = I, Φ_u C_u = −Φ_d),
//! the drivers' equations are M = Cᵀ M̃ C and the efforts Q = Cᵀ f̃: the
//! back ends evaluate Φ_q, M̃, f̃ and each load's power here and do the
//! small solve and products with numbers. For one driver and at most two
//! unknowns (a four-bar, a slider-crank) the roots are M and Q themselves
//! ([`EquationsOfMotion::reduced`]): C written out by Cramer's rule, the
//! same sums formed along the one direction C of the rates (v_P^C =
//! Σ_j c_j v_P^j, ω^C likewise: M = Σ_b m v_G^C · v_G^C + ω^Cᵀ J ω^C and
//! Q = f̃ along C), not n × n of them then reduced, so that the whole
//! reduction is part of the straight-line code and costs a dot product
//! per body and load.

use crate::diff::{partial, Memo};
use crate::dynamics::{Dynamics, LoadTarget, Turning};
use crate::ir::{Graph, Id, Leaf};
use crate::kinematics::Derived;
use crate::lower::Model;
use crate::parse::Definition;

/// The largest number of coordinates for which the equations are formed
/// (their size grows with its square); past it the back ends sum the
/// bodies and loads at run time.
pub const MAX_COORDINATES: usize = 24;

/// The equations of motion in the coordinates (see the module's
/// documentation), each a root of the graph of the parameters, q, q̇, q̈
/// and the time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EquationsOfMotion {
    /// The number of coordinates n.
    pub coordinates: usize,
    /// Φ_q: row i (one per loop equation), column j (every coordinate,
    /// drivers first), row-major.
    pub jacobian: Vec<Id>,
    /// M̃'s upper triangle, row by row: (0, 0), (0, 1), …, (0, n − 1),
    /// (1, 1), … (empty where the equations are
    /// [`EquationsOfMotion::reduced`]).
    pub mass: Vec<Id>,
    /// f̃_j, the generalized force on each coordinate, at the leaves' q̈
    /// (empty where the equations are [`EquationsOfMotion::reduced`]).
    pub forces: Vec<Id>,
    /// The power of each load whose work a forward simulation reports, in
    /// the runtime's order: each force at a point, each torque, each force
    /// on a coordinate (each in declaration order), then each spring's
    /// damper (−c L̇²).
    pub powers: Vec<Id>,
    /// For one driver and at most two unknowns ([`MAX_REDUCED_UNKNOWNS`]),
    /// the driver's M = Cᵀ M̃ C and Q = Cᵀ f̃ with C = (1, c₁, c₂) from
    /// Φ_u C_u = −Φ_d by Cramer's rule (c₁ = −Φ_0/Φ_1 for one unknown; for
    /// two, with rows a and b of Φ_q, Δ = a₁b₂ − a₂b₁, c₁ = (a₂b₀ − a₀b₂)/Δ
    /// and c₂ = (a₀b₁ − a₁b₀)/Δ), each formed along C directly: a singular
    /// Φ_u gives a value that is not finite. `None` otherwise.
    pub reduced: Option<[Id; 2]>,
}

/// The most unknowns for which the equations of one driver are formed
/// reduced ([`EquationsOfMotion::reduced`]).
pub const MAX_REDUCED_UNKNOWNS: usize = 2;

impl EquationsOfMotion {
    /// Every root in one list: M and Q, then the powers, where the
    /// equations are [`EquationsOfMotion::reduced`]; otherwise Φ_q, M̃, f̃,
    /// then the powers.
    #[must_use]
    pub fn roots(&self) -> Vec<Id> {
        let mut all = match self.reduced {
            Some(reduced) => reduced.to_vec(),
            None => {
                let mut all = self.jacobian.clone();
                all.extend(&self.mass);
                all.extend(&self.forces);
                all
            }
        };
        all.extend(&self.powers);
        all
    }
}

/// The kinematic coefficients C = (1, c₁, c₂) of one driver of `n`
/// coordinates (at most [`MAX_REDUCED_UNKNOWNS`] + 1) from Φ_q (row-major,
/// n − 1 rows), as [`EquationsOfMotion::reduced`] states them.
fn coefficients(g: &mut Graph, jacobian: &[Id], n: usize) -> Option<Vec<Id>> {
    let one = g.constant(1.0);
    Some(match (n, jacobian) {
        (1, []) => vec![one],
        (2, [a0, a1]) => {
            let r = g.div(*a0, *a1);
            vec![one, g.neg(r)]
        }
        (3, [a0, a1, a2, b0, b1, b2]) => {
            let mut det = |x: Id, y: Id, z: Id, w: Id| {
                let (xy, zw) = (g.mul(x, y), g.mul(z, w));
                g.sub(xy, zw)
            };
            let delta = det(*a1, *b2, *a2, *b1);
            let n1 = det(*a2, *b0, *a0, *b2);
            let n2 = det(*a0, *b1, *a1, *b0);
            vec![one, g.div(n1, delta), g.div(n2, delta)]
        }
        _ => return None,
    })
}

/// Σ_j w_j p_j, the partial velocities `p` (one per coordinate) along the
/// direction `w` of the coordinates' rates: p_k itself for a unit
/// direction (the simplifier drops the zero terms and the unit factor).
fn along(g: &mut Graph, p: &[[Id; 3]], w: &[Id]) -> [Id; 3] {
    let mut out = [g.constant(0.0); 3];
    for (pj, &wj) in p.iter().zip(w) {
        for (o, &c) in out.iter_mut().zip(pj) {
            let t = g.mul(wj, c);
            *o = g.sum(*o, t);
        }
    }
    out
}

/// Dot product of two vectors of roots (over the shorter).
fn dot(g: &mut Graph, a: &[Id], b: &[Id]) -> Id {
    let mut s = g.constant(0.0);
    for (&x, &y) in a.iter().zip(b) {
        let t = g.mul(x, y);
        s = g.sum(s, t);
    }
    s
}

/// J v for a 3 × 3 matrix of roots, row by row.
fn apply(g: &mut Graph, j: &[Id], v: &[Id; 3]) -> [Id; 3] {
    let mut out = [v[0]; 3];
    for (r, o) in out.iter_mut().enumerate() {
        *o = dot(g, &j[3 * r..3 * r + 3], v);
    }
    out
}

/// How a body turns, in roots: ω, α, the partials ω^j and the inertia in
/// the fixed axes (3 × 3, row by row).
struct Turn {
    omega: [Id; 3],
    alpha: [Id; 3],
    partials: Vec<[Id; 3]>,
    inertia: Vec<Id>,
}

/// The equations of motion of `d`, or `None` where they are not formed:
/// more than [`MAX_COORDINATES`] coordinates, a loop system that is not
/// square, or a name the sections use that the kinematics lack.
pub fn equations(
    def: &Definition,
    model: &mut Model,
    derived: &Derived,
    d: &Dynamics,
) -> Option<EquationsOfMotion> {
    let n = model.coords() as usize;
    let nd = model.drivers as usize;
    if n > MAX_COORDINATES || derived.phi.len() != n - nd {
        return None;
    }
    let unraw = |i: &syn::Ident| syn::ext::IdentExt::unraw(i).to_string();
    let points: Vec<String> = def.points.iter().map(|p| unraw(&p.name)).collect();
    let frames: Vec<String> = def.frames.iter().map(|f| unraw(&f.name)).collect();
    let coordinates: Vec<String> = def
        .drivers
        .iter()
        .chain(&def.unknowns)
        .map(|c| unraw(&c.name))
        .collect();
    // Every point's position, velocity and acceleration has 1 to 3
    // components (so the indexing below by a point's place holds).
    let components =
        |v: &Vec<Vec<Id>>| v.len() == points.len() && v.iter().all(|c| (1..=3).contains(&c.len()));
    if !(components(&derived.pos) && components(&derived.vel) && components(&derived.acc)) {
        return None;
    }
    let point = |name: &str| points.iter().position(|p| p == name);
    let coordinate = |name: &str| coordinates.iter().position(|c| c == name);
    let mut memo = Memo::default();
    let g = &mut model.graph;
    let zero = g.constant(0.0);
    let jacobian: Vec<Id> = derived
        .phi
        .iter()
        .flat_map(|&p| (0..n as u32).map(move |j| (p, j)))
        .collect::<Vec<_>>()
        .into_iter()
        .map(|(p, j)| partial(g, p, Leaf::Q(j), &mut memo))
        .collect();
    // The directions of the coordinates' rates along which the equations
    // are formed: each coordinate's own (M̃ and f̃), or, reduced, the one
    // driver's with the unknowns as the loops move them, C (M and Q).
    let reduced = if nd == 1 && n - nd <= MAX_REDUCED_UNKNOWNS {
        coefficients(g, &jacobian, n)
    } else {
        None
    };
    let one = g.constant(1.0);
    let directions: Vec<Vec<Id>> = match &reduced {
        Some(c) => vec![c.clone()],
        None => (0..n)
            .map(|k| (0..n).map(|j| if j == k { one } else { zero }).collect())
            .collect(),
    };
    let nk = directions.len();
    // v_P along each direction for every point, padded to three
    // components.
    let pad = |v: &[Id]| {
        [
            v[0],
            v.get(1).copied().unwrap_or(zero),
            v.get(2).copied().unwrap_or(zero),
        ]
    };
    let mut velocity_partials: Vec<Vec<[Id; 3]>> = Vec::with_capacity(points.len());
    for v in &derived.vel {
        let v = pad(v);
        let mut per = Vec::with_capacity(n);
        for j in 0..n as u32 {
            per.push(v.map(|c| partial(g, c, Leaf::Qd(j), &mut memo)));
        }
        let per: Vec<[Id; 3]> = directions.iter().map(|w| along(g, &per, w)).collect();
        velocity_partials.push(per);
    }
    let gravity = if d.gravity.is_empty() {
        [zero; 3]
    } else {
        pad(&d.gravity)
    };
    // Each body's turning.
    let mut turns = Vec::with_capacity(d.bodies.len());
    for b in &d.bodies {
        let turn = match &b.turning {
            Turning::No => None,
            Turning::Angle(terms) => {
                let mut partials = vec![[zero; 3]; n];
                let (mut w, mut a) = (zero, zero);
                for (name, c) in terms {
                    let j = coordinate(name)?;
                    partials[j][2] = *c;
                    let qd = g.leaf(Leaf::Qd(j as u32));
                    let qdd = g.leaf(Leaf::Qdd(j as u32));
                    let (wt, at) = (g.mul(*c, qd), g.mul(*c, qdd));
                    w = g.sum(w, wt);
                    a = g.sum(a, at);
                }
                // About the plane's normal only: J_zz (the last entry of
                // a tensor); the gyroscopic term does no virtual work.
                let mut inertia = vec![zero; 9];
                inertia[8] = b.inertia.last().copied().unwrap_or(zero);
                let partials = directions.iter().map(|w| along(g, &partials, w)).collect();
                Some(Turn {
                    omega: [zero, zero, w],
                    alpha: [zero, zero, a],
                    partials,
                    inertia,
                })
            }
            Turning::Frame(name) => {
                let f = derived.frames.get(frames.iter().position(|f| f == name)?)?;
                let partials: Vec<[Id; 3]> = (0..n as u32)
                    .map(|j| f.omega.map(|c| partial(g, c, Leaf::Qd(j), &mut memo)))
                    .collect();
                let partials = directions.iter().map(|w| along(g, &partials, w)).collect();
                // R J Rᵀ.
                let r: Vec<Id> = f.rotation.iter().flatten().copied().collect();
                let body = if b.inertia.len() == 9 {
                    b.inertia.clone()
                } else {
                    vec![zero; 9]
                };
                let mut rj = [zero; 9];
                for i in 0..3 {
                    for k in 0..3 {
                        let col = [body[k], body[3 + k], body[6 + k]];
                        rj[3 * i + k] = dot(g, &r[3 * i..3 * i + 3], &col);
                    }
                }
                let mut inertia = vec![zero; 9];
                for i in 0..3 {
                    for k in 0..3 {
                        inertia[3 * i + k] = dot(g, &rj[3 * i..3 * i + 3], &r[3 * k..3 * k + 3]);
                    }
                }
                Some(Turn {
                    omega: f.omega,
                    alpha: f.alpha,
                    partials,
                    inertia,
                })
            }
        };
        turns.push(turn);
    }
    let mut mass = Vec::with_capacity(nk * (nk + 1) / 2);
    for i in 0..nk {
        for j in i..nk {
            let mut m = zero;
            for (b, turn) in d.bodies.iter().zip(&turns) {
                let vg = velocity_partials.get(point(&b.center)?)?;
                let t = dot(g, &vg[i], &vg[j]);
                let t = g.mul(b.mass, t);
                m = g.sum(m, t);
                if let Some(turn) = turn {
                    let jw = apply(g, &turn.inertia, &turn.partials[j]);
                    let r = dot(g, &turn.partials[i], &jw);
                    m = g.sum(m, r);
                }
            }
            mass.push(m);
        }
    }
    let mut forces = vec![zero; nk];
    for (b, turn) in d.bodies.iter().zip(&turns) {
        let at = point(&b.center)?;
        let a = pad(&derived.acc[at]);
        let ma: Vec<Id> = (0..3)
            .map(|c| {
                let x = g.sub(a[c], gravity[c]);
                g.mul(b.mass, x)
            })
            .collect();
        let h = turn.as_ref().map(|t| {
            let ja = apply(g, &t.inertia, &t.alpha);
            let jw = apply(g, &t.inertia, &t.omega);
            let gyro = g.cross3(t.omega, jw);
            [0, 1, 2].map(|c| g.sum(ja[c], gyro[c]))
        });
        for (j, f) in forces.iter_mut().enumerate() {
            let t = dot(g, &ma, &velocity_partials[at][j]);
            *f = g.sum(*f, t);
            if let (Some(h), Some(turn)) = (&h, turn) {
                let r = dot(g, h, &turn.partials[j]);
                *f = g.sum(*f, r);
            }
        }
    }
    let body_turn = |name: &str| {
        d.bodies
            .iter()
            .position(|b| b.name == name)
            .map(|i| turns[i].as_ref())
    };
    let mut point_powers = Vec::new();
    let mut torque_powers = Vec::new();
    let mut coordinate_powers = Vec::new();
    for load in &d.loads {
        match &load.target {
            LoadTarget::Point { point: p, .. } => {
                let at = point(p)?;
                for (j, f) in forces.iter_mut().enumerate() {
                    let t = dot(g, &load.value, &velocity_partials[at][j]);
                    *f = g.sub(*f, t);
                }
                let v = pad(&derived.vel[at]);
                point_powers.push(dot(g, &load.value, &v));
            }
            LoadTarget::Torque { body } => {
                let value = match load.value.as_slice() {
                    [t] => [zero, zero, *t],
                    v => pad(v),
                };
                match body_turn(body)? {
                    Some(turn) => {
                        for (j, f) in forces.iter_mut().enumerate() {
                            let t = dot(g, &value, &turn.partials[j]);
                            *f = g.sub(*f, t);
                        }
                        torque_powers.push(dot(g, &value, &turn.omega));
                    }
                    None => torque_powers.push(zero),
                }
            }
            LoadTarget::Coordinate { coordinate: c } => {
                let j = coordinate(c)?;
                let value = *load.value.first()?;
                for (f, w) in forces.iter_mut().zip(&directions) {
                    let t = g.mul(w[j], value);
                    *f = g.sub(*f, t);
                }
                let qd = g.leaf(Leaf::Qd(j as u32));
                coordinate_powers.push(g.mul(value, qd));
            }
        }
    }
    let mut powers = point_powers;
    powers.extend(torque_powers);
    powers.extend(coordinate_powers);
    for s in &d.springs {
        let (from, to) = (point(&s.from)?, point(&s.to)?);
        let (ra, rb) = (pad(&derived.pos[from]), pad(&derived.pos[to]));
        let (va, vb) = (pad(&derived.vel[from]), pad(&derived.vel[to]));
        let r = [0, 1, 2].map(|c| g.sub(rb[c], ra[c]));
        let v = [0, 1, 2].map(|c| g.sub(vb[c], va[c]));
        let squared = dot(g, &r, &r);
        let length = g.call(crate::ir::Func::Sqrt, squared);
        let e = r.map(|c| g.div(c, length));
        let rate = dot(g, &e, &v);
        let stretch = g.sub(length, s.free_length);
        let elastic = g.mul(s.stiffness, stretch);
        let viscous = g.mul(s.damping, rate);
        let tension = g.sum(elastic, viscous);
        for (j, f) in forces.iter_mut().enumerate() {
            let (pa, pb) = (velocity_partials[from][j], velocity_partials[to][j]);
            let dv = [0, 1, 2].map(|c| g.sub(pb[c], pa[c]));
            let t = dot(g, &e, &dv);
            let t = g.mul(tension, t);
            *f = g.sum(*f, t);
        }
        let rr = g.mul(rate, rate);
        let p = g.mul(s.damping, rr);
        powers.push(g.neg(p));
    }
    if reduced.is_some() {
        // Along C alone: M and Q.
        return Some(EquationsOfMotion {
            coordinates: n,
            jacobian,
            reduced: Some([*mass.first()?, *forces.first()?]),
            mass: Vec::new(),
            forces: Vec::new(),
            powers,
        });
    }
    Some(EquationsOfMotion {
        coordinates: n,
        jacobian,
        mass,
        forces,
        powers,
        reduced: None,
    })
}
