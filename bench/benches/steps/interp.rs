//! The same step with the expression DAG of the definition evaluated at
//! run time: what a symbolic library that interprets its expressions does.
//! The DAG is built by the macro's own compiler (parse, check, lower,
//! differentiate); every node is evaluated once per stage, in topological
//! order, into a register file.

use kinematics_core::solve::Lu;

use kinematics_compiler::ir::{Graph, Id, Leaf, Node};

/// A compiled definition with its evaluation schedule.
pub struct Interp {
    g: Graph,
    regs: Vec<f64>,
    params: Vec<f64>,
    nd: usize,
    nu: usize,
    /// Nodes evaluated by each Newton iteration (Φ and Φ_u).
    newton: Vec<usize>,
    /// Then, at the converged pose: −Φ_d d', −Φ_d d'' − γ, outputs.
    vel: Vec<usize>,
    acc: Vec<usize>,
    out: Vec<usize>,
    phi: Vec<Id>,
    jac: Vec<Id>,
    vel_rhs: Vec<Id>,
    acc_rhs: Vec<Id>,
    outputs: Vec<Id>,
}

fn cone(g: &Graph, roots: &[Id], done: &mut [bool]) -> Vec<usize> {
    let live = g.reachable(roots);
    let mut order = Vec::new();
    for i in 0..g.len() {
        if live[i] && !done[i] {
            done[i] = true;
            order.push(i);
        }
    }
    order
}

impl Interp {
    /// Builds the DAG of `tokens` with parameters `params` (in order).
    ///
    /// # Panics
    /// If the definition has errors.
    pub fn new(tokens: proc_macro2::TokenStream, params: Vec<f64>) -> Self {
        let c = kinematics_compiler::compile(tokens).expect("a valid definition");
        let g = c.graph().clone();
        let jac: Vec<Id> = c.jacobian().iter().flatten().copied().collect();
        // The point of interest is the last one declared (the others help
        // to write the loops).
        let mut outputs: Vec<Id> = c
            .points()
            .last()
            .map(|p| [p.position, p.velocity, p.acceleration].concat())
            .unwrap_or_default();
        for f in c.frames() {
            let f = f.roots;
            outputs.extend(f.rotation.iter().flatten().chain(&f.omega).chain(&f.alpha));
        }
        let phi: Vec<Id> = c.residuals().iter().map(|(id, _)| *id).collect();
        let (vel_rhs, acc_rhs) = (c.velocity_rhs().to_vec(), c.acceleration_rhs().to_vec());
        let mut done = vec![false; g.len()];
        let newton_roots: Vec<Id> = phi.iter().chain(&jac).copied().collect();
        let newton = cone(&g, &newton_roots, &mut done);
        let vel = cone(&g, &vel_rhs, &mut done);
        let acc = cone(&g, &acc_rhs, &mut done);
        let out = cone(&g, &outputs, &mut done);
        Interp {
            regs: vec![0.0; g.len()],
            params,
            nd: c.drivers(),
            nu: c.unknowns(),
            newton,
            vel,
            acc,
            out,
            phi,
            jac,
            vel_rhs,
            acc_rhs,
            outputs,
            g,
        }
    }

    fn run(&mut self, nodes: &[usize], q: &[f64], qd: &[f64], qdd: &[f64]) {
        for &i in nodes {
            let r = &self.regs;
            let v = |id: Id| r[id.index()];
            let x = match self.g.node(Id::from_index(i)) {
                Node::Const(bits) => f64::from_bits(bits),
                Node::Leaf(Leaf::Param(k)) => self.params[k as usize],
                Node::Leaf(Leaf::Q(k)) => q[k as usize],
                Node::Leaf(Leaf::Qd(k)) => qd[k as usize],
                Node::Leaf(Leaf::Qdd(k)) => qdd[k as usize],
                // A kinematic graph never reads the time (only loads do).
                Node::Leaf(Leaf::Time) => f64::NAN,
                Node::Add(a, b) => v(a) + v(b),
                Node::Mul(a, b) => v(a) * v(b),
                Node::Div(a, b) => v(a) / v(b),
                Node::Neg(a) => -v(a),
                Node::Powi(a, n) => v(a).powi(n),
                Node::Call(f, a) => f.apply(v(a)),
                Node::Atan2(y, x) => v(y).atan2(v(x)),
            };
            self.regs[i] = x;
        }
    }

    fn get<const N: usize>(&self, ids: &[Id]) -> [f64; N] {
        std::array::from_fn(|k| self.regs[ids[k].index()])
    }

    /// One step; `q`, `qd`, `qdd` as in the other variants.
    pub fn step<const NQ: usize, const NU: usize>(
        &mut self,
        q: &mut [f64; NQ],
        qd: &mut [f64; NQ],
        qdd: &mut [f64; NQ],
    ) -> f64 {
        let (nd, nu) = (self.nd, self.nu);
        debug_assert_eq!(nu, NU);
        let mut jac = [[0.0; NU]; NU];
        let newton = std::mem::take(&mut self.newton);
        for _ in 0..50 {
            self.run(&newton, q, qd, qdd);
            let r: [f64; NU] = self.get(&self.phi);
            for i in 0..NU {
                for k in 0..NU {
                    jac[i][k] = self.regs[self.jac[i * NU + k].index()];
                }
            }
            if r.iter().all(|v| v.abs() < 1e-12) {
                break;
            }
            let Ok(lu) = Lu::factor(&jac, 1e-14) else {
                break;
            };
            let step = lu.solve(&r);
            for k in 0..NU {
                q[nd + k] -= step[k];
            }
        }
        self.newton = newton;
        let lu = Lu::factor(&jac, 0.0).ok();
        let solve = |b: &[f64; NU]| lu.as_ref().map_or([0.0; NU], |l| l.solve(b));
        let vel = std::mem::take(&mut self.vel);
        self.run(&vel, q, qd, qdd);
        self.vel = vel;
        let ud = solve(&self.get(&self.vel_rhs));
        qd[nd..].copy_from_slice(&ud);
        let acc = std::mem::take(&mut self.acc);
        self.run(&acc, q, qd, qdd);
        self.acc = acc;
        let udd = solve(&self.get(&self.acc_rhs));
        qdd[nd..].copy_from_slice(&udd);
        let out = std::mem::take(&mut self.out);
        self.run(&out, q, qd, qdd);
        self.out = out;
        let mut sum: f64 = (nd..NQ).map(|j| q[j] + qd[j] + qdd[j]).sum();
        sum += self
            .outputs
            .iter()
            .map(|id| self.regs[id.index()])
            .sum::<f64>();
        if nd > 1 {
            sum += q[..nd].iter().sum::<f64>();
        }
        sum
    }
}
