//! The figures of merit (`kinematics_core::merit`) against closed forms
//! written here: the Grashof class of one four-bar per class, classified
//! by hand; the four-bar's transmission angle from the law of cosines in
//! the triangle B C D; the offset slider-crank's dead centres (crank and
//! rod in line: sin φ = e/(a + b) extended, sin(φ − π) = e/(b − a)
//! folded), its stroke √((a + b)² − e²) − √((b − a)² − e²) and its time
//! ratio (π + α)/(π − α), α = asin(e/(b − a)) − asin(e/(a + b)) (checked
//! beforehand against a 30-digit search for the extremes of x(φ)); each
//! through a generated mechanism's sweep and a run-time model's, which
//! read through the same code; the crank-shaper quick-return's time
//! ratio (π + 2α)/(π − 2α), α = asin(AB/AC); the four-bar's mechanical advantage
//! ω2/ω4 = c sin(θ4 − θ3) / (a sin(φ − θ3)), from the velocity loop.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::f64::consts::PI;

use kinematics_core::merit::{
    dead_centres, grashof, mechanical_advantage, stroke, time_ratio, transmission, GrashofClass,
};
use kinematics_core::runtime::Model;
use kinematics_core::sweep::Table;
use kinematics_examples::{FourBar, FourBarCoords, RRtrRrt, SliderCrank, SliderCrankCoords};

/// The examples' crank-rocker swept over a turn in 360 steps at `rate`,
/// as generated code and as a run-time model.
fn crank_rocker_turns(
    rate: f64,
) -> (
    kinematics_core::sweep::Sweep<FourBar>,
    kinematics_core::runtime::Sweep,
) {
    let m = FourBar::CRANK_ROCKER;
    let guess = FourBar::CRANK_ROCKER_GUESS;
    let generated = m
        .sweep(FourBar::PHI, &guess)
        .turn()
        .steps(360)
        .rate(rate)
        .run();
    let run_time = model("FourBar", &[m.a, m.b, m.c, m.d, m.p, m.beta])
        .sweep("phi", &[0.0, guess.th3, guess.th4])
        .expect("a driver")
        .turn()
        .steps(360)
        .rate(rate)
        .run();
    (generated, run_time)
}

fn model(name: &str, values: &[f64]) -> Model {
    let text = kinematics_examples::definition(name).expect("an example definition");
    let mut m = Model::compile(text).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.set_values(values)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    m
}

#[test]
fn one_four_bar_per_grashof_class() {
    // (ground, input, coupler, output), and the class by hand: S + L
    // against P + Q, then which link is the shortest.
    let cases = [
        ((0.11, 0.04, 0.12, 0.10), GrashofClass::CrankRocker), // 0.16 < 0.21, input shortest
        ((2.0, 4.0, 5.0, 4.5), GrashofClass::DoubleCrank),     // 7 < 8.5, ground shortest
        ((4.0, 4.5, 2.0, 5.0), GrashofClass::DoubleRocker),    // 7 < 8.5, coupler shortest
        ((4.0, 4.5, 5.0, 2.0), GrashofClass::RockerCrank),     // 7 < 8.5, output shortest
        ((6.0, 3.0, 4.0, 4.5), GrashofClass::TripleRocker),    // 9 > 8.5
        ((0.09, 0.04, 0.09, 0.04), GrashofClass::ChangePoint), // 0.13 = 0.13
    ];
    for ((g, i, c, o), class) in cases {
        let got = grashof(g, i, c, o).expect("a four-bar");
        assert_eq!(got.class, class, "{g} {i} {c} {o}");
        let mut l = [g, i, c, o];
        l.sort_by(f64::total_cmp);
        assert_eq!((got.s_plus_l, got.p_plus_q), (l[0] + l[3], l[1] + l[2]));
    }
    // A loop that cannot close, and a length that is no length.
    assert!(grashof(1.0, 1.0, 1.0, 3.0).is_err());
    assert!(grashof(1.0, -1.0, 1.0, 1.0).is_err());
    assert!(grashof(1.0, f64::NAN, 1.0, 1.0).is_err());
}

