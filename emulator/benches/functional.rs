//! Functional-mode speed: simulated instructions per host second on one host thread, on
//! an FP-heavy ray/box slab-test loop, next to qemu-mipsel's figure on the same compiled
//! loop when qemu is installed (`common/functional.rs`). The loop is C (clang-14) so that
//! qemu's Linux user mode runs the very same code; the Rust path tracer's figure is the
//! one `trax run examples/pathtracer.rs --functional` prints.
//!
//! Run: `cargo bench -p trax-emulator --bench functional`. Target: >= 300 M instr/s and
//! faster than qemu.

#[path = "common/mod.rs"]
mod common;

fn main() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-bench-functional");
    let Some(f) = common::functional::measure(&dir, 40_000) else {
        println!("functional bench: clang-14/ld.lld-14 not available; skipped");
        return;
    };
    println!(
        "functional ray-box loop: {} instructions, best of 3: {:.3} s",
        f.instructions, f.secs
    );
    println!(
        "  trax emulator (1 host thread): {:8.1} M instr/s",
        f.mips()
    );
    match (f.qemu_mips(), f.qemu_secs) {
        (Some(q), Some(qs)) => {
            println!("  qemu-mipsel (same program):    {q:8.1} M instr/s  ({qs:.3} s)");
            println!("  ratio trax/qemu: {:.2}", f.mips() / q);
        }
        _ => println!("  qemu-mipsel not installed (or failed): no comparison"),
    }
}
