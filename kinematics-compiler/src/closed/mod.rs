//! Closed-form blocks: which diagonal blocks of Φ_u (`blocks.rs`) have an
//! exact solution, and their coefficients.
//!
//! Each equation of a block is written as a polynomial in the block's
//! symbols (cos θ and sin θ of each unknown angle θ, and each unknown
//! length λ), with coefficients that are expressions of the parameters, the
//! drivers and the unknowns of earlier blocks. sin and cos of θ + k (k free
//! of the block's unknowns) are expanded by the addition theorem, and
//! c² + s² terms with equal coefficients reduce to that coefficient. A
//! block whose polynomials have the monomials of one of the forms of
//! `kinematics_core::closed` (and whose matrices are similarities where the
//! form needs it) is solved by that form; any other block by Newton.
//!
//! Equalities and zeros of coefficients are decided by evaluating them at
//! three pseudo-random points of the parameters and coordinates (an
//! identity of analytic expressions that holds at random points holds
//! everywhere with probability one); the generated code checks the
//! residual at every closed-form solution all the same, and falls back to
//! Newton–Raphson when it is not at round-off.

mod poly;

use std::collections::HashMap;

use crate::blocks::block_triangular;
use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::lower::{CoordKind, Model};
use poly::{expand, reduce, Mono, Similarity, Values, ONE};

/// A 2×2 matrix of coefficients, row-major: one row per equation, column 0
/// multiplying cos θ and column 1 sin θ.
pub type Mat2 = [[Id; 2]; 2];

/// The closed forms (`kinematics_core::closed`), each with its
/// coefficients as named fields of the type `T` that stands for a
/// coefficient: an expression of the graph (`T = Id`) in the
/// compiler, its place in a buffer or its value in a back end
/// ([`ClosedForm::map`]). Every back end matches on this enum without a
/// wildcard, so a new form is listed by the compiler wherever it must be
/// handled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClosedForm<T> {
    /// a cos θ + b sin θ + c = 0.
    Angle {
        /// a, multiplying cos θ.
        a: T,
        /// b, multiplying sin θ.
        b: T,
        /// c.
        c: T,
    },
    /// a λ + c = 0.
    Linear {
        /// a, multiplying λ.
        a: T,
        /// c.
        c: T,
    },
    /// k + P e₀ + Q e₁ = 0 (RRR dyad), eᵢ = (cos θᵢ, sin θᵢ).
    CircleCircle {
        /// k.
        k: [T; 2],
        /// P, row by row.
        p: [[T; 2]; 2],
        /// Q, row by row.
        q: [[T; 2]; 2],
    },
    /// k + P e + λ v = 0 (RRT dyad).
    CircleLine {
        /// k.
        k: [T; 2],
        /// P, row by row.
        p: [[T; 2]; 2],
        /// v, the line's direction.
        v: [T; 2],
    },
    /// k + (P + λ W) e = 0 (RTR dyad).
    Slide {
        /// k.
        k: [T; 2],
        /// P, row by row.
        p: [[T; 2]; 2],
        /// W, row by row.
        w: [[T; 2]; 2],
    },
    /// k + λ₀ v₀ + λ₁ v₁ = 0 (TRT dyad).
    LineLine {
        /// k.
        k: [T; 2],
        /// v₀, the first line's direction.
        v0: [T; 2],
        /// v₁, the second line's direction.
        v1: [T; 2],
    },
}

/// A closed form whose coefficients are expressions of the graph.
pub type Pattern = ClosedForm<Id>;

