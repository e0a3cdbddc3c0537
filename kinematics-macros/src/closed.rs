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

use std::collections::{BTreeMap, HashMap};

use crate::blocks::block_triangular;
use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::lower::{CoordKind, Model};

/// Exponents of (cos θ₀, sin θ₀, cos θ₁, sin θ₁); a length unknown in slot
/// t uses exponent 2t.
type Mono = [u8; 4];
/// A polynomial in the block's symbols.
type Poly = BTreeMap<Mono, Id>;

const ONE: Mono = [0; 4];

/// A 2-vector of coefficients, one per equation of the block.
pub type Vec2 = [Id; 2];
/// A 2×2 matrix of coefficients, row-major: one row per equation, column 0
/// multiplying cos θ and column 1 sin θ.
pub type Mat2 = [[Id; 2]; 2];

/// The closed forms (`kinematics_core::closed`).
#[derive(Debug, Clone)]
pub enum Pattern {
    /// a cos θ + b sin θ + c = 0.
    Angle { a: Id, b: Id, c: Id },
    /// a λ + c = 0.
    Linear { a: Id, c: Id },
    /// k + P e₀ + Q e₁ = 0 (RRR dyad).
    CircleCircle { k: Vec2, p: Mat2, q: Mat2 },
    /// k + P e + λ v = 0 (RRT dyad).
    CircleLine { k: Vec2, p: Mat2, v: Vec2 },
    /// k + (P + λ W) e = 0 (RTR dyad).
    Slide { k: Vec2, p: Mat2, w: Mat2 },
    /// k + λ₀ v₀ + λ₁ v₁ = 0 (TRT dyad).
    LineLine { k: Vec2, v0: Vec2, v1: Vec2 },
}

impl Pattern {
    /// Whether the block has two solutions (an assembly mode to choose).
    pub fn has_modes(&self) -> bool {
        !matches!(self, Pattern::Linear { .. } | Pattern::LineLine { .. })
    }

    /// How the block is solved, in words.
    pub fn describe(&self) -> &'static str {
        match self {
            Pattern::Angle { .. } => "closed form: a cos θ + b sin θ + c = 0",
            Pattern::Linear { .. } => "closed form: linear in one length",
            Pattern::CircleCircle { .. } => "closed form: RRR dyad (circle–circle)",
            Pattern::CircleLine { .. } => "closed form: RRT dyad (circle–line)",
            Pattern::Slide { .. } => "closed form: RTR dyad (slider on a turning link)",
            Pattern::LineLine { .. } => "closed form: TRT dyad (line–line)",
        }
    }
}

