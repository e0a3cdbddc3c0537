//! Definitions given as text: [`compile_str`], and its errors located by
//! line and column, shown as rustc shows them (the message, the location,
//! the line with a caret under the offending tokens).

use std::fmt;

use proc_macro2::{LineColumn, TokenStream};

use crate::pipeline::{compile, Compiled};

/// One error in a definition given as text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// What is wrong and how to fix it, as `mechanism!` says it.
    pub message: String,
    /// Line of the first offending character, from 1.
    pub line: usize,
    /// Column of the first offending character, from 1, in characters.
    pub column: usize,
    /// Line and column (as above) just past the last offending character;
    /// on a later line when the offending tokens span several.
    pub end: (usize, usize),
    /// The text of the line `line`.
    pub excerpt: String,
}

impl Diagnostic {
    /// The diagnostic as rustc shows one, its location prefixed by the
    /// name of the file the text came from (`fourbar.mech:7:40`); the
    /// `Display` of a diagnostic has no file name.
    #[must_use]
    pub fn in_file<'a>(&'a self, file: &'a str) -> impl fmt::Display + 'a {
        Shown {
            diagnostic: self,
            file: Some(file),
        }
    }
}

impl fmt::Display for Diagnostic {
    /// ```text
    /// error: unknown name `th5`; did you mean `th3`?
    ///  --> 7:40
    ///   |
    /// 7 |     loops    { B + polar(b, th3) == C + polar(c, th5); }
    ///   |                                                  ^^^
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        Shown {
            diagnostic: self,
            file: None,
        }
        .fmt(f)
    }
}

/// A diagnostic shown with or without the name of its file.
struct Shown<'a> {
    diagnostic: &'a Diagnostic,
    file: Option<&'a str>,
}

impl fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let d = self.diagnostic;
        let number = d.line.to_string();
        let pad = " ".repeat(number.len());
        writeln!(f, "error: {}", d.message)?;
        match self.file {
            Some(file) => writeln!(f, "{pad}--> {file}:{}:{}", d.line, d.column)?,
            None => writeln!(f, "{pad}--> {}:{}", d.line, d.column)?,
        }
        writeln!(f, "{pad} |")?;
        writeln!(f, "{number} | {}", d.excerpt)?;
        let width = if d.end.0 == d.line {
            d.end.1.saturating_sub(d.column).max(1)
        } else {
            // To the end of the line.
            (d.excerpt.chars().count() + 1)
                .saturating_sub(d.column)
                .max(1)
        };
        // Tabs kept as tabs, so that the caret lines up in a terminal.
        let lead: String = d
            .excerpt
            .chars()
            .take(d.column.saturating_sub(1))
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        write!(f, "{pad} | {lead}{}", "^".repeat(width))
    }
}