impl<T: Copy> ClosedForm<T> {
    /// The same form with each coefficient `x` replaced by `f(x)`, visited
    /// in the order of [`ClosedForm::coefficients`].
    pub fn map<U>(&self, mut f: impl FnMut(T) -> U) -> ClosedForm<U> {
        let mut v = |x: [T; 2]| {
            let a = f(x[0]);
            [a, f(x[1])]
        };
        // Written out so that the order of the calls is the coefficients'.
        match *self {
            ClosedForm::Angle { a, b, c } => {
                let (a, b) = (f(a), f(b));
                ClosedForm::Angle { a, b, c: f(c) }
            }
            ClosedForm::Linear { a, c } => {
                let a = f(a);
                ClosedForm::Linear { a, c: f(c) }
            }
            ClosedForm::CircleCircle { k, p, q } => {
                let (k, p0, p1, q0) = (v(k), v(p[0]), v(p[1]), v(q[0]));
                ClosedForm::CircleCircle {
                    k,
                    p: [p0, p1],
                    q: [q0, v(q[1])],
                }
            }
            ClosedForm::CircleLine { k, p, v: d } => {
                let (k, p0, p1) = (v(k), v(p[0]), v(p[1]));
                ClosedForm::CircleLine {
                    k,
                    p: [p0, p1],
                    v: v(d),
                }
            }
            ClosedForm::Slide { k, p, w } => {
                let (k, p0, p1, w0) = (v(k), v(p[0]), v(p[1]), v(w[0]));
                ClosedForm::Slide {
                    k,
                    p: [p0, p1],
                    w: [w0, v(w[1])],
                }
            }
            ClosedForm::LineLine { k, v0, v1 } => {
                let (k, v0) = (v(k), v(v0));
                ClosedForm::LineLine { k, v0, v1: v(v1) }
            }
        }
    }

    /// The coefficients in one list, in the order the fields are
    /// declared (matrices row by row): what a block's stage evaluates.
    pub fn coefficients(&self) -> Vec<T> {
        let mut out = Vec::with_capacity(10);
        self.map(|x| out.push(x));
        out
    }

    /// The place of each coefficient in [`ClosedForm::coefficients`]: the
    /// typed layout of the list a back end evaluates.
    #[must_use]
    pub fn places(&self) -> ClosedForm<usize> {
        let mut next = 0;
        self.map(|_| {
            next += 1;
            next - 1
        })
    }

    /// Whether the block has two solutions (an assembly mode to choose).
    pub fn has_modes(&self) -> bool {
        match self {
            ClosedForm::Angle { .. }
            | ClosedForm::CircleCircle { .. }
            | ClosedForm::CircleLine { .. }
            | ClosedForm::Slide { .. } => true,
            ClosedForm::Linear { .. } | ClosedForm::LineLine { .. } => false,
        }
    }

    /// How many of the form's unknowns, first in its order, are angles
    /// (the others are lengths).
    pub fn angles(&self) -> usize {
        match self {
            ClosedForm::CircleCircle { .. } => 2,
            ClosedForm::Angle { .. } | ClosedForm::CircleLine { .. } | ClosedForm::Slide { .. } => {
                1
            }
            ClosedForm::Linear { .. } | ClosedForm::LineLine { .. } => 0,
        }
    }

    /// The form's short name: "angle", "linear", or the dyad ("RRR",
    /// "RRT", "RTR", "TRT").
    pub fn name(&self) -> &'static str {
        match self {
            ClosedForm::Angle { .. } => "angle",
            ClosedForm::Linear { .. } => "linear",
            ClosedForm::CircleCircle { .. } => "RRR",
            ClosedForm::CircleLine { .. } => "RRT",
            ClosedForm::Slide { .. } => "RTR",
            ClosedForm::LineLine { .. } => "TRT",
        }
    }

    /// How the block is solved, in words.
    pub fn describe(&self) -> &'static str {
        match self {
            ClosedForm::Angle { .. } => "closed form: a cos θ + b sin θ + c = 0",
            ClosedForm::Linear { .. } => "closed form: linear in one length",
            ClosedForm::CircleCircle { .. } => "closed form: RRR dyad (circle–circle)",
            ClosedForm::CircleLine { .. } => "closed form: RRT dyad (circle–line)",
            ClosedForm::Slide { .. } => "closed form: RTR dyad (slider on a turning link)",
            ClosedForm::LineLine { .. } => "closed form: TRT dyad (line–line)",
        }
    }
}

/// One diagonal block of Φ_u and how it is solved.
#[derive(Debug, Clone)]
pub struct Closed {
    /// Its equations (rows of Φ_u, ascending).
    pub rows: Vec<usize>,
    /// Its unknowns (0-based among the unknowns), in the order of the
    /// pattern's symbols (the angle first for the RRT and RTR dyads).
    pub cols: Vec<usize>,
    /// The closed form, or `None` for Newton–Raphson.
    pub pattern: Option<Pattern>,
}

