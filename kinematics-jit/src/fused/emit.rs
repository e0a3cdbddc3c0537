//! The pieces of machine code the ops are built from: the closed forms'
//! solutions and their fall-back to the helper, the sums and series, the
//! finiteness checks, the ports' slots.

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{types, BlockArg, InstBuilder, MemFlags};
use cranelift_frontend::FunctionBuilder;
use kinematics_compiler::ir::{Func, Graph, Leaf, Node};

use super::{AngleAt, Layout, Port, PORTS};
use crate::lower::{Lower, SignBits};
use crate::JitError;

/// The buffer as the code reads and writes it, with the values it is
/// known to hold at the point being emitted: a load of one of them is
/// the value itself, from a register, not a reload (a value imported, a
/// coefficient, a scale read twice, the inverse of a block). What the
/// code stored or loaded in a block that dominates the rest is known;
/// everything is forgotten where the helper may have run (a call, the
/// join after a closed form's fall-back), since it can rewrite any value.
pub(super) struct Memory<'w> {
    fp: cranelift_codegen::ir::Value,
    within: &'w dyn Fn(usize) -> Result<i32, JitError>,
    known: std::collections::HashMap<usize, cranelift_codegen::ir::Value>,
}

impl<'w> Memory<'w> {
    /// The buffer at `fp`, every offset checked by `within`.
    pub(super) fn new(
        fp: cranelift_codegen::ir::Value,
        within: &'w dyn Fn(usize) -> Result<i32, JitError>,
    ) -> Self {
        Self {
            fp,
            within,
            known: std::collections::HashMap::new(),
        }
    }

    /// The value at `at`: known, or loaded (and then known).
    pub(super) fn load(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        at: usize,
    ) -> Result<cranelift_codegen::ir::Value, JitError> {
        if let Some(&v) = self.known.get(&at) {
            return Ok(v);
        }
        let v = b
            .ins()
            .load(types::F64, MemFlags::trusted(), self.fp, (self.within)(at)?);
        self.known.insert(at, v);
        Ok(v)
    }

    /// Writes `v` at `at`, where the code goes on (it is then known).
    pub(super) fn store(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        at: usize,
        v: cranelift_codegen::ir::Value,
    ) -> Result<(), JitError> {
        self.write(b, at, v)?;
        self.known.insert(at, v);
        Ok(())
    }

    /// Writes `v` at `at` on a path that does not dominate the rest (a
    /// fast path before its join): what was known there is forgotten.
    pub(super) fn write(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        at: usize,
        v: cranelift_codegen::ir::Value,
    ) -> Result<(), JitError> {
        b.ins()
            .store(MemFlags::trusted(), v, self.fp, (self.within)(at)?);
        self.known.remove(&at);
        Ok(())
    }

    /// Records that `at` holds `v` (a join's parameter, which is what the
    /// buffer holds there on every path into it).
    pub(super) fn holds(&mut self, at: usize, v: cranelift_codegen::ir::Value) {
        self.known.insert(at, v);
    }

    /// Forgets every value (the helper may have run).
    pub(super) fn forget(&mut self) {
        self.known.clear();
    }
}

/// The slot of `port` in the table of pointers (its byte offset), with
/// `len` values of it recorded as used.
pub(super) fn port_slot(
    port: Port,
    need: &mut [usize; 2 * PORTS],
    len: usize,
) -> Result<i32, JitError> {
    let slot = port
        .slot()
        .ok_or_else(|| JitError::Codegen(format!("no port {port:?}")))?;
    need[slot] = need[slot].max(len);
    i32::try_from(slot * core::mem::size_of::<*mut f64>())
        .map_err(|_| JitError::Codegen("port table too long".into()))
}

/// The byte offset of value `i` of an array.
pub(super) fn offset(i: usize) -> Result<i32, JitError> {
    i32::try_from(i * 8).map_err(|_| JitError::Codegen("an array too long".into()))
}

