//! The synthesis as a product: exact three-position motion generation and
//! three-point function generation against four-bars solved here in
//! closed form, motion generation by Levenberg–Marquardt, and the global
//! search's constraints checked by sweeping its designs.

#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;

use kinematics_core::runtime::Model;
use kinematics_core::synthesis::exact::{
    centre_point, chebyshev, circle_point, freudenstein, three_positions,
};
use kinematics_core::synthesis::{Spec, Synthesis};

/// The four-bar of the tests: crank a from A = (0, 0), coupler b, rocker
/// c from D = (d, 0); at crank angle φ, the crank pin B = a∠φ and the
/// rocker pin C on the open branch (C to the left of B→D), by the
/// intersection of the circles |C − B| = b and |C − D| = c written here:
/// (C, the coupler's angle θ3, the rocker's angle ψ).
fn closed_form(a: f64, b: f64, c: f64, d: f64, phi: f64) -> ([f64; 2], f64, f64) {
    let bp = [a * phi.cos(), a * phi.sin()];
    let (dx, dy) = (d - bp[0], -bp[1]);
    let l = dx.hypot(dy);
    // Along B→D by x, across by h (to the left).
    let x = (b * b - c * c + l * l) / (2.0 * l);
    let h = (b * b - x * x).sqrt();
    let (ux, uy) = (dx / l, dy / l);
    let cp = [bp[0] + x * ux - h * uy, bp[1] + x * uy + h * ux];
    let th3 = (cp[1] - bp[1]).atan2(cp[0] - bp[0]);
    let psi = cp[1].atan2(cp[0] - d);
    (cp, th3, psi)
}

const FOUR_BAR: (f64, f64, f64, f64) = (1.0, 3.0, 2.5, 3.2);

/// Four positions of the rocker pin C of the test's four-bar, at crank
/// angles 0.4, 1.5, 2.9 and 4.4 rad (not told to the searches).
fn rocker_pin_targets() -> Vec<[f64; 2]> {
    let (a, b, c, d) = FOUR_BAR;
    [0.4, 1.5, 2.9, 4.4]
        .iter()
        .map(|&phi| closed_form(a, b, c, d, phi).0)
        .collect()
}

/// Freudenstein's equation at three pairs of the test's four-bar gives
/// back its crank, coupler and rocker, the ground given.
#[test]
fn three_point_function_generation_is_exact() {
    let (a, b, c, d) = FOUR_BAR;
    let pairs = [0.7, 1.4, 2.2].map(|phi| (phi, closed_form(a, b, c, d, phi).2));
    let f = freudenstein(pairs, d).unwrap();
    assert!((f.a - a).abs() < 1e-12, "{f:?}");
    assert!((f.b - b).abs() < 1e-12, "{f:?}");
    assert!((f.c - c).abs() < 1e-12, "{f:?}");
    assert!((f.k[0] - d / a).abs() < 1e-12 && (f.k[1] - d / c).abs() < 1e-12);
    // Chebyshev spacing over [0.5, 2.5]: the middle point is the centre,
    // the ends symmetric about it, all inside.
    let x = chebyshev(0.5, 2.5, 3);
    assert!((x[1] - 1.5).abs() < 1e-15 && (x[0] + x[2] - 3.0).abs() < 1e-15);
    assert!((x[0] - (1.5 - (PI / 6.0).cos())).abs() < 1e-15);
    // Two pairs the same: no unique answer, said so.
    let e = freudenstein([pairs[0], pairs[0], pairs[2]], d).unwrap_err();
    assert!(e.to_string().contains("distinct precision points"), "{e}");
    let e = freudenstein(pairs, -1.0).unwrap_err();
    assert!(e.to_string().contains("positive"), "{e}");
    // ψ = 240° + 60° log₂ x against φ = 30° + 90°(x − 1) at three
    // Chebyshev points of [1, 2]: K1 and K2 come out negative (the crank
    // and the rocker point the other way), said so.
    let g = |x: f64| {
        (
            (30.0 + 90.0 * (x - 1.0)).to_radians(),
            (240.0 + 60.0 * x.log2()).to_radians(),
        )
    };
    let x = chebyshev(1.0, 2.0, 3);
    let e = freudenstein([g(x[0]), g(x[1]), g(x[2])], 1.0).unwrap_err();
    assert!(
        e.to_string()
            .contains("crank and the rocker come out negative"),
        "{e}"
    );
}

