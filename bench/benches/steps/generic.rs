//! The same step with derivatives from forward-mode dual numbers
//! (`num-dual`) or from central finite differences, over the residual and
//! outputs written once, generically (`models::Generic`).
//!
//! Dual numbers: Φ_u from one evaluation with a vector dual of the
//! unknowns; Φ_d d' from a dual in direction (d', 0); the convective term
//! γ = d²/ds² Φ(q + s q') from a second-order dual in direction q'; points
//! and rotations likewise (v = dr/ds, a = d²r/ds² + r_q q'').

use kinematics_core::solve::Lu;
use num_dual::{Dual2_64, Dual64, DualSVec64};

use crate::models::Generic;

const TOL: f64 = 1e-12;
const MAX_IT: usize = 50;

/// Everything a step produces, summed.
fn checksum<const NQ: usize>(q: &[f64; NQ], qd: &[f64; NQ], qdd: &[f64; NQ], nd: usize) -> f64 {
    (nd..NQ).map(|j| q[j] + qd[j] + qdd[j]).sum()
}

fn axial(w: &[f64; 9]) -> [f64; 3] {
    [
        (w[7] - w[5]) / 2.0,
        (w[2] - w[6]) / 2.0,
        (w[3] - w[1]) / 2.0,
    ]
}

/// A · Bᵀ for row-major 3×3 matrices.
fn mul_t(a: &[f64; 9], b: &[f64; 9]) -> [f64; 9] {
    std::array::from_fn(|k| {
        let (i, j) = (k / 3, k % 3);
        a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] + a[3 * i + 2] * b[3 * j + 2]
    })
}

/// Point and frame outputs from their position, first and second
/// directional derivatives along q' and the derivative along q''.
fn outputs(p: [[f64; 3]; 4], r: Option<[[f64; 9]; 4]>) -> f64 {
    let mut sum = 0.0;
    for c in 0..3 {
        sum += p[0][c] + p[1][c] + p[2][c] + p[3][c];
    }
    if let Some([r0, r1, r2, r3]) = r {
        let rdd: [f64; 9] = std::array::from_fn(|k| r2[k] + r3[k]);
        let w = axial(&mul_t(&r1, &r0));
        let al = axial(&mul_t(&rdd, &r0));
        sum += r0.iter().sum::<f64>() + w.iter().sum::<f64>() + al.iter().sum::<f64>();
    }
    sum
}

