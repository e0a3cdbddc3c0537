//! Parsing: tokens to the syntax tree of one mechanism definition.
//!
//! ```text
//! mechanism! {
//!     /// Documentation.
//!     pub struct Name {
//!         params      { a, b, … }            // constants, set at run time
//!         drivers     { phi, … }             // prescribed inputs
//!         unknowns    { th3, … }             // solved for
//!         frames      { crank = rot_y(phi); … } // body frames (spatial)
//!         points      { B = polar(a, phi); … }
//!         loops       { lhs == rhs; … }      // vector equations
//!         constraints { lhs == rhs; … }      // scalar equations
//!         joints      { R: 4 }               // optional: mobility check
//!         sensitivities { a, b }             // optional: ∂/∂ parameters
//!         bodies      { rod(mass = m3, center = G3, angle = th3, inertia = j3); }
//!         loads       { gravity(vec2(0.0, -9.81)); force(C, vec2(-p, 0.0)); }
//!     }
//! }
//! ```
//!
//! Sections may come in any order; each at most once. Expressions are parsed
//! as Rust expressions (so precedence is Rust's) and interpreted in `lower.rs`.
//! Every item keeps its tokens, so later errors point at them.

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::{braced, Attribute, Expr, Ident, Token, Visibility};

/// DSL keywords.
pub mod kw {
    syn::custom_keyword!(params);
    syn::custom_keyword!(drivers);
    syn::custom_keyword!(unknowns);
    syn::custom_keyword!(points);
    syn::custom_keyword!(loops);
    syn::custom_keyword!(constraints);
    syn::custom_keyword!(joints);
    syn::custom_keyword!(frames);
    syn::custom_keyword!(sensitivities);
    syn::custom_keyword!(bodies);
    syn::custom_keyword!(loads);
}

/// A whole `mechanism!` invocation.
#[derive(Clone)]
pub struct Definition {
    pub docs: Vec<Attribute>,
    /// The other outer attributes of the struct (`#[derive(…)]`,
    /// `#[serde(…)]`, …), passed on to the parameters struct.
    pub attrs: Vec<Attribute>,
    /// The derives among them that name `Serialize` or `Deserialize`, also
    /// applied to the coordinates, motion and modes types.
    pub serde_derives: Vec<syn::Path>,
    /// The same derives written inside `#[cfg_attr(predicate, derive(…))]`:
    /// each predicate with its paths, applied to the generated types under
    /// the same predicate.
    pub serde_cfg_derives: Vec<(proc_macro2::TokenStream, Vec<syn::Path>)>,
    pub vis: Visibility,
    pub name: Ident,
    pub params: Vec<Decl>,
    pub drivers: Vec<Decl>,
    pub unknowns: Vec<Decl>,
    pub points: Vec<PointDef>,
    /// `frames { name = <rotation or 4×4 transform>; }`
    pub frames: Vec<PointDef>,
    pub loops: Vec<Equation>,
    pub constraints: Vec<Equation>,
    /// Span of the `unknowns` section (or of the name when it is missing),
    /// where counting errors point.
    pub unknowns_span: Span,
    /// The optional `joints { … }` section.
    pub joints: Option<Joints>,
    /// The optional `sensitivities { a, b, … }` section: the parameters to
    /// differentiate the motion against.
    pub sensitivities: Option<(Span, Vec<Ident>)>,
    /// The optional `bodies { name(mass = …, center = …, …); … }` section:
    /// the links' masses and inertias.
    pub bodies: Vec<Call>,
    /// The optional `loads { gravity(…); force(…); … }` section.
    pub loads: Vec<Call>,
    /// The `joints { name(kind, P, between = (first, second), …); … }`
    /// section written with items: the joints whose reactions are
    /// computed (the other form of `joints` counts them for the mobility
    /// check).
    pub joint_items: Vec<Call>,
    /// The keyword of the first of the `bodies`, `loads` and item-form
    /// `joints` sections, where errors about them as a whole point.
    pub dynamics_span: Option<Span>,
}

