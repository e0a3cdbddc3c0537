//! Tolerance analysis from exact design sensitivities.
//!
//! For a mechanism whose definition has a `sensitivities { … }` section,
//! the deviation of a point from its nominal motion when the parameters
//! deviate by δp_k is, to first order, δr = Σ_k ∂r/∂p_k δp_k (likewise its
//! velocity). With each parameter within ±t_k:
//!
//! * **worst case**, per component: Σ_k |∂r_c/∂p_k| t_k, and for the
//!   distance |δr| the largest |Σ_k ±∂r/∂p_k t_k| over the corners of the
//!   tolerance box (exact for up to 16 parameters, the bound Σ_k |∂r/∂p_k| t_k
//!   beyond);
//! * **root-sum-square**, per component: √(Σ_k (∂r_c/∂p_k t_k)²), the
//!   standard deviation of δr_c when each δp_k has standard deviation t_k
//!   (divide by √3 for δp_k uniform in ±t_k, by 3 for t_k = 3σ).
//!
//! ```
//! use kinematics_core::{mechanism, tolerance::point_deviations};
//! mechanism! {
//!     /// A crank: B = polar(a, φ).
//!     pub struct Crank {
//!         params { a }
//!         drivers { phi }
//!         unknowns { }
//!         points { B = polar(a, phi); }
//!         sensitivities { a }
//!     }
//! }
//! let m = Crank { a: 0.1 };
//! let sweep = m.sweep(Crank::PHI, &CrankCoords { phi: 0.0 }).turn().steps(8).rate(2.0).run();
//! let d = point_deviations(&m, &sweep, "B", &[("a", 0.001)])?;
//! // |δB| = t, the speed's deviation t·φ'.
//! assert!(d.iter().all(|x| (x.position_worst - 0.001).abs() < 1e-15));
//! assert!(d.iter().all(|x| (x.velocity_worst - 0.002).abs() < 1e-15));
//! # Ok::<(), kinematics_core::Error>(())
//! ```

use alloc::vec;
use alloc::vec::Vec;

use crate::error::Error;
use crate::mechanism::Mechanism;
use crate::sweep::Sweep;

/// A mechanism with exact design sensitivities (generated for a definition
/// with a `sensitivities { … }` section).
pub trait Sensitive: Mechanism {
    /// The parameters of the section, in its order.
    const PARAMETERS: &'static [&'static str];

    /// The sensitivities of every point of `motion` to every parameter of
    /// [`Sensitive::PARAMETERS`], written into `out` as
    /// `[parameter][point][position, velocity, acceleration][component]`
    /// (`PARAMETERS.len() × POINTS × 3 × POINT_DIM` numbers; as many as fit):
    /// [`Sensitive::motion_sensitivities_into`] without the coordinates.
    ///
    /// # Errors
    /// As the generated `sensitivities`.
    fn point_sensitivities_into(
        &self,
        motion: &Self::Motion,
        out: &mut [f64],
    ) -> Result<(), Error> {
        self.motion_sensitivities_into(motion, &mut [], out)
    }

    /// The sensitivities of the whole of `motion`: ∂q/∂p, ∂q'/∂p and
    /// ∂q''/∂p into `coordinates` as `[parameter][q, q', q''][coordinate]`
    /// (zero for the drivers), and every point's ∂r/∂p, ∂v/∂p and ∂a/∂p
    /// into `points` as `[parameter][point][position, velocity,
    /// acceleration][component]` (as many as fit in each).
    ///
    /// # Errors
    /// As the generated `sensitivities`.
    fn motion_sensitivities_into(
        &self,
        motion: &Self::Motion,
        coordinates: &mut [f64],
        points: &mut [f64],
    ) -> Result<(), Error>;

    /// The position-level sensitivities of `motion`, for synthesis:
    /// ∂q/∂p into `coordinates` as `[parameter][coordinate]` (zero for the
    /// drivers) and ∂r/∂p into `points` as `[parameter][point][component]`
    /// (as many as fit in each).
    ///
    /// # Errors
    /// As the generated `sensitivities`.
    fn position_sensitivities_into(
        &self,
        motion: &Self::Motion,
        coordinates: &mut [f64],
        points: &mut [f64],
    ) -> Result<(), Error>;

    /// Parameter `k` of [`Sensitive::PARAMETERS`] (NaN past the last).
    fn parameter(&self, k: usize) -> f64;

    /// Sets parameter `k` of [`Sensitive::PARAMETERS`]; `false` past the
    /// last.
    fn set_parameter(&mut self, k: usize, value: f64) -> bool;
}

/// The first-order deviation of a point at one sample of a sweep (see the
/// [module](self) for the formulas).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Deviation {
    /// The sample's value of the swept variable.
    pub at: f64,
    /// Worst case of each position component, Σ_k |∂r_c/∂p_k| t_k.
    pub position_components: Vec<f64>,
    /// Root-sum-square of each position component, √(Σ_k (∂r_c/∂p_k t_k)²).
    pub position_rss: Vec<f64>,
    /// Worst case of the distance from the nominal position.
    pub position_worst: f64,
    /// Worst case of each velocity component.
    pub velocity_components: Vec<f64>,
    /// Root-sum-square of each velocity component.
    pub velocity_rss: Vec<f64>,
    /// Worst case of the magnitude of the velocity's deviation.
    pub velocity_worst: f64,
}

