//! The ops of a fused function and the types they are built from: where
//! the leaves lie in the buffer, the ports, the blocks of the solves and
//! factorisations, the plain instructions of a guarded computation, the
//! helper the code calls back.

use kinematics_compiler::ir::Id;

/// Where the leaves lie in the buffer: the index of the first parameter,
/// coordinate, rate, acceleration, and of cos q₀ (then sin q₀, cos q₁, …),
/// and the buffer's length.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Layout {
    /// p₀.
    pub params: usize,
    /// q₀.
    pub q: usize,
    /// q'₀.
    pub qd: usize,
    /// q''₀.
    pub qdd: usize,
    /// cos q₀.
    pub trig: usize,
    /// The number of values in the buffer.
    pub len: usize,
}

/// One operation of a fused function, in order.
#[derive(Clone, Debug)]
pub enum Op {
    /// `f[at[i]]` = root i; with `finite`, unless every root is finite the
    /// function then returns that status.
    Store {
        /// The roots, nodes of the graph.
        roots: Vec<Id>,
        /// Where each is written.
        at: Vec<usize>,
        /// The status returned when a root is not finite, or (for roots
        /// near 1.8e308) when their sum overflows (`None`: not checked).
        finite: Option<i64>,
    },
    /// status = helper(f, context, argument); unless 0, the function
    /// returns that status at once.
    Call(u64),
    /// `f[at]` = max |root i · `f[scales + i]`|, NaN when any product is NaN.
    MaxScaled {
        /// The roots.
        roots: Vec<Id>,
        /// The first of their factors.
        scales: usize,
        /// Where the maximum is written.
        at: usize,
    },
    /// A linear solve by forward substitution over blocks whose inverses
    /// lie in the buffer: block after block, each row's y = (root − Σ
    /// known entry · its unknown) · scale, then each unknown x = (Σ
    /// inverse row · y) · its column scale, written at `f[to + index]`.
    Solve {
        /// The right-hand sides.
        rhs: Vec<Id>,
        /// The blocks, in the order they are solved.
        blocks: Vec<SolveBlock>,
        /// Where unknown 0 is written.
        to: usize,
        /// The status returned when an unknown is not finite (or, near
        /// 1.8e308, when their sum overflows); `None`: not checked.
        finite: Option<i64>,
    },
    /// The cosine and sine of x = `f[value]` from those of the x₀ carried at
    /// `f[carried..carried + 3]` as (cos x₀, sin x₀, x₀): where
    /// |x − x₀| ≤ `series.step`, rotated by Δ = x − x₀ with sin Δ and
    /// 1 − cos Δ by their series ([`Series`]), written at `f[to]`,
    /// `f[to + 1]` and carried; otherwise (a NaN x₀ among them) by calling
    /// the helper with `fresh`, which computes and writes them.
    CarriedTrig {
        /// Where x lies.
        value: usize,
        /// Where (cos x₀, sin x₀, x₀) lie.
        carried: usize,
        /// Where cos x and sin x are written.
        to: usize,
        /// The helper's argument for a fresh computation.
        fresh: u64,
        /// The largest step rotated by, and the series.
        series: Series,
    },
    /// The scaled diagonal blocks (each entry the root times its row's
    /// and column's scales), of one or two unknowns each, factored as
    /// `kinematics_core::solve::Lu` factors them: a 1 × 1 block a is
    /// regular when threshold < |a| < ∞, its conditioning |a|, its
    /// inverse 1/a; a 2 × 2 block when its first pivot p₀ = max(|a₀₀|,
    /// |a₁₀|) exceeds the threshold and threshold·p₀ < |det| < ∞, its
    /// inverse [[a₁₁, −a₀₁], [−a₁₀, a₀₀]]/det and its conditioning
    /// 1/‖A⁻¹‖_∞ (0 if not finite), which must exceed the threshold too.
    /// The conditioning written is the least of the blocks' (1 without
    /// blocks), the sign the product of the signs of their determinants
    /// (negated when `odd`); the function returns `singular` for a block
    /// not regular, and `wrong_branch` when `f[branch]` is ±1 and the
    /// sign is not it.
    FactorSmall {
        /// The blocks.
        blocks: Vec<SmallBlock>,
        /// Where the singularity threshold lies.
        threshold: usize,
        /// Where the sign asked for lies (0: either).
        branch: usize,
        /// Whether the sign of the product is reversed.
        odd: bool,
        /// Where the conditioning is written.
        conditioning: usize,
        /// Where the sign is written.
        sign: usize,
        /// The status of a singular block.
        singular: i64,
        /// The status of the other branch than asked.
        wrong_branch: i64,
    },
    /// A computation in plain operations with a fast path and a fall-back:
    /// the instructions of `code` are evaluated in order (instruction i
    /// defines [`Val`]`(i)`); where the flag `ok` holds, the values of
    /// `fast` are written at their offsets, else those of `slow` are
    /// written and the helper is called with `helper`, returning its
    /// status unless 0. Past the join, the values at the offsets `keep`
    /// (each written on the fast path, and by the helper on the other)
    /// go on in registers, and where such an offset is a leaf of the
    /// layout (a coordinate, its cosine or sine), later expressions read
    /// that leaf from there.
    Guarded {
        /// The instructions, each reading only values defined before it.
        code: Vec<Inst>,
        /// The flag under which the fast path is taken.
        ok: Val,
        /// What the fast path writes: where, and which value.
        fast: Vec<(usize, Val)>,
        /// What the other path writes before it calls the helper.
        slow: Vec<(usize, Val)>,
        /// The helper's argument.
        helper: u64,
        /// The offsets whose values go on in registers past the join.
        keep: Vec<usize>,
    },
    /// Unless `f[at] <= f[bound]` (false for a NaN), the function returns
    /// `status`.
    AtMost {
        /// The value.
        at: usize,
        /// Its bound.
        bound: usize,
        /// The status returned.
        status: i64,
    },
    /// `f[to..to + len]` = the first `len` values of the array at
    /// `from` (of the ports given to
    /// [`Fused::call_ports`](super::Fused::call_ports)); with `finite`,
    /// unless every one is finite the function then returns that status.
    Import {
        /// The array read.
        from: Port,
        /// Where its first value is written.
        to: usize,
        /// How many values.
        len: usize,
        /// The status returned when a value is not finite, or (for values
        /// near 1.8e308) when their sum overflows (`None`: not checked).
        finite: Option<i64>,
    },
    /// The first `len` values of output array `to` (of the ports given
    /// to [`Fused::call_ports`](super::Fused::call_ports)) =
    /// `f[from..from + len]`.
    Export {
        /// The index of the output array written.
        to: usize,
        /// Where its first value is read.
        from: usize,
        /// How many values.
        len: usize,
    },
    /// Unless `f[from..from + len]` are all finite (and their sum is), the
    /// function returns `status`.
    Finite {
        /// The first value checked.
        from: usize,
        /// How many.
        len: usize,
        /// The status returned when one is not finite.
        status: i64,
    },
}

