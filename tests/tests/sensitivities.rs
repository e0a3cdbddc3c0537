//! Design sensitivities (the `sensitivities` section) against central
//! differences of the solved motion over each parameter, fourth-order
//! stencil, for seeded random four-bars, slider-cranks, Watt six-bars,
//! RSSRs and a six-axis arm: coordinates, rates, accelerations and every
//! point's position, velocity and acceleration.
#![allow(missing_docs, clippy::expect_used, clippy::panic)]

use kinematics_core::{mechanism, MotionState, PointState};
use kinematics_tests::Rng;

mechanism! {
    pub struct FourBar {
        params { a, b, c, d, p, beta }
        drivers { phi }
        unknowns { th3, th4 }
        points { B = polar(a, phi); P = B + polar(p, th3 + beta); C = vec2(d, 0.0) + polar(c, th4); }
        loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
        sensitivities { a, b, c, d, p, beta }
    }
}

mechanism! {
    pub struct SliderCrank {
        params { a, b, e }
        drivers { phi }
        unknowns { th, x }
        points { B = polar(a, phi); C = vec2(x, e); M = B + polar(0.5 * b, th); }
        loops { polar(a, phi) + polar(b, th) == vec2(x, e); }
        sensitivities { a, b, e }
    }
}

mechanism! {
    pub struct Watt {
        params { a, b, c, d, e, gamma, f, g, gx, gy }
        drivers { phi }
        unknowns { th3, th4, th5, th6 }
        points { F = vec2(d, 0.0) + polar(e, th4 + gamma) + polar(f, th5); }
        loops {
            polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4);
            F == vec2(gx, gy) + polar(g, th6);
        }
        sensitivities { a, b, c, e, gamma, f, g, gx }
    }
}

mechanism! {
    pub struct Rssr {
        params { a, b, c, d }
        drivers { phi }
        unknowns { psi }
        points {
            A = vec3(-a * cos(phi), 0.0, a * sin(phi));
            B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
        }
        constraints { norm(B - A) == b; }
        sensitivities { a, b, c, d }
    }
}

mechanism! {
    pub struct Arm {
        params { d1, a2, a3, d5, d6 }
        drivers { q1, q2, q3, q4, q5, q6 }
        unknowns { }
        frames {
            tool = t3(0.0, 0.0, d1, q1) * t2(0.0, 0.0, 0.0, q2) * t2(a2, 0.0, 0.0, q3)
                * t1(0.0, 0.0, 0.0, q4) * t2(a3, 0.0, 0.0, q5) * t1(d5, 0.0, 0.0, q6);
        }
        points { TCP = tool * vec3(d6, 0.0, 0.0); }
        sensitivities { d1, a2, a3, d5, d6 }
    }
}

/// Every number of a motion: q, q', q'' of every coordinate, then each
/// point's position, velocity and acceleration.
fn flat<S: MotionState>(s: &S, coords: usize) -> Vec<f64> {
    use kinematics_core::Coordinates;
    let mut out = Vec::new();
    for c in [s.q(), s.qd(), s.qdd()] {
        out.extend((0..coords).map(|j| c.get(j).unwrap_or(f64::NAN)));
    }
    for p in s.points() {
        out.extend_from_slice(p.position());
        out.extend_from_slice(p.velocity());
        out.extend_from_slice(p.acceleration());
    }
    out
}

/// Compares `exact[k]` (the flattened sensitivity to parameter k) with the
/// fourth-order central difference of `motion` over parameter k, step `h`
/// relative to the parameter's size; returns the largest relative error.
fn compare(
    params: &[f64],
    exact: &[Vec<f64>],
    which: &[usize],
    motion: &dyn Fn(&[f64]) -> Vec<f64>,
) -> f64 {
    let base = motion(params);
    let scale = base.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (k, &i) in which.iter().enumerate() {
        let h = 1e-3 * params[i].abs().max(0.05);
        let at = |t: f64| {
            let mut p = params.to_vec();
            p[i] += t * h;
            motion(&p)
        };
        let (p2, p1, m1, m2) = (at(2.0), at(1.0), at(-1.0), at(-2.0));
        for n in 0..base.len() {
            let fd = (-p2[n] + 8.0 * p1[n] - 8.0 * m1[n] + m2[n]) / (12.0 * h);
            let e = (fd - exact[k][n]).abs()
                / (scale / params[i].abs().max(0.05)).max(exact[k][n].abs());
            assert!(
                e < 1e-7,
                "parameter {i}, entry {n}: exact {} against {fd}",
                exact[k][n]
            );
            worst = worst.max(e);
        }
    }
    worst
}

