//! The lowering of graph nodes to Cranelift instructions, shared by the
//! stages and the fused step: each node once, on demand, in the graph's
//! (topological) order, its value kept for every later use.

use cranelift_codegen::ir::{types, FuncRef, InstBuilder, MemFlags, Value};
use cranelift_frontend::FunctionBuilder;
use kinematics_compiler::ir::{Func, Graph, Id, Leaf, Node};

use crate::JitError;

/// Where the leaves are read: for each of p, q, q', q'' and the cosines
/// and sines of q, a pointer and the index of its first value, with the
/// number of values each holds (p and q).
#[derive(Clone, Copy)]
pub(crate) struct Sources {
    /// Pointers to p, q, q', q'', trig.
    pub(crate) ptr: [Value; 5],
    /// The index (in f64 values) of each array's first value behind its
    /// pointer.
    pub(crate) base: [usize; 5],
    /// The number of parameters.
    pub(crate) params: usize,
    /// The number of coordinates.
    pub(crate) coords: usize,
    /// Where the time t ([`Leaf::Time`]) is read in the parameters'
    /// array, for code that has it (none: the leaf is an error).
    pub(crate) time: Option<usize>,
}

/// The functions the code calls by name, declared in the function being
/// built.
pub(crate) struct Imports {
    pub(crate) refs: Vec<(&'static str, FuncRef)>,
}

impl Imports {
    fn call(
        &self,
        b: &mut FunctionBuilder<'_>,
        name: &str,
        xs: &[Value],
    ) -> Result<Value, JitError> {
        let fref = self
            .refs
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, r)| *r)
            .ok_or_else(|| JitError::Codegen(format!("`{name}` not declared")))?;
        let inst = b.ins().call(fref, xs);
        b.inst_results(inst)
            .first()
            .copied()
            .ok_or_else(|| JitError::Codegen(format!("`{name}` returned nothing")))
    }
}

/// The symbol of a called function (`None`: an instruction instead).
pub(crate) fn symbol(f: Func) -> Option<&'static str> {
    Some(match f {
        Func::Sin => "kinematics_sin",
        Func::Cos => "kinematics_cos",
        Func::Tan => "kinematics_tan",
        Func::Asin => "kinematics_asin",
        Func::Acos => "kinematics_acos",
        Func::Exp => "kinematics_exp",
        Func::Ln => "kinematics_ln",
        Func::Sqrt | Func::Abs => return None,
    })
}

/// The values of the nodes lowered so far in one function.
pub(crate) struct Lower<'g> {
    graph: &'g Graph,
    values: Vec<Option<Value>>,
    /// Nodes read from the leaves' buffer (at the index given, in the
    /// parameters' array) instead of computed: values computed once
    /// beforehand.
    preset: std::collections::HashMap<usize, usize>,
    /// The coordinates whose cosine and sine were read.
    pub(crate) trig: std::collections::BTreeSet<usize>,
    /// Whether a coordinate (or its cosine or sine) was read.
    pub(crate) reads_q: bool,
    /// Whether the time was read.
    pub(crate) reads_time: bool,
    /// Two designs at once: every value a vector of two f64 lanes, every
    /// array interleaved (value j of lane l at 2j + l).
    lanes: bool,
}

impl<'g> Lower<'g> {
    pub(crate) fn new(graph: &'g Graph) -> Self {
        Lower {
            graph,
            values: vec![None; graph.len()],
            preset: std::collections::HashMap::new(),
            trig: std::collections::BTreeSet::new(),
            reads_q: false,
            reads_time: false,
            lanes: false,
        }
    }

    /// The same lowering on two designs at once ([`Lower::lanes`]).
    pub(crate) fn in_lanes(mut self) -> Self {
        self.lanes = true;
        self
    }

    /// The values this lowering computes per value of the graph: 2 in
    /// lanes, else 1.
    pub(crate) fn width(&self) -> usize {
        if self.lanes {
            2
        } else {
            1
        }
    }

