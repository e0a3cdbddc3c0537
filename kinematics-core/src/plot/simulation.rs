//! The plot of a forward simulation ([`crate::dynamics::forward`]): the
//! drivers' speeds and the energies against time.

use std::path::Path;

use plotters::prelude::*;

use crate::dynamics::Energy;
use crate::error::Error;
use crate::mechanism::{Kind, Role};
use crate::sweep::Table;
use crate::units::AngleUnit;

use super::chart::{Curve, PALETTE, Units, output, panel};

/// Plots into an SVG file at `path` a forward simulation: on the left the
/// rate of every driver against time (rad/s, deg/s with
/// [`Units::angle`], or the length unit per second), on the right the
/// kinetic and potential energies, the work of each load, and the balance
/// T + V − ΣW, which stays flat.
///
/// # Errors
/// [`Error::InvalidGeometry`] for a run with no samples or energies of
/// another length; [`Error::Output`] when the file cannot be written.
pub fn plot_simulation<T: Table + ?Sized>(
    sweep: &T,
    energy: &[Energy],
    work_names: &[String],
    units: Units,
    path: &Path,
) -> Result<(), Error> {
    if sweep.rows() == 0 || energy.len() != sweep.rows() {
        return Err(Error::InvalidGeometry {
            what: "plot_simulation",
            detail: format!(
                "{} samples and {} energies: plot a run's own, with one sample or more",
                sweep.rows(),
                energy.len()
            ),
        });
    }
    let mut rates = Vec::new();
    let mut kinds = Vec::new();
    for (j, c) in sweep.coordinates().iter().enumerate() {
        if c.role != Role::Driver {
            continue;
        }
        let factor = if c.kind == Kind::Angle && units.angle == AngleUnit::Degrees {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        kinds.push(c.kind);
        rates.push(Curve {
            label: format!("{}'", c.name),
            points: (0..sweep.rows())
                .map(|i| (sweep.at(i), sweep.coordinate(i, j, 1) * factor))
                .collect(),
            color: PALETTE[rates.len() % PALETTE.len()],
            width: 2,
        });
    }
    let rate_unit = match (kinds.iter().all(|k| *k == Kind::Angle), units.angle) {
        (true, AngleUnit::Degrees) => "deg/s".to_owned(),
        (true, _) => "rad/s".to_owned(),
        (false, _) if kinds.iter().all(|k| *k == Kind::Length) => format!("{}/s", units.length),
        _ => "rad/s or length per s".to_owned(),
    };
    let series = |label: String, f: &dyn Fn(&Energy) -> f64, k: usize| Curve {
        label,
        points: energy.iter().map(|e| (e.t, f(e))).collect(),
        color: PALETTE[k % PALETTE.len()],
        width: 2,
    };
    let mut energies = vec![
        series("kinetic T".into(), &|e| e.kinetic, 0),
        series("potential V".into(), &|e| e.potential, 1),
    ];
    for (w, name) in work_names.iter().enumerate() {
        energies.push(series(
            format!("work of {name}"),
            &move |e: &Energy| e.work.get(w).copied().unwrap_or(f64::NAN),
            2 + w,
        ));
    }
    let mut balance = series("T + V − ΣW".into(), &Energy::balance, 0);
    balance.color = RGBColor(0, 0, 0);
    balance.width = 1;
    energies.push(balance);
    let root = SVGBackend::new(path, (1200, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let (left, right) = root.split_horizontally(600);
    panel(
        &left,
        "driver speeds",
        "t (s)",
        &format!("speed ({rate_unit})"),
        &rates,
        path,
    )?;
    panel(
        &right,
        "energies and works",
        "t (s)",
        "energy (J)",
        &energies,
        path,
    )?;
    root.present().map_err(|e| output(path, e))
}