#[test]
fn four_bar_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(0x5E45_0001);
    let mut checked = 0;
    let mut worst = 0.0f64;
    while checked < 20 {
        // A crank-rocker (Grashof, crank shortest), well away from toggle.
        let p = [
            rng.range(0.02, 0.04),
            rng.range(0.10, 0.14),
            rng.range(0.08, 0.12),
            rng.range(0.09, 0.12),
            rng.range(0.02, 0.08),
            rng.range(-1.0, 1.0),
        ];
        let phi = rng.angle();
        let make = |p: &[f64]| FourBar {
            a: p[0],
            b: p[1],
            c: p[2],
            d: p[3],
            p: p[4],
            beta: p[5],
        };
        let m = make(&p);
        let guess = FourBarCoords {
            phi,
            th3: 0.8,
            th4: 1.6,
        };
        let Ok(pose) = m.assemble(&guess) else {
            continue;
        };
        let Ok(s) = m.analyze(&pose, 7.0, -3.0) else {
            continue;
        };
        if s.conditioning < 0.05 {
            continue;
        }
        let sens = m.sensitivities(&s).expect("sensitivities");
        let exact: Vec<Vec<f64>> = sens.to_array().iter().map(|x| flat_sens(x, 3)).collect();
        let motion = |q: &[f64]| {
            let m = make(q);
            let pose = m.assemble(&pose).expect("assembles nearby");
            flat(&m.analyze(&pose, 7.0, -3.0).expect("analyses"), 3)
        };
        worst = worst.max(compare(&p, &exact, &[0, 1, 2, 3, 4, 5], &motion));
        checked += 1;
    }
    eprintln!("four-bar: largest relative difference {worst:e}");
}

/// A sensitivity flattened as [`flat`] flattens a motion.
fn flat_sens<T: SensitivityLike>(s: &T, coords: usize) -> Vec<f64> {
    s.flat(coords)
}

trait SensitivityLike {
    fn flat(&self, coords: usize) -> Vec<f64>;
}

macro_rules! sensitivity_like {
    ($($t:ty),*) => {$(
        impl SensitivityLike for $t {
            fn flat(&self, coords: usize) -> Vec<f64> {
                use kinematics_core::Coordinates;
                let mut out = Vec::new();
                for c in [&self.q, &self.qd, &self.qdd] {
                    out.extend((0..coords).map(|j| c.get(j).unwrap_or(f64::NAN)));
                }
                for p in &self.points {
                    out.extend_from_slice(p.position.as_slice());
                    out.extend_from_slice(p.velocity.as_slice());
                    out.extend_from_slice(p.acceleration.as_slice());
                }
                out
            }
        }
    )*};
}

sensitivity_like!(
    FourBarSensitivity,
    SliderCrankSensitivity,
    WattSensitivity,
    RssrSensitivity,
    ArmSensitivity
);

#[test]
fn slider_crank_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(0x5E45_0002);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let p = [
            rng.range(0.05, 0.1),
            rng.range(0.2, 0.3),
            rng.range(-0.03, 0.03),
        ];
        let phi = rng.angle();
        let make = |p: &[f64]| SliderCrank {
            a: p[0],
            b: p[1],
            e: p[2],
        };
        let m = make(&p);
        let pose = m
            .assemble(&SliderCrankCoords {
                phi,
                th: 0.0,
                x: 0.3,
            })
            .expect("assembles");
        let s = m.analyze(&pose, 12.0, 5.0).expect("analyses");
        let sens = m.sensitivities(&s).expect("sensitivities");
        let exact: Vec<Vec<f64>> = sens.to_array().iter().map(|x| flat_sens(x, 3)).collect();
        let motion = |q: &[f64]| {
            let m = make(q);
            let pose = m.assemble(&pose).expect("assembles nearby");
            flat(&m.analyze(&pose, 12.0, 5.0).expect("analyses"), 3)
        };
        worst = worst.max(compare(&p, &exact, &[0, 1, 2], &motion));
    }
    eprintln!("slider-crank: largest relative difference {worst:e}");
}

