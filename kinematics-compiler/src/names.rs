//! The vocabulary the pipeline's stages share: the error list, the name
//! table, the built-in functions, and the accessor names of the generated
//! code.

use std::collections::HashMap;

use proc_macro2::Span;
use syn::Ident;

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

    /// Records an error built by the caller (one with several spans).
    pub fn push(&mut self, error: syn::Error) {
        self.list.push(error);
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
        candidates.push("time");
        closest(wanted, candidates)
    }
}

/// The built-in function closest to `wanted`.
pub fn suggest_function(wanted: &str) -> Option<String> {
    closest(wanted, function_names().collect())
}

/// The longest name for which a "did you mean" is looked for: a longer
/// one is not a typo of a name a person wrote, and comparing it would cost
/// the product of the lengths.
const MAX_SUGGESTED_LENGTH: usize = 64;

/// The most candidates compared for one hint: a definition with more
/// names than this gets its hints from the first ones (in the table's
/// order), so that many misspelt names among many declared ones cost a
/// bounded time each.
const MAX_CANDIDATES: usize = 4096;

/// The candidate nearest `wanted` in edit distance (an insertion,
/// deletion, substitution or transposition of neighbours counts one), if
/// within a third of the longer name's length: `btea` for `beta`, `th5`
/// for `th3`.
fn closest(wanted: &str, candidates: Vec<&str>) -> Option<String> {
    let length = wanted.chars().count();
    if length > MAX_SUGGESTED_LENGTH {
        return None;
    }
    candidates
        .into_iter()
        .filter(|c| c.len() <= 4 * MAX_SUGGESTED_LENGTH)
        .take(MAX_CANDIDATES)
        .filter_map(|c| {
            let n = c.chars().count();
            let allowed = (length.max(n) / 3).max(1);
            // The distance is at least the difference of the lengths.
            (n.abs_diff(length) <= allowed)
                .then(|| (edit_distance(wanted, c), c))
                .filter(|(d, _)| *d <= allowed)
        })
        .min()
        .map(|(_, c)| c.to_owned())
}

/// The built-in functions: name, number of arguments, usage.
pub const FUNCTIONS: &[(&str, usize, &str)] = &[
    ("sin", 1, "sin(x)"),
    ("cos", 1, "cos(x)"),
    ("tan", 1, "tan(x)"),
    ("asin", 1, "asin(x)"),
    ("acos", 1, "acos(x)"),
    ("sqrt", 1, "sqrt(x)"),
    ("exp", 1, "exp(x)"),
    ("ln", 1, "ln(x)"),
    ("atan2", 2, "atan2(y, x)"),
    ("powi", 2, "powi(x, n)"),
    ("polar", 2, "polar(length, angle)"),
    ("vec2", 2, "vec2(x, y)"),
    ("vec3", 3, "vec3(x, y, z)"),
    ("dot", 2, "dot(u, v)"),
    ("cross", 2, "cross(u, v)"),
    ("norm", 1, "norm(v)"),
    ("rot_x", 1, "rot_x(angle)"),
    ("rot_y", 1, "rot_y(angle)"),
    ("rot_z", 1, "rot_z(angle)"),
    ("rot", 2, "rot(axis, angle)"),
    ("translation", 1, "translation(vec3(x, y, z))"),
    ("t1", 4, "t1(a, b, c, angle_x)"),
    ("t2", 4, "t2(a, b, c, angle_y)"),
    ("t3", 4, "t3(a, b, c, angle_z)"),
    ("t4", 5, "t4(a, b, c, angle_x, lead)"),
    ("t5", 5, "t5(a, b, c, angle_y, lead)"),
    ("t6", 5, "t6(a, b, c, angle_z, lead)"),
    ("t7", 3, "t7(a, b, c)"),
    ("screw", 3, "screw(axis, angle, slide)"),
    ("screw_about", 4, "screw_about(axis, point, angle, slide)"),
    (
        "spherical",
        4,
        "spherical(offset, angle_z, angle_x, angle_z2)",
    ),
];

/// The names of the built-in functions, for "did you mean" hints.
pub fn function_names() -> impl Iterator<Item = &'static str> {
    FUNCTIONS.iter().map(|(n, _, _)| *n)
}

/// `frame_<lowercase name>`, the accessor of a frame on the motion struct.
pub fn frame_accessor_name(name: &Ident) -> String {
    use syn::ext::IdentExt;
    format!("frame_{}", name.unraw().to_string().to_lowercase())
}

/// The mechanism's own associated constants, which no driver handle may
/// take.
pub const TAKEN_HANDLES: [&str; 6] = [
    "DRIVERS",
    "UNKNOWNS",
    "EQUATIONS",
    "POINTS",
    "FRAMES",
    "BLOCKS",
];

/// The typed handle of a driver: its name in upper case (`PHI`).
pub fn driver_handle_name(name: &Ident) -> String {
    syn::ext::IdentExt::unraw(name).to_string().to_uppercase()
}

/// `point_<lowercase name>`, the accessor of a point on the motion struct.
pub fn accessor_name(name: &Ident) -> String {
    use syn::ext::IdentExt;
    format!("point_{}", name.unraw().to_string().to_lowercase())
}

/// The edit distance between two short names, transpositions of
/// neighbours counting one (the optimal string alignment distance).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // Rows i − 2, i − 1 and i of the table.
    let mut before: Vec<usize> = Vec::new();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            let mut d = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
            if i > 0 && j > 0 && *ca == b[j - 1] && a[i - 1] == *cb {
                d = d.min(before[j - 1] + 1);
            }
            cur.push(d);
        }
        before = std::mem::replace(&mut prev, cur);
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance() {
        assert_eq!(edit_distance("th3", "th4"), 1);
        assert_eq!(edit_distance("theta", "th"), 3);
        assert_eq!(edit_distance("", "ab"), 2);
        // A transposition of neighbours is one edit.
        assert_eq!(edit_distance("btea", "beta"), 1);
        assert_eq!(edit_distance("ab", "ba"), 1);
        assert_eq!(edit_distance("abc", "ca"), 3);
    }
}
