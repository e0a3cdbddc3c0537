//! Seeded random inputs, extreme values included, for a four-bar, a
//! slider-crank, a Watt six-bar, an RSSR and a six-axis arm: no panic, no
//! `Ok` holding a NaN or an infinity, no `Ok` pose that fails to close, and
//! no velocity off Φ_u u' = −Φ_d d' beyond what the conditioning allows.
//!
//! The loop equations, their Jacobians and the arm's forward kinematics are
//! written out here, independently of the generated code; the library's own
//! residual is not used.
//!
//! CI runs a few thousand cases per mechanism; a long run:
//!
//! ```sh
//! KINEMATICS_FUZZ_CASES=100000 cargo test --release -p kinematics-tests --test fuzz -- --nocapture
//! ```
//!
//! prints the outcome classes of each mechanism; `KINEMATICS_FUZZ_DEBUG=1`
//! also prints every case that breaks a rule, with its inputs.
// Test code asserts by panicking; the independent equations index arrays
// in step with the formulas; `!(x <= bound)` also catches a NaN.
#![allow(
    clippy::expect_used,
    clippy::panic,
    clippy::needless_range_loop,
    clippy::neg_cmp_op_on_partial_ord
)]

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use kinematics_core::nalgebra::{DMatrix, DVector, Matrix4, Vector3, Vector4};
use kinematics_core::{Coordinates, Error, Mechanism, MotionState, PointState};
use kinematics_examples::{
    FourBar, FourBarCoords, Rssr, RssrCoords, SixAxisArm, SixAxisArmCoords, SliderCrank,
    SliderCrankCoords, Watt, WattCoords,
};
use kinematics_tests::Rng;

/// Cases per mechanism: `KINEMATICS_FUZZ_CASES`, or 3000.
fn cases() -> usize {
    std::env::var("KINEMATICS_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000)
}

/// Values a careless or adversarial caller may pass.
const EXTREMES: [f64; 19] = [
    0.0,
    -0.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e300,
    -1e300,
    1e-300,
    -1e-300,
    1e-12,
    1e12,
    1e20,
    -1e20,
    1e154,
    1e-154,
    f64::MAX,
    f64::MIN_POSITIVE,
    -1.0,
    1e15,
];

/// Uniform in [lo, hi) most of the time; otherwise an extreme value, or the
/// uniform value scaled by 1e±8 (tiny and huge link ratios).
fn value(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    let r = rng.unit();
    if r < 0.82 {
        rng.range(lo, hi)
    } else if r < 0.94 {
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let k = (rng.unit() * EXTREMES.len() as f64) as usize;
        EXTREMES[k.min(EXTREMES.len() - 1)]
    } else if r < 0.97 {
        rng.range(lo, hi) * 1e8
    } else {
        rng.range(lo, hi) * 1e-8
    }
}

/// How one call ended.
fn class(r: &Result<(), Error>) -> &'static str {
    match r {
        Ok(()) => "Ok",
        Err(Error::NotConverged { .. }) => "NotConverged",
        Err(Error::Singular { .. }) => "Singular",
        Err(Error::NonFinite { .. }) => "NonFinite",
        Err(Error::InvalidParameter { .. }) => "InvalidParameter",
        Err(Error::WrongBranch { .. }) => "WrongBranch",
        Err(Error::InvalidOption { .. }) => "InvalidOption",
        Err(_) => "other error",
    }
}

/// The independent model of a mechanism with unknowns: Φ(q), Φ_u(q) and
/// Φ_d(q) (one driver), the mechanism's size (the sum of its lengths), and
/// the scales in which errors are measured: each equation's term scale
/// S_i (the sum of its link lengths) and each unknown's unit (1 for an
/// angle, the characteristic length L for a length), as documented for
/// `kinematics_core::solve::Scaling`.
trait Model: Mechanism + std::fmt::Debug {
    fn size(&self) -> f64;
    fn gap(&self, q: &Self::Coords) -> Vec<f64>;
    fn jacobians(&self, q: &Self::Coords) -> (DMatrix<f64>, DVector<f64>);
    fn scales(&self) -> (Vec<f64>, Vec<f64>);
}

