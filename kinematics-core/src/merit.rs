//! Figures of merit a linkage designer checks first: the Grashof class of
//! a four-bar, the transmission angle of a dyad over the cycle, the dead
//! centres of an output (where its rate changes sign: the limit
//! positions of a rocker or a slider), the stroke of a slider, the time
//! ratio of a quick-return, and the mechanical advantage of an output.
//! Each works on a [`Table`], so that a
//! sweep of a generated mechanism and one of a run-time model give the
//! same figures through the same code.
//!
//! Between two samples, a dead centre is located on the cubic Hermite
//! interpolant of the output's slope dq/dφ (its values and derivatives
//! d²q/dφ² at both samples, from the table's rates and accelerations),
//! and the output's value there on the Hermite interpolant of q: errors
//! of the order of the step to the fourth power (about 1e-9 rad at one
//! degree a step), with no model evaluated again.
//!
//! ```
//! use kinematics_core::merit::{grashof, GrashofClass};
//! // Norton's example proportions: S + L < P + Q, the shortest the crank.
//! let g = grashof(0.11, 0.04, 0.12, 0.10)?;
//! assert_eq!(g.class, GrashofClass::CrankRocker);
//! assert!(g.s_plus_l < g.p_plus_q);
//! # Ok::<(), kinematics_core::Error>(())
//! ```

use alloc::format;
use alloc::vec::Vec;
use core::f64::consts::{PI, TAU};

use crate::Error;
use crate::mechanism::Kind;
use crate::sweep::Table;

/// The Grashof class of a four-bar, by which link is the shortest and
/// how S + L (shortest and longest) compares with P + Q (the other two).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GrashofClass {
    /// S + L < P + Q, the input link the shortest: the input turns fully,
    /// the output rocks.
    CrankRocker,
    /// S + L < P + Q, the ground the shortest: both side links turn
    /// fully (a drag link).
    DoubleCrank,
    /// S + L < P + Q, the output link the shortest: the output turns
    /// fully, the input rocks.
    RockerCrank,
    /// S + L < P + Q, the coupler the shortest: both side links rock,
    /// the coupler turns fully.
    DoubleRocker,
    /// S + L > P + Q (non-Grashof): no link turns fully relative to
    /// another; every side link rocks.
    TripleRocker,
    /// S + L = P + Q (to 1e-12 of P + Q): the links can fold into one line
    /// (a change point, where the assembly may switch branches).
    ChangePoint,
}

impl GrashofClass {
    /// The class as a designer names it.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            GrashofClass::CrankRocker => "Grashof crank-rocker (the input turns fully)",
            GrashofClass::DoubleCrank => "Grashof double-crank (drag link; both side links turn)",
            GrashofClass::RockerCrank => "Grashof rocker-crank (the output turns fully)",
            GrashofClass::DoubleRocker => "Grashof double-rocker (the coupler turns fully)",
            GrashofClass::TripleRocker => "non-Grashof triple-rocker (no link turns fully)",
            GrashofClass::ChangePoint => "change point (S + L = P + Q: the links can fold flat)",
        }
    }
}

/// A four-bar's Grashof class and its two sums.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grashof {
    /// The class.
    pub class: GrashofClass,
    /// S + L, the shortest and the longest link.
    pub s_plus_l: f64,
    /// P + Q, the other two.
    pub p_plus_q: f64,
}

