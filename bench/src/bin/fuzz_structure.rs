//! The structure-aware fuzz of definitions given as text, at full size:
//! deep nesting of every kind, long names, many items, long sums, long
//! chains of signs, extreme literals, long comments, large models
//! (`kinematics_compiler::adversarial`). Each chunk of cases runs in a
//! child process, each case on a thread of 2 MiB of stack, so that an
//! abort (a stack overflow) ends only its child and is counted: the cases
//! of a child that did not finish are run again one per process to name
//! the culprit. A case that does not answer within 10 s is a hang.
//!
//! ```text
//! cargo run --release -p kinematics-bench --bin fuzz_structure [cases] [per child]
//! ```
//!
//! Prints the number of cases, aborts, hangs, cases over 1 s, the slowest,
//! and the peak of heap bytes per byte of text, in all and by kind.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use kinematics_compiler::adversarial::{case, KINDS};
use kinematics_tests::heap::{live_and_peak, reset, Counting};

#[global_allocator]
static GLOBAL: Counting = Counting;

/// One case's result, as a child prints it.
struct Row {
    seed: u64,
    kind: String,
    bytes: usize,
    ok: bool,
    seconds: f64,
    peak: isize,
}

/// In a child: cases `from..to`, each on a 2 MiB thread, one line each:
/// `seed kind-index bytes compiled seconds peak`, or `seed panic` and
/// `seed unlocated` (an error outside the text).
fn child(from: u64, to: u64) {
    for seed in from..to {
        let worker = std::thread::Builder::new()
            .stack_size(2 << 20)
            .spawn(move || {
                let (kind, text) = case(seed);
                let kind = KINDS.iter().position(|&k| k == kind).unwrap_or(0);
                // The text itself is not counted: the peak is the
                // compiler's, above the text it was handed.
                reset();
                let started = Instant::now();
                let result = kinematics_compiler::compile_str(&text);
                let seconds = started.elapsed().as_secs_f64();
                let located = match &result {
                    Ok(_) => true,
                    Err(e) => {
                        let lines = text.lines().count().max(1);
                        !e.0.is_empty() && e.0.iter().all(|d| d.line >= 1 && d.line <= lines)
                    }
                };
                let compiled = result.is_ok();
                drop(result);
                let (_, peak) = live_and_peak();
                (kind, text.len(), located, compiled, seconds, peak)
            });
        let Ok(Ok((kind, bytes, located, compiled, seconds, peak))) = worker.map(|w| w.join())
        else {
            println!("{seed} panic");
            continue;
        };
        if !located {
            println!("{seed} unlocated");
            continue;
        }
        println!(
            "{seed} {kind} {bytes} {} {seconds} {peak}",
            u8::from(compiled)
        );
    }
}