/// `name(argument, …, key = value, …)`: an item of the `bodies` section
/// (named after the body), of the `loads` section (named after the load's
/// kind) or of the item form of `joints` (named after the joint).
#[derive(Clone)]
pub struct Call {
    pub docs: Vec<Attribute>,
    pub name: Ident,
    /// The arguments written without a key, in order.
    pub positional: Vec<Expr>,
    /// The `key = value` arguments, in order.
    pub named: Vec<(Ident, Expr)>,
    /// The whole item's tokens, where errors about it point.
    pub tokens: proc_macro2::TokenStream,
}

/// `joints { links: 4, R: 3, P: 1, passive: 0 }`: the joint kinds and their
/// numbers, for the Kutzbach–Gruebler mobility check.
#[derive(Clone)]
pub struct Joints {
    /// The `joints` keyword.
    pub span: Span,
    /// `key: count` entries as written.
    pub entries: Vec<(Ident, syn::LitInt)>,
}

/// A declared name with its doc comments.
#[derive(Clone)]
pub struct Decl {
    pub docs: Vec<Attribute>,
    pub name: Ident,
    /// `#[allow(unused)]` was written on it.
    pub allow_unused: bool,
    /// `name: length` declares a length, which must be positive.
    pub length: bool,
}

/// `Name = expr;` in the `points` section.
#[derive(Clone)]
pub struct PointDef {
    pub docs: Vec<Attribute>,
    pub name: Ident,
    pub expr: Expr,
}

/// `lhs == rhs;` in the `loops` or `constraints` section.
#[derive(Clone)]
pub struct Equation {
    pub lhs: Expr,
    pub rhs: Expr,
    /// The whole equation's tokens, where errors about it point.
    pub tokens: proc_macro2::TokenStream,
    /// The equation as written, for naming it in run-time errors.
    pub text: String,
}

impl Parse for Definition {
    fn parse(input: ParseStream<'_>) -> syn::Result<Self> {
        let all = input.call(Attribute::parse_outer)?;
        let (docs, attrs): (Vec<Attribute>, Vec<Attribute>) =
            all.into_iter().partition(|a| a.path().is_ident("doc"));
        for d in &docs {
            check_doc(d)?;
        }
        check_struct_attributes(&attrs)?;
        let serde_derives = serde_derives(&attrs)?;
        let serde_cfg_derives = serde_cfg_derives(&attrs)?;
        let vis: Visibility = input.parse()?;
        input.parse::<Token![struct]>().map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected `struct Name { … }`: a mechanism is declared as \
                 `pub struct FourBar { params { … } drivers { … } unknowns { … } loops { … } }`",
            )
        })?;
        let name: Ident = input.parse()?;
        let body;
        braced!(body in input);
        let mut def = Definition {
            docs,
            attrs,
            serde_derives,
            serde_cfg_derives,
            vis,
            unknowns_span: name.span(),
            name,
            params: Vec::new(),
            drivers: Vec::new(),
            unknowns: Vec::new(),
            points: Vec::new(),
            frames: Vec::new(),
            loops: Vec::new(),
            constraints: Vec::new(),
            joints: None,
            sensitivities: None,
            bodies: Vec::new(),
            loads: Vec::new(),
            joint_items: Vec::new(),
            dynamics_span: None,
        };
        let mut seen: Vec<(String, Span)> = Vec::new();
        while !body.is_empty() {
            let lookahead = body.lookahead1();
            let keyword_span = body.span();
            let section = if lookahead.peek(kw::params) {
                body.parse::<kw::params>()?;
                "params"
            } else if lookahead.peek(kw::drivers) {
                body.parse::<kw::drivers>()?;
                "drivers"
            } else if lookahead.peek(kw::unknowns) {
                body.parse::<kw::unknowns>()?;
                "unknowns"
            } else if lookahead.peek(kw::points) {
                body.parse::<kw::points>()?;
                "points"
            } else if lookahead.peek(kw::loops) {
                body.parse::<kw::loops>()?;
                "loops"
            } else if lookahead.peek(kw::constraints) {
                body.parse::<kw::constraints>()?;
                "constraints"
            } else if lookahead.peek(kw::joints) {
                body.parse::<kw::joints>()?;
                "joints"
            } else if lookahead.peek(kw::frames) {
                body.parse::<kw::frames>()?;
                "frames"
            } else if lookahead.peek(kw::sensitivities) {
                body.parse::<kw::sensitivities>()?;
                "sensitivities"
            } else if lookahead.peek(kw::bodies) {
                body.parse::<kw::bodies>()?;
                "bodies"
            } else if lookahead.peek(kw::loads) {
                body.parse::<kw::loads>()?;
                "loads"
            } else {
                return Err(lookahead.error());
            };
            if let Some((_, first)) = seen.iter().find(|(s, _)| s == section) {
                let mut err = syn::Error::new(
                    keyword_span,
                    format!("the `{section}` section appears twice; merge the two into one"),
                );
                err.combine(syn::Error::new(*first, "first written here"));
                return Err(err);
            }
            seen.push((section.to_owned(), keyword_span));
            let content;
            braced!(content in body);
            match section {
                "params" => def.params = parse_decls(&content)?,
                "drivers" => def.drivers = parse_decls(&content)?,
                "unknowns" => {
                    def.unknowns_span = keyword_span;
                    def.unknowns = parse_decls(&content)?;
                }
                "points" => def.points = parse_items(&content, parse_point)?,
                "frames" => def.frames = parse_items(&content, parse_point)?,
                "loops" => def.loops = parse_items(&content, parse_equation)?,
                "constraints" => def.constraints = parse_items(&content, parse_equation)?,
                "bodies" | "loads" => {
                    let items = parse_items(&content, parse_call)?;
                    def.dynamics_span.get_or_insert(keyword_span);
                    if section == "bodies" {
                        def.bodies = items;
                    } else {
                        def.loads = items;
                    }
                }
                "joints" if joint_items_follow(&content) => {
                    def.joint_items = parse_items(&content, parse_call)?;
                    def.dynamics_span.get_or_insert(keyword_span);
                }
                "sensitivities" => {
                    let names = content.parse_terminated(Ident::parse, Token![,])?;
                    def.sensitivities = Some((keyword_span, names.into_iter().collect()));
                }
                _ => {
                    let entries = content
                        .parse_terminated(
                            |input: ParseStream<'_>| {
                                let key: Ident = input.call(syn::ext::IdentExt::parse_any)?;
                                input.parse::<Token![:]>()?;
                                let count: syn::LitInt = input.parse().map_err(|e| {
                                    syn::Error::new(
                                        e.span(),
                                        "expected a whole number of joints, e.g. `R: 4`",
                                    )
                                })?;
                                Ok((key, count))
                            },
                            Token![,],
                        )?
                        .into_iter()
                        .collect();
                    def.joints = Some(Joints {
                        span: keyword_span,
                        entries,
                    });
                }
            }
        }
        Ok(def)
    }
}

