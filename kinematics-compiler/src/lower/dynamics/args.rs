//! The arguments of the `bodies`, `loads` and `joints` items: known keys,
//! scalars and vectors checked against what they may depend on, and the
//! names of points, frames and bodies they refer to; and `rate(x)`.

use syn::spanned::Spanned;
use syn::Expr;

use super::super::{Lowerer, Value};
use super::{Allowed, GROUND};
use crate::ir::{Id, Leaf};
use crate::names::Binding;
use crate::parse::Call;

impl Lowerer<'_> {
    /// `Some(())` when every key of `item` is one of `keys`.
    pub(super) fn known_keys(&mut self, item: &Call, keys: &[&str]) -> Option<()> {
        let mut ok = true;
        for (key, _) in &item.named {
            let k = key.to_string();
            if !keys.contains(&k.as_str()) {
                let list = if keys.is_empty() {
                    "none".to_owned()
                } else {
                    keys.iter()
                        .map(|k| format!("`{k}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                self.errors.at(
                    key.span(),
                    format!("`{}` takes no `{k}`; its keys: {list}", item.name),
                );
                ok = false;
            }
        }
        ok.then_some(())
    }

    /// The value of `key = value` in `item`.
    pub(super) fn named<'e>(&self, item: &'e Call, key: &str) -> Option<&'e Expr> {
        item.named.iter().find(|(k, _)| k == key).map(|(_, e)| e)
    }

    /// A scalar expression that depends on what `allowed` lets it.
    pub(super) fn scalar(&mut self, e: &Expr, allowed: Allowed, what: &str) -> Option<Id> {
        match self.motion_expr(e, allowed)? {
            Value::Scalar(id) => self.constant_check(e, id, allowed, what),
            v => {
                self.errors.spanned(
                    e,
                    format!(
                        "{what} must be a scalar, but this expression is {}",
                        v.describe()
                    ),
                );
                None
            }
        }
    }

    /// A vector of the mechanism's dimension.
    pub(super) fn vector(
        &mut self,
        e: &Expr,
        dim: usize,
        allowed: Allowed,
        what: &str,
    ) -> Option<Vec<Id>> {
        let v = self.motion_expr(e, allowed)?;
        let ids = match v {
            Value::Vec2(a) if dim == 2 => a.to_vec(),
            Value::Vec3(a) if dim == 3 => a.to_vec(),
            v => {
                let (write, kind) = if dim == 2 {
                    ("vec2(x, y)", "planar")
                } else {
                    ("vec3(x, y, z)", "spatial")
                };
                self.errors.spanned(
                    e,
                    format!(
                        "{what} must be a {dim}-D vector (the mechanism is {kind}; write \
                         `{write}`), but this expression is {}",
                        v.describe()
                    ),
                );
                return None;
            }
        };
        for &id in &ids {
            self.constant_check(e, id, allowed, what)?;
        }
        Some(ids)
    }

    /// Lowers `e` with `rate(x)` available where the coordinates are.
    pub(super) fn motion_expr(&mut self, e: &Expr, allowed: Allowed) -> Option<Value> {
        let rates = self.rates;
        self.rates = allowed == Allowed::Motion;
        let v = self.expr(e);
        self.rates = rates;
        v
    }

    /// `id` when it depends on no coordinate (or when `allowed` lets it).
    pub(super) fn constant_check(
        &mut self,
        e: &Expr,
        id: Id,
        allowed: Allowed,
        what: &str,
    ) -> Option<Id> {
        if allowed == Allowed::Constant {
            let moving = self
                .g
                .leaves_under(id)
                .find(|l| !matches!(l, Leaf::Param(_)));
            if moving == Some(Leaf::Time) {
                // Unreachable while `time` lowers only where rates do; kept
                // so that a constant can never read it.
                self.errors
                    .spanned(e, format!("{what} is a constant: it may not use `time`"));
                return None;
            }
            if let Some(Leaf::Q(j) | Leaf::Qd(j) | Leaf::Qdd(j)) = moving {
                let name = self
                    .names
                    .map
                    .iter()
                    .find(|(_, (b, _))| *b == Binding::Coord(j))
                    .map_or_else(String::new, |(n, _)| n.clone());
                self.errors.spanned(
                    e,
                    format!(
                        "{what} is a constant: it may use the parameters and numbers, but this \
                         expression uses the coordinate `{name}`"
                    ),
                );
                return None;
            }
        }
        Some(id)
    }

    /// The name and binding of `e` when it is a single declared name.
    pub(super) fn binding(&self, e: &Expr) -> Option<(String, Binding)> {
        let Expr::Path(p) = e else { return None };
        let ident = p.path.get_ident()?;
        let key = syn::ext::IdentExt::unraw(ident).to_string();
        let (b, _) = self.names.map.get(&key)?;
        Some((key, *b))
    }

    /// The name of a point of the `points` section.
    pub(super) fn point_name(&mut self, e: &Expr, what: &str) -> Option<String> {
        match self.binding(e) {
            Some((name, Binding::Point(_))) => Some(name),
            _ => {
                self.errors.spanned(
                    e,
                    format!(
                        "{what} is a point's name from `points {{ … }}`; define the point there \
                         (`G3 = polar(a, phi) + polar(r3, th3);`) and name it here"
                    ),
                );
                None
            }
        }
    }

    /// The name of a frame of the `frames` section.
    pub(super) fn frame_name(&mut self, e: &Expr) -> Option<String> {
        match self.binding(e) {
            Some((name, Binding::Frame(_))) => Some(name),
            _ => {
                self.errors.spanned(
                    e,
                    "a body turns with a frame of `frames { … }`: write `frame = name`",
                );
                None
            }
        }
    }

    /// The name of a body of the `bodies` section (or the ground, where
    /// `ground` may be named).
    pub(super) fn body_name(&mut self, e: &Expr, bodies: &[String]) -> Option<String> {
        let name = match e {
            Expr::Path(p) => p
                .path
                .get_ident()
                .map(|i| syn::ext::IdentExt::unraw(i).to_string()),
            _ => None,
        };
        match name {
            Some(n) if bodies.contains(&n) => Some(n),
            _ => {
                let list = if bodies.is_empty() {
                    "it has none".to_owned()
                } else {
                    format!("its bodies: {}", bodies.join(", "))
                };
                self.errors.spanned(
                    e,
                    format!("expected the name of a body of the `bodies` section ({list})"),
                );
                None
            }
        }
    }

    /// `(first, second)`: two bodies, either of them `ground`, that a
    /// `what` (a spring, a joint) joins.
    pub(super) fn body_pair(
        &mut self,
        e: &Expr,
        bodies: &[String],
        what: &str,
    ) -> Option<[String; 2]> {
        let Expr::Tuple(t) = e else {
            self.errors.spanned(
                e,
                format!(
                    "the bodies a {what} joins are written as a pair, `between = (ground, \
                     rocker)`"
                ),
            );
            return None;
        };
        if t.elems.len() != 2 {
            self.errors.spanned(
                e,
                format!("a {what} joins two bodies: `between = (ground, rocker)`"),
            );
            return None;
        }
        let mut with_ground = bodies.to_vec();
        with_ground.push(GROUND.to_owned());
        let first = self.body_name(&t.elems[0], &with_ground)?;
        let second = self.body_name(&t.elems[1], &with_ground)?;
        Some([first, second])
    }
}

/// `rate(x)` in a load: the leaf q'_x.
impl Lowerer<'_> {
    pub(in crate::lower) fn rate(&mut self, c: &syn::ExprCall) -> Option<Value> {
        if !self.rates {
            return self.fail(
                c.func.span(),
                "`rate(x)`, a coordinate's rate, may be used only in a load's value in \
                 `loads { … }`",
            );
        }
        let arg = match (c.args.len(), c.args.first()) {
            (1, Some(a)) => self.binding(a),
            _ => None,
        };
        match arg {
            Some((_, Binding::Coord(j))) => Some(Value::Scalar(self.g.leaf(Leaf::Qd(j)))),
            _ => self.fail(
                c.span(),
                "`rate` takes one coordinate (a driver or an unknown): `rate(x)`",
            ),
        }
    }
}
