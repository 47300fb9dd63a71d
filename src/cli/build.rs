//! `trax build`: compile a TRaX-Rust kernel and link it with the runtime start-up code into a
//! MIPS32r6 executable (or stop at an object, assembly or LLVM IR).

use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;
use trax::pipeline::{build_executable, compile_object, DEFAULT_OPT_LEVEL};
use trax_compiler::Emit;

/// Output kind of `trax build`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum EmitKind {
    /// Linked ELF executable (start-up code + kernel), ready for `trax run`.
    Exe,
    /// ELF relocatable object.
    Obj,
    /// MIPS assembly text.
    Asm,
    /// LLVM IR text (after optimisation).
    LlvmIr,
}

/// Arguments of `trax build`.
#[derive(Args, Debug)]
pub struct BuildArgs {
    /// Kernel root file (`mod` files are found next to it).
    pub kernel: PathBuf,
    /// Output file.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Optimisation level 0-3 (`-O0` .. `-O3`); inlining from -O2.
    #[arg(short = 'O', default_value_t = DEFAULT_OPT_LEVEL, value_parser = clap::value_parser!(u8).range(0..=3))]
    pub opt_level: u8,
    /// What to emit.
    #[arg(long, value_enum, default_value_t = EmitKind::Exe)]
    pub emit: EmitKind,
}

/// Runs `trax build`.
pub fn run(a: BuildArgs) -> ExitCode {
    let result = match a.emit {
        EmitKind::Exe => build_executable(&a.kernel, a.opt_level),
        other => {
            let emit = match other {
                EmitKind::Asm => Emit::Asm,
                EmitKind::LlvmIr => Emit::LlvmIr,
                EmitKind::Exe | EmitKind::Obj => Emit::Obj,
            };
            compile_object(&a.kernel, a.opt_level, emit)
        }
    };
    match result {
        Ok(bytes) => match std::fs::write(&a.output, &bytes) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: cannot write {}: {e}", a.output.display());
                ExitCode::from(1)
            }
        },
        Err(e) => {
            eprint!("{}", e.render());
            ExitCode::from(e.exit_code())
        }
    }
}
