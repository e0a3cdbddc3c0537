//! The published four-bar path-generation benchmarks A (six points on a
//! line, free timing), B (five points, prescribed crank angles), C
//! (eighteen points, 20° crank steps) and F (25 points, free timing), as
//! their sources pose them, solved by the library's search (seeded random
//! starts refined by Levenberg–Marquardt with exact derivatives) from
//! eight seeds; the best design of each drawn at its targets over its
//! coupler curve.
//!
//! ```sh
//! cargo run --release --example literature
//! ```

use std::f64::consts::TAU;

use kinematics_core::plot::{plot_skeleton_with, Overlay, Projection};
use kinematics_examples::benchmarks::{
    on_branch, solve, vector, BenchmarkFourBar, BenchmarkFourBarModes, Problem, PROBLEM_A,
    PROBLEM_B, PROBLEM_C, PROBLEM_F,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for (p, file) in [
        (PROBLEM_A, "literature-a.svg"),
        (PROBLEM_B, "literature-b.svg"),
        (PROBLEM_C, "literature-c.svg"),
        (PROBLEM_F, "literature-f.svg"),
    ] {
        draw(&p, file)?;
    }
    Ok(())
}

/// Solves problem `p` from the seeds 0 to 7 (each run's design meets
/// the constraints), and draws the best run's design at its targets.
fn draw(p: &Problem, file: &str) -> Result<(), Box<dyn std::error::Error>> {
    let (seed, o) = (0..8)
        .filter_map(|seed| solve(p, seed, 16, 8).map(|o| (seed, o)))
        .min_by(|a, b| a.1.sum_squares.total_cmp(&b.1.sum_squares))
        .ok_or("no design met the constraints")?;
    println!("Problem {}, seed {seed}:", p.name);
    let m: BenchmarkFourBar = o.design;
    println!(
        "Problem {}: E = {:.3e} (best published {:.3e}, {}), {} evaluations",
        p.name, o.sum_squares, p.best_published.0, p.best_published.1, o.evaluations
    );
    let names = ["r1", "r2", "r3", "r4", "rcx", "rcy", "x0", "y0", "θ0"];
    for (name, v) in names.iter().zip(vector(&m)) {
        print!("{name} = {v:.6}  ");
    }
    println!();
    for (t, th2) in p.targets.iter().zip(&o.crank_angles) {
        println!(
            "  target ({:6.3}, {:6.3}) at θ2 = {:7.2}°",
            t[0],
            t[1],
            th2.rem_euclid(TAU).to_degrees()
        );
    }
    // The poses at the targets, on the benchmarks' branch.
    let modes = BenchmarkFourBarModes::all()
        .find(|modes| {
            o.crank_angles
                .iter()
                .all(|&th2| m.assemble_in(th2, modes).is_ok_and(|q| on_branch(&m, &q)))
        })
        .ok_or("no assembly mode on the branch")?;
    let poses = o
        .crank_angles
        .iter()
        .map(|&th2| m.assemble_in(th2.rem_euclid(TAU), &modes))
        .collect::<Result<Vec<_>, _>>()?;
    // The coupler curve: a turn from the first target (the crank turns
    // fully: a Grashof crank).
    let curve = m
        .sweep(BenchmarkFourBar::TH2, &poses[0])
        .to(poses[0].th2 + TAU)
        .run();
    let overlay = Overlay::default().path(&curve, "C", Projection::XY, "coupler curve of C")?;
    let marks: Vec<(f64, f64)> = p.targets.iter().map(|t| (t[0], t[1])).collect();
    let label = format!("the targets of Problem {}", p.name);
    let overlay = overlay.marks(&marks, &label);
    let path = kinematics_examples::output_dir()?.join(file);
    let links = [
        ("O2", "A"),
        ("A", "B"),
        ("O4", "B"),
        ("A", "C"),
        ("B", "C"),
        ("O2", "O4"),
    ];
    plot_skeleton_with(&m, &poses, &links, &overlay, Projection::XY, &path)?;
    println!("wrote {}", path.display());
    Ok(())
}