/// One diagonal block of Φ_u and how it is solved.
#[derive(Debug, Clone)]
pub struct Closed {
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
    let g = &model.graph;
    let nonzero: Vec<Vec<bool>> = jac
        .iter()
        .map(|row| {
            row.iter()
                .map(|&id| !matches!(g.node(id), Node::Const(b) if f64::from_bits(b) == 0.0))
                .collect()
        })
        .collect();
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
                        cols,
                        pattern: Some(pattern),
                    }
                }
                None => Closed {
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

/// The polynomials of `roots` in the block's symbols (`slots`: coordinate
/// index → slot and kind), or `None` if one is not a polynomial of degree
/// ≤ 4 in them.
fn expand(
    g: &mut Graph,
    roots: &[Id],
    slots: &HashMap<u32, (usize, CoordKind)>,
) -> Option<Vec<Poly>> {
    let n = g.len();
    let live = g.reachable(roots);
    let mut dep = vec![false; n];
    let mut poly: Vec<Option<Poly>> = vec![None; n];
    let constant = |id: Id| Poly::from([(ONE, id)]);
    for i in 0..n {
        if !live[i] {
            continue;
        }
        let id = Id::from_index(i);
        let node = g.node(id);
        dep[i] = match node {
            Node::Leaf(Leaf::Q(j)) => slots.contains_key(&j),
            _ => node.children().any(|c| dep[c.index()]),
        };
        if !dep[i] {
            continue;
        }
        let get = |poly: &[Option<Poly>], c: Id| -> Option<Poly> {
            if dep[c.index()] {
                poly[c.index()].clone()
            } else {
                Some(constant(c))
            }
        };
        poly[i] = match node {
            Node::Leaf(Leaf::Q(j)) => match slots.get(&j) {
                Some(&(t, CoordKind::Length)) => {
                    let mut m = ONE;
                    m[2 * t] = 1;
                    let one = g.constant(1.0);
                    Some(Poly::from([(m, one)]))
                }
                _ => None,
            },
            Node::Add(a, b) => match (get(&poly, a), get(&poly, b)) {
                (Some(x), Some(y)) => Some(add(g, x, &y)),
                _ => None,
            },
            Node::Neg(a) => get(&poly, a).map(|x| scale(g, &x, None)),
            Node::Mul(a, b) => match (get(&poly, a), get(&poly, b)) {
                (Some(x), Some(y)) => mul(g, &x, &y),
                _ => None,
            },
            Node::Div(a, b) if !dep[b.index()] => get(&poly, a).map(|x| scale(g, &x, Some(b))),
            Node::Powi(a, k) if (1..=4).contains(&k) => get(&poly, a).and_then(|x| {
                let mut out = x.clone();
                for _ in 1..k {
                    out = mul(g, &out, &x)?;
                }
                Some(out)
            }),
            Node::Call(f @ (Func::Sin | Func::Cos), arg) => trig(g, f, arg, &dep, slots),
            _ => None,
        };
    }
    roots
        .iter()
        .map(|&r| {
            if dep[r.index()] {
                poly[r.index()].clone()
            } else {
                Some(constant(r))
            }
        })
        .collect()
}

/// sin or cos of `arg` = σ θ + k as a polynomial in (cos θ, sin θ).
fn trig(
    g: &mut Graph,
    f: Func,
    arg: Id,
    dep: &[bool],
    slots: &HashMap<u32, (usize, CoordKind)>,
) -> Option<Poly> {
    let (t, sigma, k) = affine(g, arg, dep, slots)?;
    let (mut mc, mut ms) = (ONE, ONE);
    mc[2 * t] = 1;
    ms[2 * t + 1] = 1;
    let one = g.constant(1.0);
    let (ck, sk) = match k {
        Some(k) => (g.call(Func::Cos, k), g.call(Func::Sin, k)),
        None => (one, g.constant(0.0)),
    };
    // cos(σθ + k) = cos k · c − σ sin k · s; sin(σθ + k) = sin k · c + σ cos k · s.
    let (on_c, on_s) = match f {
        Func::Cos => (ck, if sigma > 0.0 { g.neg(sk) } else { sk }),
        _ => (sk, if sigma > 0.0 { ck } else { g.neg(ck) }),
    };
    let mut p = Poly::new();
    for (m, c) in [(mc, on_c), (ms, on_s)] {
        if g.as_const(c) != Some(0.0) {
            p.insert(m, c);
        }
    }
    Some(p)
}

/// `arg` as σ θ + k with θ an unknown angle of the block (its slot), σ = ±1
/// and k free of the block's unknowns (`None` for 0).
fn affine(
    g: &mut Graph,
    arg: Id,
    dep: &[bool],
    slots: &HashMap<u32, (usize, CoordKind)>,
) -> Option<(usize, f64, Option<Id>)> {
    match g.node(arg) {
        Node::Leaf(Leaf::Q(j)) => match slots.get(&j) {
            Some(&(t, CoordKind::Angle)) => Some((t, 1.0, None)),
            _ => None,
        },
        Node::Neg(a) => {
            let (t, s, k) = affine(g, a, dep, slots)?;
            Some((t, -s, k.map(|k| g.neg(k))))
        }
        Node::Add(a, b) => {
            let (x, y) = match (dep[a.index()], dep[b.index()]) {
                (true, false) => (a, b),
                (false, true) => (b, a),
                _ => return None,
            };
            let (t, s, k) = affine(g, x, dep, slots)?;
            Some((t, s, Some(k.map_or(y, |k| g.sum(k, y)))))
        }
        _ => None,
    }
}

/// x + y.
fn add(g: &mut Graph, mut x: Poly, y: &Poly) -> Poly {
    for (m, &c) in y {
        let v = match x.get(m) {
            Some(&d) => g.sum(d, c),
            None => c,
        };
        x.insert(*m, v);
    }
    x
}

/// −x (`by` = None) or x / by.
fn scale(g: &mut Graph, x: &Poly, by: Option<Id>) -> Poly {
    x.iter()
        .map(|(m, &c)| {
            (
                *m,
                match by {
                    None => g.neg(c),
                    Some(b) => g.div(c, b),
                },
            )
        })
        .collect()
}

/// x · y, or `None` past degree 4.
fn mul(g: &mut Graph, x: &Poly, y: &Poly) -> Option<Poly> {
    let mut out = Poly::new();
    for (mx, &cx) in x {
        for (my, &cy) in y {
            let mut m = ONE;
            for e in 0..4 {
                m[e] = mx[e] + my[e];
            }
            if m.iter().sum::<u8>() > 4 {
                return None;
            }
            let c = g.mul(cx, cy);
            let v = match out.get(&m) {
                Some(&d) => g.sum(d, c),
                None => c,
            };
            out.insert(m, v);
        }
    }
    Some(out)
}

/// Reduces c² + s² = 1 where the coefficients of m·c² and m·s² are equal,
/// and drops coefficients that are identically zero (`scale`: the size of
/// the polynomial's coefficients at the sample points).
fn reduce(g: &mut Graph, p: &mut Poly, kinds: &[CoordKind], values: &Values, scale: [f64; 3]) {
    for (t, kind) in kinds.iter().enumerate() {
        if *kind != CoordKind::Angle {
            continue;
        }
        let squares: Vec<Mono> = p.keys().filter(|m| m[2 * t] >= 2).copied().collect();
        for m in squares {
            let mut ms = m;
            ms[2 * t] -= 2;
            ms[2 * t + 1] += 2;
            let (Some(&a), Some(&b)) = (p.get(&m), p.get(&ms)) else {
                continue;
            };
            if !values.equal(a, b, scale) {
                continue;
            }
            let mut m0 = m;
            m0[2 * t] -= 2;
            p.remove(&m);
            p.remove(&ms);
            let v = match p.get(&m0) {
                Some(&d) => g.sum(d, a),
                None => a,
            };
            p.insert(m0, v);
        }
    }
    p.retain(|_, c| !values.zero(*c, scale));
}

/// A 2×2 coefficient matrix's structure.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Similarity {
    Zero,
    /// [[x, −y], [y, x]].
    Rotation,
    /// [[x, y], [y, −x]].
    Reflection,
}

