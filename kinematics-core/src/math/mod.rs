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
    /// sin x.
    sin: sin, sin;
    /// cos x.
    cos: cos, cos;
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

/// (sin x, cos x).
#[inline(always)]
#[must_use]
pub fn sin_cos(x: f64) -> (f64, f64) {
    #[cfg(feature = "std")]
    return x.sin_cos();
    #[cfg(not(feature = "std"))]
    return libm::sincos(x);
}

pub mod table;

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
        if r < 0.0 { r + m.abs() } else { r }
    }
}

/// `dst` = `src` (of the same length), element by element where the
/// slices are as short as a point's, a small model's coordinates or a
/// small system's state (the library's `memcpy` costs more than the copy
/// there).
#[inline]
pub(crate) fn copy_small(dst: &mut [f64], src: &[f64]) {
    match (dst, src) {
        ([], []) => {}
        ([d0], [s0]) => *d0 = *s0,
        ([d0, d1], [s0, s1]) => (*d0, *d1) = (*s0, *s1),
        ([d0, d1, d2], [s0, s1, s2]) => (*d0, *d1, *d2) = (*s0, *s1, *s2),
        ([d0, d1, d2, d3], [s0, s1, s2, s3]) => {
            (*d0, *d1, *d2, *d3) = (*s0, *s1, *s2, *s3);
        }
        (d, s) => d.copy_from_slice(s),
    }
}

/// Every value of `dst` zero, element by element for up to two values
/// (as [`copy_small`]).
#[inline]
pub(crate) fn zero_small(dst: &mut [f64]) {
    match dst {
        [] => {}
        [d0] => *d0 = 0.0,
        [d0, d1] => (*d0, *d1) = (0.0, 0.0),
        d => d.fill(0.0),
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
}
