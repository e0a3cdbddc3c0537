//! Dense LU factors on slices, for run-time models' Jacobians and the
//! implicit integrator's iteration matrix: the factorisation with partial
//! pivoting (unrolled for 2 × 2), its solves, the sign of the determinant
//! and the conditioning 1/‖A⁻¹‖∞.

/// LU factorisation with partial pivoting of the n × n row-major `a`:
/// the factors in place, the row permutation into `perm`; the sign of the
/// permutation, or `None` at a zero or non-finite pivot.
pub(crate) fn lu(a: &mut [f64], perm: &mut [usize], n: usize) -> Option<f64> {
    lu_above(a, perm, n, 0.0).ok()
}

/// [`lu`] whose pivots must exceed `threshold` in magnitude (and be
/// finite), as `solve::Lu::factor` requires of generated code's: at the
/// first that does not, `Err((k, |pivot|))` for column k.
pub(crate) fn lu_above(
    a: &mut [f64],
    perm: &mut [usize],
    n: usize,
    threshold: f64,
) -> Result<f64, (usize, f64)> {
    if n == 2 {
        lu2(a, perm, threshold)
    } else {
        lu_general(a, perm, n, threshold)
    }
}

/// Whether a pivot of magnitude `p` is regular: above the threshold and
/// finite (false for a NaN).
fn regular(p: f64, threshold: f64) -> bool {
    p > threshold && p.is_finite()
}

/// [`lu`] of a 2 × 2 matrix: the same operations, unrolled (loops over
/// ranges this short cost more than the arithmetic); the same pivot, the
/// last of equals, as `max_by` takes it.
fn lu2(a: &mut [f64], perm: &mut [usize], threshold: f64) -> Result<f64, (usize, f64)> {
    if let ([a00, a01, a10, a11], [p0, p1]) = (&mut *a, &mut *perm) {
        let swap = a10.abs().total_cmp(&a00.abs()).is_ge();
        if swap {
            core::mem::swap(a00, a10);
            core::mem::swap(a01, a11);
        }
        (*p0, *p1) = if swap { (1, 0) } else { (0, 1) };
        if !regular(a00.abs(), threshold) {
            return Err((0, a00.abs()));
        }
        let f = *a10 / *a00;
        *a10 = f;
        *a11 -= f * *a01;
        if !regular(a11.abs(), threshold) {
            return Err((1, a11.abs()));
        }
        return Ok(if swap { -1.0 } else { 1.0 });
    }
    lu_general(a, perm, 2, threshold)
}

/// [`lu`] of any size.
fn lu_general(
    a: &mut [f64],
    perm: &mut [usize],
    n: usize,
    threshold: f64,
) -> Result<f64, (usize, f64)> {
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    let mut sign = 1.0;
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
            .unwrap_or(k);
        let pivot = a[p * n + k];
        if !regular(pivot.abs(), threshold) {
            return Err((k, pivot.abs()));
        }
        if p != k {
            for j in 0..n {
                a.swap(p * n + j, k * n + j);
            }
            perm.swap(p, k);
            sign = -sign;
        }
        for i in k + 1..n {
            let f = a[i * n + k] / pivot;
            a[i * n + k] = f;
            for j in k + 1..n {
                a[i * n + j] -= f * a[k * n + j];
            }
        }
    }
    Ok(sign)
}

/// x with A x = b, from the factors of [`lu`] (NaN where A is singular).
pub(crate) fn lu_apply(lu: &[f64], perm: &[usize], b: &[f64], x: &mut [f64], n: usize) {
    if n == 2 {
        lu_apply2(lu, perm, b, x);
    } else {
        lu_apply_general(lu, perm, b, x, n);
    }
}

/// [`lu_apply`] for a 2 × 2 matrix: the same operations, unrolled.
fn lu_apply2(lu: &[f64], perm: &[usize], b: &[f64], x: &mut [f64]) {
    if let ([l00, l01, l10, l11], [p0, p1], [x0, x1]) = (lu, perm, &mut *x) {
        let (mut y0, mut y1) = (b[*p0], b[*p1]);
        y1 -= l10 * y0;
        y1 /= l11;
        y0 -= l01 * y1;
        y0 /= l00;
        (*x0, *x1) = (y0, y1);
        return;
    }
    lu_apply_general(lu, perm, b, x, 2);
}

