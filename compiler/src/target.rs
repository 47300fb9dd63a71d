//! Stage 5: the MIPS32r6 target machine, optimisation pipeline and object emission.

use inkwell::module::Module;
use inkwell::passes::PassBuilderOptions;
use inkwell::targets::{
    CodeModel, FileType, InitializationConfig, RelocMode, Target, TargetMachine, TargetTriple,
};
use inkwell::values::{AnyValueEnum, BasicValue, CallableValue};
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
        .map_err(|e| e.to_string())?;
    mask_vector_fabs(module)
}

/// Rewrites every `llvm.fabs` on a vector as `bclri` (clear the sign bit; exact for every
/// input, NaNs included). LLVM 14 selects `fmax_a.{w,d} x, x` for it, which keeps the
/// sign (it returns the operand of larger magnitude), and the SLP vectorizer makes such
/// calls out of scalar `abs()` (two `f64::abs` on the way to a pair of compares, for
/// instance), so scalar code was miscompiled. Inline assembly, because LLVM 14's DAG
/// combiner can loop forever on the equivalent `and` of a `<2 x i64>` bit cast.
fn mask_vector_fabs(module: &Module<'_>) -> Result<(), String> {
    let ctx = module.get_context();
    let b = ctx.create_builder();
    let mut next = module.get_first_function();
    while let Some(f) = next {
        next = f.get_next_function();
        if !f.get_name().to_bytes().starts_with(b"llvm.fabs.v") {
            continue;
        }
        let callee = f.as_global_value().as_pointer_value();
        while let Some(u) = callee.get_first_use() {
            let call = match u.get_user() {
                AnyValueEnum::VectorValue(v) => v.as_instruction(),
                AnyValueEnum::InstructionValue(i) => Some(i),
                _ => None,
            }
            .ok_or("vector fabs used other than by a call")?;
            let x = call
                .get_operand(0)
                .and_then(|o| o.value())
                .ok_or("vector fabs without an operand")?
                .into_vector_value();
            let vt = x.get_type();
            let asm = match vt.get_element_type().into_float_type().get_bit_width() {
                64 => "bclri.d $0, $1, 63",
                32 => "bclri.w $0, $1, 31",
                w => return Err(format!("vector fabs on {w}-bit lanes")),
            };
            let ia = ctx.create_inline_asm(
                vt.fn_type(&[vt.into()], false),
                asm.into(),
                "=f,f".into(),
                false,
                false,
                None,
                false,
            );
            let callable = CallableValue::try_from(ia).map_err(|_| "inline asm callable")?;
            b.position_before(&call);
            let r = b
                .build_call(callable, &[x.into()], "")
                .map_err(|e| e.to_string())?
                .try_as_basic_value()
                .basic()
                .and_then(|v| v.as_instruction_value())
                .ok_or("bclri call")?;
            call.replace_all_uses_with(&r);
            call.erase_from_basic_block();
        }
    }
    Ok(())
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
