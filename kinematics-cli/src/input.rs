//! What the command reads besides the definition: parameter values,
//! coordinates, rates and accelerations given as `name=value` arguments
//! or in a parameters file, each value a number with an optional unit
//! (`90deg`, `30 deg/s`, `120rpm`: [`kinematics_core::units`]); the start
//! pose, with no guess needed where every block has a closed form (an
//! assembly chosen by number or by its modes instead); and the assemblies
//! at a pose, as `check --at` lists them.

use std::fmt::Write as _;
use std::path::Path;

use kinematics_core::closed::Mode;
use kinematics_core::runtime::Model;
use kinematics_core::units::{self, AngleUnit, Order};
use kinematics_core::Kind;

use super::{read, Failure};

/// What a parameters file holds: the parameters' values, the start pose
/// (its `[start]` table) and the links to draw (`links` of its `[draw]`
/// table); each value as its text, read with its unit where it is used.
#[derive(Default)]
pub(super) struct ParamsFile {
    pub(super) values: Vec<(String, String)>,
    pub(super) start: Vec<(String, String)>,
    pub(super) links: Vec<String>,
}

/// A TOML number or string (a number with a unit, `"30deg"`) as text, or
/// a usage error naming `key` in `file`.
fn value_text(file: &Path, key: &str, v: &toml::Value) -> Result<String, Failure> {
    match v {
        // Rust's `Display` of an f64 reads back as the same number.
        toml::Value::Float(x) => Ok(x.to_string()),
        toml::Value::Integer(i) => Ok(i.to_string()),
        toml::Value::String(s) => Ok(s.clone()),
        other => Err(Failure::usage(format!(
            "error: {}: `{key}` is {}, not a number (or a number with a unit, as \"30deg\")",
            file.display(),
            other.type_str()
        ))),
    }
}

/// Reads a parameters file: `name = number` lines (or `name = "30deg"`),
/// an optional `[start]` table of the same, an optional `[draw]` table
/// with `links`.
pub(super) fn params_file(file: &Path) -> Result<ParamsFile, Failure> {
    let text = read(file)?;
    let table: toml::Table = text
        .parse()
        .map_err(|e| Failure::usage(format!("error: {}: {e}", file.display())))?;
    let mut out = ParamsFile::default();
    for (k, v) in table {
        match (k.as_str(), v) {
            ("start", toml::Value::Table(t)) => {
                for (name, v) in t {
                    let value = value_text(file, &format!("start.{name}"), &v)?;
                    out.start.push((name, value));
                }
            }
            ("draw", toml::Value::Table(t)) => {
                for (name, v) in t {
                    let links = match (name.as_str(), v) {
                        ("links", toml::Value::Array(a)) => a
                            .into_iter()
                            .map(|l| match l {
                                toml::Value::String(s) => Ok(s),
                                other => Err(other.type_str()),
                            })
                            .collect::<Result<Vec<String>, _>>()
                            .ok(),
                        _ => None,
                    };
                    out.links.extend(links.ok_or_else(|| {
                        Failure::usage(format!(
                            "error: {}: `draw.{name}`: the [draw] table holds only \
                             `links = [\"A-B\", …]`",
                            file.display()
                        ))
                    })?);
                }
            }
            (_, v) => {
                let value = value_text(file, &k, &v)?;
                out.values.push((k, value));
            }
        }
    }
    Ok(out)
}

/// `name=value` arguments split at their `=`, the value kept as text.
pub(super) fn pairs(args: &[String], what: &str) -> Result<Vec<(String, String)>, Failure> {
    args.iter()
        .map(|a| {
            let (name, value) = a.split_once('=').ok_or_else(|| {
                Failure::usage(format!("error: {what} `{a}` is not `name=value`"))
            })?;
            Ok((name.trim().to_string(), value.trim().to_string()))
        })
        .collect()
}

/// Sets the parameters from `file`'s values then the `--param` pairs
/// (a number, or a number with an angle's unit, in radians then); every
/// parameter must have a value.
pub(super) fn set_parameters(
    m: &mut Model,
    file: &ParamsFile,
    param: &[String],
) -> Result<(), Failure> {
    let mut values = file.values.clone();
    values.extend(pairs(param, "parameter")?);
    for (name, text) in &values {
        let value = units::read_parameter(text)
            .map_err(|e| Failure::usage(format!("error: parameter `{name}` = `{text}`: {e}")))?
            .value;
        m.set(name, value)
            .map_err(|e| Failure::usage(format!("error: {e}")))?;
    }
    if let Some(missing) = m
        .parameters()
        .iter()
        .zip(m.values())
        .find(|(_, v)| v.is_nan())
    {
        return Err(Failure::usage(format!(
            "error: parameter `{}` has no value: give it with --param {}=<value> or in --params",
            missing.0, missing.0
        )));
    }
    Ok(())
}

