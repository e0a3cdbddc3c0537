//! The kinematic quantities, built from the model by exact differentiation.
//!
//! With coordinates q = (d, u) (drivers, unknowns) and constraints Φ(q) = 0:
//!
//! * position: Φ and its Jacobian Φ_u, for Newton–Raphson;
//! * velocity: Φ_u u' = −Φ_d d', the right-hand side being dΦ/dt with u' = 0;
//! * acceleration: Φ_u u'' = −Φ_d d'' − γ with γ = (Φ_q q')_q q', the
//!   right-hand side being −d²Φ/dt² with u'' = 0;
//! * points r(q): v = r_q q' and a = r_q q'' + (r_q q')_q q'.

use crate::diff::{partial, time_derivative, time_derivative_by_partials, Accelerating, Memo};
use crate::ir::{op_count, Id, Leaf, OpCount};
use crate::lower::{Body, Chain, Model};

/// Every expression the generated code evaluates.
pub struct Derived {
    /// Φ_i.
    pub phi: Vec<Id>,
    /// ∂Φ_i/∂u_k, row i, column k.
    pub jac: Vec<Vec<Id>>,
    /// −Φ_d d'.
    pub vel_rhs: Vec<Id>,
    /// −Φ_d d'' − γ.
    pub acc_rhs: Vec<Id>,
    /// Point positions (2 or 3 components each).
    pub pos: Vec<Vec<Id>>,
    /// Point velocities.
    pub vel: Vec<Vec<Id>>,
    /// Point accelerations.
    pub acc: Vec<Vec<Id>>,
    /// Frames.
    pub frames: Vec<DerivedFrame>,
}

/// A frame's rotation, angular velocity and acceleration, and its origin's
/// position, velocity and acceleration.
pub struct DerivedFrame {
    /// R, row by row.
    pub rotation: [[Id; 3]; 3],
    /// ω.
    pub omega: [Id; 3],
    /// α.
    pub alpha: [Id; 3],
    /// o, o', o''.
    pub origin: [[Id; 3]; 3],
}

/// How the velocities and accelerations of points and frames are formed.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Method {
    /// From the partial derivatives ∂/∂q_j, which the loop equations share.
    Partials,
    /// By forward differentiation along time: one pass per derivative,
    /// which suits long serial chains.
    Forward,
}

/// Differentiates the model, forming the points' and frames' motion both
/// ways and keeping the one whose analysis takes fewer operations after
/// common-subexpression elimination.
pub fn derive(model: &mut Model) -> Derived {
    let mut memo = Memo::default();
    let by_partials = derive_with(model, Method::Partials, &mut memo);
    let forward = derive_with(model, Method::Forward, &mut memo);
    let cost = |d: &Derived| operation_counts(model, d)[1].1.shared;
    if cost(&forward) < cost(&by_partials) {
        forward
    } else {
        by_partials
    }
}

