//! Lowering: the syntax tree to scalar expressions in the DAG.
//!
//! Each expression is typed as it is lowered: a scalar, a 2-D or 3-D
//! vector, a 3×3 rotation or a 4×4 homogeneous transform (kept as its
//! rotation and translation parts, the bottom row being (0, 0, 0, 1)).
//! Vectors and matrices are split into their scalar components. Type errors
//! point at the operator or call that is wrong. Equations become residuals
//! `lhs − rhs`, one per scalar component, and are counted against the
//! unknowns.

use std::collections::HashMap;

use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::names::{Errors, Names};
use crate::parse::Definition;

mod builtins;
pub mod dynamics;
mod expr;

type Mat = [[Id; 3]; 3];

/// A lowered value.
#[derive(Clone, Copy, Debug)]
enum Value {
    Scalar(Id),
    Vec2([Id; 2]),
    Vec3([Id; 3]),
    /// A 3×3 rotation matrix.
    Rot(Mat),
    /// A 4×4 homogeneous transform [[R, t], [0, 1]].
    Tf(Mat, [Id; 3]),
}

impl Value {
    fn describe(self) -> &'static str {
        match self {
            Value::Scalar(_) => "a scalar",
            Value::Vec2(_) => "a 2-D vector",
            Value::Vec3(_) => "a 3-D vector",
            Value::Rot(_) => "a 3×3 rotation matrix",
            Value::Tf(..) => "a 4×4 transform",
        }
    }

    fn is_spatial(self) -> bool {
        matches!(self, Value::Vec3(_) | Value::Rot(_) | Value::Tf(..))
    }
}

/// One scalar equation Φ_i = 0.
pub struct ModelEquation {
    pub residual: Id,
    /// The equation as written, with the component for vector loops.
    pub text: String,
    /// The equation's tokens, where errors about it point.
    pub tokens: proc_macro2::TokenStream,
}

/// A point of interest, component by component (2 or 3 of them).
pub struct ModelPoint {
    pub coords: Vec<Id>,
    /// The point as a fixed point of a body turned along a chain, when it
    /// was given as one (a transform or rotation built as a [`Chain`] times
    /// a vector free of the coordinates).
    pub attached: Option<Attached>,
}

/// A point p = R v + o fixed in a body whose rotation R is a [`Chain`]: its
/// velocity is ȯ + ω × (R v) and its acceleration
/// ö + α × (R v) + ω × (ω × (R v)), with ω and α from the chain, where
/// differentiating R v would differentiate the chain's matrices.
#[derive(Clone)]
pub struct Attached {
    pub chain: Chain,
    /// o, the body's origin.
    pub origin: [Id; 3],
    /// o as segments along the chain, when it was built so.
    pub body: Option<Body>,
    /// R v, the point relative to the origin in fixed coordinates.
    pub offset: [Id; 3],
}

/// A body frame: rotation and origin.
pub struct ModelFrame {
    pub rotation: Mat,
    pub origin: [Id; 3],
    /// The rotation as a product of rotations about axes fixed in their
    /// own bodies, when it was built as one (see [`Chain`]), and the origin
    /// as a sum of body-fixed segments along it, when it was built as one
    /// (see [`Body`]).
    pub chain: Option<Chain>,
    pub body: Option<Body>,
}

/// A transform [[R, o], [0, 1]] built along a [`Chain`] from joints with
/// constant offsets: o = Σ sₘ, each segment sₘ = R₁⋯R_{k(m)} tₘ with tₘ
/// constant, so that ṡₘ = ω_{k(m)} × sₘ and
/// s̈ₘ = α_{k(m)} × sₘ + ω_{k(m)} × (ω_{k(m)} × sₘ), ωₖ and αₖ being those
/// of the first k rotations of the chain.
#[derive(Clone)]
pub struct Body {
    pub chain: Chain,
    /// (sₘ, k(m)).
    pub segments: Vec<([Id; 3], usize)>,
}

