//! The source of a chain of n four-bars, the rocker of each driving the
//! crank of the next: a large mechanism (2n unknowns, n RRR blocks with two
//! assembly modes each, 2^n assemblies) written out as `mechanism!` text.
//!
//! Loop k (k = 1…n), with crank angle θ_{k−1} (θ₀ = φ, the driver),
//! coupler angle u_k and rocker angle r_k = θ_k:
//!
//! a·e(r_{k−1}) + b·e(u_k) = (d, 0) + c·e(r_k),  e(x) = (cos x, sin x).
//!
//! With a < b, c, d and a + max(b, c, d) ≤ the sum of the other two, every
//! loop is a crank-rocker: it assembles at every crank angle, so every
//! rocker angle the loop before it puts out is a valid input.

use std::fmt::Write;

/// `mechanism! { … }` defining the public struct `name`: a chain of `n`
/// four-bars with parameters `a, b, c, d` (crank, coupler, rocker,
/// ground), driver `phi`, unknowns `u1, r1, …, un, rn`, and the rocker
/// pins `C1…Cn` as points.
#[must_use]
pub fn source(name: &str, n: usize) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "kinematics_core::mechanism! {{");
    let _ = writeln!(
        s,
        "    /// A chain of {n} crank-rocker four-bars: the rocker angle of each is the crank angle of the next."
    );
    let _ = writeln!(s, "    pub struct {name} {{");
    let _ = writeln!(
        s,
        "        params {{\n            /// Crank length.\n            a,\n            /// Coupler length.\n            b,\n            /// Rocker length.\n            c,\n            /// Ground length (the pivots of each loop are (0, 0) and (d, 0)).\n            d\n        }}"
    );
    let _ = writeln!(s, "        drivers {{ phi }}");
    let unknowns: Vec<String> = (1..=n).map(|k| format!("u{k}, r{k}")).collect();
    let _ = writeln!(s, "        unknowns {{ {} }}", unknowns.join(", "));
    let _ = writeln!(s, "        points {{");
    for k in 1..=n {
        let _ = writeln!(s, "            C{k} = vec2(d, 0.0) + polar(c, r{k});");
    }
    let _ = writeln!(s, "        }}");
    let _ = writeln!(s, "        loops {{");
    for k in 1..=n {
        let input = if k == 1 {
            "phi".to_string()
        } else {
            format!("r{}", k - 1)
        };
        let _ = writeln!(
            s,
            "            polar(a, {input}) + polar(b, u{k}) == vec2(d, 0.0) + polar(c, r{k});"
        );
    }
    let _ = writeln!(s, "        }}");
    let _ = writeln!(s, "    }}");
    let _ = writeln!(s, "}}");
    s
}