/// The attributes passed on to the parameters struct: derives and lint
/// levels, `serde(…)`, `cfg_attr(…)`, `must_use`; any other is taken for a
/// helper of a derive other than the standard ones, and needs one.
fn check_struct_attributes(attrs: &[Attribute]) -> syn::Result<()> {
    const KNOWN: [&str; 9] = [
        "derive", "serde", "allow", "warn", "deny", "forbid", "expect", "cfg_attr", "must_use",
    ];
    const STANDARD: [&str; 8] = [
        "Debug",
        "Clone",
        "Copy",
        "PartialEq",
        "Eq",
        "PartialOrd",
        "Default",
        "Hash",
    ];
    let mut other_derive = false;
    for attr in attrs.iter().filter(|a| a.path().is_ident("derive")) {
        let paths = attr.parse_args_with(
            syn::punctuated::Punctuated::<syn::Path, Token![,]>::parse_terminated,
        )?;
        other_derive |= paths.iter().any(|p| {
            let last = p.segments.last().map(|s| s.ident.to_string());
            !matches!(last.as_deref(), Some(n) if STANDARD.contains(&n) || n == "Serialize" || n == "Deserialize")
        });
    }
    for attr in attrs {
        let name = attr.path().get_ident().map(ToString::to_string);
        let known = name.as_deref().is_some_and(|n| KNOWN.contains(&n));
        if !known && !other_derive {
            return Err(syn::Error::new_spanned(
                attr,
                "this attribute is not one the parameters struct can take: the struct accepts \
                 `///` docs, `#[derive(…)]` (e.g. serde's `Serialize, Deserialize`), \
                 `#[serde(…)]`, lint levels (`#[allow(…)]`) and `#[cfg_attr(…)]`, and the \
                 helper attributes of a derive it names",
            ));
        }
    }
    Ok(())
}

