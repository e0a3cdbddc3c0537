//! `kinematics report`: the sweep of `kinematics sweep`, its files, and one
//! HTML page (`report.html`) that gathers them for a reader: the
//! definition as written, what the compiler found in it (coordinates,
//! blocks, mobility), every assembly at the start, the figures of merit,
//! the skeleton, the plots of the motion and of every moving point's path,
//! the forces where the definition has them, and the animation. The page
//! is self-contained: its figures are inlined, it loads nothing from a
//! network and opens from a file in any browser.

use std::fmt::Write as _;
use std::path::Path;

use super::input::assemblies;
use super::sweep::swept;
use super::{read, Failure, SweepArgs};

/// Runs `kinematics report`: the sweep's summary and the page's path on
/// success.
pub(super) fn run(args: &SweepArgs) -> Result<String, Failure> {
    let text = read(&args.file)?;
    let done = swept(args)?;
    let m = &done.model;
    let mut page = String::new();
    let title = format!("{}: kinematic report", m.name());
    let _ = write!(
        page,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
        escape(&title),
        escape(&title)
    );
    let _ = writeln!(
        page,
        "<p class=\"source\">From <code>{}</code>.</p>",
        escape(&args.file.display().to_string())
    );
    if let Some(e) = &done.forces_error {
        let _ = writeln!(
            page,
            "<p class=\"stop\">The forces could not be computed: {}.</p>",
            escape(e.trim_start_matches("error: "))
        );
    }
    if let Some(stop) = &done.stop {
        let _ = writeln!(
            page,
            "<p class=\"stop\">The sweep stopped early: {}. The figures hold the samples \
             before the stop.</p>",
            escape(stop)
        );
    }
    let transmission = done
        .written
        .iter()
        .find(|f| file_name(f) == "transmission.svg")
        .map(|f| figure(f))
        .transpose()?
        .unwrap_or_default();
    section(
        &mut page,
        "merit",
        "Figures of merit",
        &(pre(&summary(&done.summary)) + &transmission),
    );
    let mut listed = assemblies(m, &done.start);
    if let Some(k) = m.assemble_all(&done.start).position(|(_, p)| {
        p.is_ok_and(|p| {
            p.iter()
                .zip(&done.start)
                .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))
        })
    }) {
        let _ = writeln!(listed, "the sweep starts in assembly {}", k + 1);
    }
    section(
        &mut page,
        "assemblies",
        "Assemblies at the start",
        &pre(&listed),
    );
    if let Some(anim) = done
        .written
        .iter()
        .find(|f| file_name(f) == "animation.html")
    {
        let html = std::fs::read_to_string(anim).map_err(|e| cannot_read(anim, &e))?;
        let frame = format!(
            "<iframe title=\"animation\" srcdoc=\"{}\"></iframe>",
            escape(&html)
        );
        section(&mut page, "animation", "Animation", &frame);
    }
    let figures = |names: &dyn Fn(&str) -> bool| -> Result<String, Failure> {
        let mut html = String::new();
        for f in done.written.iter().filter(|f| names(&file_name(f))) {
            html += &figure(f)?;
        }
        Ok(html)
    };
    section(
        &mut page,
        "skeleton",
        "The mechanism",
        &figures(&|n| n == "skeleton.svg")?,
    );
    section(
        &mut page,
        "motion",
        "The motion",
        &figures(&|n| n == "motion.svg" || n == "points.svg")?,
    );
    let paths = figures(&|n| n.starts_with("path-"))?;
    if !paths.is_empty() {
        section(&mut page, "paths", "Paths of the moving points", &paths);
    }
    let forces = figures(&|n| n == "forces.svg")?;
    if !forces.is_empty() {
        section(&mut page, "forces", "Forces", &forces);
    }
    section(&mut page, "definition", "The definition", &pre(&text));
    section(
        &mut page,
        "compiled",
        "What the compiler found",
        &pre(&m.describe()),
    );
    let mut files = String::from("<ul>");
    for f in &done.written {
        let n = escape(&file_name(f));
        let _ = write!(files, "<li><a href=\"{n}\">{n}</a></li>");
    }
    files += "</ul>";
    section(&mut page, "files", "Files", &files);
    page += "</body>\n</html>\n";
    let out = args.out.join("report.html");
    std::fs::write(&out, page)
        .map_err(|e| Failure::mechanism(format!("error: cannot write {}: {e}", out.display())))?;
    let mut summary = done.summary;
    let _ = writeln!(summary, "  wrote {}", out.display());
    if let Some(e) = done.forces_error {
        return Err(Failure::mechanism(format!(
            "{summary}{e}\n(the report holds the kinematics; the forces could not be computed)"
        )));
    }
    match done.stop {
        None => Ok(summary),
        Some(stop) => Err(Failure::mechanism(format!(
            "{summary}error: the sweep stopped early: {stop}\n(the report holds the samples \
             before the stop)"
        ))),
    }
}

/// The page's look: readable type, figures scaled to the page.
const STYLE: &str = "body{font-family:sans-serif;max-width:60rem;margin:1rem auto;padding:0 1rem;\
color:#222}h1{font-size:1.6rem}h2{font-size:1.25rem;border-bottom:1px solid #ccc;\
margin-top:2rem}pre{background:#f6f6f6;padding:.6rem;white-space:pre-wrap;font-size:.85rem}\
figure{margin:1rem 0}figure svg{max-width:100%;height:auto}figcaption{color:#555;\
font-size:.85rem}iframe{width:100%;height:62rem;border:1px solid #ccc}.stop{color:#a00}";

/// Appends a section titled `title` with the HTML `body`.
fn section(page: &mut String, id: &str, title: &str, body: &str) {
    let _ = writeln!(
        page,
        "<section id=\"{id}\">\n<h2>{}</h2>\n{body}\n</section>",
        escape(title)
    );
}

/// `text` preformatted.
fn pre(text: &str) -> String {
    format!("<pre>{}</pre>", escape(text))
}

/// The summary without the list of files written (the page lists them).
fn summary(text: &str) -> String {
    text.lines()
        .filter(|l| !l.trim_start().starts_with("wrote "))
        .map(|l| format!("{l}\n"))
        .collect()
}

/// The SVG file `f` inlined in a figure, captioned with its name.
fn figure(f: &Path) -> Result<String, Failure> {
    let svg = std::fs::read_to_string(f).map_err(|e| cannot_read(f, &e))?;
    // The document's own declaration has no place inside HTML.
    let body = svg.find("<svg").map_or(svg.as_str(), |i| &svg[i..]);
    Ok(format!(
        "<figure>{body}<figcaption>{}</figcaption></figure>",
        escape(&file_name(f))
    ))
}

fn file_name(f: &Path) -> String {
    f.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

fn cannot_read(f: &Path, e: &std::io::Error) -> Failure {
    Failure::mechanism(format!("error: cannot read {}: {e}", f.display()))
}

/// `text` with the characters that HTML reads as markup replaced.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}
