//! Checks on the declarations, before any expression is lowered.
//!
//! Every check pushes its errors into the shared [`Errors`] list instead of
//! stopping, so one build reports every problem of a definition.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::Ident;

use crate::ir::Leaf;
use crate::parse::Definition;

/// Errors collected over all passes; turned into one `compile_error!` each.
#[derive(Default)]
pub struct Errors {
    list: Vec<syn::Error>,
}

impl Errors {
    /// Records an error at `span`.
    pub fn at(&mut self, span: Span, message: impl std::fmt::Display) {
        self.list.push(syn::Error::new(span, message));
    }

    /// Records an error covering all of `tokens` (first to last token).
    pub fn spanned(&mut self, tokens: &dyn quote::ToTokens, message: impl std::fmt::Display) {
        self.list
            .push(syn::Error::new_spanned(tokens.to_token_stream(), message));
    }

    /// Whether nothing was reported.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// All errors combined into one, if any.
    pub fn finish(self) -> syn::Result<()> {
        let mut iter = self.list.into_iter();
        match iter.next() {
            None => Ok(()),
            Some(mut first) => {
                for e in iter {
                    first.combine(e);
                }
                Err(first)
            }
        }
    }
}

/// What a declared name stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binding {
    /// Parameter `i` (a field of the mechanism struct).
    Param(u32),
    /// Coordinate `j` (drivers first, then unknowns).
    Coord(u32),
    /// Point `k` of the `points` section.
    Point(u32),
    /// Frame `k` of the `frames` section.
    Frame(u32),
}

/// Whether `name` is a built-in function or constant of the expression
/// language (user names may not shadow them).
pub fn is_builtin(name: &str) -> bool {
    name == "pi" || crate::lower::function_names().any(|f| f == name)
}

/// Name table of a definition.
pub struct Names {
    pub map: HashMap<String, (Binding, Span)>,
}

impl Names {
    /// The declared name closest to `wanted`, for "did you mean" hints on
    /// a name (a function cannot be meant there).
    pub fn suggest(&self, wanted: &str) -> Option<String> {
        let mut candidates: Vec<&str> = self.map.keys().map(String::as_str).collect();
        candidates.push("pi");
        closest(wanted, candidates)
    }
}

/// The built-in function closest to `wanted`.
pub fn suggest_function(wanted: &str) -> Option<String> {
    closest(wanted, crate::lower::function_names().collect())
}

fn closest(wanted: &str, candidates: Vec<&str>) -> Option<String> {
    candidates
        .into_iter()
        .map(|c| (edit_distance(wanted, c), c))
        .filter(|(d, c)| *d <= (wanted.len().max(c.len()) / 3).max(1))
        .min()
        .map(|(_, c)| c.to_owned())
}

/// Runs the declaration checks and builds the name table.
pub fn check(def: &Definition, errors: &mut Errors) -> Names {
    check_not_empty(def, errors);
    let names = check_unique_names(def, errors);
    check_point_accessors_distinct(def, errors);
    names
}

/// Degrees of freedom of each joint kind the `joints` section accepts.
const JOINT_KINDS: &[(&str, u32, &str)] = &[
    ("R", 1, "revolute"),
    ("P", 1, "prismatic"),
    ("H", 1, "screw"),
    ("C", 2, "cylindrical"),
    ("U", 2, "universal"),
    ("S", 3, "spherical"),
    ("PL", 3, "planar pair"),
];

