//! The equations of motion as the integrators see them: a first-order
//! system in the free drivers, their rates and the works (and, where
//! asked, the sensitivities of the first two to the parameters).

use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

use super::equations::{Equations, cholesky_apply, cholesky_solve};
use super::ode::System;
use super::run::Analysis;
use crate::dynamics::Dynamics;
use crate::dynamics::terms::Terms;
use crate::error::Error;
use crate::math::{copy_small, zero_small};

/// The equations of motion as a first-order system: y = (d_f, ḋ_f, W, S),
/// y' = (ḋ_f, d̈_f, P, Ṡ), W the works of the loads and prescribed
/// drivers, S = ∂(d_f, ḋ_f)/∂p for each sensitivity parameter p (none
/// unless asked).
pub(super) struct Eom<'d, A> {
    pub(super) analysis: A,
    pub(super) dynamics: &'d Dynamics,
    pub(super) free: Vec<usize>,
    /// The prescribed drivers.
    pub(super) prescribed: Vec<usize>,
    pub(super) nd: usize,
    /// The drivers' values, rates and accelerations of the last
    /// evaluation.
    pub(super) d: Vec<f64>,
    pub(super) dd: Vec<f64>,
    pub(super) ddd: Vec<f64>,
    pub(super) mass: Vec<f64>,
    pub(super) bias: Vec<f64>,
    pub(super) powers: Vec<f64>,
    pub(super) partials: Vec<[nalgebra::Vector3<f64>; 2]>,
    pub(super) terms: Terms,
    /// Each driver's effort at the last evaluation's accelerations: zero
    /// for a free one, Q_p = b_p + M_pf d̈_f for a prescribed one.
    pub(super) effort: Vec<f64>,
    /// The drivers' names, for messages.
    pub(super) names: Vec<String>,
    /// M_ff, then its factor; −b_f, then d̈_f.
    pub(super) mff: Vec<f64>,
    pub(super) x: Vec<f64>,
    /// The number of sensitivity parameters (0: none asked).
    pub(super) parameters: usize,
    /// ∂Q_k/∂p at the actual accelerations, parameter-major.
    pub(super) effort_partials: Vec<f64>,
    /// ∂d̈_f/∂(d_f, ḋ_f) (nf × 2nf, row-major) and a scratch state.
    pub(super) jacobian: Vec<f64>,
    pub(super) scratch: Vec<f64>,
    /// The sensitivities at the output samples.
    pub(super) recorded: Vec<Vec<f64>>,
    /// The number of stops, each with the work of its impacts in the
    /// state after the prescribed drivers'.
    pub(super) stops: usize,
    /// One free driver, none prescribed and no sensitivities: the
    /// evaluation takes `rhs_one`.
    pub(super) lean: bool,
}

