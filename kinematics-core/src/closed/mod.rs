//! Closed-form solutions of the blocks of loop equations that have one.
//!
//! `mechanism!` splits the loop equations into diagonal blocks (each a group
//! of equations that fixes a group of unknowns once the earlier groups are
//! known) and recognises the blocks whose solution is exact: a planar dyad,
//! or one angle in an equation `a cos u + b sin u + c = 0`. For those it
//! calls the functions of this module instead of iterating, and needs no
//! guess: each such block has at most two real solutions, its two
//! [assembly modes](Mode). The block is written in the form the function
//! takes, with its coefficients (expressions of the parameters, the drivers
//! and the unknowns of earlier blocks) evaluated at run time:
//!
//! | function | block | form (e = (cos θ, sin θ)) |
//! |---|---|---|
//! | [`angle`] | one angle | a cos θ + b sin θ + c = 0 |
//! | [`circle_circle`] | RRR dyad: two angles | k + P e₀ + Q e₁ = 0 |
//! | [`circle_line`] | RRT dyad: an angle and a slider length | k + P e + λ v = 0 |
//! | [`slide`] | RTR dyad: a slider on a turning link | k + (P + λ W) e = 0 |
//! | [`line_line`] | TRT dyad: two slider lengths | k + λ₀ v₀ + λ₁ v₁ = 0 |
//! | [`linear`] | one length | a λ + c = 0 |
//!
//! The 2×2 matrices are row-major, one row per equation; column 0
//! multiplies cos θ and column 1 sin θ. P, Q and W must be similarities
//! (a rotation or reflection times a length, as for a link drawn as
//! `polar(l, θ + β)`), which the macro checks; then |P e| is the same for
//! every θ.
//!
//! Each function returns `Err(discriminant)` when the block has no real
//! solution: a negative discriminant means the links cannot close the loop
//! at these driver values (the mechanism is past a limit position); NaN or
//! zero means the block is degenerate there (coincident joints, parallel
//! sliders).
//!
//! ```
//! use kinematics_core::closed::{angle, Mode};
//! // cos θ + sin θ − 1 = 0: θ = 0 or θ = π/2.
//! let mut mode = Mode::Plus.sign();
//! let [c, s] = angle(1.0, 1.0, -1.0, &mut mode, || [1.0, 0.0]).unwrap();
//! assert!((s.atan2(c) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
//! let mut mode = Mode::Minus.sign();
//! let [c, s] = angle(1.0, 1.0, -1.0, &mut mode, || [1.0, 0.0]).unwrap();
//! assert!(s.atan2(c).abs() < 1e-15);
//! ```

// `!(x > 0.0)` is meant: it also catches a NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use core::f64::consts::{PI, TAU};
use core::fmt;

use crate::error::Error;

use crate::options::Options;

mod modes;
pub use modes::{AllModes, Assemblies, ModeSet};

/// How one diagonal block of a mechanism's loop equations is solved: the
/// entries of a mechanism's generated `BLOCKS` constant, in solve order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block {
    /// The block's unknowns.
    pub unknowns: &'static [&'static str],
    /// "closed form: …" with the form, or "Newton–Raphson".
    pub method: &'static str,
    /// Whether it has two assembly modes ([`Mode`]) to choose from.
    pub modes: bool,
}

impl Block {
    /// Whether the block is solved in closed form.
    #[must_use]
    pub fn is_closed_form(&self) -> bool {
        self.method.starts_with("closed form")
    }
}

impl fmt::Display for Block {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, u) in self.unknowns.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(u)?;
        }
        write!(f, ": {}", self.method)
    }
}

/// One of the two solutions of a closed-form block.
///
/// For a block with an angle solved from a cos θ + b sin θ + c = 0 (every
/// block but [`slide`] and the single-solution ones), with
/// R = √(a² + b²) and φ = atan2(b, a):
///
/// θ = φ ± acos(−c / R),
///
/// `Plus` taking the `+`: θ lies counter-clockwise of the direction φ,
/// sin(θ − φ) ≥ 0. For a dyad, φ is the direction of the line through the
/// dyad's two end joints as the block's equations see it, so the two modes
/// put the middle joint on either side of that line: the dyad's "elbow"
/// bends one way or the other. Which mode is the open and which the
/// crossed four-bar depends on how the loop is written; `assemble_all`
/// returns both. For [`slide`], `Plus` takes the larger root λ of the
/// slider length's quadratic.
///
/// The mode of a continuous motion does not change except through a
/// limit position, where the two solutions meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mode {
    /// The `+` solution.
    #[default]
    Plus,
    /// The `−` solution.
    Minus,
}

