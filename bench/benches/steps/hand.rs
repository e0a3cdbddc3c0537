//! Hand-written, hand-differentiated steps: what an expert writes for each
//! mechanism. Each angle's sine and cosine are computed once and shared by
//! the residual, the Jacobian, the velocity and acceleration equations and
//! the point; 2×2 systems are solved by Cramer's rule; the six-bar is solved
//! dyad by dyad (its Jacobian is block triangular); the arm's velocities and
//! accelerations are propagated outward joint by joint. M1 and M2 also carry
//! the converged sines and cosines to the next step and hoist the
//! driver-only parts of the residual (5 and 3 `sin_cos` per step).

use crate::models::{m1, m2, m3, m4};

const TOL: f64 = 1e-12;
const MAX_IT: usize = 50;

/// One four-bar dyad: loop r + b e(θ_b) − c e(θ_c) = 0 with (rx, ry) known.
/// Solves θ_b, θ_c by Newton and returns their sines and cosines.
fn dyad(rx: f64, ry: f64, b: f64, c: f64, tb: &mut f64, tc: &mut f64) -> [f64; 4] {
    for _ in 0..MAX_IT {
        let (sb, cb) = tb.sin_cos();
        let (sc, cc) = tc.sin_cos();
        let f0 = rx + b * cb - c * cc;
        let f1 = ry + b * sb - c * sc;
        if f0.abs().max(f1.abs()) < TOL {
            return [sb, cb, sc, cc];
        }
        // J = [[−b sb, c sc], [b cb, −c cc]], det = b c sin(θ_b − θ_c).
        let det = b * c * (sb * cc - cb * sc);
        *tb -= (-c * cc * f0 - c * sc * f1) / det;
        *tc -= (-b * cb * f0 - b * sb * f1) / det;
    }
    let (sb, cb) = tb.sin_cos();
    let (sc, cc) = tc.sin_cos();
    [sb, cb, sc, cc]
}

/// Velocities and accelerations of a dyad: with J as above,
/// J (ω_b, ω_c) = −ṙ and J (α_b, α_c) = −r̈ − (−b cb ω_b² + c cc ω_c², −b sb ω_b² + c sc ω_c²).
fn dyad_rates(b: f64, c: f64, t: [f64; 4], rd: [f64; 2], rdd: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    let [sb, cb, sc, cc] = t;
    let det = b * c * (sb * cc - cb * sc);
    let solve = |r0: f64, r1: f64| {
        // J x = r by Cramer's rule.
        let x0 = (r0 * (-c * cc) - c * sc * r1) / det;
        let x1 = (-b * sb * r1 - b * cb * r0) / det;
        [x0, x1]
    };
    let w = solve(-rd[0], -rd[1]);
    let g0 = -b * cb * w[0] * w[0] + c * cc * w[1] * w[1];
    let g1 = -b * sb * w[0] * w[0] + c * sc * w[1] * w[1];
    let al = solve(-rdd[0] - g0, -rdd[1] - g1);
    (w, al)
}

/// The unknown angles carried from one step to the next with their sines
/// and cosines: the converged iterate of a step is the first iterate of the
/// next, whose sines and cosines are therefore known.
pub struct Carried<const N: usize> {
    /// The angles.
    pub angles: [f64; N],
    /// sin and cos of each, valid for `angles`.
    trig: [(f64, f64); N],
}

impl<const N: usize> Carried<N> {
    /// Starts from `angles` (their sines and cosines computed once).
    pub fn new(angles: [f64; N]) -> Self {
        Self {
            angles,
            trig: angles.map(f64::sin_cos),
        }
    }
}