/// An array a fused function reads or writes besides its buffer: one of
/// the inputs or outputs given to
/// [`Fused::call_ports`](super::Fused::call_ports), by index (below
/// [`PORTS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Port {
    /// `ports.inputs[i]`.
    Input(usize),
    /// `ports.outputs[i]`.
    Output(usize),
}

/// The number of inputs, and of outputs, a fused function may use.
pub const PORTS: usize = 4;

impl Port {
    /// Its slot in the table of pointers handed to the machine code.
    pub(super) fn slot(self) -> Option<usize> {
        match self {
            Port::Input(i) if i < PORTS => Some(i),
            Port::Output(i) if i < PORTS => Some(PORTS + i),
            _ => None,
        }
    }
}

/// One row of a block of an [`Op::Solve`].
#[derive(Clone, Debug)]
pub struct SolveRow {
    /// Its right-hand side: an index into the op's roots.
    pub rhs: usize,
    /// Where its scale lies (the right-hand side, less the known terms,
    /// is multiplied by it).
    pub scale: usize,
    /// The known terms: where each entry lies, and the index of the
    /// unknown (solved in a block before) it multiplies.
    pub known: Vec<(usize, usize)>,
}

/// One diagonal block of an [`Op::Solve`].
#[derive(Clone, Debug)]
pub struct SolveBlock {
    /// Its rows, in the order of the inverse's columns.
    pub rows: Vec<SolveRow>,
    /// Where the inverse of its scaled matrix lies, row by row.
    pub inverse: usize,
    /// Its unknowns, in the order of the inverse's rows: each one's
    /// index, and where its column scale lies (`None`: 1).
    pub cols: Vec<(usize, Option<usize>)>,
}