/// Every error of a definition given as text, in the order `mechanism!`
/// reports them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, d) in self.0.iter().enumerate() {
            if k > 0 {
                f.write_str("\n\n")?;
            }
            write!(f, "{d}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

/// Compiles a definition given as text, exactly as written inside
/// `mechanism! { … }` (its doc comments, `pub struct Name { … }` and the
/// sections).
///
/// Tokens are located within `text`, whatever else was parsed before on
/// the thread. The locations are kept in the thread's table of source
/// text (as `proc_macro2` keeps them), which grows with every text
/// compiled on that thread.
///
/// # Errors
/// The same errors `mechanism!` reports, each located by line and column
/// in `text`; text that is not a sequence of Rust tokens (an unclosed
/// bracket or string) is reported where the lexer stopped.
///
/// ```
/// let err = kinematics_compiler::compile_str(
///     "struct M {\n    params { a }\n    drivers { phi }\n    unknowns { x }\n    \
///      loops { polar(a, phi) == vec2(x, y); }\n}",
/// )
/// .err()
/// .expect("`y` is not declared");
/// let d = &err.0[0];
/// assert_eq!((d.line, d.column), (5, 38));
/// assert!(d.message.contains("`y`"), "{}", d.message);
/// ```
pub fn compile_str(text: &str) -> Result<Compiled, Diagnostics> {
    let tokens: TokenStream = text.parse().map_err(|e: proc_macro2::LexError| {
        let span = e.span();
        Diagnostics(vec![diagnostic(
            text,
            "this text is not a sequence of Rust tokens: a bracket, brace or parenthesis \
             left open or closed twice, or a string, character or block comment not closed"
                .to_string(),
            span.start(),
            span.end(),
        )])
    })?;
    // Locations are relative to the text's own first token: other texts
    // parsed earlier on this thread do not shift them.
    compile(tokens).map_err(|errors| {
        Diagnostics(
            errors
                .into_iter()
                .map(|e| {
                    let span = e.span();
                    diagnostic(text, e.to_string(), span.start(), span.end())
                })
                .collect(),
        )
    })
}

/// A diagnostic at `start..end` (as `proc_macro2` reports them: lines from
/// 1, columns from 0) in `text`; a location outside the text (an error at
/// the end of the input) is put just past its last character.
fn diagnostic(text: &str, message: String, start: LineColumn, end: LineColumn) -> Diagnostic {
    let lines: Vec<&str> = text.lines().collect();
    let past_end = || {
        let line = lines.len().max(1);
        let column = lines.last().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    };
    let inside = |lc: LineColumn| {
        lc.line >= 1
            && lines
                .get(lc.line - 1)
                .is_some_and(|l| lc.column <= l.chars().count())
    };
    let (line, column) = if inside(start) {
        (start.line, start.column + 1)
    } else {
        past_end()
    };
    let end = if inside(end) && (end.line, end.column + 1) > (line, column) {
        (end.line, end.column + 1)
    } else {
        (line, column + 1)
    };
    Diagnostic {
        message,
        line,
        column,
        end,
        excerpt: lines.get(line - 1).copied().unwrap_or("").to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::compile_str;

    const FOUR_BAR: &str = "/// Four-bar.
pub struct FourBar {
    params   { a, b, c, d }
    drivers  { phi }
    unknowns { th3, th4 }
    loops    { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th5); }
}";

    /// The location is the offending token's in this text (found by a
    /// string search: `th5` starts at column 73 of line 6), however many
    /// texts the thread parsed before, and the caret sits under it.
    #[test]
    fn an_unknown_name_is_located_at_its_token() {
        let column = FOUR_BAR
            .lines()
            .nth(5)
            .and_then(|l| l.find("th5"))
            .map(|c| c + 1);
        assert_eq!(column, Some(73));
        for _ in 0..3 {
            let Err(e) = compile_str(FOUR_BAR) else {
                panic!("`th5` is not declared");
            };
            assert_eq!(e.0.len(), 1, "{e}");
            let d = &e.0[0];
            assert_eq!((d.line, d.column, d.end), (6, 73, (6, 76)), "{e}");
            assert!(d.message.contains("th5"), "{}", d.message);
            let shown = e.to_string();
            let lines: Vec<&str> = shown.lines().collect();
            assert_eq!(lines[1], " --> 6:73");
            assert_eq!(
                lines[3],
                format!("6 | {}", FOUR_BAR.lines().nth(5).unwrap_or(""))
            );
            assert_eq!(lines[4], format!("  | {}^^^", " ".repeat(72)));
        }
    }

    /// Several errors are all reported, each at its own token, in order.
    #[test]
    fn every_error_is_reported() {
        let text = FOUR_BAR.replace("vec2(d, 0.0)", "vec2(e, 0.0)");
        let e = compile_str(&text).err().expect("two undeclared names");
        let at: Vec<(usize, usize)> = e.0.iter().map(|d| (d.line, d.column)).collect();
        assert_eq!(at, [(6, 54), (6, 73)], "{e}");
    }

    /// Text that does not lex (an unclosed brace) and text that ends too
    /// early are errors located in the text, not panics.
    #[test]
    fn broken_text_is_an_error_inside_the_text() {
        let open = FOUR_BAR.replace("unknowns { th3, th4 }", "unknowns { th3, th4");
        let e = compile_str(&open).err().expect("an unclosed brace");
        assert!(
            e.0[0].message.contains("not a sequence of Rust tokens"),
            "{e}"
        );
        assert!(e.0[0].line >= 1 && e.0[0].line <= 7, "{e}");
        let cut = "pub struct FourBar { params { a }";
        let e = compile_str(cut).err().expect("unclosed");
        assert_eq!(e.0[0].line, 1, "{e}");
        let early = "pub struct FourBar";
        let e = compile_str(early).err().expect("no body");
        let d = &e.0[0];
        assert!(d.line == 1 && d.column <= early.len() + 1, "{e}");
        for text in [
            "",
            " ",
            "\n\n",
            "struct",
            "{}",
            "pub struct M { params { a } loops { } }",
        ] {
            let e = compile_str(text).err().expect("not a mechanism");
            assert!(
                !e.0.is_empty() && e.0.iter().all(|d| d.line >= 1 && d.column >= 1),
                "{text:?}"
            );
        }
    }
}
