//! The equations of motion in the drivers, from the same unit analyses
//! as the efforts: the mass matrix, the efforts at zero acceleration of
//! the free drivers, and the power of each load.
//!
//! At a pose q with rates q̇, the effort each driver must supply is affine
//! in the drivers' accelerations d̈ (the loads do not depend on them):
//! Q(d̈) = M(q) d̈ + b(q, q̇, t), with
//!
//! M_kl = Σ_b m_b v_G^k · v_G^l + ω_b^k · J_b ω_b^l
//!
//! from the partial velocities v^k = ∂v/∂ḋ_k, ω^k = ∂ω/∂ḋ_k (J_b in the
//! fixed axes), and b = Q at the accelerations with the free drivers'
//! set to zero (the prescribed ones at their profile's). A free driver
//! supplies no effort (a motor is a load on its coordinate), so its
//! accelerations solve M_ff d̈_f = −b_f, and a prescribed driver supplies
//! Q_p = b_p + M_pf d̈_f.

use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use nalgebra::Vector3;

use crate::dynamics::Dynamics;
use crate::dynamics::Turns;
use crate::dynamics::evaluate::{View, WithUnit, angular_velocity, turning};
use crate::dynamics::terms::Terms;
use crate::error::{Error, Input};
use crate::solve::dense::{lu, lu_apply};

/// Where the equations are written: the mass matrix (drivers × drivers,
/// row-major), the efforts at zero free acceleration, the power of each
/// load, and room for the partial velocities of the bodies' centres and
/// their angular velocities (drivers × bodies).
pub(crate) struct Equations<'w> {
    pub(crate) mass: &'w mut [f64],
    pub(crate) bias: &'w mut [f64],
    pub(crate) powers: &'w mut [f64],
    pub(crate) partials: &'w mut [[Vector3<f64>; 2]],
    /// The efforts' shared terms, kept between evaluations.
    pub(crate) terms: &'w mut Terms,
}

impl Dynamics {
    /// The number of loads whose work a forward simulation reports: every
    /// force, torque and coordinate force, then every spring's damper.
    pub(crate) fn working_loads(&self) -> usize {
        self.forces.len() + self.torques.len() + self.coordinate_forces.len() + self.springs.len()
    }

    /// The names of the loads of [`Dynamics::working_loads`], in order.
    pub(crate) fn working_load_names(&self) -> Vec<String> {
        let mut names = Vec::with_capacity(self.working_loads());
        for p in &self.load_names.forces {
            names.push(format!("force at {p}"));
        }
        for (b, _) in &self.torques {
            let body = self.bodies.get(*b).map_or("?", |b| b.name.as_str());
            names.push(format!("torque on {body}"));
        }
        for c in &self.load_names.coordinate_forces {
            names.push(format!("force on {c}"));
        }
        for sp in &self.springs {
            let name = |i: usize| self.load_names.points.get(i).map_or("?", String::as_str);
            names.push(format!("damper {}-{}", name(sp.from), name(sp.to)));
        }
        names
    }

