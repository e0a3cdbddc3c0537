//! Benchmarks of the code `mechanism!` generates; see `benches/steps/`.
//!
//! `cargo bench -p kinematics-bench --bench steps` prints the table of the
//! README's performance section.

use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;

/// CPU time of the calling thread, in nanoseconds: what the benchmarks
/// time, so that other jobs on the machine count only through the caches
/// and the clock they share.
///
/// # Panics
/// If the clock cannot be read (it always can on Linux).
#[must_use]
pub fn thread_cpu_ns() -> f64 {
    cpu_ns(libc::CLOCK_THREAD_CPUTIME_ID)
}

/// CPU time of the whole process (every thread), in nanoseconds: for
/// work a thread pool runs on the caller's behalf.
///
/// # Panics
/// If the clock cannot be read (it always can on Linux).
#[must_use]
pub fn process_cpu_ns() -> f64 {
    cpu_ns(libc::CLOCK_PROCESS_CPUTIME_ID)
}

/// The run-time model of the example definition `file` of
/// `examples/mechanisms/` with the parameter values `values`.
///
/// # Panics
/// If the file cannot be read, does not compile, or the values are not
/// the model's (a benchmark's set-up that must not fail).
#[must_use]
#[allow(clippy::expect_used)]
pub fn example_model(file: &str, values: &[f64]) -> kinematics_core::runtime::Model {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/mechanisms/");
    let text = std::fs::read_to_string(format!("{root}{file}")).expect("the example");
    kinematics_core::runtime::Model::compile(&text)
        .expect("compiled")
        .with_values(values)
        .expect("the values")
}

/// The median, the least and the largest of `v` (sorted in place).
///
/// # Panics
/// If `v` is empty.
pub fn spread(v: &mut [f64]) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    (v[v.len() / 2], v[0], v[v.len() - 1])
}

/// The CPU-time clock `clock`, in nanoseconds.
#[allow(unsafe_code)]
fn cpu_ns(clock: libc::clockid_t) -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to write into.
    let rc = unsafe { libc::clock_gettime(clock, &raw mut t) };
    assert_eq!(rc, 0, "clock_gettime({clock})");
    #[allow(clippy::cast_precision_loss)]
    let ns = t.tv_sec as f64 * 1e9 + t.tv_nsec as f64;
    ns
}

/// E as a cost for argmin, counting its evaluations.
struct Cost<F: Fn(&[f64]) -> f64>(F, std::cell::Cell<usize>);

impl<F: Fn(&[f64]) -> f64> CostFunction for Cost<F> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        self.1.set(self.1.get() + 1);
        Ok((self.0)(x))
    }
}

/// Nelder–Mead from `x0` (simplex: x0 and x0 + 10 % of each coordinate,
/// or + 0.1), at most `iterations`: (best E, evaluations).
///
/// # Panics
/// If argmin rejects the set-up (it does not for a finite `x0`).
#[allow(clippy::expect_used)]
pub fn nelder_mead(f: impl Fn(&[f64]) -> f64, x0: &[f64], iterations: u64) -> (f64, usize) {
    let mut simplex = vec![x0.to_vec()];
    for i in 0..x0.len() {
        let mut x = x0.to_vec();
        x[i] += if x[i].abs() > 1e-3 { 0.1 * x[i] } else { 0.1 };
        simplex.push(x);
    }
    let cost = Cost(f, std::cell::Cell::new(0));
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-30)
        .expect("a valid tolerance");
    let res = Executor::new(cost, solver)
        .configure(|s| s.max_iters(iterations))
        .run()
        .expect("Nelder–Mead runs");
    let best = res.state().get_best_cost();
    (
        best,
        res.problem().problem.as_ref().map_or(0, |c| c.1.get()),
    )
}

/// E as the objective of differential evolution, with its bounds,
/// counting its evaluations.
struct Objective<F: Fn(&[f64]) -> f64> {
    f: F,
    bounds: Vec<[f64; 2]>,
    evaluations: std::cell::Cell<usize>,
    /// The evaluations spent when the best E first reached the target.
    reached: std::cell::Cell<Option<usize>>,
    target: f64,
}

impl<F: Fn(&[f64]) -> f64> metaheuristics_nature::Bounded for Objective<F> {
    fn bound(&self) -> &[[f64; 2]] {
        &self.bounds
    }
}

impl<F: Fn(&[f64]) -> f64> metaheuristics_nature::ObjFunc for Objective<F> {
    type Ys = f64;
    fn fitness(&self, x: &[f64]) -> f64 {
        let n = self.evaluations.get() + 1;
        self.evaluations.set(n);
        let e = (self.f)(x);
        if e <= self.target && self.reached.get().is_none() {
            self.reached.set(Some(n));
        }
        e
    }
}

/// What a run of differential evolution found: the best E, the
/// evaluations spent, and those spent when E first reached the target
/// (`None`: not within the budget).
#[derive(Debug, Clone, Copy)]
pub struct Evolved {
    /// The best E.
    pub best: f64,
    /// The evaluations spent.
    pub evaluations: usize,
    /// The evaluations spent when E first reached the target.
    pub to_target: Option<usize>,
}

/// Differential evolution (`metaheuristics-nature`'s `De` with its
/// default strategy and factors, a population of `population`) on `f`
/// within `bounds`, seeded, until `budget` evaluations are spent or E
/// reaches `target`.
pub fn differential_evolution(
    f: impl Fn(&[f64]) -> f64,
    bounds: &[[f64; 2]],
    seed: u64,
    population: usize,
    budget: usize,
    target: f64,
) -> Evolved {
    use metaheuristics_nature::{De, Solver};
    let objective = Objective {
        f,
        bounds: bounds.to_vec(),
        evaluations: std::cell::Cell::new(0),
        reached: std::cell::Cell::new(None),
        target,
    };
    let s = Solver::build(De::default(), objective)
        .seed(seed)
        .pop_num(population)
        .task(|ctx| {
            ctx.func.evaluations.get() + population > budget || ctx.func.reached.get().is_some()
        })
        .solve();
    let func = s.func();
    Evolved {
        best: *s.as_best_fit(),
        evaluations: func.evaluations.get(),
        to_target: func.reached.get(),
    }
}
