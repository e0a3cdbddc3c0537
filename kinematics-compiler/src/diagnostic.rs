//! Definitions given as text: [`compile_str`], and its errors located by
//! line and column, shown as rustc shows them (the message, the location,
//! the line with a caret under the offending tokens).

use std::fmt;
use std::ops::Range;
use std::sync::Arc;

use proc_macro2::{LineColumn, TokenStream};

use crate::limits::MAX_TEXT_BYTES;
use crate::pipeline::{compile, Compiled};

/// The line of the text that a [`Diagnostic`] points into. Every
/// diagnostic of one text shares that text (one copy, however many
/// errors), and reads as the line's `&str`.
#[derive(Clone)]
pub struct Excerpt {
    text: Arc<str>,
    range: Range<usize>,
}

impl Excerpt {
    /// The line, without its line break.
    #[must_use]
    pub fn as_str(&self) -> &str {
        self.text.get(self.range.clone()).unwrap_or("")
    }
}

impl std::ops::Deref for Excerpt {
    type Target = str;
    fn deref(&self) -> &str {
        self.as_str()
    }
}

impl fmt::Debug for Excerpt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl fmt::Display for Excerpt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl PartialEq for Excerpt {
    fn eq(&self, other: &Self) -> bool {
        self.as_str() == other.as_str()
    }
}

impl Eq for Excerpt {}

impl PartialEq<str> for Excerpt {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl PartialEq<&str> for Excerpt {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

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
    /// The text of the line `line` (shared with the other diagnostics of
    /// the same text).
    pub excerpt: Excerpt,
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
        // A long line is shown as a window of at most `WINDOW` characters
        // around the caret, so that what is printed stays in proportion
        // to the number of errors, not to the length of the line.
        const WINDOW: usize = 160;
        let line = d.excerpt.as_str();
        let length = line.chars().count();
        let column = d.column.saturating_sub(1);
        let width = if d.end.0 == d.line {
            d.end.1.saturating_sub(d.column).max(1)
        } else {
            // To the end of the line.
            (length + 1).saturating_sub(d.column).max(1)
        };
        let (skip, ellipsis) = if length > WINDOW && column > WINDOW / 2 {
            (column - WINDOW / 2, "…")
        } else {
            (0, "")
        };
        let shown: String = line.chars().skip(skip).take(WINDOW).collect();
        let tail = if skip + WINDOW < length { "…" } else { "" };
        writeln!(f, "{number} | {ellipsis}{shown}{tail}")?;
        // Tabs kept as tabs, so that the caret lines up in a terminal.
        let lead: String = ellipsis
            .chars()
            .map(|_| ' ')
            .chain(line.chars().skip(skip).take(column - skip).map(|c| {
                if c == '\t' {
                    '\t'
                } else {
                    ' '
                }
            }))
            .collect();
        let width = width.min(WINDOW + 1 - (column - skip).min(WINDOW));
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
/// the thread. The lexer keeps each text it reads in a table of the
/// thread's (as `proc_macro2` keeps them), for the tokens' locations;
/// once the diagnostics are made the table is emptied, so a thread that
/// compiles many definitions does not grow. (The table is
/// `proc_macro2`'s: other text parsed with it on the same thread loses
/// its locations too; `Span::start` on its tokens then panics.)
///
/// The text is untrusted input: past the limits of
/// [`limits`](crate::limits) (nesting, length of an expression, items,
/// size) it is an error at the offending token, never a stack overflow.
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
    if text.len() > MAX_TEXT_BYTES {
        let source = Source::new(text);
        let start = LineColumn { line: 1, column: 0 };
        return Err(Diagnostics(vec![source.diagnostic(
            format!(
                "this definition is {} bytes long, more than the {} MiB a definition may have",
                text.len(),
                MAX_TEXT_BYTES >> 20
            ),
            start,
            start,
        )]));
    }
    let result = compile_tokens(text);
    // The lexer keeps every text it has read, for the locations of its
    // tokens, in a table of the thread's; the locations are all read by
    // now, so the table is emptied: a thread that compiles many
    // definitions does not grow.
    release_locations();
    result
}

/// [`compile_str`] without the check of the text's size and the release
/// of its locations.
fn compile_tokens(text: &str) -> Result<Compiled, Diagnostics> {
    let tokens: TokenStream = text.parse().map_err(|e: proc_macro2::LexError| {
        let span = e.span();
        Diagnostics(vec![Source::new(text).diagnostic(
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
        let source = Source::new(text);
        Diagnostics(
            errors
                .into_iter()
                .map(|e| {
                    let span = e.span();
                    source.diagnostic(e.to_string(), span.start(), span.end())
                })
                .collect(),
        )
    })
}

/// Empties the thread's table of the texts its lexer has read (see
/// `proc_macro2::extra::invalidate_current_thread_spans`). Inside a
/// procedural macro, where the compiler keeps the locations, there is no
/// such table and nothing is done.
fn release_locations() {
    // The call panics (before changing anything) only inside a procedural
    // macro, where `compile_str` has no use: `compile` takes the macro's
    // tokens. The unwind, if any, stops here.
    let _ = std::panic::catch_unwind(proc_macro2::extra::invalidate_current_thread_spans);
}

/// A text and where its lines start, for the diagnostics of one compile:
/// the lines are found once, and every excerpt shares the text.
struct Source {
    text: Arc<str>,
    /// The byte offset at which each line starts, and its length in bytes
    /// (without the line break) and in characters.
    lines: Vec<(usize, usize, usize)>,
}

impl Source {
    fn new(text: &str) -> Self {
        let mut lines = Vec::new();
        let mut start = 0;
        for line in text.lines() {
            lines.push((start, line.len(), line.chars().count()));
            // `lines` splits at "\n" and drops a "\r" before it.
            start += line.len();
            let rest = &text.as_bytes()[start.min(text.len())..];
            start += match rest {
                [b'\r', b'\n', ..] => 2,
                [b'\n', ..] => 1,
                _ => 0,
            };
        }
        Source {
            text: Arc::from(text),
            lines,
        }
    }

    /// A diagnostic at `start..end` (as `proc_macro2` reports them: lines
    /// from 1, columns from 0); a location outside the text (an error at
    /// the end of the input) is put just past its last character.
    fn diagnostic(&self, message: String, start: LineColumn, end: LineColumn) -> Diagnostic {
        let lines = &self.lines;
        let past_end = || {
            let line = lines.len().max(1);
            let column = lines.last().map_or(0, |l| l.2) + 1;
            (line, column)
        };
        let inside = |lc: LineColumn| {
            lc.line >= 1 && lines.get(lc.line - 1).is_some_and(|l| lc.column <= l.2)
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
        let range = lines
            .get(line - 1)
            .map_or(0..0, |&(from, bytes, _)| from..from + bytes);
        Diagnostic {
            message,
            line,
            column,
            end,
            excerpt: Excerpt {
                text: Arc::clone(&self.text),
                range,
            },
        }
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
