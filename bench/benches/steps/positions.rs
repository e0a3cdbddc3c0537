//! Positions only: a turn of 3600 poses (assembly from the previous pose,
//! no velocities or accelerations) through a stepper's `pose`, a sweep of
//! poses and, for a mechanism without closed forms, `assemble`; against
//! the expert's positions-only Newton loops (`hand::m1_pose` …) and the
//! full stepper.

use kinematics_core::sweep::SweepBuilder;
use kinematics_core::Options;

use crate::models::{m1, m2, m3, m5, M1, M2, M3, M5};
use crate::{angle, data, hand, thread_cpu_ns, STEPS};

/// A turn of positions: returns a checksum of the unknowns.
type Turn = Box<dyn FnMut() -> f64>;

/// The unknowns of M5 at φ = 0 (y > 0: the slider above the vertex).
const M5_START: [f64; 2] = [1.2, 0.19];

/// The variants of one mechanism: (name, turn, whether its checksum is
/// that of the positions).
fn variants(mech: &str) -> Vec<(&'static str, Turn, bool)> {
    macro_rules! closed {
        ($model:expr, $coords:ty, $start:expr, $ty:ty, $sum:expr, $rates:expr) => {{
            let start = <$coords>::from($start);
            let full: Turn = Box::new(move || {
                let m = data($model);
                let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
                let mut pose = start;
                let mut sum = 0.0;
                for k in 0..STEPS {
                    pose.phi = angle(k);
                    let s = stepper.step(&pose, $rates.0, $rates.1).expect("step");
                    pose = s.q;
                    sum += $sum(&pose);
                }
                sum
            });
            let pose: Turn = Box::new(move || {
                let m = data($model);
                let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
                let mut pose = start;
                let mut sum = 0.0;
                for k in 0..STEPS {
                    pose.phi = angle(k);
                    pose = stepper.pose(&pose).expect("pose").q;
                    sum += $sum(&pose);
                }
                sum
            });
            let swept: Turn = Box::new(move || {
                let m = data($model);
                SweepBuilder::new(&m, <$ty>::PHI, &start)
                    .turn()
                    .steps(STEPS)
                    .poses()
                    .map(|s| $sum(&s.expect("no stop").pose.q))
                    .sum()
            });
            vec![
                ("stepper (full step)", full, false),
                ("stepper.pose", pose, true),
                ("sweep of poses", swept, true),
            ]
        }};
    }
    match mech {
        "M1 four-bar" => {
            let mut v = closed!(
                M1,
                m1::FourBarCoords,
                [0.0, 1.0, 1.6],
                m1::FourBar,
                |q: &m1::FourBarCoords| q.th3 + q.th4,
                (10.0, 2.0)
            );
            v.push((
                "hand-written positions",
                Box::new(|| {
                    let m = data(M1);
                    let mut st = hand::Carried::new([1.0, 1.6]);
                    (0..STEPS)
                        .map(|k| hand::m1_pose(&m, angle(k), &mut st))
                        .sum()
                }),
                true,
            ));
            v
        }
        "M2 RSSR" => {
            let mut v = closed!(
                M2,
                m2::RssrCoords,
                [0.0, 1.2],
                m2::Rssr,
                |q: &m2::RssrCoords| q.psi,
                (8.0 * std::f64::consts::PI, 0.0)
            );
            v.push((
                "hand-written positions",
                Box::new(|| {
                    let m = data(M2);
                    let mut st = hand::Carried::new([1.2]);
                    (0..STEPS)
                        .map(|k| hand::m2_pose(&m, angle(k), &mut st))
                        .sum()
                }),
                true,
            ));
            v
        }
        "M3 Watt six-bar" => {
            let mut v = closed!(
                M3,
                m3::WattCoords,
                [0.0, 1.0, 1.6, 0.3, 1.9],
                m3::Watt,
                |q: &m3::WattCoords| q.th3 + q.th4 + q.th5 + q.th6,
                (10.0, 2.0)
            );
            v.push((
                "hand-written positions",
                Box::new(|| {
                    let m = data(M3);
                    let mut th = [1.0, 1.6, 0.3, 1.9];
                    (0..STEPS)
                        .map(|k| hand::m3_pose(&m, angle(k), &mut th))
                        .sum()
                }),
                true,
            ));
            v
        }
        _ => {
            let mut v = closed!(
                M5,
                m5::CurvedSliderCoords,
                [0.0, M5_START[0], M5_START[1]],
                m5::CurvedSlider,
                |q: &m5::CurvedSliderCoords| q.th + q.y,
                (10.0, 2.0)
            );
            v.push((
                "assemble",
                Box::new(|| {
                    let m = data(M5);
                    let mut pose = m5::CurvedSliderCoords::from([0.0, M5_START[0], M5_START[1]]);
                    let mut sum = 0.0;
                    for k in 0..STEPS {
                        pose.phi = angle(k);
                        pose = m.assemble(&pose).expect("assembles");
                        sum += pose.th + pose.y;
                    }
                    sum
                }),
                true,
            ));
            v
        }
    }
}

