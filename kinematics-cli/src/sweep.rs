//! `kinematics sweep`: a driver swept over a range from a start pose, and
//! the files written from the samples: the CSV, the plots of the
//! coordinates and of the points, the path of every moving point, the
//! transmission angle of every dyad (`transmission.svg`), the skeleton at
//! four poses, a DXF drawing of the skeleton at the first
//! sample with every moving point's path (`mechanism.dxf`), the HTML
//! animation, and, for a definition with `bodies` or `loads`, the
//! forces: the drivers' efforts, energies, power and shaking (`forces.csv`)
//! and the plot of the driving effort beside its mean (`forces.svg`); with
//! a `sensitivities` section as well, the efforts' sensitivities to its
//! parameters (`effort_sensitivities.csv`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use kinematics_core::animate::write_table_html;
use kinematics_core::plot::{
    plot_forces, plot_motion_in, plot_path_in, plot_points_in, plot_table_skeleton, Units,
};
use kinematics_core::sweep::{ChangePoints, Table};
use kinematics_core::view::{PointRole, Projection};
use kinematics_core::{Kind, Role};

use kinematics_core::units::{AngleUnit, Order};

use super::input::coordinate_value;
use super::{compile, pose, ChangePointsArg, Failure, SweepArgs};

/// Runs `kinematics sweep`: the summary printed on success.
pub(super) fn run(args: &SweepArgs) -> Result<String, Failure> {
    let done = swept(args)?;
    if let Some(e) = done.forces_error {
        return Err(Failure::mechanism(format!(
            "{}{e}\n(the kinematics' files are written; the forces' are not)",
            done.summary
        )));
    }
    match done.stop {
        None => Ok(done.summary),
        Some(stop) => Err(Failure::mechanism(format!(
            "{}error: the sweep stopped early: {stop}\n(the files hold the samples before the stop)",
            done.summary
        ))),
    }
}

/// What a sweep leaves besides its files.
pub(super) struct Swept {
    /// The model, its parameters set.
    pub model: kinematics_core::runtime::Model,
    /// The start pose, as the sweep's first sample assembled it.
    pub start: Vec<f64>,
    /// The summary as printed.
    pub summary: String,
    /// The files written, in order.
    pub written: Vec<PathBuf>,
    /// Why the sweep stopped before its end, if it did.
    pub stop: Option<String>,
    /// Why the forces could not be computed, where the definition has
    /// them and they failed (the kinematics' files are written).
    pub forces_error: Option<String>,
}

