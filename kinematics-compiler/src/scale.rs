//! Term scales of the equations: for each Φ_i, an expression S_i of the
//! parameters and drivers that measures the size of the equation's terms.
//!
//! The runtime judges convergence by |Φ_i| / S_i and singularity by the
//! scaled Jacobian diag(1/S) Φ_u diag(unit) (`kinematics_core::solve::Scaling`),
//! so that neither depends on the units or the size of the mechanism.
//!
//! S is built by structural recursion over the residual's DAG, as a bound of
//! the magnitudes of its terms:
//!
//! * a constant c: |c|; a parameter or a driver: its absolute value;
//! * an unknown angle: 1 (rad); an unknown length: the characteristic
//!   length L (a leaf that the generated code binds), or 0 in the first
//!   pass that computes L itself;
//! * a + b: S(a) + S(b); −a: S(a); a·b: S(a)·S(b); aⁿ (n ≥ 0): S(a)ⁿ;
//!   √a: √S(a); exp a: exp S(a);
//! * sin, cos: 1; asin, atan2: π/2 and π; acos: π;
//! * anything else (a quotient, tan, ln, a negative power) free of unknowns:
//!   its absolute value; with unknowns: 1 (a factor of unit size).
//!
//! For the four-bar loop a cos φ + b cos θ3 − d − c cos θ4 this gives
//! |a| + |b| + |d| + |c|, the sum of the link lengths in the loop.

use std::collections::HashMap;

use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::lower::{CoordKind, Model};

/// The scale expressions of a model's equations.
pub struct Scales {
    /// S_i with the unknown lengths counted as 0 (L is the largest).
    pub fixed: Vec<Id>,
    /// S_i with the unknown lengths counted as L (equal to `fixed` when
    /// there are none).
    pub full: Vec<Id>,
    /// Whether each unknown is a length (its column is scaled by L).
    pub is_length: Vec<bool>,
}

/// The leaf that stands for the characteristic length L in `Scales::full`:
/// one past the last parameter.
pub fn length_leaf(params: usize) -> Leaf {
    Leaf::Param(u32::try_from(params).unwrap_or(u32::MAX))
}

/// Builds the term scales of every equation of `model` into its graph.
pub fn scales(model: &mut Model, params: usize) -> Scales {
    let residuals: Vec<Id> = model.equations.iter().map(|e| e.residual).collect();
    let is_length: Vec<bool> = model.kinds[model.drivers as usize..]
        .iter()
        .map(|k| *k == CoordKind::Length)
        .collect();
    let drivers = model.drivers;
    let kinds = model.kinds.clone();
    let g = &mut model.graph;
    let fixed = {
        let zero = g.constant(0.0);
        let mut b = Builder {
            drivers,
            kinds: &kinds,
            length: zero,
            memo: HashMap::new(),
        };
        residuals.iter().map(|&r| b.magnitude(g, r)).collect()
    };
    let full = if is_length.iter().any(|&l| l) {
        let length = g.leaf(length_leaf(params));
        let mut b = Builder {
            drivers,
            kinds: &kinds,
            length,
            memo: HashMap::new(),
        };
        residuals.iter().map(|&r| b.magnitude(g, r)).collect()
    } else {
        Vec::clone(&fixed)
    };
    Scales {
        fixed,
        full,
        is_length,
    }
}

struct Builder<'a> {
    drivers: u32,
    kinds: &'a [CoordKind],
    /// What an unknown length counts as.
    length: Id,
    memo: HashMap<Id, Id>,
}