/// The Grashof class of the four-bar with these link lengths: the ground
/// (between the fixed pivots), the input link, the coupler and the output
/// link. S + L < P + Q: some link turns fully (which one by which is the
/// shortest); S + L > P + Q: none does; S + L = P + Q (to 1e-12): a
/// change point.
///
/// # Errors
/// [`Error::InvalidGeometry`] for a length that is not positive and
/// finite, or a longest link at least the sum of the others (the loop
/// cannot close).
pub fn grashof(ground: f64, input: f64, coupler: f64, output: f64) -> Result<Grashof, Error> {
    let links = [ground, input, coupler, output];
    let invalid = |detail| Error::InvalidGeometry {
        what: "grashof",
        detail,
    };
    if let Some(bad) = links.iter().find(|l| !(l.is_finite() && **l > 0.0)) {
        return Err(invalid(format!(
            "a link length is {bad}: give the four lengths (ground, input, coupler, output) as \
             positive numbers"
        )));
    }
    let total: f64 = links.iter().sum();
    let (mut s, mut l) = (0, 0);
    for (i, &x) in links.iter().enumerate() {
        if x < links[s] {
            s = i;
        }
        if x > links[l] {
            l = i;
        }
    }
    if links[l] >= total - links[l] {
        return Err(invalid(format!(
            "the longest link ({}) is at least the sum of the other three ({}): the loop cannot \
             close",
            links[l],
            total - links[l]
        )));
    }
    let s_plus_l = links[s] + links[l];
    // The other two, added as they are (not as a difference of sums).
    let (mut others, mut k) = ([0.0; 2], 0);
    for (i, &x) in links.iter().enumerate() {
        if i != s && i != l && k < 2 {
            others[k] = x;
            k += 1;
        }
    }
    let p_plus_q = others[0] + others[1];
    let class = if (s_plus_l - p_plus_q).abs() <= 1e-12 * p_plus_q {
        GrashofClass::ChangePoint
    } else if s_plus_l > p_plus_q {
        GrashofClass::TripleRocker
    } else {
        match s {
            0 => GrashofClass::DoubleCrank,
            1 => GrashofClass::CrankRocker,
            2 => GrashofClass::DoubleRocker,
            _ => GrashofClass::RockerCrank,
        }
    };
    Ok(Grashof {
        class,
        s_plus_l,
        p_plus_q,
    })
}

/// The transmission angle μ ∈ [0, π] between two links whose directions
/// are the angles `first` and `second` (a four-bar's coupler θ3 and
/// output link θ4): μ = arccos(cos(θ4 − θ3)), the angle of the triangle
/// at their common joint. Force is transmitted best at μ = 90°; designers
/// keep μ within [μ_min, 180° − μ_min], μ_min about 40°.
#[must_use]
pub fn transmission_angle(first: f64, second: f64) -> f64 {
    let d = second - first;
    crate::math::atan2(crate::math::sin(d), crate::math::cos(d)).abs()
}

/// The transmission angle over a sweep, with its extremes.
#[derive(Clone, Debug, PartialEq)]
pub struct Transmission {
    /// μ at every sample (rad).
    pub values: Vec<f64>,
    /// The least μ, and the swept value where it occurs.
    pub min: (f64, f64),
    /// The largest μ, and the swept value where it occurs.
    pub max: (f64, f64),
}

impl Transmission {
    /// The largest departure of μ from 90° over the sweep (rad): 0 is
    /// ideal; a designer keeps it below about 50°.
    #[must_use]
    pub fn worst_departure(&self) -> f64 {
        (PI / 2.0 - self.min.1).max(self.max.1 - PI / 2.0)
    }
}

/// The transmission angle between the links of directions `first` and
/// `second` (coordinate names: a four-bar's `th3` and `th4`) at every
/// sample of `table`, with its least and largest values.
///
/// # Errors
/// [`Error::InvalidGeometry`] for a name that is not an angle coordinate
/// of the table, or a table with no samples.
pub fn transmission<T: Table + ?Sized>(
    table: &T,
    first: &str,
    second: &str,
) -> Result<Transmission, Error> {
    let (a, b) = (
        angle_index(table, first, "transmission")?,
        angle_index(table, second, "transmission")?,
    );
    nonempty(table, "transmission")?;
    let values: Vec<f64> = (0..table.rows())
        .map(|i| transmission_angle(table.coordinate(i, a, 0), table.coordinate(i, b, 0)))
        .collect();
    let (mut min, mut max) = ((table.at(0), values[0]), (table.at(0), values[0]));
    for (i, &v) in values.iter().enumerate() {
        if v < min.1 {
            min = (table.at(i), v);
        }
        if v > max.1 {
            max = (table.at(i), v);
        }
    }
    Ok(Transmission { values, min, max })
}

/// A dead centre of an output coordinate: where its rate changes sign
/// (dq/dφ = 0), a limit of its motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeadCentre {
    /// The swept value there (for a turn, within [start, start + 2π)).
    pub at: f64,
    /// The output's value there.
    pub value: f64,
    /// Whether it is a maximum of the output (else a minimum).
    pub maximum: bool,
}

