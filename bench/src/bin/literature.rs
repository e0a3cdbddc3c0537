//! The published four-bar path-generation benchmarks
//! (`kinematics_examples::benchmarks`, posed as their sources pose them)
//! solved by the global strategy (seeded random starts in the bounds, each
//! refined by Levenberg–Marquardt with the exact Jacobian, the best ones
//! refined to convergence), in `runs` seeded runs per problem, with
//! Nelder–Mead (argmin) from the best start of each run's first pass on
//! the same objective with the same evaluation budget. Prints a Markdown
//! table: the best E, the share of runs within 1 % of it, the median
//! evaluations and wall time per run.
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin literature [runs] [starts]
//! ```

#![allow(clippy::expect_used)]

use std::time::Instant;

use kinematics_bench::nelder_mead;
use kinematics_examples::benchmarks::{
    drawn, penalised, solve, starting_angles, unknowns, Problem, PROBLEM_A, PROBLEM_B,
};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() {
    let runs: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let starts: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(16);
    println!(
        "| problem | method | best E | runs within 1 % of the best (or E < 1e-20) | median evaluations per run | median time per run | best published or recorded |"
    );
    println!("|---|---|---|---|---|---|---|");
    for p in [PROBLEM_B, PROBLEM_A] {
        rows(&p, runs, starts);
    }
}

/// The results of one method over the runs.
#[derive(Default)]
struct Runs {
    es: Vec<f64>,
    evaluations: Vec<f64>,
    times: Vec<f64>,
}

impl Runs {
    #[allow(clippy::cast_precision_loss)]
    fn add(&mut self, e: f64, evaluations: usize, seconds: f64) {
        self.es.push(e);
        self.evaluations.push(evaluations as f64);
        self.times.push(seconds);
    }

    fn print(&self, p: &Problem, method: &str, runs: u64) {
        let best = self.es.iter().copied().fold(f64::INFINITY, f64::min);
        let near = self
            .es
            .iter()
            .filter(|&&e| e <= best * 1.01 || e < 1e-20)
            .count();
        println!(
            "| {} | {method} | {best:.3e} | {near}/{runs} | {:.0} | {:.0} ms | {:.3e} ({}) |",
            p.name,
            median(self.evaluations.clone()),
            1e3 * median(self.times.clone()),
            p.best_published.0,
            p.best_published.1
        );
    }
}

/// Every run of problem `p`: the global strategy, then Nelder–Mead from
/// the same starting designs with the evaluations the strategy used
/// (shared among the starts), and with ten times as many.
fn rows(p: &Problem, runs: u64, starts: usize) {
    let (mut ours, mut nm1, mut nm10) = (Runs::default(), Runs::default(), Runs::default());
    for seed in 0..runs {
        let t = Instant::now();
        let Some(o) = solve(p, seed, starts, 8) else {
            continue;
        };
        ours.add(o.sum_squares, o.evaluations, t.elapsed().as_secs_f64());
        for (factor, row) in [(1, &mut nm1), (10, &mut nm10)] {
            let t = Instant::now();
            let each = (factor * o.evaluations / starts).max(1) as u64;
            let (mut best, mut used) = (f64::INFINITY, 0);
            for (m, start, mode) in drawn(p, seed, starts) {
                let x0 = unknowns(p, &m, &starting_angles(p, &start));
                let (e, n) = nelder_mead(|x| penalised(p, x, mode), &x0, each);
                best = best.min(e);
                used += n;
            }
            row.add(best, used, t.elapsed().as_secs_f64());
        }
    }
    ours.print(
        p,
        "random starts + Levenberg–Marquardt, exact Jacobian",
        runs,
    );
    nm1.print(
        p,
        "Nelder–Mead (argmin), same starts, same evaluations",
        runs,
    );
    nm10.print(p, "Nelder–Mead, same starts, 10× the evaluations", runs);
}
