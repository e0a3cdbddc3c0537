//! Unit tests of the solver.

use crate::options::Options;

use super::failure::Failure;
use super::linalg::{Lu, dense_solve};
use super::newton::{FastNewton, Next, newton, sin_cos_after};
use super::scaling::Scaling;

#[test]
fn lu_solves_a_permuted_system() {
    let a = [[0.0, 2.0, 1.0], [1.0, -1.0, 0.0], [3.0, 0.0, 1.0]];
    let x = [1.0, -2.0, 0.5];
    let mut b = [0.0; 3];
    for i in 0..3 {
        b[i] = (0..3).map(|j| a[i][j] * x[j]).sum();
    }
    let lu = Lu::factor(&a, 1e-12).map_err(|_| ()).expect("regular");
    let got = lu.solve(&b);
    for i in 0..3 {
        assert!((got[i] - x[i]).abs() < 1e-14);
    }
}

#[test]
fn lu_names_the_dependent_column() {
    // Column 1 is twice column 0.
    let a = [[1.0, 2.0, 0.0], [3.0, 6.0, 1.0], [0.5, 1.0, 4.0]];
    match Lu::factor(&a, 1e-12) {
        Err(Failure::Singular { unknown, .. }) => assert_eq!(unknown, 1),
        other => panic!("expected singular, got {other:?}"),
    }
}

#[test]
fn sin_cos_after_matches_the_library_functions() {
    // Angles over several turns and steps up to the series' limit (and
    // beyond it, where it computes afresh), from a fixed-seed generator.
    let mut rng = fastrand::Rng::with_seed(0x2545_f491_4f6c_dd1d);
    let mut uniform = || rng.f64();
    let mut worst = 0.0f64;
    for _ in 0..100_000 {
        let x0 = 40.0 * (uniform() - 0.5);
        let d = 0.07 * (uniform() - 0.5) * if uniform() < 0.5 { 1.0 } else { 1e-6 };
        let (s, c) = x0.sin_cos();
        let x = x0 + d;
        let (s1, c1) = sin_cos_after(s, c, x, x - x0);
        let (se, ce) = x.sin_cos();
        worst = worst.max((s1 - se).abs()).max((c1 - ce).abs());
    }
    assert!(worst < 4e-16, "largest error {worst:e}");
    // No previous value: computed afresh.
    assert_eq!(
        sin_cos_after(0.0, 0.0, 0.7, f64::INFINITY),
        0.7f64.sin_cos()
    );
    assert_eq!(sin_cos_after(0.0, 0.0, 0.7, f64::NAN), 0.7f64.sin_cos());
}

/// Newton on `eval` from `u` with the given scaling and options.
fn solve2(
    u: &mut [f64; 2],
    scaling: &Scaling<2>,
    options: &Options,
    eval: impl Fn(&[f64; 2]) -> ([f64; 2], [[f64; 2]; 2]),
) -> Result<usize, Failure> {
    let (mut phi, mut jac) = ([0.0; 2], [[0.0; 2]; 2]);
    newton(
        u,
        &mut phi,
        &mut jac,
        scaling,
        options,
        |u, p, j| {
            (*p, *j) = eval(u);
        },
        |j, r| dense_solve(j, r, scaling, options.singularity_threshold),
    )
}

