//! Sweeps over full cycles, stops at toggle positions, tables, plots and
//! batch evaluation.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use kinematics_core::animate::write_html;
use kinematics_core::plot::{plot_motion, plot_path, plot_points, plot_skeleton, Projection};
use kinematics_core::sweep::{
    constant_acceleration, constant_speed, ChangePoints, StopReason, Wrap,
};
use kinematics_core::{batch, mechanism, Error};
use kinematics_examples::{FourBar, FourBarCoords, SliderCrank, SliderCrankCoords};
use kinematics_tests::{non_grashof_four_bar, DistanceFourBar, DistanceFourBarCoords, Rng};

#[test]
fn crank_rocker_full_cycle_closes_and_is_periodic() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = m
        .sweep(FourBar::PHI, &start)
        .to(TAU)
        .steps(3600)
        .rate(10.0)
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.samples.len(), 3601);
    for sample in &s.samples {
        assert!(
            sample.motion.residual < 1e-10,
            "residual {} at φ = {}",
            sample.motion.residual,
            sample.at
        );
    }
    assert_eq!(s.is_periodic(1e-9), Some(true));
    // The rocker stays on its branch: θ4 in (0, π) all the way round.
    assert!(s
        .samples
        .iter()
        .all(|x| x.motion.q.th4 > 0.0 && x.motion.q.th4 < PI));
}

#[test]
fn non_grashof_four_bar_stops_at_its_toggle_position() {
    // d + a = 0.16 > b + c = 0.14: the crank cannot pass the angle where BD
    // = b + c (coupler and rocker in line).
    let (m, start, limit) = non_grashof_four_bar();
    let s = m.sweep(FourBar::PHI, &start).turn().steps(3600).run();
    let stop = s.stop.as_ref().expect("the crank cannot turn fully");
    let step = TAU / 3600.0;
    let last = s.samples.last().expect("samples before the stop").at;
    assert!(
        last < limit && last > limit - 2.0 * step,
        "last {last}, limit {limit}"
    );
    // The loop is solved in closed form: the sweep locates the limit, where
    // its discriminant vanishes, by bisection, and says it is a limit.
    assert_eq!(
        stop.reason,
        StopReason::LimitPosition {
            unknowns: "th3, th4"
        }
    );
    assert!(
        (stop.at - limit).abs() < 1e-10,
        "{} against {limit}",
        stop.at
    );
    let text = stop.to_string();
    assert!(text.contains("limit position at phi = "), "{text}");
    assert_eq!(s.is_periodic(1e-9), None);
}

#[test]
fn slider_crank_passes_its_dead_centres_on_one_branch() {
    let m = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.0,
    };
    let start = m
        .assemble(&SliderCrankCoords {
            phi: 0.0,
            th: 0.0,
            x: 0.35,
        })
        .expect("assembles");
    let s = m
        .sweep(SliderCrank::PHI, &start)
        .to(TAU)
        .steps(720)
        .rate(6.0)
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.is_periodic(1e-9), Some(true));
    for sample in &s.samples {
        let phi = sample.at;
        // The branch with the slider on the +x side: x = a cos φ + √(b² − a² sin² φ).
        let x = m.a * phi.cos() + (m.b * m.b - (m.a * phi.sin()).powi(2)).sqrt();
        assert!((sample.motion.q.x - x).abs() < 1e-12, "φ = {phi}");
    }
    // At the dead centres (φ = 0, π) the slider is at rest.
    for k in [0, 360] {
        assert!(s.samples[k].motion.qd.x.abs() < 1e-12);
    }
}