/// Sweeps as `kinematics sweep` does and writes its files.
pub(super) fn swept(args: &SweepArgs) -> Result<Swept, Failure> {
    let mut m = compile(&args.file)?;
    let file = args.parameters.set(&mut m)?;
    let drivers: Vec<&str> = m
        .coordinates()
        .iter()
        .filter(|c| c.role == Role::Driver)
        .map(|c| c.name)
        .collect();
    let driver = match (&args.driver, drivers.as_slice()) {
        (Some(d), _) => d.clone(),
        (None, [only]) => (*only).to_string(),
        (None, _) => {
            return Err(Failure::usage(format!(
                "error: {} has {} drivers ({}): say which to sweep with --driver <name>",
                m.name(),
                drivers.len(),
                drivers.join(", ")
            )))
        }
    };
    // The start pose at `--from` where the swept driver's value is given
    // nowhere else (a mechanism may not assemble at the default 0).
    let given = |(n, _): &(String, String)| *n == driver;
    let named = file.start.iter().any(given)
        || args
            .at
            .iter()
            .any(|a| a.split_once('=').is_some_and(|(n, _)| n.trim() == driver));
    let mut at = args.at.clone();
    if let (Some(from), false) = (&args.from, named) {
        at.push(format!("{driver}={from}"));
    }
    let start = pose(&m, &file.start, &at, args.assembly.as_deref())?;
    let projection = match args.projection.as_str() {
        "xy" => Projection::XY,
        "xz" => Projection::XZ,
        "yz" => Projection::YZ,
        other => {
            return Err(Failure::usage(format!(
                "error: projection `{other}`: give xy, xz or yz"
            )))
        }
    };
    let units = Units {
        length: unit(&args.unit)?,
        angle: if args.degrees {
            AngleUnit::Degrees
        } else {
            AngleUnit::Radians
        },
    };
    let links = file
        .links
        .iter()
        .chain(&args.link)
        .map(|l| {
            l.split_once('-')
                .map(|(a, b)| (a.trim().to_string(), b.trim().to_string()))
                .ok_or_else(|| Failure::usage(format!("error: link `{l}` is not `P-Q`")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    for (a, b) in &links {
        if let Some(unknown) = [a, b]
            .into_iter()
            .find(|p| !m.point_names().contains(&p.as_str()))
        {
            return Err(Failure::usage(format!(
                "error: link `{a}-{b}`: {} has no point `{unknown}`; its points are {}",
                m.name(),
                m.point_names().join(", ")
            )));
        }
    }
    let mut builder = m.sweep(&driver, &start).map_err(|_| {
        Failure::usage(format!(
            "error: `{driver}` is not a driver of {}; its drivers are {}",
            m.name(),
            drivers.join(", ")
        ))
    })?;
    let j = m.index(&driver).unwrap_or(0);
    let angle = m.coordinates()[j].kind == Kind::Angle;
    let read = |text: &Option<String>, order, option| {
        text.as_deref()
            .map(|t| coordinate_value(&m, j, t, order, option))
            .transpose()
    };
    if let Some(from) = read(&args.from, Order::Value, "--from")? {
        builder = builder.from(from);
    }
    builder = match (read(&args.to, Order::Value, "--to")?, args.turn) {
        (Some(to), _) => builder.to(to),
        (None, true) if angle => builder.turn(),
        (None, true) => {
            return Err(Failure::usage(format!(
                "error: --turn sweeps an angle; `{driver}` is a length: give --to <value>"
            )))
        }
        (None, false) => builder,
    };
    builder = builder.steps(args.steps);
    builder = match (args.rpm, read(&args.rate, Order::Rate, "--rate")?) {
        (Some(rpm), _) if angle => builder.rpm(rpm),
        (Some(_), _) => {
            return Err(Failure::usage(format!(
                "error: --rpm is for an angle; `{driver}` is a length: give --rate <value>"
            )))
        }
        (None, Some(rate)) => builder.rate(rate),
        (None, None) => builder,
    };
    if let Some(a) = read(&args.acceleration, Order::Acceleration, "--acceleration")? {
        builder = builder.acceleration(a);
    }
    let angles = if args.degrees {
        AngleUnit::Degrees
    } else {
        AngleUnit::Radians
    };
    // The driver's values as the summary prints them.
    let value = |x: f64| match (angle, angles) {
        (true, AngleUnit::Degrees) => format!("{}°", round(x.to_degrees())),
        (true, AngleUnit::Radians) => format!("{} rad", round(x)),
        (false, _) => format!("{}", round(x)),
    };
    builder = builder.change_points(match args.change_points {
        ChangePointsArg::Stop => ChangePoints::Stop,
        ChangePointsArg::Smooth => ChangePoints::Smooth,
        ChangePointsArg::Switch => ChangePoints::Switch,
    });
    let sweep = builder.run();
    if sweep.samples.is_empty() {
        let why = sweep
            .stop
            .as_ref()
            .map_or_else(|| "no samples".to_string(), stop_message);
        return Err(Failure::mechanism(format!("error: {why}")));
    }
    let roles = m
        .point_roles(&sweep.samples[0].motion.q)
        .map_err(|e| Failure::mechanism(format!("error: {e}")))?;
    // The links found from the motion, drawn where none are listed.
    let found = kinematics_core::links::links(&sweep);
    let names = m.point_names();
    let links = if links.is_empty() {
        kinematics_core::links::drawn_pairs(&found)
            .into_iter()
            .map(|(a, b)| (names[a].to_string(), names[b].to_string()))
            .collect()
    } else {
        links
    };
    let mut written = write(
        &args.out,
        &sweep,
        &roles,
        &links,
        (projection, units, angles),
        m.name(),
    )?;
    let dyads = super::merit::dyads(&m);
    if !dyads.is_empty() {
        let svg = args.out.join("transmission.svg");
        kinematics_core::plot::plot_transmission(&sweep, &dyads, &svg)
            .map_err(|e| Failure::mechanism(format!("error: {e}")))?;
        written.push(svg);
    }
    let mut mean = None;
    // The forces, where the definition has them: their failure is the
    // sweep's, but leaves the kinematics written (and reported).
    let mut forces_error = None;
    // Loads of the time have no value along a kinematic sweep: their
    // forces are a simulation's (said in the summary).
    let timed = m.loads_read_time();
    if m.has_dynamics() && !timed {
        match forces(&m, &sweep, &args.out) {
            Ok((files, m)) => {
                written.extend(files);
                mean = m;
            }
            Err(f) => forces_error = Some(f.message),
        }
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}: {} samples of {driver} from {} to {}",
        m.name(),
        sweep.rows(),
        value(sweep.samples[0].at),
        value(sweep.samples[sweep.samples.len() - 1].at)
    );
    for &at in &sweep.change_points {
        let _ = writeln!(out, "  passed a change point near {driver} = {}", value(at));
    }
    if timed {
        let _ = writeln!(
            out,
            "  forces not computed: the loads read the time, which a kinematic sweep has not \
             (`kinematics simulate` integrates the motion they produce)"
        );
    }
    if !found.is_empty() {
        let shown: Vec<String> = found
            .iter()
            .map(|l| {
                let points: Vec<&str> = l.points.iter().map(|&k| names[k]).collect();
                if l.frame {
                    format!("frame {{{}}}", points.join(", "))
                } else {
                    format!("{{{}}}", points.join(", "))
                }
            })
            .collect();
        let _ = writeln!(
            out,
            "  links (points moving together): {}",
            shown.join(", ")
        );
    }
    for f in kinematics_core::links::four_bars(&sweep, &found) {
        let [g, i, c, o] = f.lengths(&sweep, 0);
        if let Ok(class) = kinematics_core::merit::grashof(g, i, c, o) {
            let seg = |[a, b]: [usize; 2]| format!("{}{}", names[a], names[b]);
            let _ = writeln!(
                out,
                "  four-bar: ground {} = {g:.6}, input {} = {i:.6}, coupler {} = {c:.6}, \
                 output {} = {o:.6}: {} (S + L = {:.6} against P + Q = {:.6})",
                seg(f.ground),
                seg(f.input),
                seg(f.coupler),
                seg(f.output),
                class.class.describe(),
                class.s_plus_l,
                class.p_plus_q
            );
        }
    }
    out += &super::merit::figures(&m, &sweep, &|x| format!("{driver} = {}", value(x)), angles);
    if let Some(((name, kind), q)) = mean {
        let unit = if kind == Kind::Angle { "N·m" } else { "N" };
        let _ = writeln!(out, "  mean effort of {name}: {q} {unit}");
    }
    for f in &written {
        let _ = writeln!(out, "  wrote {}", f.display());
    }
    let stop = sweep.stop.as_ref().map(stop_message);
    let summary = out;
    // The pose the sweep starts from, as assembled (the guesses given may
    // only name its branch).
    let start = sweep.samples.first().map_or(start, |s| s.motion.q.clone());
    Ok(Swept {
        model: m,
        start,
        summary,
        written,
        stop,
        forces_error,
    })
}

/// The forces along `sweep` of `m` written into `dir` (the forces' CSV and
/// plot, and the efforts' sensitivities where the definition lists
/// parameters): the files, and the first driver's mean effort.
#[allow(clippy::type_complexity)]
fn forces(
    m: &kinematics_core::runtime::Model,
    sweep: &kinematics_core::runtime::Sweep,
    dir: &Path,
) -> Result<(Vec<PathBuf>, Option<((String, Kind), f64)>), Failure> {
    let failed = |e: kinematics_core::Error| Failure::mechanism(format!("error: {e}"));
    let mut written = Vec::new();
    let dynamics = m.dynamics().map_err(failed)?;
    let forces = dynamics.along_of(m, sweep).map_err(failed)?;
    if !m.sensitivity_parameters().is_empty() {
        let text = effort_sensitivities_csv(m, &dynamics, sweep, &forces).map_err(failed)?;
        let csv = dir.join("effort_sensitivities.csv");
        std::fs::write(&csv, text).map_err(|e| {
            Failure::mechanism(format!("error: cannot write {}: {e}", csv.display()))
        })?;
        written.push(csv);
    }
    let csv = dir.join("forces.csv");
    std::fs::write(&csv, forces.to_csv())
        .map_err(|e| Failure::mechanism(format!("error: cannot write {}: {e}", csv.display())))?;
    written.push(csv);
    let svg = dir.join("forces.svg");
    plot_forces(&forces, &svg).map_err(failed)?;
    written.push(svg);
    let mean = forces
        .mean_effort(0)
        .map(|q| (forces.drivers[0].clone(), q));
    Ok((written, mean))
}

/// The sensitivities of the drivers' efforts to the parameters of the
/// `sensitivities` section at every sample of `sweep`, as CSV: the swept
/// driver (degrees for an angle), then ∂Q/∂p of each driver for each
/// parameter in turn, with units.
fn effort_sensitivities_csv(
    m: &kinematics_core::runtime::Model,
    dynamics: &kinematics_core::dynamics::Dynamics,
    sweep: &kinematics_core::runtime::Sweep,
    forces: &kinematics_core::dynamics::ForceSweep,
) -> Result<String, kinematics_core::Error> {
    let angle = forces.kind == Kind::Angle;
    let mut out = format!("{} ({})", forces.variable, if angle { "deg" } else { "m" });
    for p in m.sensitivity_parameters() {
        for (name, kind) in &forces.drivers {
            let unit = if *kind == Kind::Angle { "N·m" } else { "N" };
            let _ = write!(out, ",dQ_{name}/d{p} ({unit} per unit of {p})");
        }
    }
    out.push('\n');
    for s in &sweep.samples {
        let at = if angle { s.at.to_degrees() } else { s.at };
        let _ = write!(out, "{at}");
        for one in dynamics.effort_sensitivities_of(m, &s.motion)? {
            for e in one.effort {
                let _ = write!(out, ",{e}");
            }
        }
        out.push('\n');
    }
    Ok(out)
}

/// Writes the CSV, the figures and the animation into `dir`; returns
/// the files written.
fn write(
    dir: &Path,
    sweep: &impl Table,
    roles: &[PointRole],
    links: &[(String, String)],
    (projection, units, angles): (Projection, Units, AngleUnit),
    name: &str,
) -> Result<Vec<PathBuf>, Failure> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Failure::mechanism(format!("error: cannot create {}: {e}", dir.display())))?;
    let failed = |e: kinematics_core::Error| Failure::mechanism(format!("error: {e}"));
    let mut written = Vec::new();
    let path = |file: String| -> PathBuf { dir.join(file) };
    let csv = path("sweep.csv".into());
    std::fs::write(&csv, sweep.csv_with(units.length, angles))
        .map_err(|e| Failure::mechanism(format!("error: cannot write {}: {e}", csv.display())))?;
    written.push(csv);
    let motion = path("motion.svg".into());
    plot_motion_in(sweep, units, &motion).map_err(failed)?;
    written.push(motion);
    // The points that move (a ground pivot's plots are flat lines).
    let moving: Vec<&str> = sweep
        .point_names()
        .iter()
        .zip(roles)
        .filter(|(_, r)| **r != PointRole::Fixed)
        .map(|(p, _)| *p)
        .collect();
    if !moving.is_empty() {
        let file = path("points.svg".into());
        plot_points_in(sweep, &moving, units, &file).map_err(failed)?;
        written.push(file);
    }
    for p in &moving {
        let file = path(format!("path-{p}.svg"));
        plot_path_in(sweep, p, projection, units, &file).map_err(failed)?;
        written.push(file);
    }
    let pairs: Vec<(&str, &str)> = links
        .iter()
        .map(|(a, b)| (a.as_str(), b.as_str()))
        .collect();
    // The skeleton at four poses a quarter of the sweep apart.
    let n = sweep.rows();
    let mut rows: Vec<usize> = (0..4).map(|i| i * n / 4).collect();
    rows.dedup();
    let skeleton = path("skeleton.svg".into());
    plot_table_skeleton(sweep, &rows, roles, &pairs, (projection, units), &skeleton)
        .map_err(failed)?;
    written.push(skeleton);
    let drawing = path("mechanism.dxf".into());
    kinematics_core::dxf::write_dxf(sweep, 0, roles, &pairs, projection, &drawing)
        .map_err(failed)?;
    written.push(drawing);
    let html = path("animation.html".into());
    write_table_html(sweep, name, roles, &pairs, projection, &html).map_err(failed)?;
    written.push(html);
    Ok(written)
}

/// The length units the axes can be labelled in (the values are as
/// computed, in the unit of the parameters).
const UNITS: [&str; 6] = ["m", "cm", "mm", "km", "in", "ft"];

/// `name` as one of [`UNITS`], or a usage error listing them.
fn unit(name: &str) -> Result<&'static str, Failure> {
    UNITS.iter().copied().find(|u| *u == name).ok_or_else(|| {
        Failure::usage(format!(
            "error: unit `{name}`: give one of {}",
            UNITS.join(", ")
        ))
    })
}

/// `x` to 10 significant digits, as the summary prints a value (the CSV
/// holds every digit).
fn round(x: f64) -> f64 {
    format!("{x:.9e}").parse().unwrap_or(x)
}

/// A stop's message in the command's terms.
fn stop_message(stop: &kinematics_core::sweep::Stop) -> String {
    stop.message_with("`--change-points smooth` (or `switch`)")
}
