//! The equations of motion of a run-time model's own `bodies` and `loads`
//! sections from their compiled roots
//! ([`kinematics_compiler::motion::EquationsOfMotion`]): one call of the
//! machine code gives Φ_q, the mass matrix M̃ and the generalized forces f̃
//! in the coordinates and each load's power; the kinematic coefficients C
//! (C_d = I, Φ_u C_u = −Φ_d) then give the drivers' M = Cᵀ M̃ C and
//! b = Cᵀ f̃, with no walk over the bodies and loads and no unit analysis.

use alloc::vec;
use alloc::vec::Vec;

use super::Model;
use super::sections::SectionCode;
use crate::dynamics::Dynamics;
use crate::dynamics::forward::equations::{Equations, Reduction};

/// The compiled equations of one model, with room for one evaluation.
pub(super) struct Compiled<'m> {
    code: &'m SectionCode,
    stage: usize,
    values: &'m [f64],
    /// The stage's outputs: Φ_q, M̃'s upper triangle, f̃, the powers.
    out: Vec<f64>,
    /// The coordinates' cosines and sines, two each.
    trig: Vec<f64>,
    reduction: Reduction,
}

impl<'m> Compiled<'m> {
    /// The compiled equations of `m`, when `dynamics` is exactly its
    /// sections at its present values ([`Model::dynamics`]) and the
    /// compiler formed them; `None` otherwise (the forward simulation then
    /// sums the bodies and loads at run time).
    pub(super) fn new(m: &'m Model, dynamics: &Dynamics) -> Option<Self> {
        let code: &SectionCode = m.sections()?;
        if !dynamics
            .sections_values(code.owner())
            .is_some_and(|v| crate::checks::same_bits(v, m.all_values()))
        {
            return None;
        }
        let (stage, motion) = code.motion()?;
        let (n, nd) = (motion.coordinates, m.drivers());
        let powers = motion.powers.len();
        let reduction = Reduction::new(n, nd, motion.reduced.is_some());
        // (No driver, no motion to simulate.)
        if nd == 0
            || n != m.coordinates().len()
            || powers != dynamics.working_loads()
            || code.outputs(stage) != reduction.outputs(powers)
        {
            return None;
        }
        Some(Self {
            code,
            stage,
            values: m.all_values(),
            out: vec![0.0; code.outputs(stage)],
            trig: vec![0.0; 2 * n],
            reduction,
        })
    }

    /// M, b and the loads' powers at the coordinates `coords` (q, q̇ and q̈
    /// with the free drivers' accelerations zero; the cosines and sines
    /// `trig` holds of some, as in `SectionCode::eval_at`) and the time
    /// `t`, into
    /// `eq`; `false` where Φ_u is singular or a value is not finite (the
    /// caller then sums the general way, which names the cause).
    pub(super) fn equations(
        &mut self,
        coords: [&[f64]; 3],
        t: f64,
        trig: Option<(&[f64], &[bool])>,
        eq: &mut Equations<'_>,
    ) -> bool {
        if !self.code.eval_into(
            self.stage,
            self.values,
            coords,
            t,
            trig,
            &mut self.trig,
            &mut self.out,
        ) {
            return false;
        }
        self.reduction.reduce(&self.out, eq)
    }

