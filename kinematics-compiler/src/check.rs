//! Checks on the declarations, before any expression is lowered.
//!
//! Every check pushes its errors into the shared [`Errors`] list instead of
//! stopping, so one build reports every problem of a definition.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::Ident;

use crate::names::{
    accessor_name, driver_handle_name, frame_accessor_name, Binding, Errors, Names, TAKEN_HANDLES,
};
use crate::parse::Definition;

/// Runs the declaration checks and builds the name table.
pub fn check(def: &Definition, errors: &mut Errors) -> Names {
    check_not_empty(def, errors);
    check_coordinate_count(def, errors);
    let names = check_unique_names(def, errors);
    check_point_accessors_distinct(def, errors);
    check_driver_handles_distinct(def, errors);
    check_sensitivities(def, errors);
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

/// The Kutzbach–Gruebler count of a `joints { … }` section:
/// F = λ (n − j − 1) + Σf − passive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mobility {
    /// λ: 3 for a planar mechanism, 6 for a spatial one.
    pub lambda: i64,
    /// n, the links (the ground counted).
    pub links: i64,
    /// j, the joints.
    pub joints: i64,
    /// Σf, the joints' freedoms.
    pub freedoms: i64,
    /// The passive freedoms.
    pub passive: i64,
    /// F.
    pub mobility: i64,
}

/// When joints are declared, the Kutzbach–Gruebler mobility
/// F = λ(n − j − 1) + Σf_i − (passive freedoms) must equal the number of
/// drivers (not counting those marked `#[allow(unused)]`, which move
/// nothing), with λ = 3 for a planar mechanism and 6 for a spatial one (one
/// with any 3-D quantity). The number of links n is
/// `links` when given; otherwise it follows from the independent loops,
/// L = j − n + 1, taking each vector loop as one independent loop.
pub fn check_mobility(def: &Definition, spatial: bool, errors: &mut Errors) -> Option<Mobility> {
    let joints = def.joints.as_ref()?;
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
        return None;
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
            return None;
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
    Some(Mobility {
        lambda,
        links: n,
        joints: j,
        freedoms: sum_f,
        passive,
        mobility: f,
    })
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

/// At most [`MAX_COORDINATES`](crate::limits::MAX_COORDINATES) drivers
/// and unknowns together: the derivatives and the blocks of Φ_u cost the
/// square of their number.
fn check_coordinate_count(def: &Definition, errors: &mut Errors) {
    let max = crate::limits::MAX_COORDINATES;
    if let Some(extra) = def.drivers.iter().chain(&def.unknowns).nth(max) {
        errors.at(
            extra.name.span(),
            format!(
                "this is coordinate {} of `{}`, more than the {max} drivers and unknowns a \
                 mechanism may have; split it into mechanisms that hand their outputs on",
                max + 1,
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
        // A declared name may be a built-in function's (`t3`, `T4`, `norm`):
        // it names the declared item, and the function cannot be called in
        // this definition (a call is a located error). `pi` stays the
        // constant, and `time` the time of a forward simulation.
        if key == "pi" || key == "time" {
            let what = if key == "pi" {
                "the built-in constant π"
            } else {
                "the time of a forward simulation, which loads read"
            };
            errors.at(
                name.span(),
                format!(
                    "`{key}` is {what}; choose another name for this {}",
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
            errors.push(e);
            continue;
        }
        map.insert(key.clone(), (binding, name.span()));
        section_of.insert(key, section);
    }
    Names { map }
}

/// The `sensitivities` section names parameters, each once, at least one.
fn check_sensitivities(def: &Definition, errors: &mut Errors) {
    let Some((span, names)) = &def.sensitivities else {
        return;
    };
    if names.is_empty() {
        errors.at(
            *span,
            "list the parameters to differentiate the motion against, e.g. \
             `sensitivities { a, b }`",
        );
    }
    let params: Vec<String> = def
        .params
        .iter()
        .map(|p| syn::ext::IdentExt::unraw(&p.name).to_string())
        .collect();
    let mut seen: Vec<String> = Vec::new();
    for n in names {
        let key = syn::ext::IdentExt::unraw(n).to_string();
        if !params.contains(&key) {
            errors.at(
                n.span(),
                format!(
                    "`{key}` is not a parameter; sensitivities are taken with respect to \
                     parameters: {}",
                    params.join(", ")
                ),
            );
        } else if seen.contains(&key) {
            errors.at(
                n.span(),
                format!("`{key}` is listed twice in `sensitivities`"),
            );
        } else {
            seen.push(key);
        }
    }
}

/// Each driver has a typed handle, an associated constant named after it
/// in upper case (`FourBar::PHI`): two drivers that differ only in case,
/// or a driver named after one of the mechanism's own constants, would
/// collide.
fn check_driver_handles_distinct(def: &Definition, errors: &mut Errors) {
    let mut seen: HashMap<String, &Ident> = HashMap::new();
    for d in &def.drivers {
        let handle = driver_handle_name(&d.name);
        if TAKEN_HANDLES.contains(&handle.as_str()) {
            errors.at(
                d.name.span(),
                format!(
                    "a driver named `{}` would have the handle `{handle}`, which is the number \
                     of the mechanism's {}; rename the driver",
                    d.name,
                    handle.to_lowercase()
                ),
            );
        } else if let Some(first) = seen.get(&handle) {
            errors.at(
                d.name.span(),
                format!(
                    "drivers `{first}` and `{}` would both have the handle `{handle}`; rename \
                     one of them",
                    d.name
                ),
            );
        } else {
            seen.insert(handle, &d.name);
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_duplicates_and_the_constant_pi_together() {
        let def: Definition = syn::parse_quote! {
            struct M {
                params { a, pi }
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
        assert!(msg.contains("`pi` is the built-in constant π"), "{msg}");
        assert!(msg.contains("in both `params` and `drivers`"), "{msg}");
    }
}
