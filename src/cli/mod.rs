//! Argument parsing and dispatch to subcommands.

use clap::{Parser, Subcommand};

mod annotate;
mod build;
mod common;
mod disasm;
mod native;
mod prepare;
mod progress;
mod run;
mod scene;

#[derive(Parser, Debug)]
#[command(
    name = "trax",
    version,
    about = "TRaX-Rust toolchain and ray-tracing hardware simulator"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Compile and link a TRaX-Rust kernel into a MIPS32r6 ELF executable with DWARF.
    Build(build::BuildArgs),
    /// Inspect scenes: triangles, materials, bounds, BVH, treelets, memory bytes.
    Scene(scene::SceneArgs),
    /// Build a kernel with rustc against the host prelude and run it on host threads.
    Native(native::NativeArgs),
    /// Run a linked kernel (ELF) on the simulated machine.
    Run(run::RunArgs),
    /// Disassemble an executable, optionally with source lines.
    Disasm(disasm::DisasmArgs),
    /// Run a kernel with profiling and print per-source-line costs next to the source.
    Annotate(annotate::AnnotateArgs),
}

pub fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Build(a) => build::run(a),
        Command::Scene(a) => scene::run(a),
        Command::Native(a) => native::run(a),
        Command::Run(a) => run::run(a),
        Command::Disasm(a) => disasm::run(a),
        Command::Annotate(a) => annotate::run(a),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_is_well_formed() {
        Cli::command().debug_assert();
    }
}