impl Builder<'_> {
    fn magnitude(&mut self, g: &mut Graph, id: Id) -> Id {
        if let Some(&m) = self.memo.get(&id) {
            return m;
        }
        let drivers = self.drivers;
        let free =
            |g: &Graph, x: Id| !g.depends_on(x, &|l| matches!(l, Leaf::Q(j) if j >= drivers));
        let m = match g.node(id) {
            Node::Const(bits) => g.constant(f64::from_bits(bits).abs()),
            Node::Leaf(Leaf::Q(j)) if j >= drivers => match self.kinds[j as usize] {
                CoordKind::Angle => g.constant(1.0),
                CoordKind::Length => self.length,
            },
            Node::Leaf(_) => g.call(Func::Abs, id),
            Node::Add(a, b) => {
                let (a, b) = (self.magnitude(g, a), self.magnitude(g, b));
                g.sum(a, b)
            }
            Node::Mul(a, b) => {
                let (a, b) = (self.magnitude(g, a), self.magnitude(g, b));
                g.mul(a, b)
            }
            Node::Neg(a) => self.magnitude(g, a),
            Node::Powi(a, n) if n >= 0 => {
                let a = self.magnitude(g, a);
                g.powi(a, n)
            }
            Node::Call(Func::Sin | Func::Cos, _) => g.constant(1.0),
            Node::Call(Func::Asin, _) => g.constant(std::f64::consts::FRAC_PI_2),
            Node::Call(Func::Acos, _) | Node::Atan2(..) => g.constant(std::f64::consts::PI),
            Node::Call(f @ (Func::Sqrt | Func::Exp), a) => {
                let a = self.magnitude(g, a);
                g.call(f, a)
            }
            _ if free(g, id) => g.call(Func::Abs, id),
            _ => g.constant(1.0),
        };
        self.memo.insert(id, m);
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Evaluates S for a residual built by `build`, with parameters
    /// p_i = `params`[i], drivers and unknowns at `q`, L = `length`.
    fn scale_of(
        kinds: &[CoordKind],
        drivers: u32,
        build: impl Fn(&mut Graph) -> Id,
        env: &dyn Fn(Leaf) -> f64,
    ) -> f64 {
        let mut g = Graph::new();
        let r = build(&mut g);
        let mut b = Builder {
            drivers,
            kinds,
            length: g.constant(0.0),
            memo: HashMap::new(),
        };
        let m = b.magnitude(&mut g, r);
        g.eval(&[m], env)[0]
    }

    #[test]
    fn four_bar_loop_scale_is_the_sum_of_its_link_lengths() {
        // x: a cos φ + b cos θ3 − (d + c cos θ4), with a negative offset d.
        let kinds = [CoordKind::Angle; 3];
        let s = scale_of(
            &kinds,
            1,
            |g| {
                let (a, b, c, d) = (
                    g.leaf(Leaf::Param(0)),
                    g.leaf(Leaf::Param(1)),
                    g.leaf(Leaf::Param(2)),
                    g.leaf(Leaf::Param(3)),
                );
                let (phi, t3, t4) = (g.leaf(Leaf::Q(0)), g.leaf(Leaf::Q(1)), g.leaf(Leaf::Q(2)));
                let cphi = g.call(Func::Cos, phi);
                let c3 = g.call(Func::Cos, t3);
                let c4 = g.call(Func::Cos, t4);
                let ac = g.mul(a, cphi);
                let bc = g.mul(b, c3);
                let cc = g.mul(c, c4);
                let l = g.sum(ac, bc);
                let r = g.sum(d, cc);
                g.sub(l, r)
            },
            &|l| match l {
                Leaf::Param(i) => [0.04, 0.12, 0.10, -0.11][i as usize],
                Leaf::Q(j) => [0.3, 1.0, 2.0][j as usize],
                _ => 0.0,
            },
        );
        assert!((s - 0.37).abs() < 1e-15, "{s}");
    }

    #[test]
    fn unknown_lengths_count_as_the_characteristic_length() {
        // Slider-crank: a cos φ + b cos θ − x, x an unknown length.
        let kinds = [CoordKind::Angle, CoordKind::Angle, CoordKind::Length];
        let build = |g: &mut Graph| {
            let (a, b) = (g.leaf(Leaf::Param(0)), g.leaf(Leaf::Param(1)));
            let (phi, th, x) = (g.leaf(Leaf::Q(0)), g.leaf(Leaf::Q(1)), g.leaf(Leaf::Q(2)));
            let cphi = g.call(Func::Cos, phi);
            let cth = g.call(Func::Cos, th);
            let t1 = g.mul(a, cphi);
            let t2 = g.mul(b, cth);
            let s = g.sum(t1, t2);
            g.sub(s, x)
        };
        let env = |l: Leaf| match l {
            Leaf::Param(0) => 0.1,
            Leaf::Param(1) => 0.25,
            Leaf::Param(2) => 7.0, // L
            Leaf::Q(_) => 1e20,    // never read: unknowns enter by kind
            _ => 0.0,
        };
        // First pass (L unknown): x counts 0.
        let s0 = scale_of(&kinds, 1, build, &env);
        assert!((s0 - 0.35).abs() < 1e-15, "{s0}");
        // Second pass: x counts L.
        let mut g = Graph::new();
        let r = build(&mut g);
        let length = g.leaf(Leaf::Param(2));
        let mut b = Builder {
            drivers: 1,
            kinds: &kinds,
            length,
            memo: HashMap::new(),
        };
        let m = b.magnitude(&mut g, r);
        assert!((g.eval(&[m], &env)[0] - 7.35).abs() < 1e-14);
    }
}
