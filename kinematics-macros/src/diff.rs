//! Exact differentiation on the DAG.
//!
//! [`partial`] gives ∂e/∂x for a leaf x by the chain rule, visiting each node
//! reachable from `e` once, in arena (topological) order, so the cost is
//! linear in the size of the DAG. [`time_derivative`] builds
//! de/dt = Σ_j ∂e/∂q_j · q'_j + Σ_j ∂e/∂q'_j · q''_j, from which come the
//! velocity and acceleration equations and the point velocities and
//! accelerations.

use std::collections::HashMap;

use crate::ir::{Func, Graph, Id, Leaf, Node};

/// Memo of derivatives with respect to one leaf, shared across roots.
pub type Memo = HashMap<(Id, Leaf), Id>;

/// ∂root/∂wrt.
pub fn partial(g: &mut Graph, root: Id, wrt: Leaf, memo: &mut Memo) -> Id {
    if let Some(&d) = memo.get(&(root, wrt)) {
        return d;
    }
    let live = g.reachable(&[root]);
    let zero = g.constant(0.0);
    for (i, _) in live.iter().enumerate().filter(|(_, l)| **l) {
        let id = Id::from_index(i);
        if memo.contains_key(&(id, wrt)) {
            continue;
        }
        let d = |memo: &Memo, c: Id| memo.get(&(c, wrt)).copied().unwrap_or(zero);
        let node = g.node(id);
        let result = match node {
            Node::Const(_) => zero,
            Node::Leaf(l) => {
                if l == wrt {
                    g.constant(1.0)
                } else {
                    zero
                }
            }
            Node::Add(a, b) => {
                let (da, db) = (d(memo, a), d(memo, b));
                g.sum(da, db)
            }
            Node::Neg(a) => {
                let da = d(memo, a);
                g.neg(da)
            }
            Node::Mul(a, b) => {
                // (ab)' = a'b + ab'
                let (da, db) = (d(memo, a), d(memo, b));
                let l = g.mul(da, b);
                let r = g.mul(a, db);
                g.sum(l, r)
            }
            Node::Div(a, b) => {
                // (a/b)' = a'/b − (a/b)·b'/b
                let (da, db) = (d(memo, a), d(memo, b));
                let l = g.div(da, b);
                let t = g.mul(id, db);
                let r = g.div(t, b);
                g.sub(l, r)
            }
            Node::Powi(a, n) => {
                // (aⁿ)' = n·aⁿ⁻¹·a'
                let da = d(memo, a);
                let nn = g.constant(f64::from(n));
                let p = g.powi(a, n - 1);
                let np = g.mul(nn, p);
                g.mul(np, da)
            }
            Node::Call(f, a) => {
                let da = d(memo, a);
                let outer = call_derivative(g, f, a, id);
                g.mul(outer, da)
            }
            Node::Atan2(y, x) => {
                // atan2(y, x)' = (x·y' − y·x') / (x² + y²)
                let (dy, dx) = (d(memo, y), d(memo, x));
                let l = g.mul(x, dy);
                let r = g.mul(y, dx);
                let num = g.sub(l, r);
                let x2 = g.powi(x, 2);
                let y2 = g.powi(y, 2);
                let den = g.sum(x2, y2);
                g.div(num, den)
            }
        };
        memo.insert((id, wrt), result);
    }
    memo.get(&(root, wrt)).copied().unwrap_or(zero)
}

/// f'(a) for f(a) = `value`.
fn call_derivative(g: &mut Graph, f: Func, a: Id, value: Id) -> Id {
    match f {
        Func::Sin => g.call(Func::Cos, a),
        Func::Cos => {
            let s = g.call(Func::Sin, a);
            g.neg(s)
        }
        Func::Tan => {
            // 1 + tan²a
            let one = g.constant(1.0);
            let t2 = g.powi(value, 2);
            g.sum(one, t2)
        }
        Func::Asin | Func::Acos => {
            // ±1/√(1 − a²)
            let one = g.constant(1.0);
            let a2 = g.powi(a, 2);
            let r = g.sub(one, a2);
            let s = g.call(Func::Sqrt, r);
            let inv = g.div(one, s);
            if f == Func::Asin {
                inv
            } else {
                g.neg(inv)
            }
        }
        Func::Sqrt => {
            // 1/(2√a)
            let half = g.constant(0.5);
            g.div(half, value)
        }
        Func::Exp => value,
        Func::Ln => {
            let one = g.constant(1.0);
            g.div(one, a)
        }
    }
}