impl Mode {
    /// +1 for [`Mode::Plus`], −1 for [`Mode::Minus`].
    #[must_use]
    pub const fn sign(self) -> f64 {
        match self {
            Mode::Plus => 1.0,
            Mode::Minus => -1.0,
        }
    }

    /// The mode of a sign: `Minus` for a negative number, else `Plus`.
    #[must_use]
    pub fn from_sign(sign: f64) -> Self {
        if sign < 0.0 { Mode::Minus } else { Mode::Plus }
    }
}

/// The sign of `x` as ±1 (+1 for zero and NaN).
#[inline(always)]
fn sign(x: f64) -> f64 {
    if x < 0.0 { -1.0 } else { 1.0 }
}

/// A discriminant `d` computed from terms of size `size`: a value within
/// its rounding error (|d| ≤ 8 ε · size, either sign) is taken as 0, a
/// double root (the mechanism at a limit position to round-off). A
/// positive `d` of that size would split the root by about √ε, which the
/// data cannot tell from one root; its pose closes to round-off either
/// way, the residual being quadratic in the split.
#[inline(always)]
fn clamp(d: f64, size: f64) -> f64 {
    if d.abs() <= 8.0 * f64::EPSILON * size {
        0.0
    } else {
        d
    }
}

/// (cos θ, sin θ) of the solution of a cos θ + b sin θ + c = 0 in the mode
/// `*mode` (±1; see [`Mode`]):
///
/// cos θ = (−a c − σ b √Δ) / R², sin θ = (−b c + σ a √Δ) / R²,
///
/// with R² = a² + b², Δ = R² − c² and σ = `*mode`, which is exactly
/// θ = atan2(b, a) + σ acos(−c / R) without a trigonometric call. When
/// `*mode` is NaN, the mode is taken from the guess's (cos θ, sin θ) that
/// `guess` returns, as sign(a sin θ − b cos θ), and stored in `*mode`.
///
/// # Errors
/// `Err(Δ)` when Δ < 0 (no real solution: |c| > R); `Err(NaN)` when
/// R = 0 (the equation does not involve θ) or an input is not finite.
///
/// ```
/// use kinematics_core::closed::angle;
/// // 3 cos θ + 4 sin θ = 5 has one solution, at the edge of both modes.
/// let mut mode = 1.0;
/// let [c, s] = angle(3.0, 4.0, -5.0, &mut mode, || [1.0, 0.0]).unwrap();
/// assert!((c - 0.6).abs() < 1e-15 && (s - 0.8).abs() < 1e-15);
/// assert!(angle(3.0, 4.0, -5.1, &mut mode, || [1.0, 0.0]).is_err());
/// ```
#[inline(always)]
pub fn angle(
    a: f64,
    b: f64,
    c: f64,
    mode: &mut f64,
    guess: impl FnOnce() -> [f64; 2],
) -> Result<[f64; 2], f64> {
    let r2 = a * a + b * b;
    let disc = clamp(r2 - c * c, r2 + c * c);
    if !(disc >= 0.0 && r2 > 0.0 && r2.is_finite()) {
        return Err(if disc < 0.0 { disc } else { f64::NAN });
    }
    if mode.is_nan() {
        let [cg, sg] = guess();
        *mode = sign(a * sg - b * cg);
    }
    // 1/R² is computed beside the square root, not after it: one division
    // off the dependency chain.
    let inv = 1.0 / r2;
    let root = *mode * crate::math::sqrt(disc);
    Ok([(-a * c - b * root) * inv, (-b * c + a * root) * inv])
}