/// The paths in `#[derive(…)]` attributes whose last segment is
/// `Serialize` or `Deserialize`.
fn serde_derives(attrs: &[Attribute]) -> syn::Result<Vec<syn::Path>> {
    let mut out = Vec::new();
    for attr in attrs.iter().filter(|a| a.path().is_ident("derive")) {
        out.extend(serde_paths(&attr.meta)?);
    }
    Ok(out)
}

/// The serde derives inside `#[cfg_attr(predicate, …, derive(…), …)]`
/// attributes, with their predicates: a mechanism whose serde support is
/// behind a feature of the user's crate.
fn serde_cfg_derives(
    attrs: &[Attribute],
) -> syn::Result<Vec<(proc_macro2::TokenStream, Vec<syn::Path>)>> {
    let mut out = Vec::new();
    for attr in attrs.iter().filter(|a| a.path().is_ident("cfg_attr")) {
        let (predicate, metas) = attr.parse_args_with(|input: ParseStream<'_>| {
            let predicate: syn::Meta = input.parse()?;
            input.parse::<Token![,]>()?;
            let metas =
                syn::punctuated::Punctuated::<syn::Meta, Token![,]>::parse_terminated(input)?;
            Ok((predicate, metas))
        })?;
        let mut paths = Vec::new();
        for meta in metas.iter().filter(|m| m.path().is_ident("derive")) {
            paths.extend(serde_paths(meta)?);
        }
        if !paths.is_empty() {
            out.push((quote::ToTokens::to_token_stream(&predicate), paths));
        }
    }
    Ok(out)
}

/// The paths of one `derive(…)` whose last segment is `Serialize` or
/// `Deserialize`.
fn serde_paths(meta: &syn::Meta) -> syn::Result<Vec<syn::Path>> {
    let list = meta.require_list()?;
    let paths = list
        .parse_args_with(syn::punctuated::Punctuated::<syn::Path, Token![,]>::parse_terminated)?;
    Ok(paths
        .into_iter()
        .filter(|p| {
            let last = p.segments.last().map(|s| s.ident.to_string());
            matches!(last.as_deref(), Some("Serialize" | "Deserialize"))
        })
        .collect())
}

/// Keeps `///` comments; any other attribute is an error at its tokens.
fn doc_attributes(attrs: Vec<Attribute>) -> syn::Result<Vec<Attribute>> {
    let mut out = Vec::new();
    for attr in attrs {
        if attr.path().is_ident("doc") {
            check_doc(&attr)?;
            out.push(attr);
        } else {
            return Err(syn::Error::new_spanned(
                attr,
                "only doc comments (`/// …`) may be attached here",
            ));
        }
    }
    Ok(out)
}

/// A doc attribute must be `#[doc = "text"]` (what `///` produces).
fn check_doc(attr: &Attribute) -> syn::Result<()> {
    match &attr.meta {
        syn::Meta::NameValue(syn::MetaNameValue {
            value:
                Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(_),
                    ..
                }),
            ..
        }) => Ok(()),
        _ => Err(syn::Error::new_spanned(
            attr,
            "a doc attribute must be a string, `#[doc = \"…\"]`; write doc comments as `/// …`",
        )),
    }
}

/// Whether `attr` is `#[allow(unused)]`.
fn is_allow_unused(attr: &Attribute) -> bool {
    attr.path().is_ident("allow") && attr.parse_args::<Ident>().is_ok_and(|i| i == "unused")
}

