//! The forces along a sweep ([`ForceSweep`]): per sample, each driver's
//! effort, the energies, the power and the shaking force and moment; the
//! mean effort over the range, the fluctuation of energy a flywheel must
//! absorb, and a CSV table with units.

use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt::Write as _;

use nalgebra::Vector3;

use super::{Dynamics, Forces, Reactions};
use crate::error::Error;
use crate::mechanism::{Coordinates, Kind, Mechanism, Role};
use crate::sweep::Sweep;

/// The forces at one sample of a sweep.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ForceSample {
    /// The swept driver's value.
    pub at: f64,
    /// Each driver's effort, in declaration order (N·m or N).
    pub effort: Vec<f64>,
    /// Kinetic energy (J).
    pub kinetic_energy: f64,
    /// Potential energy (J).
    pub potential_energy: f64,
    /// The drivers' power (W).
    pub power: f64,
    /// Shaking force on the frame (N).
    pub shaking_force: Vector3<f64>,
    /// Shaking moment on the frame about the origin (N·m).
    pub shaking_moment: Vector3<f64>,
    /// The total force of the mechanism on the frame, weights and loads
    /// included ([`Forces::frame_force`]: Norton's shaking force where
    /// every point load comes from outside the machine; N).
    pub frame_force: Vector3<f64>,
    /// Its moment about the origin ([`Forces::frame_moment`]; N·m).
    pub frame_moment: Vector3<f64>,
    /// The joint reactions, where the description declares joints
    /// ([`Dynamics::reactions`]).
    pub reactions: Option<Reactions>,
}

/// The forces along a sweep ([`Dynamics::along`]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ForceSweep {
    /// The swept driver.
    pub variable: String,
    /// Whether it is an angle or a length.
    pub kind: Kind,
    /// The drivers' names and kinds, in declaration order.
    pub drivers: Vec<(String, Kind)>,
    /// One per sample of the sweep, in its order.
    pub samples: Vec<ForceSample>,
}

impl ForceSample {
    /// The sample at `at` of the forces `f`, its drivers' efforts
    /// `effort` and the `reactions`.
    pub(crate) fn new<C>(
        at: f64,
        effort: Vec<f64>,
        f: &Forces<C>,
        reactions: Option<Reactions>,
    ) -> Self {
        ForceSample {
            at,
            effort,
            kinetic_energy: f.kinetic_energy,
            potential_energy: f.potential_energy,
            power: f.power,
            shaking_force: f.shaking_force,
            shaking_moment: f.shaking_moment,
            frame_force: f.frame_force,
            frame_moment: f.frame_moment,
            reactions,
        }
    }
}

impl ForceSweep {
    /// The mean effort of driver `k` over the swept range,
    /// (1/(s_n − s_0)) ∫ Q_k ds by the trapezoidal rule over the samples
    /// (s the swept value): for a crank turned at constant speed, the mean
    /// torque. Over one turn of an angle driver whose closing sample is
    /// left out (a sweep of `.turn()`), the interval from the last sample
    /// back to the first closes the cycle (the periodic trapezoidal rule,
    /// the samples' plain mean for equal steps, exact for the harmonics
    /// below half the number of samples): a conservative cycle's mean is 0
    /// to round-off. `None` with fewer than two samples, no such driver, or
    /// efforts whose integral overflows.
    #[must_use]
    pub fn mean_effort(&self, k: usize) -> Option<f64> {
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        let span = last.at - first.at;
        if self.samples.len() < 2 || span == 0.0 || k >= self.drivers.len() {
            return None;
        }
        let work = self.work(k).last().copied().unwrap_or(0.0);
        let mean = match self.closing() {
            Some(period) => {
                let effort = |s: &ForceSample| s.effort.get(k).copied().unwrap_or(f64::NAN);
                let closing = 0.5 * (effort(last) + effort(first)) * (first.at + period - last.at);
                (work + closing) / period
            }
            None => work / span,
        };
        mean.is_finite().then_some(mean)
    }