/// M1, as an expert writes it: sin/cos of the driver once per position and
/// of each unknown angle once per Newton iterate after the first (the first
/// is the previous position's converged pose, carried over); the converged
/// iterate's sines and cosines serve the Jacobian, the velocities, the
/// accelerations and the coupler point, whose offset angle θ3 + β is formed
/// by the addition theorem with sin β, cos β given; 2×2 solves by Cramer's
/// rule; only max|Φ| < tol tested in the loop. Five `sin_cos` per step
/// when Newton takes two iterations. Returns the checksum of one step.
pub fn m1_step(
    m: &m1::FourBar,
    (sin_beta, cos_beta): (f64, f64),
    phi: f64,
    st: &mut Carried<2>,
    w: f64,
    al: f64,
) -> f64 {
    let (b, c) = (m.b, m.c);
    let (s1, c1) = phi.sin_cos();
    let (ax, ay) = (m.a * c1, m.a * s1);
    m1_newton(m, ax - m.d, ay, st);
    let [t3, t4] = st.angles;
    let [(sb, cb), (sc, cc)] = st.trig;
    let rd = [-ay * w, ax * w];
    let rdd = [-ax * w * w - ay * al, -ay * w * w + ax * al];
    let (om, alpha) = dyad_rates(b, c, [sb, cb, sc, cc], rd, rdd);
    // Coupler point P = B + p e(θ3 + β), by the addition theorem.
    let (sp, cp) = (sb * cos_beta + cb * sin_beta, cb * cos_beta - sb * sin_beta);
    let (px, py) = (m.p * cp, m.p * sp);
    let p = [ax + px, ay + py];
    let v = [rd[0] - py * om[0], rd[1] + px * om[0]];
    let a = [
        rdd[0] - px * om[0] * om[0] - py * alpha[0],
        rdd[1] - py * om[0] * om[0] + px * alpha[0],
    ];
    t3 + t4 + om[0] + om[1] + alpha[0] + alpha[1] + p[0] + p[1] + v[0] + v[1] + a[0] + a[1]
}

/// M2, as an expert writes it. With k = a cos φ − d, the residual
/// Φ = |B − A|² − b² = f₀(φ) + g(φ) cos ψ, f₀ = k² + c² + a² sin²φ − b²,
/// g = −2kc, is hoisted out of the Newton loop, whose iterate costs one
/// `sin_cos` (none for the first, carried over): three per step when Newton
/// takes two iterations. Velocities and accelerations from the derivatives
/// of Φ: Φ_φ = 2a sin φ (d + c cos ψ), Φ_ψ = 2kc sin ψ,
/// Φ_φφ = 2a cos φ (d + c cos ψ), Φ_φψ = −2ac sin φ sin ψ, Φ_ψψ = 2kc cos ψ.
pub fn m2_step(m: &m2::Rssr, phi: f64, st: &mut Carried<1>, w: f64, al: f64) -> f64 {
    let (sf, cf) = phi.sin_cos();
    let k = m.a * cf - m.d;
    let g = m2_newton(m, sf, k, st);
    let [psi] = st.angles;
    let [(sp, cp)] = st.trig;
    let phi_psi = -g * sp;
    let e = m.d + m.c * cp;
    let phi_phi = 2.0 * m.a * sf * e;
    let psid = -phi_phi * w / phi_psi;
    let phi_phiphi = 2.0 * m.a * cf * e;
    let phi_phipsi = -2.0 * m.a * m.c * sf * sp;
    let phi_psipsi = -g * cp;
    let psidd = -(phi_phiphi * w * w
        + 2.0 * phi_phipsi * w * psid
        + phi_psipsi * psid * psid
        + phi_phi * al)
        / phi_psi;
    // B = (−d − c cos ψ, c sin ψ, 0) and its velocity and acceleration.
    let b = [-m.d - m.c * cp, m.c * sp, 0.0];
    let v = [m.c * sp * psid, m.c * cp * psid, 0.0];
    let a = [
        m.c * (cp * psid * psid + sp * psidd),
        m.c * (-sp * psid * psid + cp * psidd),
        0.0,
    ];
    psi + psid + psidd + b[0] + b[1] + b[2] + v[0] + v[1] + v[2] + a[0] + a[1] + a[2]
}

