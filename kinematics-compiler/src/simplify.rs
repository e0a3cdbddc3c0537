//! Algebraic simplification, applied as each node is built.
//!
//! The rules are local and value-preserving for finite inputs: constant
//! folding, the neutral and absorbing elements of `+` and `·`, double
//! negation, sign extraction, and a canonical order for the operands of
//! commutative operations (so that `a·b` and `b·a` hash-cons to one node).
//! Together with hash-consing in [`Graph::intern`] this keeps the derivative
//! graphs small: d/dq of a term that does not contain q folds to `0` at once.

use crate::ir::{Func, Graph, Id, Node};

/// The constructors of the expression store, each applying the rewrites of
/// `rewrite` (unless the graph is `raw`), so that every node is built
/// simplified.
impl Graph {
    /// Adds a node after applying the simplification rules.
    pub fn add(&mut self, node: Node) -> Id {
        if self.raw {
            return self.intern(node);
        }
        rewrite(self, node)
    }

    /// a + b
    pub fn sum(&mut self, a: Id, b: Id) -> Id {
        self.add(Node::Add(a, b))
    }

    /// a − b
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        let nb = self.neg(b);
        self.sum(a, nb)
    }

    /// a · b
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        self.add(Node::Mul(a, b))
    }

    /// a / b
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        self.add(Node::Div(a, b))
    }

    /// −a
    pub fn neg(&mut self, a: Id) -> Id {
        self.add(Node::Neg(a))
    }

    /// a × b, component by component.
    pub fn cross3(&mut self, a: [Id; 3], b: [Id; 3]) -> [Id; 3] {
        let mut out = a;
        for (i, o) in out.iter_mut().enumerate() {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let l = self.mul(a[j], b[k]);
            let r = self.mul(a[k], b[j]);
            *o = self.sub(l, r);
        }
        out
    }

    /// aⁿ for an integer n.
    pub fn powi(&mut self, a: Id, n: i32) -> Id {
        self.add(Node::Powi(a, n))
    }

    /// f(a) for an elementary function f.
    pub fn call(&mut self, f: Func, a: Id) -> Id {
        self.add(Node::Call(f, a))
    }

    /// atan2(y, x)
    pub fn atan2(&mut self, y: Id, x: Id) -> Id {
        self.add(Node::Atan2(y, x))
    }
}

/// Builds `node` in `g`, simplified.
pub fn rewrite(g: &mut Graph, node: Node) -> Id {
    match node {
        Node::Add(a, b) => add(g, a, b),
        Node::Mul(a, b) => mul(g, a, b),
        Node::Div(a, b) => div(g, a, b),
        Node::Neg(a) => neg(g, a),
        Node::Powi(a, n) => powi(g, a, n),
        Node::Call(f, a) => call(g, f, a),
        Node::Atan2(y, x) => match (g.as_const(y), g.as_const(x)) {
            (Some(y), Some(x)) => fold(g, y.atan2(x)).unwrap_or_else(|| g.intern(node)),
            _ => g.intern(node),
        },
        Node::Const(_) | Node::Leaf(_) => g.intern(node),
    }
}

/// A folded constant, or `None` when folding would overflow to a
/// non-finite value (the operation is then kept, and evaluated at run time).
fn fold(g: &mut Graph, v: f64) -> Option<Id> {
    v.is_finite().then(|| g.constant(v))
}

fn ordered(a: Id, b: Id) -> (Id, Id) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

fn add(g: &mut Graph, a: Id, b: Id) -> Id {
    match (g.as_const(a), g.as_const(b)) {
        (Some(x), Some(y)) if (x + y).is_finite() => return g.constant(x + y),
        (Some(0.0), None) => return b,
        (None, Some(0.0)) => return a,
        _ => {}
    }
    // a + (−a) = 0
    if g.node(b) == Node::Neg(a) || g.node(a) == Node::Neg(b) {
        return g.constant(0.0);
    }
    // (−a) + (−b) = −(a + b)
    if let (Node::Neg(x), Node::Neg(y)) = (g.node(a), g.node(b)) {
        let s = add(g, x, y);
        return neg(g, s);
    }
    let (a, b) = ordered(a, b);
    g.intern(Node::Add(a, b))
}

