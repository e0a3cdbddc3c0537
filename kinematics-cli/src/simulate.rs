//! `kinematics simulate`: the motion that a definition's `bodies` and
//! `loads` produce from a start pose (forward dynamics), written as a
//! sweep in time (`sweep.csv`, `motion.svg`, `animation.html`), the
//! drivers' speeds and the energies against time (`simulation.svg`), with the
//! energies and the work of each load (`energy.csv`), and the energy
//! balance printed.

use std::fmt::Write as _;
use std::path::PathBuf;

use kinematics_core::animate::write_table_html;
use kinematics_core::dynamics::{Ended, Event, Method};
use kinematics_core::plot::{plot_motion_in, plot_simulation, Units};
use kinematics_core::units::{AngleUnit, Order};
use kinematics_core::view::Projection;

use super::input::{coordinate, coordinate_value, driver_values, pairs};
use super::{compile, pose, Failure, Parameters};

/// The arguments of `kinematics simulate`.
#[derive(clap::Args)]
pub(super) struct SimulateArgs {
    /// The definition, with `bodies` and `loads` sections.
    file: PathBuf,
    #[command(flatten)]
    parameters: Parameters,
    /// A coordinate of the start pose (repeatable; after the `[start]`
    /// table of --params): a driver's value (default 0) or a guess of an
    /// unknown; a number in radians or with a unit (`phi=30deg`).
    #[arg(long = "at", value_name = "NAME=VALUE")]
    at: Vec<String>,
    /// The assembly to start in: its number as `kinematics check --at`
    /// lists them, or its modes (`+-`).
    #[arg(long)]
    assembly: Option<String>,
    /// A free driver's rate at the start (default 0; `phi=120rpm`).
    #[arg(long = "rate", value_name = "NAME=VALUE")]
    rate: Vec<String>,
    /// A driver that moves freely (repeatable; default: every driver; the
    /// others stay at their start values).
    #[arg(long)]
    free: Vec<String>,
    /// The end time: seconds, or with a unit (`3s`, `250ms`).
    #[arg(long, default_value = "1s")]
    until: String,
    /// The number of equal intervals between the output samples.
    #[arg(long, default_value_t = 100)]
    samples: usize,
    /// The relative and absolute tolerance of the local error.
    #[arg(long, default_value_t = 1e-9)]
    tolerance: f64,
    /// Stop when a coordinate reaches a value (`th4=60deg`), or a rate
    /// (`rate(phi)=1500rpm`), from either side, or only while increasing
    /// or decreasing (`th4=60deg,increasing`); repeatable, the first that
    /// happens.
    #[arg(long = "stop-when", value_name = "NAME=VALUE[,DIRECTION]")]
    stop_when: Vec<String>,
    /// A stop the motion bounces off: a coordinate's value and the
    /// coefficient of restitution (`phi=-90deg,0.5`; repeatable). Each
    /// impact is printed; its energy loss is the work `impacts at phi`.
    #[arg(long = "stop", value_name = "NAME=VALUE,E", allow_hyphen_values = true)]
    stop: Vec<String>,
    /// The integrator: the explicit Dormand–Prince pair, or the implicit
    /// TR-BDF2 for a stiff motion (a stiff spring, large damping).
    #[arg(long, value_enum, default_value = "explicit")]
    method: MethodArg,
    /// Integrate the free drivers' sensitivities to the parameters of the
    /// definition's `sensitivities` section with the motion, written to
    /// `sensitivities.csv`.
    #[arg(long)]
    sensitivities: bool,
    /// Write angles, their rates and accelerations in degrees.
    #[arg(long)]
    degrees: bool,
    /// The folder the files are written to (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// `--method`: the integrator.
#[derive(Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    /// Dormand–Prince 5(4), explicit.
    Explicit,
    /// TR-BDF2, implicit, for stiff motions.
    Implicit,
}

/// `text` as a time in seconds: a number, or one ending in `s` or `ms`.
fn seconds(text: &str) -> Result<f64, Failure> {
    let t = text.trim();
    let (number, factor) = if let Some(n) = t.strip_suffix("ms") {
        (n, 1e-3)
    } else if let Some(n) = t.strip_suffix('s') {
        (n, 1.0)
    } else {
        (t, 1.0)
    };
    number
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .map(|v| v * factor)
        .ok_or_else(|| {
            Failure::usage(format!(
                "error: --until `{text}`: give a positive time in seconds (`3`, `3s`, `250ms`)"
            ))
        })
}