/// One step with dual numbers. `q` holds the drivers (set by the caller)
/// and the previous unknowns; `qd`, `qdd` the driver rates in their first
/// entries.
pub fn dual_step<M: Generic, const NQ: usize, const NU: usize>(
    m: &M,
    q: &mut [f64; NQ],
    qd: &mut [f64; NQ],
    qdd: &mut [f64; NQ],
) -> f64 {
    let nd = M::ND;
    // Newton with Φ_u from vector duals.
    let mut jac = [[0.0; NU]; NU];
    for _ in 0..MAX_IT {
        let x: [DualSVec64<NU>; NQ] = std::array::from_fn(|j| {
            let d = DualSVec64::<NU>::from_re(q[j]);
            if j >= nd {
                d.derivative(j - nd)
            } else {
                d
            }
        });
        let mut f = [DualSVec64::<NU>::from_re(0.0); NU];
        m.residual(&x, &mut f);
        for i in 0..NU {
            for k in 0..NU {
                jac[i][k] = f[i].eps.0.as_ref().map_or(0.0, |e| e[k]);
            }
        }
        let r: [f64; NU] = std::array::from_fn(|i| f[i].re);
        if r.iter().all(|v| v.abs() < TOL) {
            break;
        }
        let Ok(lu) = Lu::factor(&jac, 1e-14) else {
            break;
        };
        let step = lu.solve(&r);
        for k in 0..NU {
            q[nd + k] -= step[k];
        }
    }
    let lu = Lu::factor(&jac, 0.0).ok();
    let solve = |b: &[f64; NU]| lu.as_ref().map_or([0.0; NU], |l| l.solve(b));
    // Velocity: Φ_u u' = −Φ_d d'.
    let x: [Dual64; NQ] =
        std::array::from_fn(|j| Dual64::new(q[j], if j < nd { qd[j] } else { 0.0 }));
    let mut f = [Dual64::from_re(0.0); NU];
    m.residual(&x, &mut f);
    let ud = solve(&std::array::from_fn(|i| -f[i].eps));
    qd[nd..].copy_from_slice(&ud);
    // Acceleration: Φ_u u'' = −Φ_d d'' − γ.
    let x: [Dual2_64; NQ] = std::array::from_fn(|j| Dual2_64::new(q[j], qd[j], 0.0));
    let mut g = [Dual2_64::from_re(0.0); NU];
    m.residual(&x, &mut g);
    let x: [Dual64; NQ] =
        std::array::from_fn(|j| Dual64::new(q[j], if j < nd { qdd[j] } else { 0.0 }));
    m.residual(&x, &mut f);
    let udd = solve(&std::array::from_fn(|i| -f[i].eps - g[i].v2));
    qdd[nd..].copy_from_slice(&udd);
    // Point (and frame): r, dr/ds, d²r/ds² along q', and r_q q''.
    let x2: [Dual2_64; NQ] = std::array::from_fn(|j| Dual2_64::new(q[j], qd[j], 0.0));
    let x1: [Dual64; NQ] = std::array::from_fn(|j| Dual64::new(q[j], qdd[j]));
    let mut p2 = [Dual2_64::from_re(0.0); 3];
    let mut p1 = [Dual64::from_re(0.0); 3];
    m.point(&x2, &mut p2[..M::DIM]);
    m.point(&x1, &mut p1[..M::DIM]);
    let p = [
        std::array::from_fn(|c| p2[c].re),
        std::array::from_fn(|c| p2[c].v1),
        std::array::from_fn(|c| p2[c].v2),
        std::array::from_fn(|c| p1[c].eps),
    ];
    let r = if M::HAS_FRAME {
        let mut r2 = [Dual2_64::from_re(0.0); 9];
        let mut r1 = [Dual64::from_re(0.0); 9];
        m.rotation(&x2, &mut r2);
        m.rotation(&x1, &mut r1);
        Some([
            std::array::from_fn(|k| r2[k].re),
            std::array::from_fn(|k| r2[k].v1),
            std::array::from_fn(|k| r2[k].v2),
            std::array::from_fn(|k| r1[k].eps),
        ])
    } else {
        None
    };
    checksum(q, qd, qdd, nd) + outputs(p, r) + drivers(q, nd)
}

fn drivers<const NQ: usize>(q: &[f64; NQ], nd: usize) -> f64 {
    if nd > 1 {
        q[..nd].iter().sum()
    } else {
        0.0
    }
}

/// Evaluates the residual at q + s·dir.
fn res_at<M: Generic, const NQ: usize, const NU: usize>(
    m: &M,
    q: &[f64; NQ],
    dir: &[f64; NQ],
    s: f64,
) -> [f64; NU] {
    let x: [f64; NQ] = std::array::from_fn(|j| q[j] + s * dir[j]);
    let mut f = [0.0; NU];
    m.residual(&x, &mut f);
    f
}

/// Φ_u by central differences with step `FD_H` in each unknown.
fn fd_jacobian<M: Generic, const NQ: usize, const NU: usize>(
    m: &M,
    q: &[f64; NQ],
    jac: &mut [[f64; NU]; NU],
) {
    for k in 0..NU {
        let mut e = [0.0; NQ];
        e[M::ND + k] = 1.0;
        let (fp, fm) = (
            res_at::<M, NQ, NU>(m, q, &e, FD_H),
            res_at::<M, NQ, NU>(m, q, &e, -FD_H),
        );
        for i in 0..NU {
            jac[i][k] = (fp[i] - fm[i]) / (2.0 * FD_H);
        }
    }
}

/// Difference step for first derivatives.
const FD_H: f64 = 1e-6;

