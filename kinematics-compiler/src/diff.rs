//! Exact differentiation on the DAG.
//!
//! [`partial`] gives ∂e/∂x for a leaf x and [`time_derivative`] gives de/dt,
//! both by forward differentiation: the chain rule applied once to each node
//! reachable from `e`, in arena (topological) order, so the cost is linear in
//! the size of the DAG. For de/dt each coordinate leaf q_j is seeded with its
//! rate q'_j, and each rate q'_j with its acceleration q''_j (or with zero,
//! which is how the right-hand sides of the velocity and acceleration
//! equations are formed), so that de/dt = Σ_j ∂e/∂q_j · q'_j + Σ_j ∂e/∂q'_j ·
//! q''_j comes out of one pass rather than one pass per coordinate: the
//! velocity of a point at the end of a six-joint chain then costs a few
//! times its position, not six times.

use std::collections::HashSet;

use crate::ir::{Func, Graph, Id, Leaf, Node};

/// Which rates q'_j carry an acceleration q''_j in a time derivative.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Accelerating {
    /// None: q''_j is taken as zero for every j.
    None,
    /// Every coordinate.
    All,
    /// The first n coordinates (the drivers).
    First(u32),
}

/// A direction of differentiation.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Along {
    /// ∂/∂x for a leaf x.
    Leaf(Leaf),
    /// d/dt.
    Time(Accelerating),
}

/// Memo of derivatives, shared across roots and directions.
pub type Memo = crate::ir::FastMap<(Id, Along), Id>;

/// ∂root/∂wrt.
pub fn partial(g: &mut Graph, root: Id, wrt: Leaf, memo: &mut Memo) -> Id {
    derivative(g, root, Along::Leaf(wrt), memo)
}

/// d(root)/dt, where coordinate j has q_j, q'_j, q''_j as leaves and only
/// the rates picked by `accelerating` carry their q''_j terms.
pub fn time_derivative(g: &mut Graph, root: Id, accelerating: Accelerating, memo: &mut Memo) -> Id {
    derivative(g, root, Along::Time(accelerating), memo)
}

/// d(root)/dt as Σ_j ∂root/∂q_j · q'_j (+ Σ_j ∂root/∂q'_j · q''_j for the
/// rates picked by `accelerating`), over the first `coords` coordinates:
/// the same value as [`time_derivative`] for a root that does not read
/// the time ([`Leaf::Time`], which only loads read), built from the
/// partial derivatives. Where those partials are needed anyway (Φ_u for the loop
/// equations), this form shares them and comes out smaller.
pub fn time_derivative_by_partials(
    g: &mut Graph,
    root: Id,
    coords: u32,
    accelerating: Accelerating,
    memo: &mut Memo,
) -> Id {
    let mut total = g.constant(0.0);
    // Only the coordinates `root` involves have nonzero partials: the
    // others are skipped rather than differentiated to zero (a loop of a
    // chain involves a few of its hundreds of coordinates).
    let mut involved: Vec<u32> = g
        .leaves_under(root)
        .filter_map(|l| match l {
            Leaf::Q(j) | Leaf::Qd(j) if j < coords => Some(j),
            _ => None,
        })
        .collect();
    // In the order of the coordinates, as the sum has always been formed.
    involved.sort_unstable();
    involved.dedup();
    for j in involved {
        let dq = partial(g, root, Leaf::Q(j), memo);
        let qd = g.leaf(Leaf::Qd(j));
        let t = g.mul(dq, qd);
        total = g.sum(total, t);
        let carries = match accelerating {
            Accelerating::None => false,
            Accelerating::All => true,
            Accelerating::First(n) => j < n,
        };
        if carries {
            let dqd = partial(g, root, Leaf::Qd(j), memo);
            let qdd = g.leaf(Leaf::Qdd(j));
            let t = g.mul(dqd, qdd);
            total = g.sum(total, t);
        }
    }
    total
}

/// The derivative of a leaf along `along`.
fn seed(g: &mut Graph, l: Leaf, along: Along) -> Id {
    match along {
        Along::Leaf(wrt) => g.constant(if l == wrt { 1.0 } else { 0.0 }),
        Along::Time(acc) => match l {
            Leaf::Q(j) => g.leaf(Leaf::Qd(j)),
            Leaf::Qd(j) => {
                let carries = match acc {
                    Accelerating::None => false,
                    Accelerating::All => true,
                    Accelerating::First(n) => j < n,
                };
                if carries {
                    g.leaf(Leaf::Qdd(j))
                } else {
                    g.constant(0.0)
                }
            }
            Leaf::Param(_) | Leaf::Qdd(_) => g.constant(0.0),
            Leaf::Time => g.constant(1.0),
        },
    }
}

/// The derivative of `root` along `along`, by forward differentiation.
fn derivative(g: &mut Graph, root: Id, along: Along, memo: &mut Memo) -> Id {
    if let Some(&d) = memo.get(&(root, along)) {
        return d;
    }
    // The nodes under `root` whose derivative along `along` is not known
    // yet, found without descending below a known one: the work is the
    // size of the new part of the DAG, not of the whole arena (a Jacobian
    // of a chain of n loops asks for n² derivatives of small expressions).
    let mut order = Vec::new();
    let mut seen: HashSet<Id, std::hash::BuildHasherDefault<crate::ir::FastHasher>> =
        HashSet::default();
    let mut stack = vec![root];
    while let Some(id) = stack.pop() {
        if memo.contains_key(&(id, along)) || !seen.insert(id) {
            continue;
        }
        order.push(id);
        stack.extend(g.node(id).children());
    }
    // Children come before their parents in the arena.
    order.sort_unstable();
    let zero = g.constant(0.0);
    for id in order {
        let d = |memo: &Memo, c: Id| memo.get(&(c, along)).copied().unwrap_or(zero);
        let node = g.node(id);
        let result = match node {
            Node::Const(_) => zero,
            Node::Leaf(l) => seed(g, l, along),
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
                // aⁿ⁻¹, or aⁿ / a where n − 1 is past i32's range (n
                // = i32::MIN, from folded powers of powers).
                let p = match n.checked_sub(1) {
                    Some(m) => g.powi(a, m),
                    None => g.div(id, a),
                };
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
        memo.insert((id, along), result);
    }
    memo.get(&(root, along)).copied().unwrap_or(zero)
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
        // d|a|/da = a/|a| (away from 0).
        Func::Abs => g.div(a, value),
    }
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
        let mut memo = Memo::default();
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
        let mut memo = Memo::default();
        let v = time_derivative(&mut g, x, Accelerating::All, &mut memo);
        let a = time_derivative(&mut g, v, Accelerating::All, &mut memo);
        let (t, w, al, rr) = (0.7_f64, 3.0_f64, -2.0_f64, 0.25_f64);
        let got = g.eval(&[a], &move |l| match l {
            Leaf::Q(_) => t,
            Leaf::Qd(_) => w,
            Leaf::Qdd(_) => al,
            Leaf::Param(_) | Leaf::Time => rr,
        })[0];
        let want = -rr * w * w * t.cos() - rr * al * t.sin();
        assert!((got - want).abs() < 1e-14);
    }
}
