//! Tests of the closed forms: the inverse length, double roots, the mode
//! nearest a guess and the combinations of modes tried.

/// The Newton step from 1/q² against 1/√m itself, near m = q⁴ (the
/// fast path) and away from it (the square root), over twelve decades
/// of q²; within 2 ulp, the two roundings of 1/√m.
#[test]
fn the_inverse_length_is_1_over_the_square_root_of_m() {
    for q2 in [1e-6, 0.0625, 1.0, 7.3, 1e6] {
        for rel in [0.0, 1e-15, -3e-13, 1e-10, -9.9e-9, 9.9e-9, 2e-8, -0.5, 3.0] {
            let m = q2 * q2 * (1.0 + rel);
            let r = super::unit_scale(m, q2);
            let exact = 1.0 / m.sqrt();
            assert!(
                r.is_ok_and(|r| (r - exact).abs() <= 2.0 * f64::EPSILON * exact),
                "q² = {q2}, m/q⁴ − 1 = {rel}: {r:?} against {exact}"
            );
        }
    }
    assert!(super::unit_scale(0.0, 1.0).is_err());
    assert!(super::unit_scale(f64::NAN, 1.0).is_err());
}

/// a cos θ + b sin θ + c = 0 with c = −R (1 − 2⁻⁵³): the discriminant
/// R² − c² ≈ 2⁻⁵² R², positive but within its rounding error, is a
/// double root (the limit position θ = 0 to round-off): both modes give
/// the same solution, sin θ = 0 exactly. A root split by more than the
/// rounding (c = −R (1 − 10⁻⁹)) keeps its two solutions.
#[test]
fn a_discriminant_within_rounding_is_a_double_root() {
    for r in [1.0, 3.7e-3, 2.5e4] {
        let c = -r * (1.0 - f64::EPSILON / 2.0);
        let solve = |c: f64, mut mode: f64| super::angle(r, 0.0, c, &mut mode, || [1.0, 0.0]);
        let (plus, minus) = (solve(c, 1.0), solve(c, -1.0));
        assert_eq!(plus, minus, "R = {r}");
        assert!(
            plus.is_ok_and(|[cos, sin]| sin == 0.0 && (cos - 1.0).abs() <= f64::EPSILON),
            "{plus:?}"
        );
        let c = -r * (1.0 - 1e-9);
        let (Ok([_, s1]), Ok([_, s2])) = (solve(c, 1.0), solve(c, -1.0)) else {
            panic!("R = {r}: no solution");
        };
        // sin θ = ±√(1 − (1 − 10⁻⁹)²) ≈ ±√(2·10⁻⁹), to the relative
        // error the cancellation in R² − c² leaves (about 10⁻⁷).
        let split = 2e-9f64.sqrt();
        assert!((s1 - split).abs() < 1e-6 * split && (s2 + split).abs() < 1e-6 * split);
    }
}

/// The mode `circle_circle` picks for a guess is the one whose
/// solution (both computed here, in each mode) is nearer the guess in
/// (1 − cos Δθ₀) + (1 − cos Δθ₁), over random dyads (P and Q rotations
/// scaled, some reflected) and random guesses; near ties (distances
/// within 1e-9) either is right.
#[test]
fn the_mode_chosen_is_the_solution_nearer_the_guess() {
    let mut rng = fastrand::Rng::with_seed(7);
    let similarity = |rng: &mut fastrand::Rng| {
        let (l, t) = (0.1 + 3.0 * rng.f64(), 7.0 * rng.f64());
        let (c, s) = (l * t.cos(), l * t.sin());
        if rng.bool() {
            [[c, -s], [s, c]]
        } else {
            [[c, s], [s, -c]]
        }
    };
    let mut checked = 0;
    for _ in 0..20_000 {
        let (p, q) = (similarity(&mut rng), similarity(&mut rng));
        let k = [4.0 * rng.f64() - 2.0, 4.0 * rng.f64() - 2.0];
        let (t0, t1) = (7.0 * rng.f64(), 7.0 * rng.f64());
        let g = [t0.cos(), t0.sin(), t1.cos(), t1.sin()];
        let solve = |mut m: f64| super::circle_circle(k, p, q, &mut m, || g);
        let (Ok(plus), Ok(minus)) = (solve(1.0), solve(-1.0)) else {
            continue;
        };
        let distance =
            |x: &[f64; 4]| 2.0 - (x[0] * g[0] + x[1] * g[1]) - (x[2] * g[2] + x[3] * g[3]);
        let (dp, dm) = (distance(&plus), distance(&minus));
        if (dp - dm).abs() < 1e-9 {
            continue;
        }
        let mut mode = f64::NAN;
        let x = super::circle_circle(k, p, q, &mut mode, || g);
        let nearer = if dm < dp { (-1.0, minus) } else { (1.0, plus) };
        assert_eq!(
            (mode, x),
            (nearer.0, Ok(nearer.1)),
            "k = {k:?}, P = {p:?}, Q = {q:?}, g = {g:?}"
        );
        checked += 1;
    }
    assert!(checked > 5_000, "{checked} dyads assembled");
}

/// For a few blocks, every other combination once; for many, the base
/// and its single flips only (not 2^N), with no shift overflow.
#[test]
fn other_modes_are_every_other_combination_or_single_flips() {
    use alloc::vec::Vec;
    let tried = [1.0, -1.0, 1.0];
    let others: Vec<[f64; 3]> = super::other_modes(tried).collect();
    assert_eq!(others.len(), 7);
    for i in 0..8usize {
        let m: [f64; 3] = core::array::from_fn(|j| if i >> j & 1 == 1 { -1.0 } else { 1.0 });
        let n = others.iter().filter(|o| **o == m).count();
        assert_eq!(n, usize::from(m != tried), "{m:?}");
    }
    // NaN modes (not yet chosen): the base (all +1) is tried too.
    assert_eq!(super::other_modes([f64::NAN; 2]).count(), 4);
    let many = [1.0; 100];
    let others: Vec<[f64; 100]> = super::other_modes(many).collect();
    assert_eq!(others.len(), 100);
    for (j, m) in others.iter().enumerate() {
        assert!(
            m.iter()
                .enumerate()
                .all(|(k, &x)| x == if k == j { -1.0 } else { 1.0 })
        );
    }
}