/// The dead centres of coordinate `name` over `table`: every zero of
/// dq/dφ between two samples where it changes sign (a sample where it is
/// exactly 0 is one), located on the Hermite interpolant (see the module's
/// documentation). For a sweep over one full turn of an angle driver
/// (the closing sample left out, as `turn()` sweeps, or included), the
/// interval from the last sample back to the first is searched too.
///
/// # Errors
/// [`Error::InvalidGeometry`] for a name that is not a coordinate of the
/// table, or a table with fewer than two samples or whose swept rate is
/// 0 somewhere.
pub fn dead_centres<T: Table + ?Sized>(table: &T, name: &str) -> Result<Vec<DeadCentre>, Error> {
    let j = index(table, name, "dead_centres")?;
    let n = table.rows();
    if n < 2 {
        return Err(Error::InvalidGeometry {
            what: "dead_centres",
            detail: format!("the sweep has {n} sample(s): dead centres need at least two"),
        });
    }
    let samples = slopes(table, j)?;
    let wrap = closing(table);
    let mut pairs: Vec<(Slope, Slope)> = samples.windows(2).map(|w| (w[0], w[1])).collect();
    if let Some(period) = wrap {
        let (last, first) = (samples[n - 1], samples[0]);
        pairs.push((
            last,
            Slope {
                x: first.x + period,
                ..first
            },
        ));
    }
    let mut out = Vec::new();
    for (k, &(p, q)) in pairs.iter().enumerate() {
        if p.g == 0.0 {
            out.push(DeadCentre {
                at: p.x,
                value: p.q,
                maximum: p.dg < 0.0,
            });
            continue;
        }
        if q.g == 0.0 {
            // Found as the next interval's start (or, at the end of a
            // sweep that is no turn, here).
            if k + 1 == pairs.len() && wrap.is_none() {
                out.push(DeadCentre {
                    at: q.x,
                    value: q.q,
                    maximum: q.dg < 0.0,
                });
            }
            continue;
        }
        if p.g.signum() == q.g.signum() {
            continue;
        }
        // Bisection on the cubic Hermite interpolant of dq/dφ.
        let h = q.x - p.x;
        let slope_at = |t: f64| hermite(t, p.g, q.g, p.dg * h, q.dg * h);
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if slope_at(mid).signum() == p.g.signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let t = 0.5 * (lo + hi);
        let mut at = p.x + t * h;
        // The closing interval's dead centre, within the turn.
        if let Some(period) = wrap.filter(|_| k + 1 == pairs.len())
            && (at - samples[0].x).abs() >= period.abs()
        {
            at -= period;
        }
        out.push(DeadCentre {
            at,
            value: hermite(t, p.q, q.q, p.g * h, q.g * h),
            // dq/dφ from + to − along increasing φ.
            maximum: (p.g > 0.0) == (h > 0.0),
        });
    }
    Ok(out)
}

/// The stroke of coordinate `name` (a slider's travel, a rocker's
/// swing): its least and largest values over the sweep, the dead centres
/// between samples included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// The least value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
}

impl Stroke {
    /// max − min.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.max - self.min
    }
}

/// The stroke of coordinate `name` over `table`.
///
/// # Errors
/// As [`dead_centres`].
pub fn stroke<T: Table + ?Sized>(table: &T, name: &str) -> Result<Stroke, Error> {
    let j = index(table, name, "stroke")?;
    let mut s = Stroke {
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
    };
    for v in (0..table.rows())
        .map(|i| table.coordinate(i, j, 0))
        .chain(dead_centres(table, name)?.iter().map(|d| d.value))
    {
        s.min = s.min.min(v);
        s.max = s.max.max(v);
    }
    Ok(s)
}

/// The time ratio of a quick-return: at constant input speed, the input
/// angle spent from one dead centre of the output to the other, over the
/// angle spent coming back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeRatio {
    /// The input angle from the output's minimum to its maximum (rad).
    pub rising: f64,
    /// The input angle from its maximum back to its minimum (rad).
    pub falling: f64,
}

impl TimeRatio {
    /// The slower stroke's angle over the faster one's (≥ 1).
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.rising.max(self.falling) / self.rising.min(self.falling)
    }
}

