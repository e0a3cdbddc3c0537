//! The forces along a sweep: each driver's effort against the swept
//! variable beside its mean, and the shaking force's polar diagram.

use std::path::Path;

use plotters::prelude::*;

use super::chart::{Curve, PALETTE, output, panel};
use crate::dynamics::ForceSweep;
use crate::error::Error;
use crate::mechanism::Kind;

/// Plots `forces` into an SVG file at `path`: on the left each driver's
/// effort against the swept variable (degrees for an angle) with its mean
/// over the range as a thin line of the same colour, then the shaking
/// force on the frame as a polar diagram (F_y against F_x, the tip of the
/// force vector over the cycle), its inertial part −Σ m a_G beside the
/// total with the weights and loads (Norton's), and where the sweep has the joint
/// reactions, each joint's force as a polar diagram likewise.
///
/// ```
/// # use kinematics_core::mechanism;
/// # use kinematics_core::dynamics::{Body, Dynamics};
/// # mechanism! {
/// #     /// Slider-crank.
/// #     pub struct SliderCrank {
/// #         params   { a, b }
/// #         drivers  { phi }
/// #         unknowns { th, x }
/// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
/// #         loops    { B + polar(b, th) == C; }
/// #     }
/// # }
/// # let m = SliderCrank { a: 0.1, b: 0.3 };
/// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
/// let s = m.sweep(SliderCrank::PHI, &start).turn().steps(72).rpm(600.0).run();
/// let dynamics = Dynamics::builder().body(Body::new("piston", 0.5).center("C")).build::<SliderCrank>()?;
/// let forces = dynamics.along(&m, &s)?;
/// let file = std::env::temp_dir().join("slider-crank-forces.svg");
/// kinematics_core::plot::plot_forces(&forces, &file)?;
/// let svg = std::fs::read_to_string(&file).expect("written");
/// assert!(svg.contains("Q_phi (N·m)") && svg.contains("shaking force"));
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::Output`] when the file cannot be written.
pub fn plot_forces(forces: &ForceSweep, path: &Path) -> Result<(), Error> {
    let joints: Vec<String> = forces
        .samples
        .first()
        .and_then(|s| s.reactions.as_ref())
        .map_or_else(Vec::new, |r| {
            r.joints.iter().map(|j| j.name.clone()).collect()
        });
    let panels = if joints.is_empty() { 2 } else { 3 };
    let width = if joints.is_empty() { 1120 } else { 1680 };
    let root = SVGBackend::new(path, (width, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| output(path, e))?;
    let areas = root.split_evenly((1, panels));
    let angle = forces.kind == Kind::Angle;
    let scale = if angle {
        180.0 / std::f64::consts::PI
    } else {
        1.0
    };
    let x_title = format!("{} ({})", forces.variable, if angle { "deg" } else { "m" });
    let mut curves = Vec::new();
    let mut units = Vec::new();
    for (k, (name, kind)) in forces.drivers.iter().enumerate() {
        let unit = if *kind == Kind::Angle { "N·m" } else { "N" };
        units.push(unit);
        let color = PALETTE[k % PALETTE.len()];
        curves.push(Curve {
            label: format!("Q_{name} ({unit})"),
            points: forces
                .samples
                .iter()
                .map(|s| (s.at * scale, s.effort.get(k).copied().unwrap_or(f64::NAN)))
                .collect(),
            color,
            width: 2,
        });
        if let (Some(mean), Some(first), Some(last)) = (
            forces.mean_effort(k),
            forces.samples.first(),
            forces.samples.last(),
        ) {
            // The mean in a dark shade of the curve's colour: tied to its
            // driver, and told apart from the curve where they cross.
            let shade = |c: u8| u8::try_from(u16::from(c) * 2 / 5).unwrap_or(c);
            curves.push(Curve {
                label: format!("mean {mean:.4} {unit}"),
                points: vec![(first.at * scale, mean), (last.at * scale, mean)],
                color: RGBColor(shade(color.0), shade(color.1), shade(color.2)),
                width: 2,
            });
        }
    }
    let y_title = if units.iter().all(|u| *u == "N·m") {
        "driving torque (N·m)"
    } else if units.iter().all(|u| *u == "N") {
        "driving force (N)"
    } else {
        "driving effort (N·m, N)"
    };
    if let Some(area) = areas.first() {
        panel(area, "driver efforts", &x_title, y_title, &curves, path)?;
    }
    let polar = [
        Curve {
            label: "inertial, −Σ m a_G".to_owned(),
            points: forces
                .samples
                .iter()
                .map(|s| (s.shaking_force.x, s.shaking_force.y))
                .collect(),
            color: PALETTE[1],
            width: 2,
        },
        Curve {
            label: "total, with weights and loads".to_owned(),
            points: forces
                .samples
                .iter()
                .map(|s| (s.frame_force.x, s.frame_force.y))
                .collect(),
            color: PALETTE[2],
            width: 2,
        },
    ];
    if let Some(area) = areas.get(1) {
        panel(
            area,
            "shaking force on the frame",
            "F_x (N)",
            "F_y (N)",
            &polar,
            path,
        )?;
    }
    let reactions: Vec<Curve> = joints
        .iter()
        .enumerate()
        .map(|(k, name)| Curve {
            label: name.clone(),
            points: forces
                .samples
                .iter()
                .filter_map(|s| s.reactions.as_ref()?.get(name))
                .map(|j| (j.force.x, j.force.y))
                .collect(),
            color: PALETTE[k % PALETTE.len()],
            width: 2,
        })
        .collect();
    if let (Some(area), false) = (areas.get(2), reactions.is_empty()) {
        panel(
            area,
            "joint reactions",
            "F_x (N)",
            "F_y (N)",
            &reactions,
            path,
        )?;
    }
    root.present().map_err(|e| output(path, e))
}