/// A rotation R = R₁(θ₁) R₂(θ₂) ⋯ Rₙ(θₙ), each Rₖ about an axis fixed in
/// its body, kept as the axes in fixed coordinates, zₖ = R₁⋯Rₖ₋₁ aₖ, and
/// the angles θₖ: then ω = Σ zₖ θ̇ₖ and α = Σ (zₖ θ̈ₖ + ωₖ₋₁ × zₖ θ̇ₖ),
/// with ωₖ₋₁ = Σ_{j<k} zⱼ θ̇ⱼ, the recursion along a serial chain, where
/// differentiating the product of matrices would cost a matrix product per
/// factor and derivative.
pub type Chain = Vec<([Id; 3], Id)>;

/// Whether a coordinate is an angle (appears inside a trigonometric function)
/// or a length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordKind {
    Angle,
    Length,
}

/// The checked, lowered mechanism.
pub struct Model {
    pub graph: Graph,
    pub drivers: u32,
    pub unknowns: u32,
    pub equations: Vec<ModelEquation>,
    pub points: Vec<ModelPoint>,
    /// 2 for planar points, 3 for spatial ones.
    pub point_dim: usize,
    pub frames: Vec<ModelFrame>,
    pub kinds: Vec<CoordKind>,
    /// The number of scalar equations of each loop, in declaration order:
    /// 2 for a planar loop, 3 for a spatial one, 0 when it failed to lower.
    pub loop_dims: Vec<usize>,
    /// Whether any 3-D quantity appears (λ = 6 for the mobility count).
    pub spatial: bool,
    /// The parameters that are the distance of a constraint `norm(v) == b`
    /// (lowered as v·v − b²), with the constraint's text: each must be
    /// positive for the two forms to have the same solutions.
    pub distances: Vec<(u32, String)>,
    /// The `bodies` and `loads` sections, where written.
    pub dynamics: Option<dynamics::LoweredDynamics>,
}

impl Model {
    /// Number of coordinates (drivers and unknowns).
    pub fn coords(&self) -> u32 {
        self.drivers + self.unknowns
    }
}