/// The time ratio of output `name` over a sweep of one full turn of an
/// angle driver at constant speed: from its two dead centres.
///
/// # Errors
/// [`Error::InvalidGeometry`] unless the table is a turn of an angle
/// driver and the output has exactly two dead centres in it (one maximum,
/// one minimum); as [`dead_centres`].
pub fn time_ratio<T: Table + ?Sized>(table: &T, name: &str) -> Result<TimeRatio, Error> {
    if closing(table).is_none() {
        return Err(Error::InvalidGeometry {
            what: "time_ratio",
            detail: format!(
                "the sweep of {} is not one full turn of an angle driver: sweep a turn \
                 (`turn()`, `--turn`) at constant speed",
                table.variable()
            ),
        });
    }
    let d = dead_centres(table, name)?;
    match d.as_slice() {
        [a, b] if a.maximum != b.maximum => {
            let (max, min) = if a.maximum { (a, b) } else { (b, a) };
            // Both within one turn: the difference within (−2π, 2π).
            let d = max.at - min.at;
            let rising = if d < 0.0 { d + TAU } else { d };
            Ok(TimeRatio {
                rising,
                falling: TAU - rising,
            })
        }
        _ => Err(Error::InvalidGeometry {
            what: "time_ratio",
            detail: format!(
                "`{name}` has {} dead centre(s) over the turn: a time ratio needs exactly two \
                 (one forward and one return stroke)",
                d.len()
            ),
        }),
    }
}

/// The value of a cubic Hermite interpolant at t ∈ [0, 1] with values
/// y0, y1 and derivatives (times the interval) m0, m1.
fn hermite(t: f64, y0: f64, y1: f64, m0: f64, m1: f64) -> f64 {
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + t) * m0
        + (-2.0 * t3 + 3.0 * t2) * y1
        + (t3 - t2) * m1
}

/// A sample as the search reads it: the swept value, q, dq/dφ, d²q/dφ².
#[derive(Clone, Copy)]
struct Slope {
    x: f64,
    q: f64,
    g: f64,
    dg: f64,
}

/// Each sample's q, dq/dφ and d²q/dφ² for coordinate `j`, from its rates
/// and accelerations and the swept variable's (for a simulation, with
/// respect to time).
fn slopes<T: Table + ?Sized>(table: &T, j: usize) -> Result<Vec<Slope>, Error> {
    let driver = table
        .coordinates()
        .iter()
        .position(|c| c.name == table.variable());
    (0..table.rows())
        .map(|i| {
            let (q, qd, qdd) = (
                table.coordinate(i, j, 0),
                table.coordinate(i, j, 1),
                table.coordinate(i, j, 2),
            );
            let (rate, accel) = match driver {
                Some(d) => (table.coordinate(i, d, 1), table.coordinate(i, d, 2)),
                None => (1.0, 0.0),
            };
            if rate == 0.0 || !rate.is_finite() {
                return Err(Error::InvalidGeometry {
                    what: "dead_centres",
                    detail: format!(
                        "the rate of {} is {rate} at sample {i}: sweep it at a nonzero rate",
                        table.variable()
                    ),
                });
            }
            let g = qd / rate;
            Ok(Slope {
                x: table.at(i),
                q,
                g,
                dg: (qdd - g * accel) / (rate * rate),
            })
        })
        .collect()
}

/// The mechanical advantage of an output over a sweep: the ratio of the
/// output's effort to the input's with no losses and no inertia, from the
/// conservation of power Q_in φ' = Q_out q': MA = Q_out / Q_in = φ' / q',
/// the swept driver's rate over the output's (N·m per N·m for an angle
/// output, N per N·m, 1/m, for a length). It is infinite at the
/// output's dead centres (the toggle positions, where q' = 0); where it
/// is least, the input must push hardest for a given output load.
#[derive(Clone, Debug, PartialEq)]
pub struct MechanicalAdvantage {
    /// MA at every sample, signed (negative where the output moves against
    /// the input's sense); ±∞ where the output's rate is 0.
    pub values: Vec<f64>,
    /// The swept value where |MA| is least, and that least |MA|.
    pub least: (f64, f64),
}

