//! The pieces of machine code the ops are built from: a guarded
//! computation and its fall-back to the helper, the sums and series, the
//! finiteness checks, the ports' slots.

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{types, BlockArg, InstBuilder, MemFlags};
use cranelift_frontend::FunctionBuilder;
use kinematics_compiler::ir::{Func, Graph, Leaf, Node};

use super::{Compare, Inst, Layout, Port, Val, PORTS};
use crate::lower::{constant, constant_last, Imports, Lower, SignBits, Sources};
use crate::JitError;

/// The buffer as the code reads and writes it, with the values it is
/// known to hold at the point being emitted: a load of one of them is
/// the value itself, from a register, not a reload (a value imported, a
/// coefficient, a scale read twice, the inverse of a block). What the
/// code stored or loaded in a block that dominates the rest is known;
/// everything is forgotten where the helper may have run (a call, the
/// join after a closed form's fall-back), since it can rewrite any value.
///
/// In lanes ([`Memory::in_lanes`]) value i holds both designs' values, a
/// vector of two f64 at byte 16 i, read and written unaligned (the buffer
/// of f64 is aligned to 8 bytes), never trapping (every offset is
/// checked).
pub(super) struct Memory<'w> {
    fp: cranelift_codegen::ir::Value,
    within: &'w dyn Fn(usize) -> Result<i32, JitError>,
    known: std::collections::HashMap<usize, cranelift_codegen::ir::Value>,
    /// F64, or F64X2 in lanes.
    ty: types::Type,
    flags: MemFlags,
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
            ty: types::F64,
            flags: MemFlags::trusted(),
        }
    }

    /// The buffer in lanes at `fp`, every offset (in values of both
    /// designs) checked by `within`.
    pub(super) fn in_lanes(
        fp: cranelift_codegen::ir::Value,
        within: &'w dyn Fn(usize) -> Result<i32, JitError>,
    ) -> Self {
        Self {
            ty: types::F64X2,
            flags: vector_flags(),
            ..Self::new(fp, within)
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
            .load(self.ty, self.flags, self.fp, (self.within)(at)?);
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
        b.ins().store(self.flags, v, self.fp, (self.within)(at)?);
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

/// Vectors are read and written unaligned (the buffer of f64 is aligned
/// to 8 bytes), never trapping (every offset is checked).
pub(super) fn vector_flags() -> MemFlags {
    MemFlags::new().with_notrap()
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

/// What a call to the helper needs: the buffer, the context, the
/// helper's reference and the block that returns a status.
pub(super) type HelperCall = (
    cranelift_codegen::ir::Value,
    cranelift_codegen::ir::Value,
    cranelift_codegen::ir::FuncRef,
    cranelift_codegen::ir::Block,
);

/// What an [`Op::Guarded`](super::Op::Guarded) computes and writes.
pub(super) struct Guard<'o> {
    pub(super) code: &'o [Inst],
    pub(super) ok: Val,
    pub(super) fast: &'o [(usize, Val)],
    pub(super) slow: &'o [(usize, Val)],
    pub(super) helper: u64,
    pub(super) keep: &'o [usize],
}

/// A value an instruction defines: a number or a flag.
#[derive(Clone, Copy)]
pub(super) enum Defined {
    Number(cranelift_codegen::ir::Value),
    Flag(cranelift_codegen::ir::Value),
}

/// A guarded computation's value `v`, a number.
pub(super) fn number_of(
    values: &[Defined],
    v: Val,
) -> Result<cranelift_codegen::ir::Value, JitError> {
    match values.get(v.0 as usize) {
        Some(Defined::Number(x)) => Ok(*x),
        Some(Defined::Flag(_)) => Err(bad_guard("reads a flag as a number")),
        None => Err(bad_guard("reads a value not defined before")),
    }
}

/// A guarded computation's value `v`, a flag.
pub(super) fn flag_of(
    values: &[Defined],
    v: Val,
) -> Result<cranelift_codegen::ir::Value, JitError> {
    match values.get(v.0 as usize) {
        Some(Defined::Flag(x)) => Ok(*x),
        Some(Defined::Number(_)) => Err(bad_guard("reads a number as a flag")),
        None => Err(bad_guard("reads a flag not defined before")),
    }
}

fn bad_guard(what: &str) -> JitError {
    JitError::Codegen(format!("a guarded computation {what}"))
}

/// The values of a guarded computation's instructions, in order (the
/// graph's roots lowered first, together; `load` reads the buffer). In
/// lanes (`lanes`), numbers are vectors of two f64 and flags are lane
/// masks, each lane computed as the scalar code computes it.
pub(super) fn evaluate(
    b: &mut FunctionBuilder<'_>,
    (lower, sources, imports): (&mut Lower<'_>, &Sources, &Imports),
    load: &mut dyn FnMut(
        &mut FunctionBuilder<'_>,
        usize,
    ) -> Result<cranelift_codegen::ir::Value, JitError>,
    code: &[Inst],
    lanes: bool,
) -> Result<Vec<Defined>, JitError> {
    let roots: Vec<_> = code
        .iter()
        .filter_map(|i| match i {
            Inst::Root(id) => Some(*id),
            _ => None,
        })
        .collect();
    lower.emit(b, sources, imports, &roots)?;
    let mut values: Vec<Defined> = Vec::with_capacity(code.len());
    let get = number_of;
    for inst in code {
        let number = |x| Ok::<_, JitError>(Defined::Number(x));
        let defined = match inst {
            Inst::Root(id) => number(lower.value(b, sources, imports, *id)?),
            Inst::Load(at) => number(load(b, *at)?),
            Inst::Const(x) => number(konst(b, lanes, *x)),
            Inst::Add(x, y) => {
                let (x, y) = constant_last(b, get(&values, *x)?, get(&values, *y)?);
                number(b.ins().fadd(x, y))
            }
            Inst::Sub(x, y) => {
                let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                number(b.ins().fsub(x, y))
            }
            Inst::Mul(x, y) => {
                let (x, y) = constant_last(b, get(&values, *x)?, get(&values, *y)?);
                number(b.ins().fmul(x, y))
            }
            Inst::Div(x, y) => {
                let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                number(b.ins().fdiv(x, y))
            }
            Inst::Neg(x) => {
                let x = get(&values, *x)?;
                number(negated(b, lanes, x))
            }
            Inst::Abs(x) => {
                let x = get(&values, *x)?;
                number(if lanes { b.ins().fabs(x) } else { b.abs(x) })
            }
            Inst::Sqrt(x) => {
                let x = get(&values, *x)?;
                number(b.ins().sqrt(x))
            }
            Inst::Dot(pairs) => {
                let pairs = pairs
                    .iter()
                    .map(|&(x, y)| Ok((get(&values, x)?, get(&values, y)?)))
                    .collect::<Result<Vec<_>, JitError>>()?;
                number(sum_of_products(b, lanes, &pairs))
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
                Ok(Defined::Flag(b.ins().fcmp(cc, x, y)))
            }
            Inst::And(x, y) => {
                let (x, y) = (flag_of(&values, *x)?, flag_of(&values, *y)?);
                Ok(Defined::Flag(b.ins().band(x, y)))
            }
            Inst::Select(c, x, y) => {
                let c = flag_of(&values, *c)?;
                let (x, y) = (get(&values, *x)?, get(&values, *y)?);
                if lanes {
                    // The mask's lanes as the vector's: all ones or zeros.
                    let c = b.ins().bitcast(types::F64X2, MemFlags::new(), c);
                    number(b.ins().bitselect(c, x, y))
                } else {
                    number(b.ins().select(c, x, y))
                }
            }
        }?;
        values.push(defined);
    }
    Ok(values)
}

/// Emits a guarded computation: its instructions in order (the graph's
/// roots lowered first, together), the branch on its flag, the fast
/// path's writes, the other path's writes and the helper's call, and the
/// join, past which the kept offsets hold the join's parameters (and the
/// layout's leaves among them are seeded into `lower`).
pub(super) fn guarded(
    b: &mut FunctionBuilder<'_>,
    (lower, sources, imports): (&mut Lower<'_>, &Sources, &Imports),
    (graph, layout): (&Graph, &Layout),
    call: HelperCall,
    memory: &mut Memory<'_>,
    guard: &Guard<'_>,
) -> Result<(), JitError> {
    let bad = |what: &str| JitError::Codegen(format!("a guarded computation {what}"));
    let values = evaluate(
        b,
        (lower, sources, imports),
        &mut |b, at| memory.load(b, at),
        guard.code,
        false,
    )?;
    let get = |values: &[Defined], v: Val| number_of(values, v);
    let flag = |values: &[Defined], v: Val| flag_of(values, v);
    let ok = flag(&values, guard.ok)?;
    // What goes on past the join from the fast path: the value it wrote
    // last at each kept offset.
    let mut kept = Vec::with_capacity(guard.keep.len());
    for &at in guard.keep {
        let &(_, v) = guard
            .fast
            .iter()
            .rev()
            .find(|&&(to, _)| to == at)
            .ok_or_else(|| bad("keeps an offset its fast path does not write"))?;
        kept.push(BlockArg::Value(get(&values, v)?));
    }
    let (fast, slow, join) = (b.create_block(), b.create_block(), b.create_block());
    b.ins().brif(ok, fast, &[], slow, &[]);
    b.switch_to_block(fast);
    for &(to, v) in guard.fast {
        let v = get(&values, v)?;
        memory.write(b, to, v)?;
    }
    let after: Vec<_> = guard
        .keep
        .iter()
        .map(|_| b.append_block_param(join, types::F64))
        .collect();
    b.ins().jump(join, &kept);
    b.switch_to_block(slow);
    for &(to, v) in guard.slow {
        let v = get(&values, v)?;
        memory.write(b, to, v)?;
    }
    let helped = b.create_block();
    call_helper(b, call, guard.helper, helped);
    memory.forget();
    let mut args = Vec::with_capacity(guard.keep.len());
    for &at in guard.keep {
        args.push(BlockArg::Value(memory.load(b, at)?));
    }
    b.ins().jump(join, &args);
    b.switch_to_block(join);
    // Past the join, the buffer holds what either path left: the kept
    // values are the join's parameters; the rest, which the helper may
    // have rewritten, is read afresh.
    memory.forget();
    for (&at, &v) in guard.keep.iter().zip(&after) {
        memory.holds(at, v);
        seed_at(lower, graph, layout, sources.coords, at, v);
    }
    Ok(())
}

/// Where offset `at` of the buffer holds a leaf of the layout (coordinate
/// q_j, or the cosine or sine of q_j) that the graph has, tells `lower`
/// its value: later ops use it from a register instead of reading the
/// buffer.
pub(super) fn seed_at(
    lower: &mut Lower<'_>,
    graph: &Graph,
    layout: &Layout,
    coords: usize,
    at: usize,
    value: cranelift_codegen::ir::Value,
) {
    let leaf = |j: usize| u32::try_from(j).ok().map(|j| Node::Leaf(Leaf::Q(j)));
    let node = match (at.checked_sub(layout.q), at.checked_sub(layout.trig)) {
        (Some(j), _) if j < coords => leaf(j),
        (_, Some(k)) if k < 2 * coords => {
            let f = if k % 2 == 0 { Func::Cos } else { Func::Sin };
            leaf(k / 2)
                .and_then(|q| graph.find(&q))
                .map(|q| Node::Call(f, q))
        }
        _ => None,
    };
    if let Some(id) = node.and_then(|n| graph.find(&n)) {
        lower.seed(id, value);
    }
}

/// The constant x: an f64, or in both lanes of a vector (`lanes`).
pub(super) fn konst(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    x: f64,
) -> cranelift_codegen::ir::Value {
    let c = b.ins().f64const(x);
    if lanes {
        b.ins().splat(types::F64X2, c)
    } else {
        c
    }
}

/// −x (an f64, or both lanes of a vector).
fn negated(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    x: cranelift_codegen::ir::Value,
) -> cranelift_codegen::ir::Value {
    if lanes {
        b.ins().fneg(x)
    } else {
        b.neg(x)
    }
}

/// Σ xᵢ yᵢ over the pairs, the terms with a factor that is the constant
/// ±0 left out (0 when every term is), a factor that is the constant 1
/// not multiplied by (in lanes: vectors, the same in each lane).
pub(super) fn sum_of_products(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
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
            _ => {
                let (x, y) = constant_last(b, x, y);
                b.ins().fmul(x, y)
            }
        };
        sum = Some(match sum {
            None => term,
            Some(s) => b.ins().fadd(s, term),
        });
    }
    sum.unwrap_or_else(|| konst(b, lanes, 0.0))
}

/// c₀ − x·(c₁ − x·(c₂ − …)) for the constants `c`, innermost first
/// evaluated (as a series with alternating signs is written).
fn alternating(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    x: cranelift_codegen::ir::Value,
    c: &[f64],
) -> cranelift_codegen::ir::Value {
    // k − x·t as (−x)·t + k, the same number: the constant is the
    // addition's second operand, which the instruction reads from memory.
    let mut rest = c.iter().rev();
    let mut t = konst(b, lanes, rest.next().copied().unwrap_or(0.0));
    let nx = negated(b, lanes, x);
    for &k in rest {
        let m = b.ins().fmul(nx, t);
        let k = konst(b, lanes, k);
        t = b.ins().fadd(m, k);
    }
    t
}

/// cos x and sin x from the carried c₀ = cos x₀ and s₀ = sin x₀, d =
/// x − x₀ (|d| within the series' step): with sin d = d − d·d²·(s₀ −
/// d²·(s₁ − …)) and 1 − cos d = d²·(v₀ − d²·(v₁ − …)), cos x = c₀ − (c₀
/// vers + s₀ sin) and sin x = s₀ − (s₀ vers − c₀ sin).
pub(super) fn rotated(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    d: cranelift_codegen::ir::Value,
    (c0, s0): (cranelift_codegen::ir::Value, cranelift_codegen::ir::Value),
    series: &super::Series,
) -> (cranelift_codegen::ir::Value, cranelift_codegen::ir::Value) {
    let d2 = b.ins().fmul(d, d);
    let inner = alternating(b, lanes, d2, &series.sin);
    let dd2 = b.ins().fmul(d, d2);
    let t = b.ins().fmul(dd2, inner);
    let sin = b.ins().fsub(d, t);
    let inner = alternating(b, lanes, d2, &series.vers);
    let vers = b.ins().fmul(d2, inner);
    let a = b.ins().fmul(c0, vers);
    let bb = b.ins().fmul(s0, sin);
    let a = b.ins().fadd(a, bb);
    let c = b.ins().fsub(c0, a);
    let a = b.ins().fmul(s0, vers);
    let bb = b.ins().fmul(c0, sin);
    let a = b.ins().fsub(a, bb);
    let sn = b.ins().fsub(s0, a);
    (c, sn)
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
/// 1.8e308) set the flag too: the caller's general path then decides. In
/// lanes (vectors), the flag is set when a lane is not finite.
pub(super) fn not_finite(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    values: &[cranelift_codegen::ir::Value],
) -> Option<cranelift_codegen::ir::Value> {
    let zero = konst(b, lanes, 0.0);
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
    let nan = b.ins().fcmp(FloatCC::Unordered, test, test);
    Some(if lanes { b.ins().vany_true(nan) } else { nan })
}
