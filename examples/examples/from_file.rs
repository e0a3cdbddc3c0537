//! A four-bar whose dimensions are read from a JSON file
//! (`examples/data/crank_rocker.json`, or the path given as the first
//! argument), swept over a full turn of the crank in 5° steps, the result
//! written as JSON to `target/kinematics/from_file.json`.
//!
//! The mechanism's definition derives `serde::Serialize` and
//! `serde::Deserialize` (with kinematics-core's `serde` feature), so its
//! parameters, coordinates and motions, and the sweep, go to and from any
//! serde format by name.
use std::path::PathBuf;

use kinematics_examples::{FourBar, FourBarCoords};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = std::env::args_os().nth(1).map_or_else(
        || {
            PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/crank_rocker.json"
            ))
        },
        PathBuf::from,
    );
    let m: FourBar = serde_json::from_str(&std::fs::read_to_string(&file)?)?;
    println!("read {}: {m:?}", file.display());
    let start = m.assemble(&FourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
    })?;
    let sweep = m
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(72)
        .rpm(100.0)
        .run();
    if let Some(stop) = sweep.stop {
        return Err(stop.into());
    }
    let dir = kinematics_examples::output_dir()?;
    let out = dir.join("from_file.json");
    std::fs::write(&out, serde_json::to_string_pretty(&sweep)?)?;
    let fastest = sweep
        .samples
        .iter()
        .map(|s| s.motion.point_p().speed())
        .fold(0.0f64, f64::max);
    println!(
        "{} samples; the coupler point's largest speed at 100 rev/min: {fastest:.4} m/s",
        sweep.samples.len()
    );
    println!("written: {}", out.display());
    Ok(())
}
