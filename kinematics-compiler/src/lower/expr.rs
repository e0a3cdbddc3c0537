//! Lowering of expressions: names, numbers, operators, fields, and the
//! vector and matrix algebra they need.

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, UnOp};

use super::{Lowerer, Mat, Value};
use crate::ir::{Func, Graph, Id, Leaf};
use crate::names::{function_names, Binding};

impl Lowerer<'_> {
    /// Lowers `e`; on error reports it and returns `None`.
    pub(super) fn expr(&mut self, e: &Expr) -> Option<Value> {
        let v = self.expr_inner(e)?;
        self.spatial |= v.is_spatial();
        let scalars: &[Id] = match &v {
            Value::Scalar(a) => core::slice::from_ref(a),
            Value::Vec2(a) => a,
            Value::Vec3(a) => a,
            Value::Rot(_) | Value::Tf(..) => &[],
        };
        for &id in scalars {
            self.finite_numbers(id, e)?;
        }
        Some(v)
    }

    /// An operation on numbers alone is folded into its value when that
    /// is finite; one left unfolded overflowed or is undefined (`1e300 *
    /// 1e300`, `0.0 / 0.0`, `ln(0.0)`): reported here, at the expression
    /// that first gives it, rather than as a NaN when the model runs.
    /// Every operation under `id` is checked, the built-ins' own among
    /// them (`norm(vec2(1e200, 1e200))` squares 1e200).
    fn finite_numbers(&mut self, id: Id, e: &Expr) -> Option<()> {
        let mut stack = vec![id];
        let mut seen = std::collections::HashSet::new();
        while let Some(n) = stack.pop() {
            let node = self.g.node(n);
            if !node.is_operation() || !seen.insert(n) {
                continue;
            }
            if !node.children().all(|c| self.g.as_const(c).is_some()) {
                stack.extend(node.children());
                continue;
            }
            let value = self.g.eval(&[n], &|_| f64::NAN).first().copied()?;
            if !value.is_finite() {
                self.fail(
                    e.span(),
                    format!(
                        "these numbers give {value}, not a finite number; check the exponents \
                         and divisors written here"
                    ),
                )?;
            }
        }
        Some(())
    }

    pub(super) fn expr_inner(&mut self, e: &Expr) -> Option<Value> {
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

    pub(super) fn fail(&mut self, span: Span, msg: impl std::fmt::Display) -> Option<Value> {
        self.errors.at(span, msg);
        None
    }

    pub(super) fn number(&mut self, parsed: syn::Result<f64>, span: Span) -> Option<Value> {
        match parsed {
            Ok(v) if v.is_finite() => Some(Value::Scalar(self.g.constant(v))),
            _ => self.fail(span, "this number is not a finite `f64`"),
        }
    }

    pub(super) fn name(&mut self, ident: &syn::Ident) -> Option<Value> {
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
            None if key == "time" => {
                if self.rates {
                    return Some(Value::Scalar(self.g.leaf(Leaf::Time)));
                }
                self.fail(
                    ident.span(),
                    "`time`, the time of a forward simulation (s), may be used only in the value \
                     of a `force(…)` or a `torque(…)` in `loads { … }`: the points, frames and \
                     loops are functions of the coordinates, and masses, inertias, gravity and a \
                     spring's constants of the parameters",
                )
            }
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

    pub(super) fn vec3_op(
        &mut self,
        a: [Id; 3],
        b: [Id; 3],
        f: fn(&mut Graph, Id, Id) -> Id,
    ) -> [Id; 3] {
        [
            f(&mut self.g, a[0], b[0]),
            f(&mut self.g, a[1], b[1]),
            f(&mut self.g, a[2], b[2]),
        ]
    }

    pub(super) fn dot3(&mut self, a: [Id; 3], b: [Id; 3]) -> Id {
        let p = self.vec3_op(a, b, Graph::mul);
        let s = self.g.sum(p[0], p[1]);
        self.g.sum(s, p[2])
    }

    pub(super) fn cross3(&mut self, a: [Id; 3], b: [Id; 3]) -> [Id; 3] {
        self.g.cross3(a, b)
    }

    /// A transform [[R, o], [0, 1]] acting on a point: R v + o, recorded as
    /// fixed in the body when R is a chain and v free of the coordinates.
    fn body_point(&mut self, m: &Mat, origin: [Id; 3], v: [Id; 3]) -> [Id; 3] {
        let offset = self.mat_vec(m, v);
        let p = self.vec3_op(offset, origin, Graph::sum);
        let moving = v
            .iter()
            .any(|&x| self.g.depends_on(x, &|l| matches!(l, Leaf::Q(_))));
        if let (false, Some(chain)) = (moving, self.chains.get(m).cloned()) {
            let body = self.body(m, origin);
            let attached = super::Attached {
                chain,
                origin,
                body,
                offset,
            };
            self.attached.entry(p).or_insert(attached);
        }
        p
    }

    pub(super) fn mat_vec(&mut self, m: &Mat, v: [Id; 3]) -> [Id; 3] {
        [self.dot3(m[0], v), self.dot3(m[1], v), self.dot3(m[2], v)]
    }

    pub(super) fn mat_mat(&mut self, a: &Mat, b: &Mat) -> Mat {
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
        // The product of two chains: b's axes carried into a's fixed
        // coordinates, z ↦ A z.
        if let (Some(first), Some(second)) = (self.chains.get(a), self.chains.get(b)) {
            let (mut chain, second) = (first.clone(), second.clone());
            for (z, theta) in second {
                chain.push((self.mat_vec(a, z), theta));
            }
            self.chains.entry(out).or_insert(chain);
        }
        out
    }

    /// [[R₁, t₁], [0, 1]] · [[R₂, t₂], [0, 1]] = [[R₁R₂, R₁t₂ + t₁], [0, 1]].
    pub(super) fn tf_tf(&mut self, (r1, t1): (Mat, [Id; 3]), (r2, t2): (Mat, [Id; 3])) -> Value {
        let r = self.mat_mat(&r1, &r2);
        let rt = self.mat_vec(&r1, t2);
        let t = self.vec3_op(rt, t1, Graph::sum);
        // Along the chain: the second body's axes and segments carried into
        // the first's fixed coordinates, its segments after the first's
        // rotations.
        if let (Some(first), Some(second)) = (self.body(&r1, t1), self.body(&r2, t2)) {
            let mut body = first.clone();
            let n = first.chain.len();
            for (z, theta) in second.chain {
                body.chain.push((self.mat_vec(&r1, z), theta));
            }
            for (seg, k) in second.segments {
                body.segments.push((self.mat_vec(&r1, seg), n + k));
            }
            self.bodies.entry((r, t)).or_insert(body);
        }
        Value::Tf(r, t)
    }

    /// The transform (R, o) as a [`Body`](super::Body): as built by
    /// [`Self::tf_tf`], or, for a rotation R along a chain and an origin o
    /// free of the coordinates, the one segment o before R's rotations.
    pub(super) fn body(&mut self, r: &Mat, o: [Id; 3]) -> Option<super::Body> {
        if let Some(b) = self.bodies.get(&(*r, o)) {
            return Some(b.clone());
        }
        let moving = o
            .iter()
            .any(|&x| self.g.depends_on(x, &|l| matches!(l, Leaf::Q(_))));
        let chain = self.chains.get(r)?.clone();
        (!moving).then(|| super::Body {
            chain,
            segments: vec![(o, 0)],
        })
    }

    pub(super) fn as_tf(&mut self, v: Value) -> Option<(Mat, [Id; 3])> {
        match v {
            Value::Rot(r) => Some((r, [self.g.constant(0.0); 3])),
            Value::Tf(r, t) => Some((r, t)),
            _ => None,
        }
    }

    pub(super) fn binary(&mut self, b: &syn::ExprBinary) -> Option<Value> {
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
                let zero = self.g.constant(0.0);
                Some(Value::Vec3(self.body_point(&m, [zero; 3], v)))
            }
            (BinOp::Mul(_), Value::Tf(m, t), Value::Vec3(v)) => {
                Some(Value::Vec3(self.body_point(&m, t, v)))
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

    pub(super) fn field(&mut self, f: &syn::ExprField) -> Option<Value> {
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
    pub(super) fn rotation(&mut self, u: [Id; 3], theta: Id) -> Mat {
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
        // An axis fixed in time (free of the coordinates) starts a chain.
        let moving = u
            .iter()
            .any(|&x| self.g.depends_on(x, &|l| matches!(l, Leaf::Q(_))));
        if !moving {
            self.chains.entry(m).or_insert_with(|| vec![(u, theta)]);
        }
        m
    }

    pub(super) fn axis_rotation(&mut self, axis: usize, theta: Id) -> Mat {
        let (zero, one) = (self.g.constant(0.0), self.g.constant(1.0));
        let mut u = [zero; 3];
        u[axis] = one;
        self.rotation(u, theta)
    }
}
