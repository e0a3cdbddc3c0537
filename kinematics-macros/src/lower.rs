//! Lowering: the syntax tree to scalar expressions in the DAG.
//!
//! Each expression is typed as it is lowered (a scalar or a 2-D vector);
//! vectors are split into their components. Type errors point at the operator
//! or call that is wrong. Equations become residuals `lhs − rhs`, one per
//! scalar component, and are counted against the unknowns.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, UnOp};

use crate::check::{Binding, Errors, Names};
use crate::ir::{Func, Graph, Id, Leaf, Node};
use crate::parse::Definition;

/// A lowered value.
#[derive(Clone, Copy, Debug)]
enum Value {
    Scalar(Id),
    Vec2([Id; 2]),
}

impl Value {
    fn describe(self) -> &'static str {
        match self {
            Value::Scalar(_) => "a scalar",
            Value::Vec2(_) => "a 2-D vector",
        }
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

/// A point of interest, component by component.
pub struct ModelPoint {
    pub xy: [Id; 2],
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
    pub kinds: Vec<CoordKind>,
}

impl Model {
    /// Number of coordinates (drivers and unknowns).
    pub fn coords(&self) -> u32 {
        self.drivers + self.unknowns
    }
}

/// Lowers every point and equation of `def`, reporting type and counting
/// errors into `errors`.
pub fn lower(def: &Definition, names: &Names, errors: &mut Errors) -> Model {
    let mut cx = Lowerer {
        g: Graph::new(),
        names,
        points: HashMap::new(),
        errors,
    };
    let mut points = Vec::new();
    for (k, p) in def.points.iter().enumerate() {
        match cx.expr(&p.expr) {
            Some(Value::Vec2(xy)) => {
                cx.points.insert(k, xy);
                points.push(ModelPoint { xy });
            }
            Some(v @ Value::Scalar(_)) => {
                cx.errors.spanned(
                    &p.expr,
                    format!(
                        "point `{}` must be a 2-D vector, but this expression is {}; \
                         build it with `vec2(x, y)` or `polar(r, angle)`",
                        p.name,
                        v.describe()
                    ),
                );
            }
            None => {}
        }
        if !cx.points.contains_key(&k) {
            // Keep later uses from cascading into "unknown point" errors.
            let nan = cx.g.constant(0.0);
            cx.points.insert(k, [nan, nan]);
            points.push(ModelPoint { xy: [nan, nan] });
        }
    }
    let mut equations = Vec::new();
    for eq in &def.loops {
        let (l, r) = (cx.expr(&eq.lhs), cx.expr(&eq.rhs));
        match (l, r) {
            (Some(Value::Vec2(a)), Some(Value::Vec2(b))) => {
                for (c, axis) in ["x", "y"].iter().enumerate() {
                    let residual = cx.g.sub(a[c], b[c]);
                    equations.push(ModelEquation {
                        residual,
                        text: format!("{} ({axis} component)", eq.text),
                        tokens: eq.tokens.clone(),
                    });
                }
            }
            (Some(Value::Scalar(_)), Some(Value::Scalar(_))) => cx.errors.spanned(
                &eq.tokens,
                "this loop equation is scalar; a loop closes a chain of vectors \
                 (`B + polar(b, th3) == C`). Move scalar equations to `constraints { … }`",
            ),
            (Some(a), Some(b)) => cx.errors.spanned(
                &eq.tokens,
                format!(
                    "the two sides of this loop have different dimensions: the left is {} \
                     and the right is {}",
                    a.describe(),
                    b.describe()
                ),
            ),
            _ => {}
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
            (Some(Value::Vec2(_)), Some(Value::Vec2(_))) => cx.errors.spanned(
                &eq.tokens,
                "this constraint equates two vectors; vector equations belong in \
                 `loops { … }` (each gives two scalar equations)",
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
    let graph = cx.g;
    let model = Model {
        kinds: Vec::new(),
        drivers: count(def.drivers.len()),
        unknowns: count(def.unknowns.len()),
        equations,
        points,
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
    for i in 0..g.len() {
        if let Node::Call(Func::Sin | Func::Cos | Func::Tan, arg) = g.node(Id::from_index(i)) {
            let live = g.reachable(&[arg]);
            for (j, kind) in kinds.iter_mut().enumerate() {
                let leaf = g_leaf_index(g, Leaf::Q(count(j)));
                if leaf.is_some_and(|l| live[l]) {
                    *kind = CoordKind::Angle;
                }
            }
        }
    }
    kinds
}

fn g_leaf_index(g: &Graph, leaf: Leaf) -> Option<usize> {
    (0..g.len()).find(|&i| g.node(Id::from_index(i)) == Node::Leaf(leaf))
}

struct Lowerer<'a> {
    g: Graph,
    names: &'a Names,
    /// Points lowered so far, by index.
    points: HashMap<usize, [Id; 2]>,
    errors: &'a mut Errors,
}

impl Lowerer<'_> {
    /// Lowers `e`; on error reports it and returns `None`.
    fn expr(&mut self, e: &Expr) -> Option<Value> {
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
                    "expected a single name (a parameter, driver, unknown or point)",
                ),
            },
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Unary(u) => {
                let v = self.expr(&u.expr)?;
                match u.op {
                    UnOp::Neg(_) => Some(self.map(v, Graph::neg)),
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
                let hint = if crate::check::BUILTINS.contains(&name.as_str()) {
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
                Some(xy) => Some(Value::Vec2(*xy)),
                None => self.fail(
                    ident.span(),
                    format!(
                        "point `{key}` is used before it is defined; a point may only use the \
                         points above it in `points {{ … }}`"
                    ),
                ),
            },
            None => {
                let hint = match self.names.suggest(&key) {
                    Some(s) => format!("; did you mean `{s}`?"),
                    None => "; declare it in `params`, `drivers`, `unknowns` or `points`".into(),
                };
                if crate::check::BUILTINS.contains(&key.as_str()) {
                    return self.fail(
                        ident.span(),
                        format!("`{key}` is a built-in function; call it as `{key}(…)`"),
                    );
                }
                self.fail(ident.span(), format!("unknown name `{key}`{hint}"))
            }
        }
    }

    fn map(&mut self, v: Value, f: fn(&mut Graph, Id) -> Id) -> Value {
        match v {
            Value::Scalar(a) => Value::Scalar(f(&mut self.g, a)),
            Value::Vec2([x, y]) => Value::Vec2([f(&mut self.g, x), f(&mut self.g, y)]),
        }
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> Option<Value> {
        let l = self.expr(&b.left);
        let r = self.expr(&b.right);
        let (l, r) = (l?, r?);
        let span = b.op.span();
        let g = &mut self.g;
        match (b.op, l, r) {
            (BinOp::Add(_), Value::Scalar(a), Value::Scalar(c)) => Some(Value::Scalar(g.sum(a, c))),
            (BinOp::Sub(_), Value::Scalar(a), Value::Scalar(c)) => Some(Value::Scalar(g.sub(a, c))),
            (BinOp::Add(_), Value::Vec2(a), Value::Vec2(c)) => {
                Some(Value::Vec2([g.sum(a[0], c[0]), g.sum(a[1], c[1])]))
            }
            (BinOp::Sub(_), Value::Vec2(a), Value::Vec2(c)) => {
                Some(Value::Vec2([g.sub(a[0], c[0]), g.sub(a[1], c[1])]))
            }
            (BinOp::Add(_) | BinOp::Sub(_), a, c) => self.fail(
                span,
                format!(
                    "cannot {} {} and {}; both sides of `{}` must have the same dimension",
                    if matches!(b.op, BinOp::Add(_)) {
                        "add"
                    } else {
                        "subtract"
                    },
                    a.describe(),
                    c.describe(),
                    if matches!(b.op, BinOp::Add(_)) {
                        "+"
                    } else {
                        "-"
                    },
                ),
            ),
            (BinOp::Mul(_), Value::Scalar(a), Value::Scalar(c)) => Some(Value::Scalar(g.mul(a, c))),
            (BinOp::Mul(_), Value::Scalar(s), Value::Vec2(v))
            | (BinOp::Mul(_), Value::Vec2(v), Value::Scalar(s)) => {
                Some(Value::Vec2([g.mul(s, v[0]), g.mul(s, v[1])]))
            }
            (BinOp::Mul(_), Value::Vec2(_), Value::Vec2(_)) => self.fail(
                span,
                "cannot multiply two vectors with `*`; use `dot(u, v)` for the scalar product \
                 or `cross(u, v)` for the planar cross product",
            ),
            (BinOp::Div(_), Value::Scalar(a), Value::Scalar(c)) => Some(Value::Scalar(g.div(a, c))),
            (BinOp::Div(_), Value::Vec2(v), Value::Scalar(s)) => {
                Some(Value::Vec2([g.div(v[0], s), g.div(v[1], s)]))
            }
            (BinOp::Div(_), _, c @ Value::Vec2(_)) => self.fail(
                span,
                format!(
                    "cannot divide by {}; the divisor must be a scalar",
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
        match (base, member.as_str()) {
            (Value::Vec2([x, _]), "x") => Some(Value::Scalar(x)),
            (Value::Vec2([_, y]), "y") => Some(Value::Scalar(y)),
            (Value::Vec2(_), _) => self.fail(
                f.member.span(),
                format!("a 2-D vector has components `.x` and `.y`, not `.{member}`"),
            ),
            (Value::Scalar(_), _) => self.fail(
                f.member.span(),
                format!("`.{member}` needs a vector, but this is a scalar"),
            ),
        }
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
        let arity = match name.as_str() {
            "sin" | "cos" | "tan" | "asin" | "acos" | "sqrt" | "exp" | "ln" | "norm" => 1,
            "atan2" | "powi" | "polar" | "vec2" | "dot" | "cross" => 2,
            _ => {
                let hint = self
                    .names
                    .suggest(&name)
                    .filter(|s| crate::check::BUILTINS.contains(&s.as_str()))
                    .map(|s| format!("; did you mean `{s}`?"))
                    .unwrap_or_default();
                return self.fail(
                    span,
                    format!(
                        "unknown function `{name}`{hint} (available: sin, cos, tan, asin, acos, \
                         atan2, sqrt, exp, ln, powi, polar, vec2, dot, norm, cross)"
                    ),
                );
            }
        };
        if c.args.len() != arity {
            let usage = usage(&name);
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
        let scalar = |cx: &mut Self, k: usize, role: &str| match args[k].0 {
            Value::Scalar(id) => Some(id),
            v => {
                cx.errors.spanned(
                    args[k].1,
                    format!(
                        "{role} of `{name}` must be a scalar, but this is {}",
                        v.describe()
                    ),
                );
                None
            }
        };
        let vector = |cx: &mut Self, k: usize| match args[k].0 {
            Value::Vec2(v) => Some(v),
            v => {
                cx.errors.spanned(
                    args[k].1,
                    format!(
                        "`{name}` takes 2-D vectors, but this argument is {}; build one with \
                         `vec2(x, y)` or `polar(r, angle)`",
                        v.describe()
                    ),
                );
                None
            }
        };
        let func = match name.as_str() {
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
            let a = scalar(self, 0, "the argument")?;
            return Some(Value::Scalar(self.g.call(f, a)));
        }
        match name.as_str() {
            "atan2" => {
                let y = scalar(self, 0, "the first argument (y)");
                let x = scalar(self, 1, "the second argument (x)");
                Some(Value::Scalar(self.g.atan2(y?, x?)))
            }
            "polar" => {
                let r = scalar(self, 0, "the length");
                let t = scalar(self, 1, "the angle");
                let (r, t) = (r?, t?);
                let c = self.g.call(Func::Cos, t);
                let s = self.g.call(Func::Sin, t);
                Some(Value::Vec2([self.g.mul(r, c), self.g.mul(r, s)]))
            }
            "vec2" => {
                let x = scalar(self, 0, "the x component");
                let y = scalar(self, 1, "the y component");
                Some(Value::Vec2([x?, y?]))
            }
            "norm" => {
                let v = vector(self, 0)?;
                let x2 = self.g.powi(v[0], 2);
                let y2 = self.g.powi(v[1], 2);
                let s = self.g.sum(x2, y2);
                Some(Value::Scalar(self.g.call(Func::Sqrt, s)))
            }
            "dot" | "cross" => {
                let u = vector(self, 0);
                let v = vector(self, 1);
                let (u, v) = (u?, v?);
                let (a, b) = if name == "dot" {
                    (self.g.mul(u[0], v[0]), self.g.mul(u[1], v[1]))
                } else {
                    let a = self.g.mul(u[0], v[1]);
                    let b = self.g.mul(u[1], v[0]);
                    (a, self.g.neg(b))
                };
                Some(Value::Scalar(self.g.sum(a, b)))
            }
            _ => None,
        }
    }
}

fn usage(name: &str) -> &'static str {
    match name {
        "atan2" => "atan2(y, x)",
        "powi" => "powi(x, n)",
        "polar" => "polar(length, angle)",
        "vec2" => "vec2(x, y)",
        "dot" => "dot(u, v)",
        "cross" => "cross(u, v)",
        "norm" => "norm(v)",
        _ => "f(x)",
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