/// Lowers every frame, point and equation of `def`, reporting type and
/// counting errors into `errors`. Frames come first (points may use them),
/// then points in order (each may use the ones above it).
pub fn lower(def: &Definition, names: &Names, errors: &mut Errors) -> Model {
    let mut cx = Lowerer {
        g: Graph::new(),
        names,
        points: HashMap::new(),
        frames: HashMap::new(),
        chains: HashMap::new(),
        attached: HashMap::new(),
        bodies: HashMap::new(),
        spatial: false,
        rates: false,
        errors,
    };
    let mut frames = Vec::new();
    for (k, f) in def.frames.iter().enumerate() {
        let frame = match cx.expr(&f.expr) {
            Some(Value::Rot(r)) => {
                let zero = cx.g.constant(0.0);
                ModelFrame {
                    rotation: r,
                    origin: [zero; 3],
                    chain: cx.chains.get(&r).cloned(),
                    body: cx.body(&r, [zero; 3]),
                }
            }
            Some(Value::Tf(r, t)) => ModelFrame {
                rotation: r,
                origin: t,
                chain: cx.chains.get(&r).cloned(),
                body: cx.body(&r, t),
            },
            other => {
                if let Some(v) = other {
                    cx.errors.spanned(
                        &f.expr,
                        format!(
                            "frame `{}` must be a rotation or a 4×4 transform, but this \
                             expression is {}; build it with `rot_z(θ)`, `rot(axis, θ)`, \
                             `t1(…)` … `t7(…)` or products of them",
                            f.name,
                            v.describe()
                        ),
                    );
                }
                let (zero, one) = (cx.g.constant(0.0), cx.g.constant(1.0));
                ModelFrame {
                    rotation: [[one, zero, zero], [zero, one, zero], [zero, zero, one]],
                    origin: [zero; 3],
                    chain: None,
                    body: None,
                }
            }
        };
        cx.frames.insert(k, (frame.rotation, frame.origin));
        frames.push(frame);
    }
    let mut points = Vec::new();
    let mut point_dim: Option<(usize, &syn::Ident)> = None;
    for (k, p) in def.points.iter().enumerate() {
        let coords = match cx.expr(&p.expr) {
            Some(Value::Vec2(xy)) => Some(xy.to_vec()),
            Some(Value::Vec3(xyz)) => Some(xyz.to_vec()),
            Some(v) => {
                cx.errors.spanned(
                    &p.expr,
                    format!(
                        "point `{}` must be a vector, but this expression is {}; build it \
                         with `vec2(x, y)`, `polar(r, angle)`, `vec3(x, y, z)` or a \
                         transform times a point",
                        p.name,
                        v.describe()
                    ),
                );
                None
            }
            None => None,
        };
        let coords = match (coords, point_dim) {
            (Some(c), Some((dim, first))) if c.len() != dim => {
                cx.errors.spanned(
                    &p.expr,
                    format!(
                        "point `{}` is {}-D but point `{first}` is {dim}-D; all points of a \
                         mechanism have the same dimension (write planar points of a spatial \
                         mechanism with `vec3(x, y, 0.0)`)",
                        p.name,
                        c.len()
                    ),
                );
                None
            }
            (c, _) => c,
        };
        let coords = match coords {
            Some(c) => {
                if point_dim.is_none() {
                    point_dim = Some((c.len(), &p.name));
                }
                c
            }
            None => {
                // Keep later uses from cascading into more errors.
                let zero = cx.g.constant(0.0);
                vec![zero; point_dim.map_or(2, |(d, _)| d)]
            }
        };
        cx.points.insert(k, coords.clone());
        let attached = <[Id; 3]>::try_from(coords.as_slice())
            .ok()
            .and_then(|c| cx.attached.get(&c).cloned());
        points.push(ModelPoint { coords, attached });
    }
    let mut equations = Vec::new();
    let mut loop_dims = Vec::new();
    for eq in &def.loops {
        let (l, r) = (cx.expr(&eq.lhs), cx.expr(&eq.rhs));
        let sides: Option<(Vec<Id>, Vec<Id>)> = match (l, r) {
            (Some(Value::Vec2(a)), Some(Value::Vec2(b))) => Some((a.to_vec(), b.to_vec())),
            (Some(Value::Vec3(a)), Some(Value::Vec3(b))) => Some((a.to_vec(), b.to_vec())),
            (Some(Value::Scalar(_)), Some(Value::Scalar(_))) => {
                cx.errors.spanned(
                    &eq.tokens,
                    "this loop equation is scalar; a loop closes a chain of vectors \
                     (`B + polar(b, th3) == C`). Move scalar equations to `constraints { … }`",
                );
                None
            }
            (Some(a), Some(b)) => {
                cx.errors.spanned(
                    &eq.tokens,
                    format!(
                        "the two sides of this loop must be vectors of the same dimension, but \
                         the left is {} and the right is {}",
                        a.describe(),
                        b.describe()
                    ),
                );
                None
            }
            _ => None,
        };
        loop_dims.push(sides.as_ref().map_or(0, |(a, _)| a.len()));
        if let Some((a, b)) = sides {
            for (c, axis) in ["x", "y", "z"].iter().enumerate().take(a.len()) {
                let residual = cx.g.sub(a[c], b[c]);
                equations.push(ModelEquation {
                    residual,
                    text: format!("{} ({axis} component)", eq.text),
                    tokens: eq.tokens.clone(),
                });
            }
        }
    }
    let mut distances = Vec::new();
    for eq in &def.constraints {
        let (l, r) = (cx.expr(&eq.lhs), cx.expr(&eq.rhs));
        match (l, r) {
            (Some(Value::Scalar(a)), Some(Value::Scalar(b))) => {
                let residual = match squared_distance(&mut cx.g, a, b) {
                    Some((residual, param)) => {
                        if let Some(k) = param {
                            if !distances.iter().any(|&(j, _)| j == k) {
                                distances.push((k, eq.text.clone()));
                            }
                        }
                        residual
                    }
                    None => cx.g.sub(a, b),
                };
                equations.push(ModelEquation {
                    residual,
                    text: eq.text.clone(),
                    tokens: eq.tokens.clone(),
                });
            }
            (Some(Value::Vec2(_)), Some(Value::Vec2(_)))
            | (Some(Value::Vec3(_)), Some(Value::Vec3(_))) => cx.errors.spanned(
                &eq.tokens,
                "this constraint equates two vectors; vector equations belong in \
                 `loops { … }` (each gives one scalar equation per component)",
            ),
            (Some(a), Some(b)) => cx.errors.spanned(
                &eq.tokens,
                format!(
                    "the two sides of this constraint have different dimensions: the left is {} \
                     and the right is {}",
                    a.describe(),
                    b.describe()
                ),
            ),
            _ => {}
        }
    }
    // The kinematics' nodes, below the dynamics' (which may not decide
    // whether a coordinate is an angle).
    let kinematic_nodes = cx.g.len();
    let dim = point_dim.map_or(2, |(d, _)| d);
    let dynamics = cx.dynamics(def, dim);
    let spatial = cx.spatial;
    let graph = cx.g;
    let model = Model {
        dynamics,
        kinds: Vec::new(),
        loop_dims,
        drivers: count(def.drivers.len()),
        unknowns: count(def.unknowns.len()),
        equations,
        points,
        point_dim: point_dim.map_or(2, |(d, _)| d),
        frames,
        spatial,
        graph,
        distances,
    };
    let kinds = coordinate_kinds(&model, kinematic_nodes);
    Model { kinds, ..model }
}

