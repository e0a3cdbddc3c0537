//! The expression store: a hash-consed DAG of scalar expressions.
//!
//! Nodes live in a flat arena; a node's children always have smaller ids than
//! the node itself, so the arena order is a topological order. [`Graph::add`]
//! looks every node up before inserting it, so a structurally identical
//! subexpression exists exactly once. Differentiation therefore never blows up
//! exponentially, and common-subexpression elimination is a matter of counting
//! uses (see `cse.rs`).
//!
//! Vectors never reach this layer: lowering splits them into scalar components.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Index of a node in a [`Graph`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct Id(u32);

impl Id {
    /// Position of the node in the arena.
    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// The id of the node at arena position `i`.
    pub fn from_index(i: usize) -> Self {
        Id(u32::try_from(i).unwrap_or(u32::MAX))
    }
}

/// A symbol the generated code reads from its inputs.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub enum Leaf {
    /// Parameter `i` in declaration order (a link length, an offset angle).
    Param(u32),
    /// Coordinate q_j: drivers first, then unknowns, in declaration order.
    Q(u32),
    /// Its first time derivative q'_j.
    Qd(u32),
    /// Its second time derivative q''_j.
    Qdd(u32),
    /// The time t of a forward simulation (s): read only by the values
    /// of loads (`time` in `loads { … }`), never by the loops, points or
    /// frames, so the kinematics never differentiate it.
    Time,
}

/// Elementary functions of one argument.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Func {
    /// sin x.
    Sin,
    /// cos x.
    Cos,
    /// tan x.
    Tan,
    /// asin x, in [−π/2, π/2].
    Asin,
    /// acos x, in [0, π].
    Acos,
    /// √x.
    Sqrt,
    /// eˣ.
    Exp,
    /// ln x.
    Ln,
    /// |x|: used only for the term scales of the equations (`scale.rs`),
    /// which are evaluated, never differentiated.
    Abs,
}

impl Func {
    /// The function applied to a number.
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Sqrt => x.sqrt(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Abs => x.abs(),
        }
    }

    /// Name of the `f64` method that evaluates it.
    pub fn method(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Sqrt => "sqrt",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Abs => "abs",
        }
    }
}

/// One node of the DAG. Subtraction is `Add(a, Neg(b))`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Node {
    /// A constant, stored as the bits of an `f64` (never `-0.0`, never NaN).
    Const(u64),
    /// An input: a parameter, a coordinate or one of its rates.
    Leaf(Leaf),
    /// a + b.
    Add(Id, Id),
    /// a · b.
    Mul(Id, Id),
    /// a / b.
    Div(Id, Id),
    /// −a.
    Neg(Id),
    /// aⁿ for an integer n.
    Powi(Id, i32),
    /// f(a) for an elementary function f.
    Call(Func, Id),
    /// atan2(y, x), the angle of (x, y), in (−π, π].
    Atan2(Id, Id),
}

impl Node {
    /// Children in evaluation order.
    pub fn children(&self) -> impl Iterator<Item = Id> {
        let (a, b) = match *self {
            Node::Const(_) | Node::Leaf(_) => (None, None),
            Node::Neg(a) | Node::Powi(a, _) | Node::Call(_, a) => (Some(a), None),
            Node::Add(a, b) | Node::Mul(a, b) | Node::Div(a, b) | Node::Atan2(a, b) => {
                (Some(a), Some(b))
            }
        };
        a.into_iter().chain(b)
    }

    /// Whether the node costs a floating-point operation when evaluated.
    pub fn is_operation(&self) -> bool {
        !matches!(self, Node::Const(_) | Node::Leaf(_))
    }
}

/// The hasher of the compiler's tables, whose keys are nodes and ids (a
/// few small integers each): every word w is folded into the state h as
/// h ← (rotl₅(h) ⊕ w)·k with the odd constant k = 0x517c_c1b7_2722_0a95.
/// Several times cheaper than the standard library's keyed SipHash,
/// which took a fifth of the time of compiling a four-bar with its
/// sensitivities; not resistant to keys chosen to collide, which a
/// definition cannot make many of (its size bounds the table's).
#[derive(Clone, Copy, Default, Debug)]
pub struct FastHasher(u64);

