//! Textbook mechanisms written with `mechanism!`, shared by the runnable
//! examples and the integration tests.
//!
//! Each definition is written as an engineer would write it from the figure:
//! vector loops through the joints, with nothing computed by hand.

use kinematics_core::mechanism;

#[cfg(feature = "synthesis")]
pub mod benchmarks;
mod definitions;
pub use definitions::{definition, definitions, mechanism_bodies};

/// Where the examples write their files: `target/kinematics/` of the
/// workspace (or of `CARGO_TARGET_DIR`), created if need be.
///
/// # Errors
/// When the folder cannot be created.
pub fn output_dir() -> std::io::Result<std::path::PathBuf> {
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(
        || std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")),
        std::path::PathBuf::from,
    );
    let dir = target.join("kinematics");
    std::fs::create_dir_all(&dir)?;
    dir.canonicalize()
}

mechanism! {
    /// Planar four-bar. Ground pivots A = (0, 0) and D = (d, 0); crank AB at
    /// angle φ, coupler BC at θ3, rocker DC at θ4 measured at D; coupler point
    /// P = B + p·(cos(θ3 + β), sin(θ3 + β)).
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
            /// Crank pivot (fixed).
            A = vec2(0.0, 0.0);
            /// Crank pin.
            B = polar(a, phi);
            /// Rocker pivot (fixed).
            D = vec2(d, 0.0);
            /// Rocker pin.
            C = D + polar(c, th4);
            /// Coupler point.
            P = B + polar(p, th3 + beta);
        }
        loops { B + polar(b, th3) == C; }
        // Exact derivatives of the motion with respect to every dimension.
        sensitivities { a, b, c, d, p, beta }
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

mechanism! {
    /// RSSR spatial four-bar (the notes' Example 7.3). The input crank
    /// A₀A = a turns about the y axis at A₀ = (0, 0, 0), so A moves in the
    /// x–z plane; the output B₀B = c turns about an axis parallel to z
    /// through B₀ = (−d, 0, 0); the coupler AB = b joins two spherical joints.
    pub struct Rssr {
        params {
            /// Input crank A₀A.
            a,
            /// Coupler AB.
            b,
            /// Output link B₀B.
            c,
            /// Distance A₀B₀.
            d
        }
        drivers  {
            /// Input angle.
            phi
        }
        unknowns {
            /// Output angle.
            psi
        }
        points {
            /// Crank pin (spherical joint).
            A = vec3(-a * cos(phi), 0.0, a * sin(phi));
            /// Output pin (spherical joint).
            B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
        }
        constraints { norm(B - A) == b; }
        // F = 6(4 − 4 − 1) + 8 = 2, one being the coupler's spin about AB.
        joints { links: 4, R: 2, S: 2, passive: 1 }
    }
}

mechanism! {
    /// Spatial crank and slider (the notes' Example 7.2). The crank A₀A = a
    /// turns in the x–z plane about the y axis; the link AB = b drives the
    /// slider B along a rod parallel to y, at x = 0 and height z = h.
    pub struct SpatialSlider {
        params {
            /// Crank A₀A.
            a,
            /// Link AB.
            b,
            /// Height of the rod above the crank's plane.
            h
        }
        drivers  {
            /// Crank angle, from the z axis toward x.
            phi
        }
        unknowns {
            /// Slider position along the rod.
            y
        }
        points {
            /// Crank pin.
            A = vec3(a * sin(phi), 0.0, a * cos(phi));
            /// Slider.
            B = vec3(0.0, y, h);
        }
        constraints { norm(B - A) == b; }
    }
}

mechanism! {
    /// Satellite dish (the notes' Example 7.4): the mount turns about the
    /// fixed z axis by φ, the dish tilts about the mount's x axis by θ; the
    /// signal horn A is at distance r along the dish's y axis.
    pub struct SatelliteDish {
        params {
            /// Distance OA to the horn.
            r
        }
        drivers  {
            /// Turn of the mount about z.
            phi,
            /// Tilt of the dish about the mount's x axis.
            th
        }
        unknowns { }
        frames {
            /// The dish.
            dish = rot_z(phi) * rot_x(th);
        }
        points {
            /// The signal horn.
            A = dish * vec3(0.0, r, 0.0);
        }
    }
}

mechanism! {
    /// Crane (the notes' Practical Exercise 2): the cab turns about the
    /// vertical z axis by φ; the boom of length l is raised by θ above the
    /// horizontal, about the cab's y axis.
    pub struct Crane {
        params {
            /// Boom length OP.
            l
        }
        drivers  {
            /// Turn of the cab.
            phi,
            /// Elevation of the boom.
            th
        }
        unknowns { }
        frames {
            /// The boom.
            boom = rot_z(phi) * rot_y(-th);
        }
        points {
            /// Tip of the boom.
            P = boom * vec3(l, 0.0, 0.0);
        }
    }
}