/// When joints are declared, the Kutzbach–Gruebler mobility
/// F = λ(n − j − 1) + Σf_i − (passive freedoms) must equal the number of
/// drivers (not counting those marked `#[allow(unused)]`, which move
/// nothing), with λ = 3 for a planar mechanism and 6 for a spatial one (one
/// with any 3-D quantity). The number of links n is
/// `links` when given; otherwise it follows from the independent loops,
/// L = j − n + 1, taking each vector loop as one independent loop.
pub fn check_mobility(def: &Definition, spatial: bool, errors: &mut Errors) {
    let Some(joints) = &def.joints else {
        return;
    };
    let lambda: i64 = if spatial { 6 } else { 3 };
    let mut links: Option<i64> = None;
    let mut passive: i64 = 0;
    let mut j: i64 = 0;
    let mut sum_f: i64 = 0;
    let mut ok = true;
    for (key, count) in &joints.entries {
        let Ok(n) = count.base10_parse::<i64>() else {
            errors.spanned(count, "expected a whole number");
            ok = false;
            continue;
        };
        let k = key.to_string();
        match k.as_str() {
            "links" => links = Some(n),
            "passive" => passive = n,
            _ => match JOINT_KINDS.iter().find(|(name, _, _)| *name == k) {
                Some((_, f, _)) => {
                    j += n;
                    sum_f += n * i64::from(*f);
                }
                None => {
                    let kinds: Vec<String> = JOINT_KINDS
                        .iter()
                        .map(|(n, f, what)| format!("{n} ({what}, f = {f})"))
                        .collect();
                    errors.at(
                        key.span(),
                        format!(
                            "unknown joint kind `{k}`; the kinds and their freedoms are {}; \
                             `links: n` gives the number of links and `passive: k` the passive \
                             freedoms",
                            kinds.join(", ")
                        ),
                    );
                    ok = false;
                }
            },
        }
    }
    if !ok {
        return;
    }
    let n = match links {
        Some(n) => n,
        None if def.constraints.is_empty() && !def.loops.is_empty() => {
            j - i64::try_from(def.loops.len()).unwrap_or(0) + 1
        }
        None => {
            errors.at(
                joints.span,
                "give the number of links, e.g. `joints { links: 4, R: 4 }`: it can be inferred \
                 from the loops (n = j − L + 1) only when the model has vector loops and no \
                 scalar constraints",
            );
            return;
        }
    };
    let f = lambda * (n - j - 1) + sum_f - passive;
    // A driver marked `#[allow(unused)]` moves nothing: not a freedom.
    let drivers =
        i64::try_from(def.drivers.iter().filter(|d| !d.allow_unused).count()).unwrap_or(0);
    if f != drivers {
        let passive_text = if passive > 0 {
            format!(" − {passive} passive")
        } else {
            String::new()
        };
        let advice = if f < 1 {
            "the joints leave the mechanism immobile (a structure); check the joint list".to_owned()
        } else if f > drivers {
            format!(
                "a mechanism needs one driver per degree of freedom: declare {f} driver{}, or, \
                 if some freedoms are passive (such as a link between two spherical joints \
                 spinning about its own axis), declare them with `passive: {}`",
                if f == 1 { "" } else { "s" },
                f - drivers
            )
        } else {
            format!("a mechanism needs one driver per degree of freedom: declare {f} driver{} or check the joint list", if f == 1 { "" } else { "s" })
        };
        errors.at(
            joints.span,
            format!(
                "the Kutzbach–Gruebler mobility is F = {lambda}(n − j − 1) + Σf{passive_text} = \
                 {lambda}({n} − {j} − 1) + {sum_f}{passive_text} = {f}, but {drivers} driver{} \
                 {} declared; {advice}",
                if drivers == 1 { "" } else { "s" },
                if drivers == 1 { "is" } else { "are" },
            ),
        );
    }
}

/// A mechanism needs at least one driver or one unknown to be analysed.
fn check_not_empty(def: &Definition, errors: &mut Errors) {
    if def.drivers.is_empty() && def.unknowns.is_empty() {
        errors.at(
            def.name.span(),
            format!(
                "mechanism `{}` has no drivers and no unknowns, so there is nothing to analyse; \
                 declare the input in `drivers {{ … }}` and the joint variables to solve for in \
                 `unknowns {{ … }}`",
                def.name
            ),
        );
    }
}

/// Every name is declared once, in one section, and shadows no built-in.
fn check_unique_names(def: &Definition, errors: &mut Errors) -> Names {
    let mut map: HashMap<String, (Binding, Span)> = HashMap::new();
    let mut section_of: HashMap<String, &'static str> = HashMap::new();
    let coords = def.drivers.iter().chain(&def.unknowns);
    let declared = def
        .params
        .iter()
        .enumerate()
        .map(|(i, d)| (&d.name, Binding::Param(index(i)), "params"))
        .chain(coords.enumerate().map(|(j, d)| {
            let section = if j < def.drivers.len() {
                "drivers"
            } else {
                "unknowns"
            };
            (&d.name, Binding::Coord(index(j)), section)
        }))
        .chain(
            def.points
                .iter()
                .enumerate()
                .map(|(k, p)| (&p.name, Binding::Point(index(k)), "points")),
        )
        .chain(
            def.frames
                .iter()
                .enumerate()
                .map(|(k, p)| (&p.name, Binding::Frame(index(k)), "frames")),
        );
    for (name, binding, section) in declared {
        let key = syn::ext::IdentExt::unraw(name).to_string();
        if is_builtin(&key) {
            errors.at(
                name.span(),
                format!(
                    "`{key}` is a built-in {}; choose another name for this {}",
                    if key == "pi" { "constant" } else { "function" },
                    singular(section)
                ),
            );
            continue;
        }
        if let Some((_, first)) = map.get(&key) {
            let first_section = section_of.get(&key).copied().unwrap_or(section);
            let where_ = if first_section == section {
                format!("twice in `{section}`")
            } else {
                format!("in both `{first_section}` and `{section}`")
            };
            let mut e = syn::Error::new(
                name.span(),
                format!("`{key}` is declared {where_}; each name must be declared once"),
            );
            e.combine(syn::Error::new(
                *first,
                format!("`{key}` first declared here"),
            ));
            errors.list.push(e);
            continue;
        }
        map.insert(key.clone(), (binding, name.span()));
        section_of.insert(key, section);
    }
    Names { map }
}