/// sin(θ + k) or cos(θ + k) of an unknown angle θ and an offset k that
/// depends on the parameters only (a coupler point at `polar(p, th3 +
/// beta)`): the closed-form path evaluates it by the addition theorem from
/// θ's sine and cosine and k's, computed once per stepper.
#[derive(Debug, Clone)]
pub struct Offset {
    /// The node sin(θ + k) or cos(θ + k).
    pub node: Id,
    /// `Sin` or `Cos`.
    pub func: Func,
    /// θ's coordinate index.
    pub coord: usize,
    /// cos k and sin k.
    pub cos_k: Id,
    pub sin_k: Id,
}

/// Every sine and cosine of an unknown angle plus a parameter-only offset
/// in the model's graph (adding the offsets' sines and cosines to it).
pub fn offsets(model: &mut Model) -> Vec<Offset> {
    let nd = model.drivers;
    let g = &mut model.graph;
    let n = g.len();
    let mut out = Vec::new();
    for i in 0..n {
        let id = Id::from_index(i);
        let Node::Call(func @ (Func::Sin | Func::Cos), arg) = g.node(id) else {
            continue;
        };
        let Node::Add(a, b) = g.node(arg) else {
            continue;
        };
        for (x, k) in [(a, b), (b, a)] {
            let Node::Leaf(Leaf::Q(j)) = g.node(x) else {
                continue;
            };
            let angle = j >= nd && model.kinds[j as usize] == CoordKind::Angle;
            if !angle || g.depends_on(k, &|l| !matches!(l, Leaf::Param(_))) {
                continue;
            }
            let (cos_k, sin_k) = (g.call(Func::Cos, k), g.call(Func::Sin, k));
            out.push(Offset {
                node: id,
                func,
                coord: j as usize,
                cos_k,
                sin_k,
            });
            break;
        }
    }
    out
}

/// The blocks of the model's Φ_u (the jacobian `jac`), in solve order (as
/// `blocks::block_triangular` orders them), each with its closed form if it
/// has one. Adds the coefficients' nodes to the model's graph.
pub fn closed_blocks(model: &mut Model, jac: &[Vec<Id>]) -> Vec<Closed> {
    let nonzero = crate::blocks::nonzero(&model.graph, jac);
    let nd = model.drivers as usize;
    block_triangular(&nonzero)
        .into_iter()
        .map(|b| {
            let kinds: Vec<CoordKind> = b.cols.iter().map(|&c| model.kinds[nd + c]).collect();
            let residuals: Vec<Id> = b
                .rows
                .iter()
                .map(|&r| model.equations[r].residual)
                .collect();
            let recognised = if b.rows.len() <= 2 {
                recognise(&mut model.graph, nd, &b.cols, &kinds, &residuals)
            } else {
                None
            };
            match recognised {
                Some((pattern, swap)) => {
                    let mut cols = b.cols.clone();
                    if swap {
                        cols.reverse();
                    }
                    Closed {
                        rows: b.rows,
                        cols,
                        pattern: Some(pattern),
                    }
                }
                None => Closed {
                    rows: b.rows,
                    cols: b.cols,
                    pattern: None,
                },
            }
        })
        .collect()
}