/// A value of an [`Op::Guarded`] computation: the index of the
/// instruction that defines it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Val(pub u32);

/// How two values are compared by [`Inst::Compare`] (IEEE: every
/// comparison with a NaN is false but [`Compare::NotEqual`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    /// x < y.
    Less,
    /// x ≤ y.
    LessOrEqual,
    /// x > y.
    Greater,
    /// x ≥ y.
    GreaterOrEqual,
    /// x = y (false when either is NaN: x = x tells a number from NaN).
    Equal,
    /// x ≠ y (true when either is NaN).
    NotEqual,
}

/// One instruction of an [`Op::Guarded`] computation: an f64 value, or a
/// flag (a comparison's result, or both of two flags).
#[derive(Clone, Debug, PartialEq)]
pub enum Inst {
    /// The value of a node of the graph.
    Root(Id),
    /// `f[at]`, as the buffer holds it when the op starts.
    Load(usize),
    /// A constant.
    Const(f64),
    /// x + y.
    Add(Val, Val),
    /// x − y.
    Sub(Val, Val),
    /// x · y.
    Mul(Val, Val),
    /// x / y.
    Div(Val, Val),
    /// −x.
    Neg(Val),
    /// |x|.
    Abs(Val),
    /// √x.
    Sqrt(Val),
    /// Σ xᵢ yᵢ over the pairs, a term with a factor that is the constant
    /// ±0 left out (0 when every term is, as the compiler's simplifier
    /// takes 0 · x to 0), a factor that is the constant 1 not multiplied.
    Dot(Vec<(Val, Val)>),
    /// The flag x ⋈ y.
    Compare(Compare, Val, Val),
    /// The flag: both flags hold.
    And(Val, Val),
    /// `if flag { x } else { y }`, without a branch.
    Select(Val, Val, Val),
}

/// The rotation of a [`Op::CarriedTrig`]: the largest step |Δ| it
/// rotates by, and the coefficients of sin Δ = Δ − Δ³ (s₀ − Δ² (s₁ −
/// Δ² (s₂ − Δ² s₃))) and 1 − cos Δ = Δ² (v₀ − Δ² (v₁ − Δ² (v₂ − Δ² (v₃ −
/// Δ² v₄)))), evaluated in that order (so that a caller's own evaluation
/// of the same series gives the same numbers, bit for bit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Series {
    /// The largest |Δ| rotated by.
    pub step: f64,
    /// s₀ … s₃ (1/3!, 1/5!, … for the Taylor series).
    pub sin: [f64; 4],
    /// v₀ … v₄ (1/2!, 1/4!, … for the Taylor series).
    pub vers: [f64; 5],
}

/// One diagonal block of an [`Op::FactorSmall`], of one or two unknowns.
#[derive(Clone, Debug)]
pub struct SmallBlock {
    /// Its entries row by row (1 or 4): the root, where its row's scale
    /// lies, and where its column's scale lies (`None`: 1).
    pub entries: Vec<(Id, usize, Option<usize>)>,
    /// Where the inverse of the scaled block is written, row by row.
    pub inverse: usize,
}

/// What a fused function calls for [`Op::Call`]: with the buffer and the
/// op's argument, a status (0: go on).
pub trait Helper {
    /// The part of the step that `argument` names, in the buffer `f`.
    fn call(&mut self, f: &mut [f64], argument: u64) -> i64;
}

/// The status a fused function returns when its helper panicked (the
/// panic stops at the helper: machine code cannot unwind).
pub const HELPER_PANICKED: i64 = i64::MIN;
