//! Textbook mechanisms written with `mechanism!`, shared by the runnable
//! examples and the integration tests.
//!
//! Each definition is written as an engineer would write it from the figure:
//! vector loops through the joints, with nothing computed by hand.

use kinematics_core::mechanism;

mechanism! {
    /// Planar four-bar. Ground pivots A = (0, 0) and D = (d, 0); crank AB at
    /// angle φ, coupler BC at θ3, rocker DC at θ4 measured at D; coupler point
    /// P = B + p·(cos(θ3 + β), sin(θ3 + β)).
    pub struct FourBar {
        params {
            /// Crank length AB.
            a,
            /// Coupler length BC.
            b,
            /// Rocker length DC.
            c,
            /// Ground length AD.
            d,
            /// Distance BP to the coupler point.
            p,
            /// Angle of BP from BC (rad).
            beta
        }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            /// Crank pin.
            B = polar(a, phi);
            /// Rocker pin.
            C = vec2(d, 0.0) + polar(c, th4);
            /// Coupler point.
            P = B + polar(p, th3 + beta);
        }
        loops { B + polar(b, th3) == C; }
    }
}

mechanism! {
    /// Offset slider-crank. Crank AB = a at angle φ about A = (0, 0); rod
    /// BC = b at angle θ; the slider pin C moves along the line y = e.
    pub struct SliderCrank {
        params {
            /// Crank length AB.
            a,
            /// Connecting-rod length BC.
            b,
            /// Offset of the slider line from A.
            e
        }
        drivers  { phi }
        unknowns { th, x }
        points {
            /// Crank pin.
            B = polar(a, phi);
            /// Slider pin.
            C = vec2(x, e);
        }
        loops { B + polar(b, th) == C; }
    }
}

mechanism! {
    /// R-TRR mechanism of the chapter's Example 4.1. The driver link 1 turns
    /// about A = (0, 0) at angle φ; slider 2 carries joint B along link 1, at
    /// distance s from A; link 3 (length BC) turns about the fixed joint
    /// C = (AC, 0) at angle φ3.
    pub struct RTrr {
        params {
            /// AC, from the driver pivot to the fixed joint C (m).
            ac,
            /// BC, length of link 3 (m).
            bc
        }
        drivers  { phi }
        unknowns { s, phi3 }
        points {
            /// Joint B (on links 1, 2 and 3).
            B = polar(s, phi);
        }
        loops { B == vec2(ac, 0.0) + polar(bc, phi3); }
    }
}

mechanism! {
    /// R-RTR-RRT mechanism of the chapter's Example 4.2. Origin at the fixed
    /// joint C; crank AB turns about A = (0, AC) at angle φ; link 3 turns
    /// about C at angle φ3 with block 2 sliding on it at B (CB = s); joint D
    /// is on link 3, on the other side of C (CD); link 4 (DE, at angle φ4)
    /// ends at slider E on the x axis.
    pub struct RRtrRrt {
        params {
            /// Crank AB (m).
            ab,
            /// Height AC of the crank pivot above C (m).
            ac,
            /// CD on link 3 (m).
            cd,
            /// Link DE (m).
            de
        }
        drivers  { phi }
        unknowns { s, phi3, x_e, phi4 }
        points {
            /// Crank pin B.
            B = vec2(0.0, ac) + polar(ab, phi);
            /// Joint D on link 3.
            D = -polar(cd, phi3);
            /// Slider pin E.
            E = vec2(x_e, 0.0);
        }
        loops {
            B == polar(s, phi3);
            D + polar(de, phi4) == E;
        }
    }
}

impl FourBar {
    /// The crank-rocker used by the examples and benchmarks: a = 0.04 m,
    /// b = 0.12 m, c = 0.10 m, d = 0.11 m, coupler point at p = 0.06 m,
    /// β = 30° from BC.
    pub const CRANK_ROCKER: FourBar = FourBar {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        p: 0.06,
        beta: std::f64::consts::FRAC_PI_6,
    };

    /// A rough starting guess for [`FourBar::CRANK_ROCKER`] at φ = 0 (open
    /// assembly, rocker pointing up).
    pub const CRANK_ROCKER_GUESS: FourBarCoords = FourBarCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
    };
}

impl RTrr {
    /// The dimensions of the chapter's Example 4.1: AC = 0.100 m, BC = 0.300 m.
    pub const EXAMPLE_4_1: RTrr = RTrr {
        ac: 0.100,
        bc: 0.300,
    };

    /// A rough guess at φ = 45°: B about 0.35 m out along the crank, link 3
    /// at about 60°.
    #[must_use]
    pub fn example_4_1_guess() -> RTrrCoords {
        RTrrCoords {
            phi: 45f64.to_radians(),
            s: 0.35,
            phi3: 60f64.to_radians(),
        }
    }
}

impl RRtrRrt {
    /// The dimensions of the chapter's Example 4.2: AB = 0.100 m,
    /// AC = 0.150 m, CD = 0.075 m, DE = 0.200 m.
    pub const EXAMPLE_4_2: RRtrRrt = RRtrRrt {
        ab: 0.100,
        ac: 0.150,
        cd: 0.075,
        de: 0.200,
    };

    /// A rough guess at φ = 45°, angles to the nearest 10°.
    #[must_use]
    pub fn example_4_2_guess() -> RRtrRrtCoords {
        RRtrRrtCoords {
            phi: 45f64.to_radians(),
            s: 0.2,
            phi3: 70f64.to_radians(),
            x_e: 0.2,
            phi4: 20f64.to_radians(),
        }
    }
}

/// Angular speed in rad/s of a shaft turning at `rpm` revolutions per minute:
/// ω = π n / 30.
#[must_use]
pub fn rpm_to_rad_per_s(rpm: f64) -> f64 {
    std::f64::consts::PI * rpm / 30.0
}