fn derive_with(model: &mut Model, method: Method, memo: &mut Memo) -> Derived {
    let nd = model.drivers;
    let nq = model.coords();
    let g = &mut model.graph;
    // The time derivative of a point or frame quantity.
    let dt = |g: &mut crate::ir::Graph, e: Id, acc: Accelerating, memo: &mut Memo| match method {
        Method::Partials => time_derivative_by_partials(g, e, nq, acc, memo),
        Method::Forward => time_derivative(g, e, acc, memo),
    };
    let phi: Vec<Id> = model.equations.iter().map(|e| e.residual).collect();
    let zero = g.constant(0.0);
    let jac = phi
        .iter()
        .map(|&p| {
            let involved: std::collections::HashSet<
                Leaf,
                std::hash::BuildHasherDefault<crate::ir::FastHasher>,
            > = g.leaves_under(p).collect();
            (nd..nq)
                .map(|j| {
                    if involved.contains(&Leaf::Q(j)) {
                        partial(g, p, Leaf::Q(j), memo)
                    } else {
                        zero
                    }
                })
                .collect()
        })
        .collect();
    let mut vel_rhs = Vec::new();
    let mut acc_rhs = Vec::new();
    for &p in &phi {
        // dΦ/dt over the drivers only is Φ_d d'.
        let mut phi_d_dd = g.constant(0.0);
        for j in 0..nd {
            let dp = partial(g, p, Leaf::Q(j), memo);
            let qd = g.leaf(Leaf::Qd(j));
            let t = g.mul(dp, qd);
            phi_d_dd = g.sum(phi_d_dd, t);
        }
        vel_rhs.push(g.neg(phi_d_dd));
        // d²Φ/dt² with u'' = 0 is Φ_d d'' + γ.
        let phi_dot = time_derivative_by_partials(g, p, nq, Accelerating::None, memo);
        let phi_ddot = time_derivative_by_partials(g, phi_dot, nq, Accelerating::First(nd), memo);
        acc_rhs.push(g.neg(phi_ddot));
    }
    let mut pos = Vec::new();
    let mut vel = Vec::new();
    let mut acc = Vec::new();
    for p in &model.points {
        pos.push(p.coords.clone());
        if let Some(b) = &p.attached {
            // v = ȯ + ω × r, a = ö + α × r + ω × (ω × r), r = R v.
            let (omega, alpha) = chain_rates(g, &b.chain, &mut |g, e, acc| dt(g, e, acc, memo));
            let [_, od, odd] = match &b.body {
                Some(body) => body_origin(g, body, &mut |g, e, acc| dt(g, e, acc, memo)),
                None => {
                    let od = b.origin.map(|e| dt(g, e, Accelerating::None, memo));
                    let odd = od.map(|e| dt(g, e, Accelerating::All, memo));
                    [b.origin, od, odd]
                }
            };
            let wr = g.cross3(omega, b.offset);
            let ar = g.cross3(alpha, b.offset);
            let wwr = g.cross3(omega, wr);
            let mut v = Vec::new();
            let mut a = Vec::new();
            for i in 0..3 {
                v.push(g.sum(od[i], wr[i]));
                let s = g.sum(odd[i], ar[i]);
                a.push(g.sum(s, wwr[i]));
            }
            vel.push(v);
            acc.push(a);
            continue;
        }
        let v: Vec<Id> = p
            .coords
            .iter()
            .map(|&c| dt(g, c, Accelerating::None, memo))
            .collect();
        let a = v
            .iter()
            .map(|&c| dt(g, c, Accelerating::All, memo))
            .collect();
        vel.push(v);
        acc.push(a);
    }
    let mut frames = Vec::new();
    for f in &model.frames {
        let r = f.rotation;
        let half = g.constant(0.5);
        // ½ axial(M Rᵀ − R Mᵀ), with (M Rᵀ)_ij = Σ_k M_ik R_jk.
        let axial = |m: &[[Id; 3]; 3], g: &mut crate::ir::Graph| {
            let w = |i: usize, j: usize, g: &mut crate::ir::Graph| {
                let mut s = g.constant(0.0);
                for k in 0..3 {
                    let p = g.mul(m[i][k], r[j][k]);
                    s = g.sum(s, p);
                }
                s
            };
            let mut v = [half; 3];
            for (c, (i, j)) in [(2, 1), (0, 2), (1, 0)].into_iter().enumerate() {
                let a = w(i, j, g);
                let b = w(j, i, g);
                let d = g.sub(a, b);
                v[c] = g.mul(half, d);
            }
            v
        };
        let (omega, alpha) = match &f.chain {
            Some(chain) => chain_rates(g, chain, &mut |g, e, acc| dt(g, e, acc, memo)),
            None => {
                // [ω]× is the skew part of Ṙ Rᵀ, and [α]× that of R̈ Rᵀ (the
                // derivative of Ṙ Rᵀ adds Ṙ Ṙᵀ, which is symmetric).
                let rd = r.map(|row| row.map(|e| dt(g, e, Accelerating::None, memo)));
                let rdd = rd.map(|row| row.map(|e| dt(g, e, Accelerating::All, memo)));
                (axial(&rd, g), axial(&rdd, g))
            }
        };
        let o = f.origin;
        let [_, od, odd] = match &f.body {
            Some(body) => body_origin(g, body, &mut |g, e, acc| dt(g, e, acc, memo)),
            None => {
                let od = o.map(|e| dt(g, e, Accelerating::None, memo));
                let odd = od.map(|e| dt(g, e, Accelerating::All, memo));
                [o, od, odd]
            }
        };
        frames.push(DerivedFrame {
            rotation: r,
            omega,
            alpha,
            origin: [o, od, odd],
        });
    }
    Derived {
        phi,
        jac,
        vel_rhs,
        acc_rhs,
        pos,
        vel,
        acc,
        frames,
    }
}