/// The index of coordinate `name`, or a usage error listing them.
pub(super) fn coordinate(m: &Model, name: &str, what: &str) -> Result<usize, Failure> {
    m.index(name).ok_or_else(|| {
        let names: Vec<&str> = m.coordinates().iter().map(|c| c.name).collect();
        Failure::usage(format!(
            "error: {what} `{name}` is not a coordinate of {}; its coordinates are {}",
            m.name(),
            names.join(", ")
        ))
    })
}

/// `text` read as the `order` (value, rate, acceleration) of coordinate
/// `j`: radians for an angle with no unit (with a warning where that
/// looks like degrees), its unit converted otherwise; a length's number
/// as written. `origin` names the argument in the messages.
pub(super) fn coordinate_value(
    m: &Model,
    j: usize,
    text: &str,
    order: Order,
    origin: &str,
) -> Result<f64, Failure> {
    let c = &m.coordinates()[j];
    let angle = c.kind == Kind::Angle;
    let reading = units::read(text, order, angle).map_err(|e| {
        let kind = if angle { "an angle" } else { "a length" };
        Failure::usage(format!(
            "error: {origin} `{}={text}` ({} is {kind}): {e}",
            c.name, c.name
        ))
    })?;
    if angle && reading.looks_like_degrees(order) {
        eprintln!(
            "warning: {origin} `{}={text}` is read as {text} rad ({:.1} turns); \
             write {text}deg for degrees",
            c.name,
            reading.value / core::f64::consts::TAU
        );
    }
    Ok(reading.value)
}

/// The `name=value` arguments `args` (`what`: "rate", "acceleration")
/// of the drivers, each in the units of its driver: every driver's value
/// (0 where none is given).
pub(super) fn driver_values(
    m: &Model,
    args: &[String],
    order: Order,
    what: &str,
) -> Result<Vec<f64>, Failure> {
    let mut out = vec![0.0; m.drivers()];
    for (name, text) in pairs(args, what)? {
        let j = coordinate(m, &name, what)?;
        if j >= m.drivers() {
            return Err(Failure::usage(format!(
                "error: `{name}` is an unknown: only drivers are given a {what}"
            )));
        }
        out[j] = coordinate_value(m, j, &text, order, &format!("--{what}"))?;
    }
    Ok(out)
}

/// The assembly modes named by `--assembly`: a number from 1 to 2^k (as
/// `check --at` lists them: assembly i + 1 has block j in `−` where bit j
/// of i is set), or one sign per block with two modes, in solve order
/// (`+-`).
pub(super) fn modes(m: &Model, assembly: &str) -> Result<Vec<Mode>, Failure> {
    let k = m.mode_count();
    let count = 1u64.checked_shl(u32::try_from(k).unwrap_or(u32::MAX));
    let signs: Option<Vec<Mode>> = assembly
        .chars()
        .map(|c| match c {
            '+' => Some(Mode::Plus),
            '-' | '−' => Some(Mode::Minus),
            _ => None,
        })
        .collect();
    let how = || match count {
        Some(n) if n > 1 => format!(
            "give a number from 1 to {n}, or {k} sign{} (+ or -), one per block with two \
             modes in solve order (`kinematics check` lists them)",
            if k == 1 { "" } else { "s" }
        ),
        _ => format!(
            "{} has {k} blocks with two modes: give 1 or leave it out",
            m.name()
        ),
    };
    if let Some(signs) = signs.filter(|s| !s.is_empty()) {
        return if signs.len() == k {
            Ok(signs)
        } else {
            Err(Failure::usage(format!(
                "error: --assembly {assembly}: {} signs for {k} blocks with two modes: {}",
                signs.len(),
                how()
            )))
        };
    }
    match (assembly.parse::<u64>(), count) {
        (Ok(n), Some(count)) if (1..=count).contains(&n) => Ok((0..k)
            .map(|j| {
                if (n - 1) >> j & 1 == 1 {
                    Mode::Minus
                } else {
                    Mode::Plus
                }
            })
            .collect()),
        _ => Err(Failure::usage(format!(
            "error: --assembly {assembly}: {}",
            how()
        ))),
    }
}

/// The unknowns (coordinate indices) solved by Newton–Raphson: those of
/// the blocks with no closed form, whose solution starts from a guess.
fn newton_unknowns(m: &Model) -> Vec<usize> {
    m.blocks()
        .iter()
        .filter(|b| !b.is_closed_form())
        .flat_map(|b| b.unknowns.iter().filter_map(|u| m.index(u)))
        .collect()
}