/// (cos θ, sin θ) solving a cos θ + b sin θ + c = 0 in the mode σ (as
/// `kinematics_core::closed::angle` computes them: R² = a² + b²,
/// Δ = R² − c², 0 within 8 ε of R² + c², cos θ = (−a c − σ b √Δ)/R²,
/// sin θ = (−b c + σ a √Δ)/R²), and whether Δ ≥ 0 and 0 < R² < ∞ (false
/// for a NaN σ, whose values are NaN).
pub(super) fn angle_solution(
    b: &mut FunctionBuilder<'_>,
    a: cranelift_codegen::ir::Value,
    bb: cranelift_codegen::ir::Value,
    c: cranelift_codegen::ir::Value,
    sigma: cranelift_codegen::ir::Value,
) -> (
    cranelift_codegen::ir::Value,
    cranelift_codegen::ir::Value,
    cranelift_codegen::ir::Value,
) {
    let x0 = b.ins().fmul(a, a);
    let x1 = b.ins().fmul(bb, bb);
    let r2 = b.ins().fadd(x0, x1);
    let cc = b.ins().fmul(c, c);
    let d = b.ins().fsub(r2, cc);
    let size = b.ins().fadd(r2, cc);
    let eps8 = b.ins().f64const(8.0 * f64::EPSILON);
    let tol = b.ins().fmul(eps8, size);
    let ad = b.abs(d);
    let tiny = b.ins().fcmp(FloatCC::LessThanOrEqual, ad, tol);
    let zero = b.ins().f64const(0.0);
    let disc = b.ins().select(tiny, zero, d);
    let inf = b.ins().f64const(f64::INFINITY);
    let ok_disc = b.ins().fcmp(FloatCC::GreaterThanOrEqual, disc, zero);
    let ok_r2 = b.ins().fcmp(FloatCC::GreaterThan, r2, zero);
    let ok_fin = b.ins().fcmp(FloatCC::LessThan, r2, inf);
    let same = b.ins().fcmp(FloatCC::Equal, sigma, sigma);
    let ok = b.ins().band(ok_disc, ok_r2);
    let ok = b.ins().band(ok, ok_fin);
    let ok = b.ins().band(ok, same);
    let one = b.ins().f64const(1.0);
    let inv = b.ins().fdiv(one, r2);
    let sq = b.ins().sqrt(disc);
    let root = b.ins().fmul(sigma, sq);
    let na = b.neg(a);
    let x0 = b.ins().fmul(na, c);
    let x1 = b.ins().fmul(bb, root);
    let x = b.ins().fsub(x0, x1);
    let cos = b.ins().fmul(x, inv);
    let nb = b.neg(bb);
    let x0 = b.ins().fmul(nb, c);
    let x1 = b.ins().fmul(a, root);
    let x = b.ins().fadd(x0, x1);
    let sin = b.ins().fmul(x, inv);
    (cos, sin, ok)
}

/// What a call to the helper needs: the buffer, the context, the
/// helper's reference and the block that returns a status.
pub(super) type HelperCall = (
    cranelift_codegen::ir::Value,
    cranelift_codegen::ir::Value,
    cranelift_codegen::ir::FuncRef,
    cranelift_codegen::ir::Block,
);