/// The time derivative of an expression, as [`derive_with`] forms it.
type TimeDerivative<'a> = dyn FnMut(&mut crate::ir::Graph, Id, Accelerating) -> Id + 'a;

/// ω and α of a rotation built as a chain (see [`Chain`]), by the
/// recursion ω = Σ zₖ θ̇ₖ, α = Σ (zₖ θ̈ₖ + ωₖ₋₁ × zₖ θ̇ₖ), with `dt` the time
/// derivative.
fn chain_rates(
    g: &mut crate::ir::Graph,
    chain: &Chain,
    dt: &mut TimeDerivative<'_>,
) -> ([Id; 3], [Id; 3]) {
    let prefixes = prefix_rates(g, chain, dt);
    let zero = g.constant(0.0);
    prefixes.last().copied().unwrap_or(([zero; 3], [zero; 3]))
}

/// (ωₖ, αₖ) of the first k rotations of `chain`, for k = 0 … n.
fn prefix_rates(
    g: &mut crate::ir::Graph,
    chain: &Chain,
    dt: &mut TimeDerivative<'_>,
) -> Vec<([Id; 3], [Id; 3])> {
    let zero = g.constant(0.0);
    let (mut omega, mut alpha) = ([zero; 3], [zero; 3]);
    let mut out = vec![(omega, alpha)];
    for &(z, theta) in chain {
        let rate = dt(g, theta, Accelerating::None);
        let acceleration = dt(g, rate, Accelerating::All);
        // zₖ θ̇ₖ, the joint's own angular velocity.
        let w = z.map(|c| g.mul(c, rate));
        let turn = g.cross3(omega, w);
        for i in 0..3 {
            let za = g.mul(z[i], acceleration);
            let a = g.sum(alpha[i], za);
            alpha[i] = g.sum(a, turn[i]);
            omega[i] = g.sum(omega[i], w[i]);
        }
        out.push((omega, alpha));
    }
    out
}

/// o, ȯ and ö of a body's origin built along its chain (see [`Body`]):
/// ȯ = Σ ω_{k(m)} × sₘ, ö = Σ α_{k(m)} × sₘ + ω_{k(m)} × (ω_{k(m)} × sₘ),
/// with ωₖ and αₖ those of the chain's first k rotations.
fn body_origin(g: &mut crate::ir::Graph, body: &Body, dt: &mut TimeDerivative<'_>) -> [[Id; 3]; 3] {
    let zero = g.constant(0.0);
    let prefix = prefix_rates(g, &body.chain, dt);
    let mut out = [[zero; 3]; 3];
    for &(s, k) in &body.segments {
        let Some(&(w, a)) = prefix.get(k) else {
            continue;
        };
        let ws = g.cross3(w, s);
        let as_ = g.cross3(a, s);
        let wws = g.cross3(w, ws);
        for i in 0..3 {
            out[0][i] = g.sum(out[0][i], s[i]);
            out[1][i] = g.sum(out[1][i], ws[i]);
            let t = g.sum(as_[i], wws[i]);
            out[2][i] = g.sum(out[2][i], t);
        }
    }
    out
}

/// Operation counts, before and after common-subexpression elimination, of
/// the Newton step (Φ and Φ_u) and of the analysis (Φ_u, both right-hand
/// sides, and every point's position, velocity and acceleration).
pub fn operation_counts(model: &Model, d: &Derived) -> [(&'static str, OpCount); 2] {
    let g = &model.graph;
    let jac: Vec<Id> = d.jac.iter().flatten().copied().collect();
    let newton: Vec<Id> = d.phi.iter().chain(&jac).copied().collect();
    let analysis: Vec<Id> = jac
        .iter()
        .chain(&d.vel_rhs)
        .chain(&d.acc_rhs)
        .chain(d.pos.iter().flatten())
        .chain(d.vel.iter().flatten())
        .chain(d.acc.iter().flatten())
        .chain(d.frames.iter().flat_map(|f| f.omega.iter().chain(&f.alpha)))
        .copied()
        .collect();
    [
        ("residual and Jacobian", op_count(g, &newton)),
        ("velocity, acceleration and points", op_count(g, &analysis)),
    ]
}
