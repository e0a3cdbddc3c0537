//! A large mechanism (a chain of 200 unknowns) must work in a debug build on
//! a default test thread (2 MiB of stack): the generated code must not keep
//! N×N matrices on the stack.
// Test code asserts by panicking.
#![allow(clippy::expect_used, clippy::panic, missing_docs)]

use kinematics_core::mechanism;

mechanism! {
    /// x₁² = a + t, x_{k+1}² = x_k + a: each x_k = √(x_{k−1} + a), solved link by link.
    pub struct Chain {
        params   { a }
        drivers  { t }
        unknowns { x1, x2, x3, x4, x5, x6, x7, x8, x9, x10, x11, x12, x13, x14, x15, x16, x17, x18, x19, x20, x21, x22, x23, x24, x25, x26, x27, x28, x29, x30, x31, x32, x33, x34, x35, x36, x37, x38, x39, x40, x41, x42, x43, x44, x45, x46, x47, x48, x49, x50, x51, x52, x53, x54, x55, x56, x57, x58, x59, x60, x61, x62, x63, x64, x65, x66, x67, x68, x69, x70, x71, x72, x73, x74, x75, x76, x77, x78, x79, x80, x81, x82, x83, x84, x85, x86, x87, x88, x89, x90, x91, x92, x93, x94, x95, x96, x97, x98, x99, x100, x101, x102, x103, x104, x105, x106, x107, x108, x109, x110, x111, x112, x113, x114, x115, x116, x117, x118, x119, x120, x121, x122, x123, x124, x125, x126, x127, x128, x129, x130, x131, x132, x133, x134, x135, x136, x137, x138, x139, x140, x141, x142, x143, x144, x145, x146, x147, x148, x149, x150, x151, x152, x153, x154, x155, x156, x157, x158, x159, x160, x161, x162, x163, x164, x165, x166, x167, x168, x169, x170, x171, x172, x173, x174, x175, x176, x177, x178, x179, x180, x181, x182, x183, x184, x185, x186, x187, x188, x189, x190, x191, x192, x193, x194, x195, x196, x197, x198, x199, x200 }
        constraints {
            x1 * x1 == a + t;
            x2 * x2 == x1 + a;
            x3 * x3 == x2 + a;
            x4 * x4 == x3 + a;
            x5 * x5 == x4 + a;
            x6 * x6 == x5 + a;
            x7 * x7 == x6 + a;
            x8 * x8 == x7 + a;
            x9 * x9 == x8 + a;
            x10 * x10 == x9 + a;
            x11 * x11 == x10 + a;
            x12 * x12 == x11 + a;
            x13 * x13 == x12 + a;
            x14 * x14 == x13 + a;
            x15 * x15 == x14 + a;
            x16 * x16 == x15 + a;
            x17 * x17 == x16 + a;
            x18 * x18 == x17 + a;
            x19 * x19 == x18 + a;
            x20 * x20 == x19 + a;
            x21 * x21 == x20 + a;
            x22 * x22 == x21 + a;
            x23 * x23 == x22 + a;
            x24 * x24 == x23 + a;
            x25 * x25 == x24 + a;
            x26 * x26 == x25 + a;
            x27 * x27 == x26 + a;
            x28 * x28 == x27 + a;
            x29 * x29 == x28 + a;
            x30 * x30 == x29 + a;
            x31 * x31 == x30 + a;
            x32 * x32 == x31 + a;
            x33 * x33 == x32 + a;
            x34 * x34 == x33 + a;
            x35 * x35 == x34 + a;
            x36 * x36 == x35 + a;
            x37 * x37 == x36 + a;
            x38 * x38 == x37 + a;
            x39 * x39 == x38 + a;
            x40 * x40 == x39 + a;
            x41 * x41 == x40 + a;
            x42 * x42 == x41 + a;
            x43 * x43 == x42 + a;
            x44 * x44 == x43 + a;
            x45 * x45 == x44 + a;
            x46 * x46 == x45 + a;
            x47 * x47 == x46 + a;
            x48 * x48 == x47 + a;
            x49 * x49 == x48 + a;
            x50 * x50 == x49 + a;
            x51 * x51 == x50 + a;
            x52 * x52 == x51 + a;
            x53 * x53 == x52 + a;
            x54 * x54 == x53 + a;
            x55 * x55 == x54 + a;
            x56 * x56 == x55 + a;
            x57 * x57 == x56 + a;
            x58 * x58 == x57 + a;
            x59 * x59 == x58 + a;
            x60 * x60 == x59 + a;
            x61 * x61 == x60 + a;
            x62 * x62 == x61 + a;
            x63 * x63 == x62 + a;
            x64 * x64 == x63 + a;
            x65 * x65 == x64 + a;
            x66 * x66 == x65 + a;
            x67 * x67 == x66 + a;
            x68 * x68 == x67 + a;
            x69 * x69 == x68 + a;
            x70 * x70 == x69 + a;
            x71 * x71 == x70 + a;
            x72 * x72 == x71 + a;
            x73 * x73 == x72 + a;
            x74 * x74 == x73 + a;
            x75 * x75 == x74 + a;
            x76 * x76 == x75 + a;
            x77 * x77 == x76 + a;
            x78 * x78 == x77 + a;
            x79 * x79 == x78 + a;
            x80 * x80 == x79 + a;
            x81 * x81 == x80 + a;
            x82 * x82 == x81 + a;
            x83 * x83 == x82 + a;
            x84 * x84 == x83 + a;
            x85 * x85 == x84 + a;
            x86 * x86 == x85 + a;
            x87 * x87 == x86 + a;
            x88 * x88 == x87 + a;
            x89 * x89 == x88 + a;
            x90 * x90 == x89 + a;
            x91 * x91 == x90 + a;
            x92 * x92 == x91 + a;
            x93 * x93 == x92 + a;
            x94 * x94 == x93 + a;
            x95 * x95 == x94 + a;
            x96 * x96 == x95 + a;
            x97 * x97 == x96 + a;
            x98 * x98 == x97 + a;
            x99 * x99 == x98 + a;
            x100 * x100 == x99 + a;
            x101 * x101 == x100 + a;
            x102 * x102 == x101 + a;
            x103 * x103 == x102 + a;
            x104 * x104 == x103 + a;
            x105 * x105 == x104 + a;
            x106 * x106 == x105 + a;
            x107 * x107 == x106 + a;
            x108 * x108 == x107 + a;
            x109 * x109 == x108 + a;
            x110 * x110 == x109 + a;
            x111 * x111 == x110 + a;
            x112 * x112 == x111 + a;
            x113 * x113 == x112 + a;
            x114 * x114 == x113 + a;
            x115 * x115 == x114 + a;
            x116 * x116 == x115 + a;
            x117 * x117 == x116 + a;
            x118 * x118 == x117 + a;
            x119 * x119 == x118 + a;
            x120 * x120 == x119 + a;
            x121 * x121 == x120 + a;
            x122 * x122 == x121 + a;
            x123 * x123 == x122 + a;
            x124 * x124 == x123 + a;
            x125 * x125 == x124 + a;
            x126 * x126 == x125 + a;
            x127 * x127 == x126 + a;
            x128 * x128 == x127 + a;
            x129 * x129 == x128 + a;
            x130 * x130 == x129 + a;
            x131 * x131 == x130 + a;
            x132 * x132 == x131 + a;
            x133 * x133 == x132 + a;
            x134 * x134 == x133 + a;
            x135 * x135 == x134 + a;
            x136 * x136 == x135 + a;
            x137 * x137 == x136 + a;
            x138 * x138 == x137 + a;
            x139 * x139 == x138 + a;
            x140 * x140 == x139 + a;
            x141 * x141 == x140 + a;
            x142 * x142 == x141 + a;
            x143 * x143 == x142 + a;
            x144 * x144 == x143 + a;
            x145 * x145 == x144 + a;
            x146 * x146 == x145 + a;
            x147 * x147 == x146 + a;
            x148 * x148 == x147 + a;
            x149 * x149 == x148 + a;
            x150 * x150 == x149 + a;
            x151 * x151 == x150 + a;
            x152 * x152 == x151 + a;
            x153 * x153 == x152 + a;
            x154 * x154 == x153 + a;
            x155 * x155 == x154 + a;
            x156 * x156 == x155 + a;
            x157 * x157 == x156 + a;
            x158 * x158 == x157 + a;
            x159 * x159 == x158 + a;
            x160 * x160 == x159 + a;
            x161 * x161 == x160 + a;
            x162 * x162 == x161 + a;
            x163 * x163 == x162 + a;
            x164 * x164 == x163 + a;
            x165 * x165 == x164 + a;
            x166 * x166 == x165 + a;
            x167 * x167 == x166 + a;
            x168 * x168 == x167 + a;
            x169 * x169 == x168 + a;
            x170 * x170 == x169 + a;
            x171 * x171 == x170 + a;
            x172 * x172 == x171 + a;
            x173 * x173 == x172 + a;
            x174 * x174 == x173 + a;
            x175 * x175 == x174 + a;
            x176 * x176 == x175 + a;
            x177 * x177 == x176 + a;
            x178 * x178 == x177 + a;
            x179 * x179 == x178 + a;
            x180 * x180 == x179 + a;
            x181 * x181 == x180 + a;
            x182 * x182 == x181 + a;
            x183 * x183 == x182 + a;
            x184 * x184 == x183 + a;
            x185 * x185 == x184 + a;
            x186 * x186 == x185 + a;
            x187 * x187 == x186 + a;
            x188 * x188 == x187 + a;
            x189 * x189 == x188 + a;
            x190 * x190 == x189 + a;
            x191 * x191 == x190 + a;
            x192 * x192 == x191 + a;
            x193 * x193 == x192 + a;
            x194 * x194 == x193 + a;
            x195 * x195 == x194 + a;
            x196 * x196 == x195 + a;
            x197 * x197 == x196 + a;
            x198 * x198 == x197 + a;
            x199 * x199 == x198 + a;
            x200 * x200 == x199 + a;
        }
    }
}

