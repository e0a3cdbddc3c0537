//! Polynomials in a block's symbols (cos θ and sin θ of each unknown angle,
//! each unknown length) with coefficients in the expression graph, and the
//! sample-point tests that decide identities between coefficients.

use std::collections::{BTreeMap, HashMap};

use super::Mat2;
use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::lower::CoordKind;

/// Exponents of (cos θ₀, sin θ₀, cos θ₁, sin θ₁); a length unknown in slot
/// t uses exponent 2t.
pub(super) type Mono = [u8; 4];
/// A polynomial in the block's symbols.
pub(super) type Poly = BTreeMap<Mono, Id>;

pub(super) const ONE: Mono = [0; 4];

/// The polynomials of `roots` in the block's symbols (`slots`: coordinate
/// index → slot and kind), or `None` if one is not a polynomial of degree
/// ≤ 4 in them.
pub(super) fn expand(
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
pub(super) fn reduce(
    g: &mut Graph,
    p: &mut Poly,
    kinds: &[CoordKind],
    values: &Values,
    scale: [f64; 3],
) {
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
pub(super) enum Similarity {
    Zero,
    /// [[x, −y], [y, x]].
    Rotation,
    /// [[x, y], [y, −x]].
    Reflection,
}

/// The values of the coefficients at three sample points.
pub(super) struct Values {
    at: HashMap<Id, [f64; 3]>,
    /// Per polynomial, the largest |coefficient| at each point.
    pub(super) scales: Vec<[f64; 3]>,
}

impl Values {
    pub(super) fn new(g: &mut Graph, polys: &[Poly]) -> Self {
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
    pub(super) fn equal(&self, a: Id, b: Id, scale: [f64; 3]) -> bool {
        let (Some(x), Some(y)) = (self.get(a), self.get(b)) else {
            return a == b;
        };
        (0..3).all(|k| (x[k] - y[k]).abs() <= 1e-9 * scale[k])
    }

    /// Whether `a` = 0 at every sample point.
    pub(super) fn zero(&self, a: Id, scale: [f64; 3]) -> bool {
        self.get(a)
            .is_some_and(|x| (0..3).all(|k| x[k].abs() <= 1e-9 * scale[k]))
    }

    /// The structure of `m`, if it is a similarity (or zero).
    pub(super) fn similarity(&self, m: &Mat2) -> Option<Similarity> {
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
        Leaf::Time => (5, 0),
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
