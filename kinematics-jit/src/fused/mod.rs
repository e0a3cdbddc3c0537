//! One machine-code function for a whole sequence of evaluations and
//! calls: a step of a run-time model as one straight line, where the
//! stages of [`crate::Program`] are separate calls with their own arrays.
//!
//! The function works in one buffer of f64 values, `f`: it reads the
//! leaves there (at the offsets of a [`Layout`]), writes the roots of each
//! [`Op::Store`] there, and hands the buffer to a helper written in Rust
//! for what is not an expression of the graph (a closed form's branches,
//! a factorisation): [`Op::Call`]. It knows expressions, not mechanisms:
//! a closed form of the engine reaches it as plain instructions with a
//! guard and a fall-back to the helper ([`Op::Guarded`]). Each node of the graph is evaluated
//! once, at its first use, and kept for every later one, so an op after a
//! call must not read a value the call changes through a node evaluated
//! before it (the ops of a step read each unknown only after the call
//! that solves it).

use std::ffi::c_void;
use std::fmt;
use std::marker::PhantomData;
use std::mem::ManuallyDrop;

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{types, AbiParam, BlockArg, InstBuilder, MemFlags, UserFuncName};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::JITModule;
use cranelift_module::{Linkage, Module};
use kinematics_compiler::ir::{Graph, Id};

use crate::lower::{Imports, Lower, SignBits, Sources};
use crate::{clear_upper, declare_imports, new_module, vex_encoded, JitError};

mod blocks;
mod callable;
mod emit;
mod lanes;
mod ops;

pub use callable::Callable;
use callable::{entry, trampoline, Entry};
use emit::{call_helper, guarded, not_finite, offset, port_slot, rotated, seed_at, Guard, Memory};
pub use ops::{
    Compare, Helper, Inst, Layout, Op, Port, Series, SmallBlock, SolveBlock, SolveRow, Val,
    HELPER_PANICKED, PORTS,
};

/// One function of a [`Fused`] set: its ops, and the nodes it reads
/// from the buffer (at the index given, past the parameters' first:
/// `layout.params + index`) instead of computing them.
#[derive(Clone, Copy, Debug)]
pub struct Function<'a> {
    /// The ops, in order.
    pub ops: &'a [Op],
    /// The nodes read, not computed.
    pub preset: &'a [(Id, usize)],
}

/// Fused functions sharing one buffer layout, compiled together:
/// [`Fused::new`] compiles them, [`Fused::call`] runs one.
pub struct Fused {
    module: ManuallyDrop<JITModule>,
    entries: Vec<Entry>,
    /// For each function, how many values of each port (by slot) it uses.
    needs: Vec<[usize; 2 * PORTS]>,
    len: usize,
    /// The code is VEX-encoded (`vzeroupper` before a call).
    vex: bool,
}

impl fmt::Debug for Fused {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Fused")
            .field("len", &self.len)
            .finish_non_exhaustive()
    }
}