/// The exact chain: x₁ = √(a + t), x_k = √(x_{k−1} + a), and the rates by
/// the chain rule, x_k' = x_{k−1}' / (2 x_k).
fn exact(a: f64, t: f64) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![(a + t).sqrt()];
    let mut xd = vec![1.0 / (2.0 * x[0])];
    for k in 1..200 {
        x.push((x[k - 1] + a).sqrt());
        xd.push(xd[k - 1] / (2.0 * x[k]));
    }
    (x, xd)
}

#[test]
fn a_chain_of_200_unknowns_steps_and_assembles_on_a_default_thread() {
    let m = Chain { a: 2.0 };
    let start = ChainCoords {
        t: 0.5,
        ..ChainCoords::default()
    };
    // Every unknown guessed at 1.5, near the fixed point x = 2 of x² = x + 2.
    let mut guess = start;
    for j in 1..=200 {
        kinematics_core::Coordinates::set(&mut guess, j, 1.5);
    }
    let pose = m.assemble(&guess).expect("assembles");
    let motion = m.step(&pose, 1.0, 0.0).expect("steps");
    let analysed = m.analyze(&pose, 1.0, 0.0).expect("analyses");
    let (x, xd) = exact(2.0, 0.5);
    for k in 0..200 {
        let q = kinematics_core::Coordinates::get(&motion.q, k + 1).expect("unknown");
        let qd = kinematics_core::Coordinates::get(&motion.qd, k + 1).expect("rate");
        let qa = kinematics_core::Coordinates::get(&analysed.qd, k + 1).expect("rate");
        assert!((q - x[k]).abs() < 1e-14, "x{} = {q} vs {}", k + 1, x[k]);
        assert!(
            (qd - xd[k]).abs() < 1e-14 && (qa - xd[k]).abs() < 1e-14,
            "x{}'",
            k + 1
        );
    }
    // `assemble` above ran the general (damped) solver; `step` from a far
    // guess runs its inline iteration on the same sparse storage.
    let mut far = start;
    for j in 1..=200 {
        kinematics_core::Coordinates::set(&mut far, j, 40.0);
    }
    let again = m.step(&far, 1.0, 0.0).expect("steps from a poor guess");
    assert!((again.q.x200 - x[199]).abs() < 1e-14);
}