/// Σ|v|.
fn sum_abs(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).sum()
}

impl Model for FourBar {
    fn size(&self) -> f64 {
        self.a.abs() + self.b.abs() + self.c.abs() + self.d.abs()
    }
    fn gap(&self, q: &FourBarCoords) -> Vec<f64> {
        vec![
            self.a * q.phi.cos() + self.b * q.th3.cos() - self.d - self.c * q.th4.cos(),
            self.a * q.phi.sin() + self.b * q.th3.sin() - self.c * q.th4.sin(),
        ]
    }
    fn scales(&self) -> (Vec<f64>, Vec<f64>) {
        let s = vec![
            sum_abs(&[self.a, self.b, self.c, self.d]),
            sum_abs(&[self.a, self.b, self.c]),
        ];
        (s, vec![1.0, 1.0])
    }
    fn jacobians(&self, q: &FourBarCoords) -> (DMatrix<f64>, DVector<f64>) {
        let (b, c) = (self.b, self.c);
        let ju = DMatrix::from_row_slice(
            2,
            2,
            &[
                -b * q.th3.sin(),
                c * q.th4.sin(),
                b * q.th3.cos(),
                -c * q.th4.cos(),
            ],
        );
        let jd = DVector::from_vec(vec![-self.a * q.phi.sin(), self.a * q.phi.cos()]);
        (ju, jd)
    }
}

impl Model for SliderCrank {
    fn size(&self) -> f64 {
        self.a.abs() + self.b.abs() + self.e.abs()
    }
    fn gap(&self, q: &SliderCrankCoords) -> Vec<f64> {
        vec![
            self.a * q.phi.cos() + self.b * q.th.cos() - q.x,
            self.a * q.phi.sin() + self.b * q.th.sin() - self.e,
        ]
    }
    fn scales(&self) -> (Vec<f64>, Vec<f64>) {
        let (fx, fy) = (
            sum_abs(&[self.a, self.b]),
            sum_abs(&[self.a, self.b, self.e]),
        );
        let l = fx.max(fy);
        (vec![fx + l, fy], vec![1.0, l])
    }
    fn jacobians(&self, q: &SliderCrankCoords) -> (DMatrix<f64>, DVector<f64>) {
        let ju = DMatrix::from_row_slice(
            2,
            2,
            &[-self.b * q.th.sin(), -1.0, self.b * q.th.cos(), 0.0],
        );
        let jd = DVector::from_vec(vec![-self.a * q.phi.sin(), self.a * q.phi.cos()]);
        (ju, jd)
    }
}

impl Model for Watt {
    fn size(&self) -> f64 {
        [
            self.a, self.b, self.c, self.d, self.e, self.f, self.g, self.gx, self.gy,
        ]
        .iter()
        .map(|v| v.abs())
        .sum()
    }
    fn gap(&self, q: &WattCoords) -> Vec<f64> {
        let t = q.th4 + self.gamma;
        vec![
            self.a * q.phi.cos() + self.b * q.th3.cos() - self.d - self.c * q.th4.cos(),
            self.a * q.phi.sin() + self.b * q.th3.sin() - self.c * q.th4.sin(),
            self.d + self.e * t.cos() + self.f * q.th5.cos() - self.gx - self.g * q.th6.cos(),
            self.e * t.sin() + self.f * q.th5.sin() - self.gy - self.g * q.th6.sin(),
        ]
    }
    fn scales(&self) -> (Vec<f64>, Vec<f64>) {
        let s = vec![
            sum_abs(&[self.a, self.b, self.c, self.d]),
            sum_abs(&[self.a, self.b, self.c]),
            sum_abs(&[self.d, self.e, self.f, self.gx, self.g]),
            sum_abs(&[self.e, self.f, self.gy, self.g]),
        ];
        (s, vec![1.0; 4])
    }
    fn jacobians(&self, q: &WattCoords) -> (DMatrix<f64>, DVector<f64>) {
        let t = q.th4 + self.gamma;
        let (b, c, e, f, g) = (self.b, self.c, self.e, self.f, self.g);
        #[rustfmt::skip]
        let ju = DMatrix::from_row_slice(4, 4, &[
            -b * q.th3.sin(), c * q.th4.sin(), 0.0, 0.0,
            b * q.th3.cos(), -c * q.th4.cos(), 0.0, 0.0,
            0.0, -e * t.sin(), -f * q.th5.sin(), g * q.th6.sin(),
            0.0, e * t.cos(), f * q.th5.cos(), -g * q.th6.cos(),
        ]);
        let jd = DVector::from_vec(vec![-self.a * q.phi.sin(), self.a * q.phi.cos(), 0.0, 0.0]);
        (ju, jd)
    }
}

