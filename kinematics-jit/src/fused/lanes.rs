//! Fused functions on two designs at once: the ops of the common path of
//! a step or pose with every value a vector of two f64 lanes, the buffer
//! and the ports interleaved (value i of design l at 2i + l), for
//! batches that run designs in pairs.
//!
//! Only the common path has a form in lanes: where either design would
//! leave it (a guard fails, a driver moved beyond the carried series'
//! step), the function returns the status `left` and the caller runs the
//! two designs alone. So no op calls the helper: [`Op::Call`] has no form
//! in lanes (an error when compiling). The checks of the others hold in
//! both lanes: a value not finite, a bound exceeded, a singular block or
//! the other branch, in either is the op's status. The small blocks'
//! factorisation and the block solve are written once for both forms
//! (`blocks.rs`).
//!
//! Each lane computes what the scalar function computes for its design,
//! operation for operation (the same IEEE operations in the same order).

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{types, Block, BlockArg, InstBuilder, MemFlags, Value};
use cranelift_frontend::FunctionBuilder;
use kinematics_compiler::ir::Graph;

use super::blocks;
use super::emit::{
    evaluate, flag_of, konst, not_finite, number_of, port_slot, rotated, seed_at, vector_flags,
    Memory,
};
use super::{Function, Fused, Inst, Layout, Op, Port, Series, Val, PORTS};
use crate::lower::{Imports, Lower, Sources};
use crate::JitError;

/// x in both lanes.
fn splat(b: &mut FunctionBuilder<'_>, x: f64) -> Value {
    konst(b, true, x)
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
    /// form in lanes ([`Op::Call`]).
    pub fn new_in_lanes(
        graph: &Graph,
        params: usize,
        coords: usize,
        layout: Layout,
        functions: &[Function<'_>],
        left: i64,
    ) -> Result<Self, JitError> {
        Self::compile(graph, (params, coords), layout, functions, Some(left))
    }
}

/// What the ops of one function in lanes are emitted with.
pub(super) struct Emit<'a, 'g> {
    pub(super) lower: &'a mut Lower<'g>,
    pub(super) sources: &'a Sources,
    pub(super) imports: &'a Imports,
    pub(super) graph: &'a Graph,
    pub(super) layout: &'a Layout,
    pub(super) coords: usize,
    pub(super) exit: Block,
    pub(super) left: i64,
}

impl Emit<'_, '_> {
    pub(super) fn op(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        memory: &mut Memory<'_>,
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
                if let (Some(status), Some(failed)) = (*finite, not_finite(b, true, &values)) {
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
                if let (Some(status), Some(failed)) = (*finite, not_finite(b, true, &values)) {
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
                if let Some(failed) = not_finite(b, true, &values) {
                    bail(b, self.exit, failed, *status);
                }
            }
            Op::Solve {
                rhs,
                blocks,
                to,
                finite,
            } => {
                let exit = self.exit;
                blocks::solve(
                    b,
                    true,
                    (&mut *self.lower, self.sources, self.imports),
                    memory,
                    (rhs, blocks, *to, *finite),
                    &mut |b, failed, status| bail(b, exit, failed, status),
                )?;
            }
            Op::FactorSmall { .. } => {
                let (blocks, at) = blocks::Factoring::of(op)
                    .ok_or_else(|| JitError::Codegen("a factorisation's fields".into()))?;
                let exit = self.exit;
                blocks::factor_small(
                    b,
                    true,
                    (&mut *self.lower, self.sources, self.imports),
                    memory,
                    (blocks, &at),
                    &mut |b, failed, status| bail(b, exit, failed, status),
                )?;
            }
            Op::Call(_) => {
                return Err(JitError::Codegen(
                    "a call of the helper has no form in lanes".into(),
                ));
            }
        }
        Ok(())
    }

    /// The carried cosine and sine of a driver, rotated by the series in
    /// both lanes; `left` where either moved beyond the series' step.
    fn carried_trig(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        memory: &mut Memory<'_>,
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
        let (c, sn) = rotated(b, true, d, (c0, s0), series);
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
        memory: &mut Memory<'_>,
        code: &[Inst],
        ok: Val,
        fast: &[(usize, Val)],
        keep: &[usize],
    ) -> Result<(), JitError> {
        let bad = |what: &str| JitError::Codegen(format!("a guarded computation {what}"));
        let values = evaluate(
            b,
            (&mut *self.lower, self.sources, self.imports),
            &mut |b, at| memory.load(b, at),
            code,
            true,
        )?;
        let get = number_of;
        let flag = flag_of;
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
