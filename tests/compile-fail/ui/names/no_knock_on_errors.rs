use kinematics_core::{mechanism, Mechanism, Options};

mechanism! {
    /// A typo in the loop: the only error the user should see, although
    /// the code below uses every generated item.
    pub struct FourBar {
        params   { a, b, c, d }
        drivers  { phi }
        unknowns { th3, th4 }
        points   { B = polar(a, phi); }
        loops    { B + polar(b, th) == vec2(d, 0.0) + polar(c, th4); }
    }
}

fn generic<M: Mechanism>(m: &M, start: &M::Coords) -> usize {
    let _ = m.step_slices(start, &[1.0], &[0.0], &Options::DEFAULT);
    M::UNKNOWNS + M::POINT_NAMES.len()
}

fn main() {
    let m = FourBar { a: 0.04, b: 0.12, c: 0.10, d: 0.11 };
    let start = FourBarCoords { phi: 0.0, th3: 1.0, th4: 1.6 };
    let _ = m.validate();
    let _ = m.assemble(&start);
    let _ = m.assemble_with(&start, &Options::DEFAULT);
    let s = m.step(&start, 10.0, 0.0).map(|s| s.point_b().velocity);
    let _ = m.step_with(&start, 10.0, 0.0, &Options::DEFAULT);
    let _ = m.analyze(&start, 10.0, 0.0).map(|s| s.qd.th3 + s.conditioning);
    let _ = m.analyze_with(&start, 10.0, 0.0, &Options::DEFAULT);
    let _: [f64; 2] = m.residual(&start);
    let _ = m.point_positions(&start)[0].x;
    let _ = m.frame_rotations(&start);
    let _ = FourBar::DRIVERS + FourBar::UNKNOWNS + FourBar::EQUATIONS + FourBar::POINTS;
    let mut stepper = m.stepper(&Options::DEFAULT).expect("a stepper");
    let _ = stepper.step(&start, 10.0, 0.0);
    let _ = (s, generic(&m, &start));
}