impl Model for Rssr {
    fn size(&self) -> f64 {
        self.a.abs() + self.b.abs() + self.c.abs() + self.d.abs()
    }
    fn gap(&self, q: &RssrCoords) -> Vec<f64> {
        let a = Vector3::new(-self.a * q.phi.cos(), 0.0, self.a * q.phi.sin());
        let b = Vector3::new(-self.d - self.c * q.psi.cos(), self.c * q.psi.sin(), 0.0);
        vec![(b - a).norm() - self.b]
    }
    fn scales(&self) -> (Vec<f64>, Vec<f64>) {
        let x = sum_abs(&[self.a, self.c, self.d]);
        let s = (x * x + self.c * self.c + self.a * self.a).sqrt() + self.b.abs();
        (vec![s], vec![1.0])
    }
    fn jacobians(&self, q: &RssrCoords) -> (DMatrix<f64>, DVector<f64>) {
        let a = Vector3::new(-self.a * q.phi.cos(), 0.0, self.a * q.phi.sin());
        let b = Vector3::new(-self.d - self.c * q.psi.cos(), self.c * q.psi.sin(), 0.0);
        let d = b - a;
        let n = d.norm();
        let db = Vector3::new(self.c * q.psi.sin(), self.c * q.psi.cos(), 0.0);
        let da = Vector3::new(self.a * q.phi.sin(), 0.0, self.a * q.phi.cos());
        (
            DMatrix::from_element(1, 1, d.dot(&db) / n),
            DVector::from_element(1, -d.dot(&da) / n),
        )
    }
}

/// Tallies of the outcomes, and the violations found.
#[derive(Default)]
struct Tally {
    classes: BTreeMap<&'static str, usize>,
    violations: Vec<String>,
}

impl Tally {
    fn record(&mut self, what: &str, r: &Result<(), Error>) {
        *self.classes.entry(class(r)).or_default() += 1;
        if let Err(e) = r {
            // Every error must render a message (and not panic doing so).
            if e.to_string().is_empty() {
                self.violations.push(format!("{what}: empty message"));
            }
        }
    }

    fn report(&self, name: &str) {
        println!("{name}: {:?}", self.classes);
        assert!(
            self.violations.is_empty(),
            "{name}: {} violations, first: {:?}",
            self.violations.len(),
            &self.violations[..self.violations.len().min(5)]
        );
    }
}