mechanism! {
    /// The robot arm of the worked problem, as a serial chain of joint
    /// transforms: the base turns by q1 about the vertical z axis; the first
    /// link O₁O₂ = l1 rises at α in the base's y–z plane; the upper joint at
    /// O₂ turns by −q4 about the base's x axis; the arm O₂A = l2 points along
    /// (0, sin α, −cos α) (at 90° to O₁O₂); the arm rolls by q5 about its own
    /// axis, carrying AB = l3 along its x axis.
    pub struct RobotArm {
        params {
            /// O₁O₂.
            l1,
            /// O₂A.
            l2,
            /// AB.
            l3,
            /// Elevation of O₁O₂ (rad).
            alpha
        }
        drivers  {
            /// Base turn.
            q1,
            /// Upper joint.
            q4,
            /// Roll of the arm.
            q5
        }
        unknowns { }
        frames {
            /// Base.
            base = rot_z(q1);
            /// Upper joint body, at O₂.
            upper = base * t1(0.0, l1 * cos(alpha), l1 * sin(alpha), -q4);
            /// Arm body, at A.
            arm = upper
                * translation(vec3(0.0, l2 * sin(alpha), -l2 * cos(alpha)))
                * rot(vec3(0.0, sin(alpha), -cos(alpha)), q5);
        }
        points {
            /// Joint A.
            A = arm * vec3(0.0, 0.0, 0.0);
            /// Tip B.
            B = arm * vec3(l3, 0.0, 0.0);
        }
    }
}

mechanism! {
    /// A six-joint serial arm built from elementary matrices: waist q1 about
    /// z, shoulder q2 and elbow q3 about y, forearm roll q4 about x, wrist
    /// pitch q5 about y and wrist roll q6 about x; upper arm a2 and forearm
    /// a3 along x, wrist offset d5, tool point at d6 along the last x axis.
    pub struct SixAxisArm {
        params {
            /// Height of the shoulder above the base.
            d1,
            /// Upper arm.
            a2,
            /// Forearm.
            a3,
            /// Wrist offset.
            d5,
            /// Tool length.
            d6
        }
        drivers  { q1, q2, q3, q4, q5, q6 }
        unknowns { }
        frames {
            /// Upper arm.
            upper = t3(0.0, 0.0, d1, q1) * t2(0.0, 0.0, 0.0, q2);
            /// Forearm.
            fore = upper * t2(a2, 0.0, 0.0, q3) * t1(0.0, 0.0, 0.0, q4);
            /// Tool flange.
            tool = fore * t2(a3, 0.0, 0.0, q5) * t1(d5, 0.0, 0.0, q6);
        }
        points {
            /// Tool centre point.
            TCP = tool * vec3(d6, 0.0, 0.0);
        }
    }
}

mechanism! {
    /// Watt II six-bar: four-bar A-B-C-D driving, through the rocker
    /// extension DE, a second four-bar D-E-F-G.
    pub struct Watt {
        params {
            /// Crank.
            a,
            /// Coupler.
            b,
            /// Rocker.
            c,
            /// Ground pivot distance AD.
            d,
            /// Rocker extension DE.
            e,
            /// Angle of DE from DC (rad).
            gamma,
            /// Link EF.
            f,
            /// Output link GF.
            g,
            /// Output pivot G, x.
            gx,
            /// Output pivot G, y.
            gy
        }
        drivers  { phi }
        unknowns { th3, th4, th5, th6 }
        points {
            B = polar(a, phi);
            D = vec2(d, 0.0);
            C = D + polar(c, th4);
            E = D + polar(e, th4 + gamma);
            F = E + polar(f, th5);
        }
        loops {
            B + polar(b, th3) == C;
            F == vec2(gx, gy) + polar(g, th6);
        }
    }
}

mechanism! {
    /// 5R five-bar with two driven cranks, at A = (0, 0) and E = (ex, ey).
    pub struct FiveBar {
        params {
            /// Crank AB.
            a,
            /// Link BC.
            b,
            /// Link DC.
            c,
            /// Crank ED.
            d,
            /// Pivot E, x.
            ex,
            /// Pivot E, y.
            ey
        }
        drivers  { phi1, phi2 }
        unknowns { th2, th3 }
        points {
            B = polar(a, phi1);
            D = vec2(ex, ey) + polar(d, phi2);
            C = B + polar(b, th2);
        }
        loops { C == D + polar(c, th3); }
    }
}

