//! Drawings for a CAD program (feature `std`): the skeleton of a
//! mechanism at one sample of a sweep and the path of every moving point
//! over the sweep, as a DXF file (release 12, ASCII), the exchange format
//! every CAD program reads.
//!
//! The drawing is in the plane of a [`Projection`] and in the
//! definition's own length unit (DXF drawings carry no unit of their
//! own). Its layers, each with its own colour:
//!
//! | layer | entities |
//! |---|---|
//! | `LINKS` | a `LINE` between the two points of every link drawn |
//! | `PIVOTS` | a `CIRCLE` at every ground pivot |
//! | `JOINTS` | a `CIRCLE` at every moving point, a slider's included |
//! | `PATHS` | a `POLYLINE` through every moving point's positions over the sweep, closed where the sweep is a full turn |
//! | `NAMES` | a `TEXT` with every point's name beside it |
//!
//! ```
//! use kinematics_core::{dxf::dxf, mechanism, view::{point_roles, Projection}};
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
//! let roles = point_roles(&m, &start);
//! let text = dxf(&s, 0, &roles, &[("A", "B"), ("B", "C")], Projection::XY)?;
//! assert!(text.starts_with("0\nSECTION\n") && text.ends_with("0\nEOF\n"));
//! assert_eq!(text.matches("\nLINE\n").count(), 2);
//! # Ok::<(), kinematics_core::Error>(())
//! ```

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Error;
use crate::sweep::Table;
use crate::view::{PointRole, Projection};

/// The layers, with their AutoCAD colour numbers.
const LAYERS: [(&str, u8); 5] = [
    ("LINKS", 7),
    ("PIVOTS", 1),
    ("JOINTS", 5),
    ("PATHS", 3),
    ("NAMES", 8),
];

/// Writes [`dxf`] of `sweep` into the file `path`.
///
/// # Errors
/// As [`dxf`]; [`Error::Output`] when the file cannot be written.
pub fn write_dxf<T: Table + ?Sized>(
    sweep: &T,
    row: usize,
    roles: &[PointRole],
    links: &[(&str, &str)],
    projection: Projection,
    path: &Path,
) -> Result<(), Error> {
    let text = dxf(sweep, row, roles, links, projection)?;
    std::fs::write(path, text).map_err(|e| Error::Output {
        path: path.display().to_string(),
        detail: e.to_string(),
    })
}