/// Three poses of the test's four-bar's coupler (the crank pin B and the
/// coupler's angle θ3): the circle points B = (0, 0) and C = (b, 0) in the
/// coupler's frame have the ground pivots A and D as centre points, and
/// the inversion gives the circle points back from the pivots.
#[test]
fn three_position_motion_generation_is_exact() {
    let (a, b, c, d) = FOUR_BAR;
    let poses = [0.3, 0.9, 1.6].map(|phi| {
        let (_, th3, _) = closed_form(a, b, c, d, phi);
        [a * phi.cos(), a * phi.sin(), th3]
    });
    let close = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) < 1e-11;
    assert!(close(centre_point(poses, [0.0, 0.0]).unwrap(), [0.0, 0.0]));
    assert!(close(centre_point(poses, [b, 0.0]).unwrap(), [d, 0.0]));
    assert!(close(circle_point(poses, [d, 0.0]).unwrap(), [b, 0.0]));
    let m = three_positions(poses, [[0.0, 0.0], [b, 0.0]]).unwrap();
    for (got, want) in m.lengths.iter().zip([a, b, c, d]) {
        assert!((got - want).abs() < 1e-11, "{:?}", m.lengths);
    }
    for (k, phi) in [0.3f64, 0.9, 1.6].iter().enumerate() {
        let psi = closed_form(a, b, c, d, *phi).2;
        assert!((m.input_angles[k] - phi).abs() < 1e-11);
        assert!((m.output_angles[k] - psi).abs() < 1e-11);
    }
    // Collinear positions: no circle, said so.
    let line = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let e = centre_point(line, [0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("collinear"), "{e}");
}

const FOUR_BAR_TEXT: &str = "struct FourBar {
    params { a, b, c, d }
    drivers { phi }
    unknowns { th3, th4 }
    points {
        A = vec2(0.0, 0.0);
        B = polar(a, phi);
        D = vec2(d, 0.0);
        C = D + polar(c, th4);
    }
    loops { B + polar(b, th3) == C; }
    sensitivities { a, b, c, d }
}";

/// Motion generation by Levenberg–Marquardt: the coupler (point B and
/// angle θ3) through five poses of the test's four-bar, from a design 10 %
/// off, with free timing, reaches the design to round-off.
#[test]
fn motion_generation_recovers_the_design() {
    let (a, b, c, d) = FOUR_BAR;
    let phis = [0.2, 0.8, 1.5, 2.3, 3.1];
    let poses: Vec<[f64; 3]> = phis
        .iter()
        .map(|&phi| {
            let (_, th3, _) = closed_form(a, b, c, d, phi);
            [a * phi.cos(), a * phi.sin(), th3]
        })
        .collect();
    let mut m = Model::compile(FOUR_BAR_TEXT).unwrap();
    m.set_values(&[1.1, 2.8, 2.7, 3.2]).unwrap();
    let start = m.assemble(&[0.2, 0.3, 1.2]).unwrap();
    let found = Synthesis::motion(&m, "phi", ("B", "th3"), &poses, 1.0, &start)
        .vary(&["a", "b", "c"])
        .driver_guesses(&phis.map(|p| p + 0.05))
        .run()
        .unwrap();
    assert!(found.sum_squares < 1e-20, "{found:?}");
    for (got, want) in found.design.values().iter().zip([a, b, c, d]) {
        assert!((got - want).abs() < 1e-9, "{:?}", found.design.values());
    }
    assert_eq!(found.target_errors.len(), 5);
    // A pose of the wrong size, and an angle that is no coordinate.
    let e = Synthesis::motion(&m, "phi", ("B", "th3"), &[[0.0, 0.0]], 1.0, &start)
        .run()
        .unwrap_err();
    assert!(e.to_string().contains("has 3"), "{e}");
    let e = Synthesis::motion(&m, "phi", ("B", "psi"), &poses, 1.0, &start)
        .run()
        .unwrap_err();
    assert!(e.to_string().contains("no angle coordinate `psi`"), "{e}");
}

