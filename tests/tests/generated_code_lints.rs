//! The expansion of `mechanism!` compiles cleanly under `deny(warnings)` and
//! clippy's pedantic lints (this file is built by `cargo clippy` in CI with
//! `-D warnings`), and uses only absolute paths: the prelude names are
//! shadowed here to prove it.
#![deny(warnings, missing_docs)]
#![warn(clippy::pedantic)]

#[allow(dead_code, non_camel_case_types)]
mod shadowing {
    // If generated code used `Result`, `Ok`, `Option`, `f64` methods through
    // the prelude or a bare `Vec`, these would capture the names.
    pub struct Result;
    pub struct Ok;
    pub struct Err;
    pub struct Option;
    pub struct Some;
    pub struct None;
    pub struct Vec;
}
#[allow(unused_imports)]
use shadowing::*;

kinematics_core::mechanism! {
    /// A slider-crank with an offset.
    pub struct Lints {
        params {
            /// Crank.
            a,
            /// Rod.
            b,
            /// Offset.
            e
        }
        drivers  { phi }
        unknowns { th, x }
        points {
            /// Crank pin.
            B = polar(a, phi);
        }
        loops { B + polar(b, th) == vec2(x, e); }
        constraints { }
    }
}

kinematics_core::mechanism! {
    /// A mechanism with no points and a scalar constraint.
    pub struct Scalar {
        params {
            /// Radius.
            r
        }
        drivers  { t }
        unknowns { y }
        constraints { powi(y, 2) + powi(t, 2) == powi(r, 2); }
    }
}

kinematics_core::mechanism! {
    /// A spatial linkage with frames, screws and 3-D points.
    pub struct Spatial {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Lead of the screw.
            k
        }
        drivers  {
            /// Crank angle.
            phi
        }
        unknowns {
            /// Slider position.
            y
        }
        frames {
            /// A screw-driven body.
            nut = t6(0.0, 0.0, 0.0, phi, k) * rot(vec3(1.0, 1.0, 0.0), pi / 4.0);
        }
        points {
            /// Crank pin.
            A = vec3(a * sin(phi), 0.0, a * cos(phi));
            /// Slider.
            B = vec3(0.0, y, 0.0);
            /// A point of the nut.
            N = nut * vec3(1.0, 0.0, 0.0);
        }
        constraints { norm(B - A) == b; }
    }
}

kinematics_core::mechanism! {
    /// An open chain: no unknowns, so no Newton iteration and no solve.
    pub struct Chain {
        params {
            /// Upper arm.
            l1,
            /// Forearm.
            l2
        }
        drivers {
            /// Shoulder.
            q1,
            /// Elbow.
            q2
        }
        unknowns { }
        frames {
            /// The hand.
            hand = t3(0.0, 0.0, 0.0, q1) * t2(l1, 0.0, 0.0, q2);
        }
        points {
            /// Wrist.
            W = hand * vec3(l2, 0.0, 0.0);
        }
    }
}

kinematics_core::mechanism! {
    /// Two loops solved one after the other (a block-triangular Jacobian).
    pub struct SixBar {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Rocker.
            c,
            /// Ground.
            d,
            /// Second coupler.
            f,
            /// Output link.
            g,
            /// Output pivot, x.
            gx
        }
        drivers {
            /// Crank angle.
            phi
        }
        unknowns { th3, th4, th5, th6 }
        points {
            /// Joint between the loops.
            C = vec2(d, 0.0) + polar(c, th4);
        }
        loops {
            polar(a, phi) + polar(b, th3) == C;
            C + polar(f, th5) == vec2(gx, 0.0) + polar(g, th6);
        }
    }
}

kinematics_core::mechanism! {
    /// A closed-form block, then one solved by Newton–Raphson.
    pub struct Slot {
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

#[test]
fn expansion_is_usable() {
    let slot = Slot {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        e: 0.05,
        f: 0.16,
        h: 0.2,
        k: 2.0,
    };
    let guess = SlotCoords {
        phi: 0.0,
        th3: 0.0,
        th4: 0.0,
        th5: 0.6,
        y: 0.13,
    };
    assert!(slot.assemble_all(&guess).all(|(_, r)| r.is_ok()));
    let chain = Chain { l1: 0.4, l2: 0.3 };
    let wrist = chain
        .step(&ChainCoords { q1: 0.0, q2: 0.0 }, [1.0, 0.0], [0.0, 0.0])
        .map(|m| m.point_w().velocity[1]);
    assert!(matches!(wrist, core::result::Result::Ok(v) if (v - 0.7).abs() < 1e-12));
    let six = SixBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        f: 0.10,
        g: 0.08,
        gx: 0.20,
    };
    let start = SixBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
        th5: 0.3,
        th6: 1.9,
    };
    assert!(six.step(&start, 10.0, 0.0).is_ok());
    let m = Lints {
        a: 0.1,
        b: 0.3,
        e: 0.0,
    };
    let pose = m.assemble(&LintsCoords {
        phi: 0.5,
        th: -0.1,
        x: 0.35,
    });
    assert!(pose.is_ok());
    let c = Scalar { r: 1.0 };
    let p = c.assemble(&ScalarCoords { t: 0.6, y: 0.7 }).map(|p| p.y);
    assert!(matches!(p, core::result::Result::Ok(y) if (y - 0.8).abs() < 1e-12));
    let s = Spatial {
        a: 0.05,
        b: 0.2,
        k: 0.01,
    };
    let pose = s.assemble(&SpatialCoords { phi: 0.3, y: 0.19 });
    assert!(pose.is_ok());
}

kinematics_core::mechanism! {
    /// A slider-crank with masses and every kind of load.
    pub struct Loaded {
        params {
            /// Crank.
            a,
            /// Rod.
            b,
            /// Mass.
            m,
            /// Damping.
            c
        }
        drivers  { phi }
        unknowns { th, x }
        points {
            /// Crank pin.
            B = polar(a, phi);
            /// Piston.
            C = vec2(x, 0.0);
            /// A fixed point.
            D = vec2(0.0, -a);
        }
        loops { B + polar(b, th) == C; }
        bodies {
            /// The rod, with its centre of mass at the crank pin.
            rod(mass = m, center = B, angle = th, inertia = m * b * b / 12.0);
            piston(mass = 2.0 * m, center = C);
        }
        loads {
            gravity(vec2(0.0, -9.81));
            force(C, vec2(-c * rate(x) - 1.0, 0.5 * sin(phi)), on = piston);
            force(x, -c * rate(x));
            torque(rod, -c * rate(th));
            spring(D, B, stiffness = 100.0 * m, free_length = a, damping = c, between = (ground, rod));
        }
        joints {
            /// The crank pin.
            pin(revolute, B, between = (ground, rod), driver = phi);
            /// The cylinder, its axis from the parameters.
            cylinder(prismatic, C, between = (ground, piston), axis = vec2(a / b, 0.0), coordinate = x);
        }
        sensitivities { a, m, c }
    }
}
