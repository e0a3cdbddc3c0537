//! Tolerance analysis of the crank-rocker's coupler point P: every length
//! within ±0.1 mm and the coupler angle β within ±0.1°. From the exact
//! sensitivities (the definition's `sensitivities` section), the
//! worst-case and root-sum-square deviation of P's position and velocity
//! over a turn of the crank at 10 rad/s, a table every 30°, and
//! `target/kinematics/tolerance-band.svg`: the coupler curve with its
//! worst-case band, magnified 20 times.
use kinematics_core::plot::{plot_band, Projection};
use kinematics_core::tolerance::point_deviations;
use kinematics_examples::FourBar;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS)?;
    let sweep = m
        .sweep(FourBar::PHI, &start)
        .from_deg(0.0)
        .turn()
        .steps(360)
        .rate(10.0)
        .run();
    if let Some(stop) = sweep.stop {
        return Err(stop.into());
    }
    let tolerances = [
        ("a", 1e-4),
        ("b", 1e-4),
        ("c", 1e-4),
        ("d", 1e-4),
        ("p", 1e-4),
        ("beta", 0.1f64.to_radians()),
    ];
    let dev = point_deviations(&m, &sweep, "P", &tolerances)?;
    println!("coupler point P, lengths ±0.1 mm, beta ±0.1 deg, crank at 10 rad/s");
    println!(
        "{:>6} {:>12} {:>12} {:>12} {:>12}",
        "phi", "|dP| worst", "dPx RSS", "dPy RSS", "|dv| worst"
    );
    println!(
        "{:>6} {:>12} {:>12} {:>12} {:>12}",
        "deg", "mm", "mm", "mm", "mm/s"
    );
    for d in dev.iter().step_by(30) {
        println!(
            "{:>6.0} {:>12.4} {:>12.4} {:>12.4} {:>12.3}",
            d.at.to_degrees(),
            d.position_worst * 1e3,
            d.position_rss[0] * 1e3,
            d.position_rss[1] * 1e3,
            d.velocity_worst * 1e3
        );
    }
    let largest = dev.iter().fold(0.0f64, |a, d| a.max(d.position_worst));
    println!(
        "largest worst-case deviation of P over the turn: {:.4} mm",
        largest * 1e3
    );
    let dir = kinematics_examples::output_dir()?;
    let file = dir.join("tolerance-band.svg");
    plot_band(&sweep, "P", &dev, 20.0, Projection::XY, &file)?;
    println!("written: {}", file.display());
    Ok(())
}