    /// For a sweep of one turn of an angle driver with the closing sample
    /// left out (the last sample one step short of the first plus 2π, to
    /// 1e-9 of a turn), the period ±2π; else `None`.
    fn closing(&self) -> Option<f64> {
        if self.kind != Kind::Angle {
            return None;
        }
        crate::sweep::closing_period(self.samples.len(), |i| self.samples[i].at)
    }

    /// The work of driver `k`'s effort from the first sample to each,
    /// W(s) = ∫ Q_k ds (trapezoidal; zero at the first).
    fn work(&self, k: usize) -> Vec<f64> {
        let mut w = Vec::with_capacity(self.samples.len());
        let mut sum = 0.0;
        let effort = |s: &ForceSample| s.effort.get(k).copied().unwrap_or(f64::NAN);
        for (i, s) in self.samples.iter().enumerate() {
            if let Some(p) = i.checked_sub(1).and_then(|p| self.samples.get(p)) {
                sum += 0.5 * (effort(p) + effort(s)) * (s.at - p.at);
            }
            w.push(sum);
        }
        w
    }

    /// The largest fluctuation of energy about the mean effort of driver
    /// `k`: ΔE = max − min over the samples of ∫ (Q_k − Q̄_k) ds, the energy
    /// a flywheel on the driver's shaft must store and give back for the
    /// driver to supply the mean effort only. With the flywheel's moment
    /// of inertia I and the mean speed ω, the coefficient of speed
    /// fluctuation is C_s = (ω_max − ω_min)/ω ≈ ΔE / (I ω²); the flywheel
    /// for a wanted C_s is I = ΔE / (C_s ω²). `None` as for
    /// [`ForceSweep::mean_effort`].
    #[must_use]
    pub fn energy_fluctuation(&self, k: usize) -> Option<f64> {
        let mean = self.mean_effort(k)?;
        let first = self.samples.first()?.at;
        let (lo, hi) = self
            .work(k)
            .iter()
            .zip(&self.samples)
            .map(|(w, s)| w - mean * (s.at - first))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
                (lo.min(e), hi.max(e))
            });
        let delta = hi - lo;
        delta.is_finite().then_some(delta)
    }

    /// The coefficient of speed fluctuation of driver `k` with a flywheel of
    /// moment of inertia `inertia` (kg·m², the whole rotating inertia on
    /// the driver's shaft) at the mean speed `speed` (rad/s):
    /// C_s = ΔE / (I ω²), with ΔE the [`ForceSweep::energy_fluctuation`].
    /// `None` as for [`ForceSweep::mean_effort`], or when I ω² is not
    /// positive.
    #[must_use]
    pub fn speed_fluctuation(&self, k: usize, inertia: f64, speed: f64) -> Option<f64> {
        let energy = inertia * speed * speed;
        if !(energy > 0.0 && energy.is_finite()) {
            return None;
        }
        let c = self.energy_fluctuation(k)? / energy;
        c.is_finite().then_some(c)
    }

    /// The table as CSV, a column per quantity with its unit in the header:
    /// the swept value (deg for an angle), each driver's effort (N·m for an
    /// angle, N for a length), T, V and the power, the shaking force and
    /// moment's components (`Fs`, `Ms`: the inertial part), the total force
    /// and moment on the frame (`Ff`, `Mf`: weights and loads included,
    /// Norton's shaking force), and for each joint of the reactions the x and y
    /// of its force and its moment's z (every component of both in a
    /// spatial mechanism).
    #[must_use]
    pub fn to_csv(&self) -> String {
        let angle = self.kind == Kind::Angle;
        let mut out = String::new();
        let _ = write!(
            out,
            "{} ({})",
            self.variable,
            if angle { "deg" } else { "m" }
        );
        for (name, kind) in &self.drivers {
            let unit = if *kind == Kind::Angle { "N·m" } else { "N" };
            let _ = write!(out, ",Q_{name} ({unit})");
        }
        out.push_str(
            ",T (J),V (J),P (W),Fs_x (N),Fs_y (N),Fs_z (N),Ms_x (N·m),Ms_y (N·m),Ms_z (N·m),\
             Ff_x (N),Ff_y (N),Ff_z (N),Mf_x (N·m),Mf_y (N·m),Mf_z (N·m)",
        );
        let joints = self.samples.first().and_then(|s| s.reactions.as_ref());
        let spatial = joints.is_some_and(|r| r.spatial);
        for j in joints.map_or(&[][..], |r| &r.joints[..]) {
            if spatial {
                let _ = write!(
                    out,
                    ",R_{0}_x (N),R_{0}_y (N),R_{0}_z (N),M_{0}_x (N·m),M_{0}_y (N·m),M_{0}_z (N·m)",
                    j.name
                );
            } else {
                let _ = write!(out, ",R_{0}_x (N),R_{0}_y (N),M_{0} (N·m)", j.name);
            }
        }
        out.push('\n');
        for s in &self.samples {
            let at = if angle { s.at.to_degrees() } else { s.at };
            let _ = write!(out, "{at}");
            for e in &s.effort {
                let _ = write!(out, ",{e}");
            }
            let f = s.shaking_force;
            let m = s.shaking_moment;
            let _ = write!(
                out,
                ",{},{},{},{},{},{},{},{},{}",
                s.kinetic_energy, s.potential_energy, s.power, f.x, f.y, f.z, m.x, m.y, m.z
            );
            let (f, m) = (s.frame_force, s.frame_moment);
            let _ = write!(out, ",{},{},{},{},{},{}", f.x, f.y, f.z, m.x, m.y, m.z);
            for j in s.reactions.as_ref().map_or(&[][..], |r| &r.joints[..]) {
                let (f, m) = (j.force, j.moment);
                if spatial {
                    let _ = write!(out, ",{},{},{},{},{},{}", f.x, f.y, f.z, m.x, m.y, m.z);
                } else {
                    let _ = write!(out, ",{},{},{}", f.x, f.y, m.z);
                }
            }
            out.push('\n');
        }
        out
    }
}