/// Points are reached through `point_<name>()` methods, so two point names
/// that differ only in case would collide.
fn check_point_accessors_distinct(def: &Definition, errors: &mut Errors) {
    let mut seen: HashMap<String, &Ident> = HashMap::new();
    let named = def
        .points
        .iter()
        .map(|p| (p, accessor_name(&p.name)))
        .chain(def.frames.iter().map(|f| (f, frame_accessor_name(&f.name))));
    for (p, accessor) in named {
        if let Some(first) = seen.get(&accessor) {
            if **first != p.name {
                errors.at(
                    p.name.span(),
                    format!(
                        "`{first}` and `{}` would both be read as `{accessor}()`; \
                         rename one of them",
                        p.name
                    ),
                );
            }
        } else {
            seen.insert(accessor, &p.name);
        }
    }
}

/// Checks on the lowered model: equation count, and that every unknown and
/// every equation takes part in the system.
pub fn check_model(def: &Definition, model: &crate::lower::Model, errors: &mut Errors) {
    check_equation_count(def, model, errors);
    check_each_equation_has_an_unknown(model, errors);
    check_each_unknown_appears(def, model, errors);
    check_drivers_used(def, model, errors);
    if errors.is_empty() {
        check_structural_rank(def, model, errors);
    }
}

/// A driver that no equation and no point uses has no effect; that is
/// usually a typo. `#[allow(unused)]` on the driver accepts it.
fn check_drivers_used(def: &Definition, model: &crate::lower::Model, errors: &mut Errors) {
    let roots: Vec<_> = model
        .equations
        .iter()
        .map(|e| e.residual)
        .chain(model.points.iter().flat_map(|p| p.coords.iter().copied()))
        .chain(
            model
                .frames
                .iter()
                .flat_map(|f| f.rotation.iter().flatten().chain(&f.origin).copied()),
        )
        .collect();
    for (j, decl) in def.drivers.iter().enumerate() {
        if decl.allow_unused {
            continue;
        }
        let leaf = Leaf::Q(index(j));
        if !roots
            .iter()
            .any(|&r| model.graph.depends_on(r, &|l| l == leaf))
        {
            errors.at(
                decl.name.span(),
                format!(
                    "driver `{}` is used by no loop, constraint, point or frame, so it moves nothing; \
                     use it, remove it, or write `#[allow(unused)] {}` if that is intended",
                    decl.name, decl.name
                ),
            );
        }
    }
}

