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
//! kinematics report fourbar.mech --params fourbar.toml --degrees --out out/
//! kinematics simulate press.mech --until 3s --out out/
//! ```
//!
//! `check` prints the definition's coordinates, equations, the blocks of
//! its loop equations in solve order (with the closed form of each), its
//! mobility (with a `joints` section) and its number of assemblies, or
//! every error, located in the file as rustc locates them. `analyze` assembles the mechanism at the drivers given,
//! from the guesses given for the unknowns (Newton–Raphson), and prints q,
//! q', q'', every point's position, velocity and acceleration, and the
//! conditioning. `sweep` sweeps a driver over a range from a start pose
//! and writes the samples as CSV, the plots of the coordinates and of the
//! points, the path of every moving point, the skeleton at four poses
//! and an HTML animation, and prints the figures of merit. `report` does
//! what `sweep` does and gathers it in one self-contained HTML page.
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

mod input;
mod merit;
mod report;
mod sides;
mod simulate;
mod sweep;
mod synthesize;

use input::{assemblies, driver_values, params_file, pose, set_parameters, ParamsFile};
use kinematics_core::units::{AngleUnit, Order};

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
    /// mobility and number of assemblies, or its errors; with --at, every
    /// assembly at the drivers given.
    Check {
        /// The definition (`pub struct Name { params { … } … }`).
        file: PathBuf,
        #[command(flatten)]
        parameters: Parameters,
        /// A driver's value at which every assembly is listed (repeatable;
        /// `phi=30deg`; drivers not given are 0).
        #[arg(long = "at", value_name = "NAME=VALUE")]
        at: Vec<String>,
    },
    /// Assemble a definition at a pose and print the motion there.
    Analyze {
        /// The definition.
        file: PathBuf,
        #[command(flatten)]
        parameters: Parameters,
        /// A driver's value (default 0), or a guess of an unknown (needed
        /// only for those solved by Newton–Raphson); a number in radians
        /// or with a unit (`phi=30deg`).
        #[arg(long = "at", value_name = "NAME=VALUE")]
        at: Vec<String>,
        /// The assembly, where the unknowns are not all guessed: its
        /// number as `kinematics check --at` lists them, or its modes
        /// (`+-`); by default the first that assembles.
        #[arg(long)]
        assembly: Option<String>,
        /// A driver's rate (default 0; `phi=120rpm`, `phi=30deg/s`).
        #[arg(long = "rate", value_name = "NAME=VALUE")]
        rate: Vec<String>,
        /// A driver's acceleration (default 0; `phi=10deg/s2`).
        #[arg(long = "acceleration", value_name = "NAME=VALUE")]
        acceleration: Vec<String>,
        /// Print angles, their rates and accelerations in degrees.
        #[arg(long)]
        degrees: bool,
    },
    /// Sweep a driver over a range; write the CSV, the figures and the
    /// animation.
    Sweep(SweepArgs),
    /// Sweep as `sweep` does, and write besides its files one HTML page,
    /// `report.html`: the figures of merit, the assemblies at the start,
    /// the skeleton, the plots, the animation, the definition and what the
    /// compiler found in it (self-contained, for any browser, offline).
    Report(SweepArgs),
    /// Solve a synthesis problem read from a TOML file (the definition,
    /// the task, the targets, the parameters varied and their bounds, the
    /// constraints, the budget) by the library's global search; print the
    /// designs found, write the best as `best.toml` (a parameters file
    /// for --params) and draw it at its targets (`synthesis.svg`).
    Synthesize(synthesize::SynthesizeArgs),
    /// Simulate the motion that the definition's `bodies` and `loads`
    /// produce from a start pose (forward dynamics): write the samples in
    /// time (`sweep.csv`), the energies and the work of each load
    /// (`energy.csv`), the motion's plot and the animation; print the
    /// energy balance.
    Simulate(simulate::SimulateArgs),
}

