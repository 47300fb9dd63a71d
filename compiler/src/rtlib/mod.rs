//! Compiler runtime functions that the MIPS32 backend calls for 64-bit division and
//! 64-bit integer/float conversions (`__udivdi3`, `__floatdidf`, ...). TRaX has no
//! compiler-rt, so when the optimised module contains such operations these definitions
//! (internal linkage, written in LLVM IR) are linked into it before code generation.

use inkwell::context::Context;
use inkwell::memory_buffer::MemoryBuffer;
use inkwell::module::Module;

/// The helpers' LLVM IR (external definitions; `provide` makes them internal).
pub const INT64_IR: &str = include_str!("int64.ll");

/// True when the module's IR has operations lowered to these library calls.
fn needs_int64(ir: &str) -> bool {
    ["udiv i64", "sdiv i64", "urem i64", "srem i64", "itofp i64"]
        .iter()
        .any(|p| ir.contains(p))
        || ir
            .lines()
            .any(|l| (l.contains("fptoui") || l.contains("fptosi")) && l.contains(" to i64"))
        || ir.contains("fpto") && ir.contains(".sat.i64.")
}

/// Links the 64-bit helpers into `module` if it needs them.
pub fn provide<'ctx>(ctx: &'ctx Context, module: &Module<'ctx>) -> Result<(), String> {
    let ir = module.print_to_string().to_string();
    if !needs_int64(&ir) {
        return Ok(());
    }
    let buf = MemoryBuffer::create_from_memory_range_copy(INT64_IR.as_bytes(), "trax-rtlib");
    let lib = ctx
        .create_module_from_ir(buf)
        .map_err(|e| format!("runtime library IR: {e}"))?;
    lib.set_triple(&module.get_triple());
    lib.set_data_layout(&module.get_data_layout());
    module
        .link_in_module(lib)
        .map_err(|e| format!("linking runtime library: {e}"))?;
    // Keep the helpers private to this object (another object may carry its own copy).
    for name in HELPERS {
        if let Some(f) = module.get_function(name) {
            f.set_linkage(inkwell::module::Linkage::Internal);
        }
    }
    Ok(())
}

/// The library-call names defined by `int64.ll`.
pub const HELPERS: &[&str] = &[
    "__udivdi3",
    "__umoddi3",
    "__divdi3",
    "__moddi3",
    "__floatundidf",
    "__floatdidf",
    "__floatundisf",
    "__floatdisf",
    "__fixunsdfdi",
    "__fixdfdi",
    "__fixunssfdi",
    "__fixsfdi",
];