const MECHANISMS: [&str; 4] = [
    "M1 four-bar",
    "M2 RSSR",
    "M3 Watt six-bar",
    "M5 slider in a curved guide",
];

/// The positions table: 41 interleaved rounds, each timing one turn of
/// every variant (thread CPU time); per variant the median ratio to the
/// reference of the same round (the hand-written positions, or for M5 the
/// full stepper) and the range of the middle 80 % of rounds. Before
/// timing, the positions' checksums are checked against each other.
pub fn table() -> String {
    const ROUNDS: usize = 41;
    let mut out = String::from(
        "Positions only (a turn of 3600 poses from the previous pose; 41 interleaved rounds, \
         thread CPU time): median ratio to the first column's reference in the same round, \
         and the range of the middle 80 % of rounds. M5, a slider in a curved guide \
         (x = h + k y²), has no closed form: Newton–Raphson on the whole system.\n\n\
         | mechanism | reference | stepper (full step) | stepper.pose | sweep of poses | assemble |\n\
         |---|---|---|---|---|---|\n",
    );
    for mech in MECHANISMS {
        let mut v = variants(mech);
        // The positions agree (to the stepping tolerance).
        let sums: Vec<f64> = v.iter_mut().filter(|x| x.2).map(|(_, f, _)| f()).collect();
        for s in &sums {
            let rel = (s - sums[0]).abs() / sums[0].abs().max(1.0);
            assert!(rel < 1e-8, "{mech}: positions' checksums {sums:?}");
        }
        let reference = v
            .iter()
            .position(|x| x.0 == "hand-written positions")
            .unwrap_or(0);
        let mut ratios: Vec<Vec<f64>> = vec![Vec::new(); v.len()];
        for _ in 0..ROUNDS {
            let mut t = vec![0.0; v.len()];
            for (i, (_, f, _)) in v.iter_mut().enumerate() {
                let t0 = thread_cpu_ns();
                std::hint::black_box(f());
                t[i] = thread_cpu_ns() - t0;
            }
            for i in 0..v.len() {
                ratios[i].push(t[i] / t[reference]);
            }
        }
        let cell = |name: &str| {
            let Some(i) = v.iter().position(|x| x.0 == name) else {
                return "–".to_string();
            };
            let mut r = ratios[i].clone();
            r.sort_by(f64::total_cmp);
            let (lo, mid, hi) = (r[ROUNDS / 10], r[ROUNDS / 2], r[ROUNDS - 1 - ROUNDS / 10]);
            format!("{mid:.2}× ({lo:.2}–{hi:.2})")
        };
        out += &format!(
            "| {mech} | {} | {} | {} | {} | {} |\n",
            v[reference].0,
            cell("stepper (full step)"),
            cell("stepper.pose"),
            cell("sweep of poses"),
            cell("assemble"),
        );
    }
    out
}
