//! The figures of merit `kinematics sweep` prints after its summary
//! ([`kinematics_core::merit`]): for every unknown, its dead centres over
//! the sweep, the stroke of every length, its least mechanical advantage
//! (the driver's rate over its own), the time ratio where the sweep
//! is a turn and the output has one forward and one return stroke; for
//! every block of two unknown angles (a dyad whose links they are), the
//! transmission angle's extremes.

use std::fmt::Write as _;

use kinematics_core::merit::{
    dead_centres, mechanical_advantage, stroke, time_ratio, transmission,
};
use kinematics_core::runtime::{Model, Sweep};
use kinematics_core::sweep::Table;
use kinematics_core::units::AngleUnit;
use kinematics_core::Kind;

/// The lines of figures for `sweep` of `m`, the driver's values written
/// by `at` and angles in `angles`.
pub(super) fn figures(
    m: &Model,
    sweep: &Sweep,
    at: &dyn Fn(f64) -> String,
    angles: AngleUnit,
) -> String {
    let mut out = String::new();
    let angle = |x: f64| match angles {
        AngleUnit::Degrees => format!("{:.4}°", x.to_degrees()),
        AngleUnit::Radians => format!("{x:.6} rad"),
    };
    let value = |j: usize, x: f64| match m.coordinates()[j].kind {
        Kind::Angle => angle(x),
        Kind::Length => format!("{x:.6}"),
    };
    let mut lines = Vec::new();
    for j in m.drivers()..m.coordinates().len() {
        let name = m.coordinates()[j].name;
        let Ok(centres) = dead_centres(sweep, name) else {
            continue;
        };
        let mut line = format!("{name}:");
        if m.coordinates()[j].kind == Kind::Length {
            if let Ok(s) = stroke(sweep, name) {
                let _ = write!(
                    line,
                    " stroke {:.6} (from {:.6} to {:.6});",
                    s.length(),
                    s.min,
                    s.max
                );
            }
        }
        if centres.is_empty() {
            line += " no dead centre over the sweep";
        } else {
            let listed: Vec<String> = centres
                .iter()
                .map(|d| {
                    format!(
                        "{} {} at {}",
                        if d.maximum { "maximum" } else { "minimum" },
                        value(j, d.value),
                        at(d.at)
                    )
                })
                .collect();
            let _ = write!(line, " dead centres: {}", listed.join(", "));
        }
        if let Ok(ma) = mechanical_advantage(sweep, name) {
            let _ = write!(
                line,
                "; mechanical advantage |{}'/{name}'| at least {:.6} at {}",
                sweep.variable(),
                ma.least.1,
                at(ma.least.0)
            );
        }
        if let Ok(r) = time_ratio(sweep, name) {
            let _ = write!(
                line,
                "; time ratio {:.6} (rising over {}, falling over {} of the input)",
                r.ratio(),
                angle(r.rising),
                angle(r.falling)
            );
        }
        lines.push(line);
    }
    for (first, second) in dyads(m) {
        {
            if let Ok(t) = transmission(sweep, first, second) {
                lines.push(format!(
                    "{first}, {second}: transmission angle (between the two links) from {} at {} \
                     to {} at {}",
                    angle(t.min.1),
                    at(t.min.0),
                    angle(t.max.1),
                    at(t.max.0)
                ));
            }
        }
    }
    if !lines.is_empty() {
        out += "  figures of merit:\n";
        for l in lines {
            let _ = writeln!(out, "    {l}");
        }
    }
    out
}

/// The blocks of two unknown angles (dyads whose links they are), as the
/// pairs of their names.
pub(super) fn dyads(m: &Model) -> Vec<(&str, &str)> {
    m.blocks()
        .iter()
        .filter_map(|b| {
            let names: Vec<&str> = b
                .unknowns
                .iter()
                .copied()
                .filter(|u| {
                    m.index(u)
                        .is_some_and(|j| m.coordinates()[j].kind == Kind::Angle)
                })
                .collect();
            match names[..] {
                [first, second] => Some((first, second)),
                _ => None,
            }
        })
        .collect()
}