/// A path problem posed as data (the TOML of `kinematics synthesize`),
/// with a transmission angle of at least 40° and a crank that turns: the
/// search's best design, swept a whole turn here, keeps the transmission
/// angle at C (between C→B and C→D) within [40°, 140°] at every sample,
/// is a Grashof crank, and passes through its targets where the search
/// says.
#[test]
fn the_search_keeps_its_constraints_over_the_cycle() {
    // Targets: four points of the coupler curve of a crank-rocker (the
    // rocker pin C of the test's four-bar), at unknown crank angles.
    let targets = rocker_pin_targets();
    let text = format!(
        r#"
        driver = "phi"
        task = {{ kind = "path", point = "C" }}
        targets = {targets:?}
        in_order = true
        full_turn = true
        grashof_crank = {{ crank = "a", coupler = "b", rocker = "c", ground = "d", margin = 0.05 }}
        values = {{ d = 3.2 }}
        [vary]
        a = [0.3, 2.0]
        b = [0.5, 5.0]
        c = [0.5, 5.0]
        [[transmission]]
        points = ["B", "C", "D"]
        min = "40deg"
        [search]
        starts = 32
        keep = 8
        seed = 3
        "#
    );
    let spec: Spec = toml::from_str(&text).unwrap();
    let mut m = Model::compile(FOUR_BAR_TEXT).unwrap();
    m.set_values(&[1.0, 2.0, 2.0, 3.2]).unwrap();
    let found = spec.search(&m, &vec![0.0; 3]).unwrap().run().unwrap();
    let best = found.best().expect("a feasible design");
    let design = &best.found.design;
    let [a, b, c, d] = design.values() else {
        panic!()
    };
    let (a, b, c, d) = (*a, *b, *c, *d);
    // Grashof, the crank shortest, with the margin.
    assert!(a + b.max(c).max(d) + 0.05 <= b + c + d - b.max(c).max(d) + 1e-9);
    assert_eq!(best.found.full_turn, Some(true));
    // Swept a turn: μ at every sample.
    let sweep = design.sweep("phi", &best.poses[0]).unwrap().turn().run();
    assert!(sweep.stop.is_none(), "{:?}", sweep.stop);
    let mut smallest = f64::INFINITY;
    for s in &sweep.samples {
        let r = |k: usize| s.motion.points[k].position;
        let (bp, cp, dp) = (r(1), r(3), r(2));
        let u = [bp[0] - cp[0], bp[1] - cp[1]];
        let v = [dp[0] - cp[0], dp[1] - cp[1]];
        let mu = ((u[0] * v[0] + u[1] * v[1]) / (u[0].hypot(u[1]) * v[0].hypot(v[1]))).acos();
        assert!(mu.is_finite());
        smallest = smallest.min(mu.min(PI - mu));
    }
    assert!(
        smallest >= 40f64.to_radians() - 1e-9,
        "{}",
        smallest.to_degrees()
    );
    let reported = best.min_transmission.unwrap();
    assert!(
        (reported - smallest).abs() < 1e-9 + 1e-3,
        "{reported} {smallest}"
    );
    // E re-scored at the search's crank angles by the closed form here
    // (the design's own branch: C left of B→D, as the targets').
    let e: f64 = best
        .found
        .driver_values
        .iter()
        .zip(&targets)
        .map(|(&phi, t)| {
            let p = closed_form(a, b, c, d, phi).0;
            (p[0] - t[0]).powi(2) + (p[1] - t[1]).powi(2)
        })
        .sum();
    assert!(
        (e - best.found.sum_squares).abs() <= 1e-9 * e + 1e-24,
        "{e} {}",
        best.found.sum_squares
    );
    assert!(e < 1e-16, "{e}");
}

