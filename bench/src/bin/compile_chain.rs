//! Release compile time and peak memory of large mechanisms: chains of n
//! crank-rocker four-bars (2n unknowns, n two-mode RRR blocks; the source
//! is `kinematics_tests::four_bar_chain`), each compiled as a one-file
//! program with `cargo build --release`, then run.
//!
//! ```sh
//! cargo run --release -p kinematics-bench --bin compile_chain [n ...]
//! ```
//!
//! The programs are written under `target/chain-compile/` and share the
//! workspace's target directory, whose dependencies a first build of a
//! one-loop chain compiles (not timed). The time is the wall time of
//! `cargo build --release` for the program alone (the macro's expansion
//! and rustc); the peak memory is the largest resident set of that build's
//! processes (rustc's, in practice), from `getrusage(RUSAGE_CHILDREN)` in
//! a child process that runs only that build.
// A measuring harness: a failed build should stop it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::cast_precision_loss)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[path = "../../../tests/src/four_bar_chain.rs"]
mod four_bar_chain;

/// The workspace's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Writes the program of a chain of `n` loops into `dir`.
fn write_program(dir: &Path, n: usize) {
    std::fs::create_dir_all(dir.join("src")).unwrap();
    let core = root().join("kinematics-core").canonicalize().unwrap();
    std::fs::write(
        dir.join("Cargo.toml"),
        format!(
            "[package]\nname = \"chain-compile\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n\
             [dependencies]\nkinematics-core = {{ path = {:?} }}\n\n[workspace]\n",
            core.display().to_string()
        ),
    )
    .unwrap();
    let main = format!(
        "#![allow(missing_docs)]\n{}\nfn main() {{\n    let m = Chain {{ a: 1.0, b: 3.0, c: 2.5, d: 3.0 }};\n    \
         let q = m.assemble_in(0.3, &ChainModes::default()).expect(\"assembles\");\n    \
         let s = m.step(&q, 1.0, 0.0).expect(\"steps\");\n    \
         println!(\"r{n} = {{:.12}} rad, r{n}' = {{:.3e}} rad/s\", s.q.r{n}, s.qd.r{n});\n}}\n",
        four_bar_chain::source("Chain", n)
    );
    std::fs::write(dir.join("src/main.rs"), main).unwrap();
}

/// `cargo build --release` in `dir` with the workspace's target directory.
fn build(dir: &Path) -> Command {
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.arg("build")
        .arg("--release")
        .arg("--quiet")
        .current_dir(dir)
        .env(
            "CARGO_TARGET_DIR",
            root().join("target/chain-compile/target"),
        );
    c
}

/// In the child: runs the build and prints its wall time (s) and the
/// largest resident set of its processes (KiB).
fn measure(dir: &Path) {
    let t = Instant::now();
    let status = build(dir).status().unwrap();
    assert!(status.success(), "the build failed");
    let seconds = t.elapsed().as_secs_f64();
    // SAFETY: getrusage writes into the zeroed struct it is given.
    #[allow(unsafe_code)]
    let max_kib = unsafe {
        let mut u: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut u);
        u.ru_maxrss
    };
    println!("{seconds} {max_kib}");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--measure") {
        measure(Path::new(&args[1]));
        return;
    }
    let sizes: Vec<usize> = if args.is_empty() {
        vec![100, 250]
    } else {
        args.iter()
            .map(|a| a.parse().expect("a number of loops"))
            .collect()
    };
    let dir = root().join("target/chain-compile/program");
    write_program(&dir, 1);
    assert!(build(&dir).status().unwrap().success(), "the dependencies");
    println!("| loops | unknowns | release build (s) | peak memory (MiB) | run |");
    println!("|---|---|---|---|---|");
    for n in sizes {
        write_program(&dir, n);
        let out = Command::new(std::env::current_exe().unwrap())
            .arg("--measure")
            .arg(&dir)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "the build of {n} loops failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let mut f = text.split_whitespace();
        let seconds: f64 = f.next().expect("a time").parse().unwrap();
        let kib: f64 = f.next().expect("a size").parse().unwrap();
        let run = Command::new(root().join("target/chain-compile/target/release/chain-compile"))
            .output()
            .unwrap();
        assert!(run.status.success(), "the program failed");
        println!(
            "| {n} | {} | {seconds:.1} | {:.0} | {} |",
            2 * n,
            kib / 1024.0,
            String::from_utf8_lossy(&run.stdout).trim()
        );
    }
}
