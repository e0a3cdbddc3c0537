//! Many designs or starting poses evaluated on all cores (feature
//! `parallel`).

use alloc::vec::Vec;

use crate::error::Error;

/// Evaluates `f` for every item of `items` (parameter sets, starting poses)
/// on all cores, returning each item's result or error in order; one failing
/// item never aborts the others (feature `parallel`).
///
/// ```
/// use kinematics_core::{batch, mechanism};
/// mechanism! {
///     /// A slider-crank.
///     pub struct SliderCrank {
///         params { a, b }
///         drivers { phi }
///         unknowns { th, x }
///         loops { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///     }
/// }
/// let designs: Vec<SliderCrank> = (1..=4).map(|k| SliderCrank { a: 0.1, b: 0.05 * f64::from(k) }).collect();
/// let start = SliderCrankCoords { phi: 1.2, th: 0.0, x: 0.2 };
/// let results = batch(&designs, |m| m.assemble(&start));
/// // b = 0.05 < a sin φ cannot reach the slider line; the others assemble.
/// assert!(results[0].is_err() && results[3].is_ok());
/// ```
pub fn batch<T, R, F>(items: &[T], f: F) -> Vec<Result<R, Error>>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> Result<R, Error> + Sync + Send,
{
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}