/// The Jacobian Φ_u must be structurally regular: there must be a perfect
/// matching between equations and unknowns in its sparsity pattern (each
/// equation paired with a distinct unknown it involves). Otherwise some
/// equations over-determine a few unknowns while others are left free, and
/// Φ_u is singular at every configuration.
fn check_structural_rank(def: &Definition, model: &crate::lower::Model, errors: &mut Errors) {
    let nd = model.drivers;
    let nu = model.unknowns as usize;
    let ne = model.equations.len();
    if ne != nu {
        return;
    }
    // involves[i]: unknowns (0-based) that equation i depends on.
    let involves: Vec<Vec<usize>> = model
        .equations
        .iter()
        .map(|e| {
            (0..nu)
                .filter(|&k| {
                    let leaf = Leaf::Q(nd + index(k));
                    model.graph.depends_on(e.residual, &|l| l == leaf)
                })
                .collect()
        })
        .collect();
    let matching = maximum_matching(&involves, nu);
    let matched = matching.iter().filter(|m| m.is_some()).count();
    if matched == nu {
        return;
    }
    // Equations reachable from an unmatched equation by alternating paths
    // over-determine the unknowns they reach; the unknowns they do not reach
    // and that no equation can take are left free.
    let mut owner: Vec<Option<usize>> = vec![None; nu];
    for (i, m) in matching.iter().enumerate() {
        if let Some(k) = m {
            owner[*k] = Some(i);
        }
    }
    let mut eq_seen = vec![false; ne];
    let mut unk_seen = vec![false; nu];
    let mut stack: Vec<usize> = (0..ne).filter(|&i| matching[i].is_none()).collect();
    for &i in &stack {
        eq_seen[i] = true;
    }
    while let Some(i) = stack.pop() {
        for &k in &involves[i] {
            if !unk_seen[k] {
                unk_seen[k] = true;
                if let Some(o) = owner[k] {
                    if !eq_seen[o] {
                        eq_seen[o] = true;
                        stack.push(o);
                    }
                }
            }
        }
    }
    let unknown_name = |k: usize| format!("`{}`", def.unknowns[k].name);
    let over: Vec<String> = (0..nu).filter(|&k| unk_seen[k]).map(unknown_name).collect();
    let rest: Vec<String> = (0..nu)
        .filter(|&k| !unk_seen[k])
        .map(unknown_name)
        .collect();
    let eqs: Vec<usize> = (0..ne).filter(|&i| eq_seen[i]).collect();
    let eq_texts: Vec<String> = eqs
        .iter()
        .map(|&i| format!("`{}`", model.equations[i].text))
        .collect();
    let plural = |n: usize, word: &str| format!("{n} {word}{}", if n == 1 { "" } else { "s" });
    let message = format!(
        "the equations {} are {} in only {} ({}): they over-determine {}, and the remaining {} \
         cannot determine the {} {}. The Jacobian is singular in every configuration; rewrite one \
         of these equations to involve {}",
        eq_texts.join(", "),
        plural(eqs.len(), "equation"),
        plural(over.len(), "unknown"),
        over.join(", "),
        if over.len() == 1 { "it" } else { "them" },
        plural(ne - eqs.len(), "equation"),
        plural(rest.len(), "unknown"),
        rest.join(", "),
        rest.join(" or "),
    );
    if let Some(&last) = eqs.last() {
        errors.spanned(&model.equations[last].tokens, message);
    }
}

/// Maximum bipartite matching (augmenting paths): for each equation, the
/// unknown it is paired with.
pub fn maximum_matching(involves: &[Vec<usize>], unknowns: usize) -> Vec<Option<usize>> {
    fn augment(
        i: usize,
        involves: &[Vec<usize>],
        owner: &mut [Option<usize>],
        seen: &mut [bool],
    ) -> bool {
        for &k in &involves[i] {
            if seen[k] {
                continue;
            }
            seen[k] = true;
            let free = match owner[k] {
                None => true,
                Some(o) => augment(o, involves, owner, seen),
            };
            if free {
                owner[k] = Some(i);
                return true;
            }
        }
        false
    }
    let mut owner: Vec<Option<usize>> = vec![None; unknowns];
    for i in 0..involves.len() {
        let mut seen = vec![false; unknowns];
        augment(i, involves, &mut owner, &mut seen);
    }
    let mut matching = vec![None; involves.len()];
    for (k, o) in owner.iter().enumerate() {
        if let Some(i) = o {
            matching[*i] = Some(k);
        }
    }
    matching
}

/// The loops (one scalar equation per component: 2 for a planar loop, 3
/// for a spatial one) and the constraints (1 each) must give as many scalar
/// equations as there are unknowns.
fn check_equation_count(def: &Definition, model: &crate::lower::Model, errors: &mut Errors) {
    // A loop that failed to lower has been reported already; its count
    // would only mislead.
    if model.loop_dims.contains(&0) {
        return;
    }
    let planar = model.loop_dims.iter().filter(|&&d| d == 2).count();
    let spatial = model.loop_dims.iter().filter(|&&d| d == 3).count();
    let n_eq = 2 * planar + 3 * spatial + def.constraints.len();
    let n_u = def.unknowns.len();
    if n_eq == n_u {
        return;
    }
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let mut parts = Vec::new();
    if spatial == 0 {
        parts.push(format!("{planar} loop{} × 2", plural(planar)));
    } else {
        if planar > 0 {
            parts.push(format!("{planar} planar loop{} × 2", plural(planar)));
        }
        parts.push(format!("{spatial} spatial loop{} × 3", plural(spatial)));
    }
    parts.push(format!(
        "{} constraint{}",
        def.constraints.len(),
        plural(def.constraints.len())
    ));
    let detail = format!(
        "{} = {n_eq} scalar equation{}",
        parts.join(" + "),
        plural(n_eq)
    );
    let fix = if n_eq > n_u {
        "declare the missing joint variables in `unknowns`, or remove a redundant equation"
    } else {
        "add loops or constraints, or move an input from `unknowns` to `drivers`"
    };
    // Only report when lowering succeeded, so a type error in an equation
    // does not also produce a misleading count.
    if model.equations.len() == n_eq || errors.is_empty() {
        errors.at(
            def.unknowns_span,
            format!("{detail} for {n_u} unknown{}; {fix}", plural(n_u)),
        );
    }
}