fn mul(g: &mut Graph, a: Id, b: Id) -> Id {
    match (g.as_const(a), g.as_const(b)) {
        (Some(x), Some(y)) if (x * y).is_finite() => return g.constant(x * y),
        (Some(0.0), _) | (_, Some(0.0)) => return g.constant(0.0),
        (Some(1.0), None) => return b,
        (None, Some(1.0)) => return a,
        (Some(-1.0), None) => return neg(g, b),
        (None, Some(-1.0)) => return neg(g, a),
        _ => {}
    }
    // Pull signs out so that (−a)·b and a·(−b) share the node a·b.
    match (g.node(a), g.node(b)) {
        (Node::Neg(x), Node::Neg(y)) => return mul(g, x, y),
        (Node::Neg(x), _) => {
            let p = mul(g, x, b);
            return neg(g, p);
        }
        (_, Node::Neg(y)) => {
            let p = mul(g, a, y);
            return neg(g, p);
        }
        _ => {}
    }
    let (a, b) = ordered(a, b);
    g.intern(Node::Mul(a, b))
}

fn div(g: &mut Graph, a: Id, b: Id) -> Id {
    match (g.as_const(a), g.as_const(b)) {
        (Some(x), Some(y)) if (x / y).is_finite() => return g.constant(x / y),
        // 0 / b = 0, but for the number 0 itself (0 / 0 is undefined).
        (Some(0.0), y) if y != Some(0.0) => return g.constant(0.0),
        (None, Some(1.0)) => return a,
        (None, Some(-1.0)) => return neg(g, a),
        _ => {}
    }
    // x / x = 1, but for the number 0 (0 / 0 is undefined).
    if a == b && g.as_const(a) != Some(0.0) {
        return g.constant(1.0);
    }
    match (g.node(a), g.node(b)) {
        (Node::Neg(x), Node::Neg(y)) => div(g, x, y),
        (Node::Neg(x), _) => {
            let q = div(g, x, b);
            neg(g, q)
        }
        (_, Node::Neg(y)) => {
            let q = div(g, a, y);
            neg(g, q)
        }
        _ => g.intern(Node::Div(a, b)),
    }
}

fn neg(g: &mut Graph, a: Id) -> Id {
    if let Some(x) = g.as_const(a) {
        return g.constant(-x);
    }
    match g.node(a) {
        Node::Neg(x) => x,
        // −(x − y) = y − x
        Node::Add(x, y) => match (g.node(x), g.node(y)) {
            (_, Node::Neg(y)) => {
                let nx = neg(g, x);
                add(g, y, nx)
            }
            (Node::Neg(x), _) => {
                let ny = neg(g, y);
                add(g, x, ny)
            }
            _ => g.intern(Node::Neg(a)),
        },
        _ => g.intern(Node::Neg(a)),
    }
}

fn powi(g: &mut Graph, a: Id, n: i32) -> Id {
    if let Some(x) = g.as_const(a) {
        if let Some(c) = fold(g, x.powi(n)) {
            return c;
        }
    }
    match n {
        0 => g.constant(1.0),
        1 => a,
        _ => match g.node(a) {
            // (aᵐ)ⁿ = aᵐⁿ for integer exponents.
            Node::Powi(x, m) => match m.checked_mul(n) {
                Some(mn) => powi(g, x, mn),
                None => g.intern(Node::Powi(a, n)),
            },
            // (−a)ⁿ = ±aⁿ
            Node::Neg(x) => {
                let p = powi(g, x, n);
                if n % 2 == 0 {
                    p
                } else {
                    neg(g, p)
                }
            }
            _ => g.intern(Node::Powi(a, n)),
        },
    }
}

fn call(g: &mut Graph, f: Func, a: Id) -> Id {
    if let Some(x) = g.as_const(a) {
        let y = f.apply(x);
        if y.is_finite() {
            return g.constant(y);
        }
    }
    match (f, g.node(a)) {
        // Parity: sin(−x) = −sin x, cos(−x) = cos x, tan(−x) = −tan x.
        (Func::Sin | Func::Tan, Node::Neg(x)) => {
            let s = call(g, f, x);
            neg(g, s)
        }
        (Func::Cos, Node::Neg(x)) => call(g, f, x),
        _ => g.intern(Node::Call(f, a)),
    }
}

