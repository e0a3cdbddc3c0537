//! A collected sweep: its samples and stop, and its output as CSV and as
//! a text table.

use alloc::borrow::ToOwned;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write as _;

use super::drive::Drive;
use super::iter::SweepIter;
use super::sample::{Sample, Stop};
use crate::mechanism::{Coordinates, Kind, Mechanism, MotionState, PointState, Role};
use crate::names::Name;

/// The samples of a sweep, and how it ended.
#[derive(Debug, Clone)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(bound(
        serialize = "M::Motion: serde::Serialize",
        deserialize = "M::Motion: serde::Deserialize<'de>"
    ))
)]
pub struct Sweep<M: Mechanism> {
    /// Name of the swept driver, or "t" for a simulation.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::names::name"))]
    pub variable: Name,
    /// The kind of the swept driver (a time is reported as a length-like
    /// plain value).
    pub kind: Kind,
    /// The samples, in order.
    pub samples: Vec<Sample<M>>,
    /// The change points passed on the branch chosen by [`ChangePoints`](super::ChangePoints)
    /// (estimates of the driver value of each).
    pub change_points: Vec<f64>,
    /// `Some` when the sweep stopped early.
    pub stop: Option<Stop>,
}

/// Collects a sweep's items.
pub(super) fn collect<M: Mechanism, D: Drive<M>>(
    mut it: SweepIter<'_, M, D>,
    kind: Kind,
) -> Sweep<M> {
    let mut samples = Vec::with_capacity(it.grid.count + 1);
    let mut stop = None;
    for item in it.by_ref() {
        match item {
            Ok(s) => samples.push(s),
            Err(s) => stop = Some(s),
        }
    }
    Sweep {
        variable: it.variable,
        kind,
        samples,
        change_points: core::mem::take(&mut it.passed),
        stop,
    }
}

impl<M: Mechanism> Sweep<M> {
    /// Whether the last sample returns to the first pose: every unknown
    /// within `tolerance`, angles compared modulo 2π. `None` for a sweep that
    /// stopped early or has fewer than two samples. Meant for a sweep whose
    /// range includes its end (`.to(…)`), one period from its start; a
    /// `.turn()` leaves the end out.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = m.sweep(SliderCrank::PHI, &start).to(std::f64::consts::TAU).steps(360).run();
    /// assert_eq!(s.is_periodic(1e-9), Some(true));
    /// ```
    #[must_use]
    pub fn is_periodic(&self, tolerance: f64) -> Option<bool> {
        if self.stop.is_some() || self.samples.len() < 2 {
            return None;
        }
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        let ok = M::COORDINATES.iter().enumerate().all(|(j, c)| {
            if c.role == Role::Driver {
                return true;
            }
            let (a, b) = (first.motion.q().get(j), last.motion.q().get(j));
            let (Some(a), Some(b)) = (a, b) else {
                return false;
            };
            let d = if c.kind == Kind::Angle {
                crate::math::rem_euclid(b - a + core::f64::consts::PI, core::f64::consts::TAU)
                    - core::f64::consts::PI
            } else {
                b - a
            };
            d.abs() <= tolerance
        });
        Some(ok)
    }

    /// Largest closure residual over the samples.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(100).run();
    /// assert!(s.max_residual() < 1e-12);
    /// ```
    #[must_use]
    pub fn max_residual(&self) -> f64 {
        self.samples
            .iter()
            .fold(0.0f64, |a, s| a.max(s.motion.residual()))
    }

    /// Column headers, plain identifiers with their units in the name:
    /// the time (`t_s`) for a simulation; each coordinate's value, rate and
    /// acceleration (`th3_rad`, `th3_rad_s`, `th3_rad_s2`; `x_m`, `x_m_s`,
    /// `x_m_s2`); each point's position, velocity and acceleration
    /// components (`B_x_m`, `B_vx_m_s`, `B_ax_m_s2`); each frame's ω and α
    /// (`tool_wx_rad_s`, `tool_alphax_rad_s2`). Lengths are taken to be in
    /// metres: see [`Sweep::headers_in`] for another unit.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).run();
    /// let h = s.headers();
    /// assert_eq!(&h[..4], ["phi_rad", "phi_rad_s", "phi_rad_s2", "th_rad"]);
    /// assert!(h.contains(&"C_vx_m_s".to_owned()));
    /// assert_eq!(h.len(), s.row(&s.samples[0]).len());
    /// ```
    #[must_use]
    pub fn headers(&self) -> Vec<String> {
        self.headers_in("m")
    }