/// The RRR dyad: (cos θ₀, sin θ₀, cos θ₁, sin θ₁) solving
/// k + P e₀ + Q e₁ = 0 for similarities P and Q (PᵀP = p² I, QᵀQ = q² I).
///
/// Eliminating θ₁ by |Q e₁| = q gives |k + P e₀|² = q², that is
/// 2 (Pᵀk)·e₀ + |k|² + p² − q² = 0, an [`angle`] equation for θ₀ (whose
/// mode is `*mode`; when NaN, the mode whose solution is nearest the
/// guess's (cos θ₀, sin θ₀, cos θ₁, sin θ₁) that `guess` returns, in
/// (1 − cos Δθ₀) + (1 − cos Δθ₁), then stored); then e₁ = −Qᵀ (k + P e₀) / q², computed as that
/// vector normalised.
///
/// # Errors
/// As [`angle`]; `Err(NaN)` also when q = 0.
///
/// ```
/// use kinematics_core::closed::circle_circle;
/// // A four-bar a = 1, b = 2, c = 2.5, d = 3 at φ = 90°: with
/// // k = (a cos φ − d, a sin φ), the loop k + b e₃ − c e₄ = 0.
/// let (a, b, c, d, phi) = (1.0, 2.0, 2.5, 3.0, std::f64::consts::FRAC_PI_2);
/// let k = [a * phi.cos() - d, a * phi.sin()];
/// for mode in [1.0, -1.0] {
///     let mut mode = mode;
///     let [c3, s3, c4, s4] =
///         circle_circle(k, [[b, 0.0], [0.0, b]], [[-c, 0.0], [0.0, -c]], &mut mode, || [1.0, 0.0, 1.0, 0.0])
///             .unwrap();
///     assert!((k[0] + b * c3 - c * c4).abs() < 1e-15 && (k[1] + b * s3 - c * s4).abs() < 1e-15);
///     assert!((c3 * c3 + s3 * s3 - 1.0).abs() < 1e-15 && (c4 * c4 + s4 * s4 - 1.0).abs() < 1e-15);
/// }
/// ```
#[inline(always)]
pub fn circle_circle(
    k: [f64; 2],
    p: [[f64; 2]; 2],
    q: [[f64; 2]; 2],
    mode: &mut f64,
    guess: impl FnOnce() -> [f64; 4],
) -> Result<[f64; 4], f64> {
    if mode.is_nan() {
        let mut sigma = nearest_mode(k, p, q, &guess());
        let x = circle_circle_in(k, p, q, &mut sigma)?;
        *mode = sigma;
        return Ok(x);
    }
    circle_circle_in(k, p, q, mode)
}

/// The mode (±1) of [`circle_circle`] whose solution is nearest the
/// guess g = (cos θ₀, sin θ₀, cos θ₁, sin θ₁), least (1 − cos Δθ₀) +
/// (1 − cos Δθ₁): the one with the larger g · x. The two solutions differ
/// by a positive multiple of d = (d₀, d₁), with d₀ = (−b, a) in e₀ for
/// (a, b) = Pᵀk (half the coefficients of [`angle`]) and d₁ = −Qᵀ P d₀ / q²
/// in e₁ (linear in e₀),
/// so the plus mode is the nearer unless g · d < 0, tested as
/// q² g₀·d₀ + g₁·(q² d₁): no solution computed twice. Kept out of line in
/// unoptimised builds, where the stack of a model of hundreds of loops
/// solved in one function would hold every block's temporaries.
#[inline]
fn nearest_mode(k: [f64; 2], p: [[f64; 2]; 2], q: [[f64; 2]; 2], g: &[f64; 4]) -> f64 {
    let q2 = q[0][0] * q[0][0] + q[1][0] * q[1][0];
    let a = p[0][0] * k[0] + p[1][0] * k[1];
    let b = p[0][1] * k[0] + p[1][1] * k[1];
    let w = [p[0][1] * a - p[0][0] * b, p[1][1] * a - p[1][0] * b];
    let e1 = [
        q[0][0] * w[0] + q[1][0] * w[1],
        q[0][1] * w[0] + q[1][1] * w[1],
    ];
    sign(q2 * (g[1] * a - g[0] * b) - (g[2] * e1[0] + g[3] * e1[1]))
}

