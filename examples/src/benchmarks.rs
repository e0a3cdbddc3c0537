//! The published four-bar path-generation benchmarks, posed as their
//! sources pose them (the formulation of the HCDJ code of Nguyen-Van et
//! al., Symmetry 2022, which the ECA code and Peñuñuri's agree with), and
//! their solution by the library's global search
//! (`kinematics_core::synthesis::Search`).

use kinematics_core::closed::{AllModes, Mode};
use kinematics_core::mechanism;
use kinematics_core::synthesis::{Search, Synthesis, Timing};
use std::f64::consts::{PI, TAU};

mechanism! {
    /// The four-bar of the benchmarks: crank pivot O2 = (x0, y0), ground
    /// link O2O4 = r1 at the angle θ0, crank O2A = r2 at θ2 from the ground
    /// link, coupler AB = r3 at θ3 and rocker O4B = r4 at θ4 (both from the
    /// x axis), coupler point C at (rcx, rcy) in the coupler's frame (x
    /// along AB, origin at A).
    pub struct BenchmarkFourBar {
        params {
            /// Ground link O2O4.
            r1,
            /// Crank O2A.
            r2,
            /// Coupler AB.
            r3,
            /// Rocker O4B.
            r4,
            /// Coupler point, along AB.
            rcx,
            /// Coupler point, across AB.
            rcy,
            /// x of the crank pivot O2.
            x0,
            /// y of the crank pivot O2.
            y0,
            /// Direction of the ground link (rad).
            t0
        }
        drivers  { th2 }
        unknowns { th3, th4 }
        points {
            /// Crank pivot (fixed).
            O2 = vec2(x0, y0);
            /// Rocker pivot (fixed).
            O4 = O2 + polar(r1, t0);
            /// Crank pin.
            A = O2 + polar(r2, th2 + t0);
            /// Rocker pin.
            B = O4 + polar(r4, th4);
            /// Coupler point.
            C = A + polar(rcx, th3) + polar(rcy, th3 + 1.5707963267948966);
        }
        loops { A + polar(r3, th3) == B; }
        sensitivities { r1, r2, r3, r4, rcx, rcy, x0, y0, t0 }
    }
}

/// Whether `pose` is on the benchmarks' assembly branch: with the crank
/// pivot at the origin and the ground link along x (O4 = (r1, 0)), the
/// crank pin A and the rocker pin B satisfy (A − O4) × (B − O4) < 0.
#[must_use]
pub fn on_branch(m: &BenchmarkFourBar, pose: &BenchmarkFourBarCoords) -> bool {
    let (ax, ay) = (m.r2 * pose.th2.cos() - m.r1, m.r2 * pose.th2.sin());
    let th4 = pose.th4 - m.t0;
    let (bx, by) = (m.r4 * th4.cos(), m.r4 * th4.sin());
    ax * by - ay * bx < 0.0
}