    /// [`Sweep::headers`] with lengths in `unit` (`"mm"`: `x_mm`,
    /// `B_vx_mm_s`); the values are as computed, in the unit of the
    /// mechanism's parameters.
    #[must_use]
    pub fn headers_in(&self, unit: &str) -> Vec<String> {
        let mut h = Vec::new();
        if self.variable == "t" {
            h.push("t_s".to_owned());
        }
        for c in M::COORDINATES {
            let u = match c.kind {
                Kind::Angle => "rad",
                Kind::Length => unit,
            };
            h.push(format!("{}_{u}", c.name));
            h.push(format!("{}_{u}_s", c.name));
            h.push(format!("{}_{u}_s2", c.name));
        }
        let axes = ["x", "y", "z"];
        for p in M::POINT_NAMES {
            for (prefix, suffix) in [("", ""), ("v", "_s"), ("a", "_s2")] {
                for axis in axes.iter().take(M::POINT_DIM) {
                    h.push(format!("{p}_{prefix}{axis}_{unit}{suffix}"));
                }
            }
        }
        for f in M::FRAME_NAMES {
            for (short, suffix) in [("w", "rad_s"), ("alpha", "rad_s2")] {
                for axis in axes {
                    h.push(format!("{f}_{short}{axis}_{suffix}"));
                }
            }
        }
        h
    }

    /// The values of one sample, in the order of [`Sweep::headers`].
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).rate(6.0).run();
    /// assert_eq!(s.row(&s.samples[10])[0], 1.0); // φ first
    /// ```
    #[must_use]
    pub fn row(&self, sample: &Sample<M>) -> Vec<f64> {
        let mo = &sample.motion;
        let mut r = Vec::new();
        if self.variable == "t" {
            r.push(sample.at);
        }
        for j in 0..M::COORDINATES.len() {
            for c in [mo.q(), mo.qd(), mo.qdd()] {
                r.push(c.get(j).unwrap_or(f64::NAN));
            }
        }
        for p in mo.points() {
            r.extend_from_slice(p.position());
            r.extend_from_slice(p.velocity());
            r.extend_from_slice(p.acceleration());
        }
        for f in mo.frames() {
            r.extend(
                f.angular_velocity
                    .iter()
                    .chain(f.angular_acceleration.iter()),
            );
        }
        r
    }

    /// The samples as CSV: a header line (see [`Sweep::headers`]), then one
    /// line per sample.
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).rate(6.0).run();
    /// assert_eq!(s.to_csv().lines().count(), 1 + 11); // a header, then a line per sample
    /// ```
    #[must_use]
    pub fn to_csv(&self) -> String {
        let mut out = self.headers().join(",");
        out.push('\n');
        for s in &self.samples {
            let row: Vec<String> = self.row(s).iter().map(|v| format!("{v:.12e}")).collect();
            out += &row.join(",");
            out.push('\n');
        }
        out
    }

    /// The samples as an aligned plain-text table, every `every`-th sample
    /// (the last one always included).
    ///
    /// ```
    /// # use kinematics_core::mechanism;
    /// # mechanism! {
    /// #     /// Slider-crank.
    /// #     pub struct SliderCrank {
    /// #         params   { a, b }
    /// #         drivers  { phi }
    /// #         unknowns { th, x }
    /// #         points   { B = polar(a, phi); C = vec2(x, 0.0); }
    /// #         loops    { B + polar(b, th) == C; }
    /// #     }
    /// # }
    /// # let m = SliderCrank { a: 0.1, b: 0.3 };
    /// # let start = SliderCrankCoords { phi: 0.0, th: 0.0, x: 0.4 };
    /// let s = m.sweep(SliderCrank::PHI, &start).to(1.0).steps(10).rate(6.0).run();
    /// print!("{}", s.to_text(5)); // every fifth sample, in aligned columns
    /// ```
    #[must_use]
    pub fn to_text(&self, every: usize) -> String {
        let headers = self.headers();
        let width = headers
            .iter()
            .map(|h| h.chars().count())
            .max()
            .unwrap_or(8)
            .max(12);
        let mut out = String::new();
        for h in &headers {
            let _ = write!(out, "{h:>width$} ");
        }
        out.push('\n');
        let n = self.samples.len();
        for (k, s) in self.samples.iter().enumerate() {
            if k % every.max(1) != 0 && k + 1 != n {
                continue;
            }
            for v in self.row(s) {
                let _ = write!(out, "{v:>width$.5} ");
            }
            out.push('\n');
        }
        out
    }
}