/// The pattern of a block of one or two equations, and whether its
/// unknowns are taken in reverse order (the angle first).
fn recognise(
    g: &mut Graph,
    nd: usize,
    cols: &[usize],
    kinds: &[CoordKind],
    residuals: &[Id],
) -> Option<(Pattern, bool)> {
    let slots: HashMap<u32, (usize, CoordKind)> = cols
        .iter()
        .zip(kinds)
        .enumerate()
        .map(|(t, (&c, &k))| (u32::try_from(nd + c).unwrap_or(u32::MAX), (t, k)))
        .collect();
    let residuals: Vec<Id> = residuals.iter().map(|&r| squared(g, r, &slots)).collect();
    let mut polys = expand(g, &residuals, &slots)?;
    let values = Values::new(g, &polys);
    for (p, v) in polys.iter_mut().zip(&values.scales) {
        reduce(g, p, kinds, &values, *v);
    }
    // The values of coefficients added by the reduction.
    let values = Values::new(g, &polys);
    for (p, v) in polys.iter_mut().zip(&values.scales) {
        p.retain(|_, c| !values.zero(*c, *v));
    }
    let zero = g.constant(0.0);
    let coef = |r: usize, m: Mono| polys[r].get(&m).copied().unwrap_or(zero);
    let only = |allowed: &[Mono]| polys.iter().all(|p| p.keys().all(|m| allowed.contains(m)));
    let has = |m: Mono| polys.iter().any(|p| p.contains_key(&m));
    let sym = |e: usize| {
        let mut m = ONE;
        m[e] = 1;
        m
    };
    let both = |a: usize, b: usize| {
        let mut m = ONE;
        m[a] += 1;
        m[b] += 1;
        m
    };
    let mat = |m0: Mono, m1: Mono| [[coef(0, m0), coef(0, m1)], [coef(1, m0), coef(1, m1)]];
    let vec2 = |m: Mono| [coef(0, m), coef(1, m)];
    use CoordKind::{Angle, Length};
    match kinds {
        [Angle] if only(&[ONE, sym(0), sym(1)]) => Some((
            Pattern::Angle {
                a: coef(0, sym(0)),
                b: coef(0, sym(1)),
                c: coef(0, ONE),
            },
            false,
        )),
        [Length] if only(&[ONE, sym(0)]) => Some((
            Pattern::Linear {
                a: coef(0, sym(0)),
                c: coef(0, ONE),
            },
            false,
        )),
        [Angle, Angle] if only(&[ONE, sym(0), sym(1), sym(2), sym(3)]) => {
            let (p, q) = (mat(sym(0), sym(1)), mat(sym(2), sym(3)));
            let similar = |m: &Mat2| values.similarity(m).is_some_and(|s| s != Similarity::Zero);
            (similar(&p) && similar(&q))
                .then_some((Pattern::CircleCircle { k: vec2(ONE), p, q }, false))
        }
        [Length, Length] if only(&[ONE, sym(0), sym(2)]) => Some((
            Pattern::LineLine {
                k: vec2(ONE),
                v0: vec2(sym(0)),
                v1: vec2(sym(2)),
            },
            false,
        )),
        [Angle, Length] | [Length, Angle] => {
            let swap = kinds[0] == Length;
            let (a, l) = if swap { (1, 0) } else { (0, 1) };
            let (c, s, lam) = (sym(2 * a), sym(2 * a + 1), sym(2 * l));
            let (lc, ls) = (both(2 * l, 2 * a), both(2 * l, 2 * a + 1));
            if !only(&[ONE, c, s, lam, lc, ls]) {
                return None;
            }
            let (k, p) = (vec2(ONE), mat(c, s));
            if !has(lc) && !has(ls) && has(lam) {
                return Some((Pattern::CircleLine { k, p, v: vec2(lam) }, swap));
            }
            if has(lam) {
                return None;
            }
            let w = mat(lc, ls);
            let (sp, sw) = (values.similarity(&p)?, values.similarity(&w)?);
            let fits = sw != Similarity::Zero && (sp == Similarity::Zero || sp == sw);
            fits.then_some((Pattern::Slide { k, p, w }, swap))
        }
        _ => None,
    }
}