    /// M, b and the powers from the roots of the equations of motion as a
    /// fused step evaluated them ([`super::Stepper::fused_motion`]), as
    /// [`Compiled::equations`] does from its own evaluation.
    #[inline]
    pub(super) fn reduce(&mut self, roots: &[f64], eq: &mut Equations<'_>) -> bool {
        self.reduction.reduce(roots, eq)
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use super::Compiled;
    use crate::dynamics::forward::equations::Equations;
    use crate::dynamics::forward::run::Timed;
    use crate::dynamics::terms::Terms;
    use crate::runtime::Model;
    use crate::runtime::dynamics::{RunTime, unit_analyses};

    /// M, b and the powers of `text` at the pose `start` (assembled there)
    /// with the rates `rates`, the free accelerations `accelerations`, at
    /// time `t`: by the compiled equations and by the sums over the bodies
    /// and loads with unit analyses, which must agree; and, where a fused
    /// step takes the pose, by the compiled equations with the cosines
    /// and sines that step holds (then `true`).
    fn agree(text: &str, values: &[f64], start: &[f64], rates: &[f64], t: f64) -> bool {
        let m = Model::compile(text)
            .expect("compiles")
            .with_values(values)
            .expect("values");
        let marked = m.dynamics().expect("sections");
        let mut compiled = Compiled::new(&m, &marked).expect("the compiled equations");
        let general = m
            .dynamics_builder()
            .expect("builder")
            .build_for(&m)
            .expect("built");
        assert!(
            Compiled::new(&m, &general).is_none(),
            "a description not marked as the sections sums at run time"
        );
        let nd = m.drivers();
        let pose = m.assemble(start).expect("assembled");
        let motion = m.analyze(&pose, rates, &vec![0.0; nd]).expect("analysed");
        let w = general.working_loads();
        let nb = general.body_count();
        let mut stepper = m.stepper(&crate::Options::default()).expect("a stepper");
        // A second stepper whose fused step evaluates the equations of
        // motion itself (`advance_motion`): everywhere a fused step is, but
        // for loads that read the time (that code reads none).
        let mut with_motion = m.stepper(&crate::Options::default()).expect("a stepper");
        let reads_time = m.sections().expect("sections").reads_time();
        let fusible = with_motion.with_motion();
        // Twenty steps toward the pose, then the pose: the fused step's
        // carried cosines and sines as a run has them, not a first step's.
        let mut q = pose.clone();
        for k in (1..=20).rev() {
            for (x, p) in q.iter_mut().zip(&pose).take(nd) {
                *x = p - 1e-3 * f64::from(k);
            }
            let flat = stepper
                .step_flat(&q, rates, &vec![0.0; nd])
                .expect("a step");
            q.copy_from_slice(flat.q);
            with_motion
                .advance_motion(&q, rates, &vec![0.0; nd])
                .expect("a step");
        }
        q[..nd].copy_from_slice(&pose[..nd]);
        let stepped: Vec<Vec<f64>> = {
            let flat = stepper
                .step_flat(&q, rates, &vec![0.0; nd])
                .expect("a step");
            vec![flat.q.to_vec(), flat.qd.to_vec(), flat.qdd.to_vec()]
        };
        let fused = stepper.fused_trig();
        assert_eq!(fusible, fused.is_some() && !reads_time);
        with_motion
            .advance_motion(&q, rates, &vec![0.0; nd])
            .expect("a step");
        let roots = with_motion.fused_motion().map(<[f64]>::to_vec);
        assert_eq!(roots.is_some(), fusible);
        let run = |mode: u8, compiled: &mut Compiled<'_>| {
            let (mut mass, mut bias, mut powers) =
                (vec![0.0; nd * nd], vec![0.0; nd], vec![0.0; w]);
            let mut partials = vec![[nalgebra::Vector3::zeros(); 2]; nd * nb];
            let mut terms = Terms::default();
            let mut out = Equations {
                mass: &mut mass,
                bias: &mut bias,
                powers: &mut powers,
                partials: &mut partials,
                terms: &mut terms,
            };
            if mode == 0 {
                assert!(compiled.equations(
                    [&motion.q, &motion.qd, &motion.qdd],
                    t,
                    None,
                    &mut out
                ));
            } else if mode == 1 {
                let coords = [&stepped[0][..], &stepped[1][..], &stepped[2][..]];
                assert!(compiled.equations(coords, t, fused, &mut out));
            } else if mode == 3 {
                assert!(compiled.reduce(roots.as_deref().unwrap_or(&[]), &mut out));
            } else {
                let view = RunTime(&motion);
                general
                    .equations(
                        &Timed(&view, t),
                        &mut unit_analyses(&m, &motion.q, nd),
                        &mut out,
                    )
                    .expect("the sums");
            }
            (mass, bias, powers)
        };
        let all = |x: &(Vec<f64>, Vec<f64>, Vec<f64>)| -> Vec<f64> {
            x.0.iter().chain(&x.1).chain(&x.2).copied().collect()
        };
        let b = all(&run(2, &mut compiled));
        let scale = b.iter().fold(1e-300_f64, |s, v| s.max(v.abs()));
        let modes: &[u8] = match (fused.is_some(), fusible) {
            (true, true) => &[0, 1, 3],
            (true, false) => &[0, 1],
            _ => &[0],
        };
        for &mode in modes {
            let a = all(&run(mode, &mut compiled));
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= 1e-12 * scale,
                    "compiled ({mode}) {a:?}\nsummed {b:?}"
                );
            }
        }
        fused.is_some()
    }

    /// After `advance_motion`, which leaves the points out, `complete`
    /// evaluates them: bit for bit the plain step's through the same
    /// poses (two steppers, one stepped each way); and where a point is
    /// not finite, the general path's error, as `Model::step` gives it.
    #[test]
    fn complete_evaluates_the_points_an_evaluation_left_out() {
        // Q is finite where the rocker is past 1.9 rad (the crank near
        // π), not where it is short of it (the crank near 0: 1.61 rad).
        let m = Model::compile(
            "struct FourBar {
                params   { a, b, c, d }
                drivers  { phi }
                unknowns { th3, th4 }
                points {
                    G3 = polar(a, phi) + polar(b / 2.0, th3);
                    G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
                    Q = vec2(sqrt(th4 - 1.9), 0.0);
                }
                loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
                bodies {
                    coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
                    rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
                }
                loads { gravity(vec2(0.0, -9.81)); }
            }",
        )
        .expect("compiles")
        .with_values(&[0.04, 0.12, 0.10, 0.11])
        .expect("values");
        let options = crate::Options::default();
        let (mut plain, mut motion) = (
            m.stepper(&options).expect("a stepper"),
            m.stepper(&options).expect("a stepper"),
        );
        assert!(
            motion.with_motion(),
            "the model has its equations of motion"
        );
        let mut q = vec![2.6, 1.0, 2.1];
        for k in 0..40 {
            q[0] = 2.6 + 0.02 * f64::from(k);
            let (rates, accelerations) = ([3.0 + 0.1 * f64::from(k)], [-2.0]);
            let flat = plain.step_flat(&q, &rates, &accelerations).expect("a step");
            let want: Vec<u64> = flat.outputs.iter().map(|v| v.to_bits()).collect();
            let want_q = flat.q.to_vec();
            motion
                .advance_motion(&q, &rates, &accelerations)
                .expect("a step");
            assert!(
                motion.fused_motion().is_some(),
                "the fused step with the equations"
            );
            motion.complete().expect("every point finite");
            let got: Vec<u64> = motion.flat().outputs.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, want, "the points at step {k}");
            assert_eq!(motion.motion_now().q, want_q);
            q.copy_from_slice(&want_q);
        }
        // The crank at 0.3 rad: the rocker short of 1.9 rad, Q not finite.
        let start = [0.3, 0.9, 1.6];
        motion
            .advance_motion(&start, &[3.0], &[0.0])
            .expect("the equations need no Q");
        let error = motion.complete().expect_err("Q is not finite");
        let general = m.step(&start, &[3.0], &[0.0]).expect_err("Q is not finite");
        assert_eq!(error.to_string(), general.to_string());
        assert!(error.to_string().contains('Q'), "{error}");
    }

    #[test]
    fn a_four_bar_with_a_motor_a_spring_damper_and_a_force_agrees_with_the_sums() {
        assert!(
            agree(
                "struct FourBar {
                    params   { a, b, c, d }
                    drivers  { phi }
                    unknowns { th3, th4 }
                    points {
                        G2 = polar(a / 2.0, phi);
                        G3 = polar(a, phi) + polar(b / 2.0, th3);
                        G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
                        P0 = vec2(0.05, 0.15);
                    }
                    loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
                    bodies {
                        crank(mass = 0.3, center = G2, angle = phi, inertia = 2.0e-3);
                        coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
                        rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
                    }
                    loads {
                        gravity(vec2(0.0, -9.81));
                        force(phi, 0.5 * (1.0 - rate(phi) / 60.0));
                        force(G3, vec2(2.0 * sin(time), -rate(th4)));
                        torque(rocker, 0.1 * cos(th4) + 0.01 * time);
                        spring(P0, G3, stiffness = 50.0, free_length = 0.10, damping = 2.0);
                    }
                }",
                &[0.04, 0.12, 0.10, 0.11],
                &[0.7, 1.2, 1.9],
                &[13.0],
                0.4,
            ),
            "the fused step's cosines and sines are used"
        );
    }

    #[test]
    fn a_coupler_placed_from_the_rocker_side_agrees_with_the_sums() {
        // The coupler's centre reached through the rocker: its velocity
        // reads both unknowns' rates, so M̃ couples them (M̃₁₂ ≠ 0), which
        // the coupler placed from the crank's side does not.
        assert!(
            agree(
                "struct FourBar {
                    params   { a, b, c, d }
                    drivers  { phi }
                    unknowns { th3, th4 }
                    points {
                        G2 = polar(a / 2.0, phi);
                        G3 = vec2(d, 0.0) + polar(c, th4) - polar(b / 2.0, th3);
                        G4 = vec2(d, 0.0) + polar(c / 2.0, th4);
                    }
                    loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
                    bodies {
                        crank(mass = 0.3, center = G2, angle = phi, inertia = 2.0e-3);
                        coupler(mass = 0.5, center = G3, angle = th3, inertia = 6.0e-4);
                        rocker(mass = 0.4, center = G4, angle = th4, inertia = 3.5e-4);
                    }
                    loads { gravity(vec2(0.0, -9.81)); force(G3, vec2(1.0, -rate(th3))); }
                }",
                &[0.04, 0.12, 0.10, 0.11],
                &[0.7, 1.2, 1.9],
                &[13.0],
                0.0,
            ),
            "the fused step's cosines and sines are used"
        );
    }

    #[test]
    fn two_free_drivers_and_a_slider_agree_with_the_sums() {
        // A two-link arm (two drivers) carrying a slider along its
        // second link, held by a spring to the frame.
        agree(
            "struct Arm {
                params   { l1, l2 }
                drivers  { t1, t2 }
                unknowns { }
                points {
                    O = vec2(0.0, 0.0);
                    E = polar(l1, t1);
                    G1 = polar(l1 / 2.0, t1);
                    G2 = polar(l1, t1) + polar(l2 / 2.0, t1 + t2);
                    T = polar(l1, t1) + polar(l2, t1 + t2);
                }
                bodies {
                    upper(mass = 1.2, center = G1, angle = t1, inertia = 0.02);
                    fore(mass = 0.8, center = G2, angle = t1 + t2, inertia = 0.01);
                    tip(mass = 0.3, center = T);
                }
                loads {
                    gravity(vec2(0.0, -9.81));
                    force(t2, -0.5 * rate(t2));
                    spring(O, T, stiffness = 20.0, free_length = 0.3, damping = 0.4);
                }
            }",
            &[0.5, 0.4],
            &[0.3, 0.9],
            &[1.5, -2.0],
            0.0,
        );
    }

    #[test]
    fn a_spatial_rssr_with_inertia_tensors_and_a_torque_agrees_with_the_sums() {
        agree(
            "struct Rssr {
                params   { a, b, c, d, g }
                drivers  { phi }
                unknowns { psi }
                frames {
                    crank = rot_y(-phi);
                    rocker = translation(vec3(-d, 0.0, 0.0)) * rot_z(-psi);
                }
                points {
                    A = vec3(-a * cos(phi), 0.0, a * sin(phi));
                    B = vec3(-d - c * cos(psi), c * sin(psi), 0.0);
                    G2 = vec3(-a * cos(phi) / 2.0, 0.0, a * sin(phi) / 2.0);
                    G3 = 0.5 * (vec3(-a * cos(phi), 0.0, a * sin(phi)) + vec3(-d - c * cos(psi), c * sin(psi), 0.0));
                    G4 = vec3(-d - c * cos(psi) / 2.0, c * sin(psi) / 2.0, 0.0);
                }
                constraints { norm(B - A) == b; }
                bodies {
                    crank(mass = 0.2, center = G2, frame = crank,
                          inertia = [[3e-5, 2e-6, 0.0], [2e-6, 1e-5, 1e-6], [0.0, 1e-6, 3e-5]]);
                    coupler(mass = 0.4, center = G3);
                    rocker(mass = 0.3, center = G4, frame = rocker,
                           inertia = [[2e-5, 2e-6, 0.0], [2e-6, 4e-5, 1e-6], [0.0, 1e-6, 5e-5]]);
                }
                loads {
                    gravity(vec3(0.0, -g, -2.0));
                    torque(rocker, vec3(0.001, 0.01 * rate(psi), 0.02));
                    force(B, vec3(0.0, 0.3, -rate(phi)));
                }
            }",
            &[0.03, 0.12, 0.08, 0.1, 9.81],
            &[0.7, 1.1],
            &[9.0],
            0.0,
        );
    }

    #[test]
    fn a_gimbal_with_its_gyroscopic_terms_agrees_with_the_sums() {
        // Two drivers turning a disc about axes that move: ω × J ω works.
        agree(
            "struct Gimbal {
                params   { r }
                drivers  { t1, t2 }
                unknowns { }
                frames   { ring = rot_z(t1) * rot_x(t2); }
                points   { G = rot_z(t1) * rot_x(t2) * vec3(r, 0.05, 0.02); }
                bodies {
                    disc(mass = 1.5, center = G, frame = ring,
                         inertia = [[0.03, 0.002, 0.001], [0.002, 0.02, 0.003], [0.001, 0.003, 0.04]]);
                }
                loads {
                    gravity(vec3(0.0, 0.0, -9.81));
                    torque(disc, vec3(0.0, 0.1, 0.02 * rate(t2)));
                }
            }",
            &[0.2],
            &[0.4, 0.9],
            &[3.0, -5.0],
            0.0,
        );
    }
}
