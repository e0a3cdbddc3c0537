//! `kinematics`: a mechanism definition in a text file (what would be
//! written inside `mechanism! { … }`), checked and analysed with no Rust
//! code of one's own.
//!
//! ```text
//! kinematics check fourbar.mech
//! kinematics analyze fourbar.mech --params fourbar.toml --at phi=0.5 \
//!     --at th3=0.9 --at th4=1.7 --rate phi=10
//! kinematics sweep fourbar.mech --params fourbar.toml --turn --steps 360 \
//!     --rpm 600 --out out/
//! ```
//!
//! `check` prints the definition's coordinates, equations, the blocks of
//! its loop equations in solve order (with the closed form of each), its
//! mobility (with a `joints` section) and its number of assemblies, or every error, located in the file as rustc
//! locates them. `analyze` assembles the mechanism at the drivers given,
//! from the guesses given for the unknowns (Newton–Raphson), and prints q,
//! q', q'', every point's position, velocity and acceleration, and the
//! conditioning. `sweep` sweeps a driver over a range from a start pose
//! and writes the samples as CSV, the plots of the coordinates and of the
//! points, the path of every moving point, and an HTML animation.
//!
//! A parameters file holds `name = value` lines, and may hold a `[start]`
//! table (the start pose: every driver's value and a guess of every
//! unknown, as `--at` gives them) and a `[draw]` table (`links = ["A-B",
//! "B-C"]`, the point pairs the animation draws as links).
//!
//! Exit status: 0 on success, 1 for a definition with errors, a mechanism
//! that cannot be assembled or analysed there, or a sweep that stopped
//! early (its files hold the samples before the stop), 2 for wrong
//! arguments.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use kinematics_core::runtime::{CompileError, Model};

mod sweep;

/// Check and analyse mechanism definitions given as text files.
#[derive(Parser)]
#[command(name = "kinematics", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Compile a definition; print its coordinates, equations, blocks,
    /// mobility and number of assemblies, or its errors.
    Check {
        /// The definition (`pub struct Name { params { … } … }`).
        file: PathBuf,
    },
    /// Assemble a definition at a pose and print the motion there.
    Analyze {
        /// The definition.
        file: PathBuf,
        /// Parameter values: a TOML file of `name = value` lines.
        #[arg(long)]
        params: Option<PathBuf>,
        /// A parameter value (repeatable; after those of --params).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        param: Vec<String>,
        /// A driver's value, or a guess of an unknown (every coordinate;
        /// angles in radians).
        #[arg(long = "at", value_name = "NAME=VALUE")]
        at: Vec<String>,
        /// A driver's rate (default 0).
        #[arg(long = "rate", value_name = "NAME=VALUE")]
        rate: Vec<String>,
        /// A driver's acceleration (default 0).
        #[arg(long = "acceleration", value_name = "NAME=VALUE")]
        acceleration: Vec<String>,
    },
    /// Sweep a driver over a range; write the CSV, the figures and the
    /// animation.
    Sweep(SweepArgs),
}

/// The arguments of `kinematics sweep`.
#[derive(clap::Args)]
#[allow(clippy::struct_excessive_bools)]
struct SweepArgs {
    /// The definition.
    file: PathBuf,
    /// Parameter values, and optionally `[start]` and `[draw]` tables: a
    /// TOML file.
    #[arg(long)]
    params: Option<PathBuf>,
    /// A parameter value (repeatable; after those of --params).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    param: Vec<String>,
    /// A coordinate of the start pose (repeatable; after the `[start]`
    /// table of --params; angles in radians).
    #[arg(long = "at", value_name = "NAME=VALUE")]
    at: Vec<String>,
    /// The driver swept (default: the only driver).
    #[arg(long)]
    driver: Option<String>,
    /// The first value of the driver (default: its value in the start
    /// pose).
    #[arg(long, allow_negative_numbers = true)]
    from: Option<f64>,
    /// The last value of the driver, included.
    #[arg(long, allow_negative_numbers = true, conflicts_with = "turn")]
    to: Option<f64>,
    /// One full turn from the first value (the end, the start again, left
    /// out); the default for an angle driver.
    #[arg(long)]
    turn: bool,
    /// The number of equal steps.
    #[arg(long, default_value_t = 360)]
    steps: usize,
    /// The driver's rate in revolutions per minute (an angle driver).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "rate")]
    rpm: Option<f64>,
    /// The driver's rate (rad/s or length unit per second; default 1).
    #[arg(long, allow_negative_numbers = true)]
    rate: Option<f64>,
    /// The driver's acceleration (default 0).
    #[arg(long, allow_negative_numbers = true)]
    acceleration: Option<f64>,
    /// A link drawn in the animation, as two point names: `A-B`
    /// (repeatable; after the `links` of the `[draw]` table).
    #[arg(long = "link", value_name = "P-Q")]
    link: Vec<String>,
    /// The plane a spatial mechanism is drawn in: xy, xz or yz.
    #[arg(long, default_value = "xy")]
    projection: String,
    /// The name of the length unit on the axes and in the CSV's headers.
    #[arg(long, default_value = "m")]
    unit: String,
    /// At a change point, where two assembly branches meet: stop there,
    /// continue on the smooth branch, or switch to the other.
    #[arg(long = "change-points", value_enum, default_value = "stop")]
    change_points: ChangePointsArg,
    /// The folder the files are written to (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// `--change-points`: what a sweep does where two branches meet.
#[derive(Clone, Copy, clap::ValueEnum)]
enum ChangePointsArg {
    /// Stop there.
    Stop,
    /// Continue on the branch on which the motion is smooth.
    Smooth,
    /// Continue on the other branch.
    Switch,
}

/// A failure and its exit status.
struct Failure {
    message: String,
    status: u8,
}

impl Failure {
    /// Wrong arguments (status 2).
    fn usage(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            status: 2,
        }
    }