/// [`circle_circle`] in the mode `*mode` (±1).
#[inline(always)]
fn circle_circle_in(
    k: [f64; 2],
    p: [[f64; 2]; 2],
    q: [[f64; 2]; 2],
    mode: &mut f64,
) -> Result<[f64; 4], f64> {
    let p2 = p[0][0] * p[0][0] + p[1][0] * p[1][0];
    let q2 = q[0][0] * q[0][0] + q[1][0] * q[1][0];
    let a = 2.0 * (p[0][0] * k[0] + p[1][0] * k[1]);
    let b = 2.0 * (p[0][1] * k[0] + p[1][1] * k[1]);
    let c = k[0] * k[0] + k[1] * k[1] + p2 - q2;
    let [c0, s0] = angle(a, b, c, mode, || [1.0, 0.0])?;
    if !(q2 > 0.0) {
        return Err(f64::NAN);
    }
    let w = [
        k[0] + p[0][0] * c0 + p[0][1] * s0,
        k[1] + p[1][0] * c0 + p[1][1] * s0,
    ];
    // −Qᵀw = QᵀQ e₁, a vector of length q² (to rounding, when θ₀ is
    // accurate): normalised, so that (cos θ₁, sin θ₁) is a unit vector
    // even where cancellation made θ₀ inaccurate (the residual check
    // catches that).
    let x = -(q[0][0] * w[0] + q[1][0] * w[1]);
    let y = -(q[0][1] * w[0] + q[1][1] * w[1]);
    let r = unit_scale(x * x + y * y, q2)?;
    Ok([c0, s0, x * r, y * r])
}

/// 1/√m for m = |−Qᵀw|², which is q⁴ when the loop closes: one Newton
/// step for the inverse square root from 1/q², computed off the
/// dependency chain, r = (1/q²)(1 − δ/2) with δ = m/q⁴ − 1. Its relative
/// error, 3δ²/8 + O(δ³), is below 4e-17 for |δ| ≤ 1e-8; beyond that (an
/// inaccurate θ₀, which the residual check then catches) the square root
/// and division themselves.
#[inline(always)]
fn unit_scale(m: f64, q2: f64) -> Result<f64, f64> {
    let r0 = 1.0 / q2;
    let delta = m * r0 * r0 - 1.0;
    if delta.abs() <= 1e-8 {
        return Ok(r0 - 0.5 * r0 * delta);
    }
    let n = crate::math::sqrt(m);
    if !(n > 0.0) {
        return Err(f64::NAN);
    }
    Ok(1.0 / n)
}

/// The RRT dyad: (cos θ, sin θ, λ) solving k + P e + λ v = 0 (any P).
///
/// Projecting on v⊥ = (−v₁, v₀) eliminates λ: (Pᵀv⊥)·e + v⊥·k = 0, an
/// [`angle`] equation for θ (whose mode is `*mode`); then
/// λ = −v·(k + P e) / |v|².
///
/// # Errors
/// As [`angle`]; `Err(NaN)` also when v = 0.
///
/// ```
/// use kinematics_core::closed::circle_line;
/// // A slider-crank: crank end (0, 1), rod b = 2, slider on the x axis:
/// // k + b e − x (1, 0) = 0 with k = (0, 1).
/// let mut mode = 1.0;
/// let [c, s, x] = circle_line([0.0, 1.0], [[2.0, 0.0], [0.0, 2.0]], [-1.0, 0.0], &mut mode, || [1.0, -0.5])
///     .unwrap();
/// assert!((s + 0.5).abs() < 1e-15 && (x - 3f64.sqrt()).abs() < 1e-15);
/// # let _ = c;
/// ```
#[inline(always)]
pub fn circle_line(
    k: [f64; 2],
    p: [[f64; 2]; 2],
    v: [f64; 2],
    mode: &mut f64,
    guess: impl FnOnce() -> [f64; 2],
) -> Result<[f64; 3], f64> {
    let v2 = v[0] * v[0] + v[1] * v[1];
    if !(v2 > 0.0) {
        return Err(f64::NAN);
    }
    let a = -v[1] * p[0][0] + v[0] * p[1][0];
    let b = -v[1] * p[0][1] + v[0] * p[1][1];
    let c = -v[1] * k[0] + v[0] * k[1];
    let [c0, s0] = angle(a, b, c, mode, guess)?;
    let w = [
        k[0] + p[0][0] * c0 + p[0][1] * s0,
        k[1] + p[1][0] * c0 + p[1][1] * s0,
    ];
    Ok([c0, s0, -(v[0] * w[0] + v[1] * w[1]) / v2])
}