/// `a, b, c` with optional doc comments and an optional trailing comma.
fn parse_decls(input: ParseStream<'_>) -> syn::Result<Vec<Decl>> {
    let mut out = Vec::new();
    while !input.is_empty() {
        let mut attrs = input.call(Attribute::parse_outer)?;
        let before = attrs.len();
        attrs.retain(|a| !is_allow_unused(a));
        let allow_unused = attrs.len() != before;
        if let Some(other) = attrs.iter().find(|a| !a.path().is_ident("doc")) {
            return Err(syn::Error::new_spanned(
                other,
                "only doc comments (`/// …`) and `#[allow(unused)]` may be attached to a name",
            ));
        }
        let docs = doc_attributes(attrs)?;
        let name: Ident = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), "expected a name, e.g. `a` or `theta3`"))?;
        let mut length = false;
        if input.peek(Token![:]) {
            input.parse::<Token![:]>()?;
            let kind: Ident = input.parse()?;
            if kind == "length" {
                length = true;
            } else if kind != "angle" {
                return Err(syn::Error::new(
                    kind.span(),
                    format!(
                        "unknown kind `{kind}`; write `{name}: length` for a length that must be \
                         positive, or `{name}: angle`"
                    ),
                ));
            }
        }
        out.push(Decl {
            docs,
            name,
            allow_unused,
            length,
        });
        if input.is_empty() {
            break;
        }
        input.parse::<Token![,]>()?;
    }
    Ok(out)
}

