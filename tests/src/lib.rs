//! Helpers shared by the integration tests: a seeded random generator and
//! finite-difference checks that are independent of the generated
//! derivatives (they use only assembled positions and residuals).
//!
//! These helpers are test assertions: they panic on a failed check.
#![allow(clippy::expect_used, clippy::panic)]
// Component loops index several arrays in step.
#![allow(clippy::needless_range_loop)]

pub mod heap;

use kinematics_core::{solve::Lu, Coordinates, Mechanism, MotionState, Options, PointState};

/// The project's one seeded random generator for tests (`fastrand`'s
/// wyrand, reproducible from its seed), with the draws the tests need.
pub struct Rng(fastrand::Rng);

impl Rng {
    /// A generator from a fixed seed.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(fastrand::Rng::with_seed(seed))
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0.f64()
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// An angle uniform in [−π, π).
    pub fn angle(&mut self) -> f64 {
        self.range(-std::f64::consts::PI, std::f64::consts::PI)
    }

    /// A vector with each component uniform in [lo, hi).
    pub fn vector3(&mut self, lo: f64, hi: f64) -> kinematics_core::nalgebra::Vector3<f64> {
        kinematics_core::nalgebra::Vector3::new(
            self.range(lo, hi),
            self.range(lo, hi),
            self.range(lo, hi),
        )
    }
}

/// Relative difference |a − b| / (|a| + |b| + floor).
#[must_use]
pub fn rel(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / (a.abs() + b.abs() + floor)
}

/// Checks Φ_u against central differences of the residual at `pose`, to
/// relative `tol` (scaled by the largest Jacobian entry).
///
/// # Panics
/// When an entry disagrees.
pub fn check_jacobian<M: Mechanism>(m: &M, pose: &M::Coords, tol: f64) {
    let (nd, nu, ne) = (M::DRIVERS, M::UNKNOWNS, M::EQUATIONS);
    let mut jac = vec![0.0; ne * nu];
    m.jacobian_into(pose, &mut jac);
    let scale = jac.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let h = 1e-6;
    for k in 0..nu {
        let j = nd + k;
        let base = pose.get(j).expect("coordinate");
        let mut plus = *pose;
        let mut minus = *pose;
        plus.set(j, base + h);
        minus.set(j, base - h);
        let mut rp = vec![0.0; ne];
        let mut rm = vec![0.0; ne];
        m.residual_into(&plus, &mut rp);
        m.residual_into(&minus, &mut rm);
        for i in 0..ne {
            let fd = (rp[i] - rm[i]) / (2.0 * h);
            let exact = jac[i * nu + k];
            assert!(
                (fd - exact).abs() <= tol * scale.max(1e-300),
                "Φ_u[{i}][{k}] = {exact}, finite difference {fd}"
            );
        }
    }
}

/// The pose at time `t` when the drivers follow d(t) = d₀ + d'·t + ½ d''·t²,
/// assembled from `pose`.
///
/// # Panics
/// When the mechanism does not assemble there.
pub fn pose_at<M: Mechanism>(
    m: &M,
    pose: &M::Coords,
    rates: &[f64],
    accels: &[f64],
    t: f64,
) -> M::Coords {
    let mut start = *pose;
    for (j, (r, a)) in rates.iter().zip(accels).enumerate() {
        let d0 = pose.get(j).expect("driver");
        start.set(j, d0 + r * t + 0.5 * a * t * t);
    }
    let options = Options {
        tolerance: 1e-14,
        ..Options::DEFAULT
    };
    m.assemble_with(&start, &options)
        .expect("assembles near the pose")
}

