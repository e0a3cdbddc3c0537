//! What the Newton iteration of `step` evaluates where: the driver-only
//! values hoisted out of the loop, the sines and cosines carried between
//! iterates, and the values kept for the analysis.

use crate::cse::Schedule;
use crate::ir::{Func, Graph, Id, Leaf, Node};

/// The driver-only nodes of the Newton cone that the unknown-dependent part
/// (or the output list itself) uses: evaluated once before the iteration.
pub(super) fn driver_frontier(g: &Graph, roots: &[Id], drivers: u32) -> Vec<Id> {
    frontier(g, roots, &|j| j >= drivers)
}

/// The nodes free of the coordinates `moving` selects that the rest of the
/// cone of `roots` (or the list itself) uses: what an iteration over those
/// coordinates evaluates once, before it.
pub(super) fn frontier(g: &Graph, roots: &[Id], moving: &dyn Fn(u32) -> bool) -> Vec<Id> {
    let live = g.reachable(roots);
    let mut dep = vec![false; g.len()];
    for i in 0..g.len() {
        let node = g.node(Id::from_index(i));
        dep[i] = match node {
            Node::Leaf(Leaf::Q(j)) => moving(j),
            _ => node.children().any(|c| dep[c.index()]),
        };
    }
    let mut frontier = vec![false; g.len()];
    for i in 0..g.len() {
        if live[i] && dep[i] {
            for c in g.node(Id::from_index(i)).children() {
                frontier[c.index()] |= !dep[c.index()];
            }
        }
    }
    for r in roots {
        frontier[r.index()] |= !dep[r.index()];
    }
    (0..g.len())
        .filter(|&i| frontier[i] && g.node(Id::from_index(i)).is_operation())
        .map(Id::from_index)
        .collect()
}

/// A sine or cosine argument that moves with one unknown: the unknown u_k
/// itself, or u_k plus an expression free of unknowns (an offset angle, a
/// driver), evaluated before the iteration's other values.
pub(super) struct TrigArg {
    /// The argument node.
    pub(super) arg: Id,
    /// Its sine and cosine nodes, either possibly absent.
    pub(super) sin: Option<Id>,
    pub(super) cos: Option<Id>,
}

/// The sines and cosines among the nodes reachable from `roots` whose
/// arguments move with one unknown ([`TrigArg`]), in arena order.
pub(super) fn unknown_trig(g: &Graph, roots: &[Id], drivers: u32) -> Vec<TrigArg> {
    let unknown_of = |id: Id| match g.node(id) {
        Node::Leaf(Leaf::Q(j)) if j >= drivers => Some((j - drivers) as usize),
        _ => None,
    };
    let free = |id: Id| !g.depends_on(id, &|l| matches!(l, Leaf::Q(j) if j >= drivers));
    let live = g.reachable(roots);
    let mut out: Vec<TrigArg> = Vec::new();
    for (i, &is_live) in live.iter().enumerate() {
        let id = Id::from_index(i);
        let Node::Call(f @ (Func::Sin | Func::Cos), a) = g.node(id) else {
            continue;
        };
        let moves = match g.node(a) {
            Node::Leaf(_) => unknown_of(a),
            Node::Add(x, y) => match (unknown_of(x), unknown_of(y)) {
                (Some(k), None) if free(y) => Some(k),
                (None, Some(k)) if free(x) => Some(k),
                _ => None,
            },
            _ => None,
        };
        if moves.is_none() || !is_live {
            continue;
        }
        let at = match out.iter().position(|e| e.arg == a) {
            Some(at) => at,
            None => {
                out.push(TrigArg {
                    arg: a,
                    sin: None,
                    cos: None,
                });
                out.len() - 1
            }
        };
        if f == Func::Sin {
            out[at].sin = Some(id);
        } else {
            out[at].cos = Some(id);
        }
    }
    out
}

/// The bound nodes of stage `stage` that a later stage uses (as an operand
/// or as an output): these are carried out of the stage's evaluation.
pub(super) fn used_later(
    g: &Graph,
    sched: &Schedule,
    stage: usize,
    _own: &[Id],
    later: &[&Vec<Id>],
) -> Vec<Id> {
    let mut keep = vec![false; g.len()];
    let in_stage = |i: usize| sched.stage_of[i] == Some(stage) && sched.bound[i];
    for i in 0..g.len() {
        if sched.stage_of[i].is_some_and(|s| s > stage) {
            for c in g.node(Id::from_index(i)).children() {
                if in_stage(c.index()) {
                    keep[c.index()] = true;
                }
            }
        }
    }
    for roots in later {
        for r in roots.iter() {
            if in_stage(r.index()) {
                keep[r.index()] = true;
            }
        }
    }
    (0..g.len())
        .filter(|&i| keep[i])
        .map(Id::from_index)
        .collect()
}
