//! Linear algebra in the generated code: the block-triangular solves with
//! Φ_u, the singularity and branch checks at a solution, and the scaling of
//! the equations and unknowns.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::Ident;

use super::print::bind;
use crate::blocks::{block_triangular, Block};
use crate::cse::schedule;
use crate::ir::{Graph, Id, Leaf};
use crate::scale::Scales;

/// Linear solves with Φ_u through its block-triangular form ([`blocks`]):
/// each diagonal block of the scaled matrix Φ̃_u = diag(1/S) Φ_u diag(unit)
/// (the local `__scaling`, see `kinematics_core::solve::Scaling`) factored
/// on its own, then forward substitution over the blocks. The matrix is the
/// local `jac`, which holds only the structurally nonzero entries of Φ_u,
/// row by row (so that a large sparse mechanism keeps no N×N array); the
/// factors are `__lu_0`, ….
pub(super) struct BlockSolve {
    blocks: Vec<Block>,
    /// The index in `jac` of each nonzero entry (r, c).
    slot: Vec<Vec<Option<usize>>>,
    /// (r, c) of each entry of `jac`, in order.
    entries: Vec<(usize, usize)>,
    /// Whether each unknown is a length (its column scale is L, not 1).
    is_length: Vec<bool>,
    nu: usize,
}

impl BlockSolve {
    pub(super) fn new(g: &Graph, jac: &[Vec<Id>], is_length: &[bool]) -> Self {
        let nonzero = crate::blocks::nonzero(g, jac);
        let mut entries = Vec::new();
        let slot = nonzero
            .iter()
            .enumerate()
            .map(|(r, row)| {
                row.iter()
                    .enumerate()
                    .map(|(c, &nz)| {
                        nz.then(|| {
                            entries.push((r, c));
                            entries.len() - 1
                        })
                    })
                    .collect()
            })
            .collect();
        BlockSolve {
            blocks: block_triangular(&nonzero),
            nu: jac.len(),
            is_length: is_length.to_vec(),
            slot,
            entries,
        }
    }

    /// The number of entries of `jac`.
    pub(super) fn nnz(&self) -> usize {
        self.entries.len()
    }

