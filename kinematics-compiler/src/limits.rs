//! The limits on a definition, stated once: text from a user is untrusted
//! input, and every stage after this one (syn's parser, lowering, the
//! derivatives, dropping the syntax tree) recurses on the nesting of an
//! expression, so the tokens are checked here first, without recursion,
//! and anything past a limit is a located error that names the limit.
//!
//! * [`MAX_NESTING`]: brackets, braces and parentheses inside each other;
//! * [`MAX_EXPRESSION_TOKENS`]: tokens in one expression or equation
//!   (between two `;` or `,` of a section, nested groups included), which
//!   bounds the depth of its syntax tree whatever its shape (a long sum is
//!   a deep tree too);
//! * [`MAX_ITEMS`]: items (names, points, equations, …) in the whole
//!   definition, which bounds the compile time;
//! * [`MAX_COORDINATES`]: drivers and unknowns (checked with the
//!   declarations, where their names are known);
//! * [`MAX_TOKENS`]: tokens in the whole definition;
//! * [`MAX_TEXT_BYTES`]: the size of a definition given as text;
//! * [`MAX_POWI_EXPONENT`]: the exponent of `powi`, so that the
//!   derivatives' exponents are exact integers.
//!
//! Each is far above what a mechanism needs (the largest definition of the
//! examples and tests nests 6 deep and has expressions of under 150
//! tokens), and low enough that a definition at the limits compiles on a
//! thread of 2 MiB of stack in a debug build.

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};

/// The deepest nesting of brackets, braces and parentheses.
pub const MAX_NESTING: usize = 64;

/// The most tokens in one expression or equation, nested groups included.
pub const MAX_EXPRESSION_TOKENS: usize = 256;

/// The most items in a definition: names declared, points, frames,
/// equations, bodies, loads (the statements of its sections, separated by
/// `;` or `,`). Compiling costs about 70 µs per point with its velocity
/// and acceleration: 5000 points compile in well under a second.
pub const MAX_ITEMS: usize = 5000;

/// The most coordinates (drivers and unknowns together) of a mechanism:
/// compiling costs the square of their number (a chain of 500 four-bars,
/// 1000 unknowns, compiles in about half a second).
pub const MAX_COORDINATES: usize = 1000;

/// The most tokens in a definition.
pub const MAX_TOKENS: usize = 1_000_000;

/// The largest |n| of `powi(x, n)`: its derivatives' exponents (n − 1,
/// n − 2) and the products of nested powers stay far inside `i32`.
pub const MAX_POWI_EXPONENT: u32 = 1 << 16;

/// The largest definition given as text, in bytes (4 MiB).
pub const MAX_TEXT_BYTES: usize = 4 << 20;

/// The group depth up to which a brace group is a section (the struct's
/// body, a section, an item of `bodies` or `joints`): its statements are
/// counted each on its own, not as a part of the statement around it.
const SECTION_DEPTH: usize = 3;

/// Checks `input` against the limits, without recursion: the first limit
/// passed, as an error at the token where it is passed.
pub fn check(input: &TokenStream) -> syn::Result<()> {
    struct Level {
        tokens: proc_macro2::token_stream::IntoIter,
        /// Tokens of the current statement at this level (its nested
        /// groups included), and where it starts.
        statement: usize,
        start: Option<Span>,
        /// Whether this level is a section's brace group (its statements
        /// counted apart from the statement around it, separated by `;`
        /// and `,`).
        section: bool,
        /// Whether its tokens count towards a statement: not inside an
        /// attribute (a doc comment of any length is one attribute).
        counted: bool,
        /// Whether the last token was `#` (an attribute's bracket follows).
        pound: bool,
    }
    let mut total = 0usize;
    let mut items = 0usize;
    let mut stack = vec![Level {
        tokens: input.clone().into_iter(),
        statement: 0,
        start: None,
        section: true,
        counted: true,
        pound: false,
    }];
    while let Some(level) = stack.last_mut() {
        let Some(token) = level.tokens.next() else {
            // A nested group's statement counts towards the statement
            // around it, unless it is a section.
            if let Some(done) = stack.pop().filter(|d| !d.section && d.counted) {
                if let Some(outer) = stack.last_mut() {
                    outer.statement += done.statement;
                    outer.start = outer.start.or(done.start);
                    if outer.statement > MAX_EXPRESSION_TOKENS {
                        return Err(too_long(outer.start));
                    }
                }
            }
            continue;
        };
        total += 1;
        if total > MAX_TOKENS {
            return Err(syn::Error::new(
                token.span(),
                format!(
                    "this definition has more than {MAX_TOKENS} tokens, the most a definition \
                     may have; split the mechanism into smaller ones"
                ),
            ));
        }
        let pound = std::mem::replace(
            &mut level.pound,
            matches!(&token, TokenTree::Punct(p) if p.as_char() == '#'),
        );
        let separator =
            matches!(&token, TokenTree::Punct(p) if p.as_char() == ';' || p.as_char() == ',');
        if separator && level.section {
            level.statement = 0;
            level.start = None;
            items += 1;
            if items > MAX_ITEMS {
                return Err(syn::Error::new(
                    token.span(),
                    format!(
                        "this definition has more than {MAX_ITEMS} items (names, points, \
                         equations, …), the most a definition may have; split the mechanism \
                         into smaller ones"
                    ),
                ));
            }
            continue;
        }
        let attribute =
            pound && matches!(&token, TokenTree::Group(g) if g.delimiter() == Delimiter::Bracket);
        if level.counted && !attribute && !level.pound {
            level.statement += 1;
            level.start = level.start.or(Some(token.span()));
            if level.statement > MAX_EXPRESSION_TOKENS {
                return Err(too_long(level.start));
            }
        }
        if let TokenTree::Group(g) = token {
            let depth = stack.len();
            if depth >= MAX_NESTING {
                return Err(syn::Error::new(
                    g.span_open(),
                    format!(
                        "brackets, braces and parentheses nest more than {MAX_NESTING} deep \
                         here, the most a definition may nest; name the inner parts as \
                         points or write them as separate terms"
                    ),
                ));
            }
            let counted = !attribute && stack.last().is_some_and(|l| l.counted);
            let section = counted && g.delimiter() == Delimiter::Brace && depth <= SECTION_DEPTH;
            if let (true, Some(level)) = (section, stack.last_mut()) {
                // A section: its statements are counted on their own.
                level.statement = 0;
                level.start = None;
            }
            stack.push(Level {
                tokens: g.stream().into_iter(),
                statement: 0,
                start: None,
                section,
                counted,
                pound: false,
            });
        }
    }
    Ok(())
}