#[test]
fn watt_six_bar_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(0x5E45_0003);
    let mut checked = 0;
    let mut tries = 0;
    let mut worst = 0.0f64;
    while checked < 10 && tries < 400 {
        tries += 1;
        let p = [
            rng.range(0.035, 0.045),
            rng.range(0.115, 0.125),
            rng.range(0.095, 0.105),
            0.11,
            rng.range(0.05, 0.07),
            rng.range(-0.2, 0.2),
            rng.range(0.09, 0.11),
            rng.range(0.07, 0.09),
            0.20,
            0.10,
        ];
        let make = |p: &[f64]| Watt {
            a: p[0],
            b: p[1],
            c: p[2],
            d: p[3],
            e: p[4],
            gamma: p[5],
            f: p[6],
            g: p[7],
            gx: p[8],
            gy: p[9],
        };
        let m = make(&p);
        let phi = rng.range(-0.5, 0.5);
        let Ok(pose) = m.assemble(&WattCoords {
            phi,
            th3: 1.0,
            th4: 1.6,
            th5: 0.3,
            th6: 1.9,
        }) else {
            continue;
        };
        let Ok(s) = m.analyze(&pose, 10.0, 2.0) else {
            continue;
        };
        if s.conditioning < 0.05 {
            continue;
        }
        let sens = m.sensitivities(&s).expect("sensitivities");
        let exact: Vec<Vec<f64>> = sens.to_array().iter().map(|x| flat_sens(x, 5)).collect();
        let motion = |q: &[f64]| {
            let m = make(q);
            let pose = m.assemble(&pose).expect("assembles nearby");
            flat(&m.analyze(&pose, 10.0, 2.0).expect("analyses"), 5)
        };
        worst = worst.max(compare(&p, &exact, &[0, 1, 2, 4, 5, 6, 7, 8], &motion));
        checked += 1;
    }
    assert_eq!(checked, 10, "too few Watt six-bars assembled");
    eprintln!("Watt six-bar: largest relative difference {worst:e}");
}

#[test]
fn rssr_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(0x5E45_0004);
    let mut checked = 0;
    let mut worst = 0.0f64;
    while checked < 20 {
        let p = [
            rng.range(0.09, 0.11),
            rng.range(0.37, 0.39),
            rng.range(0.24, 0.26),
            rng.range(0.30, 0.32),
        ];
        let make = |p: &[f64]| Rssr {
            a: p[0],
            b: p[1],
            c: p[2],
            d: p[3],
        };
        let m = make(&p);
        let phi = rng.angle();
        let Ok(pose) = m.assemble(&RssrCoords { phi, psi: 1.2 }) else {
            continue;
        };
        let Ok(s) = m.analyze(&pose, 25.0, 3.0) else {
            continue;
        };
        if s.conditioning < 0.05 {
            continue;
        }
        let sens = m.sensitivities(&s).expect("sensitivities");
        let exact: Vec<Vec<f64>> = sens.to_array().iter().map(|x| flat_sens(x, 2)).collect();
        let motion = |q: &[f64]| {
            let m = make(q);
            let pose = m.assemble(&pose).expect("assembles nearby");
            flat(&m.analyze(&pose, 25.0, 3.0).expect("analyses"), 2)
        };
        worst = worst.max(compare(&p, &exact, &[0, 1, 2, 3], &motion));
        checked += 1;
    }
    eprintln!("RSSR: largest relative difference {worst:e}");
}

#[test]
fn six_axis_arm_sensitivities_equal_central_differences() {
    let mut rng = Rng::new(0x5E45_0005);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let p = [
            rng.range(0.3, 0.5),
            rng.range(0.3, 0.5),
            rng.range(0.3, 0.5),
            rng.range(0.05, 0.1),
            rng.range(0.05, 0.15),
        ];
        let make = |p: &[f64]| Arm {
            d1: p[0],
            a2: p[1],
            a3: p[2],
            d5: p[3],
            d6: p[4],
        };
        let m = make(&p);
        let q: [f64; 6] = std::array::from_fn(|_| rng.angle());
        let rates: [f64; 6] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
        let accs: [f64; 6] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
        let pose = ArmCoords::from(q);
        let s = m.analyze(&pose, rates, accs).expect("analyses");
        let sens = m.sensitivities(&s).expect("sensitivities");
        let exact: Vec<Vec<f64>> = sens.to_array().iter().map(|x| flat_sens(x, 6)).collect();
        let motion = |p: &[f64]| flat(&make(p).analyze(&pose, rates, accs).expect("analyses"), 6);
        worst = worst.max(compare(&p, &exact, &[0, 1, 2, 3, 4], &motion));
    }
    eprintln!("six-axis arm: largest relative difference {worst:e}");
}

