//! Block-triangular form of the Jacobian Φ_u.
//!
//! A multi-loop mechanism is often solved loop by loop: a six-bar's first
//! loop fixes its own two angles, and the second loop then fixes the other
//! two. In Φ_u this shows as a block lower-triangular structure once rows and
//! columns are permuted: each diagonal block is one group of equations that
//! must be solved together, and it involves the unknowns of earlier blocks
//! only as known values. Factoring the diagonal blocks alone costs far less
//! than factoring the whole matrix (two 2×2 blocks against one 4×4 matrix),
//! and a linear solve becomes a forward substitution over the blocks.
//!
//! The blocks are the strongly connected components of the dependency graph
//! of a perfect matching between equations and unknowns, in an order where
//! each block comes after every block it depends on.

/// Which entries of Φ_u (`jac`, row by row) are not the constant 0.
pub fn nonzero(g: &crate::ir::Graph, jac: &[Vec<crate::ir::Id>]) -> Vec<Vec<bool>> {
    jac.iter()
        .map(|row| {
            row.iter()
                .map(|&id| !matches!(g.node(id), crate::ir::Node::Const(b) if f64::from_bits(b) == 0.0))
                .collect()
        })
        .collect()
}

/// One diagonal block: its equations (rows of Φ_u) and unknowns (columns),
/// each in ascending order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Block {
    pub rows: Vec<usize>,
    pub cols: Vec<usize>,
}

/// The diagonal blocks of a square pattern (`nonzero[i][j]`: equation i
/// involves unknown j), in solve order. A pattern without a perfect matching
/// (never the case after the structural checks) is one block.
pub fn block_triangular(nonzero: &[Vec<bool>]) -> Vec<Block> {
    let n = nonzero.len();
    let involves: Vec<Vec<usize>> = nonzero
        .iter()
        .map(|row| (0..n).filter(|&j| row.get(j) == Some(&true)).collect())
        .collect();
    let matching = maximum_matching(&involves, n);
    let Some(matched) = matching.iter().copied().collect::<Option<Vec<usize>>>() else {
        return vec![Block {
            rows: (0..n).collect(),
            cols: (0..n).collect(),
        }];
    };
    // Equation i, which the matching assigns to unknown matched[i], needs
    // the unknowns of every equation i' whose unknown it involves.
    let mut owner = vec![0; n];
    for (i, &k) in matched.iter().enumerate() {
        owner[k] = i;
    }
    let needs: Vec<Vec<usize>> = involves
        .iter()
        .enumerate()
        .map(|(i, ks)| ks.iter().map(|&k| owner[k]).filter(|&o| o != i).collect())
        .collect();
    strongly_connected(&needs)
        .into_iter()
        .map(|mut rows| {
            rows.sort_unstable();
            let mut cols: Vec<usize> = rows.iter().map(|&i| matched[i]).collect();
            cols.sort_unstable();
            Block { rows, cols }
        })
        .collect()
}