impl Dynamics {
    /// The forces at every sample of `sweep`, a sweep of `m`
    /// ([`Dynamics::inverse`] at each, and [`Dynamics::reactions`] where
    /// the description declares joints).
    ///
    /// # Errors
    /// As [`Dynamics::inverse`] and [`Dynamics::reactions`], at the first
    /// sample where one fails.
    pub fn along<M: Mechanism>(&self, m: &M, sweep: &Sweep<M>) -> Result<ForceSweep, Error> {
        let drivers = M::COORDINATES
            .iter()
            .filter(|c| c.role == Role::Driver)
            .map(|c| (c.name.to_string(), c.kind))
            .collect();
        self.sweep_of(sweep.variable, sweep.kind, drivers, &sweep.samples, |s| {
            let f = self.inverse(m, &s.motion)?;
            let reactions = self
                .has_joints()
                .then(|| self.reactions(m, &s.motion))
                .transpose()?;
            let effort = (0..M::DRIVERS)
                .map(|k| f.effort.get(k).unwrap_or(f64::NAN))
                .collect();
            Ok(ForceSample::new(s.at, effort, &f, reactions))
        })
    }

    /// Whether the description declares joints (then the sweeps carry the
    /// reactions).
    pub(crate) fn has_joints(&self) -> bool {
        !self.joints.is_empty()
    }

    /// The sweep of forces of the swept `variable` of `kind`, with the
    /// `drivers`' names and kinds, from `sample` at each of `samples`.
    pub(crate) fn sweep_of<S>(
        &self,
        variable: &str,
        kind: Kind,
        drivers: Vec<(String, Kind)>,
        samples: &[S],
        mut sample: impl FnMut(&S) -> Result<ForceSample, Error>,
    ) -> Result<ForceSweep, Error> {
        let samples = samples
            .iter()
            .map(&mut sample)
            .collect::<Result<Vec<_>, _>>()?;
        Ok(ForceSweep {
            variable: variable.to_string(),
            kind,
            drivers,
            samples,
        })
    }
}