impl Fused {
    /// Compiles each of `functions` over `graph` (whose leaves index
    /// `params` parameters and `coords` coordinates, read at `layout`);
    /// each [`Op::Call`] calls the [`Helper`] given to [`Fused::call`].
    ///
    /// # Errors
    /// As [`crate::Program::new`]; [`JitError::Codegen`] also for an
    /// offset at or past `layout.len`.
    pub fn new(
        graph: &Graph,
        params: usize,
        coords: usize,
        layout: Layout,
        functions: &[Function<'_>],
    ) -> Result<Self, JitError> {
        Self::compile(graph, (params, coords), layout, functions, None)
    }

    /// [`Fused::new`], or [`Fused::new_in_lanes`] with the status `lanes`
    /// where a design leaves the common path.
    fn compile(
        graph: &Graph,
        (params, coords): (usize, usize),
        layout: Layout,
        functions: &[Function<'_>],
        lanes: Option<i64>,
    ) -> Result<Self, JitError> {
        // Bytes per value of the buffer: one f64, or one for each design.
        let width = if lanes.is_some() { 16 } else { 8 };
        const HELPER: &str = "kinematics_fused_helper";
        let mut module = new_module(&[(HELPER, trampoline as *const u8)])?;
        let codegen = |e: &dyn fmt::Display| JitError::Codegen(e.to_string());
        let imports = declare_imports(&mut module)?;
        let pointer = module.target_config().pointer_type();
        let mut hsig = module.make_signature();
        hsig.params.push(AbiParam::new(pointer));
        hsig.params.push(AbiParam::new(pointer));
        hsig.params.push(AbiParam::new(types::I64));
        hsig.returns.push(AbiParam::new(types::I64));
        let helper_id = module
            .declare_function(HELPER, Linkage::Import, &hsig)
            .map_err(|e| codegen(&e))?;
        let mut sig = module.make_signature();
        sig.params.push(AbiParam::new(pointer));
        sig.params.push(AbiParam::new(pointer));
        sig.params.push(AbiParam::new(pointer));
        sig.returns.push(AbiParam::new(types::I64));
        let mut ctx = module.make_context();
        let mut fcx = FunctionBuilderContext::new();
        let mut ids = Vec::with_capacity(functions.len());
        let mut needs = Vec::with_capacity(functions.len());
        for (k, function) in functions.iter().enumerate() {
            let mut need = [0; 2 * PORTS];
            let (ops, preset) = (function.ops, function.preset);
            let id = module
                .declare_function(&format!("fused_{k}"), Linkage::Local, &sig)
                .map_err(|e| codegen(&e))?;
            ctx.func.signature = sig.clone();
            ctx.func.name = UserFuncName::user(0, id.as_u32());
            let within = |at: usize| {
                if at < layout.len {
                    i32::try_from(at * width)
                        .map_err(|_| JitError::Codegen("buffer too long".into()))
                } else {
                    Err(JitError::Codegen(format!(
                        "offset {at} past the buffer of {}",
                        layout.len
                    )))
                }
            };
            {
                let mut b = FunctionBuilder::new(&mut ctx.func, &mut fcx);
                let entry = b.create_block();
                b.append_block_params_for_function_params(entry);
                let exit = b.create_block();
                b.append_block_param(exit, types::I64);
                b.switch_to_block(entry);
                let args = b.block_params(entry).to_vec();
                let (fp, cp, pp) = (args[0], args[1], args[2]);
                let imports = Imports {
                    refs: imports
                        .iter()
                        .map(|(name, fid)| (*name, module.declare_func_in_func(*fid, b.func)))
                        .collect(),
                };
                let helper_ref = module.declare_func_in_func(helper_id, b.func);
                let sources = Sources {
                    ptr: [fp; 5],
                    base: [layout.params, layout.q, layout.qd, layout.qdd, layout.trig],
                    params,
                    coords,
                    time: None,
                };
                // Every leaf offset must lie in the buffer.
                for (base, n) in [
                    (layout.params, params),
                    (layout.q, coords),
                    (layout.qd, coords),
                    (layout.qdd, coords),
                    (layout.trig, 2 * coords),
                ] {
                    if n > 0 {
                        within(base + n - 1)?;
                    }
                }
                let flags = MemFlags::trusted();
                for &(_, at) in preset {
                    within(layout.params + at)?;
                }
                let mut lower = Lower::new(graph).with_preset(preset);
                if let Some(left) = lanes {
                    let mut lower = lower.in_lanes();
                    let mut cx = lanes::Emit {
                        lower: &mut lower,
                        sources: &sources,
                        imports: &imports,
                        graph,
                        layout: &layout,
                        coords,
                        exit,
                        left,
                    };
                    let mut memory = Memory::in_lanes(fp, &within);
                    for op in ops {
                        cx.op(&mut b, &mut memory, op, pp, &mut need)?;
                    }
                } else {
                    let bail = |b: &mut FunctionBuilder<'_>, failed, status| {
                        let next = b.create_block();
                        b.ins()
                            .brif(failed, exit, &[BlockArg::Value(status)], next, &[]);
                        b.switch_to_block(next);
                    };
                    // The buffer, with the values the code holds in registers.
                    let mut memory = Memory::new(fp, &within);
                    // The values of consecutive imports with the same status,
                    // checked together after the last of them (one branch).
                    let mut imported = Vec::new();
                    for (k, op) in ops.iter().enumerate() {
                        match op {
                            Op::Store { roots, at, finite } => {
                                if roots.len() != at.len() {
                                    return Err(JitError::Codegen(
                                        "a store's roots and offsets differ in number".into(),
                                    ));
                                }
                                lower.emit(&mut b, &sources, &imports, roots)?;
                                let mut values = Vec::with_capacity(roots.len());
                                for (&root, &at) in roots.iter().zip(at) {
                                    let v = lower.value(&mut b, &sources, &imports, root)?;
                                    memory.store(&mut b, at, v)?;
                                    values.push(v);
                                }
                                if let Some(status) = *finite {
                                    if let Some(failed) = not_finite(&mut b, false, &values) {
                                        let status = b.ins().iconst(types::I64, status);
                                        bail(&mut b, failed, status);
                                    }
                                }
                            }
                            Op::Call(arg) => {
                                let arg = b
                                    .ins()
                                    .iconst(types::I64, i64::from_ne_bytes(arg.to_ne_bytes()));
                                let inst = b.ins().call(helper_ref, &[fp, cp, arg]);
                                let status = b.inst_results(inst)[0];
                                let failed = b.ins().icmp_imm(IntCC::NotEqual, status, 0);
                                bail(&mut b, failed, status);
                                memory.forget();
                            }
                            Op::MaxScaled { roots, scales, at } => {
                                lower.emit(&mut b, &sources, &imports, roots)?;
                                // max |vᵢ sᵢ|, NaN when one is: the absolute
                                // values compared as their bit patterns, which
                                // order the non-negative numbers as their values
                                // do and put a NaN (its sign bit cleared) above
                                // them all. An integer maximum is a conditional
                                // move, where a float comparison would be a
                                // branch, mispredicted as often as a residual
                                // at rounding level is 0 or not.
                                let mut m = b.ins().iconst(types::I64, 0);
                                for (i, &root) in roots.iter().enumerate() {
                                    let v = lower.value(&mut b, &sources, &imports, root)?;
                                    let s = memory.load(&mut b, scales + i)?;
                                    let p = b.ins().fmul(v, s);
                                    let r = b.abs(p);
                                    let bits = b.ins().bitcast(types::I64, MemFlags::new(), r);
                                    m = b.ins().umax(m, bits);
                                }
                                let m = b.ins().bitcast(types::F64, MemFlags::new(), m);
                                memory.store(&mut b, *at, m)?;
                            }
                            Op::Solve {
                                rhs,
                                blocks,
                                to,
                                finite,
                            } => blocks::solve(
                                &mut b,
                                false,
                                (&mut lower, &sources, &imports),
                                &mut memory,
                                (rhs, blocks, *to, *finite),
                                &mut |b, failed, status| {
                                    let status = b.ins().iconst(types::I64, status);
                                    bail(b, failed, status);
                                },
                            )?,
                            Op::CarriedTrig {
                                value,
                                carried,
                                to,
                                fresh,
                                series: rotation,
                            } => {
                                let x = memory.load(&mut b, *value)?;
                                let c0 = memory.load(&mut b, *carried)?;
                                let s0 = memory.load(&mut b, carried + 1)?;
                                let x0 = memory.load(&mut b, carried + 2)?;
                                let d = b.ins().fsub(x, x0);
                                let ad = b.abs(d);
                                let limit = b.ins().f64const(rotation.step);
                                let near = b.ins().fcmp(FloatCC::LessThanOrEqual, ad, limit);
                                let (series, computed, join) =
                                    (b.create_block(), b.create_block(), b.create_block());
                                b.ins().brif(near, series, &[], computed, &[]);
                                b.switch_to_block(series);
                                let (c, sn) = rotated(&mut b, false, d, (c0, s0), rotation);
                                for (v, at) in [
                                    (c, *to),
                                    (sn, to + 1),
                                    (c, *carried),
                                    (sn, carried + 1),
                                    (x, carried + 2),
                                ] {
                                    memory.write(&mut b, at, v)?;
                                }
                                // The cosine and sine go on in registers (from
                                // the helper, as it wrote them).
                                let cos = b.append_block_param(join, types::F64);
                                let sin = b.append_block_param(join, types::F64);
                                b.ins()
                                    .jump(join, &[BlockArg::Value(c), BlockArg::Value(sn)]);
                                b.switch_to_block(computed);
                                let helped = b.create_block();
                                call_helper(&mut b, (fp, cp, helper_ref, exit), *fresh, helped);
                                memory.forget();
                                let c = memory.load(&mut b, *to)?;
                                let sn = memory.load(&mut b, to + 1)?;
                                b.ins()
                                    .jump(join, &[BlockArg::Value(c), BlockArg::Value(sn)]);
                                b.switch_to_block(join);
                                // Past the join: the cosine and sine as either
                                // path left them, the rest read afresh.
                                memory.forget();
                                memory.holds(*to, cos);
                                memory.holds(to + 1, sin);
                                for (at, v) in [(*value, x), (*to, cos), (to + 1, sin)] {
                                    seed_at(&mut lower, graph, &layout, coords, at, v);
                                }
                            }
                            Op::Guarded {
                                code,
                                ok,
                                fast,
                                slow,
                                helper,
                                keep,
                            } => {
                                let guard = Guard {
                                    code,
                                    ok: *ok,
                                    fast,
                                    slow,
                                    helper: *helper,
                                    keep,
                                };
                                guarded(
                                    &mut b,
                                    (&mut lower, &sources, &imports),
                                    (graph, &layout),
                                    (fp, cp, helper_ref, exit),
                                    &mut memory,
                                    &guard,
                                )?;
                            }
                            Op::AtMost { at, bound, status } => {
                                let x = memory.load(&mut b, *at)?;
                                let y = memory.load(&mut b, *bound)?;
                                let within_bound = b.ins().fcmp(FloatCC::LessThanOrEqual, x, y);
                                let failed = b.ins().icmp_imm(IntCC::Equal, within_bound, 0);
                                let status = b.ins().iconst(types::I64, *status);
                                bail(&mut b, failed, status);
                            }
                            Op::FactorSmall { .. } => {
                                let (blocks, at) = blocks::Factoring::of(op).ok_or_else(|| {
                                    JitError::Codegen("a factorisation's fields".into())
                                })?;
                                blocks::factor_small(
                                    &mut b,
                                    false,
                                    (&mut lower, &sources, &imports),
                                    &mut memory,
                                    (blocks, &at),
                                    &mut |b, failed, status| {
                                        let status = b.ins().iconst(types::I64, status);
                                        bail(b, failed, status);
                                    },
                                )?;
                            }
                            Op::Import {
                                from,
                                to,
                                len,
                                finite,
                            } => {
                                if *len > 0 {
                                    let slot = port_slot(*from, &mut need, *len)?;
                                    let base = b.ins().load(pointer, flags, pp, slot);
                                    for i in 0..*len {
                                        let v = b.ins().load(types::F64, flags, base, offset(i)?);
                                        memory.store(&mut b, to + i, v)?;
                                        if finite.is_some() {
                                            imported.push(v);
                                        }
                                    }
                                }
                                let checked_with_next = matches!(
                                    ops.get(k + 1),
                                    Some(Op::Import { finite: next, .. }) if next == finite
                                );
                                if let (Some(status), false) = (*finite, checked_with_next) {
                                    if let Some(failed) = not_finite(&mut b, false, &imported) {
                                        let status = b.ins().iconst(types::I64, status);
                                        bail(&mut b, failed, status);
                                    }
                                    imported.clear();
                                }
                            }
                            Op::Export { to, from, len } => {
                                if *len == 0 {
                                    continue;
                                }
                                let slot = port_slot(Port::Output(*to), &mut need, *len)?;
                                let base = b.ins().load(pointer, flags, pp, slot);
                                for i in 0..*len {
                                    let v = memory.load(&mut b, from + i)?;
                                    b.ins().store(flags, v, base, offset(i)?);
                                }
                            }
                            Op::Finite { from, len, status } => {
                                if *len == 0 {
                                    continue;
                                }
                                let mut values = Vec::with_capacity(*len);
                                for i in 0..*len {
                                    values.push(memory.load(&mut b, from + i)?);
                                }
                                if let Some(failed) = not_finite(&mut b, false, &values) {
                                    let status = b.ins().iconst(types::I64, *status);
                                    bail(&mut b, failed, status);
                                }
                            }
                        }
                    }
                }
                let ok = b.ins().iconst(types::I64, 0);
                b.ins().jump(exit, &[BlockArg::Value(ok)]);
                b.switch_to_block(exit);
                let status = b.block_params(exit)[0];
                b.ins().return_(&[status]);
                b.seal_all_blocks();
                b.finalize();
            }
            module
                .define_function(id, &mut ctx)
                .map_err(|e| JitError::Codegen(format!("{e:?}")))?;
            module.clear_context(&mut ctx);
            ids.push(id);
            needs.push(need);
        }
        module.finalize_definitions().map_err(|e| codegen(&e))?;
        let entries = ids
            .into_iter()
            .map(|id| entry(module.get_finalized_function(id)))
            .collect();
        Ok(Fused {
            vex: vex_encoded(&module),
            module: ManuallyDrop::new(module),
            entries,
            needs,
            len: layout.len * width / 8,
        })
    }

    /// The number of values its buffer holds.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether its buffer holds no value.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Runs function `which` (in the order given to [`Fused::new`]) on
    /// the buffer `f`, calling `helper` for each [`Op::Call`]: its status
    /// (0 when every op ran, else the first nonzero status of a call or
    /// check; [`HELPER_PANICKED`] when the helper panicked), or −1,
    /// running nothing, when `f` is not of the layout's length, there is
    /// no such function, or it reads or writes ports (then
    /// [`Fused::call_ports`] runs it).
    pub fn call(&self, which: usize, f: &mut [f64], helper: &mut dyn Helper) -> i64 {
        self.call_ports(which, f, helper, [], [])
    }

    /// [`Fused::call`] with the arrays its [`Op::Import`] and
    /// [`Op::Export`] read and write (`inputs[i]` is [`Port::Input`]`(i)`,
    /// `outputs[i]` is [`Port::Output`]`(i)`): −1, running nothing, also
    /// when one of them is missing or shorter than the ops use. The
    /// outputs are written only by the function's [`Op::Export`]s (a
    /// function that returns a nonzero status before them leaves them as
    /// they were).
    #[inline]
    pub fn call_ports<const I: usize, const O: usize>(
        &self,
        which: usize,
        f: &mut [f64],
        helper: &mut dyn Helper,
        inputs: [&[f64]; I],
        outputs: [&mut [f64]; O],
    ) -> i64 {
        self.function::<I, O>(which)
            .map_or(-1, |c| c.call(f, helper, inputs, outputs))
    }

    /// Function `which`, to be called many times without looking it up
    /// again, with `I` input ports and `O` output ports (`None`: no such
    /// function, more ports than [`PORTS`], or a function that uses a
    /// port beyond them). The ports it uses and how many values it reads
    /// or writes in each are looked up here, once; a call checks only the
    /// lengths of the arrays it is given.
    #[must_use]
    pub fn function<const I: usize, const O: usize>(
        &self,
        which: usize,
    ) -> Option<Callable<'_, I, O>> {
        let needs = self.needs.get(which)?;
        let (need_in, need_out) = needs.split_at(PORTS);
        if I > PORTS
            || O > PORTS
            || need_in[I..].iter().any(|&n| n > 0)
            || need_out[O..].iter().any(|&n| n > 0)
        {
            return None;
        }
        Some(Callable {
            entry: *self.entries.get(which)?,
            need_in: core::array::from_fn(|i| need_in[i]),
            need_out: core::array::from_fn(|i| need_out[i]),
            len: self.len,
            vex: self.vex,
            code: PhantomData,
        })
    }
}

// SAFETY (Send, Sync): as for `Program`: the module is only touched by
// `Drop`; the code keeps no state of its own (it works in the buffer and
// context its caller passes).
#[allow(unsafe_code)]
unsafe impl Send for Fused {}
#[allow(unsafe_code)]
unsafe impl Sync for Fused {}

impl Drop for Fused {
    #[allow(unsafe_code)]
    fn drop(&mut self) {
        // SAFETY: the entry is private and called only through `&self`.
        unsafe {
            let module = ManuallyDrop::take(&mut self.module);
            module.free_memory();
        }
    }
}
