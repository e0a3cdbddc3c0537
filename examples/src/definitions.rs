//! The definitions of this crate as text: the body of each `mechanism! {
//! … }` in its source, exactly as written, for the models built at run
//! time from the same definitions (`kinematics_core::runtime::Model`).

/// The source of this crate's mechanisms.
const SOURCE: &str = include_str!("lib.rs");

/// Each `mechanism! { … }` of `source`: the text between its braces and
/// the line of `source` on which that text begins (from 1). Braces are
/// counted outside `//` comments; an unclosed invocation ends the list.
#[must_use]
pub fn mechanism_bodies(source: &str) -> Vec<(&str, usize)> {
    const OPEN: &str = "mechanism! {";
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = source[from..].find(OPEN) {
        let start = from + at + OPEN.len();
        let first_line = source[..start].lines().count();
        let (mut depth, mut in_comment, mut prev) = (1usize, false, ' ');
        let mut end = None;
        for (i, c) in source[start..].char_indices() {
            match c {
                '\n' => in_comment = false,
                '/' if prev == '/' => in_comment = true,
                '{' if !in_comment => depth += 1,
                '}' if !in_comment => {
                    depth -= 1;
                    if depth == 0 {
                        end = Some(start + i);
                        break;
                    }
                }
                _ => {}
            }
            prev = c;
        }
        let Some(end) = end else { break };
        out.push((&source[start..end], first_line));
        from = end;
    }
    out
}

/// Every definition of this crate as text, with its mechanism's name, in
/// the order of the source.
///
/// ```
/// let defs = kinematics_examples::definitions();
/// assert!(defs.iter().any(|(name, text)| *name == "FourBar" && text.contains("loops")));
/// ```
#[must_use]
pub fn definitions() -> Vec<(&'static str, &'static str)> {
    mechanism_bodies(SOURCE)
        .into_iter()
        .filter_map(|(text, _)| {
            let name = text
                .split("pub struct ")
                .nth(1)?
                .split_whitespace()
                .next()?;
            Some((name, text))
        })
        .collect()
}

/// The definition of the mechanism `name` as text.
#[must_use]
pub fn definition(name: &str) -> Option<&'static str> {
    definitions()
        .into_iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| t)
}