/// A problem's mistakes are errors naming them: a parameter that is not
/// varied-able, an unknown point, a bad mode, an unknown key.
#[test]
fn problem_mistakes_are_errors() {
    let m = Model::compile(FOUR_BAR_TEXT).unwrap();
    let base = r#"
        driver = "phi"
        task = { kind = "path", point = "C" }
        targets = [[1.0, 2.0], [1.5, 2.0]]
        [vary]
        a = [0.3, 2.0]
    "#;
    let run = |text: &str| -> String {
        let spec: Spec = toml::from_str(text).unwrap();
        match spec.search(&m, &vec![0.0; 3]) {
            Ok(s) => s
                .run()
                .map(|_| String::new())
                .unwrap_or_else(|e| e.to_string()),
            Err(e) => e.to_string(),
        }
    };
    let e = run(&base.replace("a = [0.3", "q = [0.3"));
    assert!(e.contains("`q` is not a parameter"), "{e}");
    let e = run(&base.replace("point = \"C\"", "point = \"Z\""));
    assert!(e.contains("no point `Z`"), "{e}");
    let e = run(&base.replace("driver = \"phi\"", "driver = \"th3\""));
    assert!(e.contains("not a driver"), "{e}");
    let e = run(&format!("modes = [\"x\"]\n{base}"));
    assert!(e.contains("not an assembly mode"), "{e}");
    let e = run(&format!(
        "in_order = true\ntiming = {{ prescribed = [0.1, 0.2] }}\n{base}"
    ));
    assert!(e.contains("in_order orders free driver values"), "{e}");
    let e = run(&format!("{base}\n[search]\nseconds = 1e300"));
    assert!(e.contains("search.seconds"), "{e}");
    let e = run(&format!("weights = [1.0, 0.0]\n{base}"));
    assert!(e.contains("weights must be positive"), "{e}");
    let e = run(&base.replace("[1.5, 2.0]]", "[1.5, 2.0, 3.0]]"));
    assert!(e.contains("target 1 has 3 components"), "{e}");
    let e = toml::from_str::<Spec>(&format!("colour = 1\n{base}")).unwrap_err();
    assert!(e.to_string().contains("colour"), "{e}");
}

/// `examples/synthesis/NAME`: the problem read as `kinematics synthesize`
/// reads it, and its definition compiled with the problem's values.
fn data_file(name: &str) -> (Spec, Model) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/synthesis");
    let mut spec: Spec = toml::from_str(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap();
    let text = std::fs::read_to_string(dir.join(spec.mechanism.as_ref().unwrap())).unwrap();
    let mut m = Model::compile(&text).unwrap();
    for (k, v) in std::mem::take(&mut spec.values) {
        m.set(&k, v.value(&k).unwrap()).unwrap();
    }
    for (k, [lo, hi]) in &spec.vary {
        m.set(k, 0.5 * (lo.value(k).unwrap() + hi.value(k).unwrap()))
            .unwrap();
    }
    (spec, m)
}

/// Slider-crank function generation from its data file: the slider's
/// position at six crank angles of a known design; the search's design
/// re-scored by x = a cos φ + √(b² − (a sin φ − e)²), written here,
/// passes through the pairs and turns fully.
#[test]
fn slider_crank_function_generation_from_its_data_file() {
    let (spec, m) = data_file("slider_crank_function.toml");
    let found = spec.search(&m, &vec![0.0; 3]).unwrap().run().unwrap();
    let best = found.best().expect("a feasible design");
    let [a, b, e] = best.found.design.values() else {
        panic!()
    };
    let pairs = [20.0f64, 70.0, 130.0, 190.0, 250.0, 310.0].map(|deg| {
        let p: f64 = deg.to_radians();
        (
            p,
            0.05 * p.cos() + (0.04f64 - (0.05 * p.sin() - 0.01).powi(2)).sqrt(),
        )
    });
    let err: f64 = pairs
        .iter()
        .zip(&best.found.driver_values)
        .map(|(&(phi, x), &at)| {
            assert!((phi - at).abs() < 1e-15, "the timing is the pairs' inputs");
            let got = a * phi.cos() + (b * b - (a * phi.sin() - e).powi(2)).sqrt();
            (got - x).powi(2)
        })
        .sum();
    assert!(err < 1e-24, "{err:e}");
    assert!((err - best.found.sum_squares).abs() < 1e-24);
    assert_eq!(best.found.full_turn, Some(true));
}