    /// The constant `x`, in every lane.
    pub(crate) fn constant(&self, b: &mut FunctionBuilder<'_>, x: f64) -> Value {
        let c = b.ins().f64const(x);
        if self.lanes {
            b.ins().splat(types::F64X2, c)
        } else {
            c
        }
    }

    /// A call of the function `name` of the imports, lane by lane.
    fn call(
        &self,
        b: &mut FunctionBuilder<'_>,
        imports: &Imports,
        name: &str,
        xs: &[Value],
    ) -> Result<Value, JitError> {
        if !self.lanes {
            return imports.call(b, name, xs);
        }
        let mut lanes = [None; 2];
        for (lane, slot) in lanes.iter_mut().enumerate() {
            let args: Vec<Value> = xs
                .iter()
                .map(|&x| b.ins().extractlane(x, lane as u8))
                .collect();
            *slot = Some(imports.call(b, name, &args)?);
        }
        let [Some(x0), Some(x1)] = lanes else {
            return Err(JitError::Codegen(format!("`{name}` in lanes")));
        };
        let v = b.ins().splat(types::F64X2, x0);
        Ok(b.ins().insertlane(v, x1, 1))
    }

    /// Nodes to read at the given indices of the parameters' array
    /// rather than compute (what they depend on is then not evaluated).
    pub(crate) fn with_preset(mut self, preset: &[(Id, usize)]) -> Self {
        self.preset = preset.iter().map(|&(id, at)| (id.index(), at)).collect();
        self
    }

    /// The nodes `roots` need that are not lowered yet, as a mask: the
    /// search stops at lowered and preset nodes.
    fn needed(&self, roots: &[Id]) -> Vec<bool> {
        let mut seen = vec![false; self.graph.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            let i = id.index();
            if i >= seen.len() || seen[i] || self.values[i].is_some() {
                continue;
            }
            seen[i] = true;
            if self.preset.contains_key(&i) {
                continue;
            }
            // A sum with a negated term is a subtraction of the term
            // itself ([`Lower::subtrahend`], the second term's where both
            // are negated, as `emit` chooses): the negation is needed only
            // where something else reads it.
            match self.graph.node(id) {
                Node::Add(x, y) => match (self.subtrahend(x), self.subtrahend(y)) {
                    (_, Some(z)) => stack.extend([x, z]),
                    (Some(z), None) => stack.extend([z, y]),
                    (None, None) => stack.extend([x, y]),
                },
                node => stack.extend(node.children()),
            }
        }
        seen
    }

    /// The value of `id`, lowered with everything it depends on that is
    /// not lowered yet.
    pub(crate) fn value(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        s: &Sources,
        imports: &Imports,
        id: Id,
    ) -> Result<Value, JitError> {
        if let Some(v) = self.values.get(id.index()).copied().flatten() {
            return Ok(v);
        }
        self.emit(b, s, imports, &[id])?;
        self.get(id)
    }

    /// Sets the value of node `id`, computed by the caller (a closed
    /// form's angle, say): later uses take it instead of evaluating or
    /// reading the node.
    pub(crate) fn seed(&mut self, id: Id, value: Value) {
        if let Some(slot) = self.values.get_mut(id.index()) {
            *slot = Some(value);
        }
    }

    /// `z` where `id` is −z, a negation neither lowered nor preset: a
    /// sum reading it is lowered as a subtraction of `z` (x + (−z) and
    /// x − z are the same IEEE operation, bit for bit but for the sign
    /// of a NaN).
    fn subtrahend(&self, id: Id) -> Option<Id> {
        let i = id.index();
        if self.values.get(i).copied().flatten().is_some() || self.preset.contains_key(&i) {
            return None;
        }
        match self.graph.node(id) {
            Node::Neg(z) => Some(z),
            _ => None,
        }
    }

    /// A lowered node's value.
    fn get(&self, id: Id) -> Result<Value, JitError> {
        self.values
            .get(id.index())
            .copied()
            .flatten()
            .ok_or_else(|| {
                JitError::Codegen(format!("node {} used before it is computed", id.index()))
            })
    }

