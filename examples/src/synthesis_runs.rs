//! The literature's path-generation problems solved from seeded random
//! starting designs, shared by the synthesis example, its tests and the
//! synthesis benchmark.

use super::literature::{MORGAN_WAMPLER_7, NINE_POINTS};
use super::{FourBar, FourBarCoords, FourBarModes, PlacedFourBar, PlacedFourBarModes};
use kinematics_core::closed::{AllModes, ModeSet};
use kinematics_core::synthesis::{Synthesis, Synthesized};
use kinematics_core::Error;
use std::f64::consts::{PI, TAU};

/// A seeded generator of uniform numbers (xorshift64*).
#[derive(Debug, Clone)]
pub struct Uniform(u64);

impl Uniform {
    /// The generator for `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// A number in [lo, hi).
    pub fn in_range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        #[allow(clippy::cast_precision_loss)]
        let u = bits as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

/// Driver values evenly spaced over a turn from `from`.
#[must_use]
pub fn evenly(from: f64, n: usize) -> Vec<f64> {
    #[allow(clippy::cast_precision_loss)]
    (0..n).map(|j| from + TAU * j as f64 / n as f64).collect()
}

/// A design drawn by `draw` with a random assembly mode of `modes` and
/// a random start angle φ₀, drawn again until it assembles at the `n`
/// driver values spaced evenly over a turn from φ₀; with its pose at φ₀
/// and its mode.
fn drawn<M, C, Modes: ModeSet>(
    seed: u64,
    n: usize,
    mut draw: impl FnMut(&mut Uniform) -> M,
    assemble: impl Fn(&M, f64, &Modes) -> Result<C, Error>,
) -> (M, C, Modes) {
    let mut u = Uniform::new(seed);
    loop {
        let m = draw(&mut u);
        let mode = AllModes::<Modes>::new()
            .nth(usize::from(u.in_range(0.0, 1.0) < 0.5))
            .unwrap_or_else(Modes::all_plus);
        let phi0 = u.in_range(-PI, PI);
        let fits = evenly(phi0, n)
            .iter()
            .all(|&phi| assemble(&m, phi, &mode).is_ok());
        if let (true, Ok(start)) = (fits, assemble(&m, phi0, &mode)) {
            return (m, start, mode);
        }
    }
}

/// A random starting design for Morgan and Wampler's Problem 7 (ground
/// pivots (0, 0) and (1, 0); a, b, c, p in [0.2, 2], β in [−π, π], a
/// random assembly mode), drawn again until it assembles at its
/// initial driver values; with its start pose and its mode.
#[must_use]
pub fn morgan_wampler_start(seed: u64) -> (FourBar, FourBarCoords, FourBarModes) {
    let draw = |u: &mut Uniform| FourBar {
        a: u.in_range(0.2, 2.0),
        b: u.in_range(0.2, 2.0),
        c: u.in_range(0.2, 2.0),
        d: 1.0,
        p: u.in_range(0.2, 2.0),
        beta: u.in_range(-PI, PI),
    };
    drawn(seed, MORGAN_WAMPLER_7.len(), draw, |m, phi, modes| {
        m.assemble_in(phi, modes)
    })
}

/// Morgan and Wampler's Problem 7 by Levenberg–Marquardt from the
/// starting design of `seed`: a, b, c, p, β and the five crank angles
/// free (initially evenly spaced over a turn from the start pose's),
/// lengths within [0.01, 10].
///
/// # Errors
/// As [`Synthesis::run`].
pub fn morgan_wampler(seed: u64) -> Result<Synthesized<FourBar>, Error> {
    let (m, start, _) = morgan_wampler_start(seed);
    let mut s = Synthesis::path(&m, FourBar::PHI, "P", &MORGAN_WAMPLER_7, &start)
        .vary(&["a", "b", "c", "p", "beta"])
        .driver_guesses(&evenly(start.phi, MORGAN_WAMPLER_7.len()));
    for name in ["a", "b", "c", "p"] {
        s = s.bounds(name, 0.01, 10.0);
    }
    s.run()
}

/// E = Σ|P(φ_j) − t_j|² of Morgan and Wampler's Problem 7 for the
/// unknowns `x` = (a, b, c, p, β, φ₁ … φ₅) in the modes `modes`, for a
/// derivative-free method; 10⁶ where the design does not assemble.
#[must_use]
pub fn morgan_wampler_objective(x: &[f64], modes: &FourBarModes) -> f64 {
    let m = FourBar {
        a: x[0],
        b: x[1],
        c: x[2],
        d: 1.0,
        p: x[3],
        beta: x[4],
    };
    let mut e = 0.0;
    for (j, t) in MORGAN_WAMPLER_7.iter().enumerate() {
        let Ok(pose) = m.assemble_in(x[5 + j], modes) else {
            return 1e6;
        };
        let p = m.positions(&pose).P;
        e += (p.x - t[0]).powi(2) + (p.y - t[1]).powi(2);
    }
    e
}

/// A random starting design for the nine-point problem (A in
/// [−1, 3] × [−2, 2], θ0 and β in [−π, π], d, a, b, c, p in [0.2, 2.5],
/// a random assembly mode), drawn again until it assembles at its
/// initial driver values; with its start pose and its mode.
#[must_use]
pub fn nine_point_start(
    seed: u64,
) -> (
    PlacedFourBar,
    super::PlacedFourBarCoords,
    PlacedFourBarModes,
) {
    let draw = |u: &mut Uniform| PlacedFourBar {
        x0: u.in_range(-1.0, 3.0),
        y0: u.in_range(-2.0, 2.0),
        theta0: u.in_range(-PI, PI),
        d: u.in_range(0.2, 2.5),
        a: u.in_range(0.2, 2.5),
        b: u.in_range(0.2, 2.5),
        c: u.in_range(0.2, 2.5),
        p: u.in_range(0.2, 2.5),
        beta: u.in_range(-PI, PI),
    };
    drawn(seed, NINE_POINTS.len(), draw, |m, phi, modes| {
        m.assemble_in(phi, modes)
    })
}

/// The nine-point problem by Levenberg–Marquardt from the starting
/// design of `seed`: all nine dimensions and the nine crank angles
/// free (initially evenly spaced over a turn from the start pose's),
/// the pivot A within [−10, 10]², lengths within [0.01, 20], at most
/// 1000 residual evaluations per unknown.
///
/// # Errors
/// As [`Synthesis::run`].
pub fn nine_point(seed: u64) -> Result<Synthesized<PlacedFourBar>, Error> {
    let (m, start, _) = nine_point_start(seed);
    let mut s = Synthesis::path(&m, PlacedFourBar::PHI, "P", &NINE_POINTS, &start)
        .driver_guesses(&evenly(start.phi, NINE_POINTS.len()));
    for name in ["x0", "y0"] {
        s = s.bounds(name, -10.0, 10.0);
    }
    for name in ["d", "a", "b", "c", "p"] {
        s = s.bounds(name, 0.01, 20.0);
    }
    // Near its best fit on one branch the problem converges slowly
    // (E falls from 1e-11 to 3.8e-12 over thousands of evaluations).
    s.patience(1000).run()
}

/// E of the nine-point problem for the unknowns `x` = (x0, y0, θ0, d,
/// a, b, c, p, β, φ₁ … φ₉) in the modes `modes`; 10⁶ where the design
/// does not assemble.
#[must_use]
pub fn nine_point_objective(x: &[f64], modes: &PlacedFourBarModes) -> f64 {
    let m = PlacedFourBar {
        x0: x[0],
        y0: x[1],
        theta0: x[2],
        d: x[3],
        a: x[4],
        b: x[5],
        c: x[6],
        p: x[7],
        beta: x[8],
    };
    let mut e = 0.0;
    for (j, t) in NINE_POINTS.iter().enumerate() {
        let Ok(pose) = m.assemble_in(x[9 + j], modes) else {
            return 1e6;
        };
        let p = m.positions(&pose).P;
        e += (p.x - t[0]).powi(2) + (p.y - t[1]).powi(2);
    }
    e
}