/// The Watt II six-bar's point P by circle intersections written here, on
/// the assembly `(s1, s2)` of its two dyads (the intersection to the left
/// of B→D, or the right; to the left of E→G, or the right); `None` where
/// a dyad does not close.
fn watt_point(p: &[f64], phi: f64, (s1, s2): (f64, f64)) -> Option<[f64; 2]> {
    let &[a, b, c, d, e, gamma, f, g, gx, gy, pf, pb] = p else {
        return None;
    };
    let circle = |p: [f64; 2], r1: f64, q: [f64; 2], r2: f64, s: f64| -> Option<[f64; 2]> {
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let l = dx.hypot(dy);
        let x = (r1 * r1 - r2 * r2 + l * l) / (2.0 * l);
        let h2 = r1 * r1 - x * x;
        (h2 >= 0.0).then(|| {
            let h = h2.sqrt();
            let (ux, uy) = (dx / l, dy / l);
            [p[0] + x * ux - s * h * uy, p[1] + x * uy + s * h * ux]
        })
    };
    let bp = [a * phi.cos(), a * phi.sin()];
    let cp = circle(bp, b, [d, 0.0], c, s1)?;
    let th4 = cp[1].atan2(cp[0] - d);
    let ep = [d + e * (th4 + gamma).cos(), e * (th4 + gamma).sin()];
    let fp = circle(ep, f, [gx, gy], g, s2)?;
    let th5 = (fp[1] - ep[1]).atan2(fp[0] - ep[0]);
    Some([ep[0] + pf * (th5 + pb).cos(), ep[1] + pf * (th5 + pb).sin()])
}