/// Checks velocities against differences of assembled positions and
/// accelerations against differences of computed velocities, for every
/// coordinate, point and frame (ω against differences of R, α against
/// differences of ω), along d(t) = d₀ + d'·t + ½ d''·t². The differences use
/// the fourth-order five-point stencil
/// f'(0) ≈ [8(f(h) − f(−h)) − (f(2h) − f(−2h))] / 12h, h = 10⁻⁵.
///
/// # Panics
/// When a value disagrees beyond relative `tol` (scaled by the largest
/// magnitude of its kind).
pub fn check_motion<M: Mechanism>(
    m: &M,
    pose: &M::Coords,
    rates: &[f64],
    accels: &[f64],
    tol: f64,
) {
    use kinematics_core::nalgebra::Matrix3;
    let opts = Options::DEFAULT;
    let nq = M::DRIVERS + M::UNKNOWNS;
    let dim = M::POINT_DIM;
    // Positions, velocities and rotations at time t along the path.
    let snap = |t: f64| -> (Vec<f64>, Vec<f64>, Vec<Matrix3<f64>>, M::Motion) {
        let p = if t == 0.0 {
            *pose
        } else {
            pose_at(m, pose, rates, accels, t)
        };
        let r: Vec<f64> = rates.iter().zip(accels).map(|(r, a)| r + a * t).collect();
        let s = m
            .analyze_slices(&p, &r, accels, &opts)
            .expect("analysis along the path");
        let mut pos: Vec<f64> = (0..nq).map(|j| p.get(j).expect("q")).collect();
        let mut vel: Vec<f64> = (0..nq).map(|j| s.qd().get(j).expect("q'")).collect();
        let mut flat = vec![0.0; M::POINTS * dim];
        m.point_positions_into(&p, &mut flat);
        pos.extend(flat);
        for pt in s.points() {
            vel.extend_from_slice(pt.velocity());
        }
        for f in s.frames() {
            pos.extend(f.origin.iter());
            vel.extend(f.velocity.iter().chain(f.angular_velocity.iter()));
        }
        let mut rot = vec![Matrix3::zeros(); M::FRAMES];
        m.frame_rotations_into(&p, &mut rot);
        (pos, vel, rot, s)
    };
    let h = 1e-5;
    let (_, v0, r0, s0) = snap(0.0);
    let (p1, v1, r1, _) = snap(h);
    let (p2, v2, r2, _) = snap(2.0 * h);
    let (m1, w1, q1, _) = snap(-h);
    let (m2, w2, q2, _) = snap(-2.0 * h);
    let d = |a1: f64, a2: f64, b1: f64, b2: f64| (8.0 * (a1 - b1) - (a2 - b2)) / (12.0 * h);
    // Velocities: q', point velocities, frame-origin velocities, then ω.
    let mut vel_exact = Vec::new();
    let mut vel_fd = Vec::new();
    let mut k = 0;
    let mut v_index = 0;
    for j in 0..nq {
        vel_exact.push((format!("q'[{j}]"), v0[j]));
        vel_fd.push(d(p1[k], p2[k], m1[k], m2[k]));
        k += 1;
        v_index += 1;
    }
    for n in 0..M::POINTS {
        for c in 0..dim {
            vel_exact.push((format!("v[{n}][{c}]"), v0[v_index]));
            vel_fd.push(d(p1[k], p2[k], m1[k], m2[k]));
            k += 1;
            v_index += 1;
        }
    }
    for n in 0..M::FRAMES {
        for c in 0..3 {
            vel_exact.push((format!("v_o[{n}][{c}]"), v0[v_index + c]));
            vel_fd.push(d(p1[k], p2[k], m1[k], m2[k]));
            k += 1;
        }
        let rd: Matrix3<f64> = (8.0 * (r1[n] - q1[n]) - (r2[n] - q2[n])) / (12.0 * h);
        let w = rd * r0[n].transpose();
        let axial = [
            (w[(2, 1)] - w[(1, 2)]) / 2.0,
            (w[(0, 2)] - w[(2, 0)]) / 2.0,
            (w[(1, 0)] - w[(0, 1)]) / 2.0,
        ];
        for c in 0..3 {
            vel_exact.push((format!("ω[{n}][{c}]"), v0[v_index + 3 + c]));
            vel_fd.push(axial[c]);
        }
        v_index += 6;
    }
    // Accelerations: differences of every velocity above.
    let mut acc_exact = Vec::new();
    for j in 0..nq {
        acc_exact.push((format!("q''[{j}]"), s0.qdd().get(j).expect("q''")));
    }
    for (n, pt) in s0.points().iter().enumerate() {
        for c in 0..dim {
            acc_exact.push((format!("a[{n}][{c}]"), pt.acceleration()[c]));
        }
    }
    for (n, f) in s0.frames().iter().enumerate() {
        for c in 0..3 {
            acc_exact.push((format!("a_o[{n}][{c}]"), f.acceleration[c]));
        }
        for c in 0..3 {
            acc_exact.push((format!("α[{n}][{c}]"), f.angular_acceleration[c]));
        }
    }
    let acc_fd: Vec<f64> = (0..v0.len())
        .map(|i| d(v1[i], v2[i], w1[i], w2[i]))
        .collect();
    compare("velocity", &vel_exact, &vel_fd, tol);
    compare("acceleration", &acc_exact, &acc_fd, tol);
}

fn compare(what: &str, exact: &[(String, f64)], fd: &[f64], tol: f64) {
    let scale = exact.iter().fold(0.0f64, |s, (_, v)| s.max(v.abs()));
    for ((name, e), f) in exact.iter().zip(fd) {
        assert!(
            (e - f).abs() <= tol * scale.max(1e-12),
            "{what} {name}: exact {e}, finite difference {f} (scale {scale})"
        );
    }
}