/// Items separated by `;` (the last one may omit it).
fn parse_items<T>(
    input: ParseStream<'_>,
    item: fn(ParseStream<'_>) -> syn::Result<T>,
) -> syn::Result<Vec<T>> {
    let mut out = Vec::new();
    while !input.is_empty() {
        out.push(item(input)?);
        if input.is_empty() {
            break;
        }
        input.parse::<Token![;]>()?;
    }
    Ok(out)
}

fn parse_point(input: ParseStream<'_>) -> syn::Result<PointDef> {
    let docs = doc_attributes(input.call(Attribute::parse_outer)?)?;
    let name: Ident = input.parse()?;
    input.parse::<Token![=]>().map_err(|e| {
        syn::Error::new(
            e.span(),
            "expected `=`: a point or frame is defined as `Name = <expression>;`",
        )
    })?;
    let expr: Expr = input.parse()?;
    Ok(PointDef { docs, name, expr })
}

/// Whether a `joints` section is written with items (`name(…)`, each
/// perhaps with doc comments) rather than counts (`R: 4`).
fn joint_items_follow(content: ParseStream<'_>) -> bool {
    let fork = content.fork();
    fork.call(Attribute::parse_outer).is_ok() && fork.peek(Ident) && fork.peek2(syn::token::Paren)
}

fn parse_call(input: ParseStream<'_>) -> syn::Result<Call> {
    let docs = doc_attributes(input.call(Attribute::parse_outer)?)?;
    let expr: Expr = input.parse()?;
    let tokens = quote::ToTokens::to_token_stream(&expr);
    let Expr::Call(call) = expr else {
        return Err(syn::Error::new_spanned(
            expr,
            "expected `name(…)`: a body is written `rod(mass = m3, center = G3, angle = th3, \
             inertia = j3)`, a load `gravity(vec2(0.0, -9.81))`, `force(C, vec2(fx, fy))`, \
             `torque(rod, t)` or `spring(A, B, stiffness = k, free_length = l0)`, a joint \
             `bearing(revolute, O, between = (ground, crank))`",
        ));
    };
    let name = match &*call.func {
        Expr::Path(p) if p.qself.is_none() => p.path.get_ident().cloned(),
        _ => None,
    };
    let Some(name) = name else {
        return Err(syn::Error::new_spanned(
            &call.func,
            "expected a single name before the parentheses",
        ));
    };
    let mut positional = Vec::new();
    let mut named: Vec<(Ident, Expr)> = Vec::new();
    for arg in call.args {
        match arg {
            Expr::Assign(a) => {
                let key = match &*a.left {
                    Expr::Path(p) if p.qself.is_none() => p.path.get_ident().cloned(),
                    _ => None,
                };
                let Some(key) = key else {
                    return Err(syn::Error::new_spanned(
                        &a.left,
                        "expected a single name before `=`, e.g. `mass = m3`",
                    ));
                };
                if let Some((first, _)) = named.iter().find(|(k, _)| *k == key) {
                    let mut err = syn::Error::new(
                        key.span(),
                        format!("`{key}` is given twice; give it once"),
                    );
                    err.combine(syn::Error::new(first.span(), "first given here"));
                    return Err(err);
                }
                named.push((key, *a.right));
            }
            other if named.is_empty() => positional.push(other),
            other => {
                return Err(syn::Error::new_spanned(
                    other,
                    "an argument without a key follows `key = value` arguments; write the \
                     arguments without keys first",
                ))
            }
        }
    }
    Ok(Call {
        docs,
        name,
        positional,
        named,
        tokens,
    })
}

fn parse_equation(input: ParseStream<'_>) -> syn::Result<Equation> {
    let expr: Expr = input.parse()?;
    let tokens = quote::ToTokens::to_token_stream(&expr);
    let text = expr_text(&expr);
    match expr {
        Expr::Binary(syn::ExprBinary {
            left,
            op: syn::BinOp::Eq(_),
            right,
            ..
        }) => Ok(Equation {
            lhs: *left,
            rhs: *right,
            tokens,
            text,
        }),
        other => Err(syn::Error::new_spanned(
            other,
            "an equation must have the form `lhs == rhs`, e.g. `B + polar(b, th3) == C`",
        )),
    }
}

/// An expression as text, the same whether the tokens come from rustc (in
/// `mechanism!`) or from a string (at run time): calls and indexing
/// without spaces, binary operators between single spaces, ", " between
/// arguments, literals as written. Forms the language does not take are
/// printed from their tokens.
pub fn expr_text(e: &Expr) -> String {
    let list = |args: &syn::punctuated::Punctuated<Expr, Token![,]>| {
        args.iter().map(expr_text).collect::<Vec<_>>().join(", ")
    };
    match e {
        Expr::Binary(b) => {
            let op = quote::ToTokens::to_token_stream(&b.op)
                .to_string()
                .replace(' ', "");
            format!("{} {op} {}", expr_text(&b.left), expr_text(&b.right))
        }
        Expr::Unary(u) => {
            let op = quote::ToTokens::to_token_stream(&u.op).to_string();
            format!("{op}{}", expr_text(&u.expr))
        }
        Expr::Paren(p) => format!("({})", expr_text(&p.expr)),
        Expr::Call(c) => format!("{}({})", expr_text(&c.func), list(&c.args)),
        Expr::MethodCall(m) => {
            format!("{}.{}({})", expr_text(&m.receiver), m.method, list(&m.args))
        }
        Expr::Index(i) => format!("{}[{}]", expr_text(&i.expr), expr_text(&i.index)),
        Expr::Field(f) => {
            let member = match &f.member {
                syn::Member::Named(n) => n.to_string(),
                syn::Member::Unnamed(i) => i.index.to_string(),
            };
            format!("{}.{member}", expr_text(&f.base))
        }
        Expr::Path(p) if p.qself.is_none() => p
            .path
            .segments
            .iter()
            .map(|s| s.ident.to_string())
            .collect::<Vec<_>>()
            .join("::"),
        Expr::Lit(l) => quote::ToTokens::to_token_stream(&l.lit).to_string(),
        Expr::Group(g) => expr_text(&g.expr),
        other => quote::ToTokens::to_token_stream(other).to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_all_sections_in_any_order() {
        let def: Definition = syn::parse_quote! {
            /// A four-bar.
            pub struct FourBar {
                loops { B + polar(b, th3) == C; }
                params { /// crank
                         a, b, c, d }
                drivers { phi }
                unknowns { th3, th4, }
                points { B = polar(a, phi); C = vec2(d, 0.0) + polar(c, th4) }
            }
        };
        assert_eq!(def.name, "FourBar");
        assert_eq!(def.params.len(), 4);
        assert_eq!(def.params[0].docs.len(), 1);
        assert_eq!(def.unknowns.len(), 2);
        assert_eq!(def.points.len(), 2);
        assert_eq!(def.loops.len(), 1);
        assert!(def.constraints.is_empty());
    }

    #[test]
    fn rejects_an_equation_without_double_equals() {
        let r: syn::Result<Definition> = syn::parse2(quote::quote! {
            struct M { loops { a + b } }
        });
        let msg = r.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(msg.contains("lhs == rhs"), "{msg}");
    }

    #[test]
    fn rejects_unknown_section_with_the_list_of_sections() {
        let r: syn::Result<Definition> = syn::parse2(quote::quote! {
            struct M { linkages { R } }
        });
        let msg = r.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(msg.contains("params") && msg.contains("loops"), "{msg}");
    }
}