/// The RTR dyad: (cos θ, sin θ, λ) solving k + (P + λ W) e = 0 for
/// similarities P and W of the same kind (both rotations or both
/// reflections times a length, P possibly zero).
///
/// Then (P + λW)ᵀ(P + λW) = (p² + 2λ p·w + λ² w²) I with p·w the dot
/// product of their first columns, and |k| = |(P + λW) e| gives
/// w² λ² + 2 (p·w) λ + p² − |k|² = 0:
///
/// λ = (−p·w + σ √Δ) / w², Δ = (p·w)² − w² (p² − |k|²),
///
/// σ = `*mode` (when NaN, taken from the guess λ that `guess()[0]` returns
/// as sign(w² λ + p·w), and stored); then e = −(P + λW)ᵀ k / |P + λW|².
///
/// # Errors
/// `Err(Δ)` when Δ < 0 (the slider cannot reach); `Err(NaN)` when W = 0
/// or P + λW = 0 (the slider's pivot on the line of the link).
///
/// ```
/// use kinematics_core::closed::slide;
/// // An inverted slider-crank: crank end (1, 1) seen from the rocker's
/// // pivot; k − λ e = 0 with k = (1, 1): λ = ±√2, θ = 45°.
/// let mut mode = 1.0;
/// let [c, s, l] = slide([1.0, 1.0], [[0.0; 2]; 2], [[-1.0, 0.0], [0.0, -1.0]], &mut mode, || [1.0, 0.0])
///     .unwrap();
/// assert!((l - 2f64.sqrt()).abs() < 1e-15 && (c - s).abs() < 1e-15 && c > 0.0);
/// ```
#[inline(always)]
pub fn slide(
    k: [f64; 2],
    p: [[f64; 2]; 2],
    w: [[f64; 2]; 2],
    mode: &mut f64,
    guess: impl FnOnce() -> [f64; 2],
) -> Result<[f64; 3], f64> {
    let w2 = w[0][0] * w[0][0] + w[1][0] * w[1][0];
    let pw = p[0][0] * w[0][0] + p[1][0] * w[1][0];
    let p2 = p[0][0] * p[0][0] + p[1][0] * p[1][0];
    let k2 = k[0] * k[0] + k[1] * k[1];
    let disc = clamp(pw * pw - w2 * (p2 - k2), pw * pw + w2 * (p2 + k2));
    if !(disc >= 0.0 && w2 > 0.0 && w2.is_finite()) {
        return Err(if disc < 0.0 { disc } else { f64::NAN });
    }
    if mode.is_nan() {
        let [lg, _] = guess();
        *mode = sign(w2 * lg + pw);
    }
    let lambda = (-pw + *mode * crate::math::sqrt(disc)) / w2;
    let m = [
        [p[0][0] + lambda * w[0][0], p[0][1] + lambda * w[0][1]],
        [p[1][0] + lambda * w[1][0], p[1][1] + lambda * w[1][1]],
    ];
    let x = -(m[0][0] * k[0] + m[1][0] * k[1]);
    let y = -(m[0][1] * k[0] + m[1][1] * k[1]);
    let n = crate::math::sqrt(x * x + y * y);
    if !(n > 0.0) {
        return Err(f64::NAN);
    }
    Ok([x / n, y / n, lambda])
}

/// The TRT dyad: (λ₀, λ₁) solving k + λ₀ v₀ + λ₁ v₁ = 0 by Cramer's rule.
/// One solution.
///
/// # Errors
/// `Err(NaN)` when v₀ and v₁ are parallel.
///
/// ```
/// use kinematics_core::closed::line_line;
/// let [l0, l1] = line_line([-1.0, -2.0], [1.0, 0.0], [0.0, 1.0]).unwrap();
/// assert_eq!((l0, l1), (1.0, 2.0));
/// ```
#[inline(always)]
pub fn line_line(k: [f64; 2], v0: [f64; 2], v1: [f64; 2]) -> Result<[f64; 2], f64> {
    let det = v0[0] * v1[1] - v0[1] * v1[0];
    if det == 0.0 || !det.is_finite() {
        return Err(f64::NAN);
    }
    Ok([
        (-k[0] * v1[1] + k[1] * v1[0]) / det,
        (-v0[0] * k[1] + v0[1] * k[0]) / det,
    ])
}

/// λ solving a λ + c = 0. One solution.
///
/// # Errors
/// `Err(NaN)` when a = 0.
///
/// ```
/// assert_eq!(kinematics_core::closed::linear(2.0, -3.0), Ok(1.5));
/// ```
#[inline(always)]
pub fn linear(a: f64, c: f64) -> Result<f64, f64> {
    if a == 0.0 || !a.is_finite() {
        return Err(f64::NAN);
    }
    Ok(-c / a)
}

