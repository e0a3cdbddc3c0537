//! Path generation: a four-bar whose coupler point passes through the five
//! points on a line of Morgan and Wampler's Problem 7 (ground pivots at
//! (0, 0) and (1, 0)), by Levenberg–Marquardt with exact derivatives from
//! seeded random starting designs; the design found drawn at each target
//! over its coupler curve.
//!
//! ```sh
//! cargo run --example synthesis
//! ```

use std::f64::consts::TAU;

use kinematics_core::plot::{plot_skeleton_with, Overlay, Projection};
use kinematics_examples::literature::MORGAN_WAMPLER_7;
use kinematics_examples::synthesis_runs::morgan_wampler;
use kinematics_examples::{FourBar, FourBarCoords};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Twenty seeded random starts; the exact solutions are kept.
    let runs: Vec<_> = (0..20)
        .filter_map(|seed| morgan_wampler(seed).ok())
        .collect();
    let exact: Vec<_> = runs.iter().filter(|r| r.sum_squares < 1e-20).collect();
    println!(
        "{} of {} starts reach E < 1e-20 (evaluations per start: {} to {})",
        exact.len(),
        runs.len(),
        runs.iter()
            .map(|r| r.evaluations + r.jacobians)
            .min()
            .unwrap_or(0),
        runs.iter()
            .map(|r| r.evaluations + r.jacobians)
            .max()
            .unwrap_or(0),
    );
    let best = exact.first().ok_or("no start reached the exact solution")?;
    let m: FourBar = best.design;
    println!(
        "a = {:.6}, b = {:.6}, c = {:.6}, d = {}, p = {:.6}, β = {:.6} rad; E = {:.1e}",
        m.a, m.b, m.c, m.d, m.p, m.beta, best.sum_squares
    );
    // The poses at the targets, in the design's assembly mode.
    let modes = kinematics_examples::FourBarModes::all()
        .find(|modes| {
            MORGAN_WAMPLER_7
                .iter()
                .zip(&best.driver_values)
                .all(|(t, &phi)| {
                    m.assemble_in(phi, modes).is_ok_and(|pose| {
                        let p = m.positions(&pose).P;
                        (p.x - t[0]).hypot(p.y - t[1]) < 1e-9
                    })
                })
        })
        .ok_or("no assembly mode passes through every target")?;
    let poses: Vec<FourBarCoords> = best
        .driver_values
        .iter()
        .map(|&phi| m.assemble_in(phi, &modes))
        .collect::<Result<_, _>>()?;
    for (t, phi) in MORGAN_WAMPLER_7.iter().zip(&best.driver_values) {
        println!(
            "target ({:5.2}, {:5.2}) at φ = {:7.2}°",
            t[0],
            t[1],
            phi.to_degrees()
        );
    }
    // The coupler curve over the crank's range: a turn each way from the
    // first target, each sweep ending at a limit position if the crank
    // cannot turn fully; joined into one curve.
    let phi0 = best.driver_values[0];
    let back = m.sweep(FourBar::PHI, &poses[0]).to(phi0 - TAU).run();
    let ahead = m.sweep(FourBar::PHI, &poses[0]).to(phi0 + TAU).run();
    let label = "coupler curve of P";
    let mut overlay = Overlay::default().path(&back, "P", Projection::XY, label)?;
    let forward = Overlay::default().path(&ahead, "P", Projection::XY, label)?;
    overlay.curves[0].1.reverse();
    overlay.curves[0].1.extend(&forward.curves[0].1);
    if let Some(stop) = back.stop.as_ref().or(ahead.stop.as_ref()) {
        println!("the crank does not turn fully: {stop}");
    }
    let marks: Vec<(f64, f64)> = MORGAN_WAMPLER_7.iter().map(|t| (t[0], t[1])).collect();
    let overlay = overlay.marks(&marks, "target points (Morgan–Wampler, Problem 7)");
    let dir = kinematics_examples::output_dir()?;
    let file = dir.join("synthesis.svg");
    let links = [("A", "B"), ("B", "C"), ("C", "D"), ("B", "P"), ("C", "P")];
    plot_skeleton_with(&m, &poses, &links, &overlay, Projection::XY, &file)?;
    println!("wrote {}", file.display());
    Ok(())
}
