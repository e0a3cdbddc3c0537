//! An animation of a sweep as one self-contained HTML page (feature
//! `std`): the mechanism drawn in SVG, the path of every moving point, a
//! slider for the driver and a play button. The page needs no network and
//! no external script; open it in any browser.
//!
//! ```
//! use kinematics_core::{animate::write_html, mechanism, view::Projection};
//! mechanism! {
//!     /// A slider-crank.
//!     pub struct SliderCrank {
//!         params   { a, b }
//!         drivers  { phi }
//!         unknowns { th, x }
//!         points   { A = vec2(0.0, 0.0); B = polar(a, phi); C = vec2(x, 0.0); }
//!         loops    { B + polar(b, th) == C; }
//!     }
//! }
//! let m = SliderCrank { a: 0.1, b: 0.3 };
//! let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
//! let s = m.sweep(SliderCrank::PHI, &start).turn().steps(120).run();
//! let file = std::env::temp_dir().join("slider-crank.html");
//! write_html(&m, &s, &[("A", "B"), ("B", "C")], Projection::XY, &file)?;
//! let page = std::fs::read_to_string(&file).expect("written");
//! assert!(page.contains("<svg") && !page.contains("http"));
//! # Ok::<(), kinematics_core::Error>(())
//! ```

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::mechanism::{Kind, Mechanism, MotionState};
use crate::sweep::{Sweep, Table};
use crate::view::{PointRole, Projection, point_roles};

/// Writes an HTML page at `path` that plays the sweep `sweep` of `m`: each
/// link of `links` (pairs of point names) as a line, the path of every
/// moving point, ground pivots and sliders marked as in the skeleton plot,
/// a slider over the samples (one frame per sample) with the driver's value,
/// and a play/pause button. Spatial mechanisms are projected on
/// `projection`.
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point or a sweep with no
/// samples, [`Error::Output`] when the file cannot be written.
pub fn write_html<M: Mechanism>(
    m: &M,
    sweep: &Sweep<M>,
    links: &[(&str, &str)],
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let Some(first) = sweep.samples.first() else {
        return Err(no_samples());
    };
    let roles = point_roles(m, first.motion.q());
    let name = core::any::type_name::<M>()
        .rsplit("::")
        .next()
        .unwrap_or("mechanism");
    write_table_html(sweep, name, &roles, links, projection, path)
}

/// [`write_html`] for any sweep read as a [`Table`] (of a model compiled
/// at run time, say): `name` is the mechanism's name shown in the title,
/// `roles` the role of every point (from
/// [`point_roles_by`](crate::view::point_roles_by)), which marks the
/// ground pivots and the sliders.
///
/// # Errors
/// As [`write_html`]; [`Error::InvalidGeometry`] when `roles` does not
/// have a role per point.
pub fn write_table_html<T: Table + ?Sized>(
    sweep: &T,
    name: &str,
    roles: &[PointRole],
    links: &[(&str, &str)],
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let page = html(sweep, name, roles, links, projection)?;
    std::fs::write(path, page).map_err(|e| Error::Output {
        path: path.display().to_string(),
        detail: e.to_string(),
    })
}

fn no_samples() -> Error {
    Error::InvalidGeometry {
        what: "animation",
        detail: "the sweep has no samples to play".to_owned(),
    }
}