#[test]
fn a_crank_rocker_turns_and_a_triple_rocker_stops_as_classified() {
    // The class predicts the motion: the crank-rocker's crank sweeps a
    // full turn; the triple-rocker's input stops at a limit position.
    let crank_rocker = FourBar::CRANK_ROCKER;
    let s = crank_rocker
        .sweep(FourBar::PHI, &FourBar::CRANK_ROCKER_GUESS)
        .turn()
        .steps(360)
        .run();
    assert!(s.stop.is_none() && s.rows() == 360);
    let triple = FourBar {
        a: 3.0,
        b: 4.0,
        c: 4.5,
        d: 6.0,
        ..FourBar::CRANK_ROCKER
    };
    let start = FourBarCoords {
        phi: 1.0,
        th3: 0.5,
        th4: 1.5,
    };
    let s = triple.sweep(FourBar::PHI, &start).turn().steps(360).run();
    assert!(
        s.stop.is_some(),
        "a triple-rocker's input does not turn fully"
    );
}

#[test]
fn four_bar_transmission_angle_from_the_law_of_cosines() {
    let m = FourBar::CRANK_ROCKER;
    let (a, b, c, d) = (m.a, m.b, m.c, m.d);
    // μ at C between CB and CD, with BD² = a² + d² − 2ad cos φ.
    let mu = |phi: f64| {
        let f2 = a * a + d * d - 2.0 * a * d * phi.cos();
        ((b * b + c * c - f2) / (2.0 * b * c)).acos()
    };
    let (generated, run_time) = crank_rocker_turns(1.0);
    let tables: [&dyn Table; 2] = [&generated, &run_time];
    for table in tables {
        let t = transmission(table, "th3", "th4").expect("two angles");
        assert_eq!(t.values.len(), 360);
        for (i, &v) in t.values.iter().enumerate() {
            let phi = table.at(i);
            assert!(
                (v - mu(phi)).abs() < 1e-12,
                "φ = {phi}: {v} against {}",
                mu(phi)
            );
        }
        // Least at φ = 0 (BD = d − a), largest at φ = π (BD = d + a).
        assert!(t.min.0.abs() < 1e-12 && (t.min.1 - mu(0.0)).abs() < 1e-12);
        assert!((t.max.0 - PI).abs() < 1e-9 && (t.max.1 - mu(PI)).abs() < 1e-12);
        assert!((t.worst_departure() - (mu(PI) - PI / 2.0).max(PI / 2.0 - mu(0.0))).abs() < 1e-12);
    }
    assert!(transmission(&generated, "th3", "psi").is_err());
}

#[test]
fn four_bar_mechanical_advantage_from_the_velocity_loop() {
    let m = FourBar::CRANK_ROCKER;
    let (a, c) = (m.a, m.c);
    // The velocity loop a ω2 e(φ)⊥ + b ω3 e(θ3)⊥ = c ω4 e(θ4)⊥, dotted
    // with e(θ3) to drop ω3: a ω2 sin(φ − θ3) = c ω4 sin(θ4 − θ3).
    let exact = |phi: f64, t3: f64, t4: f64| c * (t4 - t3).sin() / (a * (phi - t3).sin());
    let (generated, run_time) = crank_rocker_turns(7.0);
    let tables: [&dyn Table; 2] = [&generated, &run_time];
    for table in tables {
        let ma = mechanical_advantage(table, "th4").expect("an output");
        let mut least = f64::INFINITY;
        for (i, &v) in ma.values.iter().enumerate() {
            let (phi, t3, t4) = (
                table.at(i),
                table.coordinate(i, 1, 0),
                table.coordinate(i, 2, 0),
            );
            let want = exact(phi, t3, t4);
            assert!(
                (v - want).abs() <= 1e-9 * want.abs(),
                "φ = {phi}: {v} against {want}"
            );
            least = least.min(want.abs());
        }
        assert!((ma.least.1 - least).abs() <= 1e-9 * least);
    }
    assert!(mechanical_advantage(&generated, "phi").is_err());
    assert!(mechanical_advantage(&generated, "psi").is_err());
}