    /// A definition or a mechanism that does not work (status 1).
    fn mechanism(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            status: 1,
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check { file } => check(&file),
        Command::Analyze {
            file,
            params,
            param,
            at,
            rate,
            acceleration,
        } => analyze(&file, params.as_deref(), &param, &at, &rate, &acceleration),
        Command::Sweep(args) => sweep::run(&args),
    };
    match result {
        Ok(out) => {
            print!("{out}");
            ExitCode::SUCCESS
        }
        Err(f) => {
            eprintln!("{}", f.message);
            ExitCode::from(f.status)
        }
    }
}

fn read(file: &Path) -> Result<String, Failure> {
    std::fs::read_to_string(file)
        .map_err(|e| Failure::usage(format!("error: cannot read {}: {e}", file.display())))
}

/// The definition's errors, each located in `file`.
fn located(file: &Path, errors: &kinematics_compiler::Diagnostics) -> Failure {
    let name = file.display().to_string();
    let shown: Vec<String> = errors
        .0
        .iter()
        .map(|d| d.in_file(&name).to_string())
        .collect();
    let count = errors.0.len();
    let plural = if count == 1 { "" } else { "s" };
    Failure::mechanism(format!(
        "{}\n\nerror: {name}: {count} error{plural} in the definition",
        shown.join("\n\n")
    ))
}

/// `kinematics check`: the definition compiled once, as a run-time model,
/// which describes itself.
fn check(file: &Path) -> Result<String, Failure> {
    Ok(compile(file)?.describe())
}

/// `name=value` pairs.
fn pairs(args: &[String], what: &str) -> Result<Vec<(String, f64)>, Failure> {
    args.iter()
        .map(|a| {
            let (name, value) = a.split_once('=').ok_or_else(|| {
                Failure::usage(format!("error: {what} `{a}` is not `name=value`"))
            })?;
            let value: f64 = value.trim().parse().map_err(|_| {
                Failure::usage(format!("error: {what} `{a}`: `{value}` is not a number"))
            })?;
            Ok((name.trim().to_string(), value))
        })
        .collect()
}

/// What a parameters file holds: the parameters' values, the start pose
/// (its `[start]` table) and the links to draw (`links` of its `[draw]`
/// table).
#[derive(Default)]
struct ParamsFile {
    values: Vec<(String, f64)>,
    start: Vec<(String, f64)>,
    links: Vec<String>,
}

/// A TOML number as f64, or a usage error naming `key` in `file`.
fn number(file: &Path, key: &str, v: &toml::Value) -> Result<f64, Failure> {
    match v {
        toml::Value::Float(x) => Ok(*x),
        #[allow(clippy::cast_precision_loss)]
        toml::Value::Integer(i) => Ok(*i as f64),
        other => Err(Failure::usage(format!(
            "error: {}: `{key}` is {}, not a number",
            file.display(),
            other.type_str()
        ))),
    }
}