impl<A: Analysis> Eom<'_, A> {
    /// The drivers at (t, y), the free accelerations zero.
    #[inline(always)]
    pub(super) fn set_drivers(&mut self, t: f64, y: &[f64]) {
        let nf = self.free.len();
        // (Every driver free: each is written below.)
        if !self.prescribed.is_empty() {
            self.analysis
                .profile(t, &mut self.d, &mut self.dd, &mut self.ddd);
        }
        for (i, &k) in self.free.iter().enumerate() {
            self.d[k] = y[i];
            self.dd[k] = y[nf + i];
            self.ddd[k] = 0.0;
        }
    }

    /// M, b and the powers at the drivers' motion `d`, `dd`, `ddd` and
    /// time t: the mechanism assembled and analysed there.
    #[inline(always)]
    fn equations_at(&mut self, t: f64) -> Result<(), Error> {
        self.analysis
            .analyze_for_equations(&self.d, &self.dd, &self.ddd)?;
        let mut out = Equations {
            mass: &mut self.mass,
            bias: &mut self.bias,
            powers: &mut self.powers,
            partials: &mut self.partials,
            terms: &mut self.terms,
        };
        self.analysis.equations(self.dynamics, t, &mut out)
    }

    /// The free drivers' accelerations at (t, y) into `x`: the mechanism
    /// assembled and analysed there, M_ff d̈_f = −b_f solved; M and b
    /// kept.
    #[inline(always)]
    fn accelerations(&mut self, t: f64, y: &[f64]) -> Result<(), Error> {
        let nf = self.free.len();
        self.set_drivers(t, y);
        self.equations_at(t)?;
        for (i, &k) in self.free.iter().enumerate() {
            self.x[i] = -self.bias[k];
            for (j, &l) in self.free.iter().enumerate() {
                self.mff[i * nf + j] = self.mass[k * self.nd + l];
            }
        }
        if let Err(i) = cholesky_solve(&mut self.mff, &mut self.x, nf) {
            return Err(self.singular(i));
        }
        Ok(())
    }

    /// The error of a mass matrix of the free drivers that is singular at
    /// free driver `i`.
    #[cold]
    fn singular(&self, i: usize) -> Error {
        let name = self
            .free
            .get(i)
            .and_then(|&k| self.names.get(k))
            .map_or("?", String::as_str);
        Error::InvalidDynamics {
            item: format!("free driver `{name}`"),
            detail: "moves no mass or inertia of its own at this pose (the mass matrix \
                     of the free drivers is singular): give the bodies it moves their \
                     masses and moments of inertia, or prescribe it"
                .to_string(),
        }
    }

    /// [`System::rhs`] where the evaluation is `lean`: the same
    /// numbers as the general way (d̈ = −b/M, the powers, the stops'
    /// works unchanged), with none of its loops over the drivers. The
    /// prescribed drivers' efforts are none, so `effort` stays zero.
    #[inline(always)]
    fn rhs_one(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let (Some(&[d, dd]), Some((head, rest)), Some(&k)) = (
            y.first_chunk::<2>(),
            dy.split_first_chunk_mut::<2>(),
            self.free.first(),
        ) else {
            return Err(short());
        };
        let (Some(dk), Some(ddk), Some(dddk)) =
            (self.d.get_mut(k), self.dd.get_mut(k), self.ddd.get_mut(k))
        else {
            return Err(short());
        };
        (*dk, *ddk, *dddk) = (d, dd, 0.0);
        self.equations_at(t)?;
        let (Some(&m), Some(&b), Some(factor), Some(x)) = (
            self.mass.get(k * self.nd + k),
            self.bias.get(k),
            self.mff.first_mut(),
            self.x.first_mut(),
        ) else {
            return Err(short());
        };
        let (mut f, mut r) = ([m], [-b]);
        if cholesky_solve(&mut f, &mut r, 1).is_err() {
            return Err(self.singular(0));
        }
        (*factor, *x) = (f[0], r[0]);
        *head = [dd, r[0]];
        let Some((p, works)) = rest.split_at_mut_checked(self.powers.len()) else {
            return Err(short());
        };
        copy_small(p, &self.powers);
        // The impacts' works change at the impacts only.
        zero_small(works);
        Ok(())
    }

    /// ∂d̈_f/∂(d_f, ḋ_f) at (t, y) by central differences of the
    /// accelerations, into `jacobian` (each component moved by
    /// ε (1 + |y_j|), ε = 6e-6, the cube root of the resolution).
    fn acceleration_jacobian(&mut self, t: f64, y: &[f64]) -> Result<(), Error> {
        let nf = self.free.len();
        let mut point = core::mem::take(&mut self.scratch);
        point.clear();
        point.extend_from_slice(&y[..2 * nf]);
        let mut result = Ok(());
        for j in 0..2 * nf {
            let step = 6e-6 * (1.0 + y[j].abs());
            point[j] = y[j] + step;
            if let Err(e) = self.accelerations(t, &point) {
                result = Err(e);
                break;
            }
            for i in 0..nf {
                self.jacobian[i * 2 * nf + j] = self.x[i];
            }
            point[j] = y[j] - step;
            if let Err(e) = self.accelerations(t, &point) {
                result = Err(e);
                break;
            }
            for i in 0..nf {
                let up = self.jacobian[i * 2 * nf + j];
                self.jacobian[i * 2 * nf + j] = (up - self.x[i]) / (2.0 * step);
            }
            point[j] = y[j];
        }
        self.scratch = point;
        result
    }

    /// Where the sensitivities start in the state.
    pub(super) fn sensitivity_offset(&self) -> usize {
        self.stop_offset() + self.stops
    }

    /// Where the works of the impacts start in the state.
    pub(super) fn stop_offset(&self) -> usize {
        2 * self.free.len() + self.powers.len() + self.prescribed.len()
    }

    /// The impact at a stop on coordinate `j`, restitution `e`, at the
    /// state (t, y): the free drivers' rates in `y` jump by Δḋ = λ M⁻¹ Gᵀ
    /// with G_i = ∂q̇_j/∂ḋ_i and λ = −(1 + e) w / (G M⁻¹ Gᵀ), w the
    /// coordinate's rate, so that it leaves at −e w; the kinetic energy's
    /// change is added to the work in `slot`. Returns w before and after.
    ///
    /// # Errors
    /// The analyses' errors; a stop the free drivers do not move.
    pub(super) fn impact(
        &mut self,
        t: f64,
        y: &mut [f64],
        (j, e, slot): (usize, f64, usize),
    ) -> Result<(f64, f64), Error> {
        let nf = self.free.len();
        self.accelerations(t, y)?;
        let (before, _) = self.analysis.energies(self.dynamics, t)?;
        let w = self.analysis.coordinate(j)[1];
        // G: the coordinate's rate at a unit rate of each free driver, the
        // others at rest.
        let zeros = alloc::vec![0.0; self.nd];
        let mut g = alloc::vec![0.0; nf];
        for (i, &k) in self.free.iter().enumerate() {
            let mut rates = zeros.clone();
            rates[k] = 1.0;
            self.analysis.analyze(&self.d, &rates, &zeros)?;
            g[i] = self.analysis.coordinate(j)[1];
        }
        let mut mg = g.clone();
        cholesky_apply(&self.mff, &mut mg, nf);
        let reach: f64 = g.iter().zip(&mg).map(|(a, b)| a * b).sum();
        if reach.is_nan() || reach <= 0.0 {
            let name = self.names.get(j).map_or("?", String::as_str);
            return Err(Error::InvalidDynamics {
                item: format!("the stop on `{name}`"),
                detail: "is not moved by the free drivers at this pose: no impact can \
                         reverse it"
                    .to_string(),
            });
        }
        let lambda = -(1.0 + e) * w / reach;
        for i in 0..nf {
            y[nf + i] += lambda * mg[i];
        }
        self.accelerations(t, y)?;
        let (after, _) = self.analysis.energies(self.dynamics, t)?;
        y[slot] += after - before;
        Ok((w, self.analysis.coordinate(j)[1]))
    }
}