    /// Lowers every node `roots` depend on that is not lowered yet, in the
    /// graph's order.
    pub(crate) fn emit(
        &mut self,
        b: &mut FunctionBuilder<'_>,
        s: &Sources,
        imports: &Imports,
        roots: &[Id],
    ) -> Result<(), JitError> {
        let graph = self.graph;
        let live = self.needed(roots);
        // Lanes are read as unaligned vectors (a Rust array of f64 is
        // aligned to 8 bytes, not 16).
        let (flags, float) = if self.lanes {
            (MemFlags::new().with_notrap(), types::F64X2)
        } else {
            (MemFlags::trusted(), types::F64)
        };
        let width = self.width();
        let offset = |array: usize, j: usize| {
            i32::try_from((s.base[array] + j) * 8 * width)
                .map_err(|_| JitError::Codegen("too many values for one function".into()))
        };
        for (i, &alive) in live.iter().enumerate() {
            if !alive || self.values[i].is_some() {
                continue;
            }
            if let Some(&at) = self.preset.get(&i) {
                let at = offset(0, at)?;
                self.values[i] = Some(b.ins().load(float, flags, s.ptr[0], at));
                continue;
            }
            let node = graph.node(Id::from_index(i));
            // The cosine or sine of a coordinate: read from the array of
            // them, computed once per pose.
            if let Node::Call(f @ (Func::Sin | Func::Cos), x) = node {
                if let Node::Leaf(Leaf::Q(j)) = graph.node(x) {
                    let j = j as usize;
                    if j < s.coords {
                        self.trig.insert(j);
                        self.reads_q = true;
                        let slot = 2 * j + usize::from(f == Func::Sin);
                        let at = offset(4, slot)?;
                        self.values[i] = Some(b.ins().load(float, flags, s.ptr[4], at));
                        continue;
                    }
                }
            }
            let value = match node {
                Node::Const(bits) => self.constant(b, f64::from_bits(bits)),
                Node::Leaf(leaf) => {
                    let (array, index, len) = match leaf {
                        Leaf::Param(j) => (0, j, s.params),
                        Leaf::Q(j) => (1, j, s.coords),
                        Leaf::Qd(j) => (2, j, s.coords),
                        Leaf::Qdd(j) => (3, j, s.coords),
                        Leaf::Time => match s.time {
                            Some(at) => (0, u32::try_from(at).unwrap_or(u32::MAX), at + 1),
                            None => return Err(JitError::Leaf(leaf)),
                        },
                    };
                    let j = index as usize;
                    if j >= len {
                        return Err(JitError::Leaf(leaf));
                    }
                    if array == 1 {
                        self.reads_q = true;
                    }
                    if leaf == Leaf::Time {
                        self.reads_time = true;
                    }
                    let at = offset(array, j)?;
                    b.ins().load(float, flags, s.ptr[array], at)
                }
                Node::Add(x, y) => match (self.subtrahend(x), self.subtrahend(y)) {
                    (_, Some(z)) => {
                        let (x, z) = (self.get(x)?, self.get(z)?);
                        b.ins().fsub(x, z)
                    }
                    (Some(z), None) => {
                        let (y, z) = (self.get(y)?, self.get(z)?);
                        b.ins().fsub(y, z)
                    }
                    (None, None) => {
                        let (x, y) = constant_last(b, self.get(x)?, self.get(y)?);
                        b.ins().fadd(x, y)
                    }
                },
                Node::Mul(x, y) => {
                    let (x, y) = constant_last(b, self.get(x)?, self.get(y)?);
                    b.ins().fmul(x, y)
                }
                Node::Div(x, y) => {
                    let (x, y) = (self.get(x)?, self.get(y)?);
                    b.ins().fdiv(x, y)
                }
                Node::Neg(x) => {
                    let x = self.get(x)?;
                    if self.lanes {
                        b.ins().fneg(x)
                    } else {
                        b.neg(x)
                    }
                }
                Node::Powi(x, n) => {
                    let x = self.get(x)?;
                    let one = self.constant(b, 1.0);
                    powi(b, x, n, one)
                }
                Node::Call(f, x) => {
                    let x = self.get(x)?;
                    match (f, symbol(f)) {
                        (Func::Sqrt, _) => b.ins().sqrt(x),
                        (Func::Abs, _) if self.lanes => b.ins().fabs(x),
                        (Func::Abs, _) => b.abs(x),
                        (_, Some(name)) => self.call(b, imports, name, &[x])?,
                        (_, None) => return Err(JitError::Codegen(format!("no code for {f:?}"))),
                    }
                }
                Node::Atan2(y, x) => {
                    let (y, x) = (self.get(y)?, self.get(x)?);
                    self.call(b, imports, "kinematics_atan2", &[y, x])?
                }
            };
            self.values[i] = Some(value);
        }
        Ok(())
    }
}

