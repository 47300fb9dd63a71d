//! Stage 5: the MIPS32r6 target machine, optimisation pipeline and object emission.

use inkwell::module::Module;
use inkwell::passes::PassBuilderOptions;
use inkwell::targets::{
    CodeModel, FileType, InitializationConfig, RelocMode, Target, TargetMachine, TargetTriple,
};
use inkwell::OptimizationLevel;
use std::sync::Once;

/// Target triple of TRaX.
pub const TRIPLE: &str = "mipsel-unknown-none-elf";
/// CPU name.
pub const CPU: &str = "mips32r6";
/// Target features: MSA, 64-bit FPU registers, no PIC calls.
pub const FEATURES: &str = "+msa,+fp64,+noabicalls";

static INIT: Once = Once::new();

/// Initialises the MIPS backend once per process and disables `$gp`-relative small data
/// (the TRaX linker does not provide `_gp`).
fn init() {
    INIT.call_once(|| {
        Target::initialize_mips(&InitializationConfig::default());
        // The delay-slot filler is kept from moving instructions into delay slots: LLVM
        // emits line-table rows only for the branch of a (branch, slot) bundle, so a moved
        // instruction would be attributed to the branch's source line (a faulting store
        // reported on the line after its own). Unfilled slots take r6 compact branches
        // (no delay slot) wherever one exists, so this costs few instructions.
        let args = [
            c"trax-compiler".as_ptr(),
            c"-mips-ssection-threshold=0".as_ptr(),
            c"-disable-mips-df-backward-search".as_ptr(),
            c"-disable-mips-df-succbb-search".as_ptr(),
        ];
        // SAFETY: `args` holds valid NUL-terminated strings that outlive the call;
        // LLVM only reads them. Called once per process (guarded by `Once`), as LLVM's
        // option parser requires.
        unsafe {
            llvm_sys::support::LLVMParseCommandLineOptions(
                args.len() as i32,
                args.as_ptr(),
                std::ptr::null(),
            );
        }
    });
}

/// Creates the target machine for an optimisation level 0..=3.
pub fn machine(opt: u8) -> Result<TargetMachine, String> {
    init();
    let triple = TargetTriple::create(TRIPLE);
    let target = Target::from_triple(&triple).map_err(|e| e.to_string())?;
    let level = match opt {
        0 => OptimizationLevel::None,
        1 => OptimizationLevel::Less,
        2 => OptimizationLevel::Default,
        _ => OptimizationLevel::Aggressive,
    };
    target
        .create_target_machine(
            &triple,
            CPU,
            FEATURES,
            level,
            RelocMode::Static,
            CodeModel::Default,
        )
        .ok_or_else(|| "cannot create the MIPS target machine".to_string())
}

/// Runs LLVM's standard pipeline for `opt` (inlining at -O2 and above).
pub fn optimize(module: &Module<'_>, tm: &TargetMachine, opt: u8) -> Result<(), String> {
    let pipeline = format!("default<O{}>", opt.min(3));
    module
        .run_passes(&pipeline, tm, PassBuilderOptions::create())
        .map_err(|e| e.to_string())
}

/// Emits an object file or assembly text.
pub fn emit(module: &Module<'_>, tm: &TargetMachine, asm: bool) -> Result<Vec<u8>, String> {
    let ft = if asm {
        FileType::Assembly
    } else {
        FileType::Object
    };
    tm.write_to_memory_buffer(module, ft)
        .map(|b| b.as_slice().to_vec())
        .map_err(|e| e.to_string())
}
