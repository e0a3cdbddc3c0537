//! Lowering of the built-in functions (trigonometry, vectors, rotations,
//! transforms, joints), with their arity and argument checks.

use syn::spanned::Spanned;
use syn::{Expr, Lit, UnOp};

use super::{Lowerer, Value};
use crate::ir::{Func, Graph, Id};
use crate::names::{function_names, Binding, FUNCTIONS};

impl Lowerer<'_> {
    pub(super) fn call(&mut self, c: &syn::ExprCall) -> Option<Value> {
        let Expr::Path(p) = &*c.func else {
            return self.fail(c.func.span(), "expected the name of a built-in function");
        };
        let Some(fname) = p.path.get_ident() else {
            return self.fail(p.span(), "expected the name of a built-in function");
        };
        let name = fname.to_string();
        let span = fname.span();
        if let Some((binding, _)) = self.names.map.get(&name) {
            let what = match binding {
                Binding::Param(_) => "parameter",
                Binding::Coord(_) => "coordinate",
                Binding::Point(_) => "point",
                Binding::Frame(_) => "frame",
            };
            return self.fail(
                span,
                format!(
                    "`{name}` is a {what} of this definition, so it is not the built-in function \
                     `{name}(…)` here: rename the {what} to call the function"
                ),
            );
        }
        if name == "rate" {
            return self.rate(c);
        }
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
            if n.unsigned_abs() > crate::limits::MAX_POWI_EXPONENT {
                self.errors.spanned(
                    &c.args[1],
                    format!(
                        "the exponent of `powi` is {n}, outside the range ±{} it may take; \
                         for larger exponents use `exp(k * ln(x))`",
                        crate::limits::MAX_POWI_EXPONENT
                    ),
                );
                return None;
            }
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
    pub(super) fn builtin(&mut self, name: &str, a: &mut Args<'_>) -> Option<Value> {
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

    pub(super) fn normalize(&mut self, v: [Id; 3]) -> [Id; 3] {
        let n2 = self.dot3(v, v);
        let n = self.g.call(Func::Sqrt, n2);
        v.map(|x| self.g.div(x, n))
    }
}

/// Checked access to the arguments of a built-in, collecting errors.
pub(super) struct Args<'a> {
    args: &'a [(Value, &'a Expr)],
    name: &'a str,
    usage: &'static str,
    /// Errors found, with the index of the argument they concern.
    errors: Vec<(String, usize)>,
}

impl Args<'_> {
    pub(super) fn get(&self, k: usize) -> Value {
        self.args[k].0
    }

    pub(super) fn error(&mut self, k: usize, msg: String) {
        self.errors.push((msg, k));
    }

    pub(super) fn scalar(&mut self, k: usize, role: &str) -> Option<Id> {
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

    pub(super) fn vec3(&mut self, k: usize, role: &str) -> Option<[Id; 3]> {
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

    pub(super) fn vector_error(&mut self, k: usize) -> Option<Value> {
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

pub(super) fn integer_literal(e: &Expr) -> Option<i32> {
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
