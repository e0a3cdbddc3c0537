//! Design sensitivities: the derivatives of the solved motion with respect
//! to chosen parameters, for the `sensitivities { … }` section.
//!
//! From Φ(d, u, p) = 0 at every instant, the total derivative with respect
//! to a parameter p gives, with the velocity residual V = Φ_q q' and the
//! acceleration residual A = Φ_q q'' + (Φ_q q')_q q' (both zero along the
//! motion, and linear in u' and u'' with coefficient Φ_u):
//!
//! ```text
//! Φ_u ∂u/∂p   = −Φ_p
//! Φ_u ∂u'/∂p  = −(V_p + V_u ∂u/∂p)
//! Φ_u ∂u''/∂p = −(A_p + A_u ∂u/∂p + A_u' ∂u'/∂p)
//! ```
//!
//! and for a point r(q, p) with velocity v(q, q', p) and acceleration
//! a(q, q', q'', p):
//!
//! ```text
//! ∂r/∂p = r_p + r_u ∂u/∂p
//! ∂v/∂p = v_p + v_u ∂u/∂p + v_u' ∂u'/∂p
//! ∂a/∂p = a_p + a_u ∂u/∂p + a_u' ∂u'/∂p + a_u'' ∂u''/∂p
//! ```
//!
//! Every partial derivative is exact (differentiated on the DAG), and the
//! generated code evaluates them all in one straight-line pass, shared with
//! each other by common-subexpression elimination; the three solves reuse
//! one factorisation of Φ_u.

use crate::diff::{partial, Memo};
use crate::ir::{Id, Leaf};
use crate::kinematics::Derived;
use crate::lower::Model;

/// The partial derivatives behind the sensitivities. Indices: k a chosen
/// parameter (in the order of the section), i an equation, j an unknown,
/// n a point, c a component.
pub struct Partials {
    /// The chosen parameters' indices among the parameters.
    pub params: Vec<u32>,
    /// Φ_p: `[k][i]`.
    pub phi_p: Vec<Vec<Id>>,
    /// V_p: `[k][i]`.
    pub vel_p: Vec<Vec<Id>>,
    /// V_u: `[i][j]`.
    pub vel_u: Vec<Vec<Id>>,
    /// A_p: `[k][i]`.
    pub acc_p: Vec<Vec<Id>>,
    /// A_u: `[i][j]`.
    pub acc_u: Vec<Vec<Id>>,
    /// A_u': `[i][j]`.
    pub acc_ud: Vec<Vec<Id>>,
    /// r_p: `[k][n][c]`.
    pub pos_p: Vec<Vec<Vec<Id>>>,
    /// r_u: `[n][c][j]`.
    pub pos_u: Vec<Vec<Vec<Id>>>,
    /// v_p: `[k][n][c]`.
    pub vel_pt_p: Vec<Vec<Vec<Id>>>,
    /// v_u: `[n][c][j]`.
    pub vel_pt_u: Vec<Vec<Vec<Id>>>,
    /// v_u': `[n][c][j]`.
    pub vel_pt_ud: Vec<Vec<Vec<Id>>>,
    /// a_p: `[k][n][c]`.
    pub acc_pt_p: Vec<Vec<Vec<Id>>>,
    /// a_u: `[n][c][j]`.
    pub acc_pt_u: Vec<Vec<Vec<Id>>>,
    /// a_u': `[n][c][j]`.
    pub acc_pt_ud: Vec<Vec<Vec<Id>>>,
    /// a_u'': `[n][c][j]`.
    pub acc_pt_udd: Vec<Vec<Vec<Id>>>,
}

impl Partials {
    /// Every root, for the schedule of the generated pass, and the layout
    /// of a run-time model's sensitivity stage: Φ_p `[k][i]`, V_p `[k][i]`,
    /// V_u `[i][j]`, A_p `[k][i]`, A_u `[i][j]`, A_u' `[i][j]`, then r_p `[k][n][c]`,
    /// r_u `[n][c][j]`, v_p `[k][n][c]`, v_u `[n][c][j]`, v_u' `[n][c][j]`,
    /// a_p `[k][n][c]`, a_u `[n][c][j]`, a_u' `[n][c][j]`, a_u'' `[n][c][j]`, each
    /// flattened with its last index fastest.
    #[must_use]
    pub fn roots(&self) -> Vec<Id> {
        let mut out = Vec::new();
        for m in [
            &self.phi_p,
            &self.vel_p,
            &self.vel_u,
            &self.acc_p,
            &self.acc_u,
            &self.acc_ud,
        ] {
            out.extend(m.iter().flatten());
        }
        for t in [
            &self.pos_p,
            &self.pos_u,
            &self.vel_pt_p,
            &self.vel_pt_u,
            &self.vel_pt_ud,
            &self.acc_pt_p,
            &self.acc_pt_u,
            &self.acc_pt_ud,
            &self.acc_pt_udd,
        ] {
            out.extend(t.iter().flatten().flatten());
        }
        out
    }
}

