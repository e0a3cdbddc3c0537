//! The four benchmark mechanisms, each declared once for `mechanism!` and,
//! as tokens, for the run-time interpreter; and the same residuals and
//! outputs written once more, generically over dual numbers, for the
//! automatic-differentiation and finite-difference variants.

use num_dual::DualNum;

/// Declares a mechanism with `mechanism!` and keeps its tokens.
macro_rules! model {
    ($module:ident, $($def:tt)*) => {
        pub mod $module {
            #![allow(missing_docs)]
            kinematics_core::mechanism! { $($def)* }
            /// The definition's tokens, for the interpreted variant.
            pub fn tokens() -> proc_macro2::TokenStream {
                quote::quote! { $($def)* }
            }
        }
    };
}

model!(m1, pub struct FourBar {
    params   { a, b, c, d, p, beta }
    drivers  { phi }
    unknowns { th3, th4 }
    points { P = polar(a, phi) + polar(p, th3 + beta); }
    loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
});

model!(m2, pub struct Rssr {
    params   { a, b, c, d }
    drivers  { phi }
    unknowns { psi }
    points { B = vec3(-d - c * cos(psi), c * sin(psi), 0.0); }
    constraints {
        dot(B - vec3(-a * cos(phi), 0.0, a * sin(phi)), B - vec3(-a * cos(phi), 0.0, a * sin(phi)))
            == b * b;
    }
});

model!(m3, pub struct Watt {
    params { a, b, c, d, e, gamma, f, g, gx, gy }
    drivers  { phi }
    unknowns { th3, th4, th5, th6 }
    points { F = vec2(d, 0.0) + polar(e, th4 + gamma) + polar(f, th5); }
    loops {
        polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4);
        F == vec2(gx, gy) + polar(g, th6);
    }
});

model!(m4, pub struct Arm {
    params { d1, a2, a3, d5, d6 }
    drivers  { q1, q2, q3, q4, q5, q6 }
    unknowns { }
    frames {
        tool = t3(0.0, 0.0, d1, q1) * t2(0.0, 0.0, 0.0, q2) * t2(a2, 0.0, 0.0, q3)
            * t1(0.0, 0.0, 0.0, q4) * t2(a3, 0.0, 0.0, q5) * t1(d5, 0.0, 0.0, q6);
    }
    points { TCP = tool * vec3(d6, 0.0, 0.0); }
});

/// M5, for the positions-only benchmark: a slider-crank whose slider runs
/// in a curved guide, the parabola x = h + k y², which no closed form
/// covers (Newton–Raphson on the whole system).
pub mod m5 {
    #![allow(missing_docs)]
    kinematics_core::mechanism! {
        pub struct CurvedSlider {
            params   { a, b, h, k }
            drivers  { phi }
            unknowns { th, y }
            loops { polar(a, phi) + polar(b, th) == vec2(h + k * y * y, y); }
        }
    }
}

pub const M5: m5::CurvedSlider = m5::CurvedSlider {
    a: 0.05,
    b: 0.2,
    h: 0.05,
    k: 2.0,
};

pub const M1: m1::FourBar = m1::FourBar {
    a: 0.04,
    b: 0.12,
    c: 0.10,
    d: 0.11,
    p: 0.06,
    beta: std::f64::consts::FRAC_PI_6,
};
pub const M2: m2::Rssr = m2::Rssr {
    a: 0.102,
    b: 0.381,
    c: 0.254,
    d: 0.315,
};
pub const M3: m3::Watt = m3::Watt {
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
pub const M4: m4::Arm = m4::Arm {
    d1: 0.4,
    a2: 0.45,
    a3: 0.4,
    d5: 0.08,
    d6: 0.1,
};

/// Joint path of the arm over the sweep: q_i = c_i + k_i s.
pub const ARM_OFFSET: [f64; 6] = [0.1, -0.4, 0.9, 0.2, -0.6, 0.3];
pub const ARM_SPEED: [f64; 6] = [1.0, 0.5, -0.5, 1.0, 0.7, -1.0];

/// A mechanism written generically over dual numbers: q = (drivers,
/// unknowns); the residual Φ(q), the point and (for the arm) the frame
/// rotation, row-major.
pub trait Generic {
    const ND: usize;
    const DIM: usize;
    const HAS_FRAME: bool;
    fn residual<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]);
    fn point<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]);
    fn rotation<T: DualNum<Primitive = f64> + Copy>(&self, _q: &[T], _out: &mut [T; 9]) {}
}

fn k<T: DualNum<Primitive = f64> + Copy>(x: f64) -> T {
    T::from(x)
}

