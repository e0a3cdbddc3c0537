//! Two designs per call: the stages of a [`Program`] evaluated on two
//! sets of parameters and coordinates at once, each value of the graph a
//! vector of two f64 lanes (SSE2's 128-bit registers, the widest vectors
//! Cranelift's x86-64 back end emits).
//!
//! Every array is interleaved: value j of design l is at entry 2j + l
//! (the parameters, q, q', q''), cosine and sine of coordinate j of design
//! l at 4j + l and 4j + 2 + l, and root k of a stage at 2k + l of its
//! output. Each lane is computed operation for operation as the scalar
//! program computes its design: the same IEEE operations in the same
//! order (vector sums, products, quotients and square roots round each
//! lane as the scalar instructions do), the standard library's functions
//! called lane by lane. So the two designs' results are the scalar
//! program's, bit for bit.

use kinematics_compiler::ir::{Graph, Id};
use kinematics_compiler::Compiled;

use crate::{JitError, Program};

impl Program {
    /// The number of designs one call evaluates: 2 for a program made by
    /// [`Program::new_in_lanes`] or [`Program::for_model_in_lanes`], else 1.
    /// Every array of [`Inputs`](crate::Inputs) and the output of
    /// [`Program::eval`] are that many times as long, interleaved (see
    /// the module's description).
    #[must_use]
    pub fn lanes(&self) -> usize {
        self.lanes
    }

    /// [`Program::new`] on two designs per call, in vector lanes.
    ///
    /// ```
    /// use kinematics_jit::{Inputs, Program};
    /// let model = kinematics_compiler::compile_str(
    ///     "pub struct SliderCrank {
    ///          params   { a, b }
    ///          drivers  { phi }
    ///          unknowns { th, x }
    ///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
    ///      }",
    /// )?;
    /// let one = Program::for_model(&model)?;
    /// let two = Program::for_model_in_lanes(&model)?;
    /// assert_eq!((one.lanes(), two.lanes()), (1, 2));
    /// // Design 0: a = 1, b = 2; design 1: a = 0.5, b = 3 (then each
    /// // one's characteristic length), at φ = 0.3 and 1.2.
    /// let params = [1.0, 0.5, 2.0, 3.0, 3.0, 3.5];
    /// let q = [0.3, 1.2, 2.9, 3.0, -1.0, -2.5];
    /// let mut trig = [0.0; 12];
    /// two.trig(&q, &mut trig, 0);
    /// let rates = [1.0, 2.0, 0.0, 0.0, 0.0, 0.0];
    /// let inputs = Inputs { params: &params, q: &q, qd: &rates, qdd: &[0.0; 6], trig: &trig };
    /// let mut both = vec![0.0; 2 * two.outputs(Program::VELOCITY)];
    /// two.eval(Program::VELOCITY, &inputs, &mut both)?;
    /// // Each lane is the scalar program's result for its design.
    /// for lane in 0..2 {
    ///     let pick = |v: &[f64]| v.iter().skip(lane).step_by(2).copied().collect::<Vec<_>>();
    ///     let (p, q, qd, t) = (pick(&params), pick(&q), pick(&rates), pick(&trig));
    ///     let inputs = Inputs { params: &p, q: &q, qd: &qd, qdd: &[0.0; 3], trig: &t };
    ///     let mut alone = vec![0.0; one.outputs(Program::VELOCITY)];
    ///     one.eval(Program::VELOCITY, &inputs, &mut alone)?;
    ///     assert_eq!(alone, pick(&both));
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`Program::new`].
    pub fn new_in_lanes(
        graph: &Graph,
        params: usize,
        coords: usize,
        stages: &[&[Id]],
    ) -> Result<Self, JitError> {
        Self::build(graph, params, coords, stages, true)
    }

    /// [`Program::for_model`] on two designs per call, in vector lanes.
    ///
    /// # Errors
    /// As [`Program::new`].
    pub fn for_model_in_lanes(model: &Compiled) -> Result<Self, JitError> {
        Self::for_model_with(model, true)
    }
}
