//! What a stepper computes once instead of at every step: the
//! expressions of the parameters alone that a step needs (the loop
//! invariants of a simulation, as a generated stepper's `__param_trig`
//! holds the sines and cosines of parameter angles), and the sine and
//! cosine of a coordinate plus a parameter expression, sin(q + k) and
//! cos(q + k), rewritten by the addition theorem as
//! sin q cos k + cos q sin k and cos q cos k − sin q sin k, so that a step
//! reads the cosine and sine of q it already has and those of k, computed
//! once.

use alloc::vec;
use alloc::vec::Vec;

use kinematics_compiler::ir::{Func, Graph, Id, Leaf, Node};

/// A graph rewritten for a step, and what its stepper computes once.
pub(super) struct Hoisted {
    /// The graph with the rewritten nodes added.
    pub(super) graph: Graph,
    /// The new node of each node of the original graph (by index).
    map: Vec<Id>,
    /// The expressions of the parameters alone that the roots need, each
    /// used by an expression of the coordinates (or a root itself).
    pub(super) invariants: Vec<Id>,
    /// The k of each sin(q + k) or cos(q + k) rewritten.
    pub(super) offsets: Vec<Id>,
}

impl Hoisted {
    /// The node of the rewritten graph for `id` of the original.
    pub(super) fn map(&self, id: Id) -> Id {
        self.map.get(id.index()).copied().unwrap_or(id)
    }

    /// The coordinates below `below` whose cosine or sine the rewritten
    /// graph reads for the original roots `roots`, ascending.
    pub(super) fn trig_read(&self, roots: &[Id], below: usize) -> Vec<usize> {
        let live = self.graph.reachable(&self.map_all(roots));
        let mut read: Vec<usize> = (0..self.graph.len())
            .filter(|&i| live[i])
            .filter_map(|i| match self.graph.node(Id::from_index(i)) {
                Node::Call(Func::Sin | Func::Cos, x) => match self.graph.node(x) {
                    Node::Leaf(Leaf::Q(j)) if (j as usize) < below => Some(j as usize),
                    _ => None,
                },
                _ => None,
            })
            .collect();
        read.sort_unstable();
        read.dedup();
        read
    }

    /// [`Hoisted::map`] of each of `ids`.
    pub(super) fn map_all(&self, ids: &[Id]) -> Vec<Id> {
        ids.iter().map(|&id| self.map(id)).collect()
    }
}

/// Whether each node depends on the parameters alone (not on a
/// coordinate, a rate, an acceleration, nor the parameter `varying`,
/// the characteristic length, which a stepper may change), by index.
fn parameter_only(g: &Graph, varying: u32) -> Vec<bool> {
    let mut only = vec![false; g.len()];
    for i in 0..g.len() {
        let node = g.node(Id::from_index(i));
        only[i] = match node {
            Node::Const(_) => true,
            Node::Leaf(Leaf::Param(j)) => j != varying,
            Node::Leaf(_) => false,
            _ => node.children().all(|c| only[c.index()]),
        };
    }
    only
}

/// Rewrites `g` for the roots `roots` and finds what to compute once.
/// `params` counts the parameters with the characteristic length, the
/// last; `coords` the coordinates.
pub(super) fn hoist(g: &Graph, params: usize, coords: usize, roots: &[Id]) -> Hoisted {
    let varying = u32::try_from(params.saturating_sub(1)).unwrap_or(u32::MAX);
    let original = g.len();
    let only = parameter_only(g, varying);
    let live = g.reachable(roots);
    let mut graph = g.clone();
    let mut map: Vec<Id> = Vec::with_capacity(original);
    let mut offsets: Vec<Id> = Vec::new();
    let coordinate =
        |g: &Graph, id: Id| matches!(g.node(id), Node::Leaf(Leaf::Q(j)) if (j as usize) < coords);
    for (i, &alive) in live.iter().enumerate().take(original) {
        let id = Id::from_index(i);
        let node = g.node(id);
        let m = |c: Id| map[c.index()];
        let rewritten = match node {
            Node::Call(f @ (Func::Sin | Func::Cos), x) if alive => match g.node(x) {
                Node::Add(a, b) if coordinate(g, a) && only[b.index()] => Some((f, a, b)),
                Node::Add(a, b) if coordinate(g, b) && only[a.index()] => Some((f, b, a)),
                _ => None,
            },
            _ => None,
        };
        let new = match rewritten {
            Some((f, q, k)) => {
                let (q, k) = (m(q), m(k));
                let sq = graph.intern(Node::Call(Func::Sin, q));
                let cq = graph.intern(Node::Call(Func::Cos, q));
                let sk = graph.intern(Node::Call(Func::Sin, k));
                let ck = graph.intern(Node::Call(Func::Cos, k));
                if !offsets.contains(&k) {
                    offsets.push(k);
                }
                if f == Func::Sin {
                    let x = graph.intern(Node::Mul(sq, ck));
                    let y = graph.intern(Node::Mul(cq, sk));
                    graph.intern(Node::Add(x, y))
                } else {
                    let x = graph.intern(Node::Mul(cq, ck));
                    let y = graph.intern(Node::Mul(sq, sk));
                    let y = graph.intern(Node::Neg(y));
                    graph.intern(Node::Add(x, y))
                }
            }
            None => {
                let node = match node {
                    Node::Add(a, b) => Node::Add(m(a), m(b)),
                    Node::Mul(a, b) => Node::Mul(m(a), m(b)),
                    Node::Div(a, b) => Node::Div(m(a), m(b)),
                    Node::Atan2(a, b) => Node::Atan2(m(a), m(b)),
                    Node::Neg(a) => Node::Neg(m(a)),
                    Node::Powi(a, n) => Node::Powi(m(a), n),
                    Node::Call(f, a) => Node::Call(f, m(a)),
                    other => other,
                };
                graph.intern(node)
            }
        };
        map.push(new);
    }
    let new_roots: Vec<Id> = roots.iter().map(|r| map[r.index()]).collect();
    let only = parameter_only(&graph, varying);
    let live = graph.reachable(&new_roots);
    // The parameter expressions used by a coordinate expression, or roots.
    let mut used = vec![false; graph.len()];
    for i in 0..graph.len() {
        if live[i] && !only[i] {
            for c in graph.node(Id::from_index(i)).children() {
                used[c.index()] = true;
            }
        }
    }
    for r in &new_roots {
        used[r.index()] = true;
    }
    let invariants = (0..graph.len())
        .filter(|&i| live[i] && only[i] && used[i])
        .map(Id::from_index)
        .filter(|&id| graph.node(id).is_operation())
        .collect();
    Hoisted {
        graph,
        map,
        invariants,
        offsets,
    }
}
