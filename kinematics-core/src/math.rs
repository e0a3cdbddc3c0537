//! The floating-point functions the library and the generated code use:
//! those of the standard library with the `std` feature (the default), and
//! those of `libm` without it, so that the crate and the code `mechanism!`
//! generates build for `#![no_std]` targets.
//!
//! Generated code calls these (through `__private::math`) rather than the
//! `f64` methods, which exist only with `std`.

// `x.sin()` and friends are the standard library's; `libm` gives the same
// functions to `no_std` builds.
#![allow(clippy::inline_always)]

/// One-argument functions: the `f64` method with `std`, the libm function
/// without.
macro_rules! unary {
    ($($(#[$doc:meta])* $name:ident: $method:ident, $libm:ident;)*) => {$(
        $(#[$doc])*
        #[inline(always)]
        #[must_use]
        pub fn $name(x: f64) -> f64 {
            #[cfg(feature = "std")]
            return x.$method();
            #[cfg(not(feature = "std"))]
            return libm::$libm(x);
        }
    )*};
}

unary! {
    /// tan x.
    tan: tan, tan;
    /// asin x.
    asin: asin, asin;
    /// acos x.
    acos: acos, acos;
    /// √x.
    sqrt: sqrt, sqrt;
    /// eˣ.
    exp: exp, exp;
    /// ln x.
    ln: ln, log;
    /// x rounded to the nearest integer, halves away from zero.
    round: round, round;
}

/// The largest |x| that [`sin_cos`] reduces itself (2¹⁹ rad); beyond, the
/// platform's functions do.
const REDUCED: f64 = 524_288.0;

/// π/2 = `PIO2_HI` + `PIO2_MID` + `PIO2_LO` to 2⁻¹²⁴: the first two have
/// 33 significant bits, so that k · each is exact for |k| < 2²⁰.
const PIO2_HI: f64 = 1.570_796_326_734_125_6;
const PIO2_MID: f64 = 6.077_100_506_303_966e-11;
const PIO2_LO: f64 = 2.022_266_248_795_950_6e-21;

/// 1.5 · 2⁵²: adding and subtracting it rounds |y| < 2⁵¹ to the nearest
/// integer.
const ROUND_SHIFT: f64 = 6_755_399_441_055_744.0;

/// (sin x, cos x).
///
/// For |x| ≤ 2¹⁹ (every angle a mechanism turns through in practice),
/// computed here, inline: x = k π/2 + r with k the nearest integer to
/// 2x/π and r = ((x − k h₁) − k h₂) − k h₃ (π/2 = h₁ + h₂ + h₃ split so
/// that the first two products are exact), |r| ≤ π/4; then the Taylor
/// series of sin r to r¹⁷ and of cos r to r¹⁸, whose remainders are below
/// 2⁻⁶² there, and (sin, cos) rotated by the quadrant k mod 4. Within two
/// units in the last place of the correctly rounded values; about half the
/// work of a library call, which matters because a step of a mechanism
/// calls little else that is costly. Beyond 2¹⁹, and for NaN and ±∞, the
/// standard library's (libm's without `std`).
// `inline`, not `inline(always)`: an unoptimised build of a model of
// hundreds of loops would give each of its calls its own stack slots.
#[inline]
#[must_use]
pub fn sin_cos(x: f64) -> (f64, f64) {
    // NaN fails the test too.
    if abs(x) > REDUCED || x.is_nan() {
        return sin_cos_far(x);
    }
    let k = (x * core::f64::consts::FRAC_2_PI + ROUND_SHIFT) - ROUND_SHIFT;
    let r = ((x - k * PIO2_HI) - k * PIO2_MID) - k * PIO2_LO;
    let (s, c) = sin_cos_kernel(r);
    // k is an integer of magnitude below 2²⁰: the conversion is exact.
    #[allow(clippy::cast_possible_truncation)]
    match (k as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// (sin r, cos r) for |r| ≤ π/4 + 2⁻²⁰ by their Taylor series, in
/// z = r²: sin r = r + r z Σ (−1)ⁿ zⁿ⁻¹ / (2n+1)!, n = 1…8, and
/// cos r = 1 − z/2 + z² Σ (−1)ⁿ zⁿ⁻² / (2n)!, n = 2…9.
#[inline(always)]
fn sin_cos_kernel(r: f64) -> (f64, f64) {
    const S: [f64; 8] = [
        -1.666_666_666_666_666_6e-1,
        8.333_333_333_333_333e-3,
        -1.984_126_984_126_984e-4,
        2.755_731_922_398_589_3e-6,
        -2.505_210_838_544_172e-8,
        1.605_904_383_682_161_3e-10,
        -7.647_163_731_819_816e-13,
        2.811_457_254_345_520_6e-15,
    ];
    const C: [f64; 8] = [
        4.166_666_666_666_666_4e-2,
        -1.388_888_888_888_889e-3,
        2.480_158_730_158_73e-5,
        -2.755_731_922_398_589e-7,
        2.087_675_698_786_81e-9,
        -1.147_074_559_772_972_5e-11,
        4.779_477_332_387_385e-14,
        -1.561_920_696_858_622_5e-16,
    ];
    let z = r * r;
    let ps = S[0]
        + z * (S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * (S[5] + z * (S[6] + z * S[7]))))));
    let pc = C[0]
        + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * (C[5] + z * (C[6] + z * C[7]))))));
    (r + r * z * ps, (1.0 - 0.5 * z) + z * z * pc)
}