/// A residual √x + c (a distance `norm(v) == b`, with c free of the
/// block's unknowns) as the equivalent x − c², which is polynomial in the
/// symbols where √x is not (the same zeros where −c ≥ 0; a solution with
/// −c < 0 fails the residual check of the generated code); any other
/// residual unchanged.
fn squared(g: &mut Graph, r: Id, slots: &HashMap<u32, (usize, CoordKind)>) -> Id {
    let involves = |g: &Graph, id: Id| {
        g.depends_on(id, &|l| matches!(l, Leaf::Q(j) if slots.contains_key(&j)))
    };
    if let Node::Add(a, b) = g.node(r) {
        for (root, c) in [(a, b), (b, a)] {
            if let Node::Call(Func::Sqrt, x) = g.node(root) {
                if !involves(g, c) {
                    let c2 = g.mul(c, c);
                    return g.sub(x, c2);
                }
            }
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use quote::quote;

    /// How each block of a definition is solved.
    fn methods(input: proc_macro2::TokenStream) -> Vec<&'static str> {
        let def: crate::parse::Definition = syn::parse2(input).expect("parses");
        let mut errors = crate::names::Errors::default();
        let names = crate::check::check(&def, &mut errors);
        let mut model = crate::lower::lower(&def, &names, &mut errors);
        assert!(errors.is_empty());
        let derived = crate::kinematics::derive(&mut model);
        super::closed_blocks(&mut model, &derived.jac)
            .iter()
            .map(|b| {
                b.pattern
                    .as_ref()
                    .map_or("newton", super::Pattern::describe)
            })
            .collect()
    }

    #[test]
    fn dyads_and_single_angles_are_recognised() {
        let four_bar = methods(quote! { struct M {
            params { a, b, c, d, p, beta } drivers { phi } unknowns { th3, th4 }
            points { P = polar(a, phi) + polar(p, th3 + beta); }
            loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
        }});
        assert_eq!(four_bar, ["closed form: RRR dyad (circle–circle)"]);
        let slider_crank = methods(quote! { struct M {
            params { a, b, e } drivers { phi } unknowns { th, x }
            loops { polar(a, phi) + polar(b, th) == vec2(x, e); }
        }});
        // The vertical equation fixes θ alone, then the horizontal one x.
        assert_eq!(
            slider_crank,
            [
                "closed form: a cos θ + b sin θ + c = 0",
                "closed form: linear in one length"
            ]
        );
        let inclined = methods(quote! { struct M {
            params { a, b, e, gamma } drivers { phi } unknowns { th, x }
            loops { polar(a, phi) + polar(b, th) == vec2(0.0, e) + polar(x, gamma); }
        }});
        assert_eq!(inclined, ["closed form: RRT dyad (circle–line)"]);
        let inverted = methods(quote! { struct M {
            params { a, d } drivers { phi } unknowns { th, s }
            loops { polar(a, phi) == vec2(d, 0.0) + polar(s, th); }
        }});
        assert_eq!(
            inverted,
            ["closed form: RTR dyad (slider on a turning link)"]
        );
        let trt = methods(quote! { struct M {
            params { a, h, gamma } drivers { phi } unknowns { x, y }
            loops { polar(a, phi) + polar(x, gamma) == vec2(0.0, h) + y * vec2(0.5, 0.8); }
        }});
        assert_eq!(trt, ["closed form: TRT dyad (line–line)"]);
        let rssr = methods(quote! { struct M {
            params { a, b, c, d } drivers { phi } unknowns { psi }
            points { B = vec3(-d - c * cos(psi), c * sin(psi), 0.0); }
            constraints {
                dot(B - vec3(-a * cos(phi), 0.0, a * sin(phi)), B - vec3(-a * cos(phi), 0.0, a * sin(phi)))
                    == b * b;
            }
        }});
        assert_eq!(rssr, ["closed form: a cos θ + b sin θ + c = 0"]);
        // The same written as a distance: √(v·v) = b taken as v·v = b².
        let rssr = methods(quote! { struct M {
            params { a, b, c, d } drivers { phi } unknowns { psi }
            points {
                A = vec3(-a * cos(phi), 0.0, a * sin(phi));
                B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
            }
            constraints { norm(B - A) == b; }
        }});
        assert_eq!(rssr, ["closed form: a cos θ + b sin θ + c = 0"]);
        let watt = methods(quote! { struct M {
            params { a, b, c, d, e, f, g, h, al } drivers { phi } unknowns { th3, th4, th5, th6 }
            loops {
                polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4);
                polar(c, th4 + al) + polar(e, th5) == vec2(g, h) + polar(f, th6);
            }
        }});
        assert_eq!(watt, ["closed form: RRR dyad (circle–circle)"; 2]);
    }

    #[test]
    fn other_blocks_stay_with_newton() {
        // Two angles where one link's vector is not a similarity (an
        // ellipse): no acos form.
        let ellipse = methods(quote! { struct M {
            params { a, b, c, d } drivers { phi } unknowns { th3, th4 }
            loops { polar(a, phi) + vec2(2.0 * b * cos(th3), b * sin(th3)) == vec2(d, 0.0) + polar(c, th4); }
        }});
        assert_eq!(ellipse, ["newton"]);
        // An angle outside a sine or cosine.
        let mixed = methods(quote! { struct M {
            params { a } drivers { phi } unknowns { th }
            constraints { a * cos(th) + th == phi; }
        }});
        assert_eq!(mixed, ["newton"]);
    }
}