/// Each solved angle from its carried value, θ = θₚ + asin x with
/// x = cₚ s − sₚ c by its series (as `kinematics_core::closed::
/// near_carried` takes it), where the rotation is small (cos of it
/// positive, |x| ≤ 1/32) and θ within π of the guess; where `ok` and these
/// hold for every angle, each angle, its cosine and sine are written and
/// carried, else the helper is called with `general` (the guesses and
/// carried values untouched), returning its status unless 0.
pub(super) fn store_or_general(
    b: &mut FunctionBuilder<'_>,
    (fp, cp, helper, exit): HelperCall,
    memory: &mut Memory<'_>,
    mut ok: cranelift_codegen::ir::Value,
    solved: &[(
        AngleAt,
        cranelift_codegen::ir::Value,
        cranelift_codegen::ir::Value,
    )],
    (general, coefficients, store): (u64, &[cranelift_codegen::ir::Value], usize),
) -> Result<Vec<Angle>, JitError> {
    let (fast, slow, join) = (b.create_block(), b.create_block(), b.create_block());
    let mut results = Vec::with_capacity(solved.len());
    for &(at, cv, sv) in solved {
        let cpv = memory.load(b, at.carried)?;
        let spv = memory.load(b, at.carried + 1)?;
        let tp = memory.load(b, at.carried + 2)?;
        let guess = memory.load(b, at.value)?;
        let x0 = b.ins().fmul(cpv, sv);
        let x1 = b.ins().fmul(spv, cv);
        let x = b.ins().fsub(x0, x1);
        let y0 = b.ins().fmul(cpv, cv);
        let y1 = b.ins().fmul(spv, sv);
        let y = b.ins().fadd(y0, y1);
        let x2 = b.ins().fmul(x, x);
        // asin x = x + x³/6 + 3x⁵/40 + 5x⁷/112 + 35x⁹/1152 + 63x¹¹/2816.
        let mut t = b.ins().f64const(63.0 / 2816.0);
        for coefficient in [35.0 / 1152.0, 5.0 / 112.0, 3.0 / 40.0, 1.0 / 6.0] {
            let m = b.ins().fmul(x2, t);
            let k = b.ins().f64const(coefficient);
            t = b.ins().fadd(m, k);
        }
        let series = b.ins().fmul(x2, t);
        let xs = b.ins().fmul(x, series);
        let asin = b.ins().fadd(x, xs);
        let theta = b.ins().fadd(tp, asin);
        let zero = b.ins().f64const(0.0);
        let ok_y = b.ins().fcmp(FloatCC::GreaterThan, y, zero);
        let ax = b.abs(x);
        let limit = b.ins().f64const(0.031_25);
        let ok_x = b.ins().fcmp(FloatCC::LessThanOrEqual, ax, limit);
        let off = b.ins().fsub(theta, guess);
        let aoff = b.abs(off);
        let pi = b.ins().f64const(std::f64::consts::PI);
        let ok_ref = b.ins().fcmp(FloatCC::LessThanOrEqual, aoff, pi);
        ok = b.ins().band(ok, ok_y);
        ok = b.ins().band(ok, ok_x);
        ok = b.ins().band(ok, ok_ref);
        results.push((at, cv, sv, theta));
    }
    b.ins().brif(ok, fast, &[], slow, &[]);
    b.switch_to_block(fast);
    for &(at, cv, sv, theta) in &results {
        for (value, to) in [
            (theta, at.value),
            (cv, at.trig),
            (sv, at.trig + 1),
            (cv, at.carried),
            (sv, at.carried + 1),
            (theta, at.carried + 2),
        ] {
            memory.write(b, to, value)?;
        }
    }
    // The angles, their cosines and sines go on in registers: from the
    // fast path as computed, from the helper as it wrote them.
    let mut args = Vec::with_capacity(3 * solved.len());
    let mut after = Vec::with_capacity(solved.len());
    for &(at, cv, sv, theta) in &results {
        args.extend([theta, cv, sv].map(BlockArg::Value));
        let mut param = || b.append_block_param(join, types::F64);
        after.push(Angle {
            at,
            value: param(),
            cos: param(),
            sin: param(),
        });
    }
    b.ins().jump(join, &args);
    b.switch_to_block(slow);
    for (i, &v) in coefficients.iter().enumerate() {
        memory.write(b, store + i, v)?;
    }
    let helped = b.create_block();
    call_helper(b, (fp, cp, helper, exit), general, helped);
    memory.forget();
    let mut args = Vec::with_capacity(3 * solved.len());
    for (at, _, _, _) in results {
        for from in [at.value, at.trig, at.trig + 1] {
            args.push(BlockArg::Value(memory.load(b, from)?));
        }
    }
    b.ins().jump(join, &args);
    b.switch_to_block(join);
    // Past the join, the buffer holds what either path left: the angles,
    // their cosines and sines are the join's parameters; the rest, which
    // the helper may have rewritten, is read afresh.
    memory.forget();
    for a in &after {
        memory.holds(a.at.value, a.value);
        memory.holds(a.at.trig, a.cos);
        memory.holds(a.at.trig + 1, a.sin);
    }
    Ok(after)
}

/// An angle solved by a closed form, as the code goes on with it: where
/// it lies in the buffer, and its value, cosine and sine.
#[derive(Clone, Copy)]
pub(super) struct Angle {
    pub(super) at: AngleAt,
    pub(super) value: cranelift_codegen::ir::Value,
    pub(super) cos: cranelift_codegen::ir::Value,
    pub(super) sin: cranelift_codegen::ir::Value,
}

/// Tells `lower` the values of coordinate q_j (of the angle at `at`, if
/// it is one of the layout's coordinates) and of its cosine and sine,
/// where the graph has those nodes: later ops use them from registers
/// instead of reading the buffer.
pub(super) fn seed(
    lower: &mut Lower<'_>,
    graph: &Graph,
    layout: &Layout,
    at: AngleAt,
    value: cranelift_codegen::ir::Value,
    cos: cranelift_codegen::ir::Value,
    sin: cranelift_codegen::ir::Value,
) {
    let Some(j) = at.value.checked_sub(layout.q) else {
        return;
    };
    if at.trig != layout.trig + 2 * j || at.value >= layout.qd {
        return;
    }
    let Ok(j) = u32::try_from(j) else {
        return;
    };
    let Some(q) = graph.find(&Node::Leaf(Leaf::Q(j))) else {
        return;
    };
    lower.seed(q, value);
    for (f, v) in [(Func::Cos, cos), (Func::Sin, sin)] {
        if let Some(id) = graph.find(&Node::Call(f, q)) {
            lower.seed(id, v);
        }
    }
}