#[test]
fn time_driven_simulation_follows_the_profile() {
    let m = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.0,
    };
    let start = SliderCrankCoords {
        phi: 0.0,
        th: 0.0,
        x: 0.35,
    };
    let times: Vec<f64> = (0..=200).map(|k| f64::from(k) * 0.005).collect();
    let s = m
        .simulate(&start)
        .times(&times)
        .profile(constant_acceleration(SliderCrank::PHI, 0.2, 1.0, 4.0))
        .run();
    assert!(s.stop.is_none());
    assert_eq!(s.samples.len(), times.len());
    for (t, sample) in times.iter().zip(&s.samples) {
        let q = &sample.motion;
        assert!((q.q.phi - (0.2 + t + 2.0 * t * t)).abs() < 1e-12);
        assert!((q.qd.phi - (1.0 + 4.0 * t)).abs() < 1e-12 && (q.qdd.phi - 4.0).abs() < 1e-15);
    }
    // A constant speed equals a sweep at that rate; equal steps of time.
    let by_time = m
        .simulate(&start)
        .duration(1.0)
        .steps(200)
        .profile(constant_speed(SliderCrank::PHI, 0.0, 2.0))
        .run();
    let by_angle = m
        .sweep(SliderCrank::PHI, &start)
        .to(2.0)
        .steps(200)
        .rate(2.0)
        .run();
    assert_eq!(by_time.samples.len(), 201);
    for (a, b) in by_time.samples.iter().zip(&by_angle.samples) {
        assert!((a.motion.qdd.x - b.motion.qdd.x).abs() < 1e-9);
    }
    // A closure profile, on the named coordinates.
    let custom = m
        .simulate(&start)
        .times(&times)
        .profile(
            |t: f64,
             q: &mut SliderCrankCoords,
             qd: &mut SliderCrankCoords,
             qdd: &mut SliderCrankCoords| {
                q.phi = t.sin();
                qd.phi = t.cos();
                qdd.phi = -t.sin();
            },
        )
        .run();
    assert!(custom.stop.is_none());
    assert!((custom.samples[100].motion.qd.phi - 0.5f64.cos()).abs() < 1e-15);
}

#[test]
fn csv_and_text_tables() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = m
        .sweep(FourBar::PHI, &start)
        .to(TAU)
        .steps(36)
        .rate(10.0)
        .run();
    let csv = s.to_csv();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + 37);
    let header: Vec<&str> = lines[0].split(',').collect();
    // 3 coordinates × 3, 5 points × 6; φ once.
    assert_eq!(header.len(), 9 + 30);
    assert_eq!(header[..3], ["phi_rad", "phi_rad_s", "phi_rad_s2"]);
    assert!(header.contains(&"th3_rad_s") && header.contains(&"P_ay_m_s2"));
    // Plain identifiers: letters, digits and underscores.
    assert!(header
        .iter()
        .all(|h| h.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')));
    assert!(s.headers_in("mm").contains(&"P_vx_mm_s".to_owned()));
    for line in &lines[1..] {
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("a number"))
            .collect();
        assert_eq!(values.len(), header.len());
    }
    let text = s.to_text(12);
    assert_eq!(text.lines().count(), 1 + 4);
}

/// The curves of an SVG plot: polylines of at least 50 points.
fn curves(svg: &str) -> usize {
    let doc = roxmltree::Document::parse(svg).expect("valid SVG (XML)");
    doc.descendants()
        .filter(|n| {
            n.has_tag_name("polyline")
                && n.attribute("points")
                    .is_some_and(|p| p.split_whitespace().count() >= 50)
        })
        .count()
}

/// Every text of an SVG file.
fn texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).expect("valid SVG (XML)");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().map(|t| t.trim().to_owned()))
        .collect()
}

/// Asserts that `svg` has every text of `wanted` and no tick reading "-0".
fn assert_texts(svg: &str, wanted: &[&str]) {
    let t = texts(svg);
    for w in wanted {
        assert!(t.iter().any(|x| x == w), "no text {w:?} in {t:?}");
    }
    for x in &t {
        let negative_zero = x.starts_with('-') && x[1..].chars().all(|c| c == '0' || c == '.');
        assert!(!negative_zero, "a tick reads {x:?}");
    }
}

