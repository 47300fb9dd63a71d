//! Argument parsing and dispatch to subcommands.

use clap::{Parser, Subcommand};

mod annotate;
mod build;
mod common;
mod compare;
mod config;
mod converge;
mod disasm;
mod header;
mod ladder;
mod native;
mod plot;
mod progress;
mod run;
mod scene;
mod sweep;

#[derive(Parser, Debug)]
#[command(
    name = "trax",
    version,
    about = "TRaX-Rust toolchain and ray-tracing hardware simulator",
    after_help = "TRaX-Rust kernels are Rust: every build also checks them with rustc (moves, borrows, exhaustiveness, `unsafe`; errors carry rustc's code). Without rustc: TRAX_RUSTC_CHECK=auto (default) warns and builds with the trax compiler's own checks, =require refuses, =off skips the check. The language and its prelude API: docs/LANGUAGE.md."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Compile and link a kernel (TRaX-Rust, C, C++) into a MIPS32r6 ELF executable with DWARF.
    Build(build::BuildArgs),
    /// Write the generated C/C++ kernel API headers (trax.h, trax_isa.h, trax.hpp).
    Header(header::HeaderArgs),
    /// Inspect scenes: triangles, materials, bounds, BVH, treelets, memory bytes.
    Scene(scene::SceneArgs),
    /// Chip configs: list the presets, or print one (or a file, with overrides) in full.
    Config(config::ConfigArgs),
    /// Build a kernel with rustc against the host prelude and run it on host threads.
    Native(native::NativeArgs),
    /// Run a kernel (TRaX-Rust, C or C++ source, or a linked ELF) on the simulated machine.
    Run(run::RunArgs),
    /// Disassemble an executable, optionally with source lines.
    Disasm(disasm::DisasmArgs),
    /// Run a kernel with profiling and print per-source-line costs next to the source.
    Annotate(annotate::AnnotateArgs),
    /// Run a design-space sweep (a grid of `trax run`s) here or on Slurm, or collect one.
    Sweep(sweep::SweepArgs),
    /// Chart a sweep's results (PNG and SVG).
    Plot(plot::PlotArgs),
    /// Measure an image (PNG or raw framebuffer) against a reference: RMSE, relative MSE,
    /// PSNR, maximum error, NaN and infinite pixels.
    Compare(compare::CompareArgs),
    /// Image error against samples per pixel: a `trax native` reference, one simulated run
    /// per level, a table, the log-log slope and a chart.
    Converge(converge::ConvergeArgs),
    /// The fidelity ladder: one frame in each simulation mode (functional, timing with
    /// simple or detailed DRAM, sampled at several rates), with each mode's host time and
    /// error in cycles, MRPS and energy against full detailed timing; table, CSV, JSON, chart.
    Ladder(ladder::LadderArgs),
}

pub fn main() -> std::process::ExitCode {
    watch_sweep_parent();
    let cli = Cli::parse();
    match cli.command {
        Command::Build(a) => build::run(a),
        Command::Header(a) => header::run(a),
        Command::Scene(a) => scene::run(a),
        Command::Config(a) => config::run(a),
        Command::Native(a) => native::run(a),
        Command::Run(a) => run::run(a),
        Command::Disasm(a) => disasm::run(a),
        Command::Annotate(a) => annotate::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Plot(a) => plot::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Converge(a) => converge::run(a),
        Command::Ladder(a) => ladder::run(a),
    }
}

/// A point of a sweep (`TRAX_SWEEP_PARENT` = the sweep's pid) ends when the sweep is gone,
/// so a killed sweep leaves no runs behind: a thread checks the parent every 100 ms.
pub fn watch_sweep_parent() {
    let Some(parent) = std::env::var(sweep::runner::PARENT_ENV)
        .ok()
        .and_then(|v| v.parse::<u32>().ok())
    else {
        return;
    };
    let orphaned = move || std::os::unix::process::parent_id() != parent;
    if orphaned() {
        std::process::exit(137);
    }
    std::thread::spawn(move || loop {
        std::thread::sleep(std::time::Duration::from_millis(100));
        if orphaned() {
            std::process::exit(137);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_is_well_formed() {
        Cli::command().debug_assert();
    }

    /// `--config`'s help names every preset.
    #[test]
    fn config_help_names_every_preset() {
        let mut cmd = Cli::command();
        let run = cmd.find_subcommand_mut("run").unwrap();
        let help = run
            .get_arguments()
            .find(|a| a.get_id() == "config")
            .and_then(|a| a.get_help())
            .unwrap()
            .to_string();
        for p in trax_emulator::timing::CHIP_PRESETS {
            assert!(help.contains(&format!("`{p}`")), "{p} missing from {help}");
        }
    }
}
