//! The totals of a motion other than the efforts: the kinetic and
//! potential energies, the shaking force and moment, and the force and
//! moment of the mechanism on the frame.

use core::cell::Cell;

use nalgebra::{Matrix3, Vector3};

use super::evaluate::{Instant, LoadAt, View, turning};
use super::{Dynamics, ResolvedBody};
use crate::error::{Error, Input};

/// The sums other than the efforts.
pub(crate) struct Totals {
    pub(crate) kinetic_energy: f64,
    pub(crate) potential_energy: f64,
    pub(crate) shaking_force: Vector3<f64>,
    pub(crate) shaking_moment: Vector3<f64>,
    pub(crate) frame_force: Vector3<f64>,
    pub(crate) frame_moment: Vector3<f64>,
}

impl Dynamics {
    /// A body's kinetic and potential energies at its centre's position
    /// and velocity `[r, v]` and its angular velocity ω (J in the fixed
    /// axes): ½ m |v|² + ½ ω · J ω and −m g · r.
    fn body_energies(
        &self,
        b: &ResolvedBody,
        [r, v]: [Vector3<f64>; 2],
        omega: Vector3<f64>,
        inertia: &Matrix3<f64>,
    ) -> (f64, f64) {
        (
            0.5 * b.mass * v.norm_squared() + 0.5 * omega.dot(&(inertia * omega)),
            -b.mass * self.gravity.dot(&r),
        )
    }

    /// The springs' energy at the motion `s`: Σ ½ k (L − L₀)².
    fn spring_energy(&self, s: &dyn View) -> f64 {
        let mut energy = 0.0;
        for sp in &self.springs {
            let (a, b) = (s.point(sp.from), s.point(sp.to));
            let length = match (a, b) {
                (Some([ra, _, _]), Some([rb, _, _])) => (rb - ra).norm(),
                _ => f64::NAN,
            };
            let stretch = length - sp.free_length;
            energy += 0.5 * sp.stiffness * stretch * stretch;
        }
        energy
    }

    /// The kinetic and potential energies of the motion `s`, as
    /// [`Dynamics::totals`] sums them (T = Σ ½ m |v_G|² + ½ ω · J ω over
    /// the bodies, V = −Σ m g · r_G + Σ ½ k (L − L₀)² over the bodies and
    /// springs), without the forces.
    ///
    /// # Errors
    /// An energy that is not finite.
    pub(crate) fn energies(&self, s: &dyn View) -> Result<(f64, f64), Error> {
        let (mut kinetic, mut potential) = (0.0, 0.0);
        for b in &self.bodies {
            let [r, v, _] = s.point(b.center).unwrap_or([Vector3::repeat(f64::NAN); 3]);
            let (omega, _, inertia) = turning(b, s);
            let (t, u) = self.body_energies(b, [r, v], omega, &inertia);
            kinetic += t;
            potential += u;
        }
        potential += self.spring_energy(s);
        for (name, value) in [
            ("the kinetic energy", kinetic),
            ("the potential energy", potential),
        ] {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    input: Input::Computed,
                    name,
                    value,
                });
            }
        }
        Ok((kinetic, potential))
    }

    /// The energies, the shaking force and moment and the totals on the
    /// frame of the motion `s`, its loads read at `coords` (q, q', q'').
    pub(crate) fn totals(&self, s: &dyn View, coords: [&[f64]; 3]) -> Result<Totals, Error> {
        let (mut kinetic, mut potential) = (0.0, 0.0);
        let (mut shaking_force, mut shaking_moment) = (Vector3::zeros(), Vector3::zeros());
        for b in &self.bodies {
            let [r, v, a] = s.point(b.center).unwrap_or([Vector3::repeat(f64::NAN); 3]);
            let (omega, alpha, inertia) = turning(b, s);
            let ma = a * b.mass;
            let (t, u) = self.body_energies(b, [r, v], omega, &inertia);
            kinetic += t;
            potential += u;
            shaking_force -= ma;
            shaking_moment -= r.cross(&ma) + inertia * alpha + omega.cross(&(inertia * omega));
        }
        potential += self.spring_energy(s);
        let (frame_force, frame_moment) =
            self.on_frame(s, coords, shaking_force, shaking_moment)?;
        let totals = Totals {
            kinetic_energy: kinetic,
            potential_energy: potential,
            shaking_force,
            shaking_moment,
            frame_force,
            frame_moment,
        };
        for (name, value) in [
            ("the kinetic energy", totals.kinetic_energy),
            ("the potential energy", totals.potential_energy),
            ("the shaking force", totals.shaking_force.sum()),
            ("the shaking moment", totals.shaking_moment.sum()),
            ("the force on the frame", totals.frame_force.sum()),
            ("the moment on the frame", totals.frame_moment.sum()),
        ] {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    input: Input::Computed,
                    name,
                    value,
                });
            }
        }
        Ok(totals)
    }

    /// The total force and moment of the mechanism on the frame at `s`
    /// ([`Forces::frame_force`]): the inertial parts `force` and `moment`
    /// plus the weights, the point loads and the torques on bodies, the
    /// loads read at `coords` (q, q', q'').
    fn on_frame(
        &self,
        s: &dyn View,
        coords: [&[f64]; 3],
        mut force: Vector3<f64>,
        mut moment: Vector3<f64>,
    ) -> Result<(Vector3<f64>, Vector3<f64>), Error> {
        let planar = self.dim == 2;
        let instant = |at| Instant::of(coords, at).at_time(s.time());
        for b in &self.bodies {
            let [r, _, _] = s.point(b.center).unwrap_or([Vector3::repeat(f64::NAN); 3]);
            let w = self.gravity * b.mass;
            force += w;
            moment += r.cross(&w);
        }
        for (i, (p, _, f)) in self.forces.iter().enumerate() {
            let at = s.point(*p);
            let read = Cell::new(false);
            let f = Vector3::from(f(&instant(at).watched(&read)));
            self.finite_load(f.iter().copied(), LoadAt::Force(i), read.get())?;
            let f = if planar {
                Vector3::new(f.x, f.y, 0.0)
            } else {
                f
            };
            let r = at.map_or(Vector3::zeros(), |[r, _, _]| r);
            force += f;
            moment += r.cross(&f);
        }
        for (i, (b, t)) in self.torques.iter().enumerate() {
            let body = self.bodies.get(*b);
            let read = Cell::new(false);
            let t = Vector3::from(t(
                &instant(body.and_then(|b| s.point(b.center))).watched(&read)
            ));
            self.finite_load(t.iter().copied(), LoadAt::Torque(i), read.get())?;
            moment += if planar {
                Vector3::new(0.0, 0.0, t.z)
            } else {
                t
            };
        }
        Ok((force, moment))
    }
}
