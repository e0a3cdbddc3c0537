//! A collected sweep: its samples and stop, and its output as CSV and as
//! a text table.

use alloc::string::String;
use alloc::vec::Vec;

use super::drive::Drive;
use super::iter::SweepIter;
use super::sample::{Sample, Stop};
use super::table::{Layout, Table};
use crate::mechanism::{Coordinates, FrameState, Kind, Mechanism, MotionState, PointState, Role};
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
    loop {
        it.push_common(&mut samples);
        match it.next() {
            Some(Ok(s)) => samples.push(s),
            Some(Err(s)) => stop = Some(s),
            None => break,
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
        Table::headers_in(self, unit)
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
        One {
            sweep: self,
            sample,
        }
        .row(0)
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
        self.csv_in("m")
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
        self.text(every)
    }
}

/// Coordinate `j` of a sample: its value (`order` 0), rate (1) or
/// acceleration (2); NaN for an index past the coordinates.
fn coordinate_of<M: Mechanism>(sample: &Sample<M>, j: usize, order: usize) -> f64 {
    let mo = &sample.motion;
    let c = match order {
        0 => mo.q(),
        1 => mo.qd(),
        _ => mo.qdd(),
    };
    c.get(j).unwrap_or(f64::NAN)
}

fn point_of<M: Mechanism>(sample: &Sample<M>, k: usize) -> [&[f64]; 3] {
    let p = &sample.motion.points()[k];
    [p.position(), p.velocity(), p.acceleration()]
}

impl<M: Mechanism> Table for Sweep<M> {
    fn layout(&self) -> Layout<'_> {
        Layout {
            variable: self.variable,
            kind: self.kind,
            coordinates: M::COORDINATES,
            points: M::POINT_NAMES,
            frames: M::FRAME_NAMES,
            point_dim: M::POINT_DIM,
        }
    }
    fn rows(&self) -> usize {
        self.samples.len()
    }
    fn at(&self, i: usize) -> f64 {
        self.samples[i].at
    }
    fn coordinate(&self, i: usize, j: usize, order: usize) -> f64 {
        coordinate_of(&self.samples[i], j, order)
    }
    fn point(&self, i: usize, k: usize) -> [&[f64]; 3] {
        point_of(&self.samples[i], k)
    }
    fn frame(&self, i: usize, f: usize) -> &FrameState {
        &self.samples[i].motion.frames()[f]
    }
    fn stop(&self) -> Option<&Stop> {
        self.stop.as_ref()
    }
}

/// One sample of a sweep as a table of one row, for [`Sweep::row`].
struct One<'a, M: Mechanism> {
    sweep: &'a Sweep<M>,
    sample: &'a Sample<M>,
}

impl<M: Mechanism> Table for One<'_, M> {
    fn layout(&self) -> Layout<'_> {
        self.sweep.layout()
    }
    fn rows(&self) -> usize {
        1
    }
    fn at(&self, _: usize) -> f64 {
        self.sample.at
    }
    fn coordinate(&self, _: usize, j: usize, order: usize) -> f64 {
        coordinate_of(self.sample, j, order)
    }
    fn point(&self, _: usize, k: usize) -> [&[f64]; 3] {
        point_of(self.sample, k)
    }
    fn frame(&self, _: usize, f: usize) -> &FrameState {
        &self.sample.motion.frames()[f]
    }
    fn stop(&self) -> Option<&Stop> {
        None
    }
}