/// The values of the coefficients at three sample points.
struct Values {
    at: HashMap<Id, [f64; 3]>,
    /// Per polynomial, the largest |coefficient| at each point.
    scales: Vec<[f64; 3]>,
}

impl Values {
    fn new(g: &mut Graph, polys: &[Poly]) -> Self {
        let ids: Vec<Id> = polys.iter().flat_map(|p| p.values().copied()).collect();
        let mut at: HashMap<Id, [f64; 3]> = HashMap::new();
        for k in 0..3u64 {
            let vals = g.eval(&ids, &|l| sample(l, k));
            for (id, v) in ids.iter().zip(vals) {
                at.entry(*id).or_insert([0.0; 3])[k as usize] = v;
            }
        }
        let scales = polys
            .iter()
            .map(|p| {
                let mut s = [0.0f64; 3];
                for c in p.values() {
                    for (k, sk) in s.iter_mut().enumerate() {
                        *sk = sk.max(at[c][k].abs());
                    }
                }
                s
            })
            .collect();
        Values { at, scales }
    }

    /// The sample values of `id` (evaluated when first asked).
    fn get(&self, id: Id) -> Option<[f64; 3]> {
        self.at.get(&id).copied()
    }

    /// Whether `a` = `b` at every sample point, to round-off of `scale`.
    fn equal(&self, a: Id, b: Id, scale: [f64; 3]) -> bool {
        let (Some(x), Some(y)) = (self.get(a), self.get(b)) else {
            return a == b;
        };
        (0..3).all(|k| (x[k] - y[k]).abs() <= 1e-9 * scale[k])
    }

    /// Whether `a` = 0 at every sample point.
    fn zero(&self, a: Id, scale: [f64; 3]) -> bool {
        self.get(a)
            .is_some_and(|x| (0..3).all(|k| x[k].abs() <= 1e-9 * scale[k]))
    }

    /// The structure of `m`, if it is a similarity (or zero).
    fn similarity(&self, m: &Mat2) -> Option<Similarity> {
        let v: Vec<[f64; 3]> = m
            .iter()
            .flatten()
            .map(|&id| self.get(id).unwrap_or([0.0; 3]))
            .collect();
        let scale: [f64; 3] =
            std::array::from_fn(|k| v.iter().map(|x| x[k].abs()).fold(0.0, f64::max));
        let holds = |f: &dyn Fn(usize) -> f64| (0..3).all(|k| f(k).abs() <= 1e-9 * scale[k]);
        if holds(&|k| scale[k]) {
            Some(Similarity::Zero)
        } else if holds(&|k| v[0][k] - v[3][k]) && holds(&|k| v[1][k] + v[2][k]) {
            Some(Similarity::Rotation)
        } else if holds(&|k| v[0][k] + v[3][k]) && holds(&|k| v[1][k] - v[2][k]) {
            Some(Similarity::Reflection)
        } else {
            None
        }
    }
}

/// A pseudo-random value of a leaf at sample point `k`: lengths in
/// [0.5, 2], coordinates in [−3, 3].
fn sample(leaf: Leaf, k: u64) -> f64 {
    let (kind, i) = match leaf {
        Leaf::Param(i) => (1u64, i),
        Leaf::Q(i) => (2, i),
        Leaf::Qd(i) => (3, i),
        Leaf::Qdd(i) => (4, i),
    };
    // SplitMix64 of (kind, index, point).
    let mut z = (kind << 40 | u64::from(i) << 8 | k).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    #[allow(clippy::cast_precision_loss)]
    let u = (z >> 11) as f64 / (1u64 << 53) as f64;
    match leaf {
        Leaf::Param(_) => 0.5 + 1.5 * u,
        _ => -3.0 + 6.0 * u,
    }
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
