//! Hand-written, hand-differentiated steps: what an expert writes for each
//! mechanism. Each angle's sine and cosine are computed once and shared by
//! the residual, the Jacobian, the velocity and acceleration equations and
//! the point; 2×2 systems are solved by Cramer's rule; the six-bar is solved
//! dyad by dyad (its Jacobian is block triangular); the arm's velocities and
//! accelerations are propagated outward joint by joint.

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

/// M1: returns the checksum of one step.
pub fn m1_step(m: &m1::FourBar, phi: f64, th: &mut [f64; 2], w: f64, al: f64) -> f64 {
    let (s1, c1) = phi.sin_cos();
    let (ax, ay) = (m.a * c1, m.a * s1);
    let [mut t3, mut t4] = *th;
    let t = dyad(ax - m.d, ay, m.b, m.c, &mut t3, &mut t4);
    *th = [t3, t4];
    let rd = [-ay * w, ax * w];
    let rdd = [-ax * w * w - ay * al, -ay * w * w + ax * al];
    let (om, alpha) = dyad_rates(m.b, m.c, t, rd, rdd);
    // Coupler point P = B + p e(θ3 + β).
    let (sp, cp) = (th[0] + m.beta).sin_cos();
    let (px, py) = (m.p * cp, m.p * sp);
    let p = [ax + px, ay + py];
    let v = [rd[0] - py * om[0], rd[1] + px * om[0]];
    let a = [
        rdd[0] - px * om[0] * om[0] - py * alpha[0],
        rdd[1] - py * om[0] * om[0] + px * alpha[0],
    ];
    th[0] + th[1] + om[0] + om[1] + alpha[0] + alpha[1] + p[0] + p[1] + v[0] + v[1] + a[0] + a[1]
}

/// M2: Φ = |B − A|² − b² = 0 for ψ.
pub fn m2_step(m: &m2::Rssr, phi: f64, psi: &mut f64, w: f64, al: f64) -> f64 {
    let (sf, cf) = phi.sin_cos();
    let (ax, az) = (-m.a * cf, m.a * sf);
    let (mut sp, mut cp) = psi.sin_cos();
    for _ in 0..MAX_IT {
        let (dx, dy, dz) = (-m.d - m.c * cp - ax, m.c * sp, -az);
        let f = dx * dx + dy * dy + dz * dz - m.b * m.b;
        if f.abs() < TOL {
            break;
        }
        // ∂Φ/∂ψ = 2 D·∂B/∂ψ, ∂B/∂ψ = c (sin ψ, cos ψ, 0).
        let j = 2.0 * m.c * (dx * sp + dy * cp);
        *psi -= f / j;
        (sp, cp) = psi.sin_cos();
    }
    let (dx, dy, dz) = (-m.d - m.c * cp - ax, m.c * sp, -az);
    let (bx, by) = (m.c * sp, m.c * cp); // ∂B/∂ψ
    let j = 2.0 * (dx * bx + dy * by);
    // Ȧ = a (sin φ, 0, cos φ) φ'.
    let (adx, adz) = (m.a * sf * w, m.a * cf * w);
    let psid = 2.0 * (dx * adx + dz * adz) / j;
    let (bdx, bdy) = (bx * psid, by * psid);
    // Φ̈ = 2(Ḋ·Ḋ + D·D̈) = 0 with D̈ = B̈ − Ä.
    let (ddx, ddy, ddz) = (bdx - adx, bdy, -adz);
    let (aax, aaz) = (
        m.a * cf * w * w + m.a * sf * al,
        -m.a * sf * w * w + m.a * cf * al,
    );
    let (b0x, b0y) = (m.c * cp * psid * psid, -m.c * sp * psid * psid);
    let rest = ddx * ddx + ddy * ddy + ddz * ddz + dx * (b0x - aax) + dy * b0y - dz * aaz;
    let psidd = -2.0 * rest / j;
    let b = [-m.d - m.c * cp, m.c * sp, 0.0];
    let v = [bdx, bdy, 0.0];
    let a = [b0x + bx * psidd, b0y + by * psidd, 0.0];
    *psi + psid + psidd + b[0] + b[1] + b[2] + v[0] + v[1] + v[2] + a[0] + a[1] + a[2]
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