/// Whether Φ_u at `pose` is comfortably regular (relative pivots ≥ 0.1).
#[must_use]
pub fn regular<M: Mechanism>(m: &M, pose: &M::Coords) -> bool {
    fn check<const N: usize>(j: &[f64]) -> bool {
        let mut a = [[0.0; N]; N];
        for (i, row) in a.iter_mut().enumerate() {
            row.copy_from_slice(&j[i * N..(i + 1) * N]);
        }
        Lu::factor(&a, 0.1).is_ok()
    }
    let n = M::UNKNOWNS;
    let mut j = vec![0.0; n * n];
    m.jacobian_into(pose, &mut j);
    match n {
        0 => true,
        1 => check::<1>(&j),
        2 => check::<2>(&j),
        3 => check::<3>(&j),
        4 => check::<4>(&j),
        5 => check::<5>(&j),
        6 => check::<6>(&j),
        _ => false,
    }
}

/// Assembles from the exact configuration perturbed by up to 0.01 (rad, or
/// 1 % of a length) and checks that Newton returns to it: the branch follows
/// the guess. (Larger perturbations can be nearer the other branch for the
/// samples close to a toggle position; assembly from rough guesses is tested
/// on the textbook mechanisms.)
pub fn assemble_back<M: Mechanism>(m: &M, exact: &M::Coords, rng: &mut Rng) -> M::Coords {
    let mut guess = *exact;
    for j in M::DRIVERS..M::DRIVERS + M::UNKNOWNS {
        let v = exact.get(j).expect("coordinate");
        guess.set(j, v + rng.range(-0.01, 0.01) * v.abs().max(1.0));
    }
    let pose = match m.assemble_with(&guess, &kinematics_core::Options::DEFAULT) {
        Ok(p) => p,
        Err(e) => {
            let mut r = vec![0.0; M::EQUATIONS];
            m.residual_into(&guess, &mut r);
            panic!("guess {guess:?} exact {exact:?} residual at guess {r:?}: {e}");
        }
    };
    for j in 0..M::DRIVERS + M::UNKNOWNS {
        let (a, b) = (pose.get(j).expect("q"), exact.get(j).expect("q"));
        assert!((a - b).abs() < 1e-9, "coordinate {j}: {a} vs {b}");
    }
    pose
}

kinematics_core::mechanism! {
    /// A four-bar written with the square root of its coupler's length (a
    /// form no closed form covers): solved by Newton–Raphson.
    pub struct DistanceFourBar {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Rocker.
            c,
            /// Ground.
            d
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns {
            /// Rocker angle.
            th4
        }
        constraints {
            sqrt(norm(polar(a, phi) - vec2(d, 0.0) - polar(c, th4))) == sqrt(b);
        }
    }
}

kinematics_core::mechanism! {
    /// A four-bar whose rocker, extended by e, carries a link f whose far
    /// end is a pin in a slot along the parabola x = h + k y²: the
    /// four-bar's dyad in closed form, then the pin's (θ5, y) by
    /// Newton–Raphson on that block (a mixed mechanism).
    pub struct SlotSixBar {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Rocker.
            c,
            /// Ground.
            d,
            /// Rocker extension.
            e,
            /// Link to the pin.
            f,
            /// Vertex of the slot.
            h,
            /// Curvature of the slot.
            k
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns { th3, th4, th5, y }
        loops {
            polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4);
            vec2(d, 0.0) + polar(e, th4) + polar(f, th5) == vec2(h + k * y * y, y);
        }
    }
}

impl SlotSixBar {
    /// A Grashof crank-rocker whose pin reaches the slot over a whole turn
    /// in both modes of the four-bar (checked with an independent solve
    /// when the geometry was chosen).
    pub const EXAMPLE: Self = Self {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        e: 0.05,
        f: 0.16,
        h: 0.2,
        k: 2.0,
    };

    /// A guess at crank angle `phi` for the slot's Newton block, with the
    /// pin on the side `side` (±1: the sign of the four-bar's mode, which
    /// the pin's side follows); the closed-form block needs none.
    #[must_use]
    pub fn guess(phi: f64, side: f64) -> SlotSixBarCoords {
        SlotSixBarCoords {
            phi,
            th3: 0.0,
            th4: 0.0,
            th5: 0.6 * side,
            y: 0.13 * side,
        }
    }
}

/// A non-Grashof four-bar (d + a = 0.16 > b + c = 0.14), assembled at
/// φ = 0, and its limit angle: the crank cannot pass the angle where
/// coupler and rocker are in line, BD = b + c, cos φ = (a² + d² −
/// (b + c)²) / (2ad).
#[must_use]
pub fn non_grashof_four_bar() -> (
    kinematics_examples::FourBar,
    kinematics_examples::FourBarCoords,
    f64,
) {
    let m = kinematics_examples::FourBar {
        a: 0.05,
        b: 0.08,
        c: 0.06,
        d: 0.11,
        p: 0.0,
        beta: 0.0,
    };
    let limit = ((m.a * m.a + m.d * m.d - (m.b + m.c).powi(2)) / (2.0 * m.a * m.d)).acos();
    let start = m
        .assemble(&kinematics_examples::FourBarCoords {
            phi: 0.0,
            th3: 0.5,
            th4: 1.5,
        })
        .expect("assembles");
    (m, start, limit)
}