/// One step with central finite differences (h = 1e-6 for first
/// derivatives, 1e-4 for second).
pub fn fd_step<M: Generic, const NQ: usize, const NU: usize>(
    m: &M,
    q: &mut [f64; NQ],
    qd: &mut [f64; NQ],
    qdd: &mut [f64; NQ],
) -> f64 {
    let nd = M::ND;
    let (h1, h2) = (FD_H, 1e-4);
    let mut jac = [[0.0; NU]; NU];
    let zero = [0.0; NQ];
    for _ in 0..MAX_IT {
        let r: [f64; NU] = res_at::<M, NQ, NU>(m, q, &zero, 0.0);
        if r.iter().all(|v| v.abs() < TOL) {
            break;
        }
        fd_jacobian(m, q, &mut jac);
        let Ok(lu) = Lu::factor(&jac, 1e-14) else {
            break;
        };
        let step = lu.solve(&r);
        for k in 0..NU {
            q[nd + k] -= step[k];
        }
    }
    fd_jacobian(m, q, &mut jac);
    let lu = Lu::factor(&jac, 0.0).ok();
    let solve = |b: &[f64; NU]| lu.as_ref().map_or([0.0; NU], |l| l.solve(b));
    let dd: [f64; NQ] = std::array::from_fn(|j| if j < nd { qd[j] } else { 0.0 });
    let (fp, fm) = (
        res_at::<M, NQ, NU>(m, q, &dd, h1),
        res_at::<M, NQ, NU>(m, q, &dd, -h1),
    );
    let ud = solve(&std::array::from_fn(|i| -(fp[i] - fm[i]) / (2.0 * h1)));
    qd[nd..].copy_from_slice(&ud);
    let f0 = res_at::<M, NQ, NU>(m, q, &zero, 0.0);
    let (gp, gm) = (
        res_at::<M, NQ, NU>(m, q, qd, h2),
        res_at::<M, NQ, NU>(m, q, qd, -h2),
    );
    let ddd: [f64; NQ] = std::array::from_fn(|j| if j < nd { qdd[j] } else { 0.0 });
    let (ap, am) = (
        res_at::<M, NQ, NU>(m, q, &ddd, h1),
        res_at::<M, NQ, NU>(m, q, &ddd, -h1),
    );
    let udd = solve(&std::array::from_fn(|i| {
        -(gp[i] - 2.0 * f0[i] + gm[i]) / (h2 * h2) - (ap[i] - am[i]) / (2.0 * h1)
    }));
    qdd[nd..].copy_from_slice(&udd);
    let at = |dir: &[f64; NQ], s: f64| {
        let x: [f64; NQ] = std::array::from_fn(|j| q[j] + s * dir[j]);
        let mut p = [0.0; 3];
        m.point(&x, &mut p[..M::DIM]);
        let mut r = [0.0; 9];
        m.rotation(&x, &mut r);
        (p, r)
    };
    let (p0, r0) = at(&zero, 0.0);
    let (pp, rp) = at(qd, h2);
    let (pm, rm) = at(qd, -h2);
    let (pa, ra) = at(qdd, h1);
    let (pb, rb) = at(qdd, -h1);
    let (pv1, rv1) = at(qd, h1);
    let (pw1, rw1) = at(qd, -h1);
    let d1 = |a: f64, b: f64| (a - b) / (2.0 * h1);
    let d2 = |a: f64, o: f64, b: f64| (a - 2.0 * o + b) / (h2 * h2);
    let p = [
        p0,
        std::array::from_fn(|c| d1(pv1[c], pw1[c])),
        std::array::from_fn(|c| d2(pp[c], p0[c], pm[c])),
        std::array::from_fn(|c| d1(pa[c], pb[c])),
    ];
    let r = M::HAS_FRAME.then(|| {
        [
            r0,
            std::array::from_fn(|k| d1(rv1[k], rw1[k])),
            std::array::from_fn(|k| d2(rp[k], r0[k], rm[k])),
            std::array::from_fn(|k| d1(ra[k], rb[k])),
        ]
    });
    checksum(q, qd, qdd, nd) + outputs(p, r) + drivers(q, nd)
}