/// How a problem times its targets.
#[derive(Debug, Clone, Copy)]
pub enum Posed {
    /// Every crank angle a variable.
    Free,
    /// The crank angles given.
    Prescribed(&'static [f64]),
    /// The increments of the crank angle from the first target given,
    /// the first angle a variable.
    Relative(&'static [f64]),
}

/// One benchmark problem as its source poses it.
#[derive(Debug, Clone, Copy)]
pub struct Problem {
    /// Its letter in the benchmark collection.
    pub name: &'static str,
    /// The targets, in order.
    pub targets: &'static [[f64; 2]],
    /// The timing.
    pub timing: Posed,
    /// The parameters varied, each with its bounds; the others are 0.
    pub bounds: &'static [(&'static str, f64, f64)],
    /// The best error published or recorded for it, and by whom.
    pub best_published: (f64, &'static str),
}

/// Problem A: six points on a vertical line, no prescribed timing
/// (HCDJ "Case1"; IMECE2019 "Case Study II"): lengths in [0, 60], the
/// coupler point and the pivot in [−60, 60], θ0 in [0, 2π]; Grashof with
/// the crank the shortest link. The global optimum is 0 (designs that
/// pass through the six points exactly exist inside the bounds).
pub const PROBLEM_A: Problem = Problem {
    name: "A",
    targets: &[
        [20.0, 20.0],
        [20.0, 25.0],
        [20.0, 30.0],
        [20.0, 35.0],
        [20.0, 40.0],
        [20.0, 45.0],
    ],
    timing: Posed::Free,
    bounds: &square_bounds(60.0),
    best_published: (
        1.96e-20,
        "ECA's recorded best (jmejia8/eca-four-bar-mechanisms); 4.07e-12 by Lin and Hsiao's DE",
    ),
};

/// The bounds of the problems posed over a square of half-side `l`:
/// every length in [0, l], the coupler point and the crank pivot in
/// [−l, l], θ0 in [0, 2π].
const fn square_bounds(l: f64) -> [(&'static str, f64, f64); 9] {
    [
        ("r1", 0.0, l),
        ("r2", 0.0, l),
        ("r3", 0.0, l),
        ("r4", 0.0, l),
        ("rcx", -l, l),
        ("rcy", -l, l),
        ("x0", -l, l),
        ("y0", -l, l),
        ("t0", 0.0, TAU),
    ]
}

/// The crank angles of Problem B: 30°, 45°, 60°, 75° and 90°.
const B_TIMING: [f64; 5] = [PI / 6.0, PI / 4.0, PI / 3.0, 5.0 * PI / 12.0, PI / 2.0];

/// Problem B: five points with prescribed crank angles (HCDJ "Case2"):
/// the crank pivot at the origin and the ground link along x, lengths in
/// [0, 50], the coupler point in [−50, 50]; Grashof.
pub const PROBLEM_B: Problem = Problem {
    name: "B",
    targets: &[
        [3.0, 3.0],
        [2.759, 3.363],
        [2.372, 3.663],
        [1.890, 3.862],
        [1.355, 3.943],
    ],
    timing: Posed::Prescribed(&B_TIMING),
    bounds: &[
        ("r1", 0.0, 50.0),
        ("r2", 0.0, 50.0),
        ("r3", 0.0, 50.0),
        ("r4", 0.0, 50.0),
        ("rcx", -50.0, 50.0),
        ("rcy", -50.0, 50.0),
    ],
    best_published: (1.284e-6, "MUMSA, recomputed in the HCDJ code"),
};

/// The crank's 20° steps of Problem C from its first target.
const C_STEPS: [f64; 18] = [
    0.0,
    PI / 9.0,
    2.0 * PI / 9.0,
    3.0 * PI / 9.0,
    4.0 * PI / 9.0,
    5.0 * PI / 9.0,
    6.0 * PI / 9.0,
    7.0 * PI / 9.0,
    8.0 * PI / 9.0,
    PI,
    10.0 * PI / 9.0,
    11.0 * PI / 9.0,
    12.0 * PI / 9.0,
    13.0 * PI / 9.0,
    14.0 * PI / 9.0,
    15.0 * PI / 9.0,
    16.0 * PI / 9.0,
    17.0 * PI / 9.0,
];

/// Problem C: eighteen points of a closed path, the crank advancing 20°
/// from one target to the next, its first angle free (HCDJ "Case3"):
/// lengths in [0, 50], the coupler point and the pivot in [−50, 50], θ0
/// in [0, 2π]; Grashof. The best value recorded depends on the bounds
/// (its ground link is at 49.8).
pub const PROBLEM_C: Problem = Problem {
    name: "C",
    targets: &[
        [0.5, 1.1],
        [0.4, 1.1],
        [0.3, 1.1],
        [0.2, 1.0],
        [0.1, 0.9],
        [0.05, 0.75],
        [0.02, 0.6],
        [0.0, 0.5],
        [0.0, 0.4],
        [0.03, 0.3],
        [0.1, 0.25],
        [0.15, 0.2],
        [0.2, 0.3],
        [0.3, 0.4],
        [0.4, 0.5],
        [0.5, 0.7],
        [0.6, 0.9],
        [0.6, 1.0],
    ],
    timing: Posed::Relative(&C_STEPS),
    bounds: &square_bounds(50.0),
    best_published: (0.016_078, "HCDJ's recorded best (Nguyen-Van et al. 2022)"),
};

/// Problem E: ten points of an ellipse, the first and last the same, no
/// prescribed timing (HCDJ "Case5"): lengths in [0, 80], the coupler
/// point and the pivot in [−80, 80], θ0 in [0, 2π]; Grashof, crank
/// angles in sequence.
pub const PROBLEM_E: Problem = Problem {
    name: "E",
    targets: &[
        [20.0, 10.0],
        [17.66, 15.142],
        [11.736, 17.878],
        [5.0, 16.928],
        [0.60307, 12.736],
        [0.60307, 7.2638],
        [5.0, 3.0718],
        [11.736, 2.1215],
        [17.66, 4.8577],
        [20.0, 10.0],
    ],
    timing: Posed::Free,
    bounds: &square_bounds(80.0),
    best_published: (4.02e-4, "Lin and Hsiao's DE, recomputed in the HCDJ code"),
};

/// Problem F: 25 points, no prescribed timing (Laribi, Mlika, Romdhane
/// and Zeghloul, MMT 39 (2004) 717–735, as IMECE2019 gives them). The
/// paper states no bounds; these enclose every published design: lengths
/// in [0, 20], the coupler point and the pivot in [−20, 20], θ0 in
/// [0, 2π]; Grashof, crank angles in sequence (the ant search's score,
/// the nearest crank angle on a 1° grid with no order, is looser).
pub const PROBLEM_F: Problem = Problem {
    name: "F",
    targets: &[
        [7.03, 5.99],
        [6.95, 5.45],
        [6.77, 5.03],
        [6.4, 4.6],
        [5.91, 4.03],
        [5.43, 3.56],
        [4.93, 2.94],
        [4.67, 2.6],
        [4.38, 2.2],
        [4.04, 1.67],
        [3.76, 1.22],
        [3.76, 1.97],
        [3.76, 2.78],
        [3.76, 3.56],
        [3.76, 4.34],
        [3.76, 4.91],
        [3.76, 5.47],
        [3.8, 5.98],
        [4.07, 6.4],
        [4.53, 6.75],
        [5.07, 6.85],
        [5.05, 6.84],
        [5.89, 6.83],
        [6.41, 6.8],
        [6.92, 6.58],
    ],
    timing: Posed::Free,
    bounds: &square_bounds(20.0),
    best_published: (0.1814, "dynamic ant search, IMECE2019-10262"),
};

/// Problem G: eight points, no prescribed timing (McDougall and Nokleby,
/// IDETC/CIE 2008, as IMECE2019 gives them): lengths in [0.1, 5], the
/// coupler point in [0.1, 4], the pivot in [−4, 4], θ0 in [−90°, 90°];
/// Grashof, crank angles in sequence (stricter than the ant search's
/// score).
pub const PROBLEM_G: Problem = Problem {
    name: "G",
    targets: &[
        [2.6, 1.6],
        [2.3, 1.6],
        [2.0, 1.6],
        [1.7, 1.6],
        [1.4, 1.6],
        [1.0, 1.3],
        [2.0, 0.7],
        [3.0, 1.3],
    ],
    timing: Posed::Free,
    bounds: &[
        ("r1", 0.1, 5.0),
        ("r2", 0.1, 5.0),
        ("r3", 0.1, 5.0),
        ("r4", 0.1, 5.0),
        ("rcx", 0.1, 4.0),
        ("rcy", 0.1, 4.0),
        ("x0", -4.0, 4.0),
        ("y0", -4.0, 4.0),
        ("t0", -PI / 2.0, PI / 2.0),
    ],
    best_published: (1.61e-3, "dynamic ant search, IMECE2019-10262"),
};

/// The parameters in the benchmarks' order.
const NAMES: [&str; 9] = ["r1", "r2", "r3", "r4", "rcx", "rcy", "x0", "y0", "t0"];

/// `m` with parameter `name` set to `v`.
fn set(m: &mut BenchmarkFourBar, name: &str, v: f64) {
    match name {
        "r1" => m.r1 = v,
        "r2" => m.r2 = v,
        "r3" => m.r3 = v,
        "r4" => m.r4 = v,
        "rcx" => m.rcx = v,
        "rcy" => m.rcy = v,
        "x0" => m.x0 = v,
        "y0" => m.y0 = v,
        _ => m.t0 = v,
    }
}

/// The design's parameters in the benchmarks' order
/// [r1 r2 r3 r4 rcx rcy x0 y0 θ0].
#[must_use]
pub fn vector(m: &BenchmarkFourBar) -> [f64; 9] {
    [m.r1, m.r2, m.r3, m.r4, m.rcx, m.rcy, m.x0, m.y0, m.t0]
}

/// Whether the lengths satisfy Grashof's condition with the crank the
/// shortest link, `margin` inside it.
fn grashof_crank(m: &BenchmarkFourBar, margin: f64) -> bool {
    let [a, b, c, d] = [m.r2, m.r3, m.r4, m.r1];
    a + b + margin <= c + d && a + c + margin <= b + d && a + d + margin <= b + c
}

/// Whether the crank angles, taken modulo 2π and read cyclically from
/// the smallest, increase strictly (the benchmarks' "sequence" constraint
/// on free timing: the crank turns one way through the targets, less than
/// a turn).
#[must_use]
pub fn cyclic_increasing(angles: &[f64]) -> bool {
    let a: Vec<f64> = angles.iter().map(|x| x.rem_euclid(TAU)).collect();
    let Some(first) = (0..a.len()).min_by(|&i, &j| a[i].total_cmp(&a[j])) else {
        return true;
    };
    (1..a.len()).all(|k| a[(first + k - 1) % a.len()] < a[(first + k) % a.len()])
}

/// The unknowns of problem `p` for a derivative-free method: the varied
/// parameters (in the order of its bounds), then for free timing the
/// crank angles; from the design `m` and the crank angles `crank`.
#[must_use]
pub fn unknowns(p: &Problem, m: &BenchmarkFourBar, crank: &[f64]) -> Vec<f64> {
    let v = vector(m);
    let mut x: Vec<f64> = p
        .bounds
        .iter()
        .map(|b| NAMES.iter().position(|n| *n == b.0).map_or(0.0, |i| v[i]))
        .collect();
    match p.timing {
        Posed::Free => x.extend_from_slice(crank),
        Posed::Relative(_) => x.push(crank.first().copied().unwrap_or(0.0)),
        Posed::Prescribed(_) => {}
    }
    x
}

/// E of problem `p` at the unknowns `x` ([`unknowns`]) on the
/// benchmarks' branch, with the penalty of the benchmarks' code for a
/// derivative-free method: 10⁶ for each violated constraint (a bound,
/// Grashof with the crank shortest, the angles' sequence, a target where
/// the design does not assemble on the branch).
#[must_use]
pub fn penalised(p: &Problem, x: &[f64]) -> f64 {
    let mut m = from_vector([0.0; 9]);
    let mut violations = 0u32;
    for (&v, &(name, lo, hi)) in x.iter().zip(p.bounds) {
        violations += u32::from(!(lo..=hi).contains(&v));
        set(&mut m, name, v);
    }
    violations += u32::from(!grashof_crank(&m, 0.0));
    let crank = match p.timing {
        Posed::Prescribed(v) => v.to_vec(),
        Posed::Relative(d) => {
            let first = x.get(p.bounds.len()).copied().unwrap_or(0.0);
            d.iter().map(|d| first + d).collect()
        }
        Posed::Free => x[p.bounds.len()..].to_vec(),
    };
    if let Posed::Free = p.timing {
        violations += u32::from(!cyclic_increasing(&crank));
    }
    let mut e = 0.0;
    for (&th2, t) in crank.iter().zip(p.targets) {
        match coupler_point(&m, th2) {
            Some(c) => e += (c[0] - t[0]).powi(2) + (c[1] - t[1]).powi(2),
            None => violations += 1,
        }
    }
    e + 1e6 * f64::from(violations)
}

/// The bounds of the unknowns of [`unknowns`]: the parameters', then
/// [0, 2π] for each free crank angle.
#[must_use]
pub fn unknown_bounds(p: &Problem) -> Vec<[f64; 2]> {
    let mut b: Vec<[f64; 2]> = p.bounds.iter().map(|&(_, lo, hi)| [lo, hi]).collect();
    match p.timing {
        Posed::Free => b.extend(std::iter::repeat_n([0.0, TAU], p.targets.len())),
        Posed::Relative(_) => b.push([0.0, TAU]),
        Posed::Prescribed(_) => {}
    }
    b
}

/// What one run of the global strategy found (a design that meets the
/// problem's constraints: [`solve`] returns no other).
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The best design.
    pub design: BenchmarkFourBar,
    /// Its crank angle at each target.
    pub crank_angles: Vec<f64>,
    /// E = Σ|C(θ2_i) − t_i|².
    pub sum_squares: f64,
    /// The evaluations of the residuals and of the Jacobian, all starts.
    pub evaluations: usize,
}

/// The synthesis problem `p` as posed to the library: the benchmark
/// four-bar's point C through the targets, the problem's parameters
/// varied within its bounds, the timing as posed (free timing in order),
/// the sources' branch (assembly mode −, see [`on_branch`]) and Grashof
/// with the crank the shortest link.
#[must_use]
pub fn posed(p: &Problem) -> Synthesis<BenchmarkFourBar> {
    let m = from_vector([0.0; 9]);
    let start = BenchmarkFourBarCoords {
        th2: 0.0,
        th3: 0.0,
        th4: 0.0,
    };
    let names: Vec<&str> = p.bounds.iter().map(|b| b.0).collect();
    let mut s = Synthesis::path(&m, BenchmarkFourBar::TH2, "C", p.targets, &start)
        .vary(&names)
        .modes(&[Mode::Minus])
        .grashof_crank("r2", "r3", "r4", "r1", 0.0);
    for &(name, lo, hi) in p.bounds {
        s = s.bounds(name, lo, hi);
    }
    match p.timing {
        Posed::Prescribed(v) => s.timing(Timing::Prescribed(v.to_vec())),
        Posed::Relative(d) => s.timing(Timing::Relative(d.to_vec())),
        // The sources' sequence is strict modulo a turn: the last crank
        // angle short of the first's a turn later (by 10⁻⁶ rad).
        Posed::Free => s.in_order_within(TAU - 1e-6),
    }
}

/// The library's search of problem `p` from `seed`, the links' lengths
/// drawn from a tenth of their range up (a link of length near zero is a
/// degenerate start).
fn searched(p: &Problem, seed: u64) -> Search<BenchmarkFourBar> {
    let mut search = posed(p).search().seed(seed);
    for &(name, lo, hi) in p.bounds {
        if ["r1", "r2", "r3", "r4"].contains(&name) {
            search = search.sampling(name, lo + 0.1 * (hi - lo), hi);
        }
    }
    search
}

/// One run of the library's global search
/// ([`Search`](kinematics_core::synthesis::Search)) on problem `p`,
/// reproducible from `seed`: `starts` random designs (the links' lengths
/// drawn from a tenth of their range up), the best `keep` refined to
/// convergence; the best design that meets the constraints (Grashof with
/// the crank the shortest link, and for free timing crank angles in
/// order, [`cyclic_increasing`]), checked over its motion.
#[must_use]
pub fn solve(p: &Problem, seed: u64, starts: usize, keep: usize) -> Option<Outcome> {
    let found = searched(p, seed).starts(starts).keep(keep).run().ok()?;
    let best = found.best()?;
    Some(Outcome {
        design: best.found.design,
        crank_angles: best.found.driver_values.clone(),
        sum_squares: best.found.sum_squares,
        evaluations: found.evaluations,
    })
}

/// The coupler point of `m` at the crank angle `th2` on the benchmarks'
/// branch, for a design check outside the synthesis: `None` where it does
/// not assemble.
#[must_use]
pub fn coupler_point(m: &BenchmarkFourBar, th2: f64) -> Option<[f64; 2]> {
    AllModes::<BenchmarkFourBarModes>::new().find_map(|modes| {
        let q = m.assemble_in(th2, &modes).ok()?;
        on_branch(m, &q).then(|| {
            let c = m.positions(&q).C;
            [c.x, c.y]
        })
    })
}

/// The design whose parameters are `x`, in [`vector`]'s order (for
/// published vectors).
#[must_use]
pub fn from_vector(x: [f64; 9]) -> BenchmarkFourBar {
    let mut m = BenchmarkFourBar {
        r1: 0.0,
        r2: 0.0,
        r3: 0.0,
        r4: 0.0,
        rcx: 0.0,
        rcy: 0.0,
        x0: 0.0,
        y0: 0.0,
        t0: 0.0,
    };
    for (name, v) in NAMES.iter().zip(x) {
        set(&mut m, name, v);
    }
    m
}