/// The angle atan2(`s`, `c`) + 2πn nearest `reference` (the guess, or the
/// previous pose), so that a joint angle stays continuous over a sweep of
/// several turns. A non-finite `reference` gives the angle in (−π, π].
/// Beyond 4096 rad, where the angle's own rounding (10⁻¹² rad) would no
/// longer match `c` and `s`, they are recomputed from the returned angle.
///
/// ```
/// use kinematics_core::closed::near;
/// let turn = std::f64::consts::TAU;
/// let (mut c, mut s) = (1.0, 0.0);
/// assert!((near(&mut c, &mut s, turn + 0.1) - turn).abs() < 1e-15);
/// assert_eq!(near(&mut c, &mut s, f64::NAN), 0.0);
/// ```
#[inline(always)]
#[must_use]
pub fn near(c: &mut f64, s: &mut f64, reference: f64) -> f64 {
    let theta = crate::math::atan2(*s, *c);
    let d = reference - theta;
    if d.abs() <= PI || !d.is_finite() {
        return theta;
    }
    let shifted = theta + TAU * crate::math::round(d / TAU);
    if shifted.abs() > 4096.0 {
        (*s, *c) = crate::math::sin_cos(shifted);
    }
    shifted
}

/// The largest change of a driver angle (rad) that [`carried_sin_cos`]
/// rotates by; beyond it the cosine and sine are computed afresh. The
/// run-time models' machine code takes the same rule.
pub const CARRIED_STEP: f64 = 0.0625;

/// The coefficients of sin Δ = Δ − Δ³ (c₀ − Δ² (c₁ − Δ² (c₂ − Δ² c₃))):
/// 1/3!, 1/5!, 1/7!, 1/9!.
pub const SIN_SERIES: [f64; 4] = [1.0 / 6.0, 1.0 / 120.0, 1.0 / 5040.0, 1.0 / 362_880.0];

/// The coefficients of 1 − cos Δ = Δ² (c₀ − Δ² (c₁ − Δ² (c₂ − Δ² (c₃ −
/// Δ² c₄)))): 1/2!, 1/4!, 1/6!, 1/8!, 1/10!.
pub const VERS_SERIES: [f64; 5] = [
    0.5,
    1.0 / 24.0,
    1.0 / 720.0,
    1.0 / 40_320.0,
    1.0 / 3_628_800.0,
];

/// The cosine and sine of a driver angle φ, from those of the previous
/// step's value φ₀ held in `carried` = (cos φ₀, sin φ₀, φ₀): with
/// Δ = φ − φ₀,
///
/// cos φ = cos φ₀ − (cos φ₀ (1 − cos Δ) + sin φ₀ sin Δ),
/// sin φ = sin φ₀ − (sin φ₀ (1 − cos Δ) − cos φ₀ sin Δ),
///
/// with sin Δ and 1 − cos Δ by their series (truncation below 2e-21 for
/// |Δ| ≤ 1/16), so no trigonometric function is called. Each rotation adds
/// at most about one unit in the last place; a stepper sets φ₀ to NaN every
/// 16 steps, and then, as for |Δ| > 1/16, (cos φ, sin φ) are computed
/// afresh. On return `carried` holds (cos φ, sin φ, φ).
///
/// ```
/// use kinematics_core::closed::carried_sin_cos;
/// let mut carried = [f64::NAN; 3];
/// let mut worst = 0.0f64;
/// for k in 0i32..16 {
///     // Steps of 0.01 rad, then of 0.06.
///     let phi = 1.0 + 0.01 * f64::from(k) + 0.05 * f64::from((k - 8).max(0));
///     let [c, s] = carried_sin_cos(phi, &mut carried);
///     worst = worst.max((c - phi.cos()).abs()).max((s - phi.sin()).abs());
/// }
/// assert!(worst < 4e-15);
/// ```
#[inline(always)]
#[must_use]
pub fn carried_sin_cos(phi: f64, carried: &mut [f64; 3]) -> [f64; 2] {
    let [c0, s0, phi0] = *carried;
    let d = phi - phi0;
    // Written so that a NaN φ₀ (or φ) takes the fresh computation.
    let (c, s) = if d.abs() <= CARRIED_STEP {
        let d2 = d * d;
        // sin Δ = Δ − Δ³/3! + Δ⁵/5! − Δ⁷/7! + Δ⁹/9! (next term below 2e-21);
        // 1 − cos Δ = Δ²/2! − Δ⁴/4! + Δ⁶/6! − Δ⁸/8! + Δ¹⁰/10! (next below
        // 8e-24).
        let sin = d - d
            * d2
            * (SIN_SERIES[0] - d2 * (SIN_SERIES[1] - d2 * (SIN_SERIES[2] - d2 * SIN_SERIES[3])));
        let vers = d2
            * (VERS_SERIES[0]
                - d2 * (VERS_SERIES[1]
                    - d2 * (VERS_SERIES[2] - d2 * (VERS_SERIES[3] - d2 * VERS_SERIES[4]))));
        (c0 - (c0 * vers + s0 * sin), s0 - (s0 * vers - c0 * sin))
    } else {
        let (s, c) = crate::math::table::sin_cos(phi);
        (c, s)
    };
    *carried = [c, s, phi];
    [c, s]
}