impl FourBar {
    /// The links of the skeleton drawing: crank, coupler triangle, rocker.
    pub const LINKS: [(&'static str, &'static str); 5] =
        [("A", "B"), ("B", "C"), ("B", "P"), ("C", "P"), ("C", "D")];

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

impl Watt {
    /// The six-bar used by the tests: the crank-rocker of
    /// [`FourBar::CRANK_ROCKER`] (a = 0.04 m, b = 0.12 m, c = 0.10 m,
    /// d = 0.11 m) extended by DE = 0.06 m along DC (γ = 0), driving EF =
    /// 0.10 m and GF = 0.08 m with G = (0.20, 0.10) m.
    pub const EXAMPLE: Watt = Watt {
        a: 0.04,
        b: 0.12,
        c: 0.10,
        d: 0.11,
        e: 0.06,
        gamma: 0.0,
        f: 0.10,
        g: 0.08,
        gx: 0.20,
        gy: 0.10,
    };

    /// A rough starting guess for [`Watt::EXAMPLE`] at φ = 0.
    pub const EXAMPLE_GUESS: WattCoords = WattCoords {
        phi: 0.0,
        th3: 1.0,
        th4: 1.6,
        th5: 0.3,
        th6: 1.9,
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

mechanism! {
    /// The Strider leg (diywalkers.com), with the joints of pylinkage's
    /// example: the frame A, B, B′ (B, B′ at `tri` from A, `ape` either
    /// side of the vertical), the crank A–C of unit length, the knees D
    /// and E (a femur from B′ and B, a long rocker arm from C), F and G
    /// fixed to the rocker arms (a short arm at `phi` from the long one),
    /// the feet H and I (a tibia from D and E, a foot link from F and G).
    pub struct Strider {
        params {
            /// Distance of B and B′ from A.
            tri,
            /// Angle of AB and AB′ from the vertical.
            ape,
            /// B′D and BE.
            femur,
            /// CD and CE.
            rocker_l,
            /// CF and CG.
            rocker_s,
            /// Angle of CF from CE (of CG from CD, the other way).
            phi,
            /// DH and EI.
            tibia,
            /// FH and GI.
            foot
        }
        drivers {
            /// Crank angle.
            th
        }
        unknowns { d1, d2, e1, e2, h1, h2, i1, i2 }
        points {
            C = polar(1.0, th);
            D = C + polar(rocker_l, d2);
            E = C + polar(rocker_l, e2);
            F = C + polar(rocker_s, e2 - phi);
            G = C + polar(rocker_s, d2 + phi);
            H = D + polar(tibia, h1);
            I = E + polar(tibia, i1);
        }
        loops {
            polar(tri, 0.5 * pi + ape) + polar(femur, d1) == C + polar(rocker_l, d2);
            polar(tri, 0.5 * pi - ape) + polar(femur, e1) == C + polar(rocker_l, e2);
            D + polar(tibia, h1) == F + polar(foot, h2);
            E + polar(tibia, i1) == G + polar(foot, i2);
        }
    }
}

impl Strider {
    /// The dimensions of pylinkage's Strider example (crank of unit
    /// length).
    pub const PYLINKAGE: Strider = Strider {
        tri: 2.0,
        ape: std::f64::consts::FRAC_PI_4,
        femur: 1.8,
        rocker_l: 2.6,
        rocker_s: 1.4,
        phi: std::f64::consts::PI + 0.2,
        tibia: 2.5,
        foot: 1.8,
    };

    /// A guess at crank angle `th` from the joints' starting positions in
    /// pylinkage's example (the crank pin below A, the knees outside, the
    /// feet below), which picks the assembly modes: each unknown the angle
    /// of its link between those positions.
    #[must_use]
    pub fn pylinkage_guess(th: f64) -> StriderCoords {
        let angle = |p: (f64, f64), q: (f64, f64)| (q.1 - p.1).atan2(q.0 - p.0);
        let (c, d, e) = ((0.0, -1.0), (-2.25, 0.0), (2.25, 0.0));
        let (f, g, h, i) = ((-1.4, -1.2), (1.4, -1.2), (-2.7, -2.7), (2.7, -2.7));
        let (b, bp) = ((1.41, 1.41), (-1.41, 1.41));
        StriderCoords {
            th,
            d1: angle(bp, d),
            d2: angle(c, d),
            e1: angle(b, e),
            e2: angle(c, e),
            h1: angle(d, h),
            h2: angle(f, h),
            i1: angle(e, i),
            i2: angle(g, i),
        }
    }
}

/// Angular speed in rad/s of a shaft turning at `rpm` revolutions per minute:
/// ω = π n / 30.
#[must_use]
pub fn rpm_to_rad_per_s(rpm: f64) -> f64 {
    std::f64::consts::PI * rpm / 30.0
}

mechanism! {
    /// Planar four-bar placed anywhere: crank pivot A = (x0, y0), rocker
    /// pivot D at distance d from A in the direction θ0; crank AB = a at
    /// angle φ (from the x axis), coupler BC = b at θ3, rocker DC = c at θ4,
    /// coupler point P = B + p·(cos(θ3 + β), sin(θ3 + β)). Its nine
    /// dimensions are the unknowns of the nine-point path synthesis problem.
    pub struct PlacedFourBar {
        params {
            /// x of the crank pivot A.
            x0,
            /// y of the crank pivot A.
            y0,
            /// Direction of AD from the x axis (rad).
            theta0,
            /// Ground length AD.
            d,
            /// Crank length AB.
            a,
            /// Coupler length BC.
            b,
            /// Rocker length DC.
            c,
            /// Distance BP to the coupler point.
            p,
            /// Angle of BP from BC (rad).
            beta
        }
        drivers  { phi }
        unknowns { th3, th4 }
        points {
            /// Crank pivot (fixed).
            A = vec2(x0, y0);
            /// Crank pin.
            B = A + polar(a, phi);
            /// Rocker pivot (fixed).
            D = A + polar(d, theta0);
            /// Rocker pin.
            C = D + polar(c, th4);
            /// Coupler point.
            P = B + polar(p, th3 + beta);
        }
        loops { B + polar(b, th3) == C; }
        sensitivities { x0, y0, theta0, d, a, b, c, p, beta }
    }
}

mechanism! {
    /// Single-cylinder engine with its links' masses: crank a, rod b with
    /// its centre of mass G3 at r3 from the crank pin, the piston at C on
    /// the x axis, the crank balanced (its centre of mass on the shaft O).
    /// The gas in the cylinder expands polytropically: its force on the
    /// piston is p1 A (h1 / h)^1.3, h = h0 + a + b − x the height of the
    /// gas above the piston. The joints: the main bearing, the crank pin,
    /// the piston pin and the cylinder.
    pub struct GasEngine {
        params {
            /// Crank radius (m).
            a,
            /// Rod length (m).
            b,
            /// Rod's centre of mass from the crank pin (m).
            r3,
            /// Crank mass (kg).
            m2,
            /// Crank's moment of inertia about the shaft (kg·m²).
            j2,
            /// Rod mass (kg).
            m3,
            /// Rod's moment of inertia about G3 (kg·m²).
            j3,
            /// Piston mass (kg).
            m4,
            /// Gas pressure (Pa) at the height h1.
            p1,
            /// The height of the gas at which its pressure is p1 (m).
            h1,
            /// The piston's area (m²).
            area,
            /// Clearance above the piston at top dead centre (m).
            h0
        }
        drivers  { phi }
        unknowns { th, x }
        points {
            /// Crankshaft.
            O = vec2(0.0, 0.0);
            /// Crank pin.
            B = polar(a, phi);
            /// Rod's centre of mass.
            G3 = B + polar(r3, th);
            /// Piston pin.
            C = vec2(x, 0.0);
        }
        loops { B + polar(b, th) == C; }
        bodies {
            crank(mass = m2, center = O, angle = phi, inertia = j2);
            rod(mass = m3, center = G3, angle = th, inertia = j3);
            piston(mass = m4, center = C);
        }
        loads {
            gravity(vec2(0.0, -9.81));
            force(C, vec2(-p1 * area * exp(1.3 * ln(h1 / (h0 + a + b - x))), 0.0), on = piston);
        }
        joints {
            bearing(revolute, O, between = (ground, crank), driver = phi);
            crank_pin(revolute, B, between = (crank, rod));
            piston_pin(revolute, C, between = (rod, piston));
            cylinder(prismatic, C, between = (ground, piston), axis = vec2(1.0, 0.0));
        }
    }
}

impl GasEngine {
    /// A 50 mm bore engine: crank 25 mm, rod 100 mm, 40 bar at 5 mm of
    /// clearance.
    pub const SMALL: GasEngine = GasEngine {
        a: 0.025,
        b: 0.1,
        r3: 0.03,
        m2: 1.2,
        j2: 6e-4,
        m3: 0.25,
        j3: 2.5e-4,
        m4: 0.3,
        p1: 40e5,
        h1: 0.005,
        area: 0.001_963_495_408_493_621,
        h0: 0.005,
    };
}

pub mod literature;

#[cfg(feature = "synthesis")]
pub mod synthesis_runs;
