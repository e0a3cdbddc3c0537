//! A run-time model describes itself: its coordinates, equations, blocks
//! in solve order and how each is solved, its mobility, its bodies, loads
//! and joints, and its number of assemblies, as `kinematics check`
//! prints them, from the one compile that also made its machine code.

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt::Write as _;

use kinematics_compiler::dynamics::LoadTarget;
use kinematics_compiler::{ClosedForm, Mobility};

use super::Model;
use crate::mechanism::Kind;

/// The items of a list joined by ", ", or "–" for none.
fn list(items: &[String]) -> String {
    if items.is_empty() {
        "–".to_string()
    } else {
        items.join(", ")
    }
}

/// "s" unless `n` is 1.
fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

impl Model {
    /// The Kutzbach–Gruebler count of the definition's `joints { R: …, … }`
    /// section, F = λ(n − j − 1) + Σf − (passive freedoms), checked
    /// against the drivers when the model was compiled; `None` without
    /// such a section.
    #[must_use]
    pub fn mobility(&self) -> Option<Mobility> {
        self.mobility
    }

    /// The model described as `kinematics check` prints it: its name and
    /// counts; its parameters, drivers and unknowns (each an angle or a
    /// length), points and frames; its scalar equations, numbered; its
    /// diagonal blocks in solve order, each with the equations it is
    /// solved from and how (a closed form, which dyad, whether it has two
    /// assembly modes, or Newton–Raphson); its mobility; its bodies, loads
    /// and joints where it has them; and the number of its assemblies at
    /// a pose, 2 to the number of blocks with two modes.
    ///
    /// ```
    /// use kinematics_core::runtime::Model;
    /// let m = Model::compile(
    ///     "struct SliderCrank {
    ///          params   { a, b }
    ///          drivers  { phi }
    ///          unknowns { th, x }
    ///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    ///      }",
    /// )?;
    /// let text = m.describe();
    /// assert!(text.starts_with("SliderCrank: 1 driver, 2 unknowns, 2 scalar equations"));
    /// // The y equation, a sin φ + b sin θ = 0, fixes θ alone (two
    /// // solutions, θ and π − θ); then the x equation is linear in x.
    /// assert!(text.contains("th from equation 2: closed form, a cos θ + b sin θ + c = 0, two modes"));
    /// assert!(text.contains("x from equation 1: closed form, linear"));
    /// assert!(text.ends_with("assemblies: 2\n"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn describe(&self) -> String {
        let nd = self.drivers;
        let named = |c: &crate::mechanism::Coordinate| {
            let kind = match c.kind {
                Kind::Angle => "angle",
                Kind::Length => "length",
            };
            format!("{} ({kind})", c.name)
        };
        let mut out = String::new();
        let (nu, ne) = (self.unknowns(), self.equations.len());
        let _ = writeln!(
            out,
            "{}: {nd} driver{}, {nu} unknown{}, {ne} scalar equation{}",
            self.name,
            plural(nd),
            plural(nu),
            plural(ne),
        );
        let strings = |names: &[&str]| names.iter().map(ToString::to_string).collect::<Vec<_>>();
        let drivers: Vec<String> = self.coordinates[..nd].iter().map(named).collect();
        let unknowns: Vec<String> = self.coordinates[nd..].iter().map(named).collect();
        let _ = writeln!(out, "  parameters: {}", list(&strings(&self.params)));
        let _ = writeln!(out, "  drivers:    {}", list(&drivers));
        let _ = writeln!(out, "  unknowns:   {}", list(&unknowns));
        let _ = writeln!(out, "  points:     {}", list(&strings(&self.points)));
        let _ = writeln!(out, "  frames:     {}", list(&strings(&self.frames)));
        let _ = writeln!(out, "equations:");
        for (i, text) in self.equations.iter().enumerate() {
            let _ = writeln!(out, "  {}. {text}", i + 1);
        }
        let two_modes = self.describe_blocks(&mut out);
        self.describe_mobility(&mut out);
        self.describe_dynamics(&mut out);
        let _ = writeln!(
            out,
            "assemblies: {}",
            if two_modes < 64 {
                (1u64 << two_modes).to_string()
            } else {
                format!("2^{two_modes}")
            }
        );
        out
    }

    /// The blocks in solve order into `out`; the number with two modes.
    fn describe_blocks(&self, out: &mut String) -> u32 {
        let nd = self.drivers;
        let mut two_modes = 0u32;
        if !self.parts.is_empty() {
            let _ = writeln!(out, "blocks, in solve order:");
        }
        for part in &self.parts {
            let names: Vec<&str> = part
                .cols
                .iter()
                .map(|&k| self.coordinates[nd + k].name)
                .collect();
            let rows: Vec<String> = part.rows.iter().map(|r| (r + 1).to_string()).collect();
            let how = match &part.form {
                Some(form) => {
                    let modes = form.has_modes();
                    if modes {
                        two_modes += 1;
                    }
                    let kind = match form {
                        ClosedForm::Angle { .. } => "a cos θ + b sin θ + c = 0".to_string(),
                        ClosedForm::Linear { .. } => "linear".to_string(),
                        ClosedForm::CircleCircle { .. }
                        | ClosedForm::CircleLine { .. }
                        | ClosedForm::Slide { .. }
                        | ClosedForm::LineLine { .. } => format!("{} dyad", form.name()),
                    };
                    format!(
                        "closed form, {kind}{}",
                        if modes { ", two modes" } else { "" }
                    )
                }
                None => "Newton–Raphson".to_string(),
            };
            let _ = writeln!(
                out,
                "  {} from equation{} {}: {how}",
                names.join(", "),
                plural(rows.len()),
                rows.join(", ")
            );
        }
        two_modes
    }

    /// The mobility into `out`.
    fn describe_mobility(&self, out: &mut String) {
        match self.mobility {
            Some(m) => {
                let passive = if m.passive > 0 {
                    format!(" − {}", m.passive)
                } else {
                    String::new()
                };
                let _ = writeln!(
                    out,
                    "mobility: F = {}({} − {} − 1) + {}{passive} = {} (Kutzbach–Gruebler)",
                    m.lambda, m.links, m.joints, m.freedoms, m.mobility
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "mobility: not counted (no `joints {{ R: …, … }}` section of counts)"
                );
            }
        }
    }

    /// The bodies, loads and joints into `out`, where the model has them.
    fn describe_dynamics(&self, out: &mut String) {
        let Some(d) = self
            .sections
            .as_deref()
            .map(super::sections::SectionCode::sections)
        else {
            return;
        };
        let bodies: Vec<String> = d.bodies.iter().map(|b| b.name.clone()).collect();
        let mut loads: Vec<String> = Vec::new();
        if !d.gravity.is_empty() {
            loads.push("gravity".to_string());
        }
        for l in &d.loads {
            loads.push(match &l.target {
                LoadTarget::Point { point, .. } => format!("a force at {point}"),
                LoadTarget::Coordinate { coordinate } => format!("a force on {coordinate}"),
                LoadTarget::Torque { body } => format!("a torque on {body}"),
            });
        }
        for s in &d.springs {
            loads.push(format!("a spring {}–{}", s.from, s.to));
        }
        let joints: Vec<String> = d
            .joints
            .iter()
            .map(|j| {
                let driver = j
                    .driver
                    .as_ref()
                    .map_or_else(String::new, |d| format!(", driven by {d}"));
                format!(
                    "{} ({} at {}, {}–{}{driver})",
                    j.name,
                    j.kind.word(),
                    j.point,
                    j.between[0],
                    j.between[1]
                )
            })
            .collect();
        let _ = writeln!(out, "bodies: {}", list(&bodies));
        let _ = writeln!(out, "loads:  {}", list(&loads));
        let _ = writeln!(out, "joints: {}", list(&joints));
    }
}