/// (cos x, sin x) of a guess x, from `carried` (cos θ, sin θ, θ) where
/// θ is x itself (the stepper's last solution, or the guess's own values
/// seeded by a stateless step), else computed: what the closed forms take
/// to choose a mode from the guess. Used by generated code.
#[doc(hidden)]
#[inline(always)]
#[must_use]
pub fn guess_trig(carried: &[f64; 3], x: f64) -> [f64; 2] {
    if carried[2] == x {
        [carried[0], carried[1]]
    } else {
        fresh_trig(x)
    }
}

/// (cos x, sin x), off the common path of [`guess_trig`].
#[cold]
#[inline(never)]
fn fresh_trig(x: f64) -> [f64; 2] {
    let (s, c) = crate::math::table::sin_cos(x);
    [c, s]
}

/// (cos x, sin x, x) for a guess x: the carried values of an unknown angle
/// seeded from the guess, so that [`near_carried`] takes the solution's
/// angle from the guess's without an atan2 when the two are close (NaN,
/// nothing carried, beyond 2²⁰ rad). Used by generated code.
#[doc(hidden)]
#[inline(always)]
#[must_use]
pub fn seeded(x: f64) -> [f64; 3] {
    // Beyond 2²⁰ rad an angle's ulp is too coarse to carry a solution
    // near it: the solution is taken afresh (see `near`).
    if x.abs() > 1_048_576.0 || x.is_nan() {
        return [f64::NAN; 3];
    }
    let (s, c) = crate::math::table::in_range(x);
    [c, s, x]
}

/// [`near`], from the previous solution of the same angle: `carried` holds
/// its (cos θ, sin θ, θ), and the angle is θ + Δ with
/// sin Δ = cos θ · `s` − sin θ · `c` and Δ = asin(sin Δ) by its series
/// (to 1e-17 for |sin Δ| ≤ 1/32 and cos Δ > 0), with no atan2, when that
/// is within π of `reference`; otherwise as [`near`]. On return `carried`
/// holds the new (cos, sin, angle).
///
/// ```
/// use kinematics_core::closed::near_carried;
/// let mut carried = [f64::NAN; 3];
/// let (mut c, mut s) = (0.3f64.cos(), 0.3f64.sin());
/// let a = near_carried(&mut c, &mut s, 0.0, &mut carried);
/// let (mut c, mut s) = (0.31f64.cos(), 0.31f64.sin());
/// let b = near_carried(&mut c, &mut s, a, &mut carried);
/// assert!((a - 0.3).abs() < 1e-16 && (b - 0.31).abs() < 1e-16);
/// ```
#[inline(always)]
pub fn near_carried(c: &mut f64, s: &mut f64, reference: f64, carried: &mut [f64; 3]) -> f64 {
    let [cp, sp, tp] = *carried;
    let x = cp * *s - sp * *c;
    let y = cp * *c + sp * *s;
    let mut theta = f64::NAN;
    if y > 0.0 && x.abs() <= 0.031_25 {
        let x2 = x * x;
        // asin x = x + x³/6 + 3x⁵/40 + 5x⁷/112 + 35x⁹/1152 + 63x¹¹/2816 (the
        // next term, 231x¹³/13312, is below 1e-21 x for |x| ≤ 1/32).
        let series = x2
            * (1.0 / 6.0
                + x2 * (3.0 / 40.0
                    + x2 * (5.0 / 112.0 + x2 * (35.0 / 1152.0 + x2 * (63.0 / 2816.0)))));
        theta = tp + (x + x * series);
    }
    // The representative nearest the reference (a NaN carried angle fails
    // the test too).
    if !((theta - reference).abs() <= PI) {
        theta = near(c, s, reference);
    }
    *carried = [*c, *s, theta];
    theta
}