/// Reads a parameters file: `name = number` lines, an optional `[start]`
/// table of the same, an optional `[draw]` table with `links`.
fn params_file(file: &Path) -> Result<ParamsFile, Failure> {
    let text = read(file)?;
    let table: toml::Table = text
        .parse()
        .map_err(|e| Failure::usage(format!("error: {}: {e}", file.display())))?;
    let mut out = ParamsFile::default();
    for (k, v) in table {
        match (k.as_str(), v) {
            ("start", toml::Value::Table(t)) => {
                for (name, v) in t {
                    let value = number(file, &format!("start.{name}"), &v)?;
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
                let value = number(file, &k, &v)?;
                out.values.push((k, value));
            }
        }
    }
    Ok(out)
}

/// Compiles the definition in `file`: its errors located in the file.
fn compile(file: &Path) -> Result<Model, Failure> {
    let text = read(file)?;
    match Model::compile(&text) {
        Ok(m) => Ok(m),
        Err(CompileError::Definition(e)) => Err(located(file, &e)),
        Err(e) => Err(Failure::mechanism(format!("error: {e}"))),
    }
}

/// Sets the parameters from `file`'s values then the `--param` pairs;
/// every parameter must have a value.
fn set_parameters(m: &mut Model, file: &ParamsFile, param: &[String]) -> Result<(), Failure> {
    let mut values = file.values.clone();
    values.extend(pairs(param, "parameter")?);
    for (name, value) in &values {
        m.set(name, *value)
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
fn coordinate(m: &Model, name: &str, what: &str) -> Result<usize, Failure> {
    m.index(name).ok_or_else(|| {
        let names: Vec<&str> = m.coordinates().iter().map(|c| c.name).collect();
        Failure::usage(format!(
            "error: {what} `{name}` is not a coordinate of {}; its coordinates are {}",
            m.name(),
            names.join(", ")
        ))
    })
}

/// The pose given by `start` then `--at` pairs: every coordinate must
/// have a value.
fn pose(m: &Model, start: &[(String, f64)], at: &[String]) -> Result<Vec<f64>, Failure> {
    let mut q = vec![f64::NAN; m.coordinates().len()];
    for (name, value) in start.iter().cloned().chain(pairs(at, "coordinate")?) {
        q[coordinate(m, &name, "coordinate")?] = value;
    }
    if let Some(j) = q.iter().position(|v| v.is_nan()) {
        let c = &m.coordinates()[j];
        let what = if j < m.drivers() {
            "its value"
        } else {
            "a guess"
        };
        return Err(Failure::usage(format!(
            "error: give {what} for `{0}` with --at {0}=<value> (or in the [start] table \
             of --params)",
            c.name
        )));
    }
    Ok(q)
}

fn analyze(
    file: &Path,
    params: Option<&Path>,
    param: &[String],
    at: &[String],
    rate: &[String],
    acceleration: &[String],
) -> Result<String, Failure> {
    let mut m = compile(file)?;
    let file_values = match params {
        Some(p) => params_file(p)?,
        None => ParamsFile::default(),
    };
    set_parameters(&mut m, &file_values, param)?;
    let nd = m.drivers();
    let q = pose(&m, &file_values.start, at)?;
    let mut rates = vec![0.0; nd];
    let mut accels = vec![0.0; nd];
    for (list, args, what) in [
        (&mut rates, rate, "rate"),
        (&mut accels, acceleration, "acceleration"),
    ] {
        for (name, value) in pairs(args, what)? {
            let j = coordinate(&m, &name, what)?;
            if j >= nd {
                return Err(Failure::usage(format!(
                    "error: `{name}` is an unknown: only drivers are given a {what}"
                )));
            }
            list[j] = value;
        }
    }
    let s = m
        .step(&q, &rates, &accels)
        .map_err(|e| Failure::mechanism(format!("error: {e}")))?;
    let mut out = String::new();
    let _ = writeln!(out, "{} at the assembled pose:", m.name());
    let _ = writeln!(
        out,
        "{:<12} {:>24} {:>24} {:>24}",
        "coordinate", "q", "q'", "q''"
    );
    for (j, c) in m.coordinates().iter().enumerate() {
        let _ = writeln!(
            out,
            "{:<12} {:>24.15e} {:>24.15e} {:>24.15e}",
            c.name, s.q[j], s.qd[j], s.qdd[j]
        );
    }
    if !s.points.is_empty() {
        let _ = writeln!(out, "{:<12} {:<10} components", "point", "");
    }
    for (name, p) in m.point_names().iter().zip(&s.points) {
        for (what, v) in [
            ("position", &p.position),
            ("velocity", &p.velocity),
            ("accel.", &p.acceleration),
        ] {
            let comps: Vec<String> = v.iter().map(|x| format!("{x:>24.15e}")).collect();
            let _ = writeln!(out, "{name:<12} {what:<10} {}", comps.join(" "));
        }
    }
    let _ = writeln!(
        out,
        "conditioning {:.6e}, sign of det Φ_u {:+}, largest |Φ_i|/S_i {:.3e}",
        s.conditioning, s.det_sign, s.residual
    );
    Ok(out)
}