    /// The array expression of the nonzero entries of Φ_u, from the full
    /// matrix of printed entries `full`.
    pub(super) fn array(&self, full: &[Vec<TokenStream>]) -> TokenStream {
        let e = self.entries.iter().map(|&(r, c)| &full[r][c]);
        quote!([#(#e),*])
    }

    fn lu(b: usize) -> Ident {
        format_ident!("__lu_{}", b)
    }

    /// The scaled entry Φ̃_u[r][c] (the column scale only for lengths: an
    /// angle's is 1), or the entry itself when not `scaled`.
    fn entry(&self, r: usize, c: usize, scaled: bool) -> TokenStream {
        let Some(k) = self.slot[r][c] else {
            return quote!(0.0f64);
        };
        if !scaled {
            quote!(jac[#k])
        } else if self.is_length[c] {
            quote!((jac[#k] * (__scaling.row[#r] * __scaling.col[#c])))
        } else {
            quote!((jac[#k] * __scaling.row[#r]))
        }
    }

    /// Binds the factors of the diagonal blocks; `on_fail(f)` is the
    /// statement run with `f`, the failure (its unknown made global), when
    /// a pivot of a block is at or below the singularity threshold. With
    /// `scaled` false (Newton's inline iteration, whose step does not
    /// depend on the scaling) the blocks of Φ_u itself are factored, and
    /// only a zero or non-finite pivot fails: the singularity of the
    /// solution is judged once, at the end, on the scaled matrix.
    pub(super) fn factor(
        &self,
        pp: &TokenStream,
        scaled: bool,
        on_fail: &dyn Fn(TokenStream) -> TokenStream,
    ) -> TokenStream {
        let threshold = if scaled {
            quote!(options.singularity_threshold)
        } else {
            quote!(0.0)
        };
        let mut code = TokenStream::new();
        for (b, block) in self.blocks.iter().enumerate() {
            let lu = Self::lu(b);
            let n = block.rows.len();
            let rows = block.rows.iter().map(|&r| {
                let entries = block.cols.iter().map(|&c| self.entry(r, c, scaled));
                quote!([#(#entries),*])
            });
            let cols = &block.cols;
            let fail = on_fail(quote!(f.in_block(&[#(#cols),*])));
            code.extend(quote! {
                let #lu = match #pp::Lu::<#n>::factor(&[#(#rows),*], #threshold) {
                    ::core::result::Result::Ok(lu) => lu,
                    ::core::result::Result::Err(f) => { #fail }
                };
            });
        }
        code
    }

    /// After [`BlockSolve::factor`] at a solution: binds `__conditioning`,
    /// the smallest conditioning of the blocks, and `__det_sign`, the sign
    /// of det Φ_u, running `on_fail(f)` when a conditioning is at or below
    /// the singularity threshold or when the sign is not the branch asked
    /// for.
    pub(super) fn check(
        &self,
        pp: &TokenStream,
        on_fail: &dyn Fn(TokenStream) -> TokenStream,
    ) -> TokenStream {
        let mut code = quote!(let mut __conditioning = 1.0f64;);
        let mut signs = Vec::new();
        for (b, block) in self.blocks.iter().enumerate() {
            let lu = Self::lu(b);
            let cols = &block.cols;
            let fail = on_fail(quote!(f.in_block(&[#(#cols),*])));
            code.extend(quote! {
                match #lu.check(options.singularity_threshold) {
                    ::core::result::Result::Ok(c) => {
                        if c < __conditioning {
                            __conditioning = c;
                        }
                    }
                    ::core::result::Result::Err(f) => { #fail }
                }
            });
            signs.push(quote!(#lu.det_sign()));
        }
        let fail = on_fail(quote!(f));
        // det Φ_u = sign(row order) sign(column order) Π det(block): the
        // blocks list the rows and columns in a permuted order.
        let rows: Vec<usize> = self.blocks.iter().flat_map(|b| b.rows.clone()).collect();
        let cols: Vec<usize> = self.blocks.iter().flat_map(|b| b.cols.clone()).collect();
        let odd = parity(&rows) != parity(&cols);
        let product = super::print::chain(&signs, &quote!(*));
        let sign = match signs.len() {
            0 => quote!(1.0f64),
            _ if odd => quote!(-(#product)),
            _ => product,
        };
        code.extend(quote! {
            let __det_sign: f64 = #sign;
            if let ::core::result::Result::Err(f) = #pp::branch_check(__det_sign, options) {
                #fail
            }
        });
        code
    }

    /// An expression for x with Φ_u x = `rhs`, after [`BlockSolve::factor`]
    /// with the same `scaled`: block by block, Φ̃_bb y = diag(1/S_b)(rhs_b −
    /// Φ_u,b,done x_done), x_b = diag(unit_b) y (or without the scales).
    pub(super) fn solve(&self, rhs: &TokenStream, scaled: bool) -> TokenStream {
        let nu = self.nu;
        let mut done: Vec<usize> = Vec::new();
        let mut steps = TokenStream::new();
        for (b, block) in self.blocks.iter().enumerate() {
            let lu = Self::lu(b);
            let entries = block.rows.iter().map(|&r| {
                let known: Vec<TokenStream> = done
                    .iter()
                    .filter_map(|&c| self.slot[r][c].map(|k| quote!(jac[#k] * __x[#c])))
                    .collect();
                if known.is_empty() && !scaled {
                    quote!(__rhs[#r])
                } else if known.is_empty() {
                    quote!((__rhs[#r] * __scaling.row[#r]))
                } else if !scaled {
                    let known = super::print::chain(&known, &quote!(+));
                    quote!((__rhs[#r] - (#known)))
                } else {
                    // Parenthesised, as every array element that is an
                    // operation (see `Printer::element`).
                    let known = super::print::chain(&known, &quote!(+));
                    quote!(((__rhs[#r] - (#known)) * __scaling.row[#r]))
                }
            });
            let store = block.cols.iter().enumerate().map(|(slot, &c)| {
                if scaled && self.is_length[c] {
                    quote!(__x[#c] = __y[#slot] * __scaling.col[#c];)
                } else {
                    quote!(__x[#c] = __y[#slot];)
                }
            });
            steps.extend(quote! {
                let __y = #lu.solve(&[#(#entries),*]);
                #( #store )*
            });
            done.extend(&block.cols);
        }
        quote!({
            let __rhs: [f64; #nu] = #rhs;
            let mut __x = [0.0f64; #nu];
            #steps
            __x
        })
    }
}

/// Whether the permutation `p` (of 0..n) is odd.
pub(crate) fn parity(p: &[usize]) -> bool {
    let mut seen = vec![false; p.len()];
    let mut odd = false;
    for start in 0..p.len() {
        let mut k = start;
        let mut length = 0;
        while !seen[k] {
            seen[k] = true;
            k = p[k];
            length += 1;
        }
        // A cycle of length m is m − 1 transpositions.
        if length > 0 && length % 2 == 0 {
            odd = !odd;
        }
    }
    odd
}

/// The binding of `__scaling` (`kinematics_core::solve::Scaling`) from the
/// term scales of `scale.rs`, evaluated from the parameters and the bound
/// drivers `q_…`; `on_fail(f)` runs when a scale overflows.
pub(super) fn scaling_code(
    g: &Graph,
    scales: &Scales,
    leaf: &dyn Fn(Leaf) -> TokenStream,
    params: usize,
    pp: &TokenStream,
    on_fail: &TokenStream,
) -> TokenStream {
    let length_leaf = crate::scale::length_leaf(params);
    let leaf = move |l: Leaf| {
        if l == length_leaf {
            quote!(__length)
        } else {
            leaf(l)
        }
    };
    let has_lengths = scales.is_length.iter().any(|&l| l);
    let stages = if has_lengths {
        vec![scales.fixed.clone(), scales.full.clone()]
    } else {
        vec![scales.fixed.clone()]
    };
    let sched = schedule(g, &stages);
    let (pr, lets) = bind(g, &sched, &leaf);
    let fixed: Vec<_> = scales.fixed.iter().map(|&i| pr.element(i)).collect();
    let full = if has_lengths {
        let full = scales.full.iter().map(|&i| pr.element(i));
        quote!(&[#(#full),*])
    } else {
        quote!(&__fixed)
    };
    let is_length = &scales.is_length;
    let ne = scales.fixed.len();
    let lets0 = &lets[0];
    let lets1 = lets.get(1);
    quote! {
        let __scaling = {
            #lets0
            let __fixed: [f64; #ne] = [#(#fixed),*];
            let __length = #pp::characteristic_length(&__fixed);
            #lets1
            match #pp::Scaling::new(#full, __length, [#(#is_length),*]) {
                ::core::result::Result::Ok(s) => s,
                ::core::result::Result::Err(f) => { #on_fail }
            }
        };
    }
}