impl<A: Analysis> System for Eom<'_, A> {
    fn len(&self) -> usize {
        self.sensitivity_offset() + 2 * self.free.len() * self.parameters
    }

    fn controlled(&self) -> usize {
        2 * self.free.len()
    }

    /// The drivers' positions and rates, and the sensitivities where
    /// asked; the works are quadratures.
    fn inputs(&self) -> usize {
        if self.parameters > 0 {
            self.len()
        } else {
            2 * self.free.len()
        }
    }

    #[inline]
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        if self.lean {
            return self.rhs_one(t, y, dy);
        }
        self.rhs_general(t, y, dy)
    }
}

impl<A: Analysis> Eom<'_, A> {
    /// [`System::rhs`] of any number of free and prescribed drivers, with
    /// the sensitivities where asked.
    #[inline(never)]
    fn rhs_general(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let nf = self.free.len();
        if self.parameters > 0 {
            self.acceleration_jacobian(t, y)?;
        }
        self.accelerations(t, y)?;
        copy_small(&mut dy[..nf], &y[nf..2 * nf]);
        copy_small(&mut dy[nf..2 * nf], &self.x);
        let rest = &mut dy[2 * nf..];
        copy_small(&mut rest[..self.powers.len()], &self.powers);
        zero_small(&mut self.effort);
        for &p in &self.prescribed {
            let mut q = self.bias[p];
            for (j, &l) in self.free.iter().enumerate() {
                q += self.mass[p * self.nd + l] * self.x[j];
            }
            self.effort[p] = q;
        }
        let p0 = self.powers.len();
        for (i, &p) in self.prescribed.iter().enumerate() {
            rest[p0 + i] = self.effort[p] * self.dd[p];
        }
        // The impacts' works change at the impacts only.
        let s0 = p0 + self.prescribed.len();
        zero_small(&mut rest[s0..s0 + self.stops]);
        if self.parameters > 0 {
            self.sensitivities(t, y, dy)?;
        }
        Ok(())
    }
}

impl<A: Analysis> Eom<'_, A> {
    /// Ṡ for each parameter p: Ṡ_d = S_v and Ṡ_v = ∂d̈/∂d S_d +
    /// ∂d̈/∂ḋ S_v + ∂d̈/∂p, with ∂d̈_f/∂p = −M_ff⁻¹ ∂Q_f/∂p at the actual
    /// accelerations (the compiled partials of the efforts, the drivers'
    /// motion held), M_ff's factor the one [`Eom::accelerations`] left.
    fn sensitivities(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let nf = self.free.len();
        // The motion with its accelerations, for ∂Q/∂p there.
        for (i, &k) in self.free.iter().enumerate() {
            self.ddd[k] = self.x[i];
        }
        self.analysis.analyze(&self.d, &self.dd, &self.ddd)?;
        self.analysis
            .effort_partials(self.dynamics, t, &mut self.effort_partials)?;
        let at = self.sensitivity_offset();
        let mut rhs = core::mem::take(&mut self.scratch);
        for p in 0..self.parameters {
            let s = &y[at + p * 2 * nf..at + (p + 1) * 2 * nf];
            rhs.clear();
            for &k in &self.free {
                rhs.push(-self.effort_partials[p * self.nd + k]);
            }
            cholesky_apply(&self.mff, &mut rhs, nf);
            let ds = &mut dy[at + p * 2 * nf..at + (p + 1) * 2 * nf];
            ds[..nf].copy_from_slice(&s[nf..]);
            for i in 0..nf {
                let row = &self.jacobian[i * 2 * nf..(i + 1) * 2 * nf];
                ds[nf + i] = rhs[i] + row.iter().zip(s).map(|(j, v)| j * v).sum::<f64>();
            }
        }
        self.scratch = rhs;
        Ok(())
    }
}

/// The error of a state or work array shorter than the simulation's
/// drivers: an inconsistency of the library's own, reported, not a panic.
#[cold]
fn short() -> Error {
    Error::InvalidDynamics {
        item: "a forward simulation's evaluation".to_string(),
        detail: "found its state shorter than its drivers: a defect of the library, \
                 please report it with the definition"
            .to_string(),
    }
}