impl Generic for m1::FourBar {
    const ND: usize = 1;
    const DIM: usize = 2;
    const HAS_FRAME: bool = false;
    fn residual<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let (phi, t3, t4) = (q[0], q[1], q[2]);
        out[0] = phi.cos() * self.a + t3.cos() * self.b - k::<T>(self.d) - t4.cos() * self.c;
        out[1] = phi.sin() * self.a + t3.sin() * self.b - t4.sin() * self.c;
    }
    fn point<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let (phi, t3) = (q[0], q[1]);
        let ang = t3 + self.beta;
        out[0] = phi.cos() * self.a + ang.cos() * self.p;
        out[1] = phi.sin() * self.a + ang.sin() * self.p;
    }
}

impl Generic for m2::Rssr {
    const ND: usize = 1;
    const DIM: usize = 3;
    const HAS_FRAME: bool = false;
    fn residual<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let (phi, psi) = (q[0], q[1]);
        let dx = -psi.cos() * self.c - self.d + phi.cos() * self.a;
        let dy = psi.sin() * self.c;
        let dz = -phi.sin() * self.a;
        out[0] = dx * dx + dy * dy + dz * dz - self.b * self.b;
    }
    fn point<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let psi = q[1];
        out[0] = -psi.cos() * self.c - self.d;
        out[1] = psi.sin() * self.c;
        out[2] = k(0.0);
    }
}

impl Generic for m3::Watt {
    const ND: usize = 1;
    const DIM: usize = 2;
    const HAS_FRAME: bool = false;
    fn residual<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let (phi, t3, t4, t5, t6) = (q[0], q[1], q[2], q[3], q[4]);
        out[0] = phi.cos() * self.a + t3.cos() * self.b - self.d - t4.cos() * self.c;
        out[1] = phi.sin() * self.a + t3.sin() * self.b - t4.sin() * self.c;
        let te = t4 + self.gamma;
        out[2] = te.cos() * self.e + t5.cos() * self.f + self.d - self.gx - t6.cos() * self.g;
        out[3] = te.sin() * self.e + t5.sin() * self.f - self.gy - t6.sin() * self.g;
    }
    fn point<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let (t4, t5) = (q[2], q[3]);
        let te = t4 + self.gamma;
        out[0] = te.cos() * self.e + t5.cos() * self.f + self.d;
        out[1] = te.sin() * self.e + t5.sin() * self.f;
    }
}

/// 3×3 product for the arm's generic chain.
fn mat<T: DualNum<Primitive = f64> + Copy>(a: &[T; 9], b: &[T; 9]) -> [T; 9] {
    let mut out = [k::<T>(0.0); 9];
    for i in 0..3 {
        for j in 0..3 {
            out[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
        }
    }
    out
}

fn rot<T: DualNum<Primitive = f64> + Copy>(axis: usize, t: T) -> [T; 9] {
    let (s, c) = (t.sin(), t.cos());
    let (o, z) = (k::<T>(1.0), k::<T>(0.0));
    match axis {
        0 => [o, z, z, z, c, -s, z, s, c],
        1 => [c, z, s, z, o, z, -s, z, c],
        _ => [c, -s, z, s, c, z, z, z, o],
    }
}

fn mv<T: DualNum<Primitive = f64> + Copy>(r: &[T; 9], v: [T; 3]) -> [T; 3] {
    [
        r[0] * v[0] + r[1] * v[1] + r[2] * v[2],
        r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
        r[6] * v[0] + r[7] * v[1] + r[8] * v[2],
    ]
}

impl m4::Arm {
    /// Tool rotation and origin along the chain.
    fn chain<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T]) -> ([T; 9], [T; 3]) {
        let z = k::<T>(0.0);
        let r = rot(2, q[0]);
        let mut o = [z, z, k(self.d1)];
        let r = mat(&r, &rot(1, q[1]));
        let add = |o: [T; 3], d: [T; 3]| [o[0] + d[0], o[1] + d[1], o[2] + d[2]];
        o = add(o, mv(&r, [k(self.a2), z, z]));
        let r = mat(&r, &rot(1, q[2]));
        let r = mat(&r, &rot(0, q[3]));
        o = add(o, mv(&r, [k(self.a3), z, z]));
        let r = mat(&r, &rot(1, q[4]));
        o = add(o, mv(&r, [k(self.d5), z, z]));
        let r = mat(&r, &rot(0, q[5]));
        (r, o)
    }
}

impl Generic for m4::Arm {
    const ND: usize = 6;
    const DIM: usize = 3;
    const HAS_FRAME: bool = true;
    fn residual<T: DualNum<Primitive = f64> + Copy>(&self, _q: &[T], _out: &mut [T]) {}
    fn point<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T]) {
        let (r, o) = self.chain(q);
        let p = mv(&r, [k(self.d6), k(0.0), k(0.0)]);
        for i in 0..3 {
            out[i] = o[i] + p[i];
        }
    }
    fn rotation<T: DualNum<Primitive = f64> + Copy>(&self, q: &[T], out: &mut [T; 9]) {
        *out = self.chain(q).0;
    }
}
