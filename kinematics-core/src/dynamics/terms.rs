//! The terms of the efforts that every driver shares at one motion
//! (each body's inertial terms, each load's value, each spring's pull),
//! computed once per motion, and one driver's effort from them and its
//! partial velocities: the virtual-power sum the inverse dynamics and
//! the equations of motion both use.

use core::cell::Cell;

use alloc::vec::Vec;

use nalgebra::Vector3;

use super::evaluate::{Instant, LoadAt, View, angular_velocity, turning};
use super::{Dynamics, Turns};
use crate::error::Error;

impl Dynamics {
    /// The terms of the efforts that every driver shares at the motion
    /// `s` (its loads read at `coords`, q, q', q''), written into `out`:
    /// each body's m (a_G − g) and J α + ω × J ω, each load's value (once
    /// per motion, however many drivers) and each spring's pull.
    ///
    /// # Errors
    /// A load that is not finite, named.
    pub(crate) fn terms(
        &self,
        s: &dyn View,
        coords: [&[f64]; 3],
        out: &mut Terms,
    ) -> Result<(), Error> {
        let g = self.gravity;
        let planar = self.dim == 2;
        let instant = |at| Instant::of(coords, at).at_time(s.time());
        out.bodies.clear();
        for b in &self.bodies {
            let a = s
                .acceleration(b.center)
                .unwrap_or(Vector3::repeat(f64::NAN));
            let h = match &b.turning {
                // Planar: J α about the normal; the gyroscopic term
                // vanishes.
                Turns::Angle(terms) if planar => {
                    let mut alpha = 0.0;
                    for &(j, c) in terms {
                        alpha += c * s.coordinate(j)[2];
                    }
                    Vector3::new(0.0, 0.0, b.inertia[(2, 2)] * alpha)
                }
                _ => {
                    let (omega, alpha, inertia) = turning(b, s);
                    inertia * alpha + omega.cross(&(inertia * omega))
                }
            };
            out.bodies.push([(a - g) * b.mass, h]);
        }
        out.forces.clear();
        for (i, (p, _, f)) in self.forces.iter().enumerate() {
            let read = Cell::new(false);
            let f = Vector3::from(f(&instant(s.point(*p)).watched(&read)));
            self.finite_load(f.iter().copied(), LoadAt::Force(i), read.get())?;
            out.forces.push(if planar {
                Vector3::new(f.x, f.y, 0.0)
            } else {
                f
            });
        }
        out.torques.clear();
        for (i, (b, t)) in self.torques.iter().enumerate() {
            let body = self.bodies.get(*b);
            let read = Cell::new(false);
            let t = Vector3::from(t(
                &instant(body.and_then(|b| s.point(b.center))).watched(&read)
            ));
            self.finite_load(t.iter().copied(), LoadAt::Torque(i), read.get())?;
            out.torques.push(if planar {
                Vector3::new(0.0, 0.0, t.z)
            } else {
                t
            });
        }
        out.coordinate_forces.clear();
        for (i, (_, f)) in self.coordinate_forces.iter().enumerate() {
            let read = Cell::new(false);
            let f = f(&instant(None).watched(&read));
            self.finite_load([f], LoadAt::Coordinate(i), read.get())?;
            out.coordinate_forces.push(f);
        }
        out.springs.clear();
        for sp in &self.springs {
            let pull = sp.pull(s);
            out.springs.push((pull.tension, pull.e));
        }
        Ok(())
    }

    /// One driver's effort Q_k from the shared `terms` of the motion and
    /// the driver's unit analysis `u` (its partial velocities):
    /// Q_k = Σ m (a_G − g) · v_G^k + h · ω^k − Σ F · v_P^k − Σ T · ω^k −
    /// Σ f q̇_j^k + Σ f_s e · (v_B^k − v_A^k).
    pub(super) fn effort(&self, terms: &Terms, u: &dyn View) -> f64 {
        let velocity = |p: usize| u.velocity(p).unwrap_or(Vector3::zeros());
        let mut q = 0.0;
        for (b, [ma, h]) in self.bodies.iter().zip(&terms.bodies) {
            q += ma.dot(&velocity(b.center)) + h.dot(&angular_velocity(b, u));
        }
        for ((p, _, _), f) in self.forces.iter().zip(&terms.forces) {
            q -= f.dot(&velocity(*p));
        }
        for ((b, _), t) in self.torques.iter().zip(&terms.torques) {
            let w = self
                .bodies
                .get(*b)
                .map_or(Vector3::zeros(), |b| angular_velocity(b, u));
            q -= t.dot(&w);
        }
        for ((j, _), f) in self.coordinate_forces.iter().zip(&terms.coordinate_forces) {
            q -= f * u.rate(*j);
        }
        for (sp, (tension, e)) in self.springs.iter().zip(&terms.springs) {
            q += tension * e.dot(&(velocity(sp.to) - velocity(sp.from)));
        }
        q
    }
}

/// The terms of the efforts shared by every driver at one motion
/// ([`Dynamics::terms`]); kept between motions, so that its vectors are
/// allocated once.
#[derive(Clone, Debug, Default)]
pub(crate) struct Terms {
    /// Per body: m (a_G − g) and J α + ω × J ω.
    pub(crate) bodies: Vec<[Vector3<f64>; 2]>,
    /// Per force, per torque (in the plane's terms where planar), per
    /// coordinate force: its value.
    pub(crate) forces: Vec<Vector3<f64>>,
    pub(crate) torques: Vec<Vector3<f64>>,
    pub(crate) coordinate_forces: Vec<f64>,
    /// Per spring: its tension and the unit vector from its first end.
    pub(crate) springs: Vec<(f64, Vector3<f64>)>,
    /// q, q', q'' of every coordinate, as the loads read them (kept, for
    /// a forward run's evaluations).
    pub(crate) coordinates: [Vec<f64>; 3],
}