/// M1's Newton loop for θ3, θ4 with (rx, ry) = A − D known, from the
/// carried pose (each angle's `sin_cos` once per iterate after the first),
/// the converged pose carried on in `st`.
#[inline(always)]
fn m1_newton(m: &m1::FourBar, rx: f64, ry: f64, st: &mut Carried<2>) {
    let (b, c) = (m.b, m.c);
    let [mut t3, mut t4] = st.angles;
    let [(mut sb, mut cb), (mut sc, mut cc)] = st.trig;
    for _ in 0..MAX_IT {
        let f0 = rx + b * cb - c * cc;
        let f1 = ry + b * sb - c * sc;
        if f0.abs().max(f1.abs()) < TOL {
            break;
        }
        // J = [[−b sb, c sc], [b cb, −c cc]], det = b c sin(θ3 − θ4).
        let det = b * c * (sb * cc - cb * sc);
        t3 -= (-c * cc * f0 - c * sc * f1) / det;
        t4 -= (-b * cb * f0 - b * sb * f1) / det;
        (sb, cb) = t3.sin_cos();
        (sc, cc) = t4.sin_cos();
    }
    st.angles = [t3, t4];
    st.trig = [(sb, cb), (sc, cc)];
}

/// M1's positions only, as an expert writes them: `m1_step`'s Newton loop
/// (the driver's `sin_cos` once, each angle's once per iterate after the
/// first, the converged pose carried to the next position) without the
/// rates; returns θ3 + θ4.
pub fn m1_pose(m: &m1::FourBar, phi: f64, st: &mut Carried<2>) -> f64 {
    let (s1, c1) = phi.sin_cos();
    m1_newton(m, m.a * c1 - m.d, m.a * s1, st);
    st.angles[0] + st.angles[1]
}

/// M2's Newton loop for ψ with sin φ and k = a cos φ − d known: the
/// residual hoisted to f₀ + g cos ψ, one `sin_cos` per iterate after the
/// first, the converged pose carried on in `st`; returns g = −2kc.
#[inline(always)]
fn m2_newton(m: &m2::Rssr, sf: f64, k: f64, st: &mut Carried<1>) -> f64 {
    let f0 = k * k + m.c * m.c + m.a * m.a * sf * sf - m.b * m.b;
    let g = -2.0 * k * m.c;
    let [mut psi] = st.angles;
    let [(mut sp, mut cp)] = st.trig;
    for _ in 0..MAX_IT {
        let f = f0 + g * cp;
        if f.abs() < TOL {
            break;
        }
        psi -= f / (-g * sp);
        (sp, cp) = psi.sin_cos();
    }
    st.angles = [psi];
    st.trig = [(sp, cp)];
    g
}

/// M2's positions only, as an expert writes them: `m2_step`'s hoisted
/// residual and Newton loop without the rates; returns ψ.
pub fn m2_pose(m: &m2::Rssr, phi: f64, st: &mut Carried<1>) -> f64 {
    let (sf, cf) = phi.sin_cos();
    m2_newton(m, sf, m.a * cf - m.d, st);
    st.angles[0]
}

/// M3's positions only: the two dyads of `m3_step` without the rates;
/// returns the sum of the four angles.
pub fn m3_pose(m: &m3::Watt, phi: f64, th: &mut [f64; 4]) -> f64 {
    let (s1, c1) = phi.sin_cos();
    let (mut t3, mut t4) = (th[0], th[1]);
    dyad(m.a * c1 - m.d, m.a * s1, m.b, m.c, &mut t3, &mut t4);
    let (se, ce) = (t4 + m.gamma).sin_cos();
    let (mut t5, mut t6) = (th[2], th[3]);
    dyad(
        m.d + m.e * ce - m.gx,
        m.e * se - m.gy,
        m.f,
        m.g,
        &mut t5,
        &mut t6,
    );
    *th = [t3, t4, t5, t6];
    th.iter().sum()
}

