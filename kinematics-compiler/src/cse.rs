//! Common-subexpression elimination and scheduling.
//!
//! The DAG is already hash-consed, so every shared subexpression is one node.
//! This pass decides which nodes the emitted code binds with `let` (those
//! used more than once) and which it writes inline (those used once), and
//! orders the bindings: a function evaluates its outputs in stages (for
//! example the Jacobian before a linear solve, the acceleration terms after),
//! and each binding goes in the first stage that needs it, in arena order,
//! which is a topological order.

use crate::ir::{Graph, Id};

/// Which nodes to bind, and where.
pub struct Schedule {
    /// `bound[i]`: node i gets a `let`.
    pub bound: Vec<bool>,
    /// The bound nodes of each stage, in evaluation order.
    pub stages: Vec<Vec<Id>>,
    /// The stage each live node is evaluated in (the first whose outputs
    /// need it).
    pub stage_of: Vec<Option<usize>>,
}

/// Schedules the evaluation of `stages` (each a list of output roots).
pub fn schedule(g: &Graph, stages: &[Vec<Id>]) -> Schedule {
    let all: Vec<Id> = stages.iter().flatten().copied().collect();
    let live = g.reachable(&all);
    let mut uses = vec![0u32; g.len()];
    for (i, _) in live.iter().enumerate().filter(|(_, l)| **l) {
        {
            for c in g.node(Id::from_index(i)).children() {
                uses[c.index()] += 1;
            }
        }
    }
    for r in &all {
        uses[r.index()] += 1;
    }
    let bound: Vec<bool> = (0..g.len())
        .map(|i| live[i] && uses[i] >= 2 && g.node(Id::from_index(i)).is_operation())
        .collect();
    let mut stage_of = vec![None; g.len()];
    let mut out = Vec::new();
    for (s, roots) in stages.iter().enumerate() {
        let cone = g.reachable(roots);
        let mut lets = Vec::new();
        for i in 0..g.len() {
            if cone[i] && stage_of[i].is_none() {
                stage_of[i] = Some(s);
                if bound[i] {
                    lets.push(Id::from_index(i));
                }
            }
        }
        out.push(lets);
    }
    Schedule {
        bound,
        stages: out,
        stage_of,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Func, Leaf};

    #[test]
    fn shared_nodes_are_bound_once_in_their_first_stage() {
        let mut g = Graph::new();
        let x = g.leaf(Leaf::Q(0));
        let s = g.call(Func::Sin, x);
        let c = g.call(Func::Cos, x);
        let a = g.mul(s, c); // stage 0
        let b = g.sum(s, a); // stage 1, uses s and a again
        let sched = schedule(&g, &[vec![a], vec![b]]);
        assert_eq!(sched.stages[0], vec![s, a]);
        assert!(sched.stages[1].is_empty());
        assert!(!sched.bound[c.index()], "cos x is used once and inlined");
    }
}