/// (sin x, cos x) by the platform's functions: for |x| > 2¹⁹, NaN and ±∞.
#[cold]
#[inline(never)]
fn sin_cos_far(x: f64) -> (f64, f64) {
    #[cfg(feature = "std")]
    return x.sin_cos();
    #[cfg(not(feature = "std"))]
    return libm::sincos(x);
}

/// sin x (see [`sin_cos`]).
#[inline]
#[must_use]
pub fn sin(x: f64) -> f64 {
    sin_cos(x).0
}

/// cos x (see [`sin_cos`]).
#[inline]
#[must_use]
pub fn cos(x: f64) -> f64 {
    sin_cos(x).1
}

/// atan2(y, x), the angle of (x, y).
#[inline(always)]
#[must_use]
pub fn atan2(y: f64, x: f64) -> f64 {
    #[cfg(feature = "std")]
    return y.atan2(x);
    #[cfg(not(feature = "std"))]
    return libm::atan2(y, x);
}

/// |x|.
#[inline(always)]
#[must_use]
pub fn abs(x: f64) -> f64 {
    x.abs()
}

/// xⁿ for an integer n.
#[inline(always)]
#[must_use]
pub fn powi(x: f64, n: i32) -> f64 {
    #[cfg(feature = "std")]
    return x.powi(n);
    #[cfg(not(feature = "std"))]
    return libm::pow(x, f64::from(n));
}

/// The least non-negative remainder of x modulo m (m > 0).
#[inline(always)]
#[must_use]
pub fn rem_euclid(x: f64, m: f64) -> f64 {
    #[cfg(feature = "std")]
    return x.rem_euclid(m);
    #[cfg(not(feature = "std"))]
    {
        let r = libm::fmod(x, m);
        if r < 0.0 {
            r + m.abs()
        } else {
            r
        }
    }
}

#[cfg(test)]
mod tests {
    /// With `std` these are the `f64` methods themselves; with libm they
    /// agree with them to a few units of round-off.
    #[test]
    fn the_functions_are_those_of_f64() {
        let close = |a: f64, b: f64| (a - b).abs() <= 4e-16 * (1.0 + b.abs());
        for x in [-2.5, -0.3, 0.0, 0.7, 1.9] {
            let (s, c) = super::sin_cos(x);
            assert!(close(s, x.sin()) && close(c, x.cos()), "{x}");
            assert!(close(super::sin(x), x.sin()) && close(super::cos(x), x.cos()));
            assert!(close(super::tan(x), x.tan()) && close(super::exp(x), x.exp()));
            assert!(close(super::atan2(x, 0.4), x.atan2(0.4)));
            assert!(close(super::asin(x / 3.0), (x / 3.0).asin()));
            assert!(close(super::acos(x / 3.0), (x / 3.0).acos()));
            assert!(close(super::sqrt(x.abs()), x.abs().sqrt()));
            assert!(close(super::ln(x.abs() + 1.0), (x.abs() + 1.0).ln()));
            assert!(close(super::powi(x, 3), x.powi(3)));
            assert!(close(super::rem_euclid(x, 1.0), x.rem_euclid(1.0)));
            assert_eq!(super::abs(x), x.abs());
        }
    }

    /// Units in the last place between `a` and `b` (of the same sign).
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        if a.signum() != b.signum() {
            return u64::MAX;
        }
        a.abs().to_bits().abs_diff(b.abs().to_bits())
    }

    /// `sin_cos` within 2 ulp of the platform's (itself within 1 ulp of
    /// the exact values) over seeded random angles in every range it
    /// reduces itself, near multiples of π/2 and at its boundaries; the
    /// platform's own beyond 2¹⁹, for NaN and for ±∞.
    #[test]
    fn sin_cos_is_within_two_ulp() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut unit = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            #[allow(clippy::cast_precision_loss)]
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            u
        };
        let mut xs = alloc::vec::Vec::new();
        for scale in [1e-8, 0.5, 1.0, 3.2, 10.0, 1e3, 1e5, 524_288.0] {
            for _ in 0..20_000 {
                xs.push(scale * (2.0 * unit() - 1.0));
            }
        }
        for k in -1000..=1000 {
            let m = f64::from(k) * core::f64::consts::FRAC_PI_2;
            for d in [-1e-9, -1e-15, 0.0, 1e-15, 1e-9] {
                xs.push(m + d);
                xs.push(m * (1.0 + d));
            }
        }
        xs.extend([
            0.0, -0.0, 1e-300, -1e-300, 524_288.0, -524_288.0, 524_288.1, 1e10, 1e300,
        ]);
        let mut worst = 0;
        for &x in &xs {
            let (s, c) = super::sin_cos(x);
            let (es, ec) = x.sin_cos();
            // Near a zero the value is tiny: an absolute 1e-30 is met too.
            for (got, exact) in [(s, es), (c, ec)] {
                let u = ulps(got, exact);
                assert!(
                    u <= 2 || (got - exact).abs() <= 1e-30,
                    "{x}: {got} against {exact}"
                );
                if (got - exact).abs() > 1e-30 {
                    worst = worst.max(u);
                }
            }
        }
        assert!(worst <= 2, "{worst} ulp");
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = super::sin_cos(x);
            assert!(s.is_nan() && c.is_nan());
        }
    }
}
