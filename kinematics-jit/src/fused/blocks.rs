//! The small linear algebra of a step in machine code, on one design or
//! on two at once in vector lanes: the factorisation of the scaled
//! diagonal blocks of one or two unknowns ([`Op::FactorSmall`]) and the
//! solve by forward substitution over blocks whose inverses lie in the
//! buffer ([`Op::Solve`]). Each is written once for both: in lanes every
//! number is a vector of two f64 and every flag a mask, each lane
//! computed as the scalar code computes it, operation for operation, and
//! a check fails where it fails in either lane.
//!
//! [`Op::FactorSmall`]: super::Op::FactorSmall
//! [`Op::Solve`]: super::Op::Solve

use std::collections::HashMap;

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{types, InstBuilder, MemFlags, Value};
use cranelift_frontend::FunctionBuilder;
use kinematics_compiler::ir::Id;

use super::emit::{konst, not_finite, Memory};
use super::{SmallBlock, SolveBlock};
use crate::lower::{Imports, Lower, SignBits, Sources};
use crate::JitError;

/// What a failed check emits: `fail(b, failed, status)` returns `status`
/// where the scalar flag `failed` is set, and goes on in a new block
/// otherwise.
pub(super) type Fail<'a> = &'a mut dyn FnMut(&mut FunctionBuilder<'_>, Value, i64);

/// The graph's lowering, as the ops read their roots.
pub(super) type Lowering<'a, 'g> = (&'a mut Lower<'g>, &'a Sources, &'a Imports);

/// |x|.
fn absolute(b: &mut FunctionBuilder<'_>, lanes: bool, x: Value) -> Value {
    if lanes {
        b.ins().fabs(x)
    } else {
        b.abs(x)
    }
}

/// x where `flag` holds, else y (lane by lane in lanes).
fn choose(b: &mut FunctionBuilder<'_>, lanes: bool, flag: Value, x: Value, y: Value) -> Value {
    if lanes {
        // The mask's lanes as the vector's: all ones or zeros.
        let c = b.ins().bitcast(types::F64X2, MemFlags::new(), flag);
        b.ins().bitselect(c, x, y)
    } else {
        b.ins().select(flag, x, y)
    }
}

/// A scalar flag set where `flag` is clear (in lanes: in either lane).
fn not_all(b: &mut FunctionBuilder<'_>, lanes: bool, flag: Value) -> Value {
    let all = if lanes { b.ins().vall_true(flag) } else { flag };
    b.ins().icmp_imm(IntCC::Equal, all, 0)
}

/// A scalar flag set where `flag` is set (in lanes: in either lane).
fn any(b: &mut FunctionBuilder<'_>, lanes: bool, flag: Value) -> Value {
    if lanes {
        b.ins().vany_true(flag)
    } else {
        flag
    }
}

/// [`Op::Solve`](super::Op::Solve): block after block, each row's y =
/// (root − Σ known entry · its unknown) · scale, then each unknown x = (Σ
/// inverse row · y) · its column scale, written at `to + index`; then,
/// with `finite`, that status where an unknown is not finite.
///
/// # Errors
/// A row past the roots, or one reading an unknown not yet solved; an
/// offset past the buffer.
pub(super) fn solve(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    (lower, sources, imports): Lowering<'_, '_>,
    memory: &mut Memory<'_>,
    (rhs, blocks, to, finite): (&[Id], &[SolveBlock], usize, Option<i64>),
    fail: Fail<'_>,
) -> Result<(), JitError> {
    lower.emit(b, sources, imports, rhs)?;
    let mut x: HashMap<usize, Value> = HashMap::new();
    let mut solved = Vec::new();
    for block in blocks {
        let mut ys = Vec::with_capacity(block.rows.len());
        for row in &block.rows {
            let root = *rhs
                .get(row.rhs)
                .ok_or_else(|| JitError::Codegen("a solve's row past its roots".into()))?;
            let mut t = lower.value(b, sources, imports, root)?;
            let mut sum = None;
            for &(e, c) in &row.known {
                let xc = *x.get(&c).ok_or_else(|| {
                    JitError::Codegen("a solve reads an unknown not solved".into())
                })?;
                let entry = memory.load(b, e)?;
                let p = b.ins().fmul(entry, xc);
                sum = Some(match sum {
                    None => p,
                    Some(s) => b.ins().fadd(s, p),
                });
            }
            if let Some(sum) = sum {
                t = b.ins().fsub(t, sum);
            }
            let scale = memory.load(b, row.scale)?;
            ys.push(b.ins().fmul(t, scale));
        }
        let n = ys.len();
        for (i, &(c, scale)) in block.cols.iter().enumerate() {
            let mut acc = None;
            for (j, &y) in ys.iter().enumerate() {
                let m = memory.load(b, block.inverse + i * n + j)?;
                let p = b.ins().fmul(m, y);
                acc = Some(match acc {
                    None => p,
                    Some(a) => b.ins().fadd(a, p),
                });
            }
            let mut v = match acc {
                Some(v) => v,
                None => konst(b, lanes, 0.0),
            };
            if let Some(scale) = scale {
                let s = memory.load(b, scale)?;
                v = b.ins().fmul(v, s);
            }
            memory.store(b, to + c, v)?;
            x.insert(c, v);
            solved.push(v);
        }
    }
    if let (Some(status), Some(failed)) = (finite, not_finite(b, lanes, &solved)) {
        fail(b, failed, status);
    }
    Ok(())
}

/// Where [`factor_small`] reads and writes, and its statuses (the fields
/// of [`Op::FactorSmall`](super::Op::FactorSmall) but the blocks).
pub(super) struct Factoring {
    pub(super) threshold: usize,
    pub(super) branch: usize,
    pub(super) odd: bool,
    pub(super) conditioning: usize,
    pub(super) sign: usize,
    pub(super) singular: i64,
    pub(super) wrong_branch: i64,
}

impl Factoring {
    /// The blocks of an [`Op::FactorSmall`](super::Op::FactorSmall) and
    /// the rest of its fields (`None` for another op).
    pub(super) fn of(op: &super::Op) -> Option<(&[SmallBlock], Self)> {
        let super::Op::FactorSmall {
            blocks,
            threshold,
            branch,
            odd,
            conditioning,
            sign,
            singular,
            wrong_branch,
        } = op
        else {
            return None;
        };
        let at = Self {
            threshold: *threshold,
            branch: *branch,
            odd: *odd,
            conditioning: *conditioning,
            sign: *sign,
            singular: *singular,
            wrong_branch: *wrong_branch,
        };
        Some((blocks, at))
    }
}

/// [`Op::FactorSmall`](super::Op::FactorSmall): each block's entries
/// scaled by their row's and column's factors; a 1 × 1 block a regular
/// where threshold < |a| < ∞, its conditioning |a| and its inverse 1/a;
/// a 2 × 2 block where its first pivot max(|a₀₀|, |a₁₀|) exceeds the
/// threshold and threshold · pivot < |det| < ∞, its inverse
/// [[a₁₁, −a₀₁], [−a₁₀, a₀₀]] / det and its conditioning 1/‖A⁻¹‖_∞ (0
/// when not finite), which must exceed the threshold. Then `singular`
/// where a block is not regular, `wrong_branch` where the branch asked
/// (±1; 0 for either) is not the product of the determinants' signs
/// (negated when `odd`); else the least conditioning and that sign are
/// written.
///
/// # Errors
/// A block of other than one or four entries; an offset past the buffer.
pub(super) fn factor_small(
    b: &mut FunctionBuilder<'_>,
    lanes: bool,
    (lower, sources, imports): Lowering<'_, '_>,
    memory: &mut Memory<'_>,
    (blocks, at): (&[SmallBlock], &Factoring),
    fail: Fail<'_>,
) -> Result<(), JitError> {
    let thr = memory.load(b, at.threshold)?;
    let inf = konst(b, lanes, f64::INFINITY);
    let one = konst(b, lanes, 1.0);
    let zero = konst(b, lanes, 0.0);
    let minus = konst(b, lanes, -1.0);
    let mut least = if blocks.is_empty() { one } else { inf };
    let mut product = if at.odd { minus } else { one };
    // Every block's regularity, tested once after them all (one branch
    // for the op).
    let mut regular_all: Option<Value> = None;
    let mut and = |b: &mut FunctionBuilder<'_>, flag: Value| {
        regular_all = Some(match regular_all {
            None => flag,
            Some(all) => b.ins().band(all, flag),
        });
    };
    for block in blocks {
        let mut a = Vec::with_capacity(block.entries.len());
        for &(root, row, col) in &block.entries {
            let v = lower.value(b, sources, imports, root)?;
            let r = memory.load(b, row)?;
            let mut x = b.ins().fmul(v, r);
            if let Some(col) = col {
                let c = memory.load(b, col)?;
                x = b.ins().fmul(x, c);
            }
            a.push(x);
        }
        // The determinant's sign: ±1 (it is finite and nonzero once the
        // block is regular).
        let signum = |b: &mut FunctionBuilder<'_>, d| {
            let negative = b.ins().fcmp(FloatCC::LessThan, d, zero);
            choose(b, lanes, negative, minus, one)
        };
        let (c, s) = match a.as_slice() {
            [a00] => {
                let p0 = absolute(b, lanes, *a00);
                let above = b.ins().fcmp(FloatCC::GreaterThan, p0, thr);
                let finite = b.ins().fcmp(FloatCC::LessThan, p0, inf);
                let regular = b.ins().band(above, finite);
                and(b, regular);
                let inv = b.ins().fdiv(one, *a00);
                memory.store(b, block.inverse, inv)?;
                (p0, signum(b, *a00))
            }
            [a00, a01, a10, a11] => {
                let (x00, x10) = (absolute(b, lanes, *a00), absolute(b, lanes, *a10));
                // The larger (a `maxsd`, no branch).
                let greater = b.ins().fcmp(FloatCC::LessThan, x00, x10);
                let p0 = choose(b, lanes, greater, x10, x00);
                let m0 = b.ins().fmul(*a00, *a11);
                let m1 = b.ins().fmul(*a01, *a10);
                let det = b.ins().fsub(m0, m1);
                let first = b.ins().fcmp(FloatCC::GreaterThan, p0, thr);
                and(b, first);
                let ad = absolute(b, lanes, det);
                let tp = b.ins().fmul(thr, p0);
                let above = b.ins().fcmp(FloatCC::GreaterThan, ad, tp);
                let finite = b.ins().fcmp(FloatCC::LessThan, ad, inf);
                let regular = b.ins().band(above, finite);
                and(b, regular);
                let inv = b.ins().fdiv(one, det);
                let n01 = if lanes {
                    b.ins().fneg(*a01)
                } else {
                    b.neg(*a01)
                };
                let n10 = if lanes {
                    b.ins().fneg(*a10)
                } else {
                    b.neg(*a10)
                };
                let i00 = b.ins().fmul(*a11, inv);
                let i01 = b.ins().fmul(n01, inv);
                let i10 = b.ins().fmul(n10, inv);
                let i11 = b.ins().fmul(*a00, inv);
                for (k, v) in [i00, i01, i10, i11].into_iter().enumerate() {
                    memory.store(b, block.inverse + k, v)?;
                }
                // 1/‖A⁻¹‖_∞: the larger row sum (the first where they tie
                // or one is NaN).
                let row = |b: &mut FunctionBuilder<'_>, x, y| {
                    let (x, y) = (absolute(b, lanes, x), absolute(b, lanes, y));
                    let s = b.ins().fadd(zero, x);
                    b.ins().fadd(s, y)
                };
                let s0 = row(b, i00, i01);
                let s1 = row(b, i10, i11);
                let second = b.ins().fcmp(FloatCC::LessThan, s0, s1);
                let worst = choose(b, lanes, second, s1, s0);
                let c = b.ins().fdiv(one, worst);
                let ac = absolute(b, lanes, c);
                let finite = b.ins().fcmp(FloatCC::LessThan, ac, inf);
                let c = choose(b, lanes, finite, c, zero);
                let above = b.ins().fcmp(FloatCC::GreaterThan, c, thr);
                and(b, above);
                (c, signum(b, det))
            }
            _ => {
                return Err(JitError::Codegen(
                    "a small block has one or four entries".into(),
                ))
            }
        };
        let smaller = b.ins().fcmp(FloatCC::LessThan, c, least);
        least = choose(b, lanes, smaller, c, least);
        product = b.ins().fmul(product, s);
    }
    if let Some(regular) = regular_all {
        let failed = not_all(b, lanes, regular);
        fail(b, failed, at.singular);
    }
    let wanted = memory.load(b, at.branch)?;
    let asked = b.ins().fcmp(FloatCC::NotEqual, wanted, zero);
    let other = b.ins().fcmp(FloatCC::NotEqual, product, wanted);
    let wrong = b.ins().band(asked, other);
    let failed = any(b, lanes, wrong);
    fail(b, failed, at.wrong_branch);
    memory.store(b, at.conditioning, least)?;
    memory.store(b, at.sign, product)?;
    Ok(())
}