    /// The number of bodies.
    pub(crate) fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Writes the equations of motion at the motion `s` (its free drivers'
    /// accelerations zero) into `out`, from the unit analyses `unit`
    /// provides: M, b and the loads' powers at `s`.
    ///
    /// # Errors
    /// A load or a result that is not finite, naming it; the unit
    /// analyses' errors.
    pub(crate) fn equations(
        &self,
        s: &dyn View,
        unit: &mut dyn FnMut(usize, WithUnit<'_>) -> Result<(), Error>,
        out: &mut Equations<'_>,
    ) -> Result<(), Error> {
        let nd = self.drivers;
        let nb = self.bodies.len();
        out.mass.fill(0.0);
        let terms = &mut *out.terms;
        // q and q' as the loads read them; their accelerations may not be
        // read here (the free ones are what is solved for): NaN, so that
        // a load that does is named.
        let mut coordinates = core::mem::take(&mut terms.coordinates);
        for c in &mut coordinates {
            c.clear();
        }
        for j in 0..self.coordinates {
            let [q, qd, _] = s.coordinate(j);
            coordinates[0].push(q);
            coordinates[1].push(qd);
            coordinates[2].push(f64::NAN);
        }
        let done = self.terms(
            s,
            [&coordinates[0], &coordinates[1], &coordinates[2]],
            terms,
        );
        terms.coordinates = coordinates;
        done?;
        for k in 0..nd {
            let mut effort = f64::NAN;
            let partials = &mut out.partials[k * nb..(k + 1) * nb];
            unit(k, &mut |u| {
                effort = self.effort(terms, u);
                for (b, p) in self.bodies.iter().zip(partials.iter_mut()) {
                    let v = u.velocity(b.center).unwrap_or(Vector3::zeros());
                    *p = [v, angular_velocity(b, u)];
                }
            })?;
            out.bias[k] = effort;
        }
        for (i, b) in self.bodies.iter().enumerate() {
            // J in the fixed axes, once per body (none for a slider).
            let inertia = match b.turning {
                Turns::No => None,
                Turns::Angle(_) => Some(b.inertia),
                Turns::Frame(_) => Some(turning(b, s).2),
            };
            for k in 0..nd {
                for l in 0..nd {
                    let [vk, wk] = out.partials[k * nb + i];
                    let [vl, wl] = out.partials[l * nb + i];
                    let rotation = inertia.map_or(0.0, |j| wk.dot(&(j * wl)));
                    out.mass[k * nd + l] += b.mass * vk.dot(&vl) + rotation;
                }
            }
        }
        self.load_powers(s, out.terms, out.powers);
        for &value in out.mass.iter().chain(out.bias.iter()) {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    input: Input::Computed,
                    name: "the equations of motion",
                    value,
                });
            }
        }
        Ok(())
    }

    /// The power of each load of [`Dynamics::working_loads`] at the motion
    /// `s`, from its `terms`: F · v_P, T · ω, f q̇_j, and −c L̇² for each
    /// damper.
    fn load_powers(&self, s: &dyn View, terms: &Terms, powers: &mut [f64]) {
        let mut slots = powers.iter_mut();
        let mut put = |p: f64| {
            if let Some(slot) = slots.next() {
                *slot = p;
            }
        };
        for ((p, _, _), f) in self.forces.iter().zip(&terms.forces) {
            put(f.dot(&s.velocity(*p).unwrap_or(Vector3::zeros())));
        }
        for ((b, _), t) in self.torques.iter().zip(&terms.torques) {
            put(t.dot(
                &self
                    .bodies
                    .get(*b)
                    .map_or(Vector3::zeros(), |b| angular_velocity(b, s)),
            ));
        }
        for ((j, _), f) in self.coordinate_forces.iter().zip(&terms.coordinate_forces) {
            put(f * s.rate(*j));
        }
        for (sp, (_, e)) in self.springs.iter().zip(&terms.springs) {
            let velocity = |p: usize| s.velocity(p).unwrap_or(Vector3::repeat(f64::NAN));
            let rate = e.dot(&(velocity(sp.to) - velocity(sp.from)));
            put(-sp.damping * rate * rate);
        }
    }
}

/// The drivers' M, b and the loads' powers from the equations of motion
/// in all the coordinates, as the compiled roots give them
/// ([`kinematics_compiler::motion::EquationsOfMotion`], laid out
/// `[Φ_q (u × n) | M̃'s upper triangle | f̃ (n) | powers]`): with the
/// kinematic coefficients C (n × d, C_d = I, Φ_u C_u = −Φ_d),
/// M = Cᵀ M̃ C and b = Cᵀ f̃ (the virtual power of f̃ along the drivers'
/// partial velocities). Its work arrays are allocated once. Where the
/// roots are reduced (one driver, at most two unknowns:
/// [`kinematics_compiler::motion::EquationsOfMotion::reduced`]), they are
/// `[M | b | powers]`, which it checks and copies.
pub(crate) struct Reduction {
    n: usize,
    nd: usize,
    reduced: bool,
    /// C, n × nd, row-major; the drivers' rows the identity.
    c: Vec<f64>,
    lu: Vec<f64>,
    perm: Vec<usize>,
    rhs: Vec<f64>,
    x: Vec<f64>,
}

impl Reduction {
    /// For n coordinates of which the first `nd` (at least one) are the
    /// drivers, the roots `reduced` or not.
    pub(crate) fn new(n: usize, nd: usize, reduced: bool) -> Self {
        let nu = n.saturating_sub(nd);
        let mut c = vec![0.0; n * nd];
        for k in 0..nd.min(n) {
            c[k * nd + k] = 1.0;
        }
        Self {
            n,
            nd,
            // (Reduced for one driver only.)
            reduced: reduced && nd == 1,
            c,
            lu: vec![0.0; nu * nu],
            perm: vec![0; nu],
            rhs: vec![0.0; nu],
            x: vec![0.0; nu],
        }
    }