/// The mechanical advantage of coordinate `output` at every sample of
/// `table` ([`MechanicalAdvantage`]): the input is the swept driver, or
/// for a motion over time the mechanism's one driver.
///
/// ```
/// use kinematics_core::{mechanism, merit::mechanical_advantage};
/// mechanism! {
///     /// A four-bar: crank a, coupler b, rocker c, ground d.
///     pub struct FourBar {
///         params { a, b, c, d }
///         drivers { phi }
///         unknowns { th3, th4 }
///         points { B = polar(a, phi); D = vec2(d, 0.0); C = D + polar(c, th4); }
///         loops { B + polar(b, th3) == C; }
///     }
/// }
/// let (a, c) = (0.04, 0.1);
/// let m = FourBar { a, b: 0.12, c, d: 0.11 };
/// let start = m.assemble(&FourBarCoords { phi: 0.0, th3: 1.0, th4: 1.6 })?;
/// let s = m.sweep(FourBar::PHI, &start).to(1.0).steps(10).run();
/// let ma = mechanical_advantage(&s, "th4")?;
/// // The velocity loop dotted with the coupler's direction:
/// // a φ' sin(φ − θ3) = c θ4' sin(θ4 − θ3).
/// for (sample, v) in s.samples.iter().zip(&ma.values) {
///     let FourBarCoords { phi, th3, th4 } = sample.motion.q;
///     let exact = c * (th4 - th3).sin() / (a * (phi - th3).sin());
///     assert!((v - exact).abs() < 1e-9 * exact.abs());
/// }
/// # Ok::<(), kinematics_core::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGeometry`] for a name that is not a coordinate of the
/// table (or is the swept driver), a table with no samples, or one over
/// time of a mechanism with several drivers.
pub fn mechanical_advantage<T: Table + ?Sized>(
    table: &T,
    output: &str,
) -> Result<MechanicalAdvantage, Error> {
    let j = index(table, output, "mechanical_advantage")?;
    nonempty(table, "mechanical_advantage")?;
    // The input: the swept driver, or over time the one driver.
    let coordinates = table.coordinates();
    let driver = match coordinates.iter().position(|c| c.name == table.variable()) {
        Some(d) => d,
        None => {
            let drivers: Vec<usize> = (0..coordinates.len())
                .filter(|&k| coordinates[k].role == crate::mechanism::Role::Driver)
                .collect();
            match drivers[..] {
                [d] => d,
                _ => {
                    return Err(Error::InvalidGeometry {
                        what: "mechanical_advantage",
                        detail: format!(
                            "the sweep runs over `{}`, and the mechanism has {} drivers: \
                             the input is the one driver swept, so sweep a driver",
                            table.variable(),
                            drivers.len()
                        ),
                    });
                }
            }
        }
    };
    if driver == j {
        return Err(Error::InvalidGeometry {
            what: "mechanical_advantage",
            detail: format!("`{output}` is the swept driver: name an output coordinate"),
        });
    }
    let values: Vec<f64> = (0..table.rows())
        .map(|i| {
            let rate = table.coordinate(i, driver, 1);
            let out = table.coordinate(i, j, 1);
            if out == 0.0 {
                f64::INFINITY.copysign(rate)
            } else {
                rate / out
            }
        })
        .collect();
    let mut least = (table.at(0), values[0].abs());
    for (i, v) in values.iter().enumerate() {
        if v.abs() < least.1 {
            least = (table.at(i), v.abs());
        }
    }
    Ok(MechanicalAdvantage { values, least })
}

/// For a sweep of one full turn of an angle driver, the period to add to
/// the first sample to close the last interval (`None` where the table
/// is no such turn, or already holds the closing sample).
fn closing<T: Table + ?Sized>(table: &T) -> Option<f64> {
    if table.kind() != Kind::Angle || table.variable() == "t" {
        return None;
    }
    crate::sweep::closing_period(table.rows(), |i| table.at(i))
}

fn index<T: Table + ?Sized>(table: &T, name: &str, what: &'static str) -> Result<usize, Error> {
    table
        .coordinates()
        .iter()
        .position(|c| c.name == name)
        .ok_or_else(|| {
            let names: Vec<&str> = table.coordinates().iter().map(|c| c.name).collect();
            Error::InvalidGeometry {
                what,
                detail: format!(
                    "the sweep has no coordinate `{name}`; its coordinates are {}",
                    names.join(", ")
                ),
            }
        })
}

fn angle_index<T: Table + ?Sized>(
    table: &T,
    name: &str,
    what: &'static str,
) -> Result<usize, Error> {
    let j = index(table, name, what)?;
    if table.coordinates()[j].kind == Kind::Angle {
        Ok(j)
    } else {
        Err(Error::InvalidGeometry {
            what,
            detail: format!("`{name}` is a length: a transmission angle is between two angles"),
        })
    }
}

fn nonempty<T: Table + ?Sized>(table: &T, what: &'static str) -> Result<(), Error> {
    if table.rows() == 0 {
        return Err(Error::InvalidGeometry {
            what,
            detail: "the sweep has no samples".into(),
        });
    }
    Ok(())
}