#[test]
fn fast_newton_follows_newton_and_hands_over() {
    // x² + y² = 4, y = x, as in the test below.
    let eval = |u: &[f64; 2]| {
        (
            [u[0] * u[0] + u[1] * u[1] - 4.0, u[1] - u[0]],
            [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
        )
    };
    let scaling = Scaling::<2>::UNIT;
    let w = scaling.weights(&Options::DEFAULT);
    // The protocol generated code follows: assess, solve, advance.
    let drive = |mut u: [f64; 2]| {
        let mut fast = FastNewton::new();
        let mut steps = 0;
        loop {
            let (phi, jac) = eval(&u);
            match fast.assess(&phi, &w, &Options::DEFAULT) {
                Next::Continue => {}
                end => return (end, u, steps),
            }
            let Ok(lu) = Lu::factor(&jac, Options::DEFAULT.singularity_threshold) else {
                return (Next::Fallback, u, steps);
            };
            fast.advance(&mut u, &lu.solve(&phi));
            steps += 1;
        }
    };
    // Newton's iterates without its final polishing step.
    let mut reference = [1.0, 0.5];
    let (end, u, steps) = drive([1.0, 0.5]);
    assert_eq!(end, Next::Converged);
    for _ in 0..steps {
        let (phi, jac) = eval(&reference);
        let step = Lu::factor(&jac, 1e-10)
            .map_err(|_| ())
            .expect("regular")
            .solve(&phi);
        reference = [reference[0] - step[0], reference[1] - step[1]];
    }
    assert_eq!(u, reference, "the same iterates, bit for bit");
    let mut full = [1.0, 0.5];
    let it = solve2(&mut full, &scaling, &Options::DEFAULT, eval);
    assert_eq!(it, Ok(steps));
    // From (0.1, −3) the full first step overshoots and the merit grows:
    // the fast path hands over to the damped solver.
    let (end, _, _) = drive([0.1, -3.0]);
    assert_eq!(end, Next::Fallback);
    // A non-finite residual hands over at once, and so does the
    // iteration cap once reached.
    let (phi, jac) = eval(&[1.0, 0.5]);
    let mut fast = FastNewton::new();
    assert_eq!(
        fast.assess(&[f64::NAN, 0.0], &w, &Options::DEFAULT),
        Next::Fallback
    );
    let one = Options {
        max_iterations: 1,
        ..Options::DEFAULT
    };
    let mut fast = FastNewton::new();
    let mut u = [1.0, 0.5];
    assert_eq!(fast.assess(&phi, &w, &one), Next::Continue);
    let step = Lu::factor(&jac, one.singularity_threshold)
        .map_err(|_| ())
        .expect("regular")
        .solve(&phi);
    fast.advance(&mut u, &step);
    let (phi, _) = eval(&u);
    assert_eq!(fast.assess(&phi, &w, &one), Next::Fallback);
}

#[test]
fn newton_stops_at_round_off() {
    // Φ = 10⁶ (x² − 2), with the absolute test max|Φ| ≤ 10⁻¹²: no double
    // makes |Φ| smaller than about 10⁶ · 2√2 · ulp(√2) / 2 ≈ 3·10⁻¹⁰,
    // so the iteration must end by the round-off test, next to √2. The
    // term scale is S = 10⁶ (x² + 2) ≈ 4·10⁶, and 3·10⁻¹⁰ / S is far
    // below ROUND_OFF.
    let absolute = Options {
        convergence: crate::Convergence::Absolute,
        ..Options::DEFAULT
    };
    let scaling = Scaling::new(&[4e6], 1.0, [false]).expect("finite");
    let mut u = [1.3];
    let (mut phi, mut jac) = ([0.0], [[0.0]]);
    let it = newton(
        &mut u,
        &mut phi,
        &mut jac,
        &scaling,
        &absolute,
        |u, phi, jac| {
            phi[0] = 1e6 * (u[0] * u[0] - 2.0);
            jac[0][0] = 2e6 * u[0];
        },
        |j, r| dense_solve(j, r, &scaling, 1e-10),
    );
    assert!(matches!(it, Ok(n) if n < 10), "{it:?}");
    assert!(
        (u[0] - std::f64::consts::SQRT_2).abs() <= 2.3e-16,
        "{}",
        u[0]
    );
}

#[test]
fn a_step_that_cannot_move_u_is_not_a_solution() {
    // cos u = 0.5 from u = 10²⁰: the spacing of doubles there is 16384,
    // every Newton step is "at round-off" relative to u, but the
    // residual is not: this must fail, not return the guess as a root.
    // (It returned Ok before the round-off exit looked at the residual.)
    let scaling = Scaling::new(&[1.5], 1.0, [false]).expect("finite");
    let mut u = [1e20];
    let (mut phi, mut jac) = ([0.0], [[0.0]]);
    let r = newton(
        &mut u,
        &mut phi,
        &mut jac,
        &scaling,
        &Options::DEFAULT,
        |u, phi, jac| {
            phi[0] = u[0].cos() - 0.5;
            jac[0][0] = -u[0].sin();
        },
        |j, r| dense_solve(j, r, &scaling, 1e-10),
    );
    match r {
        Ok(_) => assert!(
            (u[0].cos() - 0.5).abs() <= 1.5e-12,
            "Ok at {u:?}, Φ = {phi:?}"
        ),
        Err(f) => assert!(
            matches!(f, Failure::NotConverged { .. } | Failure::Singular { .. }),
            "{f:?}"
        ),
    }
}

#[test]
fn the_convergence_test_is_relative_to_the_term_scale() {
    // x² + y² = r², y = x for r from 1 nm to 1000 km: the same relative
    // accuracy, and the absolute option still available.
    for r in [1e-9, 1e-3, 1.0, 1e3, 1e6] {
        let scaling = Scaling::new(&[3.0 * r * r, 2.0 * r], r, [true, true]).expect("finite");
        let eval = move |u: &[f64; 2]| {
            (
                [u[0] * u[0] + u[1] * u[1] - r * r, u[1] - u[0]],
                [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
            )
        };
        let mut u = [0.9 * r, 0.5 * r];
        solve2(&mut u, &scaling, &Options::DEFAULT, eval).expect("converges");
        let exact = r * std::f64::consts::FRAC_1_SQRT_2;
        assert!((u[0] / exact - 1.0).abs() < 1e-14, "r = {r}: {u:?}");
    }
    // With the absolute test at 10⁻¹², a nanometre-sized problem is
    // "converged" after one step, still far from the root: the reason
    // the default is relative.
    let r = 1e-9;
    let scaling = Scaling::new(&[3.0 * r * r, 2.0 * r], r, [true, true]).expect("finite");
    let absolute = Options {
        convergence: crate::Convergence::Absolute,
        ..Options::DEFAULT
    };
    let mut u = [0.9 * r, 0.5 * r];
    let it = solve2(&mut u, &scaling, &absolute, |u| {
        (
            [u[0] * u[0] + u[1] * u[1] - r * r, u[1] - u[0]],
            [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
        )
    });
    assert_eq!(it, Ok(1));
    let exact = r * std::f64::consts::FRAC_1_SQRT_2;
    assert!((u[0] / exact - 1.0).abs() > 1e-4, "{u:?}");
}

#[test]
fn conditioning_is_the_distance_to_singularity_of_the_scaled_matrix() {
    // 1×1: |a|, not 1 (a 1×1 matrix used to have conditioning 1 always).
    let lu = Lu::factor(&[[1e-7]], 1e-10)
        .map_err(|_| ())
        .expect("regular");
    assert!((lu.conditioning().0 - 1e-7).abs() < 1e-22);
    // diag(1, ε): the nearest singular matrix is ε away in any norm.
    for eps in [1e-2, 1e-5, 1e-9] {
        let lu = Lu::factor(&[[1.0, 0.0], [0.0, eps]], 1e-12)
            .map_err(|_| ())
            .expect("regular");
        let (c, at) = lu.conditioning();
        assert!((c / eps - 1.0).abs() < 1e-12 && at == 1, "{c} {at}");
        let lu3 = Lu::factor(&[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, eps]], 1e-12)
            .map_err(|_| ())
            .expect("regular");
        let (c, at) = lu3.conditioning();
        assert!((c / eps - 1.0).abs() < 1e-12 && at == 2, "{c} {at}");
    }
    // A + E singular with ‖E‖_∞ = 1 / ‖A⁻¹‖_∞ (Gastinel–Kahan), checked
    // on a full matrix: E = −(y zᵀ)/‖A⁻¹‖ for the maximising row.
    let a = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
    let lu = Lu::factor(&a, 1e-12).map_err(|_| ()).expect("regular");
    let (c, _) = lu.conditioning();
    let mut inv = [[0.0; 3]; 3];
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let x = lu.solve(&e);
        for i in 0..3 {
            inv[i][j] = x[i];
        }
    }
    let norm = inv
        .iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    assert!((c * norm - 1.0).abs() < 1e-14);
    assert!(matches!(lu.check(c * 1.01), Err(Failure::Singular { .. })));
    assert_eq!(lu.check(c * 0.99), Ok(c));
}

#[test]
fn newton_finds_the_root_near_the_guess() {
    // x² + y² = 4, y = x: roots ±(√2, √2).
    let mut u = [1.0, 0.5];
    let it = solve2(&mut u, &Scaling::UNIT, &Options::DEFAULT, |u| {
        (
            [u[0] * u[0] + u[1] * u[1] - 4.0, u[1] - u[0]],
            [[2.0 * u[0], 2.0 * u[1]], [-1.0, 1.0]],
        )
    });
    assert!(it.is_ok());
    assert!((u[0] - 2f64.sqrt()).abs() < 1e-12 && (u[1] - 2f64.sqrt()).abs() < 1e-12);
}

#[test]
fn newton_reports_no_solution() {
    // x² + 1 = 0 has no real root.
    let mut u = [0.3];
    let (mut phi, mut jac) = ([0.0], [[0.0]]);
    let r = newton(
        &mut u,
        &mut phi,
        &mut jac,
        &Scaling::UNIT,
        &Options::DEFAULT,
        |u, phi, jac| {
            phi[0] = u[0] * u[0] + 1.0;
            jac[0][0] = 2.0 * u[0];
        },
        |j, r| dense_solve(j, r, &Scaling::UNIT, 1e-10),
    );
    assert!(matches!(
        r,
        Err(Failure::NotConverged { .. } | Failure::Singular { .. })
    ));
}
