//! Checks on the lowered model: the equation count, that every unknown and
//! every equation takes part in the system, that every driver is used, and
//! that Φ_u is structurally regular.

use crate::blocks::maximum_matching;
use crate::ir::{Leaf, Node};
use crate::lower::Model;
use crate::names::Errors;
use crate::parse::Definition;

/// Checks on the lowered model: equation count, and that every unknown and
/// every equation takes part in the system.
pub fn validate(def: &Definition, model: &Model, errors: &mut Errors) {
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
fn check_drivers_used(def: &Definition, model: &Model, errors: &mut Errors) {
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
    // The coordinates under any root, found in one walk of the graph.
    let live = model.graph.reachable(&roots);
    let mut used = vec![false; def.drivers.len()];
    for (i, &alive) in live.iter().enumerate() {
        if let (true, Some(Node::Leaf(Leaf::Q(j)))) = (alive, model.graph.node_at(i)) {
            if let Some(u) = used.get_mut(j as usize) {
                *u = true;
            }
        }
    }
    for (j, decl) in def.drivers.iter().enumerate() {
        if decl.allow_unused {
            continue;
        }
        if !used[j] {
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
fn check_structural_rank(def: &Definition, model: &Model, errors: &mut Errors) {
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
            let mut unknowns: Vec<usize> = model
                .graph
                .leaves_under(e.residual)
                .filter_map(|l| match l {
                    Leaf::Q(j) if j >= nd => Some((j - nd) as usize),
                    _ => None,
                })
                .filter(|&k| k < nu)
                .collect();
            unknowns.sort_unstable();
            unknowns
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

/// The loops (one scalar equation per component: 2 for a planar loop, 3
/// for a spatial one) and the constraints (1 each) must give as many scalar
/// equations as there are unknowns.
fn check_equation_count(def: &Definition, model: &Model, errors: &mut Errors) {
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
fn check_each_equation_has_an_unknown(model: &Model, errors: &mut Errors) {
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
fn check_each_unknown_appears(def: &Definition, model: &Model, errors: &mut Errors) {
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

fn index(i: usize) -> u32 {
    u32::try_from(i).unwrap_or(u32::MAX)
}