/// A constraint √x == b (a distance, `norm(v) == b`, either way round),
/// with b a parameter or a positive constant, as the residual x − b²: the
/// same solutions when b > 0 (the generated `validate` requires it of the
/// parameter, returned beside the residual), with no square root to
/// evaluate and a derivative that stays finite where v = 0. `None` for any
/// other constraint.
fn squared_distance(g: &mut Graph, a: Id, b: Id) -> Option<(Id, Option<u32>)> {
    for (root, other, flip) in [(a, b, false), (b, a, true)] {
        let Node::Call(Func::Sqrt, x) = g.node(root) else {
            continue;
        };
        let param = match g.node(other) {
            Node::Leaf(Leaf::Param(k)) => Some(k),
            Node::Const(bits) if f64::from_bits(bits) > 0.0 => None,
            _ => continue,
        };
        let b2 = g.mul(other, other);
        let residual = if flip { g.sub(b2, x) } else { g.sub(x, b2) };
        return Some((residual, param));
    }
    None
}

fn count(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// A coordinate is an angle when some sin, cos or tan of the first
/// `nodes` nodes has it in its argument.
fn coordinate_kinds(model: &Model, nodes: usize) -> Vec<CoordKind> {
    let g = &model.graph;
    let nodes = nodes.min(g.len());
    let mut kinds = vec![CoordKind::Length; model.coords() as usize];
    let leaves: Vec<Option<usize>> = (0..model.coords())
        .map(|j| (0..nodes).find(|&i| g.node(Id::from_index(i)) == Node::Leaf(Leaf::Q(j))))
        .collect();
    for i in 0..nodes {
        if let Node::Call(Func::Sin | Func::Cos | Func::Tan, arg) = g.node(Id::from_index(i)) {
            let live = g.reachable(&[arg]);
            for (kind, leaf) in kinds.iter_mut().zip(&leaves) {
                if leaf.is_some_and(|l| live[l]) {
                    *kind = CoordKind::Angle;
                }
            }
        }
    }
    kinds
}

struct Lowerer<'a> {
    g: Graph,
    names: &'a Names,
    /// Points lowered so far, by index.
    points: HashMap<usize, Vec<Id>>,
    /// Frames lowered so far, by index.
    frames: HashMap<usize, (Mat, [Id; 3])>,
    /// The rotations built as products of rotations about body-fixed axes,
    /// with their chains.
    chains: HashMap<Mat, Chain>,
    /// The vectors built as points fixed in such bodies, by their
    /// components.
    attached: HashMap<[Id; 3], Attached>,
    /// The transforms built along chains, by rotation and origin.
    bodies: HashMap<(Mat, [Id; 3]), Body>,
    spatial: bool,
    /// Whether `rate(x)` may be used (in a load's value).
    rates: bool,
    errors: &'a mut Errors,
}