#[test]
fn sensitivities_are_named() {
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    let pose = m
        .assemble(&FourBarCoords {
            phi: 0.3,
            th3: 1.0,
            th4: 1.6,
        })
        .expect("assembles");
    let s = m.step(&pose, 10.0, 0.0).expect("steps");
    let sens = m.sensitivities(&s).expect("sensitivities");
    assert_eq!(
        FourBarSensitivities::PARAMETERS,
        ["a", "b", "c", "d", "p", "beta"]
    );
    assert_eq!(sens.to_array()[5], sens.beta);
    // The crank pin B = polar(a, φ) depends on a only: ∂B/∂a = (cos φ, sin φ).
    let db = sens.a.point_b().position;
    assert!((db.x - 0.3f64.cos()).abs() < 1e-15 && (db.y - 0.3f64.sin()).abs() < 1e-15);
    assert_eq!(sens.b.point_b().position.norm(), 0.0);
    // The drivers do not move with the parameters.
    assert_eq!(
        (sens.c.q.phi, sens.c.qd.phi, sens.c.qdd.phi),
        (0.0, 0.0, 0.0)
    );
}

#[test]
fn tolerance_stack_up_agrees_with_monte_carlo() {
    use kinematics_core::tolerance::point_deviations;
    // The crank-rocker with ±0.1 mm on its lengths and ±0.1° on β, and the
    // same tolerances drawn uniformly for 2000 Monte Carlo designs.
    let m = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    };
    let start = m
        .assemble(&FourBarCoords {
            phi: 0.0,
            th3: 1.0,
            th4: 1.6,
        })
        .expect("assembles");
    let sweep = m
        .sweep(FourBar::PHI, &start)
        .turn()
        .steps(24)
        .rate(10.0)
        .run();
    assert!(sweep.stop.is_none());
    let t = [1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 0.1f64.to_radians()];
    let names = ["a", "b", "c", "d", "p", "beta"];
    let tolerances: Vec<(&str, f64)> = names.iter().copied().zip(t).collect();
    let dev = point_deviations(&m, &sweep, "P", &tolerances).expect("deviations");
    assert_eq!(dev.len(), sweep.samples.len());
    let mut rng = Rng::new(0x70_1E7A);
    let n = 2000;
    // Per sample: the largest |δr_c| and |δv_c|, Σ δ², the largest |δr|.
    let ns = sweep.samples.len();
    let mut max_c = vec![[0.0f64; 4]; ns];
    let mut sum2 = vec![[0.0f64; 4]; ns];
    let mut max_dist = vec![0.0f64; ns];
    for _ in 0..n {
        let d: Vec<f64> = t.iter().map(|t| rng.range(-t, *t)).collect();
        let mc = FourBar {
            a: m.a + d[0],
            b: m.b + d[1],
            c: m.c + d[2],
            d: m.d + d[3],
            p: m.p + d[4],
            beta: m.beta + d[5],
        };
        for (i, s) in sweep.samples.iter().enumerate() {
            let pose = mc.assemble(&s.motion.q).expect("assembles");
            let x = mc.analyze(&pose, 10.0, 0.0).expect("analyses");
            let (p0, p1) = (s.motion.point_p(), x.point_p());
            let dr = p1.position - p0.position;
            let dv = p1.velocity - p0.velocity;
            for (c, v) in [dr.x, dr.y, dv.x, dv.y].into_iter().enumerate() {
                max_c[i][c] = max_c[i][c].max(v.abs());
                sum2[i][c] += v * v;
            }
            max_dist[i] = max_dist[i].max(dr.norm());
        }
    }
    let mut worst_ratio = 0.0f64;
    let mut std_ratio = (f64::INFINITY, 0.0f64);
    for (i, d) in dev.iter().enumerate() {
        let worst = [
            d.position_components[0],
            d.position_components[1],
            d.velocity_components[0],
            d.velocity_components[1],
        ];
        let rss = [
            d.position_rss[0],
            d.position_rss[1],
            d.velocity_rss[0],
            d.velocity_rss[1],
        ];
        for c in 0..4 {
            // Never beyond the first-order worst case (the second-order
            // terms are of the relative size of the tolerances, 1e-3).
            let r = max_c[i][c] / worst[c];
            assert!(r <= 1.01, "sample {i}, component {c}: {r}");
            worst_ratio = worst_ratio.max(r);
            // Uniform deviations: the standard deviation is RSS/√3.
            let std = (sum2[i][c] / f64::from(n)).sqrt();
            let ratio = std / (rss[c] / 3f64.sqrt());
            assert!(
                (ratio - 1.0).abs() < 0.06,
                "sample {i}, component {c}: {ratio}"
            );
            std_ratio = (std_ratio.0.min(ratio), std_ratio.1.max(ratio));
        }
        assert!(max_dist[i] <= 1.01 * d.position_worst);
    }
    eprintln!(
        "Monte Carlo ({n} designs): largest deviation {:.3} of the worst case; \
         standard deviation {:.3}–{:.3} of RSS/√3",
        worst_ratio, std_ratio.0, std_ratio.1
    );
}