/// The error for an expression with more than [`MAX_EXPRESSION_TOKENS`]
/// tokens, at its first token.
fn too_long(start: Option<Span>) -> syn::Error {
    syn::Error::new(
        start.unwrap_or_else(Span::call_site),
        format!(
            "this expression has more than {MAX_EXPRESSION_TOKENS} tokens, the most one \
             expression or equation may have; split it into points or shorter terms"
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wrap(expression: &str) -> TokenStream {
        let text = format!(
            "pub struct M {{ params {{ a }} drivers {{ phi }} unknowns {{ x }} \
             loops {{ polar(a, phi) == vec2(x, {expression}); }} }}"
        );
        text.parse().unwrap_or_default()
    }

    /// Just inside each limit passes; one past it is an error naming it.
    #[test]
    fn nesting_is_limited() {
        // The struct's body, the section and vec2's arguments are three
        // levels; the parentheses add the rest.
        let inside = MAX_NESTING - 4;
        let ok = format!("{}a{}", "(".repeat(inside), ")".repeat(inside));
        assert!(check(&wrap(&ok)).is_ok());
        let deep = format!("{}a{}", "(".repeat(inside + 1), ")".repeat(inside + 1));
        let e = check(&wrap(&deep)).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|m| m.contains("nest more than 64")),
            "{e:?}"
        );
    }

    #[test]
    fn long_expressions_are_limited() {
        let terms = |n: usize| vec!["a"; n].join(" + ");
        // vec2(x, <sum>): `x`, `,` and the sum's 2n − 1 tokens, plus the
        // rest of the equation: well inside at 100 terms.
        assert!(check(&wrap(&terms(100))).is_ok());
        let e = check(&wrap(&terms(150))).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|m| m.contains("more than 256 tokens")),
            "{e:?}"
        );
        // The same tokens in separate statements pass.
        let many: String = (0..1000).map(|_| "a + a;").collect();
        let text: TokenStream = format!("pub struct M {{ loops {{ {many} }} }}")
            .parse()
            .unwrap_or_default();
        assert!(check(&text).is_ok());
    }

    #[test]
    fn items_are_limited() {
        let items = |n: usize| -> TokenStream {
            let names: Vec<String> = (0..n).map(|i| format!("p{i}")).collect();
            format!("pub struct M {{ params {{ {} }} }}", names.join(", "))
                .parse()
                .unwrap_or_default()
        };
        assert!(check(&items(MAX_ITEMS)).is_ok());
        let e = check(&items(MAX_ITEMS + 2)).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|m| m.contains("more than 5000 items")),
            "{e:?}"
        );
    }

    #[test]
    fn separate_statements_are_counted_apart() {
        let many: String = (0..1000).map(|_| "a + a;").collect();
        let text: TokenStream = format!("pub struct M {{ loops {{ {many} }} }}")
            .parse()
            .unwrap_or_default();
        assert!(check(&text).is_ok());
    }
}
