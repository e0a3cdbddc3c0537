//! `kinematics synthesize`: a synthesis problem read from a TOML file
//! (`kinematics_core::synthesis::Spec`), solved by the library's global
//! search; the distinct designs found printed, the best written as a
//! parameters file the other commands read, and drawn at its targets
//! over its path.

use std::fmt::Write as _;
use std::io::{IsTerminal, Write as _};
use std::path::{Path, PathBuf};

use kinematics_core::plot::{plot_posed, Overlay, Projection, Units};
use kinematics_core::runtime::Model;
use kinematics_core::synthesis::{Found, Progress, Spec, Task};
use kinematics_core::Kind;

use super::{compile, read, Failure, Parameters};

/// The arguments of `kinematics synthesize`.
#[derive(clap::Args)]
pub(super) struct SynthesizeArgs {
    /// The problem: a TOML file naming the definition (`mechanism`), the
    /// driver, the task, the targets, the parameters varied with their
    /// bounds, the constraints and the search's budget.
    file: PathBuf,
    #[command(flatten)]
    parameters: Parameters,
    /// The seed of the starting designs (replaces the file's).
    #[arg(long)]
    seed: Option<u64>,
    /// The number of starting designs (replaces the file's).
    #[arg(long)]
    starts: Option<usize>,
    /// The number of designs printed.
    #[arg(long, default_value_t = 5)]
    show: usize,
    /// No progress on the terminal.
    #[arg(long)]
    quiet: bool,
    /// The folder `best.toml` and `synthesis.svg` are written to.
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// Reads the problem file: the problem, and the definition's path.
fn problem(file: &Path) -> Result<(Spec, PathBuf), Failure> {
    let text = read(file)?;
    let spec: Spec = toml::from_str(&text)
        .map_err(|e| Failure::usage(format!("error: {}: {e}", file.display())))?;
    let Some(mechanism) = spec.mechanism.clone() else {
        return Err(Failure::usage(format!(
            "error: {}: the problem names no definition; add `mechanism = \"file.mech\"` \
             (a path from the problem's folder)",
            file.display()
        )));
    };
    let folder = file.parent().unwrap_or(Path::new("."));
    Ok((spec, folder.join(mechanism)))
}

pub(super) fn run(args: &SynthesizeArgs) -> Result<String, Failure> {
    let (mut spec, definition) = problem(&args.file)?;
    let mut m = compile(&definition)?;
    let failed = |e: kinematics_core::Error| {
        Failure::mechanism(format!("error: {}: {e}", args.file.display()))
    };
    // The values of the problem (any parameter of the definition), and a
    // varied parameter's mid-range, before those of --params and --param.
    for (name, v) in std::mem::take(&mut spec.values) {
        let what = format!("values.{name}");
        m.set(&name, v.value(&what).map_err(failed)?)
            .map_err(failed)?;
    }
    for (name, [lo, hi]) in &spec.vary {
        let what = format!("vary.{name}");
        let mid = 0.5 * (lo.value(&what).map_err(failed)? + hi.value(&what).map_err(failed)?);
        m.set(name, mid).map_err(failed)?;
    }
    args.parameters.set(&mut m)?;
    if let Some(seed) = args.seed {
        spec.search.seed = seed;
    }
    if let Some(starts) = args.starts {
        spec.search.starts = starts;
    }
    let start = vec![0.0; m.coordinates().len()];
    let mut search = spec.search(&m, &start).map_err(failed)?;
    if !args.quiet && std::io::stderr().is_terminal() {
        search = search.progress(show_progress);
    }
    let found = search.run().map_err(failed)?;
    if !args.quiet && std::io::stderr().is_terminal() {
        eprintln!();
    }
    let mut out = summary(&spec, &m, &found, args.show);
    let Some(best) = found.best() else {
        out += if found.optima.is_empty() {
            "no start assembled at its targets: check the assembly modes (`modes`), the \
             bounds and the sampling ranges, or give more starts (--starts)\n"
        } else {
            "no design found meets every constraint: give more starts (--starts), wider \
             bounds or looser constraints\n"
        };
        return Err(Failure::mechanism(out));
    };
    std::fs::create_dir_all(&args.out)
        .map_err(|e| Failure::usage(format!("error: cannot create {}: {e}", args.out.display())))?;
    let design = &best.found.design;
    let params = args.out.join("best.toml");
    let first = best.poses.first().cloned().unwrap_or_default();
    std::fs::write(
        &params,
        parameters_file(design, &first, &best.found.sum_squares),
    )
    .map_err(|e| Failure::usage(format!("error: cannot write {}: {e}", params.display())))?;
    let figure = args.out.join("synthesis.svg");
    draw(&spec, design, best, &figure).map_err(failed)?;
    let _ = writeln!(
        out,
        "wrote {}\nwrote {}",
        params.display(),
        figure.display()
    );
    Ok(out)
}

/// One line of progress, over the last, on the terminal.
fn show_progress(p: &Progress) {
    let mut err = std::io::stderr();
    let _ = write!(
        err,
        "\rscreened {}/{} · refined {}/{} · best E {:.4e} · {} evaluations   ",
        p.screened, p.starts, p.refined, p.keep, p.best, p.evaluations
    );
    let _ = err.flush();
}

/// The distinct designs found, best first.
fn summary(spec: &Spec, m: &Model, found: &Found<Model>, show: usize) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} by {}: {} starts tried, {} screened ({} drew no feasible design or failed), {} evaluations{}",
        m.name(),
        task_words(&spec.task),
        found.starts + found.undrawn,
        found.starts,
        found.undrawn,
        found.evaluations,
        match found.stopped_by {
            Some(why) => format!(", stopped by the budget of {why:?}").to_lowercase(),
            None => String::new(),
        }
    );
    let _ = writeln!(
        out,
        "\n  #  E             largest error  reached by  turns  min μ     feasible"
    );
    for (i, o) in found.optima.iter().take(show).enumerate() {
        let f = &o.found;
        let _ = writeln!(
            out,
            "{:>3}  {:<12.6e}  {:<13.4e}  {:>10}  {:<5}  {:<8}  {}",
            i + 1,
            f.sum_squares,
            f.max_error,
            o.reached_by,
            match f.full_turn {
                Some(true) => "yes",
                Some(false) => "no",
                None => "-",
            },
            o.min_transmission
                .map_or("-".to_string(), |mu| format!("{:.2}°", mu.to_degrees())),
            if o.feasible { "yes" } else { "no" },
        );
    }
    if let Some(best) = found.best() {
        let _ = writeln!(out, "\nbest design:");
        for (name, v) in m.parameters().iter().zip(best.found.design.values()) {
            let _ = writeln!(out, "  {name} = {v}");
        }
        let driver = &spec.driver;
        let _ = writeln!(out, "at the targets:");
        for (j, (v, e)) in best
            .found
            .driver_values
            .iter()
            .zip(&best.found.target_errors)
            .enumerate()
        {
            let shown = match m.coordinates().iter().find(|c| c.name == driver.as_str()) {
                Some(c) if c.kind == Kind::Angle => format!("{:.4}°", v.to_degrees()),
                _ => format!("{v:.6}"),
            };
            let _ = writeln!(
                out,
                "  target {:>2}: {driver} = {shown}, error {e:.3e}",
                j + 1
            );
        }
    }
    out
}