/// The chapter's R-RTR-RRT mechanism is a crank-shaper quick-return: the
/// slotted lever (φ3, about C) is at a limit where the crank AB is
/// square to it, sin(φ − φ3) = ±1 with C B ⟂ A B, so that the crank turns
/// by π + 2α one way between the limits and π − 2α the other, α =
/// asin(AB/AC); the ram E follows the lever monotonically (CD < DE: dx_E/dφ3
/// = CD sin φ3 (1 − CD cos φ3 / √(DE² − CD² sin² φ3)) keeps its sign), so
/// it has the same time ratio (π + 2α)/(π − 2α).
#[test]
fn a_crank_shapers_time_ratio_from_its_crank_square_to_the_lever() {
    let m = RRtrRrt::EXAMPLE_4_2;
    let alpha = (m.ab / m.ac).asin();
    let ratio = (PI + 2.0 * alpha) / (PI - 2.0 * alpha);
    let start = m
        .assemble(&RRtrRrt::example_4_2_guess())
        .expect("assembles");
    let generated = m.sweep(RRtrRrt::PHI, &start).turn().steps(360).run();
    let run_time = model("RRtrRrt", &[m.ab, m.ac, m.cd, m.de])
        .sweep(
            "phi",
            &[start.phi, start.s, start.phi3, start.x_e, start.phi4],
        )
        .expect("a driver")
        .turn()
        .steps(360)
        .run();
    let tables: [&dyn Table; 2] = [&generated, &run_time];
    for table in tables {
        for output in ["phi3", "x_e"] {
            let r = time_ratio(table, output).expect("a quick-return");
            // Each dead centre is located to about 1e-8 rad on the Hermite
            // interpolant at 1° a step; the ratio moves by about 2.2 per
            // radian of either.
            assert!(
                (r.ratio() - ratio).abs() < 1e-7,
                "{output}: {} against {ratio}",
                r.ratio()
            );
            assert!((r.rising + r.falling - 2.0 * PI).abs() < 1e-9);
        }
    }
}

#[test]
fn offset_slider_crank_dead_centres_stroke_and_time_ratio() {
    let (a, b, e) = (1.0f64, 3.0f64, 1.0f64);
    let extended = (e / (a + b)).asin();
    let folded = PI + (e / (b - a)).asin();
    let alpha = (e / (b - a)).asin() - (e / (a + b)).asin();
    let exact_ratio = (PI + alpha) / (PI - alpha);
    let exact_stroke = ((a + b).powi(2) - e * e).sqrt() - ((b - a).powi(2) - e * e).sqrt();
    let generated = SliderCrank { a, b, e };
    // The slider to the right of the crank, from 30° (no sample on a
    // dead centre).
    let start = SliderCrankCoords {
        phi: 0.5,
        th: -0.1,
        x: 3.5,
    };
    let generated = generated
        .sweep(SliderCrank::PHI, &start)
        .turn()
        .steps(360)
        .rate(10.0)
        .run();
    let run_time = model("SliderCrank", &[a, b, e])
        .sweep("phi", &[0.5, -0.1, 3.5])
        .expect("a driver")
        .turn()
        .steps(360)
        .rate(10.0)
        .run();
    let tables: [&dyn Table; 2] = [&generated, &run_time];
    for table in tables {
        assert_eq!(table.rows(), 360);
        let d = dead_centres(table, "x").expect("a coordinate");
        assert_eq!(d.len(), 2, "{d:?}");
        let max = d
            .iter()
            .find(|d| d.maximum)
            .expect("the extended dead centre");
        let min = d.iter().find(|d| !d.maximum).expect("the folded one");
        let turn = |x: f64| x.rem_euclid(2.0 * PI);
        assert!(
            (turn(max.at) - turn(extended)).abs() < 1e-8,
            "{max:?} against {extended}"
        );
        assert!(
            (turn(min.at) - turn(folded)).abs() < 1e-8,
            "{min:?} against {folded}"
        );
        let (xmax, xmin) = (
            ((a + b).powi(2) - e * e).sqrt(),
            ((b - a).powi(2) - e * e).sqrt(),
        );
        assert!(
            (max.value - xmax).abs() < 1e-9,
            "{} against {xmax}",
            max.value
        );
        assert!(
            (min.value - xmin).abs() < 1e-9,
            "{} against {xmin}",
            min.value
        );
        let s = stroke(table, "x").expect("a coordinate");
        assert!((s.length() - exact_stroke).abs() < 2e-9, "{s:?}");
        let r = time_ratio(table, "x").expect("a quick-return");
        assert!(
            (r.ratio() - exact_ratio).abs() < 1e-8,
            "{r:?}: {} against {exact_ratio}",
            r.ratio()
        );
        assert!((r.rising + r.falling - 2.0 * PI).abs() < 1e-12);
    }
}

