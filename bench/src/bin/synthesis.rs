//! The synthesis benchmark: the literature's path-generation problems
//! (`kinematics_examples::literature`) solved from seeded random starting
//! designs by Levenberg–Marquardt with the exact Jacobian, and by
//! Nelder–Mead (argmin) from the same starts on the same objective, in one
//! run. Prints a Markdown table: successes (E < 1e-20), best E, median
//! evaluations and wall time per start.
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin synthesis [starts]
//! ```

#![allow(clippy::expect_used)]

use std::time::Instant;

use kinematics_bench::nelder_mead;
use kinematics_examples::synthesis_runs::{
    evenly, morgan_wampler, morgan_wampler_objective, morgan_wampler_start, nine_point,
    nine_point_objective, nine_point_start,
};

fn median(mut v: Vec<usize>) -> usize {
    v.sort_unstable();
    v.get(v.len() / 2).copied().unwrap_or(0)
}

struct Row {
    method: &'static str,
    ok: usize,
    ok6: usize,
    best: f64,
    evals: Vec<usize>,
    secs: f64,
}

fn print(problem: &str, starts: usize, rows: &[Row]) {
    for r in rows {
        #[allow(clippy::cast_precision_loss)]
        let per = 1e3 * r.secs / starts as f64;
        println!(
            "| {problem} | {} | {}/{starts} | {}/{starts} | {:.1e} | {} | {per:.2} ms |",
            r.method,
            r.ok,
            r.ok6,
            r.best,
            median(r.evals.clone()),
        );
    }
}

/// One start's Levenberg–Marquardt run: its E, its evaluations, the start
/// as a vector of unknowns and the objective E for Nelder–Mead.
type Run = (f64, usize, Vec<f64>, Box<dyn Fn(&[f64]) -> f64>);

impl Row {
    fn new(method: &'static str) -> Self {
        Self {
            method,
            ok: 0,
            ok6: 0,
            best: f64::INFINITY,
            evals: vec![],
            secs: 0.0,
        }
    }

    fn add(&mut self, e: f64, evaluations: usize, secs: f64) {
        self.secs += secs;
        self.ok += usize::from(e < 1e-20);
        self.ok6 += usize::from(e < 1e-6);
        self.best = self.best.min(e);
        self.evals.push(evaluations);
    }
}

/// Both methods from each of `starts` seeded starts (`run` does the
/// Levenberg–Marquardt run and returns what Nelder–Mead starts from).
fn compare(starts: u64, nm_iterations: u64, run: impl Fn(u64) -> Run) -> [Row; 2] {
    let mut lm = Row::new("Levenberg–Marquardt, exact Jacobian");
    let mut nm = Row::new("Nelder–Mead (argmin)");
    for seed in 0..starts {
        let t = Instant::now();
        let (e, n, x0, f) = run(seed);
        lm.add(e, n, t.elapsed().as_secs_f64());
        let t = Instant::now();
        let (e, n) = nelder_mead(f, &x0, nm_iterations);
        nm.add(e, n, t.elapsed().as_secs_f64());
    }
    [lm, nm]
}

fn main() {
    let starts: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let nm_iterations = 20_000;
    println!("| problem | method | E < 1e-20 | E < 1e-6 | best E | median evaluations | time per start |");
    println!("|---|---|---|---|---|---|---|");
    #[allow(clippy::cast_possible_truncation)]
    let n = starts as usize;
    // Morgan and Wampler's Problem 7.
    let rows = compare(starts, nm_iterations, |seed| {
        let r = morgan_wampler(seed).expect("the start assembles");
        let (m, start, modes) = morgan_wampler_start(seed);
        let mut x0 = vec![m.a, m.b, m.c, m.p, m.beta];
        x0.extend(evenly(start.phi, 5));
        (
            r.sum_squares,
            r.evaluations + r.jacobians,
            x0,
            Box::new(move |x: &[f64]| morgan_wampler_objective(x, &modes)),
        )
    });
    print("Morgan–Wampler 1990, Problem 7 (5 points)", n, &rows);
    // The nine-point problem.
    let rows = compare(starts, nm_iterations, |seed| {
        let r = nine_point(seed).expect("the start assembles");
        let (m, start, modes) = nine_point_start(seed);
        let mut x0 = vec![m.x0, m.y0, m.theta0, m.d, m.a, m.b, m.c, m.p, m.beta];
        x0.extend(evenly(start.phi, 9));
        (
            r.sum_squares,
            r.evaluations + r.jacobians,
            x0,
            Box::new(move |x: &[f64]| nine_point_objective(x, &modes)),
        )
    });
    print("Wampler–Morgan–Sommese 1992, nine points", n, &rows);
}