/// An equation that does not involve any unknown is either always true (and
/// redundant), always false, or a condition on the drivers alone: none of
/// these can be solved for the unknowns.
fn check_each_equation_has_an_unknown(model: &crate::lower::Model, errors: &mut Errors) {
    let drivers = model.drivers;
    for eq in &model.equations {
        let g = &model.graph;
        if g.depends_on(eq.residual, &|l| matches!(l, Leaf::Q(j) if j >= drivers)) {
            continue;
        }
        let msg = match g.as_const(eq.residual) {
            Some(0.0) => format!(
                "`{}` holds identically (it simplifies to 0 == 0), so it is redundant; remove it",
                eq.text
            ),
            Some(_) => format!(
                "`{}` can never hold (it simplifies to a nonzero constant); check the signs and \
                 the points used",
                eq.text
            ),
            None => format!(
                "`{}` involves no unknown, so it cannot be solved for the joint variables; \
                 it constrains only parameters and drivers",
                eq.text
            ),
        };
        errors.spanned(&eq.tokens, msg);
    }
}

/// Every unknown must appear in at least one equation, or it is undetermined.
fn check_each_unknown_appears(def: &Definition, model: &crate::lower::Model, errors: &mut Errors) {
    let roots: Vec<_> = model.equations.iter().map(|e| e.residual).collect();
    for (k, decl) in def.unknowns.iter().enumerate() {
        let j = model.drivers + index(k);
        let used = roots
            .iter()
            .any(|&r| model.graph.depends_on(r, &|l| l == Leaf::Q(j)));
        if !used {
            errors.at(
                decl.name.span(),
                format!(
                    "unknown `{}` appears in no loop or constraint, so nothing determines it; \
                     use it in an equation or remove it",
                    decl.name
                ),
            );
        }
    }
}

/// `frame_<lowercase name>`, the accessor of a frame on the motion struct.
pub fn frame_accessor_name(name: &Ident) -> String {
    use syn::ext::IdentExt;
    format!("frame_{}", name.unraw().to_string().to_lowercase())
}

/// `point_<lowercase name>`, the accessor of a point on the motion struct.
pub fn accessor_name(name: &Ident) -> String {
    use syn::ext::IdentExt;
    format!("point_{}", name.unraw().to_string().to_lowercase())
}

fn singular(section: &str) -> &'static str {
    match section {
        "params" => "parameter",
        "drivers" => "driver",
        "unknowns" => "unknown",
        "frames" => "frame",
        _ => "point",
    }
}

fn index(i: usize) -> u32 {
    u32::try_from(i).unwrap_or(u32::MAX)
}

/// Levenshtein distance between two short names.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur.push(sub.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matching_finds_augmenting_paths() {
        // e0: {u0, u1}, e1: {u0}: e0 must give u0 up to e1.
        assert_eq!(
            maximum_matching(&[vec![0, 1], vec![0]], 2),
            vec![Some(1), Some(0)]
        );
        // e0: {u0}, e1: {u0}, e2: {u1, u2}: only two can be matched.
        let m = maximum_matching(&[vec![0], vec![0], vec![1, 2]], 3);
        assert_eq!(m.iter().filter(|x| x.is_some()).count(), 2);
    }

    #[test]
    fn distance() {
        assert_eq!(edit_distance("th3", "th4"), 1);
        assert_eq!(edit_distance("theta", "th"), 3);
        assert_eq!(edit_distance("", "ab"), 2);
    }

    #[test]
    fn reports_duplicates_and_builtin_shadowing_together() {
        let def: Definition = syn::parse_quote! {
            struct M {
                params { a, sin }
                drivers { a }
                unknowns { x }
                constraints { x == 1.0 }
            }
        };
        let mut errors = Errors::default();
        let _ = check(&def, &mut errors);
        let msg = errors.finish().err().map(|e| {
            e.into_iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("\n")
        });
        let msg = msg.unwrap_or_default();
        assert!(msg.contains("`sin` is a built-in function"), "{msg}");
        assert!(msg.contains("in both `params` and `drivers`"), "{msg}");
    }
}