impl FastHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

impl Hasher for FastHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }

    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }

    #[inline]
    fn write_u8(&mut self, i: u8) {
        self.add(u64::from(i));
    }

    #[inline]
    fn write_u16(&mut self, i: u16) {
        self.add(u64::from(i));
    }

    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }

    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }

    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
}

/// A hash map keyed by nodes or ids, hashed by [`FastHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<FastHasher>>;

/// The arena with its hash-consing table.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    table: FastMap<Node, Id>,
    /// When false, the algebraic rewrites of `simplify.rs` are skipped (used by
    /// tests to compare simplified against unsimplified graphs).
    pub raw: bool,
}

impl Graph {
    /// An empty graph with simplification enabled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of distinct nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the graph has no node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node at position `index` of the arena, if any.
    pub fn node_at(&self, index: usize) -> Option<Node> {
        self.nodes.get(index).copied()
    }

    /// The node behind an id.
    pub fn node(&self, id: Id) -> Node {
        self.nodes[id.index()]
    }

    /// Inserts a node as it is (after the children exist), or returns the
    /// existing identical node.
    pub fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.table.get(&node) {
            return id;
        }
        let id = Id(u32::try_from(self.nodes.len()).unwrap_or(u32::MAX));
        self.nodes.push(node);
        self.table.insert(node, id);
        id
    }

    /// The id of `node` if the graph holds it.
    pub fn find(&self, node: &Node) -> Option<Id> {
        self.table.get(node).copied()
    }

    /// The constant `value` (finite: callers fold only finite results).
    pub fn constant(&mut self, value: f64) -> Id {
        // Normalise -0.0 to 0.0 so that both hash to one node.
        let value = if value == 0.0 { 0.0 } else { value };
        self.intern(Node::Const(value.to_bits()))
    }

    /// The value of a constant node, if it is one.
    pub fn as_const(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    /// A leaf symbol.
    pub fn leaf(&mut self, leaf: Leaf) -> Id {
        self.intern(Node::Leaf(leaf))
    }

    /// Every node reachable from `roots`, as a mask over the arena.
    pub fn reachable(&self, roots: &[Id]) -> Vec<bool> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id.index()], true) {
                continue;
            }
            stack.extend(self.node(id).children());
        }
        seen
    }

    /// Evaluates `roots` with the leaves given by `leaf`; each node under
    /// them is computed once, in arena order. The cost is the size of the
    /// expressions, not of the arena (the closed forms and the scales ask
    /// this of every block and equation of a model of hundreds of loops).
    pub fn eval(&self, roots: &[Id], leaf: &dyn Fn(Leaf) -> f64) -> Vec<f64> {
        let mut order: Vec<Id> = Vec::new();
        let mut seen: FastMap<Id, f64> = FastMap::default();
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if seen.insert(id, 0.0).is_none() {
                order.push(id);
                stack.extend(self.node(id).children());
            }
        }
        // Children come before their parents in the arena.
        order.sort_unstable();
        for id in order {
            let v = |c: Id| seen.get(&c).copied().unwrap_or(f64::NAN);
            let value = match self.node(id) {
                Node::Const(bits) => f64::from_bits(bits),
                Node::Leaf(l) => leaf(l),
                Node::Add(a, b) => v(a) + v(b),
                Node::Mul(a, b) => v(a) * v(b),
                Node::Div(a, b) => v(a) / v(b),
                Node::Neg(a) => -v(a),
                Node::Powi(a, n) => v(a).powi(n),
                Node::Call(f, a) => f.apply(v(a)),
                Node::Atan2(y, x) => v(y).atan2(v(x)),
            };
            seen.insert(id, value);
        }
        roots
            .iter()
            .map(|r| seen.get(r).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// Number of operations in the expressions `roots` written as trees,
    /// without sharing (what a naive expansion would evaluate).
    pub fn tree_operations(&self, roots: &[Id]) -> u64 {
        let mut size = vec![0u64; self.nodes.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            let own = u64::from(node.is_operation());
            size[i] = node
                .children()
                .fold(own, |acc, c| acc.saturating_add(size[c.index()]));
        }
        roots
            .iter()
            .fold(0u64, |acc, r| acc.saturating_add(size[r.index()]))
    }

    /// Number of distinct operations needed for `roots` (with sharing).
    pub fn dag_operations(&self, roots: &[Id]) -> usize {
        let live = self.reachable(roots);
        self.nodes
            .iter()
            .enumerate()
            .filter(|(i, n)| live[*i] && n.is_operation())
            .count()
    }

    /// The leaves under `id`, each once, by a walk of the nodes under `id`
    /// only: its cost is the size of the expression, not of the arena
    /// (a model of hundreds of loops asks this of thousands of small
    /// expressions).
    pub fn leaves_under(&self, id: Id) -> impl Iterator<Item = Leaf> + '_ {
        let mut seen: std::collections::HashSet<Id, BuildHasherDefault<FastHasher>> =
            std::collections::HashSet::default();
        let mut stack = vec![id];
        core::iter::from_fn(move || {
            while let Some(i) = stack.pop() {
                if !seen.insert(i) {
                    continue;
                }
                match self.node(i) {
                    Node::Leaf(l) => return Some(l),
                    n => stack.extend(n.children()),
                }
            }
            None
        })
    }

    /// Whether `id` depends on a leaf for which `pred` holds (stopping at
    /// the first).
    pub fn depends_on(&self, id: Id, pred: &dyn Fn(Leaf) -> bool) -> bool {
        self.leaves_under(id).any(pred)
    }
}