/// The start pose: each driver's value from `start` then `--at` (0 where
/// none is given), each unknown's guess where given. Where an unknown
/// has none, or `--assembly` is given, the pose is assembled in that
/// assembly (by default the first that assembles there) with no guess: every unknown of a
/// closed-form block is solved exactly, and only those solved by
/// Newton–Raphson need a guess. With every guess given and no
/// `--assembly`, the guesses are returned: they name the branch.
pub(super) fn pose(
    m: &Model,
    start: &[(String, String)],
    at: &[String],
    assembly: Option<&str>,
) -> Result<Vec<f64>, Failure> {
    let mut q = vec![f64::NAN; m.coordinates().len()];
    let from_file: Vec<(String, String, &str)> = start
        .iter()
        .map(|(n, v)| (n.clone(), v.clone(), "[start]"))
        .collect();
    let given = pairs(at, "coordinate")?
        .into_iter()
        .map(|(n, v)| (n, v, "--at"));
    for (name, text, origin) in from_file.into_iter().chain(given) {
        let j = coordinate(m, &name, "coordinate")?;
        q[j] = coordinate_value(m, j, &text, Order::Value, origin)?;
    }
    for v in q.iter_mut().take(m.drivers()) {
        if v.is_nan() {
            *v = 0.0;
        }
    }
    let missing: Vec<usize> = (m.drivers()..q.len()).filter(|&j| q[j].is_nan()).collect();
    if missing.is_empty() && assembly.is_none() {
        return Ok(q);
    }
    let newton = newton_unknowns(m);
    if let Some(&j) = missing.iter().find(|j| newton.contains(j)) {
        let name = m.coordinates()[j].name;
        return Err(Failure::usage(format!(
            "error: give a guess for `{name}` with --at {name}=<value> (or in the [start] \
             table of --params): it is solved by Newton–Raphson, which starts from a guess \
             (the unknowns of closed-form blocks need none)"
        )));
    }
    for &j in &missing {
        q[j] = 0.0;
    }
    let modes = match assembly {
        Some(a) => modes(m, a)?,
        // The first assembly there is: `assemble_all` lists them in the
        // order `check --at` numbers them.
        None => match m
            .assemble_all(&q)
            .find_map(|(modes, p)| p.ok().map(|p| (modes, p)))
        {
            Some((_, p)) => return Ok(p),
            None => vec![Mode::Plus; m.mode_count()],
        },
    };
    m.assemble_in(&q, &modes).map_err(|e| {
        let at: Vec<String> = (0..m.drivers())
            .map(|j| shown(m, j, q[j], AngleUnit::Degrees))
            .collect();
        Failure::mechanism(format!(
            "error: assembly {} at {}: {e}",
            signs(&modes),
            at.join(", ")
        ))
    })
}

/// The modes as signs, `+-`.
pub(super) fn signs(modes: &[Mode]) -> String {
    modes
        .iter()
        .map(|m| if *m == Mode::Plus { '+' } else { '-' })
        .collect()
}

/// `name = value` of coordinate `j` at `value`, an angle in `angle`.
pub(super) fn shown(m: &Model, j: usize, value: f64, angle: AngleUnit) -> String {
    let c = &m.coordinates()[j];
    match (c.kind, angle) {
        (Kind::Angle, AngleUnit::Degrees) => format!("{} = {:.4}°", c.name, value.to_degrees()),
        (Kind::Angle, AngleUnit::Radians) => format!("{} = {value:.6} rad", c.name),
        (Kind::Length, _) => format!("{} = {value:.6}", c.name),
    }
}

/// Every assembly at the drivers of `q`, as `check --at` prints it: its
/// number, its modes, its unknowns (angles in degrees) and, for a block
/// of two angles (a dyad), the side of the line through its two ends its
/// joint lies on ("C left of B→D") and the difference of the angles (the
/// angle at the joint), which tell one assembly from its mirror image; or
/// why it does not assemble there.
pub(super) fn assemblies(m: &Model, q: &[f64]) -> String {
    let mut out = String::new();
    let at: Vec<String> = (0..m.drivers())
        .map(|j| shown(m, j, q[j], AngleUnit::Degrees))
        .collect();
    let _ = writeln!(out, "assemblies at {}:", at.join(", "));
    for (i, (modes, pose)) in m.assemble_all(q).enumerate() {
        let _ = write!(out, "  {}. {}: ", i + 1, signs(&modes));
        match pose {
            Ok(p) => {
                let values: Vec<String> = (m.drivers()..p.len())
                    .map(|j| shown(m, j, p[j], AngleUnit::Degrees))
                    .collect();
                let _ = write!(out, "{}", values.join(", "));
                for b in m.blocks() {
                    let angles: Vec<usize> = b
                        .unknowns
                        .iter()
                        .filter_map(|u| m.index(u))
                        .filter(|&j| m.coordinates()[j].kind == Kind::Angle)
                        .collect();
                    if let [a, c] = angles[..] {
                        let d = (p[c] - p[a]).to_degrees().rem_euclid(360.0);
                        let d = if d > 180.0 { d - 360.0 } else { d };
                        let (na, nc) = (m.coordinates()[a].name, m.coordinates()[c].name);
                        match super::sides::side(m, &p, &modes, [a, c]) {
                            Some(side) => {
                                let _ = write!(out, " ({side}; {nc} − {na} = {d:.4}°)");
                            }
                            None => {
                                let _ = write!(out, " ({nc} − {na} = {d:.4}°)");
                            }
                        }
                    }
                }
                out.push('\n');
            }
            Err(e) => {
                let _ = writeln!(out, "does not assemble: {e}");
            }
        }
    }
    out
}