/// The combinations of N modes (±1) to try after `tried` put the
/// solution on the other branch than asked: with `base` the modes of
/// `tried` (NaN taken as +1), `base` itself where it differs from `tried`
/// bit for bit, then `base` with one block's mode flipped (each flip
/// changes the sign of that block's determinant, so one of these is on
/// the other branch), then, for N ≤ 16 only, every other combination:
/// N + 1 candidates at most for a large model rather than 2^N. Used by
/// generated code.
#[doc(hidden)]
pub fn other_modes<const N: usize>(tried: [f64; N]) -> impl Iterator<Item = [f64; N]> {
    let base: [f64; N] = core::array::from_fn(|j| if tried[j] < 0.0 { -1.0 } else { 1.0 });
    let same = base
        .iter()
        .zip(&tried)
        .all(|(a, b)| a.to_bits() == b.to_bits());
    let flips = (0..N).map(move |j| {
        let mut m = base;
        m[j] = -m[j];
        m
    });
    let all = if N <= 16 { 1usize << N } else { 0 };
    let rest = (0..all)
        .filter(|i| i.count_ones() >= 2)
        .map(move |i| core::array::from_fn(|j| if i >> j & 1 == 1 { -base[j] } else { base[j] }));
    (!same).then_some(base).into_iter().chain(flips).chain(rest)
}

/// How a closed-form pose's residual stands: see [`closing`].
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Closing {
    /// At round-off: the pose is returned.
    Closed,
    /// Within min(tolerance, 1e-12) but above the bound every step's pose
    /// is brought to: polished by Newton–Raphson from the pose, in the
    /// same modes.
    Polish,
    /// Beyond min(tolerance, 1e-12), or NaN: not trusted; Newton–Raphson
    /// from the guess, in modes taken afresh.
    Refuse,
}

/// The check of a closed-form pose, with r = max |Φ_i| w_i computed once:
/// [`Closing::Closed`] for r ≤ the larger of [`POLISH`](crate::solve::POLISH)
/// times the tolerance and [`CLOSED`](crate::solve::CLOSED) (and within
/// min(tolerance, 1e-12)), [`Closing::Polish`] for r ≤ min(tolerance,
/// 1e-12), [`Closing::Refuse`] beyond (or NaN). Used by generated code.
#[doc(hidden)]
#[inline(always)]
#[must_use]
pub fn closing<const N: usize>(phi: &[f64; N], w: &[f64; N], options: &Options) -> Closing {
    let mut max = 0.0f64;
    for i in 0..N {
        let r = (phi[i] * w[i]).abs();
        // A NaN fails both tests below.
        max = if r > max || r.is_nan() { r } else { max };
    }
    let limit = options.tolerance.min(1e-12);
    let bound = (crate::solve::POLISH * options.tolerance).max(crate::solve::CLOSED);
    if max <= bound.min(limit) {
        Closing::Closed
    } else if max <= limit {
        Closing::Polish
    } else {
        Closing::Refuse
    }
}

/// max |x_i|, NaN if any x_i is NaN. Used by generated code.
#[doc(hidden)]
#[inline(always)]
#[must_use]
pub fn max_abs<const N: usize>(x: &[f64; N]) -> f64 {
    let mut max = 0.0f64;
    for v in x {
        let r = v.abs();
        max = if r > max || r.is_nan() { r } else { max };
    }
    max
}

/// [`Error::CannotAssemble`] for the block of `unknowns` at the drivers
/// `d` (named by `names`). Used by generated code.
#[doc(hidden)]
#[cold]
#[must_use]
pub fn cannot_assemble(
    unknowns: &'static str,
    discriminant: f64,
    names: &crate::solve::Names,
    d: &[f64],
) -> Error {
    Error::CannotAssemble {
        unknowns,
        discriminant,
        drivers: names
            .coordinates
            .iter()
            .copied()
            .zip(d.iter().copied())
            .collect(),
    }
}

#[cfg(test)]
mod tests;