/// Tarjan's strongly connected components of the graph `edges`, each
/// component listed after every component its vertices have edges to.
fn strongly_connected(edges: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct State<'a> {
        edges: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(s: &mut State<'_>, v: usize) {
        s.index[v] = Some(s.next);
        s.low[v] = s.next;
        s.next += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for &w in &s.edges[v] {
            match s.index[w] {
                None => {
                    visit(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            s.out.push(component);
        }
    }
    let n = edges.len();
    let mut s = State {
        edges,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(&mut s, v);
        }
    }
    s.out
}

/// Maximum bipartite matching (augmenting paths): for each equation, the
/// unknown it is paired with.
pub fn maximum_matching(involves: &[Vec<usize>], unknowns: usize) -> Vec<Option<usize>> {
    fn augment(
        i: usize,
        involves: &[Vec<usize>],
        owner: &mut [Option<usize>],
        seen: &mut [bool],
    ) -> bool {
        for &k in &involves[i] {
            if seen[k] {
                continue;
            }
            seen[k] = true;
            let free = match owner[k] {
                None => true,
                Some(o) => augment(o, involves, owner, seen),
            };
            if free {
                owner[k] = Some(i);
                return true;
            }
        }
        false
    }
    let mut owner: Vec<Option<usize>> = vec![None; unknowns];
    for i in 0..involves.len() {
        let mut seen = vec![false; unknowns];
        augment(i, involves, &mut owner, &mut seen);
    }
    let mut matching = vec![None; involves.len()];
    for (k, o) in owner.iter().enumerate() {
        if let Some(i) = o {
            matching[*i] = Some(k);
        }
    }
    matching
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matching_finds_augmenting_paths() {
        // e0: {u0, u1}, e1: {u0}: e0 must give u0 up to e1.
        assert_eq!(
            maximum_matching(&[vec![0, 1], vec![0]], 2),
            vec![Some(1), Some(0)]
        );
        // e0: {u0}, e1: {u0}, e2: {u1, u2}: only two can be matched.
        let m = maximum_matching(&[vec![0], vec![0], vec![1, 2]], 3);
        assert_eq!(m.iter().filter(|x| x.is_some()).count(), 2);
    }

    fn pattern(rows: &[&[usize]], n: usize) -> Vec<Vec<bool>> {
        rows.iter()
            .map(|r| (0..n).map(|j| r.contains(&j)).collect())
            .collect()
    }

    #[test]
    fn six_bar_splits_into_its_two_loops() {
        // Unknowns θ3, θ4, θ5, θ6; loop 1 (rows 0, 1) involves θ3, θ4; loop 2
        // (rows 2, 3) involves θ4, θ5, θ6.
        let p = pattern(&[&[0, 1], &[0, 1], &[1, 2, 3], &[1, 2, 3]], 4);
        let blocks = block_triangular(&p);
        assert_eq!(
            blocks,
            vec![
                Block {
                    rows: vec![0, 1],
                    cols: vec![0, 1]
                },
                Block {
                    rows: vec![2, 3],
                    cols: vec![2, 3]
                },
            ]
        );
    }

    #[test]
    fn order_follows_dependencies_not_declaration() {
        // Loop 2 declared first: rows 0, 1 involve unknowns 0..3; rows 2, 3
        // only unknowns 2, 3, so they come first.
        let p = pattern(&[&[0, 1, 2], &[0, 1, 3], &[2, 3], &[2, 3]], 4);
        let blocks = block_triangular(&p);
        assert_eq!(blocks.len(), 2);
        assert_eq!(blocks[0].rows, vec![2, 3]);
        assert_eq!(blocks[0].cols, vec![2, 3]);
        assert_eq!(blocks[1].rows, vec![0, 1]);
        assert_eq!(blocks[1].cols, vec![0, 1]);
    }

    #[test]
    fn coupled_and_triangular_extremes() {
        let full = pattern(&[&[0, 1, 2], &[0, 1, 2], &[0, 1, 2]], 3);
        assert_eq!(block_triangular(&full).len(), 1);
        // Lower triangular: three 1×1 blocks, in order.
        let lower = pattern(&[&[0], &[0, 1], &[0, 1, 2]], 3);
        let blocks = block_triangular(&lower);
        let cols: Vec<Vec<usize>> = blocks.iter().map(|b| b.cols.clone()).collect();
        assert_eq!(cols, vec![vec![0], vec![1], vec![2]]);
        assert!(block_triangular(&[]).is_empty());
    }

    #[test]
    fn every_block_uses_only_itself_and_earlier_blocks() {
        // Random sparse patterns with a guaranteed diagonal, from a fixed
        // seed: the permuted matrix must be block lower triangular.
        let mut rng = fastrand::Rng::with_seed(0x9e37_79b9_7f4a_7c15);
        for _ in 0..500 {
            let n = rng.usize(1..8);
            let p: Vec<Vec<bool>> = (0..n)
                .map(|i| (0..n).map(|j| i == j || rng.usize(..4) == 0).collect())
                .collect();
            let blocks = block_triangular(&p);
            let mut block_of_col = vec![usize::MAX; n];
            let mut rows_seen = vec![false; n];
            for (b, block) in blocks.iter().enumerate() {
                assert_eq!(block.rows.len(), block.cols.len());
                for &c in &block.cols {
                    block_of_col[c] = b;
                }
                for &r in &block.rows {
                    rows_seen[r] = true;
                }
            }
            assert!(rows_seen.iter().all(|&s| s), "every row in a block");
            assert!(block_of_col.iter().all(|&b| b != usize::MAX));
            for (b, block) in blocks.iter().enumerate() {
                for &r in &block.rows {
                    for j in 0..n {
                        if p[r][j] {
                            assert!(block_of_col[j] <= b, "row {r} uses a later block: {p:?}");
                        }
                    }
                }
            }
        }
    }
}
