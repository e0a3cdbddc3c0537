//! Plots of the figures of merit over a sweep ([`crate::merit`]).

use std::path::Path;

use plotters::prelude::*;

use crate::error::Error;
use crate::merit::transmission;
use crate::sweep::Table;

use super::chart::{Curve, PALETTE, Units, output, panel, x_axis};

/// The transmission angle μ below which (and above 180° − μ) designers
/// judge a dyad to transmit force poorly: 40°, drawn as the band's edges.
const MU_MIN_DEG: f64 = 40.0;

/// Plots into an SVG file at `path` the transmission angle μ (deg) of each
/// dyad of `pairs` (the names of its two links' angles: a four-bar's `th3`
/// and `th4`) against the swept driver, with the edges of the band
/// [40°, 140°] designers keep it in as thin grey lines.
///
/// ```
/// # use kinematics_core::{mechanism, plot::plot_transmission};
/// # mechanism! {
/// #     /// A four-bar.
/// #     pub struct FourBar {
/// #         params { a, b, c, d }
/// #         drivers { phi }
/// #         unknowns { th3, th4 }
/// #         points { B = polar(a, phi); D = vec2(d, 0.0); C = D + polar(c, th4); }
/// #         loops { B + polar(b, th3) == C; }
/// #     }
/// # }
/// let m = FourBar { a: 0.04, b: 0.12, c: 0.1, d: 0.11 };
/// let s = m.sweep(FourBar::PHI, &FourBarCoords { phi: 0.0, th3: 1.0, th4: 1.6 }).turn().run();
/// let file = std::env::temp_dir().join("four-bar-transmission.svg");
/// plot_transmission(&s, &[("th3", "th4")], &file)?;
/// let svg = std::fs::read_to_string(&file).expect("written");
/// assert!(svg.contains("transmission angle (deg)") && svg.contains("th3, th4"));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGeometry`] for a name that is not an angle coordinate
/// or a sweep with no samples, [`Error::Output`] when the file cannot be
/// written.
pub fn plot_transmission<T: Table + ?Sized>(
    sweep: &T,
    pairs: &[(&str, &str)],
    path: &Path,
) -> Result<(), Error> {
    let (x_title, x_scale) = x_axis(sweep, Units::METRES);
    let xs: Vec<f64> = (0..sweep.rows()).map(|i| sweep.at(i) * x_scale).collect();
    let mut curves = Vec::with_capacity(pairs.len() + 2);
    for (k, (first, second)) in pairs.iter().enumerate() {
        let t = transmission(sweep, first, second)?;
        curves.push(Curve {
            label: format!("{first}, {second}"),
            points: xs
                .iter()
                .zip(&t.values)
                .map(|(&x, &mu)| (x, mu.to_degrees()))
                .collect(),
            color: PALETTE[k % PALETTE.len()],
            width: 2,
        });
    }
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    for (label, mu) in [
        (format!("{MU_MIN_DEG}°"), MU_MIN_DEG),
        (format!("{}°", 180.0 - MU_MIN_DEG), 180.0 - MU_MIN_DEG),
    ] {
        curves.push(Curve {
            label,
            points: vec![(lo, mu), (hi, mu)],
            color: RGBColor(160, 160, 160),
            width: 1,
        });
    }
    let root = SVGBackend::new(path, (760, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    panel(
        &root,
        "transmission angles",
        &x_title,
        "transmission angle (deg)",
        &curves,
        path,
    )?;
    root.present().map_err(|e| output(path, e))
}