/// Runs `kinematics simulate`: the summary printed on success.
pub(super) fn run(args: &SimulateArgs) -> Result<String, Failure> {
    let mut m = compile(&args.file)?;
    if !m.has_dynamics() {
        return Err(Failure::usage(format!(
            "error: {} has no `bodies` or `loads` section: a forward simulation needs the \
             masses the loads move",
            m.name()
        )));
    }
    let file = args.parameters.set(&mut m)?;
    let failed = |e: kinematics_core::Error| Failure::mechanism(format!("error: {e}"));
    let dynamics = m.dynamics().map_err(failed)?;
    let start = pose(&m, &file.start, &args.at, args.assembly.as_deref())?;
    let rates = driver_values(&m, &args.rate, Order::Rate, "rate")?;
    let until = seconds(&args.until)?;
    let mut builder = dynamics
        .forward_of(&m, &start)
        .rates(&rates)
        .until(until)
        .samples(args.samples)
        .tolerance(args.tolerance)
        .method(match args.method {
            MethodArg::Explicit => Method::Explicit,
            MethodArg::Implicit => Method::Implicit,
        });
    if args.sensitivities {
        builder = builder.sensitivities();
    }
    for name in &args.free {
        let j = coordinate(&m, name, "--free")?;
        if j >= m.drivers() {
            return Err(Failure::usage(format!(
                "error: --free `{name}` is an unknown: only drivers are freed"
            )));
        }
        builder = builder.free(name);
    }
    for (name, text) in pairs(&args.stop_when, "stop-when")? {
        let given = format!("{name}={text}");
        let (name, rate) = match name.strip_prefix("rate(").and_then(|n| n.strip_suffix(')')) {
            Some(inner) => (inner.trim().to_string(), true),
            None => (name, false),
        };
        let j = coordinate(&m, &name, "--stop-when")?;
        let order = if rate { Order::Rate } else { Order::Value };
        let (text, direction) = match text.rsplit_once(',') {
            Some((value, direction)) => (value, Some(direction.trim())),
            None => (text.as_str(), None),
        };
        let value = coordinate_value(&m, j, text.trim(), order, "--stop-when")?;
        let event = if rate {
            Event::rate_reaches(&name, value)
        } else {
            Event::reaches(&name, value)
        };
        builder = builder.stop_when(match direction {
            None => event,
            Some("increasing") => event.increasing(),
            Some("decreasing") => event.decreasing(),
            Some(other) => {
                return Err(Failure::usage(format!(
                    "error: --stop-when `{given}`: the direction `{other}` is neither \
                     `increasing` nor `decreasing` (give none for either)"
                )))
            }
        });
    }
    for (name, text) in pairs(&args.stop, "stop")? {
        let Some((value, e)) = text.rsplit_once(',') else {
            return Err(Failure::usage(format!(
                "error: --stop `{name}={text}`: give the value and the coefficient of \
                 restitution, `{name}=<value>,<e>`"
            )));
        };
        let j = coordinate(&m, &name, "--stop")?;
        let value = coordinate_value(&m, j, value.trim(), Order::Value, "--stop")?;
        let e: f64 = e.trim().parse().map_err(|_| {
            Failure::usage(format!(
                "error: --stop `{name}={text}`: `{e}` is not a coefficient of restitution (a \
                 number from 0 to 1)"
            ))
        })?;
        builder = builder.stop_when(Event::stop(&name, value, e));
    }
    let run = builder.run().map_err(failed)?;
    std::fs::create_dir_all(&args.out).map_err(|e| {
        Failure::mechanism(format!("error: cannot create {}: {e}", args.out.display()))
    })?;
    let angles = if args.degrees {
        AngleUnit::Degrees
    } else {
        AngleUnit::Radians
    };
    let units = Units {
        length: "m",
        angle: angles,
    };
    let write = |path: PathBuf, text: String| -> Result<PathBuf, Failure> {
        std::fs::write(&path, text).map_err(|e| {
            Failure::mechanism(format!("error: cannot write {}: {e}", path.display()))
        })?;
        Ok(path)
    };
    use kinematics_core::sweep::Table;
    let mut written = vec![write(
        args.out.join("sweep.csv"),
        run.sweep.csv_with("m", angles),
    )?];
    written.push(write(args.out.join("energy.csv"), energy_csv(&m, &run))?);
    if args.sensitivities {
        let csv = sensitivities_csv(&m, &run, &args.free);
        written.push(write(args.out.join("sensitivities.csv"), csv)?);
    }
    let motion = args.out.join("motion.svg");
    plot_motion_in(&run.sweep, units, &motion).map_err(failed)?;
    written.push(motion);
    let speeds = args.out.join("simulation.svg");
    plot_simulation(&run.sweep, &run.energy, &run.work_names, units, &speeds).map_err(failed)?;
    written.push(speeds);
    if !run.sweep.samples.is_empty() {
        let roles = m
            .point_roles(&run.sweep.samples[0].motion.q)
            .map_err(failed)?;
        let found = kinematics_core::links::links(&run.sweep);
        let names = m.point_names();
        let pairs: Vec<(&str, &str)> = kinematics_core::links::drawn_pairs(&found)
            .into_iter()
            .map(|(a, b)| (names[a], names[b]))
            .collect();
        let html = args.out.join("animation.html");
        write_table_html(&run.sweep, m.name(), &roles, &pairs, Projection::XY, &html)
            .map_err(failed)?;
        written.push(html);
    }
    let mut out = String::new();
    let s = run.statistics;
    let _ = writeln!(
        out,
        "{}: {} samples from t = 0 to {} s; {} steps ({} rejected), {} evaluations (M and b: {} \
         by the compiled equations of motion, {} summed)",
        m.name(),
        run.sweep.samples.len(),
        run.sweep.samples.last().map_or(0.0, |x| x.at),
        s.steps,
        s.rejected,
        s.evaluations,
        s.compiled,
        s.summed
    );
    if let (Some(first), Some(last)) = (run.energy.first(), run.energy.last()) {
        let _ = writeln!(
            out,
            "  energy: T {:.6e} → {:.6e} J, V {:.6e} → {:.6e} J; balance T + V − ΣW kept to \
             {:.1e} of the largest term",
            first.kinetic,
            last.kinetic,
            first.potential,
            last.potential,
            run.energy_error()
        );
        for (name, w) in run.work_names.iter().zip(&last.work) {
            let _ = writeln!(out, "  work of {name}: {w:.6e} J");
        }
    }
    for i in &run.impacts {
        let _ = writeln!(
            out,
            "  impact at t = {:.9} s: rate {:.6e} → {:.6e}",
            i.t, i.before, i.after
        );
    }
    for f in &written {
        let _ = writeln!(out, "  wrote {}", f.display());
    }
    match (&run.ended, &run.sweep.stop) {
        (Ended::Complete, _) => Ok(out),
        (Ended::Event { index, at }, _) => {
            let _ = writeln!(
                out,
                "  stopped at t = {at} s: {} reached",
                args.stop_when
                    .get(*index)
                    .map_or("the event", String::as_str)
            );
            Ok(out)
        }
        (Ended::Failed { at }, stop) => Err(Failure::mechanism(format!(
            "{out}error: the motion could not go on past t = {at} s{}\n(the files hold the \
             samples before)",
            stop.as_ref()
                .and_then(|s| s.reason.error())
                .map_or(String::new(), |e| format!(": {e}"))
        ))),
        (Ended::StepLimit { at }, _) => Err(Failure::mechanism(format!(
            "{out}error: the step limit was reached at t = {at} s"
        ))),
    }
}