#[cfg(test)]
mod tests {
    use quote::quote;

    use crate::ir::{Func, Node};

    /// The lowered model of a definition, and whether any residual still
    /// takes a square root.
    fn lowered(input: proc_macro2::TokenStream) -> (super::Model, bool) {
        let def: crate::parse::Definition = syn::parse2(input).expect("parses");
        let mut errors = crate::names::Errors::default();
        let names = crate::check::check(&def, &mut errors);
        let model = super::lower(&def, &names, &mut errors);
        assert!(errors.is_empty());
        let roots: Vec<_> = model.equations.iter().map(|e| e.residual).collect();
        let live = model.graph.reachable(&roots);
        let sqrt = (0..live.len()).any(|i| {
            live[i]
                && matches!(
                    model.graph.node(crate::ir::Id::from_index(i)),
                    Node::Call(Func::Sqrt, _)
                )
        });
        (model, sqrt)
    }

    #[test]
    fn a_distance_is_solved_squared_and_its_parameter_must_be_positive() {
        // Either way round; the point B keeps its own expression.
        for constraint in [quote!(norm(B - A) == b;), quote!(b == norm(B - A);)] {
            let (model, sqrt) = lowered(quote! { struct M {
                params { a, b, c, d } drivers { phi } unknowns { psi }
                points {
                    A = vec3(-a * cos(phi), 0.0, a * sin(phi));
                    B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
                }
                constraints { #constraint }
            }});
            assert!(!sqrt, "{constraint}: the residual still has a square root");
            assert_eq!(model.distances.len(), 1);
            assert_eq!(model.distances[0].0, 1, "the parameter b");
        }
        // A positive constant needs no check.
        let (model, sqrt) = lowered(quote! { struct M {
            params { a } drivers { phi } unknowns { y }
            constraints { norm(vec2(a * cos(phi), y)) == 2.0; }
        }});
        assert!(!sqrt && model.distances.is_empty());
    }

    #[test]
    fn other_square_roots_are_kept() {
        // An expression of parameters, a negative constant, an unknown:
        // none is squared.
        for rhs in [quote!(b + c), quote!(-1.0), quote!(y)] {
            let (model, sqrt) = lowered(quote! { struct M {
                params { a, b, c } drivers { phi } unknowns { y, z }
                constraints {
                    norm(vec2(a * cos(phi), y)) == #rhs;
                    z == y;
                }
            }});
            assert!(sqrt, "{rhs}");
            assert!(model.distances.is_empty());
        }
    }

    /// A product of rotations about axes fixed in their bodies keeps its
    /// chain (one entry per rotation: R times the translation's identity
    /// is R itself, and keeps R's chain), and with constant offsets its
    /// origin's segments; a point fixed in it is attached to it. A slide
    /// that moves with a coordinate leaves the origin without segments; a
    /// rotation about an axis that moves with a coordinate has no chain.
    #[test]
    fn rotations_about_body_fixed_axes_keep_their_chain() {
        let (model, _) = lowered(quote! {
            pub struct Gimbal {
                params { l }
                drivers { q1, q2 }
                unknowns { }
                frames {
                    chained = rot_z(q1) * translation(vec3(l, 0.0, 0.0)) * rot_x(q2);
                    sliding = chained * t7(q1, 0.0, 0.0);
                    moving = rot(vec3(cos(q1), sin(q1), 0.5), q2);
                }
                points {
                    P = chained * vec3(0.1, l, 0.2);
                    Q = moving * vec3(0.1, l, 0.2);
                }
            }
        });
        let [chained, sliding, moving] = &model.frames[..] else {
            panic!("three frames");
        };
        assert_eq!(chained.chain.as_ref().map(Vec::len), Some(2));
        assert_eq!(chained.body.as_ref().map(|b| b.segments.len()), Some(3));
        assert!(sliding.chain.is_some() && sliding.body.is_none());
        assert!(moving.chain.is_none() && moving.body.is_none());
        assert!(model.points[0]
            .attached
            .as_ref()
            .is_some_and(|a| a.body.is_some()));
        assert!(model.points[1].attached.is_none());
    }
}