    /// The length of the output it reads, with `powers` loads' powers.
    pub(crate) fn outputs(&self, powers: usize) -> usize {
        let (n, nd) = (self.n, self.nd);
        if self.reduced {
            return 2 + powers;
        }
        n.saturating_sub(nd) * n + n * (n + 1) / 2 + n + powers
    }

    /// M, b and the powers from `out` into `eq`; `false` where `out` has
    /// not the length of [`Reduction::outputs`] for `eq`'s powers, Φ_u is
    /// singular or a value is not finite (the caller then sums the
    /// general way, which names the cause).
    #[inline]
    pub(crate) fn reduce(&mut self, out: &[f64], eq: &mut Equations<'_>) -> bool {
        if self.reduced {
            // M and b as compiled (not finite where Φ_u is singular), then
            // the powers; their sum is finite where each is (a sum that
            // overflows sends the step to the general way, which decides).
            return match (out.split_first_chunk::<2>(), &mut *eq.mass, &mut *eq.bias) {
                (Some(([m, b], powers)), [mass, ..], [bias, ..])
                    if powers.len() == eq.powers.len() =>
                {
                    (*mass, *bias) = (*m, *b);
                    crate::math::copy_small(eq.powers, powers);
                    (m + b + powers.iter().sum::<f64>()).is_finite()
                }
                _ => false,
            };
        }
        self.reduce_full(out, eq)
    }

    /// [`Reduction::reduce`] of roots in all the coordinates.
    #[inline(never)]
    fn reduce_full(&mut self, out: &[f64], eq: &mut Equations<'_>) -> bool {
        let (n, nd) = (self.n, self.nd);
        if nd == 0
            || nd > n
            || out.len() != self.outputs(eq.powers.len())
            || eq.mass.len() < nd * nd
            || eq.bias.len() < nd
        {
            return false;
        }
        let nu = n - nd;
        let (jacobian, rest) = out.split_at(nu * n);
        let (upper, rest) = rest.split_at(n * (n + 1) / 2);
        let (forces, powers) = rest.split_at(n);
        if let ([a0, a1, a2, b0, b1, b2], [m00, m01, m02, m11, m12, m22], [f0, f1, f2]) =
            (jacobian, upper, forces)
        {
            // One driver and two unknowns (a four-bar, a slider-crank),
            // unrolled: C = (1, x₀, x₁) with Φ_u x = −Φ_d by elimination
            // with the larger pivot, M = Cᵀ M̃ C, b = Cᵀ f̃.
            let ([p, q, r], [s, t, u]) = if b1.abs() > a1.abs() {
                ([*b1, *b2, -*b0], [*a1, *a2, -*a0])
            } else {
                ([*a1, *a2, -*a0], [*b1, *b2, -*b0])
            };
            let l = s / p;
            let d = t - l * q;
            // (A pivot of zero, infinite or NaN: the general way says why.)
            if !(p.abs() > 0.0 && p.is_finite() && d.abs() > 0.0 && d.is_finite()) {
                return false;
            }
            let x1 = (u - l * r) / d;
            let x0 = (r - q * x1) / p;
            eq.mass[0] =
                m00 + 2.0 * (m01 * x0 + m02 * x1 + m12 * x0 * x1) + m11 * x0 * x0 + m22 * x1 * x1;
            eq.bias[0] = f0 + f1 * x0 + f2 * x1;
            if eq.powers.len() == powers.len() {
                crate::math::copy_small(eq.powers, powers);
            }
            return eq.mass[0].is_finite()
                && eq.bias[0].is_finite()
                && powers.iter().all(|v| v.is_finite());
        }
        // C: the drivers' rows the identity (written once, in `new`), the
        // unknowns' from Φ_u C_u = −Φ_d.
        if nu > 0 {
            for i in 0..nu {
                for j in 0..nu {
                    self.lu[i * nu + j] = jacobian[i * n + nd + j];
                }
            }
            if lu(&mut self.lu, &mut self.perm, nu).is_none() {
                return false;
            }
            for k in 0..nd {
                for i in 0..nu {
                    self.rhs[i] = -jacobian[i * n + k];
                }
                lu_apply(&self.lu, &self.perm, &self.rhs, &mut self.x, nu);
                for i in 0..nu {
                    self.c[(nd + i) * nd + k] = self.x[i];
                }
            }
        }
        let c = &self.c;
        if nd == 1 {
            // One driver: C is a column, M = Σ_i c_i (M̃_ii c_i + 2 Σ_{j>i}
            // M̃_ij c_j), row i of the triangle holding M̃_ii … M̃_in.
            let (mut mass, mut rows) = (0.0, upper);
            for (i, &ci) in c.iter().enumerate() {
                let (row, rest) = rows.split_at(n - i);
                rows = rest;
                let mut s = 0.5 * row[0] * ci;
                for (&v, &cj) in row[1..].iter().zip(&c[i + 1..]) {
                    s += v * cj;
                }
                mass += 2.0 * ci * s;
            }
            eq.mass[0] = mass;
            eq.bias[0] = c.iter().zip(forces).map(|(c, f)| c * f).sum();
        } else {
            let mass = &mut eq.mass[..nd * nd];
            mass.fill(0.0);
            let mut at = 0;
            for i in 0..n {
                for j in i..n {
                    let v = upper[at];
                    at += 1;
                    for k in 0..nd {
                        let (cik, cjk) = (c[i * nd + k], c[j * nd + k]);
                        for l in 0..nd {
                            let other = if i == j { 0.0 } else { cjk * c[i * nd + l] };
                            mass[k * nd + l] += v * (cik * c[j * nd + l] + other);
                        }
                    }
                }
            }
            for k in 0..nd {
                let mut b = 0.0;
                for (j, f) in forces.iter().enumerate() {
                    b += c[j * nd + k] * f;
                }
                eq.bias[k] = b;
            }
        }
        for (p, v) in eq.powers.iter_mut().zip(powers) {
            *p = *v;
        }
        eq.mass[..nd * nd]
            .iter()
            .chain(&eq.bias[..nd])
            .chain(powers)
            .all(|v| v.is_finite())
    }
}

