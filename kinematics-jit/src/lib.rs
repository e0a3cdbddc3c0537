//! Native code, at run time, for the expression graph of a mechanism
//! definition (`kinematics_compiler::Compiled`): each stage of the
//! analysis becomes one machine-code function, compiled by Cranelift.
//!
//! A stage is a list of roots of the graph. Its function reads the leaves
//! (parameters p, coordinates q, rates q', accelerations q'') from four
//! arrays, and the cosine and sine of each coordinate from a fifth (the
//! caller computes them once per pose, [`Program::trig`], where the
//! stages would each call sin and cos of the same coordinates: as the
//! macro's code computes each coordinate's sine and cosine once). It
//! evaluates every node the roots depend on once, in the graph's order (a
//! topological order, shared subexpressions computed once, as the macro's
//! straight-line Rust computes them), and writes the roots to an output
//! array. Arithmetic is IEEE double precision, operation for operation as
//! written in the graph (no fused multiply-add, no reassociation); sin,
//! cos, tan, asin, acos, exp, ln and atan2 are the standard library's (the
//! platform's libm), √ and |x| the processor's instructions, xⁿ the binary
//! powering of the standard library's `powi`.
//!
//! ```
//! use kinematics_jit::{Inputs, Program};
//! let model = kinematics_compiler::compile_str(
//!     "pub struct SliderCrank {
//!          params   { a, b }
//!          drivers  { phi }
//!          unknowns { th, x }
//!          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
//!      }",
//! )?;
//! let program = Program::for_model(&model)?;
//! // Φ and Φ_u at a closed pose: a = 1, b = 2, φ = 0, θ = π, x = −1.
//! let q = [0.0, std::f64::consts::PI, -1.0];
//! // cos and sin of every coordinate the stages read them of.
//! let mut trig = [0.0; 6];
//! program.trig(&q, &mut trig, 0);
//! // The parameters, then the characteristic length (unused here).
//! let inputs = Inputs {
//!     params: &[1.0, 2.0, 3.0],
//!     q: &q,
//!     qd: &[0.0; 3],
//!     qdd: &[0.0; 3],
//!     trig: &trig,
//! };
//! let mut out = vec![0.0; program.outputs(Program::NEWTON)];
//! program.eval(Program::NEWTON, &inputs, &mut out)?;
//! let (phi, jac) = out.split_at(2);
//! assert!(phi.iter().all(|r| r.abs() < 1e-15));
//! // Φ_u = [[−b sin θ, −1], [b cos θ, 0]].
//! assert!((jac[1] + 1.0).abs() < 1e-15 && (jac[2] + 2.0).abs() < 1e-15);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt;
use std::mem::ManuallyDrop;

use cranelift_codegen::ir::{types, AbiParam, InstBuilder, MemFlags, UserFuncName};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Linkage, Module};
use kinematics_compiler::ir::{Graph, Id, Leaf};
use kinematics_compiler::Compiled;

mod fused;
mod lanes;
mod lower;

pub use fused::{
    Callable, Compare, Function, Fused, Helper, Inst, Layout, Op, Port, Series, SmallBlock,
    SolveBlock, SolveRow, Val, HELPER_PANICKED, PORTS,
};
use lower::{Imports, Lower, Sources};

/// The machine-code signature of every stage: (p, q, q', q'', out, the
/// cosines and sines of q).
type Entry =
    unsafe extern "C" fn(*const f64, *const f64, *const f64, *const f64, *mut f64, *const f64);

/// Why a program could not be built.
#[derive(Debug)]
pub enum JitError {
    /// Cranelift has no back end for this host, or refused a setting.
    Host(String),
    /// Cranelift could not compile or link a stage.
    Codegen(String),
    /// A leaf of the graph indexes past the declared parameters or
    /// coordinates (a graph that does not belong to the lengths given),
    /// or is the time where the code has none (a fused step).
    Leaf(Leaf),
}

