//! Helpers shared by the integration tests: a seeded random generator and
//! finite-difference checks that are independent of the generated
//! derivatives (they use only assembled positions and residuals).
//!
//! These helpers are test assertions: they panic on a failed check.
#![allow(clippy::expect_used, clippy::panic)]
// Component loops index several arrays in step.
#![allow(clippy::needless_range_loop)]

use kinematics_core::{Coordinates, Mechanism, MotionState, Options, PointState};

/// SplitMix64: a small, seeded, reproducible generator.
pub struct Rng(u64);

impl Rng {
    /// A generator from a fixed seed.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // 53 random bits into [0, 1); the shift leaves an exact integer.
        #[allow(clippy::cast_precision_loss)]
        let v = (z >> 11) as f64;
        v / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// An angle uniform in [−π, π).
    pub fn angle(&mut self) -> f64 {
        self.range(-std::f64::consts::PI, std::f64::consts::PI)
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

/// Checks velocities against central differences of assembled positions and
/// accelerations against central differences of computed velocities, for
/// every coordinate, point and frame (ω against differences of R, α against
/// differences of ω), along d(t) = d₀ + d'·t + ½ d''·t².
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
    let nq = M::DRIVERS + M::UNKNOWNS;
    let np = M::POINTS;
    let opts = Options::DEFAULT;
    let s0 = m
        .analyze_slices(pose, rates, accels, &opts)
        .expect("analysis at the pose");
    let h = 1e-6;
    let pp = pose_at(m, pose, rates, accels, h);
    let pm = pose_at(m, pose, rates, accels, -h);
    // Rates of the drivers at ±h, for the velocity-difference check.
    let rates_at =
        |t: f64| -> Vec<f64> { rates.iter().zip(accels).map(|(r, a)| r + a * t).collect() };
    let sp = m
        .analyze_slices(&pp, &rates_at(h), accels, &opts)
        .expect("analysis at +h");
    let sm = m
        .analyze_slices(&pm, &rates_at(-h), accels, &opts)
        .expect("analysis at -h");

    let mut vel_exact = Vec::new();
    let mut vel_fd = Vec::new();
    let mut acc_exact = Vec::new();
    let mut acc_fd = Vec::new();
    for j in 0..nq {
        let g = |c: &M::Coords| c.get(j).expect("coordinate");
        vel_exact.push((format!("q'[{j}]"), g(s0.qd())));
        vel_fd.push((g(&pp) - g(&pm)) / (2.0 * h));
        acc_exact.push((format!("q''[{j}]"), g(s0.qdd())));
        acc_fd.push((g(sp.qd()) - g(sm.qd())) / (2.0 * h));
    }
    let dim = M::POINT_DIM;
    let mut rp = vec![0.0; np * dim];
    let mut rm = vec![0.0; np * dim];
    m.point_positions_into(&pp, &mut rp);
    m.point_positions_into(&pm, &mut rm);
    for k in 0..np {
        let p0 = s0.points()[k];
        for c in 0..dim {
            vel_exact.push((format!("v[{k}][{c}]"), p0.velocity()[c]));
            vel_fd.push((rp[k * dim + c] - rm[k * dim + c]) / (2.0 * h));
            acc_exact.push((format!("a[{k}][{c}]"), p0.acceleration()[c]));
            acc_fd.push((sp.points()[k].velocity()[c] - sm.points()[k].velocity()[c]) / (2.0 * h));
        }
    }
    // Frames: ω against the axial vector of (R(t+h) − R(t−h))/(2h) · Rᵀ, and
    // α against central differences of ω.
    let nf = M::FRAMES;
    let mut r0 = vec![kinematics_core::nalgebra::Matrix3::zeros(); nf];
    let mut rpl = r0.clone();
    let mut rmi = r0.clone();
    m.frame_rotations_into(pose, &mut r0);
    m.frame_rotations_into(&pp, &mut rpl);
    m.frame_rotations_into(&pm, &mut rmi);
    for k in 0..nf {
        let w = (rpl[k] - rmi[k]) / (2.0 * h) * r0[k].transpose();
        let axial = [
            (w[(2, 1)] - w[(1, 2)]) / 2.0,
            (w[(0, 2)] - w[(2, 0)]) / 2.0,
            (w[(1, 0)] - w[(0, 1)]) / 2.0,
        ];
        let f0 = s0.frames()[k];
        for c in 0..3 {
            vel_exact.push((format!("ω[{k}][{c}]"), f0.angular_velocity[c]));
            vel_fd.push(axial[c]);
            acc_exact.push((format!("α[{k}][{c}]"), f0.angular_acceleration[c]));
            acc_fd.push(
                (sp.frames()[k].angular_velocity[c] - sm.frames()[k].angular_velocity[c])
                    / (2.0 * h),
            );
            vel_exact.push((format!("v_o[{k}][{c}]"), f0.velocity[c]));
            vel_fd.push((sp.frames()[k].origin[c] - sm.frames()[k].origin[c]) / (2.0 * h));
            acc_exact.push((format!("a_o[{k}][{c}]"), f0.acceleration[c]));
            acc_fd.push((sp.frames()[k].velocity[c] - sm.frames()[k].velocity[c]) / (2.0 * h));
        }
    }
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