/// de/dt, where coordinate j has q_j, q'_j, q''_j as leaves. Only the
/// coordinates with `moving(j)` contribute their q'_j terms, and only those
/// with `accelerating(j)` their q''_j terms (the others are taken as zero,
/// which is how the right-hand sides of the velocity and acceleration
/// equations are formed).
pub fn time_derivative(
    g: &mut Graph,
    e: Id,
    coords: u32,
    accelerating: &dyn Fn(u32) -> bool,
    memo: &mut Memo,
) -> Id {
    let mut total = g.constant(0.0);
    for j in 0..coords {
        let dq = partial(g, e, Leaf::Q(j), memo);
        let qd = g.leaf(Leaf::Qd(j));
        let t = g.mul(dq, qd);
        total = g.sum(total, t);
        if accelerating(j) {
            let dqd = partial(g, e, Leaf::Qd(j), memo);
            let qdd = g.leaf(Leaf::Qdd(j));
            let t = g.mul(dqd, qdd);
            total = g.sum(total, t);
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks ∂e/∂x against a central finite difference at several points.
    fn check(build: impl Fn(&mut Graph, Id, Id) -> Id) {
        let mut g = Graph::new();
        let x = g.leaf(Leaf::Q(0));
        let y = g.leaf(Leaf::Q(1));
        let e = build(&mut g, x, y);
        let mut memo = Memo::new();
        let dx = partial(&mut g, e, Leaf::Q(0), &mut memo);
        let dy = partial(&mut g, e, Leaf::Q(1), &mut memo);
        for k in 0..20 {
            let (x0, y0) = (0.1 + 0.037 * f64::from(k), 0.2 + 0.021 * f64::from(k));
            let at =
                |x: f64, y: f64| g.eval(&[e], &move |l| if l == Leaf::Q(0) { x } else { y })[0];
            let exact = g.eval(&[dx, dy], &move |l| if l == Leaf::Q(0) { x0 } else { y0 });
            let h = 1e-6;
            let fx = (at(x0 + h, y0) - at(x0 - h, y0)) / (2.0 * h);
            let fy = (at(x0, y0 + h) - at(x0, y0 - h)) / (2.0 * h);
            assert!(
                (exact[0] - fx).abs() < 1e-7 * (1.0 + fx.abs()),
                "d/dx {} vs {fx}",
                exact[0]
            );
            assert!(
                (exact[1] - fy).abs() < 1e-7 * (1.0 + fy.abs()),
                "d/dy {} vs {fy}",
                exact[1]
            );
        }
    }

    #[test]
    fn sum() {
        check(|g, x, y| g.sum(x, y));
    }
    #[test]
    fn product() {
        check(|g, x, y| g.mul(x, y));
    }
    #[test]
    fn quotient() {
        check(|g, x, y| g.div(x, y));
    }
    #[test]
    fn negation() {
        check(|g, x, y| {
            let p = g.mul(x, y);
            g.neg(p)
        });
    }
    #[test]
    fn power() {
        check(|g, x, y| {
            let p = g.powi(x, 3);
            let q = g.powi(y, -2);
            g.mul(p, q)
        });
    }
    #[test]
    fn sine() {
        check(|g, x, y| {
            let p = g.mul(x, y);
            g.call(Func::Sin, p)
        });
    }
    #[test]
    fn cosine() {
        check(|g, x, y| {
            let p = g.sum(x, y);
            g.call(Func::Cos, p)
        });
    }
    #[test]
    fn tangent() {
        check(|g, x, y| {
            let p = g.mul(x, y);
            g.call(Func::Tan, p)
        });
    }
    #[test]
    fn arcsine() {
        check(|g, x, y| {
            let p = g.mul(x, y);
            g.call(Func::Asin, p)
        });
    }
    #[test]
    fn arccosine() {
        check(|g, x, y| {
            let p = g.mul(x, y);
            g.call(Func::Acos, p)
        });
    }
    #[test]
    fn square_root() {
        check(|g, x, y| {
            let p = g.sum(x, y);
            g.call(Func::Sqrt, p)
        });
    }
    #[test]
    fn exponential() {
        check(|g, x, y| {
            let p = g.mul(x, y);
            g.call(Func::Exp, p)
        });
    }
    #[test]
    fn logarithm() {
        check(|g, x, y| {
            let p = g.sum(x, y);
            g.call(Func::Ln, p)
        });
    }
    #[test]
    fn arctangent2() {
        check(|g, x, y| g.atan2(y, x));
    }

    #[test]
    fn second_time_derivative_of_polar_is_centripetal_plus_tangential() {
        // x = r cos θ: x'' = −r θ'² cos θ − r θ'' sin θ (r constant).
        let mut g = Graph::new();
        let th = g.leaf(Leaf::Q(0));
        let r = g.leaf(Leaf::Param(0));
        let c = g.call(Func::Cos, th);
        let x = g.mul(r, c);
        let mut memo = Memo::new();
        let v = time_derivative(&mut g, x, 1, &|_| true, &mut memo);
        let a = time_derivative(&mut g, v, 1, &|_| true, &mut memo);
        let (t, w, al, rr) = (0.7_f64, 3.0_f64, -2.0_f64, 0.25_f64);
        let got = g.eval(&[a], &move |l| match l {
            Leaf::Q(_) => t,
            Leaf::Qd(_) => w,
            Leaf::Qdd(_) => al,
            Leaf::Param(_) => rr,
        })[0];
        let want = -rr * w * w * t.cos() - rr * al * t.sin();
        assert!((got - want).abs() < 1e-14);
    }
}