/// Runs cases `from..to` in one child; the rows it printed, and whether
/// it finished (exit 0 within the time allowed).
fn spawn(from: u64, to: u64, limit: Duration) -> (Vec<Row>, Vec<u64>, bool) {
    let exe = std::env::current_exe().unwrap_or_default();
    let Ok(mut child) = Command::new(exe)
        .args(["--child", &from.to_string(), &to.to_string()])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
    else {
        return (Vec::new(), Vec::new(), false);
    };
    let stdout = child.stdout.take();
    // Read the rows on a thread while the child runs.
    let reader = std::thread::spawn(move || {
        let mut rows = Vec::new();
        let mut failures = Vec::new();
        if let Some(out) = stdout {
            for line in BufReader::new(out).lines().map_while(Result::ok) {
                let f: Vec<&str> = line.split_whitespace().collect();
                let seed = f.first().and_then(|s| s.parse().ok()).unwrap_or(0);
                if f.len() == 6 {
                    let kind = f[1]
                        .parse::<usize>()
                        .ok()
                        .and_then(|k| KINDS.get(k))
                        .copied();
                    rows.push(Row {
                        seed,
                        kind: kind.unwrap_or("?").to_string(),
                        bytes: f[2].parse().unwrap_or(0),
                        ok: f[3] == "1",
                        seconds: f[4].parse().unwrap_or(f64::NAN),
                        peak: f[5].parse().unwrap_or(0),
                    });
                } else {
                    failures.push(seed);
                }
            }
        }
        (rows, failures)
    });
    let started = Instant::now();
    let finished = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status.success(),
            Ok(None) if started.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                break false;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(_) => break false,
        }
    };
    let (rows, failures) = reader.join().unwrap_or_default();
    (rows, failures, finished)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).map(String::as_str) == Some("--child") {
        let from = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
        let to = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0);
        child(from, to);
        return;
    }
    let cases: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let per_child: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(500);
    let mut rows: Vec<Row> = Vec::new();
    let (mut aborts, mut hangs, mut panics) = (Vec::new(), Vec::new(), Vec::new());
    let started = Instant::now();
    let mut from = 0;
    while from < cases {
        let to = (from + per_child).min(cases);
        let limit = Duration::from_secs(10 * (to - from));
        let (mut got, failures, finished) = spawn(from, to, limit);
        panics.extend(failures);
        if !finished {
            // Run the cases the child did not report, one per process.
            let done: Vec<u64> = got
                .iter()
                .map(|r| r.seed)
                .chain(panics.iter().copied())
                .collect();
            let missing: Vec<u64> = (from..to).filter(|s| !done.contains(s)).collect();
            for seed in missing {
                let started = Instant::now();
                let (one, failures, finished) = spawn(seed, seed + 1, Duration::from_secs(10));
                panics.extend(failures);
                if finished {
                    got.extend(one);
                } else if started.elapsed() >= Duration::from_secs(10) {
                    hangs.push(seed);
                } else {
                    aborts.push(seed);
                }
            }
        }
        rows.extend(got);
        from = to;
        if from % 10_000 == 0 {
            eprintln!("{from} cases, {:.0} s", started.elapsed().as_secs_f64());
        }
    }
    let over = rows.iter().filter(|r| r.seconds > 1.0).count();
    let slowest = rows.iter().max_by(|a, b| a.seconds.total_cmp(&b.seconds));
    // Peak heap per byte of text, over texts of 1 KiB or more (below, the
    // fixed cost of a compile dominates).
    let per_byte = |r: &Row| r.peak as f64 / r.bytes as f64;
    let large: Vec<&Row> = rows.iter().filter(|r| r.bytes >= 1024).collect();
    let worst = large
        .iter()
        .max_by(|a, b| per_byte(a).total_cmp(&per_byte(b)));
    println!(
        "{} cases in {:.0} s: {} answered, {} aborts, {} hangs, {} panics or unlocated errors, {} over 1 s",
        cases,
        started.elapsed().as_secs_f64(),
        rows.len(),
        aborts.len(),
        hangs.len(),
        panics.len(),
        over
    );
    if let Some(s) = slowest {
        println!(
            "slowest: case {} ({}, {} bytes) in {:.3} s",
            s.seed, s.kind, s.bytes, s.seconds
        );
    }
    if let Some(w) = worst {
        println!(
            "most heap per byte of text (texts of 1 KiB or more): {:.0} (case {}, {}, {} bytes, peak {} bytes)",
            per_byte(w),
            w.seed,
            w.kind,
            w.bytes,
            w.peak
        );
    }
    println!(
        "| kind | cases | accepted | slowest (s) | largest text (bytes) | most heap per byte |"
    );
    println!("|---|---|---|---|---|---|");
    for kind in KINDS {
        let of: Vec<&Row> = rows.iter().filter(|r| r.kind == kind).collect();
        let slow = of.iter().map(|r| r.seconds).fold(0.0, f64::max);
        let biggest = of.iter().map(|r| r.bytes).max().unwrap_or(0);
        let heap = of
            .iter()
            .filter(|r| r.bytes >= 1024)
            .map(|r| per_byte(r))
            .fold(0.0, f64::max);
        println!(
            "| {kind} | {} | {} | {slow:.3} | {biggest} | {heap:.0} |",
            of.len(),
            of.iter().filter(|r| r.ok).count()
        );
    }
    for (what, list) in [("abort", &aborts), ("hang", &hangs), ("panic", &panics)] {
        for seed in list.iter().take(10) {
            println!("{what}: case {seed}");
        }
    }
    if !(aborts.is_empty() && hangs.is_empty() && panics.is_empty()) {
        std::process::exit(1);
    }
}