/// The partial derivatives for the parameters `params` (indices).
pub fn partials(model: &mut Model, d: &Derived, params: &[u32]) -> Partials {
    let nd = model.drivers;
    let nu = model.unknowns;
    let g = &mut model.graph;
    let mut memo = Memo::default();
    // The velocity and acceleration residuals, V = Φ_u u' − (−Φ_d d') and
    // A = Φ_u u'' − (−Φ_d d'' − γ).
    let mut vel = Vec::new();
    let mut acc = Vec::new();
    for (i, row) in d.jac.iter().enumerate() {
        let mut v = g.neg(d.vel_rhs[i]);
        let mut a = g.neg(d.acc_rhs[i]);
        for (j, &e) in row.iter().enumerate() {
            let j = u32::try_from(j).unwrap_or(0);
            let ud = g.leaf(Leaf::Qd(nd + j));
            let udd = g.leaf(Leaf::Qdd(nd + j));
            let t = g.mul(e, ud);
            v = g.sum(v, t);
            let t = g.mul(e, udd);
            a = g.sum(a, t);
        }
        vel.push(v);
        acc.push(a);
    }
    let by =
        |g: &mut crate::ir::Graph, memo: &mut Memo, e: Id, leaf: Leaf| partial(g, e, leaf, memo);
    let per_param = |g: &mut crate::ir::Graph, memo: &mut Memo, roots: &[Id]| -> Vec<Vec<Id>> {
        params
            .iter()
            .map(|&k| {
                roots
                    .iter()
                    .map(|&e| by(g, memo, e, Leaf::Param(k)))
                    .collect()
            })
            .collect()
    };
    let per_unknown =
        |g: &mut crate::ir::Graph, memo: &mut Memo, roots: &[Id], rate: u8| -> Vec<Vec<Id>> {
            roots
                .iter()
                .map(|&e| {
                    (0..nu)
                        .map(|j| {
                            let leaf = match rate {
                                0 => Leaf::Q(nd + j),
                                1 => Leaf::Qd(nd + j),
                                _ => Leaf::Qdd(nd + j),
                            };
                            by(g, memo, e, leaf)
                        })
                        .collect()
                })
                .collect()
        };
    let phi_p = per_param(g, &mut memo, &d.phi);
    let vel_p = per_param(g, &mut memo, &vel);
    let vel_u = per_unknown(g, &mut memo, &vel, 0);
    let acc_p = per_param(g, &mut memo, &acc);
    let acc_u = per_unknown(g, &mut memo, &acc, 0);
    let acc_ud = per_unknown(g, &mut memo, &acc, 1);
    // Points, component by component.
    let points_p =
        |g: &mut crate::ir::Graph, memo: &mut Memo, of: &[Vec<Id>]| -> Vec<Vec<Vec<Id>>> {
            params
                .iter()
                .map(|&k| {
                    of.iter()
                        .map(|p| p.iter().map(|&e| by(g, memo, e, Leaf::Param(k))).collect())
                        .collect()
                })
                .collect()
        };
    let points_u = |g: &mut crate::ir::Graph,
                    memo: &mut Memo,
                    of: &[Vec<Id>],
                    rate: u8|
     -> Vec<Vec<Vec<Id>>> {
        of.iter().map(|p| per_unknown(g, memo, p, rate)).collect()
    };
    let pos_p = points_p(g, &mut memo, &d.pos);
    let pos_u = points_u(g, &mut memo, &d.pos, 0);
    let vel_pt_p = points_p(g, &mut memo, &d.vel);
    let vel_pt_u = points_u(g, &mut memo, &d.vel, 0);
    let vel_pt_ud = points_u(g, &mut memo, &d.vel, 1);
    let acc_pt_p = points_p(g, &mut memo, &d.acc);
    let acc_pt_u = points_u(g, &mut memo, &d.acc, 0);
    let acc_pt_ud = points_u(g, &mut memo, &d.acc, 1);
    let acc_pt_udd = points_u(g, &mut memo, &d.acc, 2);
    Partials {
        params: params.to_vec(),
        phi_p,
        vel_p,
        vel_u,
        acc_p,
        acc_u,
        acc_ud,
        pos_p,
        pos_u,
        vel_pt_p,
        vel_pt_u,
        vel_pt_ud,
        acc_pt_p,
        acc_pt_u,
        acc_pt_ud,
        acc_pt_udd,
    }
}