/// The arguments of `kinematics sweep`.
#[derive(clap::Args)]
#[allow(clippy::struct_excessive_bools)]
struct SweepArgs {
    /// The definition.
    file: PathBuf,
    #[command(flatten)]
    parameters: Parameters,
    /// A coordinate of the start pose (repeatable; after the `[start]`
    /// table of --params): a driver's value (default 0) or a guess of an
    /// unknown (needed only for those solved by Newton–Raphson); a number
    /// in radians or with a unit (`phi=30deg`).
    #[arg(long = "at", value_name = "NAME=VALUE")]
    at: Vec<String>,
    /// The assembly to start in, where the unknowns are not all guessed:
    /// its number as `kinematics check --at` lists them, or its modes
    /// (`+-`); by default the first that assembles.
    #[arg(long)]
    assembly: Option<String>,
    /// The driver swept (default: the only driver).
    #[arg(long)]
    driver: Option<String>,
    /// The first value of the driver (default: its value in the start
    /// pose): radians or a length, or with a unit (`30deg`).
    #[arg(long, allow_hyphen_values = true)]
    from: Option<String>,
    /// The last value of the driver, included.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "turn")]
    to: Option<String>,
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
    /// The driver's rate (rad/s or length unit per second, or with a
    /// unit: `30deg/s`, `120rpm`; default 1).
    #[arg(long, allow_hyphen_values = true)]
    rate: Option<String>,
    /// The driver's acceleration (default 0; `10deg/s2`).
    #[arg(long, allow_hyphen_values = true)]
    acceleration: Option<String>,
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
    /// Write angles, their rates and accelerations in degrees (the CSV's
    /// columns `phi_deg`, `phi_deg_s`, …, and the summary).
    #[arg(long)]
    degrees: bool,
    /// The folder the files are written to (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// The parameters' values: a file and `--param` pairs.
#[derive(clap::Args)]
struct Parameters {
    /// Parameter values, and optionally `[start]` and `[draw]` tables: a
    /// TOML file of `name = value` lines (a number, or a string with an
    /// angle's unit: `beta = "30deg"`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// A parameter value (repeatable; after those of --params; `beta=30deg`).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    param: Vec<String>,
}

impl Parameters {
    /// Reads the file (if any) and sets every parameter of `m` from it
    /// and the `--param` pairs: what the file holds besides.
    fn set(&self, m: &mut Model) -> Result<ParamsFile, Failure> {
        let file = match &self.params {
            Some(p) => params_file(p)?,
            None => ParamsFile::default(),
        };
        set_parameters(m, &file, &self.param)?;
        Ok(file)
    }
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
        Command::Check {
            file,
            parameters,
            at,
        } => check(&file, &parameters, &at),
        Command::Analyze {
            file,
            parameters,
            at,
            assembly,
            rate,
            acceleration,
            degrees,
        } => analyze(
            &file,
            &parameters,
            (&at, assembly.as_deref()),
            (&rate, &acceleration),
            if degrees {
                AngleUnit::Degrees
            } else {
                AngleUnit::Radians
            },
        ),
        Command::Sweep(args) => sweep::run(&args),
        Command::Report(args) => report::run(&args),
        Command::Synthesize(args) => synthesize::run(&args),
        Command::Simulate(args) => simulate::run(&args),
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
/// which describes itself; with `--at`, every assembly there.
fn check(file: &Path, parameters: &Parameters, at: &[String]) -> Result<String, Failure> {
    let mut m = compile(file)?;
    let mut out = m.describe();
    if !at.is_empty() {
        parameters.set(&mut m)?;
        let mut q = vec![0.0; m.coordinates().len()];
        for (name, text) in input::pairs(at, "coordinate")? {
            let j = input::coordinate(&m, &name, "coordinate")?;
            if j >= m.drivers() {
                return Err(Failure::usage(format!(
                    "error: `{name}` is an unknown: `check --at` takes the drivers, and lists \
                     every assembly there"
                )));
            }
            q[j] = input::coordinate_value(&m, j, &text, Order::Value, "--at")?;
        }
        out += &assemblies(&m, &q);
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

fn analyze(
    file: &Path,
    parameters: &Parameters,
    (at, assembly): (&[String], Option<&str>),
    (rate, acceleration): (&[String], &[String]),
    angle: AngleUnit,
) -> Result<String, Failure> {
    let mut m = compile(file)?;
    let file_values = parameters.set(&mut m)?;
    let q = pose(&m, &file_values.start, at, assembly)?;
    let rates = driver_values(&m, rate, Order::Rate, "rate")?;
    let accels = driver_values(&m, acceleration, Order::Acceleration, "acceleration")?;
    let s = m
        .step(&q, &rates, &accels)
        .map_err(|e| Failure::mechanism(format!("error: {e}")))?;
    let mut out = String::new();
    let _ = writeln!(out, "{} at the assembled pose:", m.name());
    let _ = writeln!(
        out,
        "{:<12} {:>24} {:>24} {:>24} units",
        "coordinate", "q", "q'", "q''"
    );
    for (j, c) in m.coordinates().iter().enumerate() {
        let (k, unit) = match c.kind {
            kinematics_core::Kind::Angle => {
                let a = angle.name();
                (angle.factor(), format!("{a}, {a}/s, {a}/s²"))
            }
            kinematics_core::Kind::Length => (1.0, String::new()),
        };
        let _ = writeln!(
            out,
            "{:<12} {:>24.15e} {:>24.15e} {:>24.15e} {unit}",
            c.name,
            s.q[j] * k,
            s.qd[j] * k,
            s.qdd[j] * k
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