impl fmt::Display for JitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Host(m) => write!(f, "no native code generator for this machine: {m}"),
            Self::Codegen(m) => write!(f, "native code generation failed: {m}"),
            Self::Leaf(l) => write!(
                f,
                "the expression graph reads {l:?}, beyond the model's parameters or \
                 coordinates, or a time where there is none"
            ),
        }
    }
}

impl std::error::Error for JitError {}

/// Arrays handed to a stage whose lengths are not the model's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LengthMismatch {
    /// Which array: "params", "q", "qd", "qdd", "trig" or "out".
    pub array: &'static str,
    /// The length the program needs.
    pub expected: usize,
    /// The length given.
    pub found: usize,
}

impl fmt::Display for LengthMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`{}` has {} values; this model needs {}",
            self.array, self.found, self.expected
        )
    }
}

impl std::error::Error for LengthMismatch {}

/// The leaves a stage reads: parameters in declaration order, and the
/// coordinates, rates and accelerations (drivers first, then unknowns).
#[derive(Clone, Copy, Debug)]
pub struct Inputs<'a> {
    /// p; then the time t where the program reads it
    /// ([`Program::reads_time`]).
    pub params: &'a [f64],
    /// q.
    pub q: &'a [f64],
    /// q'.
    pub qd: &'a [f64],
    /// q''.
    pub qdd: &'a [f64],
    /// cos q_j and sin q_j at entries 2j and 2j + 1, for every coordinate
    /// j of [`Program::trig_coordinates`] (the others are not read), as
    /// [`Program::trig`] writes them. In lanes ([`Program::lanes`]) every
    /// array holds both designs interleaved: value j of design l at
    /// 2j + l, cos q_j and sin q_j of design l at 4j + l and 4j + 2 + l.
    pub trig: &'a [f64],
}

/// One compiled stage.
struct Stage {
    entry: Entry,
    outputs: usize,
    /// Whether it reads a coordinate (or its cosine or sine).
    reads_q: bool,
    /// Whether it reads the time.
    reads_time: bool,
}

/// Machine code for the stages of one expression graph. The code lives as
/// long as the program.
pub struct Program {
    module: ManuallyDrop<JITModule>,
    stages: Vec<Stage>,
    /// The values of [`Inputs::params`]: the parameters, and the time
    /// after them where a stage reads it.
    params: usize,
    /// A stage reads the time.
    time: bool,
    coords: usize,
    /// The coordinates whose cosine and sine some stage reads, ascending.
    trig: Vec<usize>,
    /// The code is VEX-encoded ([`clear_upper`] before a call).
    vex: bool,
    /// The designs evaluated by one call: 1, or 2 in vector lanes
    /// ([`Program::new_in_lanes`]).
    lanes: usize,
}

impl fmt::Debug for Program {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Program")
            .field(
                "stages",
                &self.stages.iter().map(|s| s.outputs).collect::<Vec<_>>(),
            )
            .field("params", &self.params)
            .field("coords", &self.coords)
            .field("trig", &self.trig)
            .field("lanes", &self.lanes)
            .finish_non_exhaustive()
    }
}

/// The functions of one argument the generated code calls, and atan2, as
/// the standard library computes them.
mod calls {
    pub extern "C" fn sin(x: f64) -> f64 {
        x.sin()
    }
    pub extern "C" fn cos(x: f64) -> f64 {
        x.cos()
    }
    pub extern "C" fn tan(x: f64) -> f64 {
        x.tan()
    }
    pub extern "C" fn asin(x: f64) -> f64 {
        x.asin()
    }
    pub extern "C" fn acos(x: f64) -> f64 {
        x.acos()
    }
    pub extern "C" fn exp(x: f64) -> f64 {
        x.exp()
    }
    pub extern "C" fn ln(x: f64) -> f64 {
        x.ln()
    }
    pub extern "C" fn atan2(y: f64, x: f64) -> f64 {
        y.atan2(x)
    }
}

