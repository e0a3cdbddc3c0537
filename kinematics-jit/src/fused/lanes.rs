//! Fused functions on two designs at once: the ops of the common path of
//! a step or pose with every value a vector of two f64 lanes, the buffer
//! and the ports interleaved (value i of design l at 2i + l), for
//! batches that run designs in pairs.
//!
//! Only the common path has a form in lanes: where either design would
//! leave it (a guard fails, a driver moved beyond the carried series'
//! step), the function returns the status `left` and the caller runs the
//! two designs alone. So no op calls the helper: [`Op::Call`],
//! [`Op::Solve`] and [`Op::FactorSmall`] have no form in lanes (an error
//! when compiling). The checks of the others hold in both lanes: a value
//! not finite, or a bound exceeded, in either is the op's status.
//!
//! Each lane computes what the scalar function computes for its design,
//! operation for operation (the same IEEE operations in the same order).

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{
    types, AbiParam, Block, BlockArg, InstBuilder, InstructionData, MemFlags, Opcode, UserFuncName,
    Value,
};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_module::{Linkage, Module};
use kinematics_compiler::ir::Graph;

use super::callable::entry;
use super::emit::{port_slot, seed_at};
use super::{Compare, Function, Fused, Inst, Layout, Op, Port, Series, Val, PORTS};
use crate::lower::{constant, Imports, Lower, Sources};
use crate::{declare_imports, new_module, vex_encoded, JitError};

/// Vectors are read and written unaligned (the buffer of f64 is aligned
/// to 8 bytes), never trapping (every offset is checked).
fn vector_flags() -> MemFlags {
    MemFlags::new().with_notrap()
}

/// The buffer in lanes: value i of both designs at byte 16 i, with the
/// values the code holds in registers (as the scalar `Memory`).
struct Lanes<'w> {
    fp: Value,
    within: &'w dyn Fn(usize) -> Result<i32, JitError>,
    known: std::collections::HashMap<usize, Value>,
}

impl Lanes<'_> {
    fn load(&mut self, b: &mut FunctionBuilder<'_>, at: usize) -> Result<Value, JitError> {
        if let Some(&v) = self.known.get(&at) {
            return Ok(v);
        }
        let v = b
            .ins()
            .load(types::F64X2, vector_flags(), self.fp, (self.within)(at)?);
        self.known.insert(at, v);
        Ok(v)
    }

    fn store(&mut self, b: &mut FunctionBuilder<'_>, at: usize, v: Value) -> Result<(), JitError> {
        b.ins()
            .store(vector_flags(), v, self.fp, (self.within)(at)?);
        self.known.insert(at, v);
        Ok(())
    }
}

/// x in both lanes.
fn splat(b: &mut FunctionBuilder<'_>, x: f64) -> Value {
    let c = b.ins().f64const(x);
    b.ins().splat(types::F64X2, c)
}

/// The constant both lanes of `v` hold, where `v` is a splatted constant.
fn lane_constant(b: &FunctionBuilder<'_>, v: Value) -> Option<f64> {
    let dfg = &b.func.dfg;
    let cranelift_codegen::ir::ValueDef::Result(inst, 0) = dfg.value_def(v) else {
        return None;
    };
    match dfg.insts[inst] {
        InstructionData::Unary {
            opcode: Opcode::Splat,
            arg,
        } => constant(b, arg),
        _ => None,
    }
}

/// A flag (an `i8`) set when a lane of one of `values` is not finite, as
/// the scalar check (a pairwise sum, times 0, is NaN); `None` for none.
fn not_finite(b: &mut FunctionBuilder<'_>, values: &[Value]) -> Option<Value> {
    let varying: Vec<_> = values
        .iter()
        .copied()
        .filter(|&v| lane_constant(b, v).is_none_or(f64::is_nan))
        .collect();
    let mut level = varying;
    while level.len() > 1 {
        level = level
            .chunks(2)
            .map(|p| match p {
                [x, y] => b.ins().fadd(*x, *y),
                [x] => *x,
                _ => unreachable_zero(b),
            })
            .collect();
    }
    let sum = level.pop()?;
    let zero = splat(b, 0.0);
    let test = b.ins().fmul(sum, zero);
    let nan = b.ins().fcmp(FloatCC::Unordered, test, test);
    Some(b.ins().vany_true(nan))
}