#[test]
fn plots_have_titled_axes_with_units_and_the_curves_asked_for() {
    let dir = std::env::temp_dir().join(format!("kinematics-plots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let read = |f: &std::path::Path| std::fs::read_to_string(f).expect("read");
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = m
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(360)
        .rate(10.0)
        .run();
    // q, q', q'' of θ3 and θ4: one column of angles, two curves per panel.
    let motion = dir.join("motion.svg");
    plot_motion(&s, &motion).expect("written");
    let svg = read(&motion);
    assert_eq!(curves(&svg), 3 * 2);
    assert_texts(
        &svg,
        &[
            "phi (deg)",
            "angle (deg)",
            "angular velocity (rad/s)",
            "angular acceleration (rad/s²)",
            "th3",
            "th4",
        ],
    );
    // Points: positions (x, y), velocities and accelerations (x, y and the
    // magnitude) of B and P.
    let points = dir.join("points.svg");
    plot_points(&s, &["B", "P"], &points).expect("written");
    let svg = read(&points);
    assert_eq!(curves(&svg), 2 * (2 + 3 + 3));
    assert_texts(
        &svg,
        &[
            "position (m)",
            "velocity (m/s)",
            "acceleration (m/s²)",
            "|v|",
            "|a|",
            "velocity of P",
        ],
    );
    assert!(plot_points(&s, &["Q"], &points).is_err());
    let path = dir.join("path.svg");
    plot_path(&s, "P", Projection::XY, &path).expect("written");
    let svg = read(&path);
    assert_eq!(curves(&svg), 1);
    assert_texts(&svg, &["x (m)", "y (m)", "start, phi = 0°"]);
    // The skeleton every 90°: a legend of the crank angles, and the two
    // ground pivots A and D marked (a filled triangle each).
    let skeleton = dir.join("skeleton.svg");
    let poses: Vec<FourBarCoords> = s.samples.iter().step_by(90).map(|x| x.motion.q).collect();
    assert_eq!(poses.len(), 4);
    plot_skeleton(&m, &poses, &FourBar::LINKS, Projection::XY, &skeleton).expect("written");
    let svg = read(&skeleton);
    assert_texts(
        &svg,
        &[
            "phi = 0°",
            "phi = 90°",
            "phi = 180°",
            "phi = 270°",
            "A",
            "D",
            "x (m)",
        ],
    );
    let polygons = |svg: &str| {
        roxmltree::Document::parse(svg)
            .expect("valid SVG")
            .descendants()
            .filter(|n| n.has_tag_name("polygon"))
            .count()
    };
    assert_eq!(polygons(&svg), 2);
    // With a single pose, only the ground pivots are marked as such (every
    // point was, when "fixed" meant "the same in every pose drawn").
    plot_skeleton(&m, &poses[..1], &FourBar::LINKS, Projection::XY, &skeleton).expect("written");
    assert_eq!(polygons(&read(&skeleton)), 2);
    // An unknown point is an error, not a panic.
    assert!(plot_skeleton(&m, &poses, &[("A", "Q")], Projection::XY, &skeleton).is_err());
    // A slider-crank: angles and lengths in their own columns, the slider
    // drawn as a block on its guide, its crank pivot as ground.
    let sc = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.02,
    };
    let start = sc
        .assemble(&SliderCrankCoords {
            phi: 0.0,
            th: 0.0,
            x: 0.35,
        })
        .expect("assembles");
    let s = sc.sweep(SliderCrank::PHI, &start).turn().rpm(600.0).run();
    plot_motion(&s, &motion).expect("written");
    let svg = read(&motion);
    assert_eq!(curves(&svg), 6);
    assert_texts(
        &svg,
        &[
            "angle (deg)",
            "length (m)",
            "velocity (m/s)",
            "acceleration (m/s²)",
        ],
    );
    let sc_poses: Vec<SliderCrankCoords> =
        s.samples.iter().step_by(120).map(|x| x.motion.q).collect();
    plot_skeleton(&sc, &sc_poses, &[("B", "C")], Projection::XY, &skeleton).expect("written");
    let doc = read(&skeleton);
    let blocks = roxmltree::Document::parse(&doc)
        .expect("valid SVG")
        .descendants()
        .filter(|n| n.has_tag_name("rect") && n.attribute("opacity") == Some("0.25"))
        .count();
    assert_eq!(blocks, sc_poses.len(), "one slider block per pose");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_animation_is_one_self_contained_page_with_a_frame_per_sample() {
    let dir = std::env::temp_dir().join(format!("kinematics-animation-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = m.sweep(FourBar::PHI, &start).turn().steps(90).run();
    let page = dir.join("fourbar.html");
    write_html(&m, &s, &FourBar::LINKS, Projection::XY, &page).expect("written");
    let html = std::fs::read_to_string(&page).expect("read");
    // Self-contained: nothing fetched from anywhere.
    assert!(
        !html.contains("http") && !html.contains("src="),
        "external references"
    );
    // Well-formed (as XML too), with the drawing, the slider and the player.
    let body = html.trim_start_matches("<!DOCTYPE html>");
    let doc = roxmltree::Document::parse(body).expect("well-formed");
    let has = |tag: &str| doc.descendants().any(|n| n.has_tag_name(tag));
    assert!(has("svg") && has("button") && has("script"));
    let range = doc
        .descendants()
        .find(|n| n.attribute("type") == Some("range"))
        .expect("a slider for the driver");
    assert_eq!(range.attribute("max"), Some("89"));
    // One frame per sample, each with the position of every point.
    let frames = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("frames"))
        .and_then(|n| n.text())
        .expect("frames");
    let frames: Vec<Vec<f64>> = serde_json::from_str(frames).expect("JSON frames");
    assert_eq!(frames.len(), s.samples.len());
    let k = <FourBar as kinematics_core::Mechanism>::POINT_NAMES
        .iter()
        .position(|n| *n == "P")
        .expect("a point P");
    for (f, sample) in frames.iter().zip(&s.samples) {
        assert_eq!(f.len(), 2 * FourBar::POINTS);
        let p = sample.motion.point_p().position;
        // Seven significant digits.
        assert!((f[2 * k] - p.x).abs() < 1e-7 && (f[2 * k + 1] - p.y).abs() < 1e-7);
    }
    // Each link is a line of the drawing; each moving point's path too.
    let lines = doc
        .descendants()
        .filter(|n| n.attribute("id").is_some_and(|i| i.starts_with("link")))
        .count();
    assert_eq!(lines, FourBar::LINKS.len());
    let paths = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .count();
    assert_eq!(paths, 3); // B, C and P; A and D are ground pivots
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn batch_reports_every_design() {
    let mut rng = Rng::new(0xBA7C);
    let designs: Vec<FourBar> = (0..10_000)
        .map(|_| FourBar {
            a: rng.range(0.02, 0.06),
            b: rng.range(0.05, 0.15),
            c: rng.range(0.05, 0.15),
            ..FourBar::CRANK_ROCKER
        })
        .collect();
    let results = batch(&designs, |m| {
        m.step(&FourBar::CRANK_ROCKER_GUESS, 10.0, 0.0)
    });
    assert_eq!(results.len(), designs.len());
    let failed = results.iter().filter(|r| r.is_err()).count();
    assert!(failed > 100 && failed < 5_000, "{failed} failed");
    // Each result is the one of its own design, in order.
    for (m, r) in designs.iter().zip(&results).step_by(97) {
        match r {
            Ok(s) => assert!(m.residual(&s.q).iter().all(|v| v.abs() < 1e-10)),
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn a_profile_of_one_driver_holds_the_others_at_their_start_values() {
    use kinematics_examples::{FiveBar, FiveBarCoords};
    // A five-bar whose second crank stands at φ2 = 2.0: driving the first
    // at constant speed must leave φ2 there (it was set to 0, and the
    // simulation failed with a misleading NotConverged).
    let (a, b, c, d) = (0.05, 0.12, 0.12, 0.05);
    let (phi1, phi2, th2, th3) = (1.0, 2.0, 0.9, 2.2);
    let ex = a * f64::cos(phi1) + b * f64::cos(th2) - c * f64::cos(th3) - d * f64::cos(phi2);
    let ey = a * f64::sin(phi1) + b * f64::sin(th2) - c * f64::sin(th3) - d * f64::sin(phi2);
    let m = FiveBar { a, b, c, d, ex, ey };
    let start = FiveBarCoords {
        phi1,
        phi2,
        th2,
        th3,
    };
    let s = m
        .simulate(&start)
        .duration(0.1)
        .steps(50)
        .profile(constant_speed(FiveBar::PHI1, phi1, 1.0))
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    for sample in &s.samples {
        assert_eq!(sample.motion.q.phi2, phi2);
        assert_eq!((sample.motion.qd.phi2, sample.motion.qdd.phi2), (0.0, 0.0));
        assert!((sample.motion.q.phi1 - (phi1 + sample.at)).abs() < 1e-15);
    }
}

/// A parallelogram four-bar (a = c, b = d) at 10°, on its parallelogram
/// branch: θ3 = 0, θ4 = φ.
fn parallelogram() -> (FourBar, FourBarCoords) {
    let m = FourBar {
        a: 0.04,
        b: 0.11,
        c: 0.04,
        d: 0.11,
        p: 0.05,
        beta: 0.0,
    };
    let phi = 10f64.to_radians();
    let start = m
        .assemble(&FourBarCoords {
            phi,
            th3: 0.0,
            th4: phi,
        })
        .expect("assembles");
    (m, start)
}

/// The difference of two angles, modulo 2π, in (−π, π].
fn angle_gap(a: f64, b: f64) -> f64 {
    Wrap::Signed.apply(a - b)
}

#[test]
fn a_parallelogram_stops_at_its_change_point_unless_told_which_branch_to_follow() {
    // At φ = 180° the links fold flat: the parallelogram and the crossed
    // (anti-parallelogram) branches meet. With 1° steps from 10° a sample
    // falls on it.
    let (m, start) = parallelogram();
    let s = m.sweep(FourBar::PHI, &start).turn().steps(360).run();
    let stop = s.stop.expect("stops at the change point");
    assert!(
        matches!(stop.reason, StopReason::ChangePoint { .. }),
        "{stop:?}"
    );
    assert!((stop.at - PI).abs() < 1e-12, "{}", stop.at);
    assert!(stop.to_string().contains("ChangePoints::Smooth"));
    assert!(s.samples.iter().all(|x| x.at < PI));
    // Off the grid (0.7° steps from 10°, no sample on 180°), the dip of the
    // conditioning is seen between samples.
    let s = m.sweep(FourBar::PHI, &start).turn().steps(514).run();
    let stop = s.stop.expect("stops at the change point");
    match stop.reason {
        StopReason::ChangePoint { from, to } => {
            assert!(from < PI && to > PI, "{from} {to}");
            // Located to second order in the step from the V of the
            // conditioning.
            assert!((stop.at - PI).abs() < 1e-4, "{}", stop.at);
        }
        other => panic!("{other:?}"),
    }
    assert!(s.samples.iter().all(|x| x.at < PI));
}

#[test]
fn a_parallelogram_sweeps_a_full_turn_on_the_branch_named() {
    let (m, start) = parallelogram();
    // Smooth: the parallelogram all the way round, through 180° and 360°.
    let s = m
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(360)
        .change_points(ChangePoints::Smooth)
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.change_points.len(), 2, "{:?}", s.change_points);
    assert!((s.change_points[0] - PI).abs() < 1e-9 && (s.change_points[1] - TAU).abs() < 1e-6);
    // Only the samples on the change points themselves (where Φ_u is
    // singular) are left out.
    assert!(s.samples.len() >= 358, "{}", s.samples.len());
    assert!((s.samples.last().expect("samples").at - 369f64.to_radians()).abs() < 1e-12);
    for x in &s.samples {
        let q = x.motion.q;
        // At a double root the pose is fixed to about √ε only.
        let near = s.change_points.iter().any(|c| (x.at - c).abs() < 1e-6);
        let tolerance = if near { 1e-7 } else { 1e-9 };
        assert!(q.th3.abs() < tolerance, "θ3 = {} at φ = {}", q.th3, x.at);
        assert!(angle_gap(q.th4, x.at).abs() < tolerance);
        // The coupler translates: it does not turn.
        if !near {
            assert!(x.motion.qd.th3.abs() < 1e-9);
        }
    }
    // Switch: past 180° the crossed branch, which is the other assembly
    // at each driver value.
    let s = m
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(360)
        .change_points(ChangePoints::Switch)
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    let mut crossed = 0;
    for x in &s.samples {
        let q = x.motion.q;
        let mut all = m.assemble_all(x.at).map(|(_, r)| r.expect("assembles"));
        let (a, b) = (all.next().expect("two"), all.next().expect("two"));
        // The parallelogram assembly of the two, and the other.
        let (par, other) = if a.th3.abs() < b.th3.abs() {
            (a, b)
        } else {
            (b, a)
        };
        let expected = if x.at > PI && x.at < TAU { other } else { par };
        // At a double root the pose is fixed to about √ε only, and there
        // the two assemblies are one.
        let near = s.change_points.iter().any(|c| (x.at - c).abs() < 1e-6);
        let tolerance = if near { 1e-7 } else { 1e-9 };
        assert!(
            angle_gap(q.th3, expected.th3).abs() < tolerance
                && angle_gap(q.th4, expected.th4).abs() < tolerance,
            "at φ = {}: {q:?} against {expected:?}",
            x.at
        );
        if x.at > PI + 0.01 && x.at < TAU - 0.01 {
            crossed += 1;
            assert!(q.th3.abs() > 1e-3);
        }
    }
    assert!(crossed > 170, "{crossed}");
}

#[test]
fn ranges_rates_and_angles_in_degrees_and_revolutions_per_minute() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let deg = m
        .sweep(FourBar::PHI, &start)
        .from_deg(30.0)
        .to_deg(90.0)
        .steps(60)
        .rpm(600.0)
        .run();
    let rad = m
        .sweep(FourBar::PHI, &start)
        .from(30f64.to_radians())
        .to(90f64.to_radians())
        .steps(60)
        .rate(20.0 * PI)
        .run();
    assert_eq!(deg.samples.len(), 61);
    for (a, b) in deg.samples.iter().zip(&rad.samples) {
        assert_eq!(a.at, b.at);
        assert!((a.motion.qd.th3 - b.motion.qd.th3).abs() < 1e-12);
    }
    assert!((deg.samples[60].at - FRAC_PI_2).abs() < 1e-15);
    // A full turn: n samples, the end (the start again) left out.
    let turn = m.sweep(FourBar::PHI, &start).turn().steps(3600).run();
    assert_eq!(turn.samples.len(), 3600);
    assert!((turn.samples[3599].at - 359.9f64.to_radians()).abs() < 1e-12);
    // Two turns clockwise, reported wrapped.
    let wrapped = m
        .sweep(FourBar::PHI, &start)
        .turns(-2.0)
        .steps(720)
        .deg_per_s(-90.0)
        .wrap(Wrap::Signed)
        .run();
    assert!(wrapped.stop.is_none(), "{:?}", wrapped.stop);
    assert!((wrapped.samples[500].at + 500f64.to_radians()).abs() < 1e-12);
    for x in &wrapped.samples {
        for v in [x.motion.q.phi, x.motion.q.th3, x.motion.q.th4] {
            assert!(v > -PI && v <= PI, "{v}");
        }
        assert!(angle_gap(x.motion.q.phi, x.at).abs() < 1e-12);
        assert!((x.motion.qd.phi + FRAC_PI_2).abs() < 1e-15);
    }
    let positive = m
        .sweep(FourBar::PHI, &start)
        .turns(-1.0)
        .wrap(Wrap::Positive)
        .run();
    assert!(positive
        .samples
        .iter()
        .all(|x| x.motion.q.th4 >= 0.0 && x.motion.q.th4 < TAU && x.motion.q.phi >= 0.0));
}

#[test]
fn streamed_samples_are_the_collected_ones() {
    let m = FourBar::CRANK_ROCKER;
    let start = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let sweep = m.sweep(FourBar::PHI, &start).turn().steps(720).rate(10.0);
    let collected = sweep.clone().run();
    let mut n = 0;
    for (item, kept) in sweep.into_iter().zip(&collected.samples) {
        let item = item.expect("no stop");
        assert_eq!((item.at, item.motion), (kept.at, kept.motion));
        n += 1;
    }
    assert_eq!(n, 720);
    // The stop comes last, as an error.
    let short = FourBar {
        a: 0.05,
        b: 0.08,
        c: 0.06,
        d: 0.11,
        p: 0.0,
        beta: 0.0,
    };
    let start = short
        .assemble(&FourBarCoords {
            phi: 0.0,
            th3: 0.5,
            th4: 1.5,
        })
        .expect("assembles");
    let items: Vec<_> = short
        .sweep(FourBar::PHI, &start)
        .turn()
        .into_iter()
        .collect();
    let (last, before) = items.split_last().expect("items");
    assert!(before.iter().all(Result::is_ok));
    assert!(matches!(
        last,
        Err(stop) if matches!(stop.reason, StopReason::LimitPosition { .. })
    ));
}

mechanism! {
    /// An inverted slider-crank driven by its slider: the crank a turns
    /// about A; the slider's distance s from B along the link through the
    /// ground pivot D = (d, 0) is prescribed.
    pub struct SliderDriven {
        params {
            /// Crank.
            a,
            /// Ground.
            d
        }
        drivers { s }
        unknowns { phi, th }
        loops { polar(a, phi) + polar(s, th) == vec2(d, 0.0); }
    }
}

#[test]
fn a_length_driver_sweeps_between_the_lengths_given() {
    let m = SliderDriven { a: 0.05, d: 0.12 };
    let start = m
        .assemble(&SliderDrivenCoords {
            s: 0.1,
            phi: 1.0,
            th: -0.4,
        })
        .expect("assembles");
    let s = m
        .sweep(SliderDriven::S, &start)
        .to(0.15)
        .steps(50)
        .rate(0.2)
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.kind, kinematics_core::Kind::Length);
    assert!((s.samples[50].motion.q.s - 0.15).abs() < 1e-15);
    // |AB|: the crank stays a, whatever the slider does.
    for x in &s.samples {
        let q = x.motion.q;
        let b = (q.d_x(&m), q.phi.sin() * m.a);
        assert!(((b.0 * b.0 + b.1 * b.1).sqrt() - m.a).abs() < 1e-12);
        assert_eq!(x.motion.qd.s, 0.2);
    }
    // A length driver has no default end: a clear stop, no samples.
    let s = m.sweep(SliderDriven::S, &start).run();
    assert!(s.samples.is_empty());
    let stop = s.stop.expect("refused");
    assert!(
        matches!(
            stop.reason,
            StopReason::Invalid(Error::InvalidOption { name: "to", .. })
        ),
        "{stop:?}"
    );
    assert!(stop.to_string().contains(".to(value)"), "{stop}");
}

trait CrankX {
    fn d_x(&self, m: &SliderDriven) -> f64;
}

impl CrankX for SliderDrivenCoords {
    fn d_x(&self, m: &SliderDriven) -> f64 {
        m.a * self.phi.cos()
    }
}

#[test]
fn a_sweep_solved_by_newton_stops_where_it_cannot_go_on() {
    // The non-Grashof four-bar of the limit-position test, by
    // Newton–Raphson: the rocker angle cannot follow past the toggle.
    let (f, _, limit) = non_grashof_four_bar();
    let m = DistanceFourBar {
        a: f.a,
        b: f.b,
        c: f.c,
        d: f.d,
    };
    let start = m
        .assemble(&DistanceFourBarCoords { phi: 0.0, th4: 1.5 })
        .expect("assembles");
    let s = m
        .sweep(DistanceFourBar::PHI, &start)
        .turn()
        .steps(3600)
        .run();
    let stop = s.stop.expect("stops");
    assert!(
        matches!(
            stop.reason,
            StopReason::Singular(Error::Singular { .. })
                | StopReason::NotAssembled(Error::NotConverged { .. })
        ),
        "{stop:?}"
    );
    let last = s.samples.last().expect("samples").at;
    assert!(
        last < limit && stop.at > last && stop.at < limit + 0.01,
        "{last} {} {limit}",
        stop.at
    );
    assert!(s.samples.iter().all(|x| x.motion.residual < 1e-12));
    assert!(!stop.to_string().is_empty());
}

#[test]
fn points_by_name_and_their_acceleration_parts() {
    let m = FourBar::CRANK_ROCKER;
    let pose = m.assemble(&FourBar::CRANK_ROCKER_GUESS).expect("assembles");
    let s = m.analyze(&pose, 10.0, 3.0).expect("analyses");
    let at = m.positions(&pose);
    // The same positions as the motion's, by name.
    assert_eq!(at.P, s.point_p().position);
    assert_eq!(at.C, s.point_c().position);
    assert_eq!((at.A.x, at.A.y, at.D.x), (0.0, 0.0, m.d));
    // |a|² = a_t² + a_n², and a_t is the rate of change of the speed:
    // against a central difference of |v| over a step of the crank in time.
    let p = s.point_p();
    let (t, n) = (p.tangential_acceleration(), p.normal_acceleration());
    assert!((p.acceleration_magnitude() - (t * t + n * n).sqrt()).abs() < 1e-12);
    let h = 1e-5;
    let speed_at = |dt: f64| {
        let phi = pose.phi + 10.0 * dt + 1.5 * dt * dt;
        let q = m
            .assemble(&FourBarCoords { phi, ..pose })
            .expect("assembles");
        m.analyze(&q, 10.0 + 3.0 * dt, 3.0)
            .expect("analyses")
            .point_p()
            .speed()
    };
    let fd = (speed_at(h) - speed_at(-h)) / (2.0 * h);
    assert!((fd - t).abs() < 1e-5 * t.abs().max(1.0), "{fd} against {t}");
}

#[test]
fn a_parallelogram_solved_by_newton_crosses_on_the_smooth_branch() {
    // The parallelogram written as a distance, solved by Newton–Raphson:
    // det Φ_u changes sign at the folds, located between samples by the
    // conditioning; Smooth continues along θ4 = φ, Switch is refused with
    // the reason (no closed form holds the other branch).
    let m = DistanceFourBar {
        a: 0.04,
        b: 0.11,
        c: 0.04,
        d: 0.11,
    };
    let phi = 10f64.to_radians();
    let start = m
        .assemble(&DistanceFourBarCoords { phi, th4: phi })
        .expect("assembles");
    let s = m
        .sweep(DistanceFourBar::PHI, &start)
        .turn()
        .steps(514)
        .run();
    let stop = s.stop.expect("stops");
    assert!(
        matches!(stop.reason, StopReason::ChangePoint { .. }),
        "{stop:?}"
    );
    assert!((stop.at - PI).abs() < 1e-6, "{}", stop.at);
    let s = m
        .sweep(DistanceFourBar::PHI, &start)
        .turn()
        .steps(514)
        .change_points(ChangePoints::Smooth)
        .run();
    assert!(s.stop.is_none(), "{:?}", s.stop);
    assert_eq!(s.samples.len(), 514);
    assert_eq!(s.change_points.len(), 2);
    assert!(s
        .samples
        .iter()
        .all(|x| angle_gap(x.motion.q.th4, x.at).abs() < 1e-6));
    let s = m
        .sweep(DistanceFourBar::PHI, &start)
        .turn()
        .steps(514)
        .change_points(ChangePoints::Switch)
        .run();
    let stop = s.stop.expect("refused");
    assert!(
        matches!(
            stop.reason,
            StopReason::Invalid(Error::InvalidOption {
                name: "change_points",
                ..
            })
        ),
        "{stop:?}"
    );
    assert!(s.change_points.is_empty() && s.samples.iter().all(|x| x.at < PI));
}

#[test]
// The accelerations are given by reference on purpose: both forms are
// accepted.
#[allow(clippy::needless_borrows_for_generic_args)]
fn rates_of_several_drivers_are_given_by_name() {
    use kinematics_examples::{FiveBar, FiveBarCoords};
    let (a, b, c, d) = (0.05, 0.12, 0.12, 0.05);
    let (phi1, phi2, th2, th3) = (1.0, 2.0, 0.9, 2.2);
    let ex = a * f64::cos(phi1) + b * f64::cos(th2) - c * f64::cos(th3) - d * f64::cos(phi2);
    let ey = a * f64::sin(phi1) + b * f64::sin(th2) - c * f64::sin(th3) - d * f64::sin(phi2);
    let m = FiveBar { a, b, c, d, ex, ey };
    let pose = FiveBarCoords {
        phi1,
        phi2,
        th2,
        th3,
    };
    let by_name = m
        .analyze(
            &pose,
            FiveBarCoords {
                phi1: 2.0,
                phi2: -1.0,
                ..Default::default()
            },
            &FiveBarCoords {
                phi2: 0.5,
                ..Default::default()
            },
        )
        .expect("analyses");
    let by_order = m.analyze(&pose, [2.0, -1.0], [0.0, 0.5]).expect("analyses");
    assert_eq!(by_name, by_order);
}
