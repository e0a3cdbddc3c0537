//! Crank-rocker four-bar over a full turn of the crank: the main example.
//!
//! a = 0.04 m, b = 0.12 m, c = 0.10 m, d = 0.11 m; coupler point P at
//! p = 0.06 m from B, β = 30° from BC; the crank turns at a constant
//! φ' = 10 rad/s. The cycle is swept in 3600 steps; a table every 30° is
//! printed, and the whole cycle is written to `target/kinematics/`:
//! `fourbar.csv` (every coordinate and point, q, q', q''),
//! `fourbar-motion.svg` (θ3, θ4 and their rates and accelerations),
//! `fourbar-points.svg` (position, velocity and acceleration of B and of
//! the coupler point P), `fourbar-path.svg` (the coupler curve of P),
//! `fourbar-skeleton.svg` (the linkage drawn every 90°) and `fourbar.html`
//! (an animation of the cycle, to open in a browser).
use std::time::Instant;

use kinematics_core::animate::write_html;
use kinematics_core::batch;
use kinematics_core::plot::{plot_motion, plot_path, plot_points, plot_skeleton, Projection};
use kinematics_examples::{output_dir, FourBar, FourBarCoords};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let m = FourBar::CRANK_ROCKER;
    let omega = 10.0;
    println!(
        "Crank-rocker four-bar: a = {} m, b = {} m, c = {} m, d = {} m, p = {} m, beta = 30 deg",
        m.a, m.b, m.c, m.d, m.p
    );
    println!("crank speed phi' = {omega} rad/s (constant), full turn in 3600 steps");
    for block in FourBar::BLOCKS {
        println!("solved: {block}");
    }
    // Both assemblies at phi = 0, with no guess: the rough guess below picks
    // the open one.
    for (modes, pose) in m.assemble_all(0.0) {
        let pose = pose.map_err(|e| e.to_string())?;
        println!(
            "  assembly {:?}: th3 = {:.3} deg, th4 = {:.3} deg",
            modes.th3_th4,
            pose.th3.to_degrees(),
            pose.th4.to_degrees()
        );
    }
    println!();
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS)?;
    // One full turn of the crank from 0°, 3600 samples 0.1° apart.
    let cycle = m
        .sweep(FourBar::PHI, &start)
        .from_deg(0.0)
        .turn()
        .steps(3600)
        .rate(omega)
        .run();
    if let Some(stop) = cycle.stop {
        return Err(stop.into());
    }
    println!(
        "{:>6} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8}",
        "phi", "th3", "th4", "w3", "w4", "a3", "a4", "vPx", "vPy", "aPx", "aPy"
    );
    println!(
        "{:>6} {:>8} {:>8} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8}",
        "deg", "deg", "deg", "rad/s", "rad/s", "rad/s2", "rad/s2", "m/s", "m/s", "m/s2", "m/s2"
    );
    for sample in cycle.samples.iter().step_by(300) {
        let s = &sample.motion;
        let p = s.point_p();
        println!(
            "{:>6.1} {:>8.3} {:>8.3} {:>8.4} {:>8.4} {:>9.3} {:>9.3} {:>8.4} {:>8.4} {:>8.3} {:>8.3}",
            s.q.phi.to_degrees(),
            s.q.th3.to_degrees(),
            s.q.th4.to_degrees(),
            s.qd.th3,
            s.qd.th4,
            s.qdd.th3,
            s.qdd.th4,
            p.velocity.x,
            p.velocity.y,
            p.acceleration.x,
            p.acceleration.y,
        );
    }
    println!(
        "\nlargest loop-closure residual over the cycle: {:.1e} m",
        cycle.max_residual()
    );

    let dir = output_dir()?;
    let csv = dir.join("fourbar.csv");
    std::fs::write(&csv, cycle.to_csv())?;
    let motion = dir.join("fourbar-motion.svg");
    plot_motion(&cycle, &motion)?;
    let points = dir.join("fourbar-points.svg");
    plot_points(&cycle, &["B", "P"], &points)?;
    let path = dir.join("fourbar-path.svg");
    plot_path(&cycle, "P", Projection::XY, &path)?;
    let skeleton = dir.join("fourbar-skeleton.svg");
    let poses: Vec<FourBarCoords> = cycle
        .samples
        .iter()
        .step_by(900)
        .map(|s| s.motion.q)
        .collect();
    plot_skeleton(&m, &poses, &FourBar::LINKS, Projection::XY, &skeleton)?;
    // The animation: one frame per 2° (180 frames).
    let frames = m
        .sweep(FourBar::PHI, &start)
        .from_deg(0.0)
        .turn()
        .steps(180)
        .rate(omega)
        .run();
    let page = dir.join("fourbar.html");
    write_html(&m, &frames, &FourBar::LINKS, Projection::XY, &page)?;
    println!("\nwritten:");
    for f in [&csv, &motion, &points, &path, &skeleton, &page] {
        println!("  {}", f.display());
    }

    // A design study: 10 000 random variants of the linkage, assembled at
    // φ = 0 serially and on all cores; some cannot close and are reported.
    let mut rng = fastrand::Rng::with_seed(0x2545_F491_4F6C_DD1D);
    let mut rand = move || rng.f64();
    let designs: Vec<FourBar> = (0..10_000)
        .map(|_| FourBar {
            a: 0.02 + 0.04 * rand(),
            b: 0.05 + 0.10 * rand(),
            c: 0.05 + 0.10 * rand(),
            ..FourBar::CRANK_ROCKER
        })
        .collect();
    let study = |f: &FourBar| f.step(&FourBar::CRANK_ROCKER_GUESS, omega, 0.0);
    let t = Instant::now();
    let serial: Vec<_> = designs.iter().map(study).collect();
    let serial_time = t.elapsed();
    let t = Instant::now();
    let parallel = batch(&designs, study);
    let parallel_time = t.elapsed();
    let ok = parallel.iter().filter(|r| r.is_ok()).count();
    assert_eq!(serial.iter().filter(|r| r.is_ok()).count(), ok);
    println!(
        "\ndesign study: {} variants, {ok} assemble, {} do not (each with its reason); \
         serial {:.1} ms, parallel {:.1} ms on {} threads",
        designs.len(),
        designs.len() - ok,
        serial_time.as_secs_f64() * 1e3,
        parallel_time.as_secs_f64() * 1e3,
        rayon_threads()
    );
    Ok(())
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
}
