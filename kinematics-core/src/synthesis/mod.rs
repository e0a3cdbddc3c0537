//! Dimensional synthesis by Levenberg–Marquardt with exact derivatives.
//!
//! Path generation: find parameters p (link lengths, the coupler point,
//! the ground pivots: whatever the mechanism declares in its
//! `sensitivities` section and the synthesis varies) and, unless the
//! timing is prescribed, the driver values φ_j, so that a point passes
//! through N targets t_j:
//!
//! min over (p, φ) of  E = Σ_j |r(φ_j, p) − t_j|².
//!
//! Function generation: the same with an unknown coordinate u(φ_j, p)
//! instead of a point, against prescribed input–output pairs (φ_j, ψ_j),
//! with angle differences taken in (−π, π].
//!
//! Every residual's derivatives are exact: ∂r/∂p from the generated design
//! sensitivities (Φ_u ∂u/∂p = −Φ_p, ∂r/∂p = r_p + r_u ∂u/∂p) and ∂r/∂φ_j
//! as the point's velocity for a unit driver rate. The least-squares
//! problem is solved by the `levenberg-marquardt` crate (MINPACK's
//! trust-region algorithm).
//!
//! * **Assembly.** Every target is assembled in the same assembly modes,
//!   those of the starting pose (or those given by
//!   [`Synthesis::modes`]), so the design found works on one branch.
//!   A trial design that cannot be assembled at some target is rejected
//!   as a step that does not decrease E (the trust region shrinks).
//! * **Bounds** lo ≤ p ≤ hi are kept by the change of variables
//!   p = lo + (hi − lo)(1 + sin x)/2 (one bound: p = lo − 1 + √(x² + 1)),
//!   so every iterate is within them.
//! * **Linear inequalities** Σ c_k p_k ≤ h (and the Grashof condition for
//!   a crank, which is three of them) are added as residuals
//!   w · max(0, Σ c_k p_k − h); when the result violates one by more than
//!   10⁻¹⁰ of the design's scale, w grows a hundredfold and the
//!   minimisation goes on from there (at most six times).
//! * **Order.** With free timing, [`Synthesis::in_order`] keeps the
//!   driver values increasing through the targets (φ_j ≤ φ_{j+1}, and
//!   φ_N ≤ φ₁ + 2π for an angle driver), as penalty residuals like the
//!   linear inequalities'.
//! * **Run-time models.** A `runtime::Model` is
//!   synthesised as a generated mechanism is (see [`Subject`]; with the
//!   `runtime` feature).
//! * **Full turn.** For an angle driver, [`Synthesized::full_turn`] says
//!   whether the design sweeps a whole turn in its assembly modes.
//!
//! ```
//! use kinematics_core::{mechanism, synthesis::Synthesis};
//!
//! mechanism! {
//!     /// A four-bar with its coupler point P.
//!     struct FourBar {
//!         params { a, b, c, d, p, beta }
//!         drivers { phi }
//!         unknowns { th3, th4 }
//!         points { P = polar(a, phi) + polar(p, th3 + beta); }
//!         loops { polar(a, phi) + polar(b, th3) == vec2(d, 0.0) + polar(c, th4); }
//!         sensitivities { a, b, c, p, beta }
//!     }
//! }
//!
//! # fn main() -> Result<(), kinematics_core::Error> {
//! // Targets: five points of the coupler curve of a known design, at
//! // φ = 0.3, 1.1, 2.0, 3.5 and 5.0.
//! let truth = FourBar { a: 1.0, b: 3.0, c: 2.5, d: 3.0, p: 1.5, beta: 0.6 };
//! let start = truth.assemble(&FourBarCoords { phi: 0.0, th3: 0.5, th4: 1.5 })?;
//! let targets: Vec<[f64; 2]> = [0.3, 1.1, 2.0, 3.5, 5.0]
//!     .iter()
//!     .map(|&phi| {
//!         let pose = truth.assemble(&FourBarCoords { phi, ..start }).unwrap();
//!         let p = truth.positions(&pose).P;
//!         [p.x, p.y]
//!     })
//!     .collect();
//! // From a design 10 % off, with the same crank angles prescribed.
//! let guess = FourBar { a: 1.1, b: 2.8, c: 2.7, d: 3.0, p: 1.3, beta: 0.5 };
//! let found = Synthesis::path(&guess, FourBar::PHI, "P", &targets, &start)
//!     .prescribed(&[0.3, 1.1, 2.0, 3.5, 5.0])
//!     .run()?;
//! assert!(found.sum_squares < 1e-20);
//! assert!((found.design.c - 2.5).abs() < 1e-9);
//! # Ok(())
//! # }
//! ```

mod cycle;
mod design;
pub mod exact;
mod found;
mod problem;
mod search;
mod spec;
mod starts;
mod subject;

pub use design::{Synthesis, Synthesized, Timing};
pub use search::{Budget, Found, Optimum, Progress, Search};
pub use spec::{
    Amount, Grashof, Inequality, Region, SearchSpec, Spec, Task, TimingSpec, TransmissionSpec,
};
#[cfg(feature = "runtime")]
pub(crate) use subject::sealed::Sealed;
pub use subject::{DriverOf, Shape, Solved, Subject};