/// Σ xᵢ yᵢ over the pairs, the terms with a factor that is the constant
/// ±0 left out (0 when every term is), a factor that is the constant 1
/// not multiplied by.
pub(super) fn sum_of_products(
    b: &mut FunctionBuilder<'_>,
    pairs: &[(cranelift_codegen::ir::Value, cranelift_codegen::ir::Value)],
) -> cranelift_codegen::ir::Value {
    let mut sum = None;
    for &(x, y) in pairs {
        let (cx, cy) = (constant(b, x), constant(b, y));
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
    sum.unwrap_or_else(|| b.ins().f64const(0.0))
}

/// c₀ − x·(c₁ − x·(c₂ − …)) for the constants `c`, innermost first
/// evaluated (as a series with alternating signs is written).
pub(super) fn alternating(
    b: &mut FunctionBuilder<'_>,
    x: cranelift_codegen::ir::Value,
    c: &[f64],
) -> cranelift_codegen::ir::Value {
    // k − x·t as (−x)·t + k, the same number: the constant is the
    // addition's second operand, which the instruction reads from memory.
    let mut rest = c.iter().rev();
    let mut t = b.ins().f64const(rest.next().copied().unwrap_or(0.0));
    let nx = b.neg(x);
    for &k in rest {
        let m = b.ins().fmul(nx, t);
        let k = b.ins().f64const(k);
        t = b.ins().fadd(m, k);
    }
    t
}

/// Calls the helper with `argument`, then goes on at `join` when it
/// returns 0, else returns its status (through `exit`).
pub(super) fn call_helper(
    b: &mut FunctionBuilder<'_>,
    (fp, cp, helper, exit): HelperCall,
    argument: u64,
    join: cranelift_codegen::ir::Block,
) {
    let arg = b
        .ins()
        .iconst(types::I64, i64::from_ne_bytes(argument.to_ne_bytes()));
    let inst = b.ins().call(helper, &[fp, cp, arg]);
    let status = b.inst_results(inst)[0];
    let failed = b.ins().icmp_imm(IntCC::NotEqual, status, 0);
    b.ins()
        .brif(failed, exit, &[BlockArg::Value(status)], join, &[]);
    b.switch_to_block(join);
}

/// A flag set when one of `values` is not finite (`None` for none): their
/// sum, taken pairwise so that its dependency chain is as short as it can
/// be, is NaN or infinite when one is, and its product with 0 is then NaN
/// (0 for a finite sum). Finite values whose sum overflows (beyond
/// 1.8e308) set the flag too: the caller's general path then decides.
pub(super) fn not_finite(
    b: &mut FunctionBuilder<'_>,
    values: &[cranelift_codegen::ir::Value],
) -> Option<cranelift_codegen::ir::Value> {
    let zero = b.ins().f64const(0.0);
    // A constant is finite (or the check would fail at every call).
    let varying: Vec<_> = values
        .iter()
        .copied()
        .filter(|&v| constant(b, v).is_none_or(f64::is_nan))
        .collect();
    let mut level = varying;
    while level.len() > 1 {
        level = level
            .chunks(2)
            .map(|p| match p {
                [x, y] => b.ins().fadd(*x, *y),
                [x] => *x,
                _ => zero,
            })
            .collect();
    }
    let sum = level.pop()?;
    let test = b.ins().fmul(sum, zero);
    Some(b.ins().fcmp(FloatCC::Unordered, test, test))
}

/// The value of `v` when it is a constant.
pub(super) fn constant(b: &FunctionBuilder<'_>, v: cranelift_codegen::ir::Value) -> Option<f64> {
    let dfg = &b.func.dfg;
    let cranelift_codegen::ir::ValueDef::Result(inst, 0) = dfg.value_def(v) else {
        return None;
    };
    match dfg.insts[inst] {
        cranelift_codegen::ir::InstructionData::UnaryIeee64 { imm, .. } => {
            Some(f64::from_bits(imm.bits()))
        }
        _ => None,
    }
}