/// The energies as CSV: t, T, V, the work of each load and prescribed
/// driver, the balance T + V − ΣW, then each prescribed driver's effort
/// (what it must supply to follow its motion; N·m for an angle, N for a
/// length).
fn energy_csv(
    m: &kinematics_core::runtime::Model,
    run: &kinematics_core::runtime::TrajectoryOf,
) -> String {
    let mut out = String::from("t (s),kinetic (J),potential (J)");
    for name in &run.work_names {
        let _ = write!(out, ",work of {name} (J)");
    }
    out.push_str(",balance (J)");
    // The prescribed drivers: those whose work is counted.
    let prescribed: Vec<usize> = m.coordinates()[..m.drivers()]
        .iter()
        .enumerate()
        .filter(|(_, c)| {
            run.work_names
                .iter()
                .any(|w| *w == format!("driver {}", c.name))
        })
        .map(|(k, _)| k)
        .collect();
    for &k in &prescribed {
        let c = &m.coordinates()[k];
        let unit = if c.kind == kinematics_core::Kind::Angle {
            "N·m"
        } else {
            "N"
        };
        let _ = write!(out, ",effort of {} ({unit})", c.name);
    }
    out.push('\n');
    for e in &run.energy {
        let _ = write!(out, "{},{},{}", e.t, e.kinetic, e.potential);
        for w in &e.work {
            let _ = write!(out, ",{w}");
        }
        let _ = write!(out, ",{}", e.balance());
        for &k in &prescribed {
            let _ = write!(out, ",{}", e.effort.get(k).copied().unwrap_or(f64::NAN));
        }
        out.push('\n');
    }
    out
}

/// The trajectory's sensitivities as CSV: t, then for each parameter p
/// and free driver d, ∂d/∂p and ∂d'/∂p (in the model's units: rad or the
/// length unit, and per second, per unit of p).
fn sensitivities_csv(
    m: &kinematics_core::runtime::Model,
    run: &kinematics_core::runtime::TrajectoryOf,
    free: &[String],
) -> String {
    let drivers: Vec<&str> = m.coordinates()[..m.drivers()]
        .iter()
        .map(|c| c.name)
        .filter(|n| free.is_empty() || free.iter().any(|f| f == n))
        .collect();
    let mut out = String::from("t (s)");
    for p in &run.parameters {
        for d in &drivers {
            let _ = write!(out, ",d{d}/d{p},d{d}_rate/d{p}");
        }
    }
    out.push('\n');
    let nf = drivers.len();
    for s in &run.sensitivities {
        let _ = write!(out, "{}", s.t);
        for p in 0..run.parameters.len() {
            for i in 0..nf {
                let at = p * nf + i;
                let _ = write!(
                    out,
                    ",{},{}",
                    s.position.get(at).copied().unwrap_or(f64::NAN),
                    s.rate.get(at).copied().unwrap_or(f64::NAN)
                );
            }
        }
        out.push('\n');
    }
    out
}
