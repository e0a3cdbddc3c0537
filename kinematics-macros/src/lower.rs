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

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, UnOp};

use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::names::{function_names, Binding, Errors, Names, FUNCTIONS};
use crate::parse::Definition;

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
}

/// A body frame: rotation and origin.
pub struct ModelFrame {
    pub rotation: Mat,
    pub origin: [Id; 3],
}

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
        spatial: false,
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
                }
            }
            Some(Value::Tf(r, t)) => ModelFrame {
                rotation: r,
                origin: t,
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
        points.push(ModelPoint { coords });
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
    for eq in &def.constraints {
        let (l, r) = (cx.expr(&eq.lhs), cx.expr(&eq.rhs));
        match (l, r) {
            (Some(Value::Scalar(a)), Some(Value::Scalar(b))) => {
                let residual = cx.g.sub(a, b);
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
    let spatial = cx.spatial;
    let graph = cx.g;
    let model = Model {
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
    };
    let kinds = coordinate_kinds(&model);
    Model { kinds, ..model }
}

fn count(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// A coordinate is an angle when some sin, cos or tan has it in its argument.
fn coordinate_kinds(model: &Model) -> Vec<CoordKind> {
    let g = &model.graph;
    let mut kinds = vec![CoordKind::Length; model.coords() as usize];
    let leaves: Vec<Option<usize>> = (0..model.coords())
        .map(|j| (0..g.len()).find(|&i| g.node(Id::from_index(i)) == Node::Leaf(Leaf::Q(j))))
        .collect();
    for i in 0..g.len() {
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
    spatial: bool,
    errors: &'a mut Errors,
}

impl Lowerer<'_> {
    /// Lowers `e`; on error reports it and returns `None`.
    fn expr(&mut self, e: &Expr) -> Option<Value> {
        let v = self.expr_inner(e)?;
        self.spatial |= v.is_spatial();
        Some(v)
    }

    fn expr_inner(&mut self, e: &Expr) -> Option<Value> {
        match e {
            Expr::Lit(lit) => match &lit.lit {
                Lit::Float(f) => self.number(f.base10_parse::<f64>(), f.span()),
                Lit::Int(i) => self.number(i.base10_parse::<f64>(), i.span()),
                other => self.fail(
                    other.span(),
                    "only numbers may appear in a mechanism expression",
                ),
            },
            Expr::Path(p) => match p.path.get_ident() {
                Some(ident) => self.name(ident),
                None => self.fail(
                    p.span(),
                    "expected a single name (a parameter, driver, unknown, point or frame)",
                ),
            },
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Unary(u) => {
                let v = self.expr(&u.expr)?;
                match (u.op, v) {
                    (UnOp::Neg(_), Value::Scalar(a)) => Some(Value::Scalar(self.g.neg(a))),
                    (UnOp::Neg(_), Value::Vec2(a)) => Some(Value::Vec2(a.map(|x| self.g.neg(x)))),
                    (UnOp::Neg(_), Value::Vec3(a)) => Some(Value::Vec3(a.map(|x| self.g.neg(x)))),
                    (UnOp::Neg(_), m) => self.fail(
                        u.op.span(),
                        format!(
                            "cannot negate {}; negate the vectors it acts on",
                            m.describe()
                        ),
                    ),
                    _ => self.fail(
                        u.op.span(),
                        "unsupported operator: only `+ - * /` and unary `-` are available",
                    ),
                }
            }
            Expr::Binary(b) => self.binary(b),
            Expr::Field(f) => self.field(f),
            Expr::Call(c) => self.call(c),
            Expr::MethodCall(m) => {
                let name = m.method.to_string();
                let hint = if function_names().any(|f| f == name) {
                    format!("; write `{name}(…)` as a function call")
                } else {
                    String::new()
                };
                self.fail(
                    m.method.span(),
                    format!("method calls are not part of the expression language{hint}"),
                )
            }
            other => self.fail(
                other.span(),
                "this kind of expression is not supported in a mechanism; use numbers, names, \
                 `+ - * /`, parentheses and the built-in functions",
            ),
        }
    }

    fn fail(&mut self, span: Span, msg: impl std::fmt::Display) -> Option<Value> {
        self.errors.at(span, msg);
        None
    }

    fn number(&mut self, parsed: syn::Result<f64>, span: Span) -> Option<Value> {
        match parsed {
            Ok(v) if v.is_finite() => Some(Value::Scalar(self.g.constant(v))),
            _ => self.fail(span, "this number is not a finite `f64`"),
        }
    }

    fn name(&mut self, ident: &syn::Ident) -> Option<Value> {
        let key = syn::ext::IdentExt::unraw(ident).to_string();
        if key == "pi" {
            return Some(Value::Scalar(self.g.constant(std::f64::consts::PI)));
        }
        match self.names.map.get(&key) {
            Some((Binding::Param(i), _)) => Some(Value::Scalar(self.g.leaf(Leaf::Param(*i)))),
            Some((Binding::Coord(j), _)) => Some(Value::Scalar(self.g.leaf(Leaf::Q(*j)))),
            Some((Binding::Point(k), _)) => match self.points.get(&(*k as usize)) {
                Some(c) if c.len() == 2 => Some(Value::Vec2([c[0], c[1]])),
                Some(c) => Some(Value::Vec3([c[0], c[1], c[2]])),
                None => self.fail(
                    ident.span(),
                    format!(
                        "point `{key}` is used before it is defined; a point may only use the \
                         points above it in `points {{ … }}`"
                    ),
                ),
            },
            Some((Binding::Frame(k), _)) => match self.frames.get(&(*k as usize)) {
                Some((r, t)) => Some(Value::Tf(*r, *t)),
                None => self.fail(
                    ident.span(),
                    format!(
                        "frame `{key}` is used before it is defined; a frame may only use the \
                         frames above it in `frames {{ … }}`"
                    ),
                ),
            },
            None => {
                if function_names().any(|f| f == key) {
                    return self.fail(
                        ident.span(),
                        format!("`{key}` is a built-in function; call it as `{key}(…)`"),
                    );
                }
                let hint = match self.names.suggest(&key) {
                    Some(s) => format!("; did you mean `{s}`?"),
                    None => "; declare it in `params`, `drivers`, `unknowns` or `points`".into(),
                };
                self.fail(ident.span(), format!("unknown name `{key}`{hint}"))
            }
        }
    }

    fn vec3_op(&mut self, a: [Id; 3], b: [Id; 3], f: fn(&mut Graph, Id, Id) -> Id) -> [Id; 3] {
        [
            f(&mut self.g, a[0], b[0]),
            f(&mut self.g, a[1], b[1]),
            f(&mut self.g, a[2], b[2]),
        ]
    }

    fn dot3(&mut self, a: [Id; 3], b: [Id; 3]) -> Id {
        let p = self.vec3_op(a, b, Graph::mul);
        let s = self.g.sum(p[0], p[1]);
        self.g.sum(s, p[2])
    }

    fn cross3(&mut self, a: [Id; 3], b: [Id; 3]) -> [Id; 3] {
        let mut out = [a[0]; 3];
        for (i, o) in out.iter_mut().enumerate() {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let l = self.g.mul(a[j], b[k]);
            let r = self.g.mul(a[k], b[j]);
            *o = self.g.sub(l, r);
        }
        out
    }

    fn mat_vec(&mut self, m: &Mat, v: [Id; 3]) -> [Id; 3] {
        [self.dot3(m[0], v), self.dot3(m[1], v), self.dot3(m[2], v)]
    }

    fn mat_mat(&mut self, a: &Mat, b: &Mat) -> Mat {
        let cols = [
            [b[0][0], b[1][0], b[2][0]],
            [b[0][1], b[1][1], b[2][1]],
            [b[0][2], b[1][2], b[2][2]],
        ];
        let mut out = *a;
        for i in 0..3 {
            for j in 0..3 {
                out[i][j] = self.dot3(a[i], cols[j]);
            }
        }
        out
    }

    /// [[R₁, t₁], [0, 1]] · [[R₂, t₂], [0, 1]] = [[R₁R₂, R₁t₂ + t₁], [0, 1]].
    fn tf_tf(&mut self, (r1, t1): (Mat, [Id; 3]), (r2, t2): (Mat, [Id; 3])) -> Value {
        let r = self.mat_mat(&r1, &r2);
        let rt = self.mat_vec(&r1, t2);
        Value::Tf(r, self.vec3_op(rt, t1, Graph::sum))
    }

    fn as_tf(&mut self, v: Value) -> Option<(Mat, [Id; 3])> {
        match v {
            Value::Rot(r) => Some((r, [self.g.constant(0.0); 3])),
            Value::Tf(r, t) => Some((r, t)),
            _ => None,
        }
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> Option<Value> {
        let l = self.expr(&b.left);
        let r = self.expr(&b.right);
        let (l, r) = (l?, r?);
        let span = b.op.span();
        match (b.op, l, r) {
            (BinOp::Add(_) | BinOp::Sub(_), Value::Scalar(a), Value::Scalar(c)) => {
                let f = if matches!(b.op, BinOp::Add(_)) {
                    Graph::sum
                } else {
                    Graph::sub
                };
                Some(Value::Scalar(f(&mut self.g, a, c)))
            }
            (BinOp::Add(_) | BinOp::Sub(_), Value::Vec2(a), Value::Vec2(c)) => {
                let f = if matches!(b.op, BinOp::Add(_)) {
                    Graph::sum
                } else {
                    Graph::sub
                };
                Some(Value::Vec2([
                    f(&mut self.g, a[0], c[0]),
                    f(&mut self.g, a[1], c[1]),
                ]))
            }
            (BinOp::Add(_) | BinOp::Sub(_), Value::Vec3(a), Value::Vec3(c)) => {
                let f = if matches!(b.op, BinOp::Add(_)) {
                    Graph::sum
                } else {
                    Graph::sub
                };
                Some(Value::Vec3(self.vec3_op(a, c, f)))
            }
            (BinOp::Add(_) | BinOp::Sub(_), a, c) => {
                let add = matches!(b.op, BinOp::Add(_));
                let hint = if matches!(
                    (a, c),
                    (Value::Vec2(_), Value::Vec3(_)) | (Value::Vec3(_), Value::Vec2(_))
                ) {
                    "; planar and spatial vectors cannot be mixed (write a planar vector as \
                     `vec3(x, y, 0.0)`)"
                } else {
                    ""
                };
                self.fail(
                    span,
                    format!(
                        "cannot {} {} and {}; both sides of `{}` must have the same dimension{hint}",
                        if add { "add" } else { "subtract" },
                        a.describe(),
                        c.describe(),
                        if add { "+" } else { "-" },
                    ),
                )
            }
            (BinOp::Mul(_), Value::Scalar(a), Value::Scalar(c)) => {
                Some(Value::Scalar(self.g.mul(a, c)))
            }
            (BinOp::Mul(_), Value::Scalar(s), Value::Vec2(v))
            | (BinOp::Mul(_), Value::Vec2(v), Value::Scalar(s)) => {
                Some(Value::Vec2(v.map(|x| self.g.mul(s, x))))
            }
            (BinOp::Mul(_), Value::Scalar(s), Value::Vec3(v))
            | (BinOp::Mul(_), Value::Vec3(v), Value::Scalar(s)) => {
                Some(Value::Vec3(v.map(|x| self.g.mul(s, x))))
            }
            (BinOp::Mul(_), Value::Rot(m), Value::Vec3(v)) => {
                Some(Value::Vec3(self.mat_vec(&m, v)))
            }
            (BinOp::Mul(_), Value::Tf(m, t), Value::Vec3(v)) => {
                // A transform acts on a point: R p + t.
                let rv = self.mat_vec(&m, v);
                Some(Value::Vec3(self.vec3_op(rv, t, Graph::sum)))
            }
            (BinOp::Mul(_), Value::Rot(a), Value::Rot(c)) => Some(Value::Rot(self.mat_mat(&a, &c))),
            (
                BinOp::Mul(_),
                a @ (Value::Rot(_) | Value::Tf(..)),
                c @ (Value::Rot(_) | Value::Tf(..)),
            ) => {
                let (a, c) = (self.as_tf(a)?, self.as_tf(c)?);
                Some(self.tf_tf(a, c))
            }
            (BinOp::Mul(_), Value::Vec2(_), Value::Vec2(_))
            | (BinOp::Mul(_), Value::Vec3(_), Value::Vec3(_)) => self.fail(
                span,
                "cannot multiply two vectors with `*`; use `dot(u, v)` for the scalar product \
                 or `cross(u, v)` for the cross product",
            ),
            (BinOp::Mul(_), a, c) => self.fail(
                span,
                format!(
                    "cannot multiply {} by {}; a rotation or transform multiplies a 3-D vector \
                     or another rotation or transform, and a scalar multiplies a vector",
                    a.describe(),
                    c.describe()
                ),
            ),
            (BinOp::Div(_), Value::Scalar(a), Value::Scalar(c)) => {
                Some(Value::Scalar(self.g.div(a, c)))
            }
            (BinOp::Div(_), Value::Vec2(v), Value::Scalar(s)) => {
                Some(Value::Vec2(v.map(|x| self.g.div(x, s))))
            }
            (BinOp::Div(_), Value::Vec3(v), Value::Scalar(s)) => {
                Some(Value::Vec3(v.map(|x| self.g.div(x, s))))
            }
            (BinOp::Div(_), a, c) => self.fail(
                span,
                format!(
                    "cannot divide {} by {}; only scalars and vectors may be divided, and only by \
                     a scalar",
                    a.describe(),
                    c.describe()
                ),
            ),
            (BinOp::Eq(_), _, _) => self.fail(
                span,
                "`==` may appear only once, between the two sides of an equation",
            ),
            _ => self.fail(
                span,
                "unsupported operator: only `+ - * /` and unary `-` are available",
            ),
        }
    }

    fn field(&mut self, f: &syn::ExprField) -> Option<Value> {
        let base = self.expr(&f.base)?;
        let member = match &f.member {
            syn::Member::Named(n) => n.to_string(),
            syn::Member::Unnamed(i) => i.index.to_string(),
        };
        let index = match member.as_str() {
            "x" => Some(0),
            "y" => Some(1),
            "z" => Some(2),
            _ => None,
        };
        match (base, index) {
            (Value::Vec2(v), Some(i)) if i < 2 => Some(Value::Scalar(v[i])),
            (Value::Vec3(v), Some(i)) => Some(Value::Scalar(v[i])),
            (Value::Vec2(_), _) => self.fail(
                f.member.span(),
                format!("a 2-D vector has components `.x` and `.y`, not `.{member}`"),
            ),
            (Value::Vec3(_), _) => self.fail(
                f.member.span(),
                format!("a 3-D vector has components `.x`, `.y` and `.z`, not `.{member}`"),
            ),
            (v, _) => self.fail(
                f.member.span(),
                format!("`.{member}` needs a vector, but this is {}", v.describe()),
            ),
        }
    }

    /// The rotation by θ about the unit axis u (eq. 32), built symbolically.
    fn rotation(&mut self, u: [Id; 3], theta: Id) -> Mat {
        let s = self.g.call(Func::Sin, theta);
        let c = self.g.call(Func::Cos, theta);
        let one = self.g.constant(1.0);
        let v = self.g.sub(one, c);
        let mut m = [[one; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let uu = self.g.mul(u[i], u[j]);
                let uuv = self.g.mul(uu, v);
                m[i][j] = if i == j {
                    self.g.sum(uuv, c)
                } else {
                    // The skew term ε_ijk u_k sin θ, with the sign of the
                    // permutation (i, j, k).
                    let k = 3 - i - j;
                    let us = self.g.mul(u[k], s);
                    if (j + 3 - i) % 3 == 1 {
                        self.g.sub(uuv, us)
                    } else {
                        self.g.sum(uuv, us)
                    }
                };
            }
        }
        m
    }

    fn axis_rotation(&mut self, axis: usize, theta: Id) -> Mat {
        let (zero, one) = (self.g.constant(0.0), self.g.constant(1.0));
        let mut u = [zero; 3];
        u[axis] = one;
        self.rotation(u, theta)
    }

    fn call(&mut self, c: &syn::ExprCall) -> Option<Value> {
        let Expr::Path(p) = &*c.func else {
            return self.fail(c.func.span(), "expected the name of a built-in function");
        };
        let Some(fname) = p.path.get_ident() else {
            return self.fail(p.span(), "expected the name of a built-in function");
        };
        let name = fname.to_string();
        let span = fname.span();
        let Some(&(_, arity, usage)) = FUNCTIONS.iter().find(|(n, _, _)| *n == name) else {
            let hint = crate::names::suggest_function(&name)
                .map(|s| format!("; did you mean `{s}`?"))
                .unwrap_or_default();
            let all: Vec<&str> = function_names().collect();
            return self.fail(
                span,
                format!(
                    "unknown function `{name}`{hint} (available: {})",
                    all.join(", ")
                ),
            );
        };
        if c.args.len() != arity {
            self.errors.spanned(
                c,
                format!(
                    "`{name}` takes {arity} argument{}, but {} {} given; write `{usage}`",
                    if arity == 1 { "" } else { "s" },
                    c.args.len(),
                    if c.args.len() == 1 { "was" } else { "were" },
                ),
            );
            return None;
        }
        if name == "powi" {
            let base = self.expr(&c.args[0]);
            let n = integer_literal(&c.args[1]);
            let Some(n) = n else {
                self.errors.spanned(
                    &c.args[1],
                    "the exponent of `powi` must be an integer literal, e.g. `powi(x, 2)`; \
                     for other exponents use `exp(k * ln(x))`",
                );
                return None;
            };
            return match base? {
                Value::Scalar(a) => Some(Value::Scalar(self.g.powi(a, n))),
                v => {
                    self.errors.spanned(
                        &c.args[0],
                        format!("`powi` needs a scalar base, but this is {}", v.describe()),
                    );
                    None
                }
            };
        }
        let mut args = Vec::with_capacity(arity);
        let mut ok = true;
        for a in &c.args {
            match self.expr(a) {
                Some(v) => args.push((v, a)),
                None => ok = false,
            }
        }
        if !ok {
            return None;
        }
        let mut a = Args {
            args: &args,
            name: &name,
            usage,
            errors: Vec::new(),
        };
        let value = self.builtin(&name, &mut a);
        if !a.errors.is_empty() {
            for (msg, k) in a.errors {
                self.errors.spanned(args[k].1, msg);
            }
            return None;
        }
        value
    }

    /// Applies a built-in to checked arguments.
    fn builtin(&mut self, name: &str, a: &mut Args<'_>) -> Option<Value> {
        let func = match name {
            "sin" => Some(Func::Sin),
            "cos" => Some(Func::Cos),
            "tan" => Some(Func::Tan),
            "asin" => Some(Func::Asin),
            "acos" => Some(Func::Acos),
            "sqrt" => Some(Func::Sqrt),
            "exp" => Some(Func::Exp),
            "ln" => Some(Func::Ln),
            _ => None,
        };
        if let Some(f) = func {
            let x = a.scalar(0, "the argument")?;
            return Some(Value::Scalar(self.g.call(f, x)));
        }
        match name {
            "atan2" => {
                let (y, x) = (
                    a.scalar(0, "the first argument (y)"),
                    a.scalar(1, "the second argument (x)"),
                );
                Some(Value::Scalar(self.g.atan2(y?, x?)))
            }
            "polar" => {
                let (r, t) = (a.scalar(0, "the length"), a.scalar(1, "the angle"));
                let (r, t) = (r?, t?);
                let c = self.g.call(Func::Cos, t);
                let s = self.g.call(Func::Sin, t);
                Some(Value::Vec2([self.g.mul(r, c), self.g.mul(r, s)]))
            }
            "vec2" => {
                let (x, y) = (
                    a.scalar(0, "the x component"),
                    a.scalar(1, "the y component"),
                );
                Some(Value::Vec2([x?, y?]))
            }
            "vec3" => {
                let x = a.scalar(0, "the x component");
                let y = a.scalar(1, "the y component");
                let z = a.scalar(2, "the z component");
                Some(Value::Vec3([x?, y?, z?]))
            }
            "norm" => match a.get(0) {
                Value::Vec2(v) => {
                    let (x2, y2) = (self.g.powi(v[0], 2), self.g.powi(v[1], 2));
                    let s = self.g.sum(x2, y2);
                    Some(Value::Scalar(self.g.call(Func::Sqrt, s)))
                }
                Value::Vec3(v) => {
                    let s = self.dot3(v, v);
                    Some(Value::Scalar(self.g.call(Func::Sqrt, s)))
                }
                _ => a.vector_error(0),
            },
            "dot" | "cross" => match (a.get(0), a.get(1)) {
                (Value::Vec2(u), Value::Vec2(v)) => {
                    let (p, q) = if name == "dot" {
                        (self.g.mul(u[0], v[0]), self.g.mul(u[1], v[1]))
                    } else {
                        let p = self.g.mul(u[0], v[1]);
                        let q = self.g.mul(u[1], v[0]);
                        (p, self.g.neg(q))
                    };
                    Some(Value::Scalar(self.g.sum(p, q)))
                }
                (Value::Vec3(u), Value::Vec3(v)) => Some(if name == "dot" {
                    Value::Scalar(self.dot3(u, v))
                } else {
                    Value::Vec3(self.cross3(u, v))
                }),
                (Value::Vec2(_) | Value::Vec3(_), Value::Vec2(_) | Value::Vec3(_)) => {
                    a.error(
                        1,
                        format!("`{name}` needs two vectors of the same dimension"),
                    );
                    None
                }
                (Value::Vec2(_) | Value::Vec3(_), _) => a.vector_error(1),
                _ => a.vector_error(0),
            },
            "rot_x" | "rot_y" | "rot_z" => {
                let t = a.scalar(0, "the angle")?;
                let axis = usize::from(name.as_bytes()[4] - b'x');
                Some(Value::Rot(self.axis_rotation(axis, t)))
            }
            "rot" => {
                let axis = a.vec3(0, "the axis");
                let t = a.scalar(1, "the angle");
                let (axis, t) = (axis?, t?);
                let u = self.normalize(axis);
                Some(Value::Rot(self.rotation(u, t)))
            }
            "translation" => {
                let v = a.vec3(0, "the translation")?;
                let zero = self.g.constant(0.0);
                let r = self.axis_rotation(2, zero);
                Some(Value::Tf(r, v))
            }
            "t1" | "t2" | "t3" | "t4" | "t5" | "t6" => {
                let k = usize::from(name.as_bytes()[1] - b'1');
                let axis = k % 3;
                let abc = [a.scalar(0, "a"), a.scalar(1, "b"), a.scalar(2, "c")];
                let t = a.scalar(3, "the angle");
                let lead = if k >= 3 {
                    Some(a.scalar(4, "the lead"))
                } else {
                    None
                };
                let mut abc = [abc[0]?, abc[1]?, abc[2]?];
                let t = t?;
                if let Some(lead) = lead {
                    // Screw advance kθ/2π along the axis.
                    let kt = self.g.mul(lead?, t);
                    let tau = self.g.constant(std::f64::consts::TAU);
                    let adv = self.g.div(kt, tau);
                    abc[axis] = self.g.sum(abc[axis], adv);
                }
                Some(Value::Tf(self.axis_rotation(axis, t), abc))
            }
            "t7" => {
                let abc = [a.scalar(0, "a"), a.scalar(1, "b"), a.scalar(2, "c")];
                let zero = self.g.constant(0.0);
                let r = self.axis_rotation(2, zero);
                Some(Value::Tf(r, [abc[0]?, abc[1]?, abc[2]?]))
            }
            "screw" | "screw_about" => {
                let about = name == "screw_about";
                let axis = a.vec3(0, "the axis");
                let point = if about {
                    Some(a.vec3(1, "the point on the axis"))
                } else {
                    None
                };
                let o = usize::from(about);
                let t = a.scalar(1 + o, "the angle");
                let slide = a.scalar(2 + o, "the slide along the axis");
                let (axis, t, slide) = (axis?, t?, slide?);
                let u = self.normalize(axis);
                let r = self.rotation(u, t);
                let mut d = u.map(|x| self.g.mul(x, slide));
                if let Some(p) = point {
                    // Δû + P − R P
                    let p = p?;
                    let rp = self.mat_vec(&r, p);
                    let pr = self.vec3_op(p, rp, Graph::sub);
                    d = self.vec3_op(d, pr, Graph::sum);
                }
                Some(Value::Tf(r, d))
            }
            "spherical" => {
                let off = a.vec3(0, "the offset");
                let (t1, t2, t3) = (
                    a.scalar(1, "the first angle (about z)"),
                    a.scalar(2, "the second angle (about x)"),
                    a.scalar(3, "the third angle (about z)"),
                );
                let (off, t1, t2, t3) = (off?, t1?, t2?, t3?);
                let rz1 = self.axis_rotation(2, t1);
                let rx = self.axis_rotation(0, t2);
                let rz2 = self.axis_rotation(2, t3);
                let r = self.mat_mat(&rz1, &rx);
                let r = self.mat_mat(&r, &rz2);
                Some(Value::Tf(r, off))
            }
            _ => None,
        }
    }

    fn normalize(&mut self, v: [Id; 3]) -> [Id; 3] {
        let n2 = self.dot3(v, v);
        let n = self.g.call(Func::Sqrt, n2);
        v.map(|x| self.g.div(x, n))
    }
}

/// Checked access to the arguments of a built-in, collecting errors.
struct Args<'a> {
    args: &'a [(Value, &'a Expr)],
    name: &'a str,
    usage: &'static str,
    /// Errors found, with the index of the argument they concern.
    errors: Vec<(String, usize)>,
}

impl Args<'_> {
    fn get(&self, k: usize) -> Value {
        self.args[k].0
    }

    fn error(&mut self, k: usize, msg: String) {
        self.errors.push((msg, k));
    }

    fn scalar(&mut self, k: usize, role: &str) -> Option<Id> {
        match self.get(k) {
            Value::Scalar(id) => Some(id),
            v => {
                let msg = format!(
                    "{role} of `{}` must be a scalar, but this is {}; write `{}`",
                    self.name,
                    v.describe(),
                    self.usage
                );
                self.error(k, msg);
                None
            }
        }
    }

    fn vec3(&mut self, k: usize, role: &str) -> Option<[Id; 3]> {
        match self.get(k) {
            Value::Vec3(v) => Some(v),
            v => {
                let msg = format!(
                    "{role} of `{}` must be a 3-D vector, but this is {}; build it with \
                     `vec3(x, y, z)`",
                    self.name,
                    v.describe()
                );
                self.error(k, msg);
                None
            }
        }
    }

    fn vector_error(&mut self, k: usize) -> Option<Value> {
        let msg = format!(
            "`{}` takes vectors, but this argument is {}; build one with `vec2(x, y)`, \
             `polar(r, angle)` or `vec3(x, y, z)`",
            self.name,
            self.get(k).describe()
        );
        self.error(k, msg);
        None
    }
}

fn integer_literal(e: &Expr) -> Option<i32> {
    match e {
        Expr::Lit(syn::ExprLit {
            lit: Lit::Int(i), ..
        }) => i.base10_parse::<i32>().ok(),
        Expr::Unary(syn::ExprUnary {
            op: UnOp::Neg(_),
            expr,
            ..
        }) => integer_literal(expr).and_then(i32::checked_neg),
        Expr::Paren(p) => integer_literal(&p.expr),
        _ => None,
    }
}