#[cfg(test)]
mod tests {
    use crate::ir::{Func, Graph, Id, Leaf};

    /// Builds the same expression with and without simplification and checks
    /// that both evaluate to the same numbers, and that simplification shrinks.
    fn compare(build: impl Fn(&mut Graph) -> Id) {
        let mut raw = Graph::new();
        raw.raw = true;
        let mut simp = Graph::new();
        let r = build(&mut raw);
        let s = build(&mut simp);
        for k in 0..25 {
            let k = f64::from(k);
            let env = move |l: Leaf| match l {
                Leaf::Q(i) => 0.3 + 0.17 * k + f64::from(i),
                Leaf::Param(i) => 1.1 + 0.05 * k * f64::from(i + 1),
                Leaf::Qd(i) | Leaf::Qdd(i) => -0.4 + 0.1 * k - f64::from(i),
                Leaf::Time => 0.25 * k,
            };
            let a = raw.eval(&[r], &env)[0];
            let b = simp.eval(&[s], &env)[0];
            assert!((a - b).abs() <= 1e-12 * (1.0 + a.abs()), "{a} vs {b}");
        }
        assert!(simp.dag_operations(&[s]) <= raw.dag_operations(&[r]));
    }

    #[test]
    fn constant_folding() {
        compare(|g| {
            let two = g.constant(2.0);
            let three = g.constant(3.0);
            let x = g.leaf(Leaf::Q(0));
            let s = g.sum(two, three);
            g.mul(s, x)
        });
    }

    #[test]
    fn neutral_and_absorbing_elements() {
        compare(|g| {
            let zero = g.constant(0.0);
            let one = g.constant(1.0);
            let x = g.leaf(Leaf::Q(0));
            let y = g.leaf(Leaf::Param(0));
            let a = g.mul(x, one);
            let b = g.mul(y, zero);
            let c = g.sum(a, b);
            g.div(c, one)
        });
    }

    #[test]
    fn signs_and_cancellation() {
        compare(|g| {
            let x = g.leaf(Leaf::Q(0));
            let y = g.leaf(Leaf::Q(1));
            let nx = g.neg(x);
            let nnx = g.neg(nx);
            let p = g.mul(nx, y);
            let q = g.mul(y, x);
            let d = g.sum(p, q); // −xy + yx = 0
            let s = g.call(Func::Sin, nnx);
            let c = g.call(Func::Cos, nx);
            let e = g.sum(d, s);
            g.sum(e, c)
        });
    }

    #[test]
    fn commutative_operands_share_a_node() {
        let mut g = Graph::new();
        let x = g.leaf(Leaf::Q(0));
        let y = g.leaf(Leaf::Q(1));
        assert_eq!(g.mul(x, y), g.mul(y, x));
        assert_eq!(g.sum(x, y), g.sum(y, x));
        let nx = g.neg(x);
        let a = g.mul(nx, y);
        let b = g.mul(y, x);
        assert_eq!(g.neg(b), a);
        let z = g.sub(x, x);
        assert_eq!(g.as_const(z), Some(0.0));
    }

    #[test]
    fn negated_difference_is_reversed() {
        let mut g = Graph::new();
        let x = g.leaf(Leaf::Q(0));
        let y = g.leaf(Leaf::Q(1));
        let d = g.sub(x, y);
        let n = g.neg(d);
        assert_eq!(n, g.sub(y, x));
        compare(|g| {
            let x = g.leaf(Leaf::Q(0));
            let y = g.leaf(Leaf::Param(0));
            let s = g.call(Func::Sin, x);
            let d = g.sub(s, y);
            let e = g.neg(d);
            let f = g.sub(e, x);
            g.neg(f)
        });
    }

    #[test]
    fn powers() {
        compare(|g| {
            let x = g.leaf(Leaf::Q(0));
            let nx = g.neg(x);
            let p = g.powi(nx, 3);
            let q = g.powi(p, 2);
            let r = g.powi(x, 1);
            let s = g.powi(x, 0);
            let t = g.sum(q, r);
            g.sum(t, s)
        });
    }
}