/// Operation counts of a set of outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OpCount {
    /// Operations if every output were written as an expression tree.
    pub tree: u64,
    /// Operations after sharing (each distinct node evaluated once).
    pub shared: usize,
}

/// Counts operations of `roots` before and after elimination.
pub fn op_count(g: &Graph, roots: &[Id]) -> OpCount {
    OpCount {
        tree: g.tree_operations(roots),
        shared: g.dag_operations(roots),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::hash::BuildHasher;

    /// The table's hasher tells apart every pair of ids and every id
    /// along either of two leaves below 2¹⁶, and spreads them over the
    /// low bits the table indexes by (each of 4096 buckets used).
    #[test]
    fn fast_hasher_separates_small_keys() {
        let build = BuildHasherDefault::<FastHasher>::default();
        let mut hashes = std::collections::HashSet::new();
        let mut buckets = vec![false; 4096];
        for i in 0..1u32 << 16 {
            for key in [(Id(i), Leaf::Q(0)), (Id(i), Leaf::Q(1))] {
                let h = build.hash_one(key);
                assert!(hashes.insert(h), "a collision at {i}");
                buckets[(h % 4096) as usize] = true;
            }
        }
        assert!(buckets.iter().all(|&b| b));
    }

    #[test]
    fn identical_subexpressions_are_stored_once() {
        let mut g = Graph::new();
        let x = g.leaf(Leaf::Q(0));
        let s1 = g.call(Func::Sin, x);
        let s2 = g.call(Func::Sin, x);
        assert_eq!(s1, s2);
        let n = g.len();
        let a = g.mul(s1, x);
        let b = g.mul(s2, x);
        assert_eq!(a, b);
        assert_eq!(g.len(), n + 1);
    }

    #[test]
    fn sharing_makes_dag_smaller_than_tree() {
        let mut g = Graph::new();
        let x = g.leaf(Leaf::Q(0));
        let mut e = g.call(Func::Sin, x);
        for _ in 0..20 {
            e = g.mul(e, e);
        }
        assert_eq!(g.dag_operations(&[e]), 21);
        assert!(g.tree_operations(&[e]) > 1_000_000);
    }
}