/// The symbol each called function is registered under, with its address
/// and arity.
fn symbols() -> [(&'static str, *const u8, usize); 8] {
    [
        ("kinematics_sin", calls::sin as *const u8, 1),
        ("kinematics_cos", calls::cos as *const u8, 1),
        ("kinematics_tan", calls::tan as *const u8, 1),
        ("kinematics_asin", calls::asin as *const u8, 1),
        ("kinematics_acos", calls::acos as *const u8, 1),
        ("kinematics_exp", calls::exp as *const u8, 1),
        ("kinematics_ln", calls::ln as *const u8, 1),
        ("kinematics_atan2", calls::atan2 as *const u8, 2),
    ]
}

/// A JIT module for the host, with the called functions and `extra`
/// symbols registered.
fn new_module(extra: &[(&'static str, *const u8)]) -> Result<JITModule, JitError> {
    let mut flags = settings::builder();
    // Cranelift's verifier checks its own output: kept in debug builds
    // (the tests), off in release builds, where it took a tenth of the
    // time of compiling a large model.
    let verifier = if cfg!(debug_assertions) {
        "true"
    } else {
        "false"
    };
    for (name, value) in [
        ("opt_level", "speed"),
        ("use_colocated_libcalls", "false"),
        ("is_pic", "false"),
        ("enable_verifier", verifier),
    ] {
        flags
            .set(name, value)
            .map_err(|e| JitError::Host(e.to_string()))?;
    }
    let isa = cranelift_native::builder()
        .map_err(|e| JitError::Host(e.to_string()))?
        .finish(settings::Flags::new(flags))
        .map_err(|e| JitError::Host(e.to_string()))?;
    let mut builder = JITBuilder::with_isa(isa, default_libcall_names());
    for (name, address, _) in symbols() {
        builder.symbol(name, address);
    }
    for &(name, address) in extra {
        builder.symbol(name, address);
    }
    Ok(JITModule::new(builder))
}

/// Whether `module` compiles VEX-encoded code: an x86-64 host with AVX,
/// which Cranelift then uses for the arithmetic.
fn vex_encoded(module: &JITModule) -> bool {
    cfg!(target_arch = "x86_64")
        && module
            .isa()
            .isa_flags()
            .iter()
            .any(|flag| flag.name == "has_avx" && flag.as_bool() == Some(true))
}

/// Marks the upper halves of the vector registers unused (`vzeroupper`)
/// before VEX-encoded code runs, where `vex` says it is.
///
/// Cranelift encodes the arithmetic with VEX on a host with AVX but moves
/// and spills some registers with legacy SSE encodings. Entered while the
/// upper halves are in use (after 256-bit code in the same thread that did
/// not end with `vzeroupper`), each of those pays the processor's
/// transition between the two: the RSSR's fused step ran 26 times slower
/// on an Intel Xeon. Clearing them first costs about a cycle.
#[inline(always)]
#[allow(unsafe_code)]
fn clear_upper(vex: bool) {
    #[cfg(target_arch = "x86_64")]
    if vex {
        // SAFETY: `vex` holds only on a host with AVX (as Cranelift found
        // it), which has the instruction; it changes only the upper
        // halves of ymm0–ymm15, all of them declared clobbered.
        unsafe {
            core::arch::asm!(
                "vzeroupper",
                out("xmm0") _, out("xmm1") _, out("xmm2") _, out("xmm3") _,
                out("xmm4") _, out("xmm5") _, out("xmm6") _, out("xmm7") _,
                out("xmm8") _, out("xmm9") _, out("xmm10") _, out("xmm11") _,
                out("xmm12") _, out("xmm13") _, out("xmm14") _, out("xmm15") _,
                options(nomem, nostack, preserves_flags),
            );
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = vex;
}

/// The called functions of [`symbols`], declared once for `module`.
fn declare_imports(module: &mut JITModule) -> Result<Vec<(&'static str, FuncId)>, JitError> {
    let mut imports = Vec::new();
    for (name, _, arity) in symbols() {
        let mut sig = module.make_signature();
        for _ in 0..arity {
            sig.params.push(AbiParam::new(types::F64));
        }
        sig.returns.push(AbiParam::new(types::F64));
        let id = module
            .declare_function(name, Linkage::Import, &sig)
            .map_err(|e| JitError::Codegen(e.to_string()))?;
        imports.push((name, id));
    }
    Ok(imports)
}

/// The roots of [`Program::OUTPUTS`]: each point's position, velocity
/// and acceleration, then each frame's rotation (row by row), ω, α and
/// its origin's position, velocity and acceleration.
#[must_use]
pub fn output_roots(model: &Compiled) -> Vec<Id> {
    let mut outputs: Vec<Id> = Vec::new();
    for p in model.points() {
        outputs.extend(p.position.iter().chain(p.velocity).chain(p.acceleration));
    }
    for f in model.frames() {
        let r = f.roots;
        outputs.extend(r.rotation.iter().flatten());
        outputs.extend(r.omega.iter().chain(&r.alpha));
        outputs.extend(r.origin.iter().flatten());
    }
    outputs
}

impl Program {
    /// The stage of [`Program::for_model`] that gives Φ (one value per
    /// equation) then Φ_u row by row.
    pub const NEWTON: usize = 0;
    /// The stage that gives −Φ_d d', the velocity equations' right-hand side.
    pub const VELOCITY: usize = 1;
    /// The stage that gives −Φ_d d'' − γ, the acceleration equations'
    /// right-hand side.
    pub const ACCELERATION: usize = 2;
    /// The stage that gives, for each point in declaration order, its
    /// position, velocity and acceleration (2 or 3 components each), then
    /// for each frame its rotation (row by row), ω, α, and its origin's
    /// position, velocity and acceleration.
    pub const OUTPUTS: usize = 3;
    /// The stage that gives each equation's term scale S_i
    /// (`Compiled::term_scales`).
    pub const SCALES: usize = 4;
    /// The stage that gives each equation's term scale with the unknown
    /// lengths counted as the characteristic length L
    /// (`Compiled::full_term_scales`), read as one more parameter after
    /// the model's.
    pub const FULL_SCALES: usize = 5;

    /// The stage that gives the partial derivatives behind the design
    /// sensitivities (`Partials::roots`, in its order; no outputs for a
    /// definition without a `sensitivities` section).
    pub const SENSITIVITIES: usize = 6;

    /// The stage of diagonal block `i`'s closed-form coefficients
    /// (`Block::coefficients` of [`Program::for_model`]'s model; no
    /// outputs for a block solved by Newton–Raphson).
    #[must_use]
    pub const fn block(i: usize) -> usize {
        7 + i
    }

    /// The stages of a compiled model ([`Program::NEWTON`],
    /// [`Program::VELOCITY`], [`Program::ACCELERATION`],
    /// [`Program::OUTPUTS`], [`Program::SCALES`],
    /// [`Program::FULL_SCALES`], [`Program::SENSITIVITIES`], then
    /// [`Program::block`] of each diagonal block), reading one parameter more than the model declares: the
    /// characteristic length L, last.
    ///
    /// # Errors
    /// As [`Program::new`].
    pub fn for_model(model: &Compiled) -> Result<Self, JitError> {
        Self::for_model_with(model, false)
    }

    /// [`Program::for_model`], in lanes or not.
    fn for_model_with(model: &Compiled, lanes: bool) -> Result<Self, JitError> {
        let newton: Vec<Id> = model
            .residuals()
            .iter()
            .map(|(id, _)| *id)
            .chain(model.jacobian().iter().flatten().copied())
            .collect();
        let outputs = output_roots(model);
        let blocks = model.blocks();
        let partials = model.sensitivities().map(|s| s.roots()).unwrap_or_default();
        let mut stages: Vec<&[Id]> = vec![
            &newton,
            model.velocity_rhs(),
            model.acceleration_rhs(),
            &outputs,
            model.term_scales(),
            model.full_term_scales(),
            &partials,
        ];
        let coefficients: Vec<Vec<Id>> = blocks
            .iter()
            .map(kinematics_compiler::Block::coefficients)
            .collect();
        stages.extend(coefficients.iter().map(Vec::as_slice));
        Self::build(
            model.graph(),
            model.parameters().len() + 1,
            model.coordinates().len(),
            &stages,
            lanes,
        )
    }

    /// Compiles one function per stage of `graph`, each writing its roots
    /// in order; the graph's leaves index `params` parameters and `coords`
    /// coordinates. Where a stage reads the time ([`Leaf::Time`], in the
    /// values of loads), it is read after the parameters: the program then
    /// takes `params + 1` values in [`Inputs::params`], the time last
    /// ([`Program::reads_time`]).
    ///
    /// # Errors
    /// [`JitError::Host`] where Cranelift has no back end for the machine,
    /// [`JitError::Codegen`] if it fails, [`JitError::Leaf`] for a leaf
    /// beyond the lengths given.
    pub fn new(
        graph: &Graph,
        params: usize,
        coords: usize,
        stages: &[&[Id]],
    ) -> Result<Self, JitError> {
        Self::build(graph, params, coords, stages, false)
    }

    /// [`Program::new`], in lanes or not.
    fn build(
        graph: &Graph,
        params: usize,
        coords: usize,
        stages: &[&[Id]],
        lanes: bool,
    ) -> Result<Self, JitError> {
        let mut module = new_module(&[])?;
        let codegen = |e: &dyn fmt::Display| JitError::Codegen(e.to_string());
        let imports = declare_imports(&mut module)?;
        let pointer = module.target_config().pointer_type();
        let mut sig = module.make_signature();
        for _ in 0..6 {
            sig.params.push(AbiParam::new(pointer));
        }
        let mut time = false;
        let mut trig = std::collections::BTreeSet::new();
        let mut ids = Vec::with_capacity(stages.len());
        let mut ctx = module.make_context();
        let mut fcx = FunctionBuilderContext::new();
        for (k, roots) in stages.iter().enumerate() {
            let id = module
                .declare_function(&format!("stage_{k}"), Linkage::Local, &sig)
                .map_err(|e| codegen(&e))?;
            ctx.func.signature = sig.clone();
            ctx.func.name = UserFuncName::user(0, id.as_u32());
            let mut lower = Lower::new(graph);
            if lanes {
                lower = lower.in_lanes();
            }
            let width = lower.width();
            {
                let mut b = FunctionBuilder::new(&mut ctx.func, &mut fcx);
                let block = b.create_block();
                b.append_block_params_for_function_params(block);
                b.switch_to_block(block);
                let args = b.block_params(block).to_vec();
                let imports = Imports {
                    refs: imports
                        .iter()
                        .map(|(name, fid)| (*name, module.declare_func_in_func(*fid, b.func)))
                        .collect(),
                };
                let sources = Sources {
                    ptr: [args[0], args[1], args[2], args[3], args[5]],
                    base: [0; 5],
                    params,
                    coords,
                    time: Some(params),
                };
                lower.emit(&mut b, &sources, &imports, roots)?;
                let flags = if lanes {
                    MemFlags::new().with_notrap()
                } else {
                    MemFlags::trusted()
                };
                for (k, &root) in roots.iter().enumerate() {
                    let value = lower.value(&mut b, &sources, &imports, root)?;
                    let offset = i32::try_from(k * 8 * width)
                        .map_err(|_| JitError::Codegen("too many outputs".into()))?;
                    b.ins().store(flags, value, args[4], offset);
                }
                b.ins().return_(&[]);
                b.seal_all_blocks();
                b.finalize();
            }
            trig.extend(lower.trig.iter().copied());
            time |= lower.reads_time;
            module
                .define_function(id, &mut ctx)
                .map_err(|e| JitError::Codegen(format!("{e:?}")))?;
            module.clear_context(&mut ctx);
            ids.push((id, roots.len(), lower.reads_q, lower.reads_time));
        }
        module.finalize_definitions().map_err(|e| codegen(&e))?;
        let vex = vex_encoded(&module);
        let stages = ids
            .into_iter()
            .map(|(id, outputs, reads_q, reads_time)| Stage {
                entry: entry(module.get_finalized_function(id)),
                outputs,
                reads_q,
                reads_time,
            })
            .collect();
        Ok(Self {
            module: ManuallyDrop::new(module),
            stages,
            params: params + usize::from(time),
            time,
            coords,
            trig: trig.into_iter().collect(),
            vex,
            lanes: if lanes { 2 } else { 1 },
        })
    }

    /// Whether a stage reads the time ([`Leaf::Time`]): then the last of
    /// [`Inputs::params`] is the time (for every stage).
    #[must_use]
    pub fn reads_time(&self) -> bool {
        self.time
    }

    /// Whether stage `stage` reads the time (false past the last).
    #[must_use]
    pub fn stage_reads_time(&self, stage: usize) -> bool {
        self.stages.get(stage).is_some_and(|s| s.reads_time)
    }

    /// Number of stages.
    #[must_use]
    pub fn stages(&self) -> usize {
        self.stages.len()
    }

    /// Number of values stage `stage` writes (0 for no such stage).
    #[must_use]
    pub fn outputs(&self, stage: usize) -> usize {
        self.stages.get(stage).map_or(0, |s| s.outputs)
    }

    /// Whether stage `stage` reads a coordinate q_j or its cosine or
    /// sine (`false` for no such stage): a stage that reads none gives
    /// the same values at every pose.
    #[must_use]
    pub fn reads_coordinates(&self, stage: usize) -> bool {
        self.stages.get(stage).is_some_and(|s| s.reads_q)
    }

    /// The coordinates whose cosine and sine the stages read from
    /// [`Inputs::trig`], ascending.
    #[must_use]
    pub fn trig_coordinates(&self) -> &[usize] {
        &self.trig
    }

    /// Writes cos q_j and sin q_j at `trig[2j]` and `trig[2j + 1]` for
    /// every coordinate j ≥ `from` of [`Program::trig_coordinates`] (the
    /// standard library's `sin_cos`): the [`Inputs::trig`] of the pose
    /// `q`. With `from` the number of drivers, it updates a pose whose
    /// drivers have not changed. Entries past either array are skipped.
    /// In lanes, both designs' (interleaved as [`Inputs::trig`] says).
    pub fn trig(&self, q: &[f64], trig: &mut [f64], from: usize) {
        self.trig_between(q, trig, from, usize::MAX);
    }

    /// [`Program::trig`] for the coordinates j with `from` ≤ j < `to`
    /// only (the drivers of a pose whose unknowns' cosines and sines come
    /// from elsewhere, say).
    pub fn trig_between(&self, q: &[f64], trig: &mut [f64], from: usize, to: usize) {
        let start = self.trig.partition_point(|&j| j < from);
        let end = self.trig.partition_point(|&j| j < to).max(start);
        // In lanes, value j of lane l is at 2j + l, its cosine at 4j + l
        // and its sine at 4j + 2 + l.
        let w = self.lanes;
        for &j in &self.trig[start..end] {
            for l in 0..w {
                let (x, c, s) = (w * j + l, 2 * w * j + l, 2 * w * j + w + l);
                if let (Some(&x), true) = (q.get(x), s < trig.len()) {
                    let (sin, cos) = x.sin_cos();
                    trig[c] = cos;
                    trig[s] = sin;
                }
            }
        }
    }

    /// The first array of a call whose length is not the program's.
    #[cold]
    fn mismatch(&self, inputs: &Inputs<'_>, outputs: usize, out: usize) -> LengthMismatch {
        let w = self.lanes;
        [
            ("params", w * self.params, inputs.params.len()),
            ("q", w * self.coords, inputs.q.len()),
            ("qd", w * self.coords, inputs.qd.len()),
            ("qdd", w * self.coords, inputs.qdd.len()),
            ("trig", 2 * w * self.coords, inputs.trig.len()),
            ("out", outputs, out),
        ]
        .into_iter()
        .find(|(_, expected, found)| expected != found)
        .map_or(
            LengthMismatch {
                array: "out",
                expected: outputs,
                found: out,
            },
            |(array, expected, found)| LengthMismatch {
                array,
                expected,
                found,
            },
        )
    }

    /// Runs stage `stage` on `inputs`, writing its roots into `out`.
    ///
    /// # Errors
    /// [`LengthMismatch`] for an array whose length is not the model's
    /// (parameters, coordinates, or the stage's outputs); nothing is
    /// evaluated then.
    pub fn eval(
        &self,
        stage: usize,
        inputs: &Inputs<'_>,
        out: &mut [f64],
    ) -> Result<(), LengthMismatch> {
        let w = self.lanes;
        let outputs = w * self.outputs(stage);
        let coords = w * self.coords;
        if inputs.params.len() != w * self.params
            || inputs.q.len() != coords
            || inputs.qd.len() != coords
            || inputs.qdd.len() != coords
            || inputs.trig.len() != 2 * coords
            || out.len() != outputs
        {
            return Err(self.mismatch(inputs, outputs, out.len()));
        }
        let Some(s) = self.stages.get(stage) else {
            return Ok(());
        };
        clear_upper(self.vex);
        call(s.entry, inputs, out);
        Ok(())
    }
}

/// The finalized code of a stage as a function pointer.
#[allow(unsafe_code)]
fn entry(code: *const u8) -> Entry {
    // SAFETY: `code` is the address of a function Cranelift compiled and
    // linked with the signature `sig` built above, six pointer-sized
    // arguments and no result in the host's default calling convention,
    // which is `Entry`'s.
    unsafe { std::mem::transmute::<*const u8, Entry>(code) }
}

/// Calls a stage.
#[allow(unsafe_code)]
fn call(entry: Entry, inputs: &Inputs<'_>, out: &mut [f64]) {
    // SAFETY: the caller checked every array's length against the
    // program's, times its lanes w: the code reads parameters below
    // `w params`, coordinates, rates and accelerations below `w coords`,
    // cosines and sines below `2 w coords` (in lanes as unaligned
    // 16-byte vectors, each within those bounds), and writes exactly
    // `out.len()` values; the module holding the code lives as long as
    // the program, which the caller borrows.
    unsafe {
        entry(
            inputs.params.as_ptr(),
            inputs.q.as_ptr(),
            inputs.qd.as_ptr(),
            inputs.qdd.as_ptr(),
            out.as_mut_ptr(),
            inputs.trig.as_ptr(),
        );
    }
}

// SAFETY (Send): the program owns its module; the module is touched
// only by `Drop`, which frees the code's pages, which any thread may do.
// The stages are plain functions of their arguments.
#[allow(unsafe_code)]
unsafe impl Send for Program {}

// SAFETY (Sync): through `&Program` only the stages are called and the
// lengths read. A stage keeps no state: it reads its five input arrays and
// writes its output array, both borrowed by the caller, and the code's
// pages are not written after `finalize_definitions`. Several threads may
// call the same stage at once.
#[allow(unsafe_code)]
unsafe impl Sync for Program {}

impl Drop for Program {
    #[allow(unsafe_code)]
    fn drop(&mut self) {
        // SAFETY: the function pointers are private to the program and
        // called only through `&self`; none can run or be called after it
        // is dropped. The module is taken once.
        unsafe {
            let module = ManuallyDrop::take(&mut self.module);
            module.free_memory();
        }
    }
}

#[cfg(test)]
mod tests {
    /// The upper halves are cleared exactly where Cranelift emits VEX:
    /// on an x86-64 host with AVX.
    #[test]
    #[allow(clippy::unwrap_used)]
    fn vex_where_the_host_has_avx() {
        let module = super::new_module(&[]).unwrap();
        #[cfg(target_arch = "x86_64")]
        assert_eq!(
            super::vex_encoded(&module),
            std::arch::is_x86_feature_detected!("avx")
        );
        #[cfg(not(target_arch = "x86_64"))]
        assert!(!super::vex_encoded(&module));
    }
}