/// M3: the four-bar dyad, then the output dyad driven by the rocker.
pub fn m3_step(m: &m3::Watt, phi: f64, th: &mut [f64; 4], w: f64, al: f64) -> f64 {
    let (s1, c1) = phi.sin_cos();
    let (ax, ay) = (m.a * c1, m.a * s1);
    let (mut t3, mut t4) = (th[0], th[1]);
    let t = dyad(ax - m.d, ay, m.b, m.c, &mut t3, &mut t4);
    let rd = [-ay * w, ax * w];
    let rdd = [-ax * w * w - ay * al, -ay * w * w + ax * al];
    let (om, alpha) = dyad_rates(m.b, m.c, t, rd, rdd);
    // Second loop: E − G + f e(θ5) − g e(θ6) = 0, E = D + e e(θ4 + γ).
    let (se, ce) = (t4 + m.gamma).sin_cos();
    let (ex, ey) = (m.d + m.e * ce, m.e * se);
    let (mut t5, mut t6) = (th[2], th[3]);
    let u = dyad(ex - m.gx, ey - m.gy, m.f, m.g, &mut t5, &mut t6);
    let ed = [-m.e * se * om[1], m.e * ce * om[1]];
    let edd = [
        -m.e * ce * om[1] * om[1] - m.e * se * alpha[1],
        -m.e * se * om[1] * om[1] + m.e * ce * alpha[1],
    ];
    let (om2, alpha2) = dyad_rates(m.f, m.g, u, ed, edd);
    *th = [t3, t4, t5, t6];
    let (s5, c5) = (u[0], u[1]);
    let p = [ex + m.f * c5, ey + m.f * s5];
    let v = [ed[0] - m.f * s5 * om2[0], ed[1] + m.f * c5 * om2[0]];
    let a = [
        edd[0] - m.f * c5 * om2[0] * om2[0] - m.f * s5 * alpha2[0],
        edd[1] - m.f * s5 * om2[0] * om2[0] + m.f * c5 * alpha2[0],
    ];
    th.iter().sum::<f64>()
        + om[0]
        + om[1]
        + om2[0]
        + om2[1]
        + alpha[0]
        + alpha[1]
        + alpha2[0]
        + alpha2[1]
        + p[0]
        + p[1]
        + v[0]
        + v[1]
        + a[0]
        + a[1]
}

type V3 = [f64; 3];
type M3 = [[f64; 3]; 3];

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn column(r: &M3, k: usize) -> V3 {
    [r[0][k], r[1][k], r[2][k]]
}
/// R · R_axis(q), with (s, c) = sin q, cos q, for axis x (0) or y (1).
fn post(r: &M3, axis: usize, s: f64, c: f64) -> M3 {
    let mut o = *r;
    for row in &mut o {
        let (i, j) = if axis == 0 { (1, 2) } else { (2, 0) };
        let (ri, rj) = (row[i], row[j]);
        row[i] = ri * c + rj * s;
        row[j] = -ri * s + rj * c;
    }
    o
}

/// M4: forward recursion of rotation, ω, α, origin velocity and
/// acceleration along the chain; the tool frame and the tool point.
pub fn m4_step(m: &m4::Arm, q: &[f64; 6], qd: &[f64; 6], qdd: &[f64; 6]) -> f64 {
    let sc: [(f64, f64); 6] = std::array::from_fn(|i| q[i].sin_cos());
    // Joint 1 about z at (0, 0, d1).
    let (s, c) = sc[0];
    let mut r: M3 = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
    let mut o = [0.0, 0.0, m.d1];
    let mut w = [0.0, 0.0, qd[0]];
    let mut al = [0.0, 0.0, qdd[0]];
    let (mut v, mut a) = ([0.0; 3], [0.0; 3]);
    // Each later joint: axis (x = 0, y = 1) and the offset along x before it.
    let joints = [(1, 0.0), (1, m.a2), (0, 0.0), (1, m.a3), (0, m.d5)];
    for (k, &(axis, offset)) in joints.iter().enumerate() {
        if offset != 0.0 {
            let d = scale(column(&r, 0), offset);
            let wd = cross(w, d);
            o = add(o, d);
            a = add(add(a, cross(al, d)), cross(w, wd));
            v = add(v, wd);
        }
        // The joint axis in fixed coordinates (before this joint turns).
        let z = column(&r, axis);
        let wj = scale(z, qd[k + 1]);
        al = add(add(al, scale(z, qdd[k + 1])), cross(w, wj));
        w = add(w, wj);
        let (s, c) = sc[k + 1];
        r = post(&r, axis, s, c);
    }
    let d = scale(column(&r, 0), m.d6);
    let wd = cross(w, d);
    let p = add(o, d);
    let pv = add(v, wd);
    let pa = add(add(a, cross(al, d)), cross(w, wd));
    let mut sum = 0.0;
    for i in 0..3 {
        sum += p[i] + pv[i] + pa[i] + w[i] + al[i] + r[i][0] + r[i][1] + r[i][2];
    }
    sum + q.iter().sum::<f64>()
}