/// Zero in both lanes (a chunk of two values has one or two).
fn unreachable_zero(b: &mut FunctionBuilder<'_>) -> Value {
    splat(b, 0.0)
}

/// Σ xᵢ yᵢ as the scalar code forms it: terms with a constant ±0 factor
/// left out, a factor 1 not multiplied by.
fn sum_of_products(b: &mut FunctionBuilder<'_>, pairs: &[(Value, Value)]) -> Value {
    let mut sum = None;
    for &(x, y) in pairs {
        let (cx, cy) = (lane_constant(b, x), lane_constant(b, y));
        if cx == Some(0.0) || cy == Some(0.0) {
            continue;
        }
        let term = match (cx, cy) {
            (Some(1.0), _) => y,
            (_, Some(1.0)) => x,
            _ => b.ins().fmul(x, y),
        };
        sum = Some(match sum {
            None => term,
            Some(s) => b.ins().fadd(s, term),
        });
    }
    sum.unwrap_or_else(|| splat(b, 0.0))
}

/// c₀ − x·(c₁ − x·(c₂ − …)) in both lanes, as the scalar code forms it.
fn alternating(b: &mut FunctionBuilder<'_>, x: Value, c: &[f64]) -> Value {
    let mut rest = c.iter().rev();
    let mut t = splat(b, rest.next().copied().unwrap_or(0.0));
    let nx = b.ins().fneg(x);
    for &k in rest {
        let m = b.ins().fmul(nx, t);
        let k = splat(b, k);
        t = b.ins().fadd(m, k);
    }
    t
}

/// Goes on in a new block when `failed` is 0, else returns `status`.
fn bail(b: &mut FunctionBuilder<'_>, exit: Block, failed: Value, status: i64) {
    let status = b.ins().iconst(types::I64, status);
    let next = b.create_block();
    b.ins()
        .brif(failed, exit, &[BlockArg::Value(status)], next, &[]);
    b.switch_to_block(next);
}

/// Goes on in a new block when both lanes of `mask` are set, else
/// returns `status`.
fn unless_all(b: &mut FunctionBuilder<'_>, exit: Block, mask: Value, status: i64) {
    let all = b.ins().vall_true(mask);
    let failed = b.ins().icmp_imm(IntCC::Equal, all, 0);
    bail(b, exit, failed, status);
}