/// The operands of a commutative operation (a sum or a product) with a
/// constant second: the x86-64 back end reads a second operand that is a
/// constant from the constant pool within the instruction, where a first
/// one is built in a register (two instructions, and a register held).
/// The result is the same number either way: IEEE 754 addition and
/// multiplication commute (a NaN's payload aside).
pub(crate) fn constant_last(b: &FunctionBuilder<'_>, x: Value, y: Value) -> (Value, Value) {
    if constant(b, x).is_some() && constant(b, y).is_none() {
        (y, x)
    } else {
        (x, y)
    }
}

/// The value of `v` when it is a constant.
pub(crate) fn constant(b: &FunctionBuilder<'_>, v: Value) -> Option<f64> {
    let dfg = &b.func.dfg;
    let cranelift_codegen::ir::ValueDef::Result(inst, 0) = dfg.value_def(v) else {
        return None;
    };
    match dfg.insts[inst] {
        cranelift_codegen::ir::InstructionData::UnaryIeee64 { imm, .. } => {
            Some(f64::from_bits(imm.bits()))
        }
        // A constant in both lanes of a vector.
        cranelift_codegen::ir::InstructionData::Unary {
            opcode: cranelift_codegen::ir::Opcode::Splat,
            arg,
        } => constant(b, arg),
        _ => None,
    }
}

/// |x| and −x as bitwise operations with a constant mask (clearing or
/// flipping the sign bit: the same bits as `fabs` and `fneg`), which
/// the x86-64 back end reads from the constant pool in one instruction
/// where its `fabs` and `fneg` first build the mask in a register.
pub(crate) trait SignBits {
    /// |x|.
    fn abs(&mut self, x: Value) -> Value;
    /// −x.
    fn neg(&mut self, x: Value) -> Value;
}

impl SignBits for FunctionBuilder<'_> {
    fn abs(&mut self, x: Value) -> Value {
        let mask = self.ins().f64const(f64::from_bits(0x7fff_ffff_ffff_ffff));
        self.ins().band(x, mask)
    }
    fn neg(&mut self, x: Value) -> Value {
        let mask = self.ins().f64const(f64::from_bits(0x8000_0000_0000_0000));
        self.ins().bxor(x, mask)
    }
}

/// xⁿ by binary powering, as the standard library's `powi` computes it
/// (r = 1; for each bit of |n| from the lowest: r ← r·x where it is set,
/// x ← x²), then 1/r for n < 0; `one` is 1 in x's type.
fn powi(b: &mut FunctionBuilder<'_>, x: Value, n: i32, one: Value) -> Value {
    let mut bits = n.unsigned_abs();
    let mut base = x;
    let mut r: Option<Value> = None;
    loop {
        if bits & 1 == 1 {
            r = Some(match r {
                None => base,
                Some(r) => b.ins().fmul(r, base),
            });
        }
        bits >>= 1;
        if bits == 0 {
            break;
        }
        base = b.ins().fmul(base, base);
    }
    let r = r.unwrap_or(one);
    if n < 0 {
        b.ins().fdiv(one, r)
    } else {
        r
    }
}