/// The DXF drawing of `sweep`: the skeleton at sample `row` (each link of
/// `links`, pairs of point names, as a line; each point as a circle,
/// ground pivots on their own layer by `roles`, the role of every point
/// from [`point_roles_by`](crate::view::point_roles_by); the points'
/// names) and the path of every point that moves over the sweep, in the
/// plane of `projection`. The circles' radius and the names' height are
/// 1 % and 2 % of the drawing's larger extent.
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point, a sample past the
/// end of the sweep, `roles` without a role per point, or a position
/// that is not finite.
pub fn dxf<T: Table + ?Sized>(
    sweep: &T,
    row: usize,
    roles: &[PointRole],
    links: &[(&str, &str)],
    projection: Projection,
) -> Result<String, Error> {
    let invalid = |detail: String| Error::InvalidGeometry {
        what: "DXF drawing",
        detail,
    };
    let ends: Vec<(usize, usize)> = links
        .iter()
        .map(|(p, q)| {
            Ok((
                sweep.point_index(p, "DXF drawing")?,
                sweep.point_index(q, "DXF drawing")?,
            ))
        })
        .collect::<Result<_, Error>>()?;
    let names = sweep.point_names();
    if roles.len() != names.len() {
        return Err(invalid(format!(
            "{} point roles for {} points",
            roles.len(),
            names.len()
        )));
    }
    if row >= sweep.rows() {
        return Err(invalid(format!(
            "sample {row} asked of a sweep of {} samples",
            sweep.rows()
        )));
    }
    let at = |i: usize, k: usize| -> (f64, f64) { projection.of(sweep.point(i, k)[0]) };
    let moving: Vec<usize> = (0..names.len())
        .filter(|&k| roles[k] != PointRole::Fixed)
        .collect();
    let mut extent = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (i, k) in (0..sweep.rows())
        .flat_map(|i| moving.iter().map(move |&k| (i, k)))
        .chain((0..names.len()).map(|k| (row, k)))
    {
        let (x, y) = at(i, k);
        if !(x.is_finite() && y.is_finite()) {
            return Err(invalid(format!(
                "point {} is not finite at sample {i}",
                names[k]
            )));
        }
        extent = (
            extent.0.min(x),
            extent.1.max(x),
            extent.2.min(y),
            extent.3.max(y),
        );
    }
    if !extent.0.is_finite() {
        // No point at all: an empty drawing about the origin.
        extent = (0.0, 0.0, 0.0, 0.0);
    }
    let size = (extent.1 - extent.0).max(extent.3 - extent.2);
    let size = if size > 0.0 { size } else { 1.0 };
    let mut out = String::new();
    header(&mut out, extent);
    out += "0\nSECTION\n2\nENTITIES\n";
    for &(p, q) in &ends {
        let ((x0, y0), (x1, y1)) = (at(row, p), at(row, q));
        let _ = write!(
            out,
            "0\nLINE\n8\nLINKS\n10\n{x0}\n20\n{y0}\n30\n0.0\n11\n{x1}\n21\n{y1}\n31\n0.0\n"
        );
    }
    for (k, name) in names.iter().enumerate() {
        let (x, y) = at(row, k);
        let layer = if roles[k] == PointRole::Fixed {
            "PIVOTS"
        } else {
            "JOINTS"
        };
        let (r, h) = (0.01 * size, 0.02 * size);
        let _ = write!(
            out,
            "0\nCIRCLE\n8\n{layer}\n10\n{x}\n20\n{y}\n30\n0.0\n40\n{r}\n\
             0\nTEXT\n8\nNAMES\n10\n{}\n20\n{}\n30\n0.0\n40\n{h}\n1\n{}\n",
            x + 1.5 * r,
            y + 1.5 * r,
            text(name)
        );
    }
    let closed = crate::sweep::closing_period(sweep.rows(), |i| sweep.at(i)).is_some();
    for &k in &moving {
        // Closed polyline (70 = 1) over a full turn, open otherwise.
        let _ = write!(
            out,
            "0\nPOLYLINE\n8\nPATHS\n66\n1\n10\n0.0\n20\n0.0\n30\n0.0\n70\n{}\n",
            u8::from(closed)
        );
        for i in 0..sweep.rows() {
            let (x, y) = at(i, k);
            let _ = write!(out, "0\nVERTEX\n8\nPATHS\n10\n{x}\n20\n{y}\n30\n0.0\n");
        }
        out += "0\nSEQEND\n8\nPATHS\n";
    }
    out += "0\nENDSEC\n0\nEOF\n";
    Ok(out)
}

/// The header (the release, the drawing's extent) and the layer table.
fn header(out: &mut String, (x0, x1, y0, y1): (f64, f64, f64, f64)) {
    let _ = write!(
        out,
        "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1009\n\
         9\n$EXTMIN\n10\n{x0}\n20\n{y0}\n30\n0.0\n\
         9\n$EXTMAX\n10\n{x1}\n20\n{y1}\n30\n0.0\n0\nENDSEC\n"
    );
    let _ = write!(
        out,
        "0\nSECTION\n2\nTABLES\n0\nTABLE\n2\nLAYER\n70\n{}\n",
        LAYERS.len()
    );
    for (name, colour) in LAYERS {
        let _ = write!(
            out,
            "0\nLAYER\n2\n{name}\n70\n0\n62\n{colour}\n6\nCONTINUOUS\n"
        );
    }
    out.push_str("0\nENDTAB\n0\nENDSEC\n");
}

/// A point's name as a DXF string: one line, no control characters, and
/// every character past ASCII as the `\U+XXXX` escape CAD programs read
/// (a release-12 file is read in its code page otherwise).
fn text(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars().filter(|c| !c.is_control()) {
        if c.is_ascii() {
            out.push(c);
        } else {
            let _ = write!(out, "\\U+{:04X}", u32::from(c));
        }
    }
    out
}
