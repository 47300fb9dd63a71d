//! Compile time of the largest kernel in `examples/` at -O2 (target: under 1 s in a
//! release build). Prints figures; run with `cargo bench -p trax-compiler`.

use std::path::PathBuf;
use std::time::Instant;
use trax_compiler::{compile_file, CompileOptions, Emit, Prelude};

fn main() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let largest = std::fs::read_dir(&dir)
        .expect("examples dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .max_by_key(|p| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0))
        .expect("at least one example");
    let opts = CompileOptions {
        opt_level: 2,
        emit: Emit::Obj,
        prelude: Some(Prelude::runtime()),
    };
    // Warm-up (LLVM initialisation happens once per process).
    if let Err(e) = compile_file(&largest, &opts) {
        eprintln!("{e}");
        std::process::exit(1);
    }
    let runs = 10;
    let mut times = Vec::new();
    let mut size = 0;
    for _ in 0..runs {
        let t = Instant::now();
        let out = compile_file(&largest, &opts).expect("compiles");
        times.push(t.elapsed().as_secs_f64());
        size = out.bytes.len();
    }
    times.sort_by(|a, b| a.total_cmp(b));
    let median = times[runs / 2];
    println!("kernel:        {}", largest.display());
    println!("object size:   {size} bytes");
    println!(
        "compile -O2:   median {:.1} ms, min {:.1} ms, max {:.1} ms over {runs} runs",
        median * 1e3,
        times[0] * 1e3,
        times[runs - 1] * 1e3
    );
    println!(
        "target:        < 1000 ms -> {}",
        if median < 1.0 { "met" } else { "NOT met" }
    );
}
