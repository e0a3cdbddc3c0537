//! The whole pipeline, as pure functions over `proc_macro2` tokens.

use proc_macro2::TokenStream;

use crate::{
    check, closed, emit, ir, kinematics, lower, names, parse, scale, sensitivity, validate,
};

/// The whole expansion: code for a valid definition, or `compile_error!`s
/// spanned on the offending tokens (with stub types, so uses of the
/// mechanism elsewhere do not add knock-on errors).
pub fn expand(input: TokenStream) -> TokenStream {
    let def: parse::Definition = match syn::parse2(input) {
        Ok(def) => def,
        Err(e) => return e.into_compile_error(),
    };
    let mut errors = names::Errors::default();
    let names = check::check(&def, &mut errors);
    let mut model = lower::lower(&def, &names, &mut errors);
    check::check_mobility(&def, model.spatial, &mut errors);
    if errors.is_empty() {
        validate::validate(&def, &model, &mut errors);
    }
    if let Err(e) = errors.finish() {
        return emit::fallback(&def, e.into_compile_error());
    }
    let derived = kinematics::derive(&mut model);
    let scales = scale::scales(&mut model, def.params.len());
    let closed = closed::closed_blocks(&mut model, &derived.jac);
    let offsets = closed::offsets(&mut model);
    let sensitivities = def.sensitivities.as_ref().map(|(_, names)| {
        let params: Vec<u32> = names
            .iter()
            .filter_map(|n| def.params.iter().position(|p| p.name == *n))
            .filter_map(|k| u32::try_from(k).ok())
            .collect();
        sensitivity::partials(&mut model, &derived, &params)
    });
    emit::expand(
        &def,
        &model,
        &derived,
        &scales,
        &closed,
        &offsets,
        sensitivities.as_ref(),
    )
}

/// The operation counts of a definition (see [`emit::operation_counts`]), or
/// `None` if it has errors.
// Used by the unit tests and the benchmarks.
#[cfg_attr(not(test), allow(dead_code))]
pub fn op_counts(input: TokenStream) -> Option<[(&'static str, ir::OpCount); 2]> {
    let def: parse::Definition = syn::parse2(input).ok()?;
    let mut errors = names::Errors::default();
    let names = check::check(&def, &mut errors);
    let mut model = lower::lower(&def, &names, &mut errors);
    errors.finish().ok()?;
    let derived = kinematics::derive(&mut model);
    Some(kinematics::operation_counts(&model, &derived))
}