/// [`lu_apply`] of any size.
fn lu_apply_general(lu: &[f64], perm: &[usize], b: &[f64], x: &mut [f64], n: usize) {
    for (xi, &p) in x.iter_mut().zip(perm) {
        *xi = b[p];
    }
    for i in 0..n {
        for j in 0..i {
            x[i] -= lu[i * n + j] * x[j];
        }
    }
    for i in (0..n).rev() {
        for j in i + 1..n {
            x[i] -= lu[i * n + j] * x[j];
        }
        x[i] /= lu[i * n + i];
    }
}

/// 1/‖A⁻¹‖∞ and the row of A⁻¹ with the largest absolute sum (the unknown
/// the equations determine worst); (0, 0) when A is singular. `a` is
/// overwritten by its factors; `scratch` holds three arrays of n.
pub(crate) fn conditioning(
    a: &mut [f64],
    n: usize,
    perm: &mut [usize],
    scratch: [&mut [f64]; 3],
) -> (f64, usize) {
    match n {
        0 => return (1.0, 0),
        // |A⁻¹| = 1/|a|.
        1 => return (if a[0].is_finite() { a[0].abs() } else { 0.0 }, 0),
        // A⁻¹ = [[d, −b], [−c, a]] / det: its rows' absolute sums are
        // (|d| + |b|) / |det| and (|c| + |a|) / |det|.
        2 => {
            let det = a[0] * a[3] - a[1] * a[2];
            let (r0, r1) = (a[3].abs() + a[1].abs(), a[2].abs() + a[0].abs());
            let (at, worst) = if r1 >= r0 { (1, r1) } else { (0, r0) };
            let c = det.abs() / worst;
            return (if c.is_finite() { c } else { 0.0 }, at);
        }
        _ => {}
    }
    let [col, unit, sums] = scratch;
    if lu(a, perm, n).is_none() {
        return (0.0, 0);
    }
    sums.fill(0.0);
    for j in 0..n {
        unit.fill(0.0);
        unit[j] = 1.0;
        lu_apply(a, perm, unit, col, n);
        for (r, v) in sums.iter_mut().zip(col.iter()) {
            *r += v.abs();
        }
    }
    let (at, worst) = sums
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, f64::INFINITY));
    let c = 1.0 / worst;
    (if c.is_finite() { c } else { 0.0 }, at)
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;

    /// The unrolled 2 × 2 factorisation and solve give, bit for bit, what
    /// the general ones give: on random matrices, on ties between the
    /// pivot candidates (where both take the last), on singular ones and
    /// with NaN and infinite entries.
    #[test]
    fn the_two_by_two_path_is_the_general_one() {
        let mut rng = fastrand::Rng::with_seed(7);
        let mut cases: Vec<[f64; 4]> = (0..2000)
            .map(|_| core::array::from_fn(|_| rng.f64() * 4.0 - 2.0))
            .collect();
        cases.extend([
            [1.0, 2.0, 1.0, 3.0],
            [-1.0, 2.0, 1.0, 3.0],
            [1.0, 2.0, 2.0, 4.0],
            [0.0, 1.0, 0.0, 2.0],
            [0.0, 0.0, 0.0, 0.0],
            [f64::NAN, 1.0, 2.0, 3.0],
            [1.0, 2.0, f64::NAN, 3.0],
            [1.0, f64::INFINITY, 2.0, 3.0],
            [1.0, 2.0, 3.0, f64::NAN],
        ]);
        for (m, threshold) in cases.iter().flat_map(|m| [(*m, 0.0), (*m, 0.5)]) {
            let (mut a, mut b) = (m.to_vec(), m.to_vec());
            let (mut pa, mut pb) = ([0; 2], [0; 2]);
            // The pivot that fails compared by its column (its magnitude
            // may be NaN).
            let (sa, sb) = (
                lu2(&mut a, &mut pa, threshold).map_err(|e| e.0),
                lu_general(&mut b, &mut pb, 2, threshold).map_err(|e| e.0),
            );
            assert_eq!(sa, sb, "{m:?}");
            if sa.is_err() {
                continue;
            }
            assert_eq!(pa, pb, "{m:?}");
            assert!(
                a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
                "{m:?}"
            );
            let rhs = [rng.f64() - 0.5, rng.f64() - 0.5];
            let (mut xa, mut xb) = ([0.0; 2], [0.0; 2]);
            lu_apply2(&a, &pa, &rhs, &mut xa);
            lu_apply_general(&b, &pb, &rhs, &mut xb, 2);
            assert!(
                xa.iter().zip(&xb).all(|(x, y)| x.to_bits() == y.to_bits()),
                "{m:?}"
            );
        }
    }
}