impl Fused {
    /// [`Fused::new`] on two designs per call, in vector lanes: the
    /// buffer holds `2 · layout.len` values, value i of design l at
    /// 2i + l, and each port's array both designs' values, interleaved
    /// alike. Where either design leaves the common path the function
    /// returns `left` (the scalar function would call the helper there).
    ///
    /// # Errors
    /// As [`Fused::new`]; [`JitError::Codegen`] also for an op with no
    /// form in lanes ([`Op::Call`], [`Op::Solve`], [`Op::FactorSmall`]).
    pub fn new_in_lanes(
        graph: &Graph,
        params: usize,
        coords: usize,
        layout: Layout,
        functions: &[Function<'_>],
        left: i64,
    ) -> Result<Self, JitError> {
        let mut module = new_module(&[])?;
        let codegen = |e: &dyn core::fmt::Display| JitError::Codegen(e.to_string());
        let imports = declare_imports(&mut module)?;
        let pointer = module.target_config().pointer_type();
        let mut sig = module.make_signature();
        for _ in 0..3 {
            sig.params.push(AbiParam::new(pointer));
        }
        sig.returns.push(AbiParam::new(types::I64));
        let mut ctx = module.make_context();
        let mut fcx = FunctionBuilderContext::new();
        let mut ids = Vec::with_capacity(functions.len());
        let mut needs = Vec::with_capacity(functions.len());
        let within = |at: usize| {
            if at < layout.len {
                i32::try_from(at * 16).map_err(|_| JitError::Codegen("buffer too long".into()))
            } else {
                Err(JitError::Codegen(format!(
                    "offset {at} past the buffer of {}",
                    layout.len
                )))
            }
        };
        for (k, function) in functions.iter().enumerate() {
            let mut need = [0; 2 * PORTS];
            let id = module
                .declare_function(&format!("lanes_{k}"), Linkage::Local, &sig)
                .map_err(|e| codegen(&e))?;
            ctx.func.signature = sig.clone();
            ctx.func.name = UserFuncName::user(0, id.as_u32());
            {
                let mut b = FunctionBuilder::new(&mut ctx.func, &mut fcx);
                let start = b.create_block();
                b.append_block_params_for_function_params(start);
                let exit = b.create_block();
                b.append_block_param(exit, types::I64);
                b.switch_to_block(start);
                let args = b.block_params(start).to_vec();
                let (fp, pp) = (args[0], args[2]);
                let imports = Imports {
                    refs: imports
                        .iter()
                        .map(|(name, fid)| (*name, module.declare_func_in_func(*fid, b.func)))
                        .collect(),
                };
                let sources = Sources {
                    ptr: [fp; 5],
                    base: [layout.params, layout.q, layout.qd, layout.qdd, layout.trig],
                    params,
                    coords,
                    time: None,
                };
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
                for &(_, at) in function.preset {
                    within(layout.params + at)?;
                }
                let mut lower = Lower::new(graph).with_preset(function.preset).in_lanes();
                let mut memory = Lanes {
                    fp,
                    within: &within,
                    known: std::collections::HashMap::new(),
                };
                let mut cx = Emit {
                    lower: &mut lower,
                    sources: &sources,
                    imports: &imports,
                    graph,
                    layout: &layout,
                    coords,
                    exit,
                    left,
                };
                for op in function.ops {
                    cx.op(&mut b, &mut memory, op, pp, &mut need)?;
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
            module: core::mem::ManuallyDrop::new(module),
            entries,
            needs,
            len: 2 * layout.len,
        })
    }
}

/// What the ops of one function in lanes are emitted with.
struct Emit<'a, 'g> {
    lower: &'a mut Lower<'g>,
    sources: &'a Sources,
    imports: &'a Imports,
    graph: &'a Graph,
    layout: &'a Layout,
    coords: usize,
    exit: Block,
    left: i64,
}

impl Emit<'_, '_> {
    fn op(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        memory: &mut Lanes<'_>,
        op: &Op,
        pp: Value,
        need: &mut [usize; 2 * PORTS],
    ) -> Result<(), JitError> {
        let pointer = types::I64;
        match op {
            Op::Store { roots, at, finite } => {
                if roots.len() != at.len() {
                    return Err(JitError::Codegen(
                        "a store's roots and offsets differ in number".into(),
                    ));
                }
                self.lower.emit(b, self.sources, self.imports, roots)?;
                let mut values = Vec::with_capacity(roots.len());
                for (&root, &at) in roots.iter().zip(at) {
                    let v = self.lower.value(b, self.sources, self.imports, root)?;
                    memory.store(b, at, v)?;
                    values.push(v);
                }
                if let (Some(status), Some(failed)) = (*finite, not_finite(b, &values)) {
                    bail(b, self.exit, failed, status);
                }
            }
            Op::MaxScaled { roots, scales, at } => {
                self.lower.emit(b, self.sources, self.imports, roots)?;
                // The scalar maximum of the bit patterns of |vᵢ sᵢ|, lane
                // by lane (a NaN above every number).
                let mut m = [b.ins().iconst(types::I64, 0), b.ins().iconst(types::I64, 0)];
                for (i, &root) in roots.iter().enumerate() {
                    let v = self.lower.value(b, self.sources, self.imports, root)?;
                    let s = memory.load(b, scales + i)?;
                    let p = b.ins().fmul(v, s);
                    let r = b.ins().fabs(p);
                    for (lane, m) in m.iter_mut().enumerate() {
                        let x = b.ins().extractlane(r, lane as u8);
                        let bits = b.ins().bitcast(types::I64, MemFlags::new(), x);
                        *m = b.ins().umax(*m, bits);
                    }
                }
                let m0 = b.ins().bitcast(types::F64, MemFlags::new(), m[0]);
                let m1 = b.ins().bitcast(types::F64, MemFlags::new(), m[1]);
                let v = b.ins().splat(types::F64X2, m0);
                let v = b.ins().insertlane(v, m1, 1);
                memory.store(b, *at, v)?;
            }
            Op::CarriedTrig {
                value,
                carried,
                to,
                series,
                ..
            } => self.carried_trig(b, memory, (*value, *carried, *to), series)?,
            Op::Guarded {
                code,
                ok,
                fast,
                keep,
                ..
            } => self.guarded(b, memory, code, *ok, fast, keep)?,
            Op::AtMost { at, bound, status } => {
                let x = memory.load(b, *at)?;
                let y = memory.load(b, *bound)?;
                let within = b.ins().fcmp(FloatCC::LessThanOrEqual, x, y);
                unless_all(b, self.exit, within, *status);
            }
            Op::Import {
                from,
                to,
                len,
                finite,
            } => {
                if *len == 0 {
                    return Ok(());
                }
                let slot = port_slot(*from, need, 2 * len)?;
                let base = b.ins().load(pointer, MemFlags::trusted(), pp, slot);
                let mut values = Vec::with_capacity(*len);
                for i in 0..*len {
                    let v = b
                        .ins()
                        .load(types::F64X2, vector_flags(), base, lane_offset(i)?);
                    memory.store(b, to + i, v)?;
                    values.push(v);
                }
                if let (Some(status), Some(failed)) = (*finite, not_finite(b, &values)) {
                    bail(b, self.exit, failed, status);
                }
            }
            Op::Export { to, from, len } => {
                if *len == 0 {
                    return Ok(());
                }
                let slot = port_slot(Port::Output(*to), need, 2 * len)?;
                let base = b.ins().load(pointer, MemFlags::trusted(), pp, slot);
                for i in 0..*len {
                    let v = memory.load(b, from + i)?;
                    b.ins().store(vector_flags(), v, base, lane_offset(i)?);
                }
            }
            Op::Finite { from, len, status } => {
                let mut values = Vec::with_capacity(*len);
                for i in 0..*len {
                    values.push(memory.load(b, from + i)?);
                }
                if let Some(failed) = not_finite(b, &values) {
                    bail(b, self.exit, failed, *status);
                }
            }
            Op::Call(_) | Op::Solve { .. } | Op::FactorSmall { .. } => {
                return Err(JitError::Codegen(format!(
                    "{} has no form in lanes",
                    match op {
                        Op::Call(_) => "a call of the helper",
                        Op::Solve { .. } => "a block solve",
                        _ => "a factorisation of small blocks",
                    }
                )));
            }
        }
        Ok(())
    }

    /// The carried cosine and sine of a driver, rotated by the series in
    /// both lanes; `left` where either moved beyond the series' step.
    fn carried_trig(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        memory: &mut Lanes<'_>,
        (value, carried, to): (usize, usize, usize),
        series: &Series,
    ) -> Result<(), JitError> {
        let x = memory.load(b, value)?;
        let c0 = memory.load(b, carried)?;
        let s0 = memory.load(b, carried + 1)?;
        let x0 = memory.load(b, carried + 2)?;
        let d = b.ins().fsub(x, x0);
        let ad = b.ins().fabs(d);
        let limit = splat(b, series.step);
        let near = b.ins().fcmp(FloatCC::LessThanOrEqual, ad, limit);
        unless_all(b, self.exit, near, self.left);
        let d2 = b.ins().fmul(d, d);
        let inner = alternating(b, d2, &series.sin);
        let dd2 = b.ins().fmul(d, d2);
        let t = b.ins().fmul(dd2, inner);
        let sin = b.ins().fsub(d, t);
        let inner = alternating(b, d2, &series.vers);
        let vers = b.ins().fmul(d2, inner);
        let a = b.ins().fmul(c0, vers);
        let bb = b.ins().fmul(s0, sin);
        let a = b.ins().fadd(a, bb);
        let c = b.ins().fsub(c0, a);
        let a = b.ins().fmul(s0, vers);
        let bb = b.ins().fmul(c0, sin);
        let a = b.ins().fsub(a, bb);
        let sn = b.ins().fsub(s0, a);
        for (v, at) in [
            (c, to),
            (sn, to + 1),
            (c, carried),
            (sn, carried + 1),
            (x, carried + 2),
        ] {
            memory.store(b, at, v)?;
        }
        for (at, v) in [(value, x), (to, c), (to + 1, sn)] {
            seed_at(self.lower, self.graph, self.layout, self.coords, at, v);
        }
        Ok(())
    }

    /// A guarded computation in both lanes: its fast path where its flag
    /// holds in both, else `left`.
    fn guarded(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        memory: &mut Lanes<'_>,
        code: &[Inst],
        ok: Val,
        fast: &[(usize, Val)],
        keep: &[usize],
    ) -> Result<(), JitError> {
        let bad = |what: &str| JitError::Codegen(format!("a guarded computation {what}"));
        let roots: Vec<_> = code
            .iter()
            .filter_map(|i| match i {
                Inst::Root(id) => Some(*id),
                _ => None,
            })
            .collect();
        self.lower.emit(b, self.sources, self.imports, &roots)?;
        // Numbers are F64X2, flags are lane masks (I64X2).
        let mut values: Vec<(Value, bool)> = Vec::with_capacity(code.len());
        let get = |values: &[(Value, bool)], v: Val| match values.get(v.0 as usize) {
            Some(&(x, false)) => Ok(x),
            Some(_) => Err(bad("reads a flag as a number")),
            None => Err(bad("reads a value not defined before")),
        };
        let flag = |values: &[(Value, bool)], v: Val| match values.get(v.0 as usize) {
            Some(&(x, true)) => Ok(x),
            Some(_) => Err(bad("reads a number as a flag")),
            None => Err(bad("reads a flag not defined before")),
        };
        for inst in code {
            let defined = match inst {
                Inst::Root(id) => (self.lower.value(b, self.sources, self.imports, *id)?, false),
                Inst::Load(at) => (memory.load(b, *at)?, false),
                Inst::Const(x) => (splat(b, *x), false),
                Inst::Add(x, y) => {
                    let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                    (b.ins().fadd(x, y), false)
                }
                Inst::Sub(x, y) => {
                    let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                    (b.ins().fsub(x, y), false)
                }
                Inst::Mul(x, y) => {
                    let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                    (b.ins().fmul(x, y), false)
                }
                Inst::Div(x, y) => {
                    let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                    (b.ins().fdiv(x, y), false)
                }
                Inst::Neg(x) => (b.ins().fneg(get(&values, *x)?), false),
                Inst::Abs(x) => (b.ins().fabs(get(&values, *x)?), false),
                Inst::Sqrt(x) => (b.ins().sqrt(get(&values, *x)?), false),
                Inst::Dot(pairs) => {
                    let pairs = pairs
                        .iter()
                        .map(|&(x, y)| Ok((get(&values, x)?, get(&values, y)?)))
                        .collect::<Result<Vec<_>, JitError>>()?;
                    (sum_of_products(b, &pairs), false)
                }
                Inst::Compare(how, x, y) => {
                    let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                    let cc = match how {
                        Compare::Less => FloatCC::LessThan,
                        Compare::LessOrEqual => FloatCC::LessThanOrEqual,
                        Compare::Greater => FloatCC::GreaterThan,
                        Compare::GreaterOrEqual => FloatCC::GreaterThanOrEqual,
                        Compare::Equal => FloatCC::Equal,
                        Compare::NotEqual => FloatCC::NotEqual,
                    };
                    (b.ins().fcmp(cc, x, y), true)
                }
                Inst::And(x, y) => {
                    let (x, y) = (flag(&values, *x)?, flag(&values, *y)?);
                    (b.ins().band(x, y), true)
                }
                Inst::Select(c, x, y) => {
                    let c = flag(&values, *c)?;
                    let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                    let c = b.ins().bitcast(types::F64X2, MemFlags::new(), c);
                    (b.ins().bitselect(c, x, y), false)
                }
            };
            values.push(defined);
        }
        let ok = flag(&values, ok)?;
        unless_all(b, self.exit, ok, self.left);
        for &(to, v) in fast {
            let v = get(&values, v)?;
            memory.store(b, to, v)?;
        }
        for &at in keep {
            let &(_, v) = fast
                .iter()
                .rev()
                .find(|&&(to, _)| to == at)
                .ok_or_else(|| bad("keeps an offset its fast path does not write"))?;
            let v = get(&values, v)?;
            seed_at(self.lower, self.graph, self.layout, self.coords, at, v);
        }
        Ok(())
    }
}

/// The byte offset of value i of both designs in an interleaved array.
fn lane_offset(i: usize) -> Result<i32, JitError> {
    i32::try_from(i * 16).map_err(|_| JitError::Codegen("an array too long".into()))
}