/// Solves M x = r in place (x in `r`) for the symmetric positive definite
/// n × n matrix `m` (row-major, overwritten by its Cholesky factor L,
/// M = L Lᵀ). `Err(k)` when the k-th pivot is not positive: the free
/// driver k moves no mass that the earlier ones do not.
#[inline]
pub(crate) fn cholesky_solve(m: &mut [f64], r: &mut [f64], n: usize) -> Result<(), usize> {
    // One free driver: its factor √m, and x = r / m, in the caller's code
    // (no call, no loops).
    if let ([m], [r]) = (&mut *m, &mut *r) {
        if !m.is_finite() || *m <= 0.0 {
            return Err(0);
        }
        *r /= *m;
        *m = crate::math::sqrt(*m);
        return Ok(());
    }
    cholesky_loops(m, r, n)
}

/// [`cholesky_solve`] of two or more free drivers.
#[inline(never)]
fn cholesky_loops(m: &mut [f64], r: &mut [f64], n: usize) -> Result<(), usize> {
    // The scale below which a pivot counts as zero.
    let largest = (0..n).map(|i| m[i * n + i].abs()).fold(0.0, f64::max);
    for j in 0..n {
        let mut d = m[j * n + j];
        for k in 0..j {
            d -= m[j * n + k] * m[j * n + k];
        }
        if d.is_nan() || d <= 1e-14 * largest {
            return Err(j);
        }
        let d = crate::math::sqrt(d);
        m[j * n + j] = d;
        for i in j + 1..n {
            let mut v = m[i * n + j];
            for k in 0..j {
                v -= m[i * n + k] * m[j * n + k];
            }
            m[i * n + j] = v / d;
        }
    }
    cholesky_apply(m, r, n);
    Ok(())
}