/// The page as a string.
fn html<T: Table + ?Sized>(
    sweep: &T,
    name: &str,
    roles: &[PointRole],
    links: &[(&str, &str)],
    projection: Projection,
) -> Result<String, Error> {
    let ends: Vec<(usize, usize)> = links
        .iter()
        .map(|(p, q)| {
            Ok((
                sweep.point_index(p, "animation")?,
                sweep.point_index(q, "animation")?,
            ))
        })
        .collect::<Result<_, Error>>()?;
    if sweep.rows() == 0 {
        return Err(no_samples());
    }
    let points = sweep.point_names().len();
    if roles.len() != points {
        return Err(Error::InvalidGeometry {
            what: "animation",
            detail: format!("{} point roles for {points} points", roles.len()),
        });
    }
    let frames: Vec<Vec<(f64, f64)>> = (0..sweep.rows())
        .map(|i| {
            (0..points)
                .map(|k| projection.of(sweep.point(i, k)[0]))
                .collect()
        })
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in frames.iter().flatten() {
        if p.0.is_finite() && p.1.is_finite() {
            x0 = x0.min(p.0);
            x1 = x1.max(p.0);
            y0 = y0.min(p.1);
            y1 = y1.max(p.1);
        }
    }
    if !(x0.is_finite() && y0.is_finite()) {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    let span = (x1 - x0).max(y1 - y0).max(1e-12);
    let pad = 0.12 * span;
    let (vx, vy, vw, vh) = (
        x0 - pad,
        -(y1 + pad),
        (x1 - x0) + 2.0 * pad,
        (y1 - y0) + 2.0 * pad,
    );
    let unit = span / 100.0;
    // The driver's value of each sample, as shown.
    let variable = sweep.variable();
    let label = |i: usize| -> String {
        let at = sweep.at(i);
        if variable == "t" {
            format!("t = {at:.4} s")
        } else if sweep.kind() == Kind::Angle {
            format!("{variable} = {:.2}°", at.to_degrees())
        } else {
            format!("{variable} = {at:.5} m")
        }
    };
    let mut out = String::new();
    let title = format!("{name} over the sweep of {variable}");
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>{title}</title>\n\
         <style>\nbody {{ font-family: sans-serif; margin: 1.5em; }}\n\
         svg {{ border: 1px solid #ccc; background: #fff; width: min(90vw, 720px); height: min(90vw, 720px); }}\n\
         .controls {{ margin: 0.8em 0; display: flex; gap: 1em; align-items: center; }}\n\
         input[type=range] {{ width: min(70vw, 560px); }}\n</style>\n</head>\n<body>\n\
         <h1 style=\"font-size: 1.2em\">{title}</h1>\n"
    );
    let _ = write!(
        out,
        "<svg id=\"view\" viewBox=\"{vx} {vy} {vw} {vh}\" role=\"img\">\n<g transform=\"scale(1,-1)\">\n"
    );
    // Paths of the moving points.
    for (k, role) in roles.iter().enumerate() {
        if *role == PointRole::Fixed {
            continue;
        }
        let pts: Vec<String> = frames
            .iter()
            .map(|f| format!("{:.6e},{:.6e}", f[k].0, f[k].1))
            .collect();
        let _ = writeln!(
            out,
            "<polyline class=\"path\" points=\"{}\" fill=\"none\" stroke=\"#9ecae1\" stroke-width=\"{}\"/>",
            pts.join(" "),
            unit * 0.3
        );
    }
    // Ground pivots.
    for (k, role) in roles.iter().enumerate() {
        if *role != PointRole::Fixed {
            continue;
        }
        let (px, py) = frames[0][k];
        let s = unit * 2.5;
        let _ = writeln!(
            out,
            "<polygon points=\"{px},{py} {},{} {},{}\" fill=\"#777\"/>\n<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#000\" stroke-width=\"{}\"/>",
            px - s,
            py - 1.6 * s,
            px + s,
            py - 1.6 * s,
            px - 1.5 * s,
            py - 1.65 * s,
            px + 1.5 * s,
            py - 1.65 * s,
            unit * 0.4
        );
    }
    for (i, _) in ends.iter().enumerate() {
        let _ = writeln!(
            out,
            "<line id=\"link{i}\" stroke=\"#1f77b4\" stroke-width=\"{}\" stroke-linecap=\"round\"/>",
            unit * 0.9
        );
    }
    for (k, role) in roles.iter().enumerate() {
        let _ = match role {
            PointRole::Slider => writeln!(
                out,
                "<rect id=\"point{k}\" width=\"{w}\" height=\"{h}\" fill=\"#d62728\" fill-opacity=\"0.3\" stroke=\"#d62728\" stroke-width=\"{sw}\"/>",
                w = unit * 5.0,
                h = unit * 3.4,
                sw = unit * 0.4
            ),
            _ => writeln!(
                out,
                "<circle id=\"point{k}\" r=\"{}\" fill=\"#fff\" stroke=\"#000\" stroke-width=\"{}\"/>",
                unit * 1.0,
                unit * 0.3
            ),
        };
    }
    out.push_str("</g>\n");
    for (k, name) in sweep.point_names().iter().enumerate() {
        let _ = writeln!(
            out,
            "<text id=\"name{k}\" font-size=\"{}\" fill=\"#333\">{name}</text>",
            unit * 3.5
        );
    }
    out.push_str("</svg>\n");
    let n = frames.len();
    let _ = write!(
        out,
        "<div class=\"controls\">\n<button id=\"play\" type=\"button\">play</button>\n\
         <input id=\"driver\" type=\"range\" min=\"0\" max=\"{}\" value=\"0\" step=\"1\"/>\n\
         <span id=\"value\"></span>\n</div>\n",
        n.saturating_sub(1)
    );
    // The frames, one array per sample: x, y of every point.
    out.push_str("<script id=\"frames\" type=\"application/json\">\n[\n");
    for (i, f) in frames.iter().enumerate() {
        let xs: Vec<String> = f
            .iter()
            .flat_map(|p| [p.0, p.1])
            .map(|v| {
                if v.is_finite() {
                    format!("{v:.6e}")
                } else {
                    "null".to_owned()
                }
            })
            .collect();
        let _ = write!(out, "[{}]", xs.join(","));
        out.push_str(if i + 1 == n { "\n" } else { ",\n" });
    }
    out.push_str("]\n</script>\n<script id=\"labels\" type=\"application/json\">\n[");
    let labels: Vec<String> = (0..sweep.rows())
        .map(|i| format!("\"{}\"", label(i)))
        .collect();
    out.push_str(&labels.join(","));
    out.push_str("]\n</script>\n");
    let links_js: Vec<String> = ends.iter().map(|(p, q)| format!("[{p},{q}]")).collect();
    let sliders: Vec<String> = roles
        .iter()
        .map(|r| if *r == PointRole::Slider { "1" } else { "0" }.to_owned())
        .collect();
    // The player; written without the characters `<` and `&`, so that the
    // page is well-formed XML as well as HTML.
    let _ = write!(
        out,
        "<script>\n\
         const frames = JSON.parse(document.getElementById('frames').textContent);\n\
         const labels = JSON.parse(document.getElementById('labels').textContent);\n\
         const links = [{links}];\n\
         const sliders = [{sliders}];\n\
         const unit = {unit};\n\
         const slider = document.getElementById('driver');\n\
         const value = document.getElementById('value');\n\
         function show(i) {{\n\
           const f = frames[i];\n\
           links.forEach(function (l, n) {{\n\
             const e = document.getElementById('link' + n);\n\
             e.setAttribute('x1', f[2 * l[0]]); e.setAttribute('y1', f[2 * l[0] + 1]);\n\
             e.setAttribute('x2', f[2 * l[1]]); e.setAttribute('y2', f[2 * l[1] + 1]);\n\
           }});\n\
           sliders.forEach(function (s, k) {{\n\
             const e = document.getElementById('point' + k);\n\
             if (s === 1) {{\n\
               e.setAttribute('x', f[2 * k] - 2.5 * unit); e.setAttribute('y', f[2 * k + 1] - 1.7 * unit);\n\
             }} else {{\n\
               e.setAttribute('cx', f[2 * k]); e.setAttribute('cy', f[2 * k + 1]);\n\
             }}\n\
             const t = document.getElementById('name' + k);\n\
             t.setAttribute('x', f[2 * k] + 1.5 * unit); t.setAttribute('y', -f[2 * k + 1] - 1.5 * unit);\n\
           }});\n\
           value.textContent = labels[i] + '  (sample ' + (i + 1) + ' of ' + frames.length + ')';\n\
         }}\n\
         slider.addEventListener('input', function () {{ show(Number(slider.value)); }});\n\
         let timer = null;\n\
         document.getElementById('play').addEventListener('click', function (ev) {{\n\
           if (timer !== null) {{ clearInterval(timer); timer = null; ev.target.textContent = 'play'; return; }}\n\
           ev.target.textContent = 'pause';\n\
           timer = setInterval(function () {{\n\
             const i = (Number(slider.value) + 1) % frames.length;\n\
             slider.value = i; show(i);\n\
           }}, Math.max(10, 4000 / frames.length));\n\
         }});\n\
         show(0);\n\
         </script>\n</body>\n</html>\n",
        links = links_js.join(","),
        sliders = sliders.join(","),
    );
    Ok(out)
}
