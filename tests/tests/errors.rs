//! Every failure is a typed error that names what is wrong; no panic, no NaN.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic)]

use kinematics_core::{mechanism, Error, Input, Options};
use kinematics_examples::{FourBar, FourBarCoords, SliderCrank, SliderCrankCoords};
use kinematics_tests::{DistanceFourBar, DistanceFourBarCoords};

mechanism! {
    /// A model whose equation is undefined for negative `r`.
    pub struct Root {
        params {
            /// Must be non-negative for `sqrt`.
            r
        }
        drivers  {
            /// Input.
            t
        }
        unknowns {
            /// Output.
            y
        }
        constraints { y * y == sqrt(r) + t; }
    }
}

mechanism! {
    /// A slider `y = t` carrying a point at height √y: its position is finite
    /// at y = 0, but its velocity y′/(2√y) is not.
    pub struct RootPoint {
        drivers  {
            /// Input.
            t
        }
        unknowns {
            /// Slider position.
            y
        }
        constraints { y == t; }
        points {
            /// Point whose velocity is infinite at y = 0.
            Q = vec2(0.0, sqrt(y));
        }
    }
}

fn four_bar() -> FourBar {
    FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: 0.5,
    }
}

#[test]
fn links_too_short_to_close_the_loop() {
    // b + c = 0.04 < d − a = 0.16: the loop cannot close at any crank angle.
    let m = FourBar {
        a: 0.04,
        b: 0.02,
        c: 0.02,
        d: 0.2,
        p: 0.0,
        beta: 0.0,
    };
    let err = m
        .assemble(&FourBarCoords {
            phi: 0.0,
            th3: 0.5,
            th4: 2.0,
        })
        .expect_err("cannot assemble");
    // The four-bar's loop is one RRR dyad, solved in closed form: its
    // discriminant is negative, an exact statement that it cannot close.
    match &err {
        Error::CannotAssemble {
            unknowns,
            discriminant,
            drivers,
        } => {
            assert_eq!(*unknowns, "th3, th4");
            assert!(*discriminant < 0.0);
            assert_eq!(drivers.as_slice(), &[("phi", 0.0)]);
        }
        other => panic!("unexpected {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.contains("cannot be assembled at phi = 0.000000") && text.contains("th3, th4"),
        "{text}"
    );
    // Solved by Newton–Raphson, the same loop does not converge.
    let newton = DistanceFourBar {
        a: 0.04,
        b: 0.02,
        c: 0.02,
        d: 0.2,
    };
    match newton.assemble(&DistanceFourBarCoords { phi: 0.0, th4: 2.0 }) {
        Err(Error::NotConverged {
            residual,
            equation,
            configuration,
            ..
        }) => {
            assert!(residual > 1e-3);
            assert!(equation.starts_with("sqrt(norm("), "{equation}");
            assert_eq!(configuration.len(), 2);
        }
        Err(Error::Singular { .. }) => {}
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn dead_centre_is_reported_as_singular() {
    // a = 0.2 > b = 0.1: at φ = −30° the rod stands vertical (θ = 90°) and
    // the slider cannot be driven by the crank: Φ_u is singular.
    let m = SliderCrank {
        a: 0.2,
        b: 0.1,
        e: 0.0,
    };
    let phi = -30f64.to_radians();
    let pose = SliderCrankCoords {
        phi,
        th: 90f64.to_radians(),
        x: 0.2 * phi.cos(),
    };
    assert!(m.residual(&pose).iter().all(|r| r.abs() < 1e-15));
    let err = m.analyze(&pose, 1.0, 0.0).expect_err("singular");
    match &err {
        Error::Singular {
            unknown,
            configuration,
            conditioning,
        } => {
            assert!(["th", "x"].contains(unknown), "{unknown}");
            assert!(*conditioning < 1e-10);
            assert_eq!(configuration[1].0, "th");
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("dead-centre"), "{err}");
}

#[test]
fn toggle_of_a_six_bars_second_loop_names_its_unknown() {
    use kinematics_examples::{Watt, WattCoords};
    // Assemble the driving four-bar, then place the output pivot G so that
    // EF and GF are collinear and point the same way (θ5 = θ6): the second
    // loop's own 2×2 block of Φ_u, with determinant f g sin(θ5 − θ6), is
    // singular while the first loop's is regular.
    let mut w = Watt {
        gamma: 0.3,
        ..Watt::EXAMPLE
    };
    let start = WattCoords {
        phi: 0.4,
        ..Watt::EXAMPLE_GUESS
    };
    let first = FourBar {
        a: w.a,
        b: w.b,
        c: w.c,
        d: w.d,
        p: 0.0,
        beta: 0.0,
    }
    .assemble(&FourBarCoords {
        phi: start.phi,
        th3: start.th3,
        th4: start.th4,
    })
    .expect("the driving four-bar assembles");
    let angle = 0.3f64;
    let (ex, ey) = (
        w.d + w.e * (first.th4 + w.gamma).cos(),
        w.e * (first.th4 + w.gamma).sin(),
    );
    w.gx = ex + (w.f - w.g) * angle.cos();
    w.gy = ey + (w.f - w.g) * angle.sin();
    let pose = WattCoords {
        phi: first.phi,
        th3: first.th3,
        th4: first.th4,
        th5: angle,
        th6: angle,
    };
    assert!(w.residual(&pose).iter().all(|r| r.abs() < 1e-12));
    for err in [
        w.analyze(&pose, 1.0, 0.0).expect_err("singular"),
        w.step(&pose, 1.0, 0.0).expect_err("singular"),
    ] {
        match &err {
            Error::Singular {
                unknown,
                conditioning,
                ..
            } => {
                assert!(["th5", "th6"].contains(unknown), "{unknown}");
                assert!(*conditioning < 1e-10, "{conditioning}");
            }
            other => panic!("unexpected {other:?}"),
        }
    }
    // The guess does not move the pose: the second loop, solved in closed
    // form, is at its toggle whatever the guess.
    let off = WattCoords {
        th5: angle + 0.01,
        ..pose
    };
    assert!(matches!(w.assemble(&off), Err(Error::Singular { .. })));
    // A little away from the toggle (on the side where the loop closes)
    // both loops are regular, and the conditioning is small but positive.
    let assembled = [0.01, -0.01]
        .iter()
        .find_map(|dphi| {
            w.assemble(&WattCoords {
                phi: pose.phi + dphi,
                ..off
            })
            .ok()
        })
        .expect("assembles on one side of the toggle");
    let motion = w.analyze(&assembled, 1.0, 0.0).expect("regular");
    assert!(
        motion.conditioning > 0.0 && motion.conditioning < 0.2,
        "{}",
        motion.conditioning
    );
}

#[test]
fn non_finite_inputs_are_named() {
    let mut m = four_bar();
    m.c = f64::NAN;
    let start = FourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
    };
    let err = m.assemble(&start).expect_err("NaN parameter");
    assert!(
        matches!(err, Error::NonFinite { input: Input::Parameter, name: "c", value } if value.is_nan()),
        "{err:?}"
    );
    assert!(err.to_string().contains("parameter `c` is NaN"), "{err}");
    let m = four_bar();
    let bad = FourBarCoords {
        th4: f64::INFINITY,
        ..start
    };
    assert!(matches!(
        m.assemble(&bad),
        Err(Error::NonFinite {
            input: Input::Guess,
            name: "th4",
            ..
        })
    ));
    let pose = m.assemble(&start).expect("assembles");
    let err = m.analyze(&pose, f64::INFINITY, 0.0).expect_err("bad rate");
    assert!(matches!(
        err,
        Error::NonFinite {
            input: Input::DriverRate,
            name: "phi",
            ..
        }
    ));
    assert!(
        err.to_string().contains("rate of driver `phi` is inf"),
        "{err}"
    );
    let err = m
        .analyze(&pose, 1.0, f64::NAN)
        .expect_err("bad acceleration");
    assert!(matches!(
        err,
        Error::NonFinite {
            input: Input::DriverAcceleration,
            ..
        }
    ));
}

#[test]
fn undefined_model_expression_is_reported_not_returned() {
    let m = Root { r: -1.0 };
    let err = m
        .assemble(&RootCoords { t: 1.0, y: 1.0 })
        .expect_err("sqrt(-1)");
    match &err {
        Error::NonFinite {
            input: Input::Computed,
            name,
            value,
        } => {
            assert!(name.contains("sqrt"), "{name}");
            assert!(value.is_nan());
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("undefined"), "{err}");
    // And with valid data it works: y² = 1 + 2.
    let ok = Root { r: 1.0 }
        .assemble(&RootCoords { t: 2.0, y: 1.5 })
        .expect("assembles");
    assert!((ok.y - 3f64.sqrt()).abs() < 1e-12);
}

#[test]
fn invalid_options_are_rejected() {
    let m = four_bar();
    let start = FourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
    };
    for (options, name) in [
        (
            Options {
                tolerance: -1.0,
                ..Options::DEFAULT
            },
            "tolerance",
        ),
        (
            Options {
                tolerance: f64::NAN,
                ..Options::DEFAULT
            },
            "tolerance",
        ),
        (
            Options {
                max_iterations: 0,
                ..Options::DEFAULT
            },
            "max_iterations",
        ),
        (
            Options {
                singularity_threshold: 2.0,
                ..Options::DEFAULT
            },
            "singularity_threshold",
        ),
    ] {
        match m.assemble_with(&start, &options) {
            Err(Error::InvalidOption { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: unexpected {other:?}"),
        }
    }
}

#[test]
fn too_few_iterations_reports_the_residual() {
    let m = DistanceFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    assert_eq!(DistanceFourBar::BLOCKS[0].method, "Newton–Raphson");
    let options = Options {
        max_iterations: 1,
        ..Options::DEFAULT
    };
    match m.assemble_with(&DistanceFourBarCoords { phi: 0.0, th4: 2.5 }, &options) {
        Err(Error::NotConverged {
            iterations: 1,
            residual,
            ..
        }) => assert!(residual > 1e-12),
        other => panic!("unexpected {other:?}"),
    }
}

mechanism! {
    /// A slider-crank whose links are declared lengths.
    pub struct Declared {
        params {
            /// Crank.
            a: length,
            /// Rod.
            b: length,
            /// Offset (may be negative).
            e
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns {
            /// Rod angle.
            th,
            /// Slider.
            x
        }
        loops { polar(a, phi) + polar(b, th) == vec2(x, e); }
    }
}

#[test]
fn declared_lengths_must_be_positive() {
    let start = DeclaredCoords {
        phi: 0.3,
        th: 0.0,
        x: 0.3,
    };
    assert!(Declared {
        a: 0.1,
        b: 0.25,
        e: -0.02
    }
    .assemble(&start)
    .is_ok());
    for (a, b) in [(0.0, 0.25), (0.1, -0.25)] {
        let err = Declared { a, b, e: 0.0 }
            .assemble(&start)
            .expect_err("not a length");
        assert!(matches!(err, Error::InvalidParameter { .. }), "{err:?}");
        assert!(err.to_string().contains("must be positive"), "{err}");
    }
}

#[test]
fn the_distance_of_a_norm_constraint_must_be_positive() {
    use kinematics_examples::{Rssr, RssrCoords};
    // `norm(B - A) == b` is solved as (B − A)·(B − A) = b², which has the
    // same solutions only for b > 0: with b < 0 the distance cannot be
    // met, and the squared form must not pretend it is.
    let start = RssrCoords { phi: 0.0, psi: 1.2 };
    let good = Rssr {
        a: 0.102,
        b: 0.381,
        c: 0.254,
        d: 0.314,
    };
    let pose = good.assemble(&start).expect("assembles");
    for b in [-0.381, 0.0] {
        let bad = Rssr { b, ..good };
        let err = bad.assemble(&start).expect_err("no such distance");
        assert!(
            matches!(err, Error::InvalidParameter { name, .. } if name == "b"),
            "{err:?}"
        );
        assert!(err.to_string().contains("distance"), "{err}");
        assert!(bad.step(&pose, 1.0, 0.0).is_err());
        assert!(bad.stepper(&Options::DEFAULT).is_err());
    }
}

#[test]
fn the_requested_assembly_branch_is_enforced() {
    use kinematics_core::Branch;
    let m = four_bar();
    // The open assembly (θ3 < θ4, det Φ_u = b c sin(θ3 − θ4) < 0) and the
    // crossed one.
    let open = FourBarCoords {
        phi: 0.5,
        th3: 0.6,
        th4: 1.5,
    };
    let crossed = FourBarCoords {
        phi: 0.5,
        th3: -1.2,
        th4: -1.9,
    };
    let wants = |branch| Options {
        branch,
        ..Options::DEFAULT
    };
    let p = m
        .assemble_with(&open, &wants(Branch::Negative))
        .expect("open branch");
    assert!((p.th3 - p.th4).sin() < 0.0);
    let q = m
        .assemble_with(&crossed, &wants(Branch::Positive))
        .expect("crossed branch");
    assert!((q.th3 - q.th4).sin() > 0.0);
    // Solved in closed form, asking for the other branch from a guess on
    // this one chooses the other assembly mode.
    let other = m
        .assemble_with(&open, &wants(Branch::Positive))
        .expect("the crossed assembly");
    assert!((other.th3 - other.th4).sin() > 0.0);
    // The same pose as from the crossed guess, modulo 2π.
    let same = |x: f64, y: f64| (x - y).sin().abs() < 1e-12 && (x - y).cos() > 0.0;
    assert!(same(other.th3, q.th3) && same(other.th4, q.th4));
    let stepped = m
        .step_with(&open, 1.0, 0.0, &wants(Branch::Positive))
        .expect("the crossed assembly");
    assert!(same(stepped.q.th4, q.th4));
    // Solved by Newton–Raphson, it is a check: an error, not a silent
    // answer on the wrong branch.
    let n = DistanceFourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
    };
    let guess = DistanceFourBarCoords { phi: 0.5, th4: 1.5 };
    let found = n.assemble(&guess).expect("assembles");
    let sign = n.analyze(&found, 1.0, 0.0).expect("regular").det_sign;
    let other_branch = if sign > 0.0 {
        Branch::Negative
    } else {
        Branch::Positive
    };
    let err = n
        .assemble_with(&guess, &wants(other_branch))
        .expect_err("wrong branch");
    assert!(matches!(err, Error::WrongBranch { .. }), "{err:?}");
    assert!(err.to_string().contains("other branch"), "{err}");
}

#[test]
fn every_solution_reports_its_conditioning() {
    // A slider-crank with a = 2b assembles only for |sin φ| ≤ ½, and at
    // φ = −30° its rod stands normal to the slider line (a dead point): the
    // conditioning falls toward 0 as the crank approaches it.
    let m = SliderCrank {
        a: 0.2,
        b: 0.1,
        e: 0.0,
    };
    let at = |deg: f64| {
        let phi = f64::to_radians(deg);
        let th = (-(0.2 * phi.sin()) / 0.1).asin();
        let pose = SliderCrankCoords {
            phi,
            th,
            x: 0.2 * phi.cos() + 0.1 * th.cos(),
        };
        m.analyze(&pose, 1.0, 0.0).map(|s| s.conditioning)
    };
    // Clear of zero away from it...
    assert!(at(-5.0).expect("regular") > 0.05);
    // ...and falling toward 0 on the last approach.
    let mut last = f64::INFINITY;
    for deg in [-29.9, -29.99, -29.999, -29.9999] {
        let c = at(deg).expect("regular");
        assert!(c > 0.0 && c < last, "{deg}: {c}");
        last = c;
    }
    assert!(last < 1e-2);
    // A user threshold refuses configurations worse than it.
    let phi = f64::to_radians(-29.9);
    let th = (-(0.2 * phi.sin()) / 0.1).asin();
    let pose = SliderCrankCoords {
        phi,
        th,
        x: 0.2 * phi.cos() + 0.1 * th.cos(),
    };
    let strict = Options {
        singularity_threshold: 0.1,
        ..Options::DEFAULT
    };
    assert!(matches!(
        m.analyze_with(&pose, 1.0, 0.0, &strict),
        Err(Error::Singular { .. })
    ));
}

#[test]
fn non_finite_point_output_names_the_point() {
    let m = RootPoint {};
    let pose = m
        .assemble(&RootPointCoords { t: 0.0, y: 0.5 })
        .expect("assembles at y = 0");
    assert!(pose.y.abs() < 1e-12);
    let err = m.analyze(&pose, 1.0, 0.0).expect_err("v_Q = 1/(2·0)");
    assert!(
        matches!(
            err,
            Error::NonFinite {
                input: Input::Computed,
                name: "Q",
                ..
            }
        ),
        "{err:?}"
    );
    // Away from y = 0 the same model analyzes: v_Q = 1/(2√y).
    let pose = m
        .assemble(&RootPointCoords { t: 0.25, y: 0.3 })
        .expect("assembles");
    let motion = m.analyze(&pose, 1.0, 0.0).expect("finite");
    assert!((motion.point_q().velocity.y - 1.0).abs() < 1e-12);
}

#[test]
fn an_overflow_is_reported_as_an_overflow() {
    // A rate of 1e300 squares to infinity in the convective terms (and ∞ − ∞
    // to NaN): the message said only "square root of a negative number,
    // division by zero…"; it must name the overflow.
    let m = four_bar();
    let pose = m
        .assemble(&FourBarCoords {
            phi: 0.3,
            th3: 1.0,
            th4: 1.6,
        })
        .expect("assembles");
    let e = m.analyze(&pose, 1e300, 0.0).expect_err("overflows");
    assert!(
        matches!(e, Error::NonFinite { input: Input::Computed, value, .. } if !value.is_finite()),
        "{e:?}"
    );
    let text = e.to_string();
    assert!(text.contains("overflowed"), "{text}");
    // A parameter so large that the size of the loop's terms overflows.
    let huge = FourBar {
        a: 1e308,
        b: 1e308,
        ..four_bar()
    };
    let e = huge
        .assemble(&FourBarCoords {
            phi: 0.3,
            th3: 1.0,
            th4: 1.6,
        })
        .expect_err("overflows");
    assert!(e.to_string().contains("overflowed"), "{e}");
}

#[test]
fn the_branch_is_the_sign_of_the_whole_determinant_when_blocks_are_permuted() {
    use kinematics_core::{Branch, MotionState};
    // Slider-crank: Φ_u = [[−b sin θ, −1], [b cos θ, 0]], det Φ_u = b cos θ.
    // Its block form solves the y equation for θ first, then x: the rows
    // are permuted, and the product of the blocks' determinants alone has
    // the opposite sign.
    let m = SliderCrank {
        a: 0.1,
        b: 0.25,
        e: 0.02,
    };
    let start = SliderCrankCoords {
        phi: 0.7,
        th: -0.2,
        x: 0.3,
    };
    let wants = |branch| Options {
        branch,
        ..Options::DEFAULT
    };
    let q = m
        .assemble_with(&start, &wants(Branch::Positive))
        .expect("rod pointing forward: cos θ > 0");
    assert!(q.th.cos() > 0.0);
    let s = m.analyze(&q, 1.0, 0.0).expect("analysis");
    assert_eq!(s.det_sign(), 1.0);
    // The other branch, chosen in closed form: the rod pointing back.
    let back = m
        .assemble_with(&start, &wants(Branch::Negative))
        .expect("rod pointing back: cos θ < 0");
    assert!(back.th.cos() < 0.0);
    assert_eq!(
        m.analyze(&back, 1.0, 0.0).expect("analysis").det_sign(),
        -1.0
    );
}