fn task_words(task: &Task) -> String {
    match task {
        Task::Path { point } => format!("path generation of {point}"),
        Task::Motion { point, angle, .. } => format!("motion generation of {point} and {angle}"),
        Task::Function { output } => format!("function generation of {output}"),
    }
}

/// The parameters file of a design: every parameter's value and, as its
/// `[start]` table, the pose at the first target.
fn parameters_file(m: &Model, pose: &[f64], e: &f64) -> String {
    let mut out = format!("# {} by kinematics synthesize: E = {e:e}\n", m.name());
    for (name, v) in m.parameters().iter().zip(m.values()) {
        let _ = writeln!(out, "{name} = {v:?}");
    }
    if !pose.is_empty() {
        out += "\n# The pose at the first target.\n[start]\n";
        for (c, v) in m.coordinates().iter().zip(pose) {
            let _ = writeln!(out, "{} = {v:?}", c.name);
        }
    }
    out
}

/// Draws the best design at its targets over the path of its point (a
/// turn if it turns, else from its first target to the others), the
/// targets marked.
fn draw(
    spec: &Spec,
    m: &Model,
    best: &kinematics_core::synthesis::Optimum<Model>,
    file: &Path,
) -> Result<(), kinematics_core::Error> {
    let Some(first) = best.poses.first() else {
        return Ok(());
    };
    let values = &best.found.driver_values;
    let phi0 = values[0];
    let turn = best.found.full_turn == Some(true);
    let (lo, hi) = values
        .iter()
        .fold((phi0, phi0), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let ends: Vec<f64> = if turn {
        vec![phi0 + std::f64::consts::TAU]
    } else {
        [lo, hi].into_iter().filter(|&v| v != phi0).collect()
    };
    let point = match &spec.task {
        Task::Path { point } | Task::Motion { point, .. } => Some(point.as_str()),
        Task::Function { .. } => None,
    };
    let mut overlay = Overlay::default();
    let mut links = Vec::new();
    for (k, to) in ends.iter().enumerate() {
        let sweep = m.sweep(&spec.driver, first)?.to(*to).steps(360).run();
        if k == 0 {
            let found = kinematics_core::links::links(&sweep);
            let names = m.point_names();
            links = kinematics_core::links::drawn_pairs(&found)
                .into_iter()
                .map(|(a, b)| (names[a].to_string(), names[b].to_string()))
                .collect();
        }
        if let Some(p) = point {
            if !sweep.samples.is_empty() {
                overlay = overlay.path(&sweep, p, Projection::XY, &format!("path of {p}"))?;
            }
        }
    }
    if point.is_some() {
        let marks: Vec<(f64, f64)> = spec
            .targets
            .iter()
            .filter_map(|t| {
                Some((
                    t.first()?.value("target").ok()?,
                    t.get(1)?.value("target").ok()?,
                ))
            })
            .collect();
        overlay = overlay.marks(&marks, "targets");
    }
    let names: Vec<&str> = m.point_names().iter().map(|n| n.as_ref()).collect();
    let roles = m.point_roles(first)?;
    let poses: Vec<(String, Vec<f64>)> = best
        .poses
        .iter()
        .enumerate()
        .map(|(j, q)| Ok((format!("target {}", j + 1), m.point_positions(q)?)))
        .collect::<Result<_, kinematics_core::Error>>()?;
    let pairs: Vec<(&str, &str)> = links
        .iter()
        .map(|(a, b)| (a.as_str(), b.as_str()))
        .collect();
    plot_posed(
        (&names, &roles),
        &pairs,
        &poses,
        &overlay,
        (Projection::XY, Units::METRES),
        file,
    )
}