/// Six-bar path generation from its data file (twelve targets at
/// prescribed crank angles, eight dimensions of the second loop free):
/// the search's design, re-scored by the circle
/// intersections above on one assembly of its two dyads at every target,
/// has the E the search reports, below 1e-12 of the targets' scale, and
/// turns fully, its targets reached without a stop.
#[test]
fn six_bar_path_generation_from_its_data_file() {
    let (spec, m) = data_file("watt_path.toml");
    let found = spec.search(&m, &vec![0.0; 5]).unwrap().run().unwrap();
    let best = found.best().expect("a feasible design");
    let p = best.found.design.values();
    let targets: Vec<[f64; 2]> = spec
        .targets
        .iter()
        .map(|t| [t[0].value("x").unwrap(), t[1].value("y").unwrap()])
        .collect();
    assert!(targets.len() >= 10);
    let e = [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
        .into_iter()
        .filter_map(|sides| {
            best.found
                .driver_values
                .iter()
                .zip(&targets)
                .map(|(&phi, t)| {
                    let r = watt_point(p, phi, sides)?;
                    Some((r[0] - t[0]).powi(2) + (r[1] - t[1]).powi(2))
                })
                .sum::<Option<f64>>()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(
        (e - best.found.sum_squares).abs() <= 1e-9 * e + 1e-24,
        "{e} {}",
        best.found.sum_squares
    );
    assert!(e < 1e-12, "E = {e:e}");
    assert_eq!(best.found.full_turn, Some(true));
    assert!(best.one_branch);
}

/// The search started from the exact answer: y = log₁₀ x on [1, 2] as
/// φ = 40° + 60°(x − 1), ψ = 100° + 60° log₂ x; Freudenstein's four-bar
/// through three Chebyshev points, then the search over six points from
/// it alone (no drawn start). E of both designs over the six points by
/// the closed form here (the rocker pin to the right of B→D): the
/// search's is the E it reports, and below the exact three-point answer's.
#[test]
fn the_search_starts_from_the_exact_three_point_answer() {
    let f = |x: f64| {
        (
            (40.0 + 60.0 * (x - 1.0)).to_radians(),
            (100.0 + 60.0 * x.log2()).to_radians(),
        )
    };
    let xs = chebyshev(1.0, 2.0, 3);
    let exact = freudenstein([f(xs[0]), f(xs[1]), f(xs[2])], 1.0).unwrap();
    let pairs: Vec<(f64, f64)> = (0..6).map(|k| f(1.0 + 0.2 * f64::from(k))).collect();
    // ψ on the branch to the right of B→D (the branch of the pairs).
    let psi = |(a, b, c, d): (f64, f64, f64, f64), phi: f64| -> f64 {
        let (cp, _, _) = closed_form_right(a, b, c, d, phi);
        cp[1].atan2(cp[0] - d)
    };
    let wrapped = |x: f64| PI - (PI - x).rem_euclid(2.0 * PI);
    let e = |m: (f64, f64, f64, f64)| -> f64 {
        pairs
            .iter()
            .map(|&(phi, y)| wrapped(psi(m, phi) - y).powi(2))
            .sum()
    };
    let e_exact = e((exact.a, exact.b, exact.c, 1.0));
    let mut m = Model::compile(FOUR_BAR_TEXT).unwrap();
    m.set_values(&[exact.a, exact.b, exact.c, 1.0]).unwrap();
    let (_, th3, _) = closed_form_right(exact.a, exact.b, exact.c, 1.0, pairs[0].0);
    let start = m.assemble(&[pairs[0].0, th3, pairs[0].1]).unwrap();
    assert!(
        (start[2] - pairs[0].1).abs() < 0.01,
        "the start on the pairs' branch"
    );
    let found = Synthesis::function(&m, "phi", "th4", &pairs, &start)
        .vary(&["a", "b", "c"])
        .bounds("a", 0.1, 10.0)
        .bounds("b", 0.1, 10.0)
        .bounds("c", 0.1, 10.0)
        .search()
        .also_from(&m, None)
        .starts(0)
        .run()
        .unwrap();
    // The design given, alone.
    assert_eq!(found.starts, 1);
    let best = found.best().expect("a feasible design");
    let [a, b, c, d] = best.found.design.values() else {
        panic!()
    };
    // On the pairs' branch, or on the other if the search ended there.
    let left: f64 = pairs
        .iter()
        .map(|&(phi, y)| {
            let (cp, _, _) = closed_form(*a, *b, *c, *d, phi);
            wrapped(cp[1].atan2(cp[0] - d) - y).powi(2)
        })
        .sum();
    let reported = best.found.sum_squares;
    let e_best = [e((*a, *b, *c, *d)), left]
        .into_iter()
        .find(|e| (e - reported).abs() <= 1e-9 * e)
        .unwrap_or_else(|| panic!("neither branch gives E = {reported:e}"));
    assert!(e_best < 0.5 * e_exact, "{e_best:e} against {e_exact:e}");
}

/// [`closed_form`] on the other branch: the rocker pin to the right of
/// B→D.
fn closed_form_right(a: f64, b: f64, c: f64, d: f64, phi: f64) -> ([f64; 2], f64, f64) {
    let bp = [a * phi.cos(), a * phi.sin()];
    let (dx, dy) = (d - bp[0], -bp[1]);
    let l = dx.hypot(dy);
    let x = (b * b - c * c + l * l) / (2.0 * l);
    let h = (b * b - x * x).sqrt();
    let (ux, uy) = (dx / l, dy / l);
    let cp = [bp[0] + x * ux + h * uy, bp[1] + x * uy - h * ux];
    let th3 = (cp[1] - bp[1]).atan2(cp[0] - bp[0]);
    let psi = cp[1].atan2(cp[0] - d);
    (cp, th3, psi)
}

/// A constraint no design meets over its motion makes every optimum
/// infeasible, and the search says it found no feasible design: the
/// rocker's pivot kept inside a box it is not in.
#[test]
fn a_constraint_over_the_motion_is_enforced() {
    let targets = rocker_pin_targets();
    let mut m = Model::compile(FOUR_BAR_TEXT).unwrap();
    m.set_values(&[1.0, 2.0, 2.0, 3.2]).unwrap();
    let search = |region: bool| {
        let s = Synthesis::path(&m, "phi", "C", &targets, &vec![0.0; 3])
            .vary(&["a", "b", "c"])
            .bounds("a", 0.3, 2.0)
            .bounds("b", 0.5, 5.0)
            .bounds("c", 0.5, 5.0)
            .search()
            .starts(8)
            .seed(3);
        let s = if region {
            // The ground pivot D = (3.2, 0), which no varied dimension
            // moves, kept left of x = 3.
            s.inside("D", &[-10.0, -10.0], &[3.0, 10.0])
        } else {
            s
        };
        s.run().unwrap()
    };
    let free = search(false);
    assert!(free.best().is_some());
    let boxed = search(true);
    assert!(!boxed.optima.is_empty());
    assert!(boxed.best().is_none());
    assert!(boxed.optima.iter().all(|o| !o.feasible));
    // A box that is not one is refused by name.
    let e = Synthesis::path(&m, "phi", "C", &targets, &vec![0.0; 3])
        .bounds("a", 0.3, 2.0)
        .search()
        .inside("C", &[1.0, 0.0], &[0.0, 1.0])
        .run()
        .unwrap_err();
    assert!(e.to_string().contains("lo ≤ hi"), "{e}");
}