/// Checks one `Ok` analysis of `m` at its pose, for driver rate `rate`.
fn check_ok<M: Model>(m: &M, motion: &M::Motion, rate: f64, tally: &mut Tally, what: &str) {
    let q = motion.q();
    let nq = M::DRIVERS + M::UNKNOWNS;
    let mut values: Vec<f64> = Vec::new();
    for j in 0..nq {
        values.extend([
            q.get(j).unwrap_or(f64::NAN),
            motion.qd().get(j).unwrap_or(f64::NAN),
            motion.qdd().get(j).unwrap_or(f64::NAN),
        ]);
    }
    for p in motion.points() {
        values.extend(
            p.position()
                .iter()
                .chain(p.velocity())
                .chain(p.acceleration()),
        );
    }
    values.push(motion.conditioning());
    if values.iter().any(|v| !v.is_finite()) {
        tally.violations.push(format!(
            "{what}: Ok holding a NaN or an infinity: {motion:?}"
        ));
        return;
    }
    // The pose closes, by the equations written out here.
    let size = m.size();
    let gap = m.gap(q).iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(gap <= 1e-9 * size) {
        tally.violations.push(format!(
            "{what}: Ok pose does not close: gap {gap:e} for size {size:e} ({m:?}, {q:?})",
            m = std::any::type_name::<M>()
        ));
    }
    // Velocities, in the scaled units of the conditioning (rows divided by
    // S_i, unknowns by their units): the residual of Φ̃_u ỹ = b̃ is at the
    // round-off of its terms (a backward-stable solve, with the entries of
    // Φ̃_u themselves evaluated to the round-off of their terms, which are
    // of order one after scaling even where an entry nearly cancels), and ỹ
    // is within ‖Ã⁻¹‖ (‖δÃ‖ ‖ỹ‖ + ‖δb̃‖) = (…) / conditioning of an
    // independent solve. Likewise the right-hand side b̃ = −Φ_d d' / S is
    // evaluated to the round-off of its terms, of order |d'| (the driver
    // angle's unit is 1 rad), even where they cancel to a tiny b̃ (a link
    // 1e20 long beside one of 0.2). The floor 1e-290 is the underflow of
    // the scaled system (rates some 1e300 times smaller than the
    // mechanism).
    let (ju, jd) = m.jacobians(q);
    let (rows, cols) = m.scales();
    let n = M::UNKNOWNS;
    let ud = DVector::from_iterator(
        n,
        (0..n).map(|k| motion.qd().get(M::DRIVERS + k).unwrap_or(f64::NAN)),
    );
    let scaled = DMatrix::from_fn(n, n, |i, k| ju[(i, k)] * cols[k] / rows[i]);
    let b = DVector::from_fn(n, |i, _| -jd[i] * rate / rows[i]);
    let y = DVector::from_fn(n, |k, _| ud[k] / cols[k]);
    let norm_a = (0..n)
        .map(|i| (0..n).map(|k| scaled[(i, k)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let residual = (&scaled * &y - &b).amax();
    let terms = norm_a.max(1.0) * y.amax() + b.amax() + rate.abs();
    if !(residual <= 1e-9 * terms + 1e-290) {
        tally.violations.push(format!(
            "{what}: velocity residual {residual:e} against terms {terms:e}"
        ));
    }
    // The reported branch is the sign of the independent det Φ_u (where
    // the pose is not so near a toggle that round-off could flip it).
    let det = ju.clone().lu().determinant();
    if motion.conditioning() > 1e-6 && det.signum() != motion.det_sign() {
        tally.violations.push(format!(
            "{what}: det Φ_u = {det:e} but det_sign {}",
            motion.det_sign()
        ));
    }
    if let Some(reference) = scaled.clone().lu().solve(&b) {
        let err = (&y - &reference).amax();
        let bound = (1e-8 * (norm_a.max(1.0) * reference.amax() + b.amax() + rate.abs()) + 1e-290)
            / motion.conditioning();
        if !(err <= bound) {
            tally.violations.push(format!(
                "{what}: u' off an independent solve by {err:e} > {bound:e} (conditioning {:e})",
                motion.conditioning()
            ));
        }
    }
}

/// Runs `assemble` + `analyze` and `step` of `m` from `start` with driver
/// rate `rate` and acceleration `acc`, catching panics, and checks every
/// `Ok`.
fn exercise<M: Model>(m: &M, start: &M::Coords, rate: f64, acc: f64, tally: &mut Tally) {
    let options = kinematics_core::Options::DEFAULT;
    let run = catch_unwind(AssertUnwindSafe(|| {
        let analysed = m
            .assemble_with(start, &options)
            .and_then(|q| m.analyze_slices(&q, &[rate], &[acc], &options));
        let stepped = m.step_slices(start, &[rate], &[acc], &options);
        (analysed, stepped)
    }));
    let Ok((analysed, stepped)) = run else {
        tally
            .violations
            .push(format!("panic for {start:?}, rate {rate}, acc {acc}"));
        return;
    };
    for (what, r) in [("assemble + analyze", analysed), ("step", stepped)] {
        let outcome = match &r {
            Ok(motion) => {
                let before = tally.violations.len();
                check_ok(m, motion, rate, tally, what);
                if tally.violations.len() > before
                    && std::env::var_os("KINEMATICS_FUZZ_DEBUG").is_some()
                {
                    println!("DEBUG {what}: m = {m:?}\n start = {start:?} rate {rate:e} acc {acc:e}\n motion = {motion:?}");
                }
                Ok(())
            }
            Err(e) => Err(e.clone()),
        };
        tally.record(what, &outcome);
    }
}

#[test]
fn four_bar_under_random_and_extreme_inputs() {
    let mut rng = Rng::new(0x00F0_0BA2);
    let mut tally = Tally::default();
    for k in 0..cases() {
        let mut m = FourBar {
            a: value(&mut rng, 0.01, 0.2),
            b: value(&mut rng, 0.01, 0.3),
            c: value(&mut rng, 0.01, 0.3),
            d: value(&mut rng, 0.01, 0.3),
            p: value(&mut rng, 0.0, 0.2),
            beta: value(&mut rng, -3.0, 3.0),
        };
        let mut start = FourBarCoords {
            phi: value(&mut rng, -7.0, 7.0),
            th3: value(&mut rng, -7.0, 7.0),
            th4: value(&mut rng, -7.0, 7.0),
        };
        if k % 2 == 0 {
            // Half the cases close at a random pose: the ground link from
            // the others (D on the x axis needs the loop's y to vanish, so
            // the rocker angle follows), and a guess near it.
            let (phi, th3) = (rng.angle(), rng.angle());
            let y = m.a * phi.sin() + m.b * th3.sin();
            if (y / m.c).abs() < 1.0 {
                let th4 = (y / m.c).asin();
                m.d = m.a * phi.cos() + m.b * th3.cos() - m.c * th4.cos();
                let near = rng.range(0.0, 0.3) * if rng.unit() < 0.1 { 10.0 } else { 1.0 };
                start = FourBarCoords {
                    phi,
                    th3: th3 + near * rng.range(-1.0, 1.0),
                    th4: th4 + near * rng.range(-1.0, 1.0),
                };
            }
        }
        let (rate, acc) = (value(&mut rng, -50.0, 50.0), value(&mut rng, -500.0, 500.0));
        exercise(&m, &start, rate, acc, &mut tally);
    }
    tally.report("four-bar");
}

#[test]
fn slider_crank_under_random_and_extreme_inputs() {
    let mut rng = Rng::new(0x0051_1DE2);
    let mut tally = Tally::default();
    for k in 0..cases() {
        let mut m = SliderCrank {
            a: value(&mut rng, 0.01, 0.2),
            b: value(&mut rng, 0.01, 0.5),
            e: value(&mut rng, -0.1, 0.1),
        };
        let mut start = SliderCrankCoords {
            phi: value(&mut rng, -7.0, 7.0),
            th: value(&mut rng, -7.0, 7.0),
            x: value(&mut rng, -0.5, 0.7),
        };
        if k % 2 == 0 {
            // A closing pose: the offset from the others, a guess near it.
            let (phi, th) = (rng.angle(), rng.angle());
            m.e = m.a * phi.sin() + m.b * th.sin();
            let x = m.a * phi.cos() + m.b * th.cos();
            let near = rng.range(0.0, 0.3);
            start = SliderCrankCoords {
                phi,
                th: th + near * rng.range(-1.0, 1.0),
                x: x + near * m.b * rng.range(-1.0, 1.0),
            };
        }
        let (rate, acc) = (value(&mut rng, -50.0, 50.0), value(&mut rng, -500.0, 500.0));
        exercise(&m, &start, rate, acc, &mut tally);
    }
    tally.report("slider-crank");
}

#[test]
fn watt_six_bar_under_random_and_extreme_inputs() {
    let mut rng = Rng::new(0x6BA2);
    let mut tally = Tally::default();
    for k in 0..cases() {
        let mut m = Watt {
            a: value(&mut rng, 0.01, 0.1),
            b: value(&mut rng, 0.05, 0.2),
            c: value(&mut rng, 0.05, 0.2),
            d: value(&mut rng, 0.05, 0.2),
            e: value(&mut rng, 0.02, 0.2),
            gamma: value(&mut rng, -3.0, 3.0),
            f: value(&mut rng, 0.05, 0.2),
            g: value(&mut rng, 0.05, 0.2),
            gx: value(&mut rng, -0.2, 0.3),
            gy: value(&mut rng, -0.2, 0.2),
        };
        let mut start = WattCoords {
            phi: value(&mut rng, -7.0, 7.0),
            th3: value(&mut rng, -7.0, 7.0),
            th4: value(&mut rng, -7.0, 7.0),
            th5: value(&mut rng, -7.0, 7.0),
            th6: value(&mut rng, -7.0, 7.0),
        };
        if k % 2 == 0 {
            // A closing pose: the ground link of the first loop and the
            // output pivot G from the others, a guess near it.
            let [phi, th3, th5, th6] = [rng.angle(), rng.angle(), rng.angle(), rng.angle()];
            let y = m.a * phi.sin() + m.b * th3.sin();
            if (y / m.c).abs() < 1.0 {
                let th4 = (y / m.c).asin();
                m.d = m.a * phi.cos() + m.b * th3.cos() - m.c * th4.cos();
                let t = th4 + m.gamma;
                m.gx = m.d + m.e * t.cos() + m.f * th5.cos() - m.g * th6.cos();
                m.gy = m.e * t.sin() + m.f * th5.sin() - m.g * th6.sin();
                let near = rng.range(0.0, 0.2);
                let mut jitter = || near * rng.range(-1.0, 1.0);
                start = WattCoords {
                    phi,
                    th3: th3 + jitter(),
                    th4: th4 + jitter(),
                    th5: th5 + jitter(),
                    th6: th6 + jitter(),
                };
            }
        }
        let (rate, acc) = (value(&mut rng, -50.0, 50.0), value(&mut rng, -500.0, 500.0));
        exercise(&m, &start, rate, acc, &mut tally);
    }
    tally.report("Watt six-bar");
}

#[test]
fn rssr_under_random_and_extreme_inputs() {
    let mut rng = Rng::new(0x7552);
    let mut tally = Tally::default();
    for k in 0..cases() {
        let mut m = Rssr {
            a: value(&mut rng, 0.02, 0.2),
            b: value(&mut rng, 0.1, 0.5),
            c: value(&mut rng, 0.05, 0.4),
            d: value(&mut rng, 0.1, 0.5),
        };
        let mut start = RssrCoords {
            phi: value(&mut rng, -7.0, 7.0),
            psi: value(&mut rng, -7.0, 7.0),
        };
        if k % 2 == 0 {
            // A closing pose: the coupler length from the others (a toggle
            // now and then: ψ = 0 or π), a guess near it.
            let phi = rng.angle();
            let psi = if rng.unit() < 0.05 { 1e-9 } else { rng.angle() };
            let a = Vector3::new(-m.a * phi.cos(), 0.0, m.a * phi.sin());
            let b = Vector3::new(-m.d - m.c * psi.cos(), m.c * psi.sin(), 0.0);
            m.b = (b - a).norm();
            start = RssrCoords {
                phi,
                psi: psi + rng.range(-0.3, 0.3),
            };
        }
        let (rate, acc) = (value(&mut rng, -50.0, 50.0), value(&mut rng, -500.0, 500.0));
        exercise(&m, &start, rate, acc, &mut tally);
    }
    tally.report("RSSR");
}

/// The arm's tool point by its own forward kinematics: the products of the
/// elementary matrices written out.
fn arm_tool_point(m: &SixAxisArm, q: &[f64; 6]) -> Vector3<f64> {
    let rot = |axis: usize, t: f64| {
        let (s, c) = t.sin_cos();
        let mut r = Matrix4::identity();
        let (i, j) = [(1, 2), (2, 0), (0, 1)][axis];
        r[(i, i)] = c;
        r[(j, j)] = c;
        r[(i, j)] = -s;
        r[(j, i)] = s;
        r
    };
    let tr = |x: f64, y: f64, z: f64| {
        let mut t = Matrix4::identity();
        t[(0, 3)] = x;
        t[(1, 3)] = y;
        t[(2, 3)] = z;
        t
    };
    let upper = tr(0.0, 0.0, m.d1) * rot(2, q[0]) * rot(1, q[1]);
    let fore = upper * tr(m.a2, 0.0, 0.0) * rot(1, q[2]) * rot(0, q[3]);
    let tool = fore * tr(m.a3, 0.0, 0.0) * rot(1, q[4]) * tr(m.d5, 0.0, 0.0) * rot(0, q[5]);
    let p = tool * Vector4::new(m.d6, 0.0, 0.0, 1.0);
    Vector3::new(p.x, p.y, p.z)
}

#[test]
fn six_axis_arm_under_random_and_extreme_inputs() {
    let mut rng = Rng::new(0x0A23);
    let mut tally = Tally::default();
    let options = kinematics_core::Options::DEFAULT;
    for _ in 0..cases() {
        let m = SixAxisArm {
            d1: value(&mut rng, 0.1, 0.6),
            a2: value(&mut rng, 0.1, 0.6),
            a3: value(&mut rng, 0.1, 0.6),
            d5: value(&mut rng, 0.0, 0.2),
            d6: value(&mut rng, 0.0, 0.2),
        };
        let q: [f64; 6] = std::array::from_fn(|_| value(&mut rng, -4.0, 4.0));
        let rates: [f64; 6] = std::array::from_fn(|_| value(&mut rng, -5.0, 5.0));
        let accs: [f64; 6] = std::array::from_fn(|_| value(&mut rng, -50.0, 50.0));
        let pose = SixAxisArmCoords::from(q);
        let run = catch_unwind(AssertUnwindSafe(|| {
            m.analyze_with(&pose, rates, accs, &options)
        }));
        let Ok(r) = run else {
            tally.violations.push(format!("panic at {pose:?}"));
            continue;
        };
        let outcome =
            match &r {
                Ok(s) => {
                    let p = s.point_tcp();
                    let all_finite =
                        p.position
                            .iter()
                            .chain(&p.velocity)
                            .chain(&p.acceleration)
                            .chain(s.frames.iter().flat_map(|f| {
                                f.angular_velocity.iter().chain(&f.angular_acceleration)
                            }))
                            .all(|v| v.is_finite());
                    if all_finite {
                        let exact = arm_tool_point(&m, &q);
                        let size = m.d1.abs() + m.a2.abs() + m.a3.abs() + m.d5.abs() + m.d6.abs();
                        let gap = (p.position - exact).amax();
                        if !(gap <= 1e-12 * size) {
                            tally
                                .violations
                                .push(format!("tool point off its forward kinematics by {gap:e}"));
                        }
                    } else {
                        tally
                            .violations
                            .push(format!("Ok holding a NaN or an infinity at {pose:?}"));
                    }
                    Ok(())
                }
                Err(e) => Err(e.clone()),
            };
        tally.record("analyze", &outcome);
    }
    tally.report("six-axis arm");
}

/// The largest relative residual max_i |Φ_i| / S_i of a pose, by the
/// equations and term scales written out here.
fn relative_gap<M: Model>(m: &M, q: &M::Coords) -> f64 {
    let (s, _) = m.scales();
    m.gap(q)
        .iter()
        .zip(&s)
        .fold(0.0f64, |a, (g, s)| a.max((g / s).abs()))
}

/// 64 units of round-off: the bound every `Ok` pose of `assemble` and of
/// `step` meets, at every scale (see `guide::failures`).
const CLOSED: f64 = 64.0 * f64::EPSILON;

/// `assemble` and `step` of `m` from `start` (a guess near a closing
/// pose): each `Ok` pose within [`CLOSED`]; returns how many were `Ok`.
fn closes_at_round_off<M: Model>(m: &M, start: &M::Coords, what: &str) -> usize {
    let options = kinematics_core::Options::DEFAULT;
    let assembled = m
        .assemble_with(start, &options)
        .map(|q| relative_gap(m, &q));
    let stepped = m
        .step_slices(start, &[1.0], &[0.0], &options)
        .map(|s| relative_gap(m, s.q()));
    let mut ok = 0;
    for (how, r) in [("assemble", assembled), ("step", stepped)] {
        if let Ok(gap) = r {
            assert!(
                gap <= CLOSED,
                "{what}: {how} closes to {gap:e} (> 64 ε) for {m:?} from {start:?}"
            );
            ok += 1;
        }
    }
    ok
}

/// Scales by 10^k, k uniform in [78, 100] (or, for `tiny`, in [−100, −78]).
fn extreme_scale(rng: &mut Rng, tiny: bool) -> f64 {
    let k = rng.range(78.0, 100.0);
    10f64.powf(if tiny { -k } else { k })
}

#[test]
fn step_and_assemble_close_to_the_same_bound_at_extreme_scales() {
    let mut rng = Rng::new(0x5CA1E);
    let (mut ok, mut tried) = (0, 0);
    for k in 0..400 {
        let s = extreme_scale(&mut rng, k % 4 == 3);
        // A four-bar closing at a random pose (its ground link from the
        // others), scaled, from a guess 0.05 rad off.
        let (phi, th3) = (rng.angle(), rng.angle());
        let (a, b, c) = (
            rng.range(0.02, 0.2),
            rng.range(0.05, 0.3),
            rng.range(0.05, 0.3),
        );
        let y = a * phi.sin() + b * th3.sin();
        if (y / c).abs() < 0.95 {
            let th4 = (y / c).asin();
            let d = a * phi.cos() + b * th3.cos() - c * th4.cos();
            let m = FourBar {
                a: a * s,
                b: b * s,
                c: c * s,
                d: d * s,
                p: 0.1 * s,
                beta: 0.3,
            };
            let start = FourBarCoords {
                phi,
                th3: th3 + 0.05,
                th4: th4 - 0.05,
            };
            ok += closes_at_round_off(&m, &start, "four-bar");
            tried += 2;
        }
        // A slider-crank, its slider from the crank and rod.
        let (a, b) = (rng.range(0.02, 0.1), rng.range(0.15, 0.4));
        let e = rng.range(-0.05, 0.05);
        let th = ((e - a * phi.sin()) / b).asin();
        let x = a * phi.cos() + b * th.cos();
        let m = SliderCrank {
            a: a * s,
            b: b * s,
            e: e * s,
        };
        let start = SliderCrankCoords {
            phi,
            th: th + 0.05,
            x: x * s * 1.01,
        };
        ok += closes_at_round_off(&m, &start, "slider-crank");
        // An RSSR at the textbook's proportions, its coupler from a pose.
        let psi = rng.angle();
        let (a, c, d) = (0.102, 0.254, 0.315);
        let pa = Vector3::new(-a * phi.cos(), 0.0, a * phi.sin());
        let pb = Vector3::new(-d - c * psi.cos(), c * psi.sin(), 0.0);
        let m = Rssr {
            a: a * s,
            b: (pb - pa).norm() * s,
            c: c * s,
            d: d * s,
        };
        let start = RssrCoords {
            phi,
            psi: psi + 0.05,
        };
        ok += closes_at_round_off(&m, &start, "RSSR");
        tried += 4;
    }
    // Most calls succeed: the bound is not met by failing.
    println!("{ok} of {tried} calls Ok, every one within 64 ε");
    assert!(ok * 10 >= tried * 9, "{ok} of {tried} Ok");
}