#[test]
fn zero_offset_stroke_is_twice_the_crank_and_its_strokes_take_equal_time() {
    let (a, b) = (0.05, 0.2);
    let m = SliderCrank { a, b, e: 0.0 };
    // Samples land exactly on both dead centres (φ = 0 and π).
    let start = SliderCrankCoords {
        phi: 0.0,
        th: 0.0,
        x: a + b,
    };
    let s = m.sweep(SliderCrank::PHI, &start).turn().steps(360).run();
    let st = stroke(&s, "x").expect("a coordinate");
    assert!((st.length() - 2.0 * a).abs() < 1e-14, "{st:?}");
    assert!((st.max - (a + b)).abs() < 1e-14 && (st.min - (b - a)).abs() < 1e-14);
    let r = time_ratio(&s, "x").expect("two dead centres");
    assert!((r.ratio() - 1.0).abs() < 1e-12, "{r:?}");
}

#[test]
fn figures_that_do_not_apply_say_why() {
    // Not a turn: no time ratio.
    let part = slider_crank_part();
    let e = time_ratio(&part, "x").expect_err("not a turn").to_string();
    assert!(e.contains("not one full turn"), "{e}");
    // No such coordinate; a length where an angle is needed.
    assert!(stroke(&part, "y")
        .expect_err("no y")
        .to_string()
        .contains("its coordinates are phi, th, x"));
    assert!(transmission(&part, "th", "x").is_err());
}

#[test]
fn the_four_bars_links_are_found_from_its_motion() {
    use kinematics_core::links::{drawn_pairs, four_bar, links};
    let m = FourBar::CRANK_ROCKER;
    let s = m
        .sweep(FourBar::PHI, &FourBar::CRANK_ROCKER_GUESS)
        .to(1.0)
        .steps(10)
        .run();
    // Points A, B, D, C, P (declaration order): the frame A D, the crank
    // A B, the coupler B C P, the rocker D C.
    let found = links(&s);
    let sets: Vec<(Vec<usize>, bool)> = found.iter().map(|l| (l.points.clone(), l.frame)).collect();
    assert_eq!(
        sets,
        [
            (vec![0, 2], true),
            (vec![0, 1], false),
            (vec![1, 3, 4], false),
            (vec![2, 3], false)
        ]
    );
    assert_eq!(drawn_pairs(&found).len(), 5);
    let f = four_bar(&s, &found).expect("a four-bar");
    assert_eq!(
        (f.ground, f.input, f.coupler, f.output),
        ([0, 2], [0, 1], [1, 3], [2, 3])
    );
    let lengths = f.lengths(&s, 5);
    for (got, want) in lengths.iter().zip([m.d, m.a, m.b, m.c]) {
        assert!((got - want).abs() < 1e-15, "{lengths:?}");
    }
    assert_eq!(
        grashof(lengths[0], lengths[1], lengths[2], lengths[3])
            .expect("a four-bar")
            .class,
        GrashofClass::CrankRocker
    );
    // A slider-crank is no four-bar: its slider has no second pivot.
    let s = slider_crank_part();
    assert!(four_bar(&s, &links(&s)).is_none());
}

/// A zero-offset slider-crank (a = 1, b = 3) swept from φ = 0.5 to 1 rad.
fn slider_crank_part() -> kinematics_core::sweep::Sweep<SliderCrank> {
    let m = SliderCrank {
        a: 1.0,
        b: 3.0,
        e: 0.0,
    };
    let start = SliderCrankCoords {
        phi: 0.5,
        th: -0.1,
        x: 3.5,
    };
    m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).run()
}