/// The first-order deviations of point `point` over `sweep` for the
/// parameter tolerances `tolerances` (name, ±t), each name among the
/// parameters of the `sensitivities` section; a parameter not listed is
/// exact.
///
/// # Errors
/// [`Error::InvalidGeometry`] for an unknown point,
/// [`Error::InvalidOption`] for a tolerance on a parameter the section does
/// not list or a negative or non-finite tolerance, and the errors of the
/// sensitivities at a sample.
pub fn point_deviations<M: Sensitive>(
    m: &M,
    sweep: &Sweep<M>,
    point: &str,
    tolerances: &[(&str, f64)],
) -> Result<Vec<Deviation>, Error> {
    deviations_by(
        (M::POINT_NAMES, M::PARAMETERS, M::POINT_DIM),
        point,
        tolerances,
        sweep.samples.len(),
        |i, buf| {
            let s = &sweep.samples[i];
            m.point_sensitivities_into(&s.motion, buf)?;
            Ok(s.at)
        },
    )
}

/// [`point_deviations`] for any model: `points`, `parameters` and `dim`
/// name its points, the parameters of its `sensitivities` section and the
/// points' dimension; `sample(i, buf)` writes into `buf` the
/// sensitivities of every point at sample i as
/// `[parameter][point][position, velocity, acceleration][component]` and
/// returns the sample's swept value.
pub(crate) fn deviations_by(
    (points, parameters, dim): (&[&str], &[&str], usize),
    point: &str,
    tolerances: &[(&str, f64)],
    samples: usize,
    mut sample: impl FnMut(usize, &mut [f64]) -> Result<f64, Error>,
) -> Result<Vec<Deviation>, Error> {
    let n = crate::view::index_of(points, point, "tolerance analysis")?;
    let np = parameters.len();
    let mut t = vec![0.0; np];
    for (name, tol) in tolerances {
        let Some(k) = parameters.iter().position(|p| p == name) else {
            return Err(Error::InvalidOption {
                name: "tolerances",
                value: *tol,
                requirement: "must name parameters of the mechanism's `sensitivities` section",
            });
        };
        if !(tol.is_finite() && *tol >= 0.0) {
            return Err(Error::InvalidOption {
                name: "tolerances",
                value: *tol,
                requirement: "must be finite and not negative",
            });
        }
        t[k] = *tol;
    }
    let per_param = points.len() * 3 * dim;
    let mut buf = vec![0.0; np * per_param];
    let mut out = Vec::with_capacity(samples);
    for i in 0..samples {
        let at = sample(i, &mut buf)?;
        // ∂r/∂p_k t_k and ∂v/∂p_k t_k of the point, per parameter.
        let part = |k: usize, which: usize| -> Vec<f64> {
            let o = k * per_param + (n * 3 + which) * dim;
            buf[o..o + dim].iter().map(|v| v * t[k]).collect()
        };
        let pos: Vec<Vec<f64>> = (0..np).map(|k| part(k, 0)).collect();
        let vel: Vec<Vec<f64>> = (0..np).map(|k| part(k, 1)).collect();
        let components = |d: &[Vec<f64>]| -> Vec<f64> {
            (0..dim)
                .map(|c| d.iter().map(|v| v[c].abs()).sum())
                .collect()
        };
        let rss = |d: &[Vec<f64>]| -> Vec<f64> {
            (0..dim)
                .map(|c| crate::math::sqrt(d.iter().map(|v| v[c] * v[c]).sum()))
                .collect()
        };
        out.push(Deviation {
            at,
            position_components: components(&pos),
            position_rss: rss(&pos),
            position_worst: corner_max(&pos, dim),
            velocity_components: components(&vel),
            velocity_rss: rss(&vel),
            velocity_worst: corner_max(&vel, dim),
        });
    }
    Ok(out)
}

/// max over signs s_k = ±1 of |Σ_k s_k d_k|: by enumeration of the corners
/// for up to 16 vectors, else the bound Σ_k |d_k|.
fn corner_max(d: &[Vec<f64>], dim: usize) -> f64 {
    let norm = |v: &[f64]| crate::math::sqrt(v.iter().map(|x| x * x).sum());
    if d.len() > 16 {
        return d.iter().map(|v| norm(v)).sum();
    }
    let mut best = 0.0f64;
    for signs in 0..1usize << d.len() {
        let mut s = vec![0.0; dim];
        for (k, v) in d.iter().enumerate() {
            let sign = if signs >> k & 1 == 1 { -1.0 } else { 1.0 };
            for c in 0..dim {
                s[c] += sign * v[c];
            }
        }
        best = best.max(norm(&s));
    }
    best
}