/// Solves M x = r in place with the Cholesky factor L of
/// [`cholesky_solve`] (L y = r, then Lᵀ x = y).
pub(crate) fn cholesky_apply(l: &[f64], r: &mut [f64], n: usize) {
    for i in 0..n {
        let mut v = r[i];
        for k in 0..i {
            v -= l[i * n + k] * r[k];
        }
        r[i] = v / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut v = r[i];
        for k in i + 1..n {
            v -= l[k * n + i] * r[k];
        }
        r[i] = v / l[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec::Vec;

    use super::{Equations, Reduction, cholesky_solve};
    use crate::dynamics::terms::Terms;

    /// The arrays as `Equations`.
    fn room<'w>(
        mass: &'w mut [f64],
        bias: &'w mut [f64],
        powers: &'w mut [f64],
        (partials, terms): (&'w mut [[nalgebra::Vector3<f64>; 2]], &'w mut Terms),
    ) -> Equations<'w> {
        Equations {
            mass,
            bias,
            powers,
            partials,
            terms,
        }
    }

    /// M = Cᵀ M̃ C and b = Cᵀ f̃ of one driver and two unknowns (the
    /// unrolled case) against C solved here and the products summed, with
    /// either row the larger pivot; an infinite entry refused.
    #[test]
    fn one_driver_and_two_unknowns_reduce_as_the_products() {
        use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
        let upper = [2.0, 0.3, -0.2, 1.5, 0.4, 0.9];
        let forces = [0.7, -1.1, 0.25];
        for jacobian in [
            [0.3, 2.0, -0.5, -0.8, 0.4, 1.7],
            [0.3, 0.4, -0.5, -0.8, 2.0, 1.7],
        ] {
            let mut out: Vec<f64> = jacobian.to_vec();
            out.extend(upper);
            out.extend(forces);
            out.push(0.125);
            let (mut mass, mut bias, mut powers) = ([0.0], [0.0], [0.0]);
            let mut partials = Vec::new();
            let mut terms = Terms::default();
            let mut eq = room(
                &mut mass,
                &mut bias,
                &mut powers,
                (&mut partials, &mut terms),
            );
            let mut r = Reduction::new(3, 1, false);
            assert!(r.reduce(&out, &mut eq));
            let phi_u = Matrix2::new(jacobian[1], jacobian[2], jacobian[4], jacobian[5]);
            let x = phi_u
                .lu()
                .solve(&-Vector2::new(jacobian[0], jacobian[3]))
                .expect("regular");
            let c = Vector3::new(1.0, x[0], x[1]);
            let [a, b, d, e, f, g] = upper;
            let mt = Matrix3::new(a, b, d, b, e, f, d, f, g);
            let m = (c.transpose() * mt * c)[0];
            let q = c.dot(&Vector3::from(forces));
            assert!((mass[0] - m).abs() < 1e-14 * m.abs(), "{} {m}", mass[0]);
            assert!(
                (bias[0] - q).abs() < 1e-14 * (1.0 + q.abs()),
                "{} {q}",
                bias[0]
            );
            assert_eq!(powers[0], 0.125);
            // An infinite pivot is refused, not reduced to a finite M.
            let mut bad = out.clone();
            bad[if jacobian[4].abs() > jacobian[1].abs() {
                4
            } else {
                1
            }] = f64::INFINITY;
            let mut eq = room(
                &mut mass,
                &mut bias,
                &mut powers,
                (&mut partials, &mut terms),
            );
            assert!(!r.reduce(&bad, &mut eq));
        }
    }

    /// Reduced roots `[M | b | powers]` are copied as they are; one that
    /// is not finite, or the wrong number of powers, is refused (the
    /// caller then sums the general way); reduced roots are for one
    /// driver only.
    #[test]
    fn reduced_roots_are_copied_or_refused() {
        let (mut mass, mut bias, mut powers) = ([0.0], [0.0], [0.0, 0.0]);
        let mut partials = Vec::new();
        let mut terms = Terms::default();
        let mut r = Reduction::new(3, 1, true);
        assert_eq!(r.outputs(2), 4);
        for (out, ok) in [
            (&[2.5, -0.75, 0.125, -3.0][..], true),
            (&[f64::NAN, -0.75, 0.125, -3.0][..], false),
            (&[2.5, f64::INFINITY, 0.125, -3.0][..], false),
            (&[2.5, -0.75, 0.125, f64::NEG_INFINITY][..], false),
            (&[2.5, -0.75, 0.125][..], false),
            (&[2.5][..], false),
        ] {
            let mut eq = room(
                &mut mass,
                &mut bias,
                &mut powers,
                (&mut partials, &mut terms),
            );
            assert_eq!(r.reduce(out, &mut eq), ok, "{out:?}");
            if ok {
                assert_eq!((mass, bias, powers), ([2.5], [-0.75], [0.125, -3.0]));
            }
        }
        // Two drivers: the full layout.
        assert_eq!(Reduction::new(3, 2, true).outputs(0), 3 + 6 + 3);
    }

    #[test]
    fn cholesky_solves_a_positive_definite_system_and_names_a_zero_pivot() {
        // M = [[4, 2], [2, 3]], x = (1, −2): r = (0, −4).
        let mut m = [4.0, 2.0, 2.0, 3.0];
        let mut r = [0.0, -4.0];
        cholesky_solve(&mut m, &mut r, 2).unwrap();
        assert!(
            (r[0] - 1.0).abs() < 1e-15 && (r[1] + 2.0).abs() < 1e-15,
            "{r:?}"
        );
        // The second driver moves only what the first does.
        let mut m = [1.0, 1.0, 1.0, 1.0];
        let mut r = [1.0, 1.0];
        assert_eq!(cholesky_solve(&mut m, &mut r, 2), Err(1));
    }
}
